/* Rayleigh-Benard convection (Hoover & Hoover 2001, CiSE, Fig. 4): an ideal gas
 * (P = (gamma - 1) rho e, T = (gamma - 1) e, k = m = 1) with Newtonian viscosity and heat
 * conduction fills a cell L x H, periodic in x, between no-slip isothermal mirror walls:
 * hot (T_b) at y = 0, cold (T_t) at y = H, under gravity (0, -g). The gas starts in the
 * conduction state, T(y) = T_b - (T_b - T_t) y / H, in hydrostatic balance dP/dy = -rho g
 * with P = rho T: P = P_b (T / T_b)^(g H / (T_b - T_t)) (rho ~ exp(-g y / T) when
 * T_b = T_t). Particles sit on a square lattice of unit spacing with masses
 * m_i = rho(y_i) x (cell area): the lattice stays regular, so every particle has the same
 * neighbours within h, the kernel sums have the same discretisation error at every height,
 * and the walls' mirror images (half a spacing beyond each wall) continue the lattice. (Equal
 * masses on rows spaced by the cumulative mass would make the spacing, hence h in
 * spacings, vary with height.) Small seeded random velocities start the rolls.
 * The primary parameters are the Rayleigh and Prandtl numbers: the viscosity and
 * conductivity the scene gives the model by default are those that make
 *   Ra = g alpha dT H^3 / (nu chi),  alpha = 1 / T_mean,  nu = eta / rho_mean,
 *   chi = kappa / (rho_mean c_p),  c_p = gamma / (gamma - 1),  Pr = nu / chi,
 * with dT the superadiabatic difference T_b - T_t - g H / c_p (Schwarzschild): the part of
 * the temperature difference a compressible gas can convect. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt  nx, ny;     /* square lattice of unit spacing: the cell is nx x ny       */
  double    ra, prandtl; /* Rayleigh number (superadiabatic) and Prandtl number       */
  double    g;          /* gravity of the hydrostatic start (and of the run by default) */
  double    t_bottom, t_top; /* the wall temperatures T_b, T_t (-wall_ylo/yhi_temperature) */
  double    amplitude;  /* size of the seeded random velocities                       */
  PetscInt  seed;
  SpamSolidParams solid;
} SpamConvectionParams;

