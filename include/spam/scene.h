/* Scenes build the initial particles, the box and the model from options. */
#ifndef SPAM_SCENE_H
#define SPAM_SCENE_H
#include <spam/sim.h>
#include <spam/walls.h>
#include <stdint.h>

/* The columns a particle file can give (SpamParticles.columns): positions and velocities,
 * per-particle mass, energy per unit mass, density, stress and the particle id. */
#define SPAM_COLUMN_X      (1u << 0)
#define SPAM_COLUMN_V      (1u << 1)
#define SPAM_COLUMN_M      (1u << 2)
#define SPAM_COLUMN_E      (1u << 3)
#define SPAM_COLUMN_RHO    (1u << 4)
#define SPAM_COLUMN_STRESS (1u << 5)
#define SPAM_COLUMN_ID     (1u << 6)

/* Stress components per particle: D(D+1)/2 (1 in 1D, 3 in 2D, 6 in 3D). */
static inline int SpamStressComponents(int dim)
{
  return dim * (dim + 1) / 2;
}

/* splitmix64: a small generator whose stream depends only on the seed, so the scenes'
 * random perturbations reproduce on every platform. Returns a uniform number in [-1, 1). */
static inline double SpamSceneUniform(uint64_t *state)
{
  uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
  z          = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z          = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return 2.0 * ((double)(z >> 11) * 0x1.0p-53) - 1.0;
}

/* Particles as a scene makes them, before they go into the swarm. */
typedef struct {
  int           dim;
  PetscInt      n;
  double       *x, *v;   /* [n*dim] each                                         */
  /* Optional initial fields ([n], [n], [n D(D+1)/2]) or NULL; sigma per particle in the
   * order xx xy yy (2D), xx xy xz yy yz zz (3D: the upper triangle row by row), xx (1D). */
  double       *e, *rho, *sigma;
  double       *m;       /* [n] per-particle mass, or NULL: every particle has mass  */
  PetscInt     *id;      /* [n] particle ids, or NULL: ids are the input rows         */
  unsigned      columns; /* SPAM_COLUMN_* bits of the columns the input gave (0: a scene) */
  double        mass;
  SpamBox       box;
  SpamSceneInfo info;
  PetscBool     model_set; /* the scene declared its model; else the isentropic gas */
  SpamModel     model;
  /* Mirror walls of the box faces: the scene's defaults (set in its build, after
   * SpamParticlesAllocate), then overridden face by face by the options (c->walls: what
   * was given); a direction with a wall is not periodic. */
  SpamWalls     walls;
  /* The scene's default gravity (used when -gravity is not given; gravity_set). */
  double        gravity[3];
  PetscBool     gravity_set;
} SpamParticles;

/* Options shared by every scene. */
typedef struct {
  int       dim;
  double    h, mass, skin, gamma, kappa;
  double    box_lo[3], box_len[3];
  PetscBool box_len_set;
  PetscBool periodic[3];
  double    translate[3];
  PetscInt  threads;     /* OpenMP threads of the pair passes                        */
  SpamKernel kernel;     /* -kernel at -h in -dim                                    */
  double    gravity[3];  /* -gravity                                                 */
  PetscBool gravity_given; /* -gravity was given (else a scene may set its own default) */
  SpamWalls walls;       /* -wall_* (walls.h)                                         */
  PetscBool periodic_ghosts; /* -periodic_images ghost                               */
  PetscBool reproducible;    /* -reproducible (the isentropic gas; the adaptive-range gas) */
} SpamCommonParams;

/* A gas channel between mirror walls at y = 0 and y = H (couette, poiseuille): a square
 * lattice of unit spacing, n rows across, nx columns along the periodic x (and z in 3D). */
typedef struct {
  PetscInt  n, nx;        /* rows across (H = n), columns along x and z (0: automatic)   */
  double    speed;        /* couette: U of the upper wall; poiseuille: the peak speed    */
  PetscBool steady_start; /* start on the exact steady profile instead of at rest        */
} SpamShearParams;

/* What a scene's option is: how it is read and how option_use.c checks the given value
 * (an integer within PetscInt, a list without an empty element, a boolean takes no value). */
typedef enum {
  SPAM_SCENE_OPTION_INT,
  SPAM_SCENE_OPTION_REAL,
  SPAM_SCENE_OPTION_BOOL,
  SPAM_SCENE_OPTION_STRING,
  SPAM_SCENE_OPTION_REALS, /* a list of reals */
  SPAM_SCENE_OPTION_BOOLS  /* a list of booleans */
} SpamSceneOptionType;

