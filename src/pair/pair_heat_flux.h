/* Fourier conduction's term of the energy equation (CiSE Eq. 14, PRE Sec. II):
 *   de_i/dt += -sum_j m_j [(Q/rho^2)_i + (Q/rho^2)_j].grad_i w_ij,
 * with heat[] holding Q/rho^2; the pair terms m_i de_i + m_j de_j cancel. The rate goes
 * into qdot, apart from the work, so that a wall's heat and work are booked apart. */
#ifndef SPAM_PAIR_HEAT_FLUX_H
#define SPAM_PAIR_HEAT_FLUX_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairHeatFlux(const int dim, SpamFields *f, int i, int j, const double dx[3], double g)
{
  double s = 0.0;
  for (int d = 0; d < dim; d++) s += (f->heat[(size_t)i * dim + d] + f->heat[(size_t)j * dim + d]) * dx[d];
  f->qdot[i] -= f->m[j] * g * s;
  f->qdot[j] += f->m[i] * g * s;
}
#endif
