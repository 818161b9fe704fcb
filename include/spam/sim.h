/* The simulation: particles in a DMSwarm whose one packed field is the state vector,
 * the box, the model, neighbour list and the scratch that the right-hand side uses. */
#ifndef SPAM_SIM_H
#define SPAM_SIM_H
#include <spam/swarm.h>
#include <spam/decompose.h>
#include <spam/box.h>
#include <spam/model.h>
#include <spam/neighbours.h>
#include <spam/walls.h>
#include <spam/wall_books.h>
#include <spam/fields.h>
#include <spam/diffusion_cache.h>

/* Per-particle data kept outside the state, copied into the swarm only to travel with
 * their particle through a migration (migrate.c): the mass and the body label. These and
 * SPAM_XREF_FIELD exist on several ranks only (one rank never migrates). */
#define SPAM_MASS_FIELD "spam_mass"
#define SPAM_BODY_FIELD "spam_body"
/* The neighbour list's reference position of the particle (dim reals): a migration carries
 * it and rebuilds the list there, as the list was built, so that the list's geometry and
 * the times of its rebuilds do not depend on migrations (-reproducible needs this: a
 * rebuild at another time can wrap a particle that crossed a periodic face otherwise). */
#define SPAM_XREF_FIELD "spam_xref"
/* The adaptive kernel range's h_i (the next solve's start), carried with the particle. */
#define SPAM_H_FIELD "spam_h"

typedef struct {
  long   rhs_evals;
  long   rhs_evals_diffusion; /* of rhs_evals, those of the diffusion part alone (IMEX) */
  double rhs_time;      /* seconds inside the right-hand side, list builds included */
  double pair_visits;   /* pair-list entries visited in force passes                */
  /* This process's evaluations (rhs_evals also holds a checkpoint's and leaves out the
   * interpolant's), and the list updates and ghost placements (on several ranks the
   * halo's exchange of positions) they made: one each per evaluation is the rule. */
  long counted, list_updates, ghost_placements;
  /* The evolved range (-smoothing_length evolved): the particle evaluations whose grad-h
   * factor Omega_i was not positive and took 1 (a particle whose range holds too few
   * partners), and the most in one evaluation; summed (and the most taken) over the ranks
   * at the end, for summary.json and a note. */
  long omega_floored, omega_floored_max;
} SpamRhsStats;

/* PETSc log events (-log_view) of the right-hand side and its passes; registered per
 * simulation (PETSc returns the existing event for a name already registered). */
typedef struct {
  PetscLogEvent rhs, density, force;
} SpamLogEvents;

typedef struct {
  char   name[64];
  double volume_ratio;          /* final / initial gas volume; 0 if not an expansion */
  double sound_traversal_time;  /* time for sound to cross the initial body          */
  double t_end_default;
} SpamSceneInfo;

/* Where the particles are: the box, its mirror walls and, on more than one rank
 * (sim_distribute.c), the decomposition the particles migrate by, and with it the halo of
 * the neighbour list (NULL on one rank). */
typedef struct {
  SpamBox            box;
  SpamWalls          walls; /* mirror walls of the box faces (walls.h) */
  struct SpamDecomp *dec;
} SpamGeometry;

/* What the pair passes work on: the list, the per-particle fields and the threads. */
typedef struct {
  SpamNeighbours nl;
  double         skin;
  SpamFields     f;        /* per-particle fields of the passes, with ghost slots:    */
                           /* masses, density, P/rho^2, accelerations a[i*dim + d]   */
                           /* (interleaved: a pair's update touches one cache line)  */
                           /* and the tensor path's arrays                           */
  int            threads;  /* OpenMP threads of the pair passes (-threads; 1: none)   */
  double        *tacc, *trho; /* per-thread sums of threads 1..T-1 (NULL for T = 1)  */
  PetscBool      periodic_ghosts; /* periodic images as ghost slots (-periodic_images) */
  PetscBool      reproducible;    /* -reproducible: canonical pair sums (the list's      */
                                  /* canonical rows) and a partition-independent norm  */
  long           ghost_mass_build; /* the list build whose ghost slots hold their masses */
  SpamDiffusionCache dcache;      /* the diffusion part's position fields (IMEX)         */
} SpamPairState;

