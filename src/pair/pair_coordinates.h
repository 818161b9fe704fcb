/* The coordinate updates that average over neighbours (PRE Secs. IV, VI):
 *   R1: dr_i/dt = <v>_i = sum_j v_j w_ij / sum_j w_ij (self term included by the caller),
 *   R2: dr_i/dt = v_i + eps sum_j m_j (v_j - v_i) w_ij / rho_ij (Monaghan's XSPH),
 * R2's pair term is antisymmetric (with the masses) and so keeps the momentum. */
#ifndef SPAM_PAIR_COORDINATES_H
#define SPAM_PAIR_COORDINATES_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairAverageVelocity(const int dim, SpamFields *f, int i, int j, double w)
{
  f->wsum[i] += w;
  f->wsum[j] += w;
  for (int d = 0; d < dim; d++) {
    f->xdot[(size_t)i * dim + d] += w * f->v[(size_t)j * dim + d];
    f->xdot[(size_t)j * dim + d] += w * f->v[(size_t)i * dim + d];
  }
}

/* c = eps w_ij / rho_ij. */
static inline __attribute__((always_inline)) void SpamPairXsph(const int dim, SpamFields *f, int i, int j, double c)
{
  for (int d = 0; d < dim; d++) {
    const double dv = c * (f->v[(size_t)j * dim + d] - f->v[(size_t)i * dim + d]);
    f->xdot[(size_t)i * dim + d] += f->m[j] * dv;
    f->xdot[(size_t)j * dim + d] -= f->m[i] * dv;
  }
}
#endif
