/* Fourier heat conduction (CiSE Eq. 14, PRE Sec. II): the heat flux Q = -kappa grad T and
 * its term of the energy equation,
 *   de_i/dt += -m sum_j [(Q/rho^2)_i + (Q/rho^2)_j].grad_i w_ij,
 * whose pair terms are equal and opposite for i and j, so sum m e is unchanged by it. */
#include <spam/physics.h>

void SpamFourierConduction(SpamSim *sim, double *heat)
{
  const SpamModel      *m  = &sim->model;
  const SpamImage       im = SpamBoxImage(&sim->box);
  const SpamNeighbours *nl = &sim->nl;
  SpamPhysicsScratch   *ps = sim->ps;

  for (PetscInt i = 0; i < sim->n; i++) /* heat: grad T -> Q / rho^2 */
    for (int a = 0; a < 2; a++) heat[2 * i + a] *= -m->solid.conductivity / (sim->rho[i] * sim->rho[i]);
  for (int i = 0; i < nl->n; i++) {
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int    j = nl->nbr[p];
      double       dx[2];
      const double r2 = SpamPairDelta2(nl, &im, i, j, dx);
      if (r2 >= m->kernel.h2) continue;
      const double g = m->mass * SpamKernelDWOverR(&m->kernel, r2);
      const double f = g * ((heat[2 * i] + heat[2 * j]) * dx[0] + (heat[2 * i + 1] + heat[2 * j + 1]) * dx[1]);
      ps->edot[i] -= f;
      ps->edot[j] += f;
    }
  }
}
