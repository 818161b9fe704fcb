/* Velocity gradient of the tensor path (CiSE Eq. 18; the PRE Sec. IX form has the sign of
 * v_ij reversed and drops m):
 *   (grad v)_i^{ab} = dv^b/dx^a = m sum_j (v_j - v_i)^b (grad_i w_ij)^a / rho_ij.
 * The pair term is the same for i and j (both factors change sign), so each listed pair
 * adds it to both. */
#include <spam/physics.h>

void SpamVelocityGradient(const SpamSim *sim, const double *y, const double *rho, double *gradv)
{
  const SpamModel  *m  = &sim->model;
  const SpamLayout *l  = &m->layout;
  const int         nv = l->nvar;
  const SpamImage   im = SpamBoxImage(&sim->box);
  const SpamNeighbours *nl = &sim->nl;

  for (PetscInt k = 0; k < 4 * sim->n; k++) gradv[k] = 0.0;
  for (int i = 0; i < nl->n; i++) {
    const double *vi = y + (size_t)i * nv + l->v;
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j = nl->nbr[p];
      double    dx[2];
      const double r2 = SpamPairDelta2(nl, &im, i, j, dx);
      if (r2 >= m->kernel.h2) continue;
      const double *vj = y + (size_t)j * nv + l->v;
      const double  c  = m->mass * SpamKernelDWOverR(&m->kernel, r2) / SpamPairDensity(m->solid.rho_geometric, rho[i], rho[j]);
      for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
          const double t = c * (vj[b] - vi[b]) * dx[a];
          gradv[4 * i + 2 * a + b] += t;
          gradv[4 * j + 2 * a + b] += t;
        }
    }
  }
}
