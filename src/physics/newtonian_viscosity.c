/* Newtonian viscosity in two dimensions: shear viscosity eta_s on the traceless strain
 * rate and bulk viscosity eta_b on the divergence,
 *   sigma_v = eta_s (grad v + grad v^T - (div v) I) + eta_b (div v) I,
 * added to the stress of the tensor path (a gas, or a Kelvin-Voigt solid). It enters the
 * pair force like any stress, so the energy equation turns its work into heat. */
#include <spam/physics.h>

void SpamNewtonianViscosity(const SpamSim *sim, const double *gradv, double *qs)
{
  const double es = sim->model.solid.shear_visc, eb = sim->model.solid.bulk_visc;

  for (PetscInt i = 0; i < sim->n; i++) {
    const double *g = gradv + 4 * i, div = g[0] + g[3], r2 = sim->rho[i] * sim->rho[i];
    qs[3 * i] += (es * (2.0 * g[0] - div) + eb * div) / r2;
    qs[3 * i + 1] += es * (g[1] + g[2]) / r2;
    qs[3 * i + 2] += (es * (2.0 * g[3] - div) + eb * div) / r2;
  }
}
