/* The decaying Taylor-Green vortex of the viscous gas (a transport test, now a
 * scene): on the unit lattice of n^D points (rho = m) filling the periodic box of edge L = n,
 *   u = U sin(kx) cos(ky) [cos(kz)], v = -U cos(kx) sin(ky) [cos(kz)], w = 0, k = 2 pi / L.
 * The flow is divergence-free, so at low Mach and Reynolds number its kinetic energy
 * decays as exp(-2 D nu k^2 t), nu = eta_s / rho. The defaults are tests/run_taylor_green.py's
 * physics: gas with e0 = 1e-4 (Mach 0.007 for U = 1e-4: the square lattice's pressure
 * stiffness against this mode stays far below the viscous decay), -viscosity_shear 2. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;          /* lattice points per direction: the box edge L               */
  double   amplitude;  /* velocity amplitude U                                       */
} SpamTaylorGreenParams;

static const SpamSceneOption Table[] = {
  {"taylorgreen_n", SPAM_SCENE_OPTION_INT, "Lattice points per direction: the periodic box edge L, the wavelength (N = n^D)", NULL},
  {"taylorgreen_amplitude", SPAM_SCENE_OPTION_REAL, "Velocity amplitude U", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamTaylorGreenOptions(const SpamCommonParams *c, SpamTaylorGreenParams *p)
{
  char val[64];

  PetscFunctionBeginUser;
  p->n         = 24;
  p->amplitude = 1e-4;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene taylor-green (decaying Taylor-Green vortex)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "taylorgreen_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "taylorgreen_amplitude", &p->amplitude, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 1) SPAM_BAD_INPUT("-taylorgreen_n", val, "must be a positive number of lattice points");
  PetscCall(SpamCheckParticleCount("-taylorgreen_n", val, pow((double)p->n, c->dim)));
  PetscCall(SpamOptionText("-taylorgreen_amplitude", p->amplitude, val, sizeof val));
  /* 1e100: the kinetic energy (U^2 N) stays finite. */
  if (!(fabs(p->amplitude) <= 1e100)) SPAM_BAD_INPUT("-taylorgreen_amplitude", val, "must be a finite number up to 1e100 in size");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamTaylorGreenBuild(const SpamCommonParams *c, const SpamTaylorGreenParams *p, const SpamSolidParams *s, SpamParticles *out)
{
  const int    dim = c->dim;
  const double L = (double)p->n, k = 2.0 * PETSC_PI / L, U = p->amplitude;
  const double nu = s->shear_visc / s->rho0, rate = 2.0 * dim * nu * k * k;
  PetscInt     n;
  char         line[256];

  PetscFunctionBeginUser;
  PetscCall(SpamLatticeCube(dim, p->n, c->mass, out));
  n = out->n;
  for (PetscInt i = 0; i < n; i++) {
    const double *r  = &out->x[i * dim];
    const double  cz = dim == 3 ? cos(k * r[2]) : 1.0;
    out->v[i * dim]     = U * sin(k * r[0]) * cos(k * r[1]) * cz;
    out->v[i * dim + 1] = -U * cos(k * r[0]) * sin(k * r[1]) * cz;
  }
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.len[d]      = L;
    out->box.periodic[d] = PETSC_TRUE;
  }
  PetscCall(PetscStrncpy(out->info.name, "taylor-green", sizeof out->info.name));
  out->info.sound_traversal_time = s->gas_e0 > 0.0 ? L / sqrt(s->gamma * (s->gamma - 1.0) * s->gas_e0) : 0.0;
  /* One e-folding of the continuum kinetic energy; without viscosity, one sound crossing. */
  out->info.t_end_default = rate > 0.0 ? 1.0 / rate : out->info.sound_traversal_time > 0.0 ? out->info.sound_traversal_time : L;
  (void)snprintf(line, sizeof line, "taylor-green: L = %g, k = %.6g, nu = %g: continuum kinetic-energy decay rate 2 D nu k^2 = %.10g\n", L, k, nu, rate);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SpamTaylorGreenOptions(c, p));
  SpamSolidGasDefaults(c->mass, solid);
  solid->gas_e0          = 1e-4;
  solid->shear_visc      = 2.0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  PetscCall(SpamSceneRequireGas("taylor-green", solid));
  PetscCall(SpamTaylorGreenBuild(c, p, solid, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneTaylorGreen(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"taylor-green", 4 | 8, PETSC_FALSE, Table, sizeof(SpamTaylorGreenParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