/* One option a scene takes. The scene reads it through SpamSceneOption* below, which find
 * it here by name (reading an option not in the table is an error), so -help shows this
 * help with the scene's default; option_use.c accepts the option for the scenes whose
 * tables hold it and refuses it for the others, naming them. help NULL: the common options
 * read it (scene.c: -box_lo, -box_len, -periodic), the table says which scenes use it. */
typedef struct {
  const char         *name; /* without the leading '-' */
  SpamSceneOptionType type;
  const char         *help;
  const char         *note; /* added after another scene's name when refused, or NULL */
} SpamSceneOption;

/* A scene: one file holds it (its descriptor function is a row of scene_list.h). It reads
 * its own options into its params (params_size bytes, allocated and zeroed by scene.c; the
 * struct is the scene's own) and the defaults of the model it is made for into solid
 * (material, Lame constants, density choices); the model itself is then read from the
 * options for every scene, and build makes the particles (geometry and initial state) with
 * the model's parameters. */
typedef struct {
  const char  *name;
  int          dims;      /* bit d set: the scene exists in d dimensions              */
  PetscBool    own_model; /* the scene's particles carry their model (springs)        */
  const SpamSceneOption *options_table; /* its options, ended by a row with name NULL */
  size_t       params_size;
  PetscBool    sorted;    /* -sort_particles defaults to true (rows come in any order) */
  const char  *box_size;  /* what sets the box, for a box too small for h: NULL "the lattice size" */
  PetscErrorCode (*options)(const SpamCommonParams *c, void *p, SpamSolidParams *solid);
  PetscErrorCode (*build)(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out);
} SpamSceneOps;
typedef PetscErrorCode (*SpamSceneOpsFn)(SpamSceneOps *ops);

/* The scenes of scene_list.h, in its order: how many, the i-th one's descriptor, and the
 * list by name that -scene chooses from. */
int            SpamSceneCount(void);
PetscErrorCode SpamSceneGet(int i, SpamSceneOps *ops);
PetscErrorCode SpamSceneRegisterAll(PetscFunctionList *list);

/* A scene's option read from the options database by its row of table (inside
 * PetscOptionsBegin/End, whose PetscOptionsObject is passed): -name with the row's help,
 * *value the default on entry. A name not in table, or of another type, is an error. */
PetscErrorCode SpamSceneOptionInt(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, PetscInt *value, PetscBool *set);
PetscErrorCode SpamSceneOptionReal(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, double *value, PetscBool *set);
/* The same with the help made at run time (it names the values of other options). */
PetscErrorCode SpamSceneOptionRealHelp(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, const char *help, double *value, PetscBool *set);
PetscErrorCode SpamSceneOptionBool(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, PetscBool *value, PetscBool *set);
PetscErrorCode SpamSceneOptionString(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, char *value, size_t len, PetscBool *set);
/* The row of table named name (case as PETSc: ignored), or NULL. */
const SpamSceneOption *SpamSceneOptionFind(const SpamSceneOption *table, const char *name);

/* Why v cannot be a particle mass or a length such as h: NULL when it is a positive, finite,
 * normal number. A subnormal one is refused as too small: a mass of 4.9e-324 gives zero
 * energies and a NaN entropy. -mass and the particle files (CSV and HDF5) share it. */
const char *SpamPositiveNormalProblem(double v);

/* The shear channels' common part (shear_channel.c): the gas model's defaults (shear
 * viscosity 1, summed density of the unit lattice), the options -NAME_speed, -NAME_n,
 * -NAME_nx and -NAME_start (start names the steady profile) from the scene's table, and
 * the lattice at rest in its box with no-slip walls on the y faces the user left alone. */
void           SpamShearChannelDefaults(const SpamCommonParams *c, SpamSolidParams *solid);
PetscErrorCode SpamShearChannelOptions(const SpamCommonParams *c, const char *name, const char *start, const SpamSceneOption *table, SpamShearParams *p);
PetscErrorCode SpamShearChannelBuild(const SpamCommonParams *c, const char *name, const SpamShearParams *p, SpamParticles *out);
/* The kinematic viscosity eta/rho0 and sound speed of the channel's gas; bad input (naming
 * -NAME_speed) unless the viscosity is positive and |speed| below the sound speed. */
