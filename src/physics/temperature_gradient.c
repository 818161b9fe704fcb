/* Temperature gradient (CiSE Eq. 19): (grad T)_i = m sum_j (T_j - T_i) grad_i w_ij / rho_ij,
 * with T = (gamma - 1) e in units where k = m = 1 (the ideal gas P = rho T). As for the
 * velocity gradient, each pair adds the same term to both particles. */
#include <spam/physics.h>

void SpamTemperatureGradient(const SpamSim *sim, const double *y, const double *rho, double *gradT)
{
  const SpamModel      *m  = &sim->model;
  const SpamLayout     *l  = &m->layout;
  const SpamImage       im = SpamBoxImage(&sim->box);
  const SpamNeighbours *nl = &sim->nl;
  const double          tc = m->solid.gamma - 1.0;

  for (PetscInt k = 0; k < 2 * sim->n; k++) gradT[k] = 0.0;
  for (int i = 0; i < nl->n; i++) {
    const double ti = tc * y[(size_t)i * l->nvar + l->e];
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int    j = nl->nbr[p];
      double       dx[2];
      const double r2 = SpamPairDelta2(nl, &im, i, j, dx);
      if (r2 >= m->kernel.h2) continue;
      const double tj = tc * y[(size_t)j * l->nvar + l->e];
      const double c  = m->mass * (tj - ti) * SpamKernelDWOverR(&m->kernel, r2) / SpamPairDensity(m->solid.rho_geometric, rho[i], rho[j]);
      for (int a = 0; a < 2; a++) {
        gradT[2 * i + a] += c * dx[a];
        gradT[2 * j + a] += c * dx[a];
      }
    }
  }
}
