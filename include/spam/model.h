/* The model: which physics a scene switches on. It fixes the state layout and which
 * right-hand-side passes run. */
#ifndef SPAM_MODEL_H
#define SPAM_MODEL_H
#include <spam/kernel.h>
#include <spam/layout.h>
#include <spam/eos.h>
#include <spam/solid.h>
#include <spam/diffusion_jacobian.h>

struct SpamSim;

/* The right-hand side of a model: ydot = f(y) on raw arrays of n*nvar reals. Sets *bad to
 * the first particle with a non-finite or unphysical state (else -1) and returns 0. */
typedef PetscErrorCode (*SpamRhsFn)(struct SpamSim *sim, const double *y, double *ydot, PetscInt *bad);
/* Which terms an evaluation returns, for a method that treats the diffusion apart (IMEX):
 * all of them; all but the diffusion; the diffusion alone (the pair Laplacians of
 * viscosity and conduction in the velocity and energy rows, with the viscous force's
 * work). The last two sum to the first, up to round-off. */
typedef enum { SPAM_RHS_ALL, SPAM_RHS_EXPLICIT, SPAM_RHS_DIFFUSION } SpamRhsPart;
typedef PetscErrorCode (*SpamRhsPartFn)(struct SpamSim *sim, const double *y, double *ydot, SpamRhsPart part, PetscInt *bad);
/* The diffusion part's Jacobian at state y, into jac (diffusion_jacobian.h). */
typedef PetscErrorCode (*SpamDiffusionJacFn)(struct SpamSim *sim, const double *y, SpamDiffusionJac *jac, PetscInt *bad);
/* The right-hand side restricted to the particles marked in active (one byte per local
 * particle): their rows of ydot, as the full evaluation would give them up to round-off;
 * the other rows untouched. near: scratch of two bytes per local particle. *done false
 * (nothing written) where the state needs the full evaluation (a rank's own ghost slots:
 * walls, periodic images), the same on every rank; collective on several ranks. */
typedef PetscErrorCode (*SpamRhsActiveFn)(struct SpamSim *sim, const double *y, double *ydot, const unsigned char *active, unsigned char *near, PetscBool *done, PetscInt *bad);
/* Accelerations from positions alone, into sim->acc (models whose state is r and v only:
 * the force half of a symplectic split). x has stride 'stride' between particles. */
typedef PetscErrorCode (*SpamAccelFn)(struct SpamSim *sim, const double *x, int stride, PetscInt *bad);

/* Largest sound speed of state y (for the CFL step bound and the error weights). */
typedef PetscErrorCode (*SpamSoundSpeedFn)(struct SpamSim *sim, const double *y, double *cmax);
/* Model-specific diagnostics of state y: the internal energy sum m e (or the potential
 * energy of a molecular model), the spurious torque sum_{i<j} Ldot_ij before any
 * scaling (0 where the forces are central, NaN where not computed), and the bodies. The
 * summed density of y is in sim->pair.f.rho when it is called. */
typedef struct {
  double internal, torque;
  double potential;       /* energy of the external field (gravity), else 0              */
  int    nbody;           /* connected bodies labelled at set-up (0: none)               */
  double lbody[2];        /* Lz of bodies 0 and 1 about their own centres (NaN: n/a)     */
  double gauss_singular;  /* evaluations where Gauss's principle was singular            */
} SpamModelDiag;
typedef PetscErrorCode (*SpamModelDiagFn)(struct SpamSim *sim, const double *y, SpamModelDiag *d);
/* A jump of state y between steps (closest-approach reflection): sets *changed to the
 * number of particles or pairs it altered. The driver then restarts the integrator, whose
 * history (FSAL stage, Adams differences) belongs to the state before the jump. */
typedef PetscErrorCode (*SpamPostStepFn)(struct SpamSim *sim, double *y, PetscInt *changed);
/* Data a model keeps per particle outside the state vector (the springs' bonds), carried
 * through a migration: depart before the particles leave (their gids and local order the
 * old ones; dest[i] the rank particle i goes to), arrive once the arrived particles are in
 * their new local order. Both collective. */
