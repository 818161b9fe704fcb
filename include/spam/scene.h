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
  PetscBool reproducible;    /* -reproducible (the isentropic gas only)               */
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

typedef struct {
  PetscInt  nx, ny;     /* lattice columns and rows (ny even: periodic)            */
  PetscBool longitudinal;
  double    amplitude;
  PetscBool continuum_stress; /* -planewave_stress continuum: Hooke(grad u), not SPAM's */
  SpamSolidParams solid;
} SpamPlanewaveParams;

typedef struct {
  PetscInt  n;          /* shells: N = 1 + 3n + 3n^2                                */
  double    speed;      /* speed of the vertices                                    */
  double    gap;        /* rotor-pair: gap between the two hexagons                 */
  PetscBool pair;
  SpamSolidParams solid;
} SpamRotorParams;

typedef struct {
  PetscInt n;
  double   speed, k, range;
} SpamRotorMdParams;

typedef struct {
  PetscInt n;          /* particles of the ring (even)                               */
  double   k, amplitude;
} SpamChainParams;

typedef struct {
  PetscInt nx, ny;
  double   stress, kick;
  SpamSolidParams solid;
} SpamTensileParams;

typedef struct {
  PetscInt  nx, ny;     /* square lattice of unit spacing: the cell is nx x ny       */
  double    ra, prandtl; /* Rayleigh number (superadiabatic) and Prandtl number       */
  double    g;          /* gravity of the hydrostatic start (and of the run by default) */
  double    t_bottom, t_top; /* the wall temperatures T_b, T_t (-wall_ylo/yhi_temperature) */
  double    amplitude;  /* size of the seeded random velocities                       */
  PetscInt  seed;
  SpamSolidParams solid;
} SpamConvectionParams;

typedef struct {
  PetscInt n;      /* lattice spacings per unit length of the classical tube            */
  double   length; /* tube length in those units (periodic)                             */
  PetscInt width;  /* lattice points across the tube in each transverse direction       */
} SpamSodParams;

typedef struct {
  PetscInt n;      /* lattice points per direction of the periodic box                  */
  double   energy; /* blast energy E0                                                   */
} SpamSedovParams;

typedef struct {
  PetscInt n;          /* particles per row of the triangular lattice                */
  double   p0;         /* pressure at the vortex centre (standard: 5)                */
} SpamGreshoParams;

typedef struct {
  PetscInt n;          /* lattice points per direction: the box edge L               */
  double   amplitude;  /* velocity amplitude U                                       */
} SpamTaylorGreenParams;

typedef struct {
  PetscInt n, ny;      /* lattice points along x (the wavelength L) and across       */
  double   eps;        /* relative amplitude of the energy mode                      */
} SpamHeatModeParams;

/* A gas channel between mirror walls at y = 0 and y = H (couette, poiseuille): a square
 * lattice of unit spacing, n rows across, nx columns along the periodic x (and z in 3D). */
typedef struct {
  PetscInt  n, nx;        /* rows across (H = n), columns along x and z (0: automatic)   */
  double    speed;        /* couette: U of the upper wall; poiseuille: the peak speed    */
  PetscBool steady_start; /* start on the exact steady profile instead of at rest        */
} SpamShearParams;

/* The lid-driven cavity: the unit square lattice of n x n points between no-slip walls,
 * the top one (the lid) sliding at U along x; Re and Mach set the gas's eta and e0. */
typedef struct {
  PetscInt n;         /* lattice points per side: L = n                               */
  double   speed;     /* U of the lid                                                 */
  double   re, mach;  /* Reynolds number U L / nu and Mach number U / c              */
} SpamCavityParams;

/* Every scene's parameters (a new scene adds its struct here). */
typedef union {
  SpamExpansionParams expansion;
  SpamFileParams      file;
  SpamPlanewaveParams planewave;
  SpamRotorParams     rotor;
  SpamRotorMdParams   rotor_md;
  SpamChainParams     chain;
  SpamTensileParams   tensile;
  SpamConvectionParams convection;
  SpamSodParams       sod;
  SpamSedovParams     sedov;
  SpamGreshoParams      gresho;
  SpamTaylorGreenParams taylor_green;
  SpamHeatModeParams    heat_mode;
  SpamShearParams     couette, poiseuille;
  SpamCavityParams    cavity;
} SpamSceneParams;

/* A scene, registered by name (scene_list.c): it reads its own options into p and the
 * defaults of the model it is made for into solid (material, Lame constants, density
 * choices); the model itself is then read from the options for every scene, and build
 * makes the particles (geometry and initial state) with the model's parameters. */