/* What the run counts and times. */
typedef struct {
  SpamRhsStats  stats;
  SpamLogEvents ev;
  long          migrations_run; /* migrations between steps, after the first distribution */
  PetscInt64    migrated;       /* particles they moved between ranks                   */
} SpamRunCounts;

/* What the outputs report beyond the state. */
typedef struct {
  SpamSceneInfo scene;
  SpamWallRates wall_rates; /* what the walls gave the fluid at the last RHS */
} SpamSimReport;

typedef struct SpamSim {
  SpamSwarm     p;     /* the swarm, the state X, the gids (swarm.h) */
  SpamGeometry  geo;
  SpamModel     model; /* the law and its parameters                 */
  SpamPairState pair;
  struct SpamPhysicsScratch *ps; /* scratch of the tensor path and bonds (NULL for the gas) */
  SpamRunCounts run;
  SpamSimReport out;
  /* One rank, which has no carried fields (SPAM_MASS_FIELD): the masses, reference
   * positions and body labels by gid while a migration (a local sort) is under way. */
  struct {
    double   *m, *xref;
    PetscInt *body;
  } stash;
} SpamSim;

/* Input row of particle i, and the local particle of the r-th smallest gid (swarm.h). */
static inline PetscInt SpamSimRowOf(const SpamSim *sim, PetscInt i)
{
  return SpamSwarmRowOf(&sim->p, i);
}
static inline PetscInt SpamSimAtRow(const SpamSim *sim, PetscInt r)
{
  return SpamSwarmAtRow(&sim->p, r);
}

/* Creates the swarm with n local particles and the model's layout; X is not yet made.
 * Collective on comm: the particles get gids in rank order (this rank's first gid is the
 * count on the ranks before it). */
PetscErrorCode SpamSimCreate(MPI_Comm comm, const SpamModel *model, const SpamBox *box, PetscInt n, double skin, SpamSim *sim);
/* Copies positions and velocities ([n*dim] each) into the swarm's packed field, and the
 * masses ([n], or NULL: every particle has the model's mass). */
PetscErrorCode SpamSimFill(SpamSim *sim, const double *x, const double *v, const double *m);
/* Wraps the packed field in X (zero copy) and allocates scratch: call once the swarm is filled. */
PetscErrorCode SpamSimSetUp(SpamSim *sim);
/* After the local particles changed (a migration): sim->p.n from the swarm, the fields,
 * thread buffers, body labels and the (empty) neighbour list made to fit it, the masses
 * and body labels taken from the swarm's carried fields. The other per-particle fields
 * (density, accelerations, ...) hold nothing valid until the next right-hand side.
 * Collective once distributed (equal masses are decided over every rank), else local;
 * statistics (list builds, RHS counts) go on. SpamSimBuildList must follow once X is
 * re-made. */
PetscErrorCode SpamSimResize(SpamSim *sim);
/* Builds the neighbour list (and its ghosts) at the positions in X. */
PetscErrorCode SpamSimBuildList(SpamSim *sim);
PetscErrorCode SpamSimDestroy(SpamSim *sim);
/* Collective. On more than one rank: the particles, built on rank 0 and set up there
 * exactly as on one rank, are cut into equal pieces along a Hilbert curve of the occupied
 * cells and sent to their owners; the neighbour list then takes other ranks' particles as
 * remote ghosts (halo.h). The bodies' count is shared. Nothing on one rank. */
