/* The isentropic gas's pair force (Hoover & Hoover 2001, Eq. 8, with unequal masses):
 *   dv_i/dt = -sum_j m_j [(P/rho^2)_i + (P/rho^2)_j] grad_i w_ij,
 * and the opposite term m_i [...] for j, so that m_i dv_i + m_j dv_j = 0. q = P/rho^2. */
#ifndef SPAM_PAIR_PRESSURE_FORCE_H
#define SPAM_PAIR_PRESSURE_FORCE_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairPressureForce(const int dim, SpamFields *f, int i, int j, const double dx[3], double g)
{
  const double c = -(f->q[i] + f->q[j]) * g;
  for (int d = 0; d < dim; d++) {
    f->acc[(size_t)i * dim + d] += f->m[j] * c * dx[d];
    f->acc[(size_t)j * dim + d] -= f->m[i] * c * dx[d];
  }
}
#endif
