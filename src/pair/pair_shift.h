/* The transport shift's pair sum (gas_flow.h): the plain pair force of a unit pressure,
 *   S_i = sum_j m_j (1/rho_i^2 + 1/rho_j^2) grad_i w_ij,
 * antisymmetric in the pair, so each particle's share is the other's with the sign
 * changed (grad_i w_ij = g dx). */
#ifndef SPAM_PAIR_SHIFT_H
#define SPAM_PAIR_SHIFT_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairShift(const int dim, SpamFields *f, int i, int j, const double dx[3], double g)
{
  const double c = g * (1.0 / (f->rho[i] * f->rho[i]) + 1.0 / (f->rho[j] * f->rho[j]));
  for (int d = 0; d < dim; d++) {
    f->shift[(size_t)i * dim + d] += f->m[j] * c * dx[d];
    f->shift[(size_t)j * dim + d] -= f->m[i] * c * dx[d];
  }
}

/* The moment of the SPAM gradient, M_i = sum_j m_j g dx dx^T / rho_ij (-I on a regular
 * arrangement in the continuum limit): a linear field's SPAM gradient is -M G^T, so
 * -M^-1 undoes the arrangement's error (Bonet and Lok's correction). The same for i and j. */
static inline __attribute__((always_inline)) void SpamPairGradientMoment(const int dim, SpamFields *f, int i, int j, const double dx[3], double c)
{
  double *mi = f->gmom + (size_t)i * dim * dim, *mj = f->gmom + (size_t)j * dim * dim;
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) {
      const double t = c * dx[a] * dx[b];
      mi[a * dim + b] += f->m[j] * t;
      mj[a * dim + b] += f->m[i] * t;
    }
}
#endif