static const SpamSceneOption Table[] = {
  {"convection_nx", SPAM_SCENE_OPTION_INT, "Lattice columns: the cell's width L (unit spacing; periodic in x; L = 2H holds one pair of rolls)", NULL},
  {"convection_ny", SPAM_SCENE_OPTION_INT, "Lattice rows: the cell's height H between the walls", NULL},
  {"convection_ra", SPAM_SCENE_OPTION_REAL, "Rayleigh number of the superadiabatic difference T_b - T_t - gH/c_p (T_b, T_t: -wall_ylo_temperature, -wall_yhi_temperature); onset 1707.76", NULL},
  {"convection_prandtl", SPAM_SCENE_OPTION_REAL, "Prandtl number nu/chi: with Ra it sets the defaults of -viscosity_shear and -conductivity", NULL},
  {"convection_g", SPAM_SCENE_OPTION_REAL, "Gravity g of the hydrostatic start and of Ra (the run's too, unless -gravity is given) (default 0.1 c_p / H)", NULL},
  {"convection_amplitude", SPAM_SCENE_OPTION_REAL, "Size of the seeded random velocities that start the rolls (units of the sound speed at T = 1)", NULL},
  {"convection_seed", SPAM_SCENE_OPTION_INT, "Seed of the random velocities", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

#define RA_CRITICAL 1707.76 /* rigid-rigid onset (Boussinesq), at k_c = 3.117 / H */
#define FACE_BOTTOM 2       /* ylo */
#define FACE_TOP    3       /* yhi */

static double HeatCapacity(double gamma)
{
  return gamma / (gamma - 1.0);
}

/* The superadiabatic temperature difference T_b - T_t - g H / c_p. */
static double Superadiabatic(const SpamConvectionParams *p, double gamma)
{
  return p->t_bottom - p->t_top - p->g * (double)p->ny / HeatCapacity(gamma);
}

/* The wall temperatures: the user's -wall_ylo_temperature and -wall_yhi_temperature, else
 * the scene's (T_b = 1.25, T_t = 0.75 about T_mean = 1). */
static void WallTemperatures(const SpamCommonParams *c, SpamConvectionParams *p)
{
  p->t_bottom = c->walls.temperature_given[FACE_BOTTOM] ? c->walls.temperature[FACE_BOTTOM] : 1.25;
  p->t_top    = c->walls.temperature_given[FACE_TOP] ? c->walls.temperature[FACE_TOP] : 0.75;
}

static PetscErrorCode CheckConvection(const SpamConvectionParams *p)
{
  char val[128];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->nx));
  if (p->nx < 1) SPAM_BAD_INPUT("-convection_nx", val, "must be a positive number of lattice columns");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->ny));
  if (p->ny < 1) SPAM_BAD_INPUT("-convection_ny", val, "must be a positive number of lattice rows");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT " x %" PetscInt_FMT, p->nx, p->ny));
  PetscCall(SpamCheckParticleCount("-convection_nx x -convection_ny", val, (double)p->nx * (double)p->ny));
  PetscCall(SpamOptionText("-convection_ra", p->ra, val, sizeof val));
  if (!(p->ra >= 1e-6 && p->ra <= 1e12)) SPAM_BAD_INPUT("-convection_ra", val, "allowed: 1e-6 <= Ra <= 1e12");
  PetscCall(SpamOptionText("-convection_prandtl", p->prandtl, val, sizeof val));
  if (!(p->prandtl >= 1e-6 && p->prandtl <= 1e6)) SPAM_BAD_INPUT("-convection_prandtl", val, "allowed: 1e-6 <= Pr <= 1e6");
  PetscCall(SpamOptionText("-convection_g", p->g, val, sizeof val));
  if (!(p->g >= 1e-12 && p->g <= 1e6)) SPAM_BAD_INPUT("-convection_g", val, "allowed: 1e-12 <= g <= 1e6 (the hydrostatic start and Ra need gravity)");
  /* The top of the column must keep a positive pressure: the conduction state's density
   * falls as T^(gH/dT - 1), exp(-g y / T) when isothermal; 700 e-foldings is the end of double. */
  if (p->t_bottom > p->t_top ? (p->g * p->ny / (p->t_bottom - p->t_top)) * log(p->t_bottom / p->t_top) > 700.0 : p->g * p->ny / p->t_bottom > 700.0)
    SPAM_BAD_INPUT("-convection_g", val, "too strong for this cell: the hydrostatic density would fall by more than e^700 over the height");
  PetscCall(SpamOptionText("-convection_amplitude", p->amplitude, val, sizeof val));
  if (!(p->amplitude >= 0.0 && p->amplitude <= 1.0)) SPAM_BAD_INPUT("-convection_amplitude", val, "allowed: 0 <= amplitude <= 1 (velocity, in units of the sound speed at T = 1)");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamConvectionOptions(const SpamCommonParams *c, SpamConvectionParams *p)
{
  char help[256];

  PetscFunctionBeginUser;
  p->nx        = 32;
  p->ny        = 16;
  p->ra        = 5.0 * RA_CRITICAL;
  p->prandtl   = 1.0;
  p->amplitude = 0.01;
  p->seed      = 1;
  WallTemperatures(c, p);
  SpamSolidDefaults(&p->solid);
  /* gamma decides c_p, hence the adiabatic gradient and chi: peek at the model's option
   * (read again, and checked, with the model's options). */
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-gas_gamma", &p->solid.gamma, NULL));
  if (!(p->solid.gamma > 1.0 && isfinite(p->solid.gamma))) p->solid.gamma = 2.0; /* refused later, one line */
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene convection (Hoover & Hoover 2001, Fig. 4)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "convection_nx", &p->nx, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "convection_ny", &p->ny, NULL));
  PetscOptionsEnd();
  p->g = 0.1 * HeatCapacity(p->solid.gamma) / (double)PetscMax(p->ny, 1);
  (void)snprintf(help, sizeof help, "Rayleigh number of the superadiabatic difference T_b - T_t - gH/c_p (T_b, T_t: -wall_ylo_temperature, -wall_yhi_temperature, here %g and %g); onset 1707.76", p->t_bottom, p->t_top);
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene convection: Rayleigh number, gravity and seed", "spam-ark");
  PetscCall(SpamSceneOptionRealHelp(PetscOptionsObject, Table, "convection_ra", help, &p->ra, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "convection_prandtl", &p->prandtl, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "convection_g", &p->g, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "convection_amplitude", &p->amplitude, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "convection_seed", &p->seed, NULL));
  PetscOptionsEnd();
  PetscCall(CheckConvection(p));
  PetscFunctionReturn(0);
}

