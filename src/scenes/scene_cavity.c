/* The lid-driven cavity (Ghia, Ghia & Shin 1982, J. Comput. Phys. 48, 387): a viscous gas
 * in the square L x L between no-slip mirror walls on all four faces; the top wall (yhi)
 * slides along x at U, the others are at rest. The gas starts at rest on the unit square
 * lattice of n x n points at (i + 1/2, j + 1/2), so the walls lie half a spacing beyond the
 * outer rows and columns, the images continue the lattice, and L = n. The primary
 * parameters are those of the incompressible problem, the Reynolds number Re = U L / nu
 * (nu = eta / rho, rho = m on the unit lattice), and the Mach number U / c of the lid,
 * which sets how far the gas is from that problem (density changes of order Ma^2): the
 * scene gives the model the eta and e0 that make them. Ghia's centreline profiles are
 * those of the steady flow; docs/scenes/cavity.md compares a run with them. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;         /* lattice points per side: L = n                               */
  double   speed;     /* U of the lid                                                 */
  double   re, mach;  /* Reynolds number U L / nu and Mach number U / c              */
} SpamCavityParams;

static const SpamSceneOption Table[] = {
  {"cavity_n", SPAM_SCENE_OPTION_INT, "Lattice points per side: the cavity's side L = n between the walls (unit spacing, N = n^2)", NULL},
  {"cavity_lid_velocity", SPAM_SCENE_OPTION_REAL, "Speed U of the lid (the top wall, yhi) along +x: the default of -wall_yhi_velocity U,0", NULL},
  {"cavity_re", SPAM_SCENE_OPTION_REAL, "Reynolds number U L / nu: sets the default of -viscosity_shear, eta = rho U L / Re", NULL},
  {"cavity_mach", SPAM_SCENE_OPTION_REAL, "Mach number U / c of the lid: sets the default of -gas_e0, c^2 = gamma (gamma - 1) e0", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

#define FACE_TOP 3 /* yhi: the lid */

/* The lid's speed: the user's -wall_yhi_velocity, else -cavity_lid_velocity. */
static double LidSpeed(const SpamCommonParams *c, const SpamCavityParams *p)
{
  return c->walls.velocity_given[FACE_TOP] ? c->walls.velocity[FACE_TOP][0] : p->speed;
}

static PetscErrorCode CheckCavity(const SpamCommonParams *c, const SpamCavityParams *p)
{
  char val[64], hs[32];

  PetscFunctionBeginUser;
  (void)snprintf(hs, sizeof hs, "%g", c->h); /* PETSc's %g would print 3 as "3." */
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 2) SPAM_BAD_INPUT("-cavity_n", val, "must be at least 2 lattice points per side");
  if ((double)p->n < c->h) SPAM_BAD_INPUT("-cavity_n", val, "the cavity's side n must be at least h = %s (one mirror image per wall)", hs);
  PetscCall(SpamCheckParticleCount("-cavity_n", val, (double)p->n * (double)p->n));
  /* Beyond these ranges e0 = (U / Ma)^2 / (gamma (gamma - 1)) and eta = U L / Re leave the
   * numbers a run can step through (a step shrinks as h Ma / U and h^2 Re / (U L)). */
  PetscCall(SpamOptionText("-cavity_lid_velocity", p->speed, val, sizeof val));
  if (!(p->speed >= 1e-6 && p->speed <= 1e6)) SPAM_BAD_INPUT("-cavity_lid_velocity", val, "allowed: 1e-6 <= U <= 1e6 (the lid's speed along +x)");
  PetscCall(SpamOptionText("-cavity_re", p->re, val, sizeof val));
  if (!(p->re >= 1e-6 && p->re <= 1e6)) SPAM_BAD_INPUT("-cavity_re", val, "allowed: 1e-6 <= Re <= 1e6");
  PetscCall(SpamOptionText("-cavity_mach", p->mach, val, sizeof val));
  if (!(p->mach >= 1e-3 && p->mach < 1.0)) SPAM_BAD_INPUT("-cavity_mach", val, "allowed: 1e-3 <= Ma < 1 (the lid below the sound speed)");
  if (c->walls.velocity_given[FACE_TOP]) {
    const double U = LidSpeed(c, p);
    (void)snprintf(val, sizeof val, "%g,%g", c->walls.velocity[FACE_TOP][0], c->walls.velocity[FACE_TOP][1]);
    if (!(fabs(U) >= 1e-6 && fabs(U) <= 1e6)) SPAM_BAD_INPUT("-wall_yhi_velocity", val, "-scene cavity sets Re and Mach from the lid's speed: its x component must be from 1e-6 to 1e6 in size");
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamCavityOptions(const SpamCommonParams *c, SpamCavityParams *p)
{
  PetscBool set;
  char      val[64];

  PetscFunctionBeginUser;
  p->n     = 64;
  p->speed = 0.1;
  p->re    = 100.0;
  p->mach  = 0.1;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene cavity (lid-driven cavity; Ghia, Ghia & Shin 1982)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "cavity_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "cavity_lid_velocity", &p->speed, &set));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "cavity_re", &p->re, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "cavity_mach", &p->mach, NULL));
  PetscOptionsEnd();
  PetscCall(SpamOptionText("-cavity_lid_velocity", p->speed, val, sizeof val));
  if (set && c->walls.velocity_given[FACE_TOP]) SPAM_BAD_INPUT("-cavity_lid_velocity", val, "-wall_yhi_velocity is given too and sets the lid's velocity: give one of them");
  PetscCall(CheckCavity(c, p));
  PetscFunctionReturn(0);
}

/* The model's defaults: the gas with summed density (the images complete the sums at the
 * walls), and the eta and e0 of Re and Mach. gamma decides e0: peek at the model's option
 * (read again, and checked, with the model's options). */
static PetscErrorCode ModelDefaults(const SpamCommonParams *c, const SpamCavityParams *p, SpamSolidParams *solid)
{
  const double U = fabs(LidSpeed(c, p)), L = (double)p->n;
  double       gamma = solid->gamma;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-gas_gamma", &gamma, NULL));
  if (!(gamma > 1.0 && isfinite(gamma))) gamma = solid->gamma; /* refused later, one line */
  solid->shear_visc = solid->rho0 * U * L / p->re;
  solid->gas_e0     = (U / p->mach) * (U / p->mach) / (gamma * (gamma - 1.0));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  SpamSolidGasDefaults(c->mass, solid); /* unit square lattice: rho = m */
  PetscCall(SpamCavityOptions(c, p));
  PetscCall(ModelDefaults(c, p, solid));
  PetscFunctionReturn(0);
}

/* No-slip walls on the four faces where the user gave no condition; the lid's velocity
 * where the user gave none and the top wall is no-slip (a free-slip wall has none). */
static void CavityWalls(double U, SpamWalls *w)
{
  for (int f = 0; f < 4; f++)
    if (!w->slip_given[f]) w->slip[f] = SPAM_WALL_NOSLIP;
  if (w->slip[FACE_TOP] == SPAM_WALL_NOSLIP) w->velocity[FACE_TOP][0] = U;
}

static PetscErrorCode Report(const SpamCommonParams *c, const SpamCavityParams *p, const SpamSolidParams *s, SpamParticles *out)
{
  const double L = (double)p->n, U = LidSpeed(c, p), nu = s->shear_visc / s->rho0;
  const double cs = sqrt(s->gamma * (s->gamma - 1.0) * s->gas_e0);
  char         line[400];

  PetscFunctionBeginUser;
  (void)snprintf(line, sizeof line, "cavity: L = %g (%" PetscInt_FMT " x %" PetscInt_FMT " particles), lid U = %g, nu = %.6g, Re = U L / nu = %.6g, Mach U / c = %.4g, c h / nu = %.4g, L / U = %.6g, diffusion time L^2/nu = %.6g\n", L, p->n, p->n,
                 U, nu, fabs(U) * L / nu, fabs(U) / cs, cs * c->h / nu, L / fabs(U), L * L / nu);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  PetscCall(PetscStrncpy(out->info.name, "cavity", sizeof out->info.name));
  out->info.sound_traversal_time = L / cs;
  /* Ten lid transits: the primary vortex turns over several times. Whether the run is
   * steady shows in its kinetic energy (tests/run_cavity.py: its change over the last L/U). */
  out->info.t_end_default = 10.0 * L / fabs(U);
  PetscCall(SpamShearLatticeNote(c, s, "cavity"));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  const SpamCavityParams *q = p;
  const PetscInt          side[2] = {q->n, q->n};
  char                    val[64];

  PetscFunctionBeginUser;
  PetscCall(SpamSceneRequireGas("cavity", solid));
  (void)snprintf(val, sizeof val, "%g", solid->shear_visc);
  if (!(solid->shear_visc > 0.0)) SPAM_BAD_INPUT("-viscosity_shear", val, "-scene cavity needs a shear viscosity: its steady flow is set by Re = U L / nu");
  PetscCall(SpamParticlesAllocate(2, q->n * q->n, out));
  out->mass = c->mass;
  SpamLatticeSquare(2, side, out->x);
  out->box = (SpamBox){2, {0, 0, 0}, {(double)q->n, (double)q->n, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
  CavityWalls(LidSpeed(c, q), &out->walls);
  PetscCall(Report(c, q, solid, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneCavity(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"cavity", 4, PETSC_FALSE, Table, sizeof(SpamCavityParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