PetscErrorCode SpamShearChannelCheck(const char *name, const SpamShearParams *p, const SpamSolidParams *solid, double *nu, double *c);
/* The note a run of a viscous-gas lattice scene prints where its lattice is known to
 * rearrange at rest (the Lucy kernel under the plain scheme). */
PetscErrorCode SpamShearLatticeNote(const SpamCommonParams *c, const SpamSolidParams *solid, const char *name);

/* Triangular lattices of unit spacing a: nx x ny rows filling a periodic box
 * (nx a) x (ny sqrt(3)/2 a); and the hexagon of n shells about the origin (vertices on
 * the x axis at distance n a), 1 + 3n + 3n^2 points. x has room for the points. */
void     SpamLatticeTriangular(PetscInt nx, PetscInt ny, double a, double *x);
PetscInt SpamLatticeHexagon(PetscInt n, double a, double *x);
/* The unit simple-cubic lattice of n[0] x ... x n[dim-1] points at (i + 1/2, j + 1/2, ...),
 * x fastest, filling the box [0, n[0]) x ...; x has room for the points. */
void     SpamLatticeSquare(int dim, const PetscInt n[], double *x);
/* n^dim particles of mass m allocated into out on that lattice, n points a side. */
PetscErrorCode SpamLatticeCube(int dim, PetscInt n, double mass, SpamParticles *out);
/* The solid's defaults (PRE): lambda = eta = sqrt(3)/4, rho0 = sqrt(4/3), continuity
 * density from the ideal value, R0, eps 1, no angular-momentum treatment. */
void SpamSolidDefaults(SpamSolidParams *p);
/* The gas scenes' defaults: -material gas with the summed density (from the start) and the
 * reference density rho0; and their check that the run kept the gas (bad input otherwise). */
void           SpamSolidGasDefaults(double rho0, SpamSolidParams *p);
PetscErrorCode SpamSceneRequireGas(const char *scene, const SpamSolidParams *p);
/* -smoothing_length adaptive against the rest of the run (smoothing_options.c): the laws,
 * ranks, walls, periodic edges and options it does not take yet are refused in one line. */
PetscErrorCode SpamSmoothingCheck(const SpamCommonParams *c, const SpamParticles *p, const SpamSolidParams *s, PetscMPIInt size);
/* Allocates the optional fields e, rho, sigma of p. */
PetscErrorCode SpamParticlesAllocateFields(SpamParticles *p);
/* Open box around the particles with a margin (non-periodic). */
void SpamParticlesOpenBox(SpamParticles *p, double margin);
/* Copies the optional fields of p into the swarm where the layout has them. */
PetscErrorCode SpamSimFillFields(SpamSim *sim, const SpamParticles *p);
/* The file scene's HDF5 input: the program's own snapshot (scene_file_hdf5.c). */
PetscErrorCode SpamFileIsHdf5(const char *path, PetscBool *hdf5);
PetscErrorCode SpamFileReadHdf5(const SpamCommonParams *c, const char *path, SpamParticles *out);
/* Columns of a particle file against the model (particle_columns.c): a column the layout
 * cannot hold (e without l->e, rho without l->rho, stress without l->s) is bad input
 * naming the column and the model. */
PetscErrorCode SpamParticlesCheckColumns(const SpamParticles *p, const SpamLayout *l);
PetscErrorCode SpamParticlesAllocate(int dim, PetscInt n, SpamParticles *p);
/* The largest particle count a run can hold here: state indices within PetscInt and a
 * lower bound of the bytes per particle within the physical memory (scene_size.c). A
 * count asked for by option opt = val (computed in double) above it is bad input. */
double         SpamMaxParticles(void);
PetscErrorCode SpamCheckParticleCount(const char *opt, const char *val, double count);
PetscErrorCode SpamParticlesFree(SpamParticles *p);
/* Reorders the particles (and their optional fields) by cells of the given width, row by
 * row in 1D and 2D and along a Morton curve in 3D; row_of[i] ([n]) receives the input
 * row of the particle now at i. */
PetscErrorCode SpamParticlesSortByCell(SpamParticles *p, double width, PetscInt *row_of);

/* Reads -scene and every option of the chosen scene, builds the particles and creates the
 * simulation with its state vector. With -help, lists the options of every scene. */
PetscErrorCode SpamSceneCreateSim(MPI_Comm comm, SpamSim *sim);
#endif