typedef PetscErrorCode (*SpamCarryDepartFn)(struct SpamSim *sim, const PetscInt *dest);
typedef PetscErrorCode (*SpamCarryArriveFn)(struct SpamSim *sim);
/* Set-up once the swarm is filled (scratch, bodies, bond lists, initial density). */
typedef PetscErrorCode (*SpamModelSetUpFn)(struct SpamSim *sim);

typedef struct {
  double k, r0, range; /* spring constant, rest length, bonding range at set-up */
} SpamSpringParams;

typedef struct {
  char             name[32];     /* e.g. "isentrope"                                  */
  SpamRhsFn        rhs;
  SpamRhsPartFn    rhs_part;     /* NULL: the model has no diffusion to treat apart     */
  SpamDiffusionJacFn diffusion_jac; /* with rhs_part: that part's Jacobian (a preconditioner's) */
  SpamRhsActiveFn  rhs_active;   /* NULL: no pass restricted to active particles        */
  SpamAccelFn      accel;        /* NULL unless the state is exactly [x, v]            */
  SpamSoundSpeedFn max_sound_speed;
  int              dim;
  double           mass;         /* the particles' mass when they share one            */
  double           gravity[3];   /* uniform acceleration g (-gravity)                   */
  PetscBool        gravity_on;
  SpamKernel       kernel;
  SpamKernel       shift_kernel; /* the flow scheme's transport shift: the kernel, or Wendland C2 (model_tensor.c) */
  SpamEosIsentrope eos;
  PetscBool        density_free; /* force pass only, no density pass */
  PetscBool        tensor;       /* the tensor path (rhs_tensor.c) and its field arrays */
  PetscBool        inverse_mass; /* outside the tensor path, the pair passes read 1/m */
  PetscBool        energy_given; /* the input set e per particle (else the gas's e0)    */
  SpamLayout       layout;
  SpamSolidParams  solid;        /* elastic solid: the tensor-path choices             */
  SpamSpringParams springs;      /* molecular springs (rotor-md)                       */
  SpamModelDiagFn  diag;
  SpamModelSetUpFn setup;        /* NULL: nothing beyond SpamSimSetUp                   */
  SpamPostStepFn   post_step;    /* NULL: the state never jumps                          */
  SpamCarryDepartFn carry_depart; /* NULL: nothing per particle outside the state      */
  SpamCarryArriveFn carry_arrive;
} SpamModel;

/* One setting of a model, for outputs (summary.json, snapshot attributes): a number, or
 * a string when str is set. */
typedef struct {
  const char *key, *str;
  double      num;
} SpamSetting;
#define SPAM_MAX_SETTINGS 32
/* The settings of model m (its name, kernel, gravity and the parameters of its laws) into
 * s[SPAM_MAX_SETTINGS]; returns how many. Outputs print these rather than reading the
 * model's internals. */
int SpamModelSettings(const SpamModel *m, SpamSetting *s);

PetscErrorCode SpamModelIsentropeSetUp(int dim, const SpamKernel *kernel, double mass, double gamma, double kappa, SpamModel *m);
/* The tensor path (PRE Secs. I-II) with the choices in p: the linear elastic solid or the
 * gas with the energy equation, in 1D to 3D. */
PetscErrorCode SpamModelSolidSetUp(int dim, const SpamKernel *kernel, double mass, const SpamSolidParams *p, SpamModel *m);
/* The neighbour list's range: h, or with the adaptive range the upper bound of every h_i. */
double SpamModelListRange(const SpamModel *m);
/* Whether the model's gas takes the adaptive kernel range (each particle its own h_i). */
PetscBool SpamModelAdaptive(const SpamModel *m);
/* Molecular dynamics with springs phi = k/2 (r0 - r)^2 between the particles closer than
 * bond_range at set-up (the rotor-md of PRE Fig. 4a); state [x, v]. */
PetscErrorCode SpamModelSpringsSetUp(int dim, double h, double mass, double kspring, double r0, double bond_range, SpamModel *m);
#endif
