/* Transport terms of the tensor path on the perfect periodic triangular lattice (24 x 24,
 * h = 3), an ideal gas at uniform density, against the lattice analysis of
 * dispersion_lucy.c (the same sum G(k) = sum_l sin(k.l) (w'/r) l):
 *  - Fourier conduction: e_i = e0 + d cos(k y_i), at rest: de_i/dt = -kappa (gamma - 1)
 *    m^2 |G|^2 / rho0^3 (e_i - e0), exactly (the term is linear in e at fixed positions);
 *  - Newtonian shear viscosity: v_x = d sin(k y_i): dv_x/dt = -eta_s m^2 |G|^2 / rho0^3 v_x;
 *  - bulk viscosity on the longitudinal v_y = d sin(k y_i): rate (eta_s + eta_b) m^2 |G|^2 / rho0^3.
 * Both tend to the continuum rates kappa (gamma - 1) k^2 / rho and eta k^2 / rho as k -> 0.
 * The flow scheme's pair form of both (pair_diffusion.h) against its own lattice sum,
 * rate = -2 chi N m S1(k) / rho0^2 with S1(k) = sum_l (w'/r)(1 - cos(k.l)) and
 * N = -2 rho0 / (m sum_l (w'/r) |l|^2), on the same long wave and on the wave that
 * alternates row by row (k = pi / row spacing): there G(k) = 0, so the gradient form
 * leaves it undamped, and the pair form damps it. */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

static PetscErrorCode MakeGas(const SpamSolidParams *sp, double d, int field, double k, SpamSim *sim)
{
  SpamParticles p;
  SpamModel     m;
  const double  ly = 12.0 * sqrt(3.0);

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, 576, &p));
  PetscCall(SpamParticlesAllocateFields(&p));
  SpamLatticeTriangular(24, 24, 1.0, p.x);
  for (PetscInt i = 0; i < p.n; i++) {
    p.rho[i] = sp->rho0;
    if (field == 0) p.e[i] = d * cos(k * p.x[2 * i + 1]);
    else if (field == 3) p.v[2 * i] = d * cos(k * p.x[2 * i + 1]);
    else p.v[2 * i + (field == 1 ? 0 : 1)] = d * sin(k * p.x[2 * i + 1]);
  }
  p.mass = 1.0;
  p.box  = (SpamBox){2, {0, 0, 0}, {24.0, ly, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  PetscCall(SpamTestModelSolid(2, 3.0, sp, &m));
  PetscCall(SpamSimCreate(PETSC_COMM_WORLD, &m, &p.box, p.n, 0.3, sim));
  PetscCall(SpamSimFill(sim, p.x, p.v, NULL));
  PetscCall(SpamSimFillFields(sim, &p));
  PetscCall(SpamSimSetUp(sim));
  PetscCall(sim->model.setup(sim)); /* sets e = gas_e0 */
  {
    PetscScalar *y;
    PetscCall(VecGetArray(sim->p.X, &y));
    for (PetscInt i = 0; i < p.n; i++) y[(size_t)i * m.layout.nvar + m.layout.e] += p.e[i];
    PetscCall(VecRestoreArray(sim->p.X, &y));
  }
  PetscCall(SpamParticlesFree(&p));
  PetscFunctionReturn(0);
}

/* Largest |ydot[c] / y[c] + rate| / rate (absolute where rate = 0) over particles with
 * |y[c]| > 1/2 of the amplitude. */
static PetscErrorCode RateError(SpamSim *sim, int c, double base, double amp, double rate, double *err)
{
  const int          nv = sim->model.layout.nvar;
  const PetscScalar *y;
  double            *f;
  PetscInt           bad;

  PetscFunctionBeginUser;
  *err = 0.0;
  PetscCall(PetscMalloc1((size_t)sim->p.n * nv, &f));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamRhs(sim, y, f, &bad));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double dy = y[(size_t)i * nv + c] - base;
    if (fabs(dy) > 0.5 * amp) *err = PetscMax(*err, fabs(f[(size_t)i * nv + c] / dy + rate) / (rate > 0.0 ? rate : 1.0));
  }
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscFree(f));
  PetscFunctionReturn(0);
}

/* The pair form's lattice sums S1(k) = sum_l (w'/r)(1 - cos(k l_y)) and S0 = sum_l (w'/r)|l|^2
 * over the triangular lattice of spacing 1 within the Lucy kernel's range h. */
static void PairSums(double h, double k, double *S1, double *S0)
{
  SpamKernel   ker;
  const int    nmax = (int)ceil(h) + 2;
  const double ry   = 0.5 * sqrt(3.0);

  *S1 = *S0 = 0.0;
  (void)SpamKernelLucyInit(2, h, &ker);
  for (int row = -nmax; row <= nmax; row++)
    for (int col = -nmax; col <= nmax; col++) {
      const double l[2] = {col + 0.5 * row, ry * row}, r2 = l[0] * l[0] + l[1] * l[1];
      if (r2 == 0.0 || r2 >= ker.h2) continue;
      *S1 += SpamKernelDWOverR(&ker, r2) * (1.0 - cos(k * l[1]));
      *S0 += SpamKernelDWOverR(&ker, r2) * r2;
    }
}

