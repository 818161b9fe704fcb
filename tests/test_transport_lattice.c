/* Transport terms of the tensor path on the perfect periodic triangular lattice (24 x 24,
 * h = 3), an ideal gas at uniform density, against the lattice analysis of
 * dispersion_lucy.c (the same sum G(k) = sum_l sin(k.l) (w'/r) l):
 *  - Fourier conduction: e_i = e0 + d cos(k y_i), at rest: de_i/dt = -kappa (gamma - 1)
 *    m^2 |G|^2 / rho0^3 (e_i - e0), exactly (the term is linear in e at fixed positions);
 *  - Newtonian shear viscosity: v_x = d sin(k y_i): dv_x/dt = -eta_s m^2 |G|^2 / rho0^3 v_x;
 *  - bulk viscosity on the longitudinal v_y = d sin(k y_i): rate (eta_s + eta_b) m^2 |G|^2 / rho0^3.
 * Both tend to the continuum rates kappa (gamma - 1) k^2 / rho and eta k^2 / rho as k -> 0. */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

static PetscErrorCode MakeGas(const SpamSolidParams *sp, double d, int field, SpamSim *sim)
{
  SpamParticles p;
  SpamModel     m;
  const double  ly = 12.0 * sqrt(3.0), k = 2.0 * PETSC_PI / ly;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, 576, &p));
  PetscCall(SpamParticlesAllocateFields(&p));
  SpamLatticeTriangular(24, 24, 1.0, p.x);
  for (PetscInt i = 0; i < p.n; i++) {
    p.rho[i] = sp->rho0;
    if (field == 0) p.e[i] = d * cos(k * p.x[2 * i + 1]);
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

/* Largest |ydot[c] / y[c] + rate| over particles with |y[c]| > 1/2 of the amplitude. */
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
    if (fabs(dy) > 0.5 * amp) *err = PetscMax(*err, fabs(f[(size_t)i * nv + c] / dy + rate) / rate);
  }
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscFree(f));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount       c = {0, 0};
  SpamSolidParams sp;
  SpamSim         sim;
  double          G[2], g2, err;
  const double    ly = 12.0 * sqrt(3.0), k = 2.0 * PETSC_PI / ly, kv[2] = {0.0, 2.0 * PETSC_PI / (12.0 * sqrt(3.0))};

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  SpamSolidDefaults(&sp);
  sp.material = SPAM_MATERIAL_GAS;
  sp.gamma    = 2.0;
  sp.gas_e0   = 1.0;
  SpamLatticeGradientSum(3.0, 1.0, kv, G);
  g2 = G[0] * G[0] + G[1] * G[1];
  {
    const double rho3 = sp.rho0 * sp.rho0 * sp.rho0;
    sp.conductivity   = 0.3;
    PetscCall(MakeGas(&sp, 0.01, 0, &sim));
    const double rate = sp.conductivity * (sp.gamma - 1.0) * g2 / rho3;
    PetscCall(RateError(&sim, sim.model.layout.e, sp.gas_e0, 0.01, rate, &err));
    TestCheck(&c, err < 1e-9, "conduction: decay rate %.8f (continuum %.8f), largest relative error %.1e", rate, sp.conductivity * k * k / sp.rho0, err);
    PetscCall(SpamSimDestroy(&sim));
    sp.conductivity = 0.0;
    sp.shear_visc   = 0.2;
    PetscCall(MakeGas(&sp, 0.01, 1, &sim));
    PetscCall(RateError(&sim, sim.model.layout.v, 0.0, 0.01, sp.shear_visc * g2 / rho3, &err));
    TestCheck(&c, err < 1e-9, "shear viscosity: decay rate %.8f (continuum %.8f), largest relative error %.1e", sp.shear_visc * g2 / rho3, sp.shear_visc * k * k / sp.rho0, err);
    PetscCall(SpamSimDestroy(&sim));
    sp.bulk_visc = 0.1;
    PetscCall(MakeGas(&sp, 0.01, 2, &sim));
    PetscCall(RateError(&sim, sim.model.layout.v + 1, 0.0, 0.01, (sp.shear_visc + sp.bulk_visc) * g2 / rho3, &err));
    TestCheck(&c, err < 1e-9, "bulk + shear on the longitudinal wave: rate %.8f, largest relative error %.1e", (sp.shear_visc + sp.bulk_visc) * g2 / rho3, err);
    PetscCall(SpamSimDestroy(&sim));
  }
  PetscCall(PetscFinalize());
  return TestFinish(&c);
}