/* The model's defaults: the gas with the energy equation, summation density (mirror
 * images complete the sums at the walls), and the eta and kappa of Ra and Pr. A column
 * with no superadiabatic difference (isothermal, or stable) cannot set them from Ra: it
 * takes those of the default cell's difference, 0.5 - 0.1 = 0.4 (T_mean units), at this Ra. */
static void ModelDefaults(const SpamCommonParams *c, SpamConvectionParams *p)
{
  const double cp = HeatCapacity(p->solid.gamma), H = (double)p->ny, rho_mean = c->mass;
  const double t_mean = 0.5 * (p->t_bottom + p->t_top), dt_sa = Superadiabatic(p, p->solid.gamma);
  const double dt     = dt_sa > 0.0 ? dt_sa : 0.4 * t_mean;
  const double nu     = sqrt(p->g * dt / t_mean * H * H * H * p->prandtl / p->ra), chi = nu / p->prandtl;

  p->solid.material        = SPAM_MATERIAL_GAS;
  p->solid.density         = SPAM_DENSITY_SUMMATION;
  p->solid.density_initial = SPAM_DENSITY_INITIAL_SUMMED;
  p->solid.rho0            = rho_mean;
  p->solid.gas_e0          = t_mean / (p->solid.gamma - 1.0);
  p->solid.shear_visc      = rho_mean * nu;
  p->solid.conductivity    = rho_mean * cp * chi;
  /* The flow scheme's cell convects from about 0.5 Ra_c (docs/gas-flow.md): until its onset
   * is right the cell keeps the plain scheme unless -gas_scheme flow is given. */
  p->solid.plain_default   = PETSC_TRUE;
}

/* Temperature and (unnormalised) density of the conduction state at height y. */
static void ConductionState(const SpamConvectionParams *p, double y, double *T, double *rho)
{
  const double beta = (p->t_bottom - p->t_top) / (double)p->ny;

  *T = p->t_bottom - beta * y;
  /* rho ~ (T / T_b)^(g / beta - 1): log1p keeps it exact as beta -> 0, where it becomes exp(-g y / T_b) */
  if (beta == 0.0) *rho = exp(-p->g * y / p->t_bottom);
  else *rho = exp((p->g / beta) * log1p(-beta * y / p->t_bottom)) * p->t_bottom / *T;
}

/* Seeded random velocities of zero total momentum (the cell must not drift along x). */
static void SeedVelocities(const SpamConvectionParams *p, SpamParticles *out)
{
  uint64_t rng = (uint64_t)p->seed;
  double   mom[2] = {0, 0}, mtot = 0.0;

  for (PetscInt i = 0; i < out->n; i++) {
    for (int d = 0; d < 2; d++) {
      out->v[2 * i + d] = p->amplitude * SpamSceneUniform(&rng);
      mom[d] += out->m[i] * out->v[2 * i + d];
    }
    mtot += out->m[i];
  }
  for (PetscInt i = 0; i < out->n; i++)
    for (int d = 0; d < 2; d++) out->v[2 * i + d] -= mom[d] / mtot;
}

/* The faces the cell needs where the user gave nothing: no-slip isothermal walls. */
static void CellWalls(const SpamConvectionParams *p, SpamWalls *w)
{
  const int    faces[2] = {FACE_BOTTOM, FACE_TOP};
  const double temps[2] = {p->t_bottom, p->t_top};

  for (int k = 0; k < 2; k++) {
    const int f = faces[k];
    if (!w->slip_given[f]) w->slip[f] = SPAM_WALL_NOSLIP;
    if (!w->temperature_given[f]) {
      w->isothermal[f]  = PETSC_TRUE;
      w->temperature[f] = temps[k];
    }
  }
}