PetscErrorCode SpamSimDistribute(SpamSim *sim);
/* The particles moved by the decomposition (SpamSwarmMigrate, decompose.h), the masses,
 * reference positions and body labels carried in the swarm, the model's carry hooks
 * around the move, then the scratch re-made and the list rebuilt at the carried reference
 * positions (sim_migrate.c). Collective. */
PetscErrorCode SpamSimMigrate(SpamSim *sim, SpamDecomp *dec, SpamMigrateInfo *info);
/* A restart's placement of the particles in the checkpoint's blocks (SpamSwarmPlace),
 * carried as by a migration; the list is left to the caller. Collective. */
PetscErrorCode SpamSimPlace(SpamSim *sim, PetscInt n, const PetscInt64 *gids, PetscBool *changed);
/* The masses (and inverse masses, and the gas's P/rho^2 when gamma = 2 makes it the same
 * for every particle) of the ghost slots: gathered once after each list build, since a
 * particle's mass never changes and the slots change only at builds. Collective on more
 * than one rank (the build count is the same on every rank). */
PetscErrorCode SpamSimGhostMasses(SpamSim *sim);
/* Whether the run is on more than one rank. */
static inline PetscBool SpamSimDistributed(const SpamSim *sim)
{
  return (PetscBool)(sim->geo.dec != NULL);
}

/* The right-hand side ydot = f(y) of the sim's model on raw arrays of length n*nvar,
 * timed and counted in sim->run.stats. *bad is the first particle with a non-finite (or
 * unphysical) state, or -1. Every integrator calls this one function. */
PetscErrorCode SpamRhs(SpamSim *sim, const double *y, double *ydot, PetscInt *bad);
/* One part of it (model.h's SpamRhsPart; the model must have rhs_part), timed and counted
 * as SpamRhs; evaluations of the diffusion part also in stats.rhs_evals_diffusion. */
PetscErrorCode SpamRhsOfPart(SpamSim *sim, const double *y, double *ydot, SpamRhsPart part, PetscInt *bad);
/* The model's rhs_active (model.h), counted as an evaluation when *done. */
PetscErrorCode SpamRhsActive(SpamSim *sim, const double *y, double *ydot, const unsigned char *active, unsigned char *near, PetscBool *done, PetscInt *bad);
/* Accelerations of positions x (stride between particles) into sim->acc, timed and counted
 * as one RHS evaluation; only for models with an accel function (state [x, v]). */
PetscErrorCode SpamAccel(SpamSim *sim, const double *x, int stride, PetscInt *bad);
/* The isentropic gas (Hoover & Hoover 2001). */
PetscErrorCode SpamRhsIsentrope(SpamSim *sim, const double *y, double *ydot, PetscInt *bad);
PetscErrorCode SpamAccelIsentrope(SpamSim *sim, const double *x, int stride, PetscInt *bad);
PetscErrorCode SpamMaxSoundSpeedIsentrope(SpamSim *sim, const double *y, double *cmax);
/* Potential energy of the model's uniform gravity, -sum m g.(x - box corner), reduced
 * over the ranks (0 without gravity). */
PetscErrorCode SpamGravityEnergy(SpamSim *sim, const double *y, double *pot);
/* Summation density of state y into sim->pair.f.rho, ghost slots included (diagnostics): a
 * list update, then SpamDensityOfList (in the flow scheme with mirror walls, after the
 * ghosts' temperatures, which set the images' densities: gas_images.h). */
PetscErrorCode SpamDensitySummation(SpamSim *sim, const double *y, PetscInt *bad);
/* The same on the list as the caller's update left it, slots reserved (the tensor path,
 * which has updated the list for its own passes). Collective once distributed. */
PetscErrorCode SpamDensityOfList(SpamSim *sim);
/* Particles beyond a mirror wall after a step reflected back into the box (wall_reflect.c):
 * position mirrored in the wall, normal velocity reversed; *changed counts them. */
PetscErrorCode SpamWallReflect(SpamSim *sim, double *y, PetscInt *changed);
#endif
