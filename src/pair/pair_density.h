/* Summation density (CiSE Eq. 6): rho_i = sum_j m_j w_ij, the self term m_i w(0)
 * included by the caller. The pair adds m_j w to i and m_i w to j. */
#ifndef SPAM_PAIR_DENSITY_H
#define SPAM_PAIR_DENSITY_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairDensity(SpamFields *f, int i, int j, double w)
{
  f->rho[i] += f->m[j] * w;
  f->rho[j] += f->m[i] * w;
}
#endif