/* The flow scheme's pair form on the long wave and on the row-alternating wave: its rate
 * against the lattice sum, and the gradient form's rate on the alternating wave (zero). */
static PetscErrorCode PairForm(SpamSolidParams sp, double k_long, TestCount *c)
{
  const double k_alt = PETSC_PI / (0.5 * sqrt(3.0)), ks[2] = {k_long, k_alt};
  SpamSim      sim;
  double       S1, S0, err;

  PetscFunctionBeginUser;
  sp.scheme     = SPAM_GAS_FLOW;
  sp.background = SPAM_BACKGROUND_NONE;
  sp.shift_coef = 0.0;
  for (int w = 0; w < 2; w++) {
    PairSums(3.0, ks[w], &S1, &S0);
    const double N = -2.0 * sp.rho0 / S0, per = -2.0 * N * S1 / (sp.rho0 * sp.rho0); /* m = 1 */
    for (int form = 0; form < 2; form++) {
      const double expect = form == 1 || w == 0 ? per : 0.0;
      sp.diffusion        = form ? SPAM_DIFFUSION_PAIR : SPAM_DIFFUSION_GRADIENT;
      if (form == 0 && w == 0) continue; /* the gradient form's long wave: main() */
      sp.conductivity = 0.3, sp.shear_visc = 0.0;
      PetscCall(MakeGas(&sp, 0.01, 0, ks[w], &sim));
      PetscCall(RateError(&sim, sim.model.layout.e, sp.gas_e0, 0.01, sp.conductivity * (sp.gamma - 1.0) * expect, &err));
      TestCheck(c, err < 1e-9, "%s form, conduction, %s wave: rate %.8f expected (lattice sum), largest error %.1e", form ? "pair" : "gradient", w ? "row-alternating" : "long", sp.conductivity * (sp.gamma - 1.0) * expect, err);
      PetscCall(SpamSimDestroy(&sim));
      sp.conductivity = 0.0, sp.shear_visc = 0.2;
      PetscCall(MakeGas(&sp, 0.01, 3, ks[w], &sim));
      PetscCall(RateError(&sim, sim.model.layout.v, 0.0, 0.01, sp.shear_visc * expect, &err));
      TestCheck(c, err < 1e-9, "%s form, shear viscosity, %s wave: rate %.8f expected, largest error %.1e", form ? "pair" : "gradient", w ? "row-alternating" : "long", sp.shear_visc * expect, err);
      PetscCall(SpamSimDestroy(&sim));
    }
  }
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount       c = {0, 0};
  SpamSolidParams sp;
  SpamSim         sim;
  double          G[2], g2, err;
  const double    ly = 12.0 * sqrt(3.0), k = 2.0 * PETSC_PI / ly, kv[2] = {0.0, 2.0 * PETSC_PI / (12.0 * sqrt(3.0))};

  PetscCall(TestInitialize(&argc, &argv));
  SpamSolidDefaults(&sp);
  sp.material = SPAM_MATERIAL_GAS;
  sp.gamma    = 2.0;
  sp.gas_e0   = 1.0;
  SpamLatticeGradientSum(3.0, 1.0, kv, G);
  g2 = G[0] * G[0] + G[1] * G[1];
  {
    const double rho3 = sp.rho0 * sp.rho0 * sp.rho0;
    sp.conductivity   = 0.3;
    PetscCall(MakeGas(&sp, 0.01, 0, k, &sim));
    const double rate = sp.conductivity * (sp.gamma - 1.0) * g2 / rho3;
    PetscCall(RateError(&sim, sim.model.layout.e, sp.gas_e0, 0.01, rate, &err));
    TestCheck(&c, err < 1e-9, "conduction: decay rate %.8f (continuum %.8f), largest relative error %.1e", rate, sp.conductivity * k * k / sp.rho0, err);
    PetscCall(SpamSimDestroy(&sim));
    sp.conductivity = 0.0;
    sp.shear_visc   = 0.2;
    PetscCall(MakeGas(&sp, 0.01, 1, k, &sim));
    PetscCall(RateError(&sim, sim.model.layout.v, 0.0, 0.01, sp.shear_visc * g2 / rho3, &err));
    TestCheck(&c, err < 1e-9, "shear viscosity: decay rate %.8f (continuum %.8f), largest relative error %.1e", sp.shear_visc * g2 / rho3, sp.shear_visc * k * k / sp.rho0, err);
    PetscCall(SpamSimDestroy(&sim));
    sp.bulk_visc = 0.1;
    PetscCall(MakeGas(&sp, 0.01, 2, k, &sim));
    PetscCall(RateError(&sim, sim.model.layout.v + 1, 0.0, 0.01, (sp.shear_visc + sp.bulk_visc) * g2 / rho3, &err));
    TestCheck(&c, err < 1e-9, "bulk + shear on the longitudinal wave: rate %.8f, largest relative error %.1e", (sp.shear_visc + sp.bulk_visc) * g2 / rho3, err);
    PetscCall(SpamSimDestroy(&sim));
  }
  sp.bulk_visc = 0.0;
  PetscCall(PairForm(sp, k, &c));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
