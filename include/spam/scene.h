/* Scenes build the initial particles, the box and the model from options. */
#ifndef SPAM_SCENE_H
#define SPAM_SCENE_H
#include <spam/sim.h>

/* Particles as a scene makes them, before they go into the swarm. */
typedef struct {
  int           dim;
  PetscInt      n;
  double       *x, *v;   /* [n*dim] each                                         */
  double        mass;
  SpamBox       box;
  SpamSceneInfo info;
} SpamParticles;

/* Options shared by every scene. */
typedef struct {
  int       dim;
  double    h, mass, skin, gamma, kappa;
  double    box_lo[3], box_len[3];
  PetscBool box_len_set;
  PetscBool periodic[3];
  double    translate[3];
} SpamCommonParams;

typedef struct {
  PetscInt  n;          /* lattice points per direction                           */
  double    amplitude;  /* size of the random offsets or velocities               */
  PetscInt  seed;
  PetscBool velocities; /* perturb velocities instead of positions                */
} SpamExpansionParams;

typedef struct {
  char path[PETSC_MAX_PATH_LEN];
} SpamFileParams;

PetscErrorCode SpamExpansionOptions(const SpamCommonParams *c, SpamExpansionParams *p);
PetscErrorCode SpamExpansionBuild(const SpamCommonParams *c, const SpamExpansionParams *p, SpamParticles *out);
PetscErrorCode SpamFileOptions(SpamFileParams *p);
PetscErrorCode SpamFileBuild(const SpamCommonParams *c, const SpamFileParams *p, SpamParticles *out);
PetscErrorCode SpamParticlesAllocate(int dim, PetscInt n, SpamParticles *p);
PetscErrorCode SpamParticlesFree(SpamParticles *p);

/* Reads -scene and every option of the chosen scene, builds the particles and creates the
 * simulation with its state vector. With -help, lists the options of every scene. */
PetscErrorCode SpamSceneCreateSim(MPI_Comm comm, SpamSim *sim);
#endif
