/* The transport shift's pair sum (gas_flow.h), in particle volumes V = m / rho:
 *   S_i = sum_j (V_i^2 + V_j^2) grad_i w_ij,
 * the pair force of a uniform pressure in the form of Adami, Hu and Adams's transport
 * velocity: zero on a lattice of equal volumes whatever the masses (a layer whose density
 * is made by the masses stays put), and zero to first order in a smooth density field.
 * Antisymmetric in the pair: each particle's share is the other's with the sign changed
 * (grad_i w_ij = g dx). */
#ifndef SPAM_PAIR_SHIFT_H
#define SPAM_PAIR_SHIFT_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairShift(const int dim, SpamFields *f, int i, int j, const double dx[3], double g)
{
  const double c = g * (f->vol2[i] + f->vol2[j]);
  for (int d = 0; d < dim; d++) {
    f->shift[(size_t)i * dim + d] += c * dx[d];
    f->shift[(size_t)j * dim + d] -= c * dx[d];
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