static PetscErrorCode Report(const SpamCommonParams *c, const SpamConvectionParams *p, SpamParticles *out)
{
  const SpamSolidParams *s  = &p->solid;
  const double           cp = HeatCapacity(s->gamma), H = (double)p->ny, rho_mean = c->mass;
  const double           t_mean = 0.5 * (p->t_bottom + p->t_top), nu = s->shear_visc / rho_mean;
  const double           chi = s->conductivity / (rho_mean * cp), dt_sa = Superadiabatic(p, s->gamma);
  const double           scale = nu * chi > 0.0 ? p->g / t_mean * H * H * H / (nu * chi) : INFINITY; /* no transport: Ra is infinite (no division by 0 under -fp_trap) */
  char                   line[512];

  PetscFunctionBeginUser;
  (void)snprintf(line, sizeof line,
                 "convection: Ra = %.6g (superadiabatic dT = %.6g; Ra_c = %.2f, Ra/Ra_c = %.4g), Ra of the full dT %.6g, Pr = %.4g, g = %.6g, "
                 "T_b = %g, T_t = %g, nu = %.6g, chi = %.6g, diffusion time H^2/chi = %.6g\n",
                 scale * dt_sa, dt_sa, RA_CRITICAL, scale * dt_sa / RA_CRITICAL, scale * (p->t_bottom - p->t_top), chi > 0.0 ? nu / chi : INFINITY, p->g, p->t_bottom, p->t_top, nu, chi, chi > 0.0 ? H * H / chi : INFINITY);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  PetscCall(PetscStrncpy(out->info.name, "convection", sizeof out->info.name));
  out->info.sound_traversal_time = H / sqrt(s->gamma * t_mean);
  out->info.t_end_default        = chi > 0.0 ? H * H / chi : 100.0 * out->info.sound_traversal_time;
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamConvectionBuild(const SpamCommonParams *c, const SpamConvectionParams *p, SpamParticles *out)
{
  const SpamSolidParams *s = &p->solid;
  const PetscInt         n = p->nx * p->ny;
  double                 mean = 0.0;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  PetscCall(PetscMalloc1(n + 1, &out->m));
  for (PetscInt j = 0; j < p->ny; j++) {
    double T, rho;
    ConductionState(p, (double)j + 0.5, &T, &rho);
    mean += rho / (double)p->ny;
  }
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt col = i % p->nx, row = i / p->nx;
    double         T, rho;
    out->x[2 * i]     = (double)col + 0.5;
    out->x[2 * i + 1] = (double)row + 0.5;
    ConductionState(p, out->x[2 * i + 1], &T, &rho);
    out->rho[i] = c->mass * rho / mean; /* the lattice's mean density is m / (unit cell) */
    out->m[i]   = out->rho[i];          /* times the unit cell's area */
    out->e[i]   = T / (s->gamma - 1.0);
  }
  SeedVelocities(p, out);
  for (PetscInt k = 0; k < 2 * n; k++) out->v[k] *= sqrt(s->gamma); /* amplitude in sound speeds at T = 1 */
  out->mass    = c->mass;
  out->columns = SPAM_COLUMN_X | SPAM_COLUMN_V | SPAM_COLUMN_M | SPAM_COLUMN_E;
  if (s->density != SPAM_DENSITY_SUMMATION) out->columns |= SPAM_COLUMN_RHO; /* the state holds rho */
  out->box = (SpamBox){2, {0, 0, 0}, {(double)p->nx, (double)p->ny, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  CellWalls(p, &out->walls);
  out->gravity[1]  = -p->g;
  out->gravity_set = PETSC_TRUE;
  PetscCall(Report(c, p, out));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SpamConvectionOptions(c, p));
  ModelDefaults(c, p);
  *solid = ((const SpamConvectionParams *)p)->solid;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  SpamConvectionParams q = *(const SpamConvectionParams *)p;

  PetscFunctionBeginUser;
  q.solid = *solid;
  PetscCall(SpamConvectionBuild(c, &q, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneConvection(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"convection", 4, PETSC_FALSE, Table, sizeof(SpamConvectionParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