typedef struct {
  const char  *name;
  int          dims;      /* bit d set: the scene exists in d dimensions              */
  PetscBool    own_model; /* the scene's particles carry their model (springs)        */
  PetscErrorCode (*options)(const SpamCommonParams *c, SpamSceneParams *p, SpamSolidParams *solid);
  PetscErrorCode (*build)(const SpamCommonParams *c, const SpamSceneParams *p, const SpamSolidParams *solid, SpamParticles *out);
} SpamSceneOps;
typedef PetscErrorCode (*SpamSceneOpsFn)(SpamSceneOps *ops);

/* The registered scenes (one line each in scene_list.c). */
/* Why v cannot be a particle mass or a length such as h: NULL when it is a positive, finite,
 * normal number. A subnormal one is refused as too small: a mass of 4.9e-324 gives zero
 * energies and a NaN entropy. -mass and the particle files (CSV and HDF5) share it. */
const char *SpamPositiveNormalProblem(double v);
PetscErrorCode SpamSceneRegisterAll(PetscFunctionList *list);
PetscErrorCode SpamSceneExpansion(SpamSceneOps *ops);
PetscErrorCode SpamSceneFile(SpamSceneOps *ops);
PetscErrorCode SpamSceneChain(SpamSceneOps *ops);
PetscErrorCode SpamScenePlanewave(SpamSceneOps *ops);
PetscErrorCode SpamSceneRotor(SpamSceneOps *ops);
PetscErrorCode SpamSceneRotorPair(SpamSceneOps *ops);
PetscErrorCode SpamSceneRotorMd(SpamSceneOps *ops);
PetscErrorCode SpamSceneTensile(SpamSceneOps *ops);
PetscErrorCode SpamSceneConvection(SpamSceneOps *ops);
PetscErrorCode SpamSceneSod(SpamSceneOps *ops);
PetscErrorCode SpamSceneSedov(SpamSceneOps *ops);
PetscErrorCode SpamSceneGresho(SpamSceneOps *ops);
PetscErrorCode SpamSceneTaylorGreen(SpamSceneOps *ops);
PetscErrorCode SpamSceneHeatMode(SpamSceneOps *ops);
PetscErrorCode SpamSceneCouette(SpamSceneOps *ops);
PetscErrorCode SpamScenePoiseuille(SpamSceneOps *ops);
PetscErrorCode SpamSceneCavity(SpamSceneOps *ops);

/* The shear channels' common part (shear_channel.c): the gas model's defaults (shear
 * viscosity 1, summed density of the unit lattice), the options -NAME_speed (speed_help
 * says what it is), -NAME_n, -NAME_nx and -NAME_start (start names the steady profile), and
 * the lattice at rest in its box with no-slip walls on the y faces the user left alone. */
void           SpamShearChannelDefaults(const SpamCommonParams *c, SpamSolidParams *solid);
PetscErrorCode SpamShearChannelOptions(const SpamCommonParams *c, const char *name, const char *start, const char *speed_help, SpamShearParams *p);
PetscErrorCode SpamShearChannelBuild(const SpamCommonParams *c, const char *name, const SpamShearParams *p, SpamParticles *out);
/* The kinematic viscosity eta/rho0 and sound speed of the channel's gas; bad input (naming
 * -NAME_speed) unless the viscosity is positive and |speed| below the sound speed. */
PetscErrorCode SpamShearChannelCheck(const char *name, const SpamShearParams *p, const SpamSolidParams *solid, double *nu, double *c);

/* Triangular lattices of unit spacing a: nx x ny rows filling a periodic box
 * (nx a) x (ny sqrt(3)/2 a); and the hexagon of n shells about the origin (vertices on
 * the x axis at distance n a), 1 + 3n + 3n^2 points. x has room for the points. */
void     SpamLatticeTriangular(PetscInt nx, PetscInt ny, double a, double *x);
PetscInt SpamLatticeHexagon(PetscInt n, double a, double *x);
/* The unit simple-cubic lattice of n[0] x ... x n[dim-1] points at (i + 1/2, j + 1/2, ...),
 * x fastest, filling the box [0, n[0]) x ...; x has room for the points. */
void     SpamLatticeSquare(int dim, const PetscInt n[], double *x);
/* The solid's defaults (PRE): lambda = eta = sqrt(3)/4, rho0 = sqrt(4/3), continuity
 * density from the ideal value, R0, eps 1, no angular-momentum treatment. */
void SpamSolidDefaults(SpamSolidParams *p);
/* The gas scenes' defaults: -material gas with the summed density (from the start) and the
 * reference density rho0; and their check that the run kept the gas (bad input otherwise). */
void           SpamSolidGasDefaults(double rho0, SpamSolidParams *p);
PetscErrorCode SpamSceneRequireGas(const char *scene, const SpamSolidParams *p);
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
