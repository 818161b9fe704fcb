/* The isentropic gas's density and force passes under -reproducible, over the canonical
 * rows of the neighbour list (neighbours_canonical.c): each local particle sums its own
 * terms in the order of its row, sorted by partner (gid, image), and writes only its own
 * value -- no Newton update of the partner, no fold of ghost shares, no thread buffers.
 * So rho_i and a_i are the same bits whichever rank holds each partner, whether the
 * partner is a local particle, a periodic image or another rank's particle, and whatever
 * -threads is (a row is one thread's). The pair terms are those of pair_density.h and
 * pair_pressure_force.h (the default passes), taken from i's side:
 *   rho_i = m_i w(0) + sum_j m_j w_ij,
 *   a_i   = sum_j m_j c_ij (u_i - u_j),  c_ij = -(q_i + q_j) w'(r)/r,  q = P/rho^2.
 * The cost: every pair is evaluated twice (once in each row) instead of once.
 * Compiled with -ffp-contract=off (CMakeLists.txt): the same roundings on every machine. */
#include <spam/sim.h>
#include "../pair/pair_walk.h"

#define SPAM_INLINE static inline __attribute__((always_inline))

/* u_i - u_j and its square: the canonical rows have no minimum image. */
SPAM_INLINE double Separation(const int dim, const SpamNeighbours *nl, int i, int j, double dx[3])
{
  double r2 = 0.0;
  for (int d = 0; d < dim; d++) {
    dx[d] = nl->u[d][i] - nl->u[d][j];
    r2 += dx[d] * dx[d];
  }
  return r2;
}

SPAM_INLINE void CanonDensityRows(const int dim, const int kind, const SpamNeighbours *nl, const SpamKernel *k, SpamFields *f, int T)
{
#pragma omp parallel for if (T > 1) num_threads(T) schedule(static)
  for (int i = 0; i < nl->n; i++) {
    double rho = f->m[i] * k->wnorm;
    for (int p = nl->cstart[i]; p < nl->cstart[i + 1]; p++) {
      const int j = nl->cnbr[p];
      double    dx[3];
      const double r2 = Separation(dim, nl, i, j, dx);
      if (r2 >= k->h2) continue;
      rho += f->m[j] * SpamKernelShapeScaledF(kind, dim, k->wnorm, sqrt(r2) * k->hinv);
    }
    f->rho[i] = rho;
  }
}

SPAM_INLINE void CanonForceRows(const int dim, const int kind, const SpamNeighbours *nl, const SpamKernel *k, SpamFields *f, int T)
{
#pragma omp parallel for if (T > 1) num_threads(T) schedule(static)
  for (int i = 0; i < nl->n; i++) {
    double a[3] = {0.0, 0.0, 0.0};
    for (int p = nl->cstart[i]; p < nl->cstart[i + 1]; p++) {
      const int j = nl->cnbr[p];
      double    dx[3];
      const double r2 = Separation(dim, nl, i, j, dx);
      if (r2 >= k->h2) continue;
      const double c = -(f->q[i] + f->q[j]) * SpamKernelShapeScaledG(kind, dim, k->gnorm, sqrt(r2) * k->hinv);
      for (int d = 0; d < dim; d++) a[d] += f->m[j] * c * dx[d];
    }
    for (int d = 0; d < dim; d++) f->acc[(size_t)i * dim + d] = a[d];
  }
}

void SpamCanonicalDensity(SpamSim *sim)
{
  const SpamKernel *k = &sim->model.kernel;
  SPAM_WALK_DISPATCH(CanonDensity, k->dim, k->kind, &sim->nl, k, &sim->f, sim->threads)
}

void SpamCanonicalForce(SpamSim *sim)
{
  const SpamKernel *k = &sim->model.kernel;
  SPAM_WALK_DISPATCH(CanonForce, k->dim, k->kind, &sim->nl, k, &sim->f, sim->threads)
}
