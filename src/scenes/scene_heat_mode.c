/* A Fourier mode of temperature in the conducting gas at rest (a transport test,
 * now a scene): on the unit lattice of n points along x times ny across (rho = m), filling
 * the periodic box n x ny [x ny],
 *   e = e0 (1 + eps cos kx),  k = 2 pi / n,  v = 0,
 * e0 = -gas_e0. Pure conduction at fixed density decays the mode at kappa k^2 / (rho c_v),
 * c_v = 1/(gamma - 1); the pressure imbalance also launches sound, negligible while
 * conduction outruns it (c k << kappa k^2 / (rho c_v): hence the default e0 = 1e-6). The
 * defaults are tests/run_heat_mode.py's physics: -conductivity 1, e0 = 1e-6, eps = 1e-3. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n, ny;      /* lattice points along x (the wavelength L) and across       */
  double   eps;        /* relative amplitude of the energy mode                      */
} SpamHeatModeParams;

static const SpamSceneOption Table[] = {
  {"heatmode_n", SPAM_SCENE_OPTION_INT, "Lattice points along x: the box edge and the wavelength of the mode", NULL},
  {"heatmode_ny", SPAM_SCENE_OPTION_INT, "Lattice points along y (and z) in 2D and 3D", NULL},
  {"heatmode_eps", SPAM_SCENE_OPTION_REAL, "Relative amplitude eps of e = e0 (1 + eps cos kx)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamHeatModeOptions(const SpamCommonParams *c, SpamHeatModeParams *p)
{
  char      val[64];
  PetscBool ny_set;

  PetscFunctionBeginUser;
  p->n   = 24;
  p->ny  = 12;
  p->eps = 1e-3;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene heat-mode (temperature mode of the conducting gas)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "heatmode_n", &p->n, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "heatmode_ny", &p->ny, &ny_set));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "heatmode_eps", &p->eps, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 1) SPAM_BAD_INPUT("-heatmode_n", val, "must be a positive number of lattice points");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->ny));
  if (p->ny < 1) SPAM_BAD_INPUT("-heatmode_ny", val, "must be a positive number of lattice points");
  if (ny_set && c->dim == 1) SPAM_BAD_INPUT("-heatmode_ny", val, "the run is one-dimensional (-dim 1): it has no y direction");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT " x %" PetscInt_FMT "^%d", p->n, p->ny, c->dim - 1));
  PetscCall(SpamCheckParticleCount("-heatmode_n x -heatmode_ny", val, (double)p->n * pow((double)p->ny, c->dim - 1)));
  PetscCall(SpamOptionText("-heatmode_eps", p->eps, val, sizeof val));
  if (!(fabs(p->eps) < 1.0)) SPAM_BAD_INPUT("-heatmode_eps", val, "allowed: |eps| < 1 (the energy e0 (1 + eps cos kx) stays positive)");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamHeatModeBuild(const SpamCommonParams *c, const SpamHeatModeParams *p, const SpamSolidParams *s, SpamParticles *out)
{
  const int    dim = c->dim;
  const double L = (double)p->n, k = 2.0 * PETSC_PI / L, cv = 1.0 / (s->gamma - 1.0);
  const double sigma = s->conductivity * k * k / (s->rho0 * cv);
  PetscInt     n = 1, side[3];
  char         line[256];

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) {
    side[d] = d ? p->ny : p->n;
    n *= side[d];
  }
  PetscCall(SpamParticlesAllocate(dim, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  out->mass    = c->mass;
  out->columns = SPAM_COLUMN_X | SPAM_COLUMN_V | SPAM_COLUMN_E; /* the mode, not a uniform -gas_e0 */
  SpamLatticeSquare(dim, side, out->x);
  for (PetscInt i = 0; i < n; i++) {
    out->e[i]   = s->gas_e0 * (1.0 + p->eps * cos(k * out->x[i * dim]));
    out->rho[i] = s->rho0;
  }
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.len[d]      = (double)side[d];
    out->box.periodic[d] = PETSC_TRUE;
  }
  PetscCall(PetscStrncpy(out->info.name, "heat-mode", sizeof out->info.name));
  out->info.sound_traversal_time = s->gas_e0 > 0.0 ? L / sqrt(s->gamma * (s->gamma - 1.0) * s->gas_e0) : 0.0;
  /* One e-folding of the isochoric decay; without conduction, one sound crossing. */
  out->info.t_end_default = sigma > 0.0 ? 1.0 / sigma : out->info.sound_traversal_time > 0.0 ? out->info.sound_traversal_time : L;
  (void)snprintf(line, sizeof line, "heat-mode: L = %g, k = %.6g: isochoric decay rate kappa k^2/(rho c_v) = %.10g, isobaric kappa k^2/(rho c_p) = %.10g\n", L, k, sigma, sigma / s->gamma);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SpamHeatModeOptions(c, p));
  SpamSolidGasDefaults(c->mass, solid);
  solid->gas_e0          = 1e-6;
  solid->conductivity    = 1.0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  PetscCall(SpamSceneRequireGas("heat-mode", solid));
  PetscCall(SpamHeatModeBuild(c, p, solid, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneHeatMode(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"heat-mode", 2 | 4 | 8, PETSC_FALSE, Table, sizeof(SpamHeatModeParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
