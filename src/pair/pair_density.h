/* Summation density (CiSE Eq. 6): rho_i = sum_j m_j w_ij, the self term m_i w(0)
 * included by the caller. The one coding of the law, for every traversal of the list
 * (pass_chunked.c's chunked rows, pass_canonical.c's sorted rows, the tensor path's
 * and the diagnostics' callers of those):
 *   the pair's term c F(s), w_ij = wnorm F(s), with c = m wnorm when every particle has
 *   the mass m (the mass folded into the kernel's scale: one product per pair fewer),
 *   else c = wnorm and the term m_j (c F) for i, m_i (c F) for j. */
#ifndef SPAM_PAIR_DENSITY_H
#define SPAM_PAIR_DENSITY_H
#include "../kernels/kernel_shape.h"

static inline __attribute__((always_inline)) double SpamPairDensityTerm(const int kind, const int dim, double c, double s)
{
  return SpamKernelShapeScaledF(kind, dim, c, s);
}
#endif
