/* A harmonic spring phi(r) = k/2 (r0 - r)^2 between bonded particles (PRE Fig. 4a):
 * the central force on i is F = -phi'(r) r_ij / r = k (r0 - r) r_ij / r, and -F on j. */
#ifndef SPAM_PAIR_SPRING_H
#define SPAM_PAIR_SPRING_H
#include <spam/fields.h>

static inline __attribute__((always_inline)) void SpamPairSpring(const int dim, SpamFields *f, double k, double r0, int i, int j, const double dx[3], double r)
{
  const double c = k * (r0 - r) / r;
  for (int d = 0; d < dim; d++) {
    f->acc[(size_t)i * dim + d] += c * dx[d] * f->minv[i];
    f->acc[(size_t)j * dim + d] -= c * dx[d] * f->minv[j];
  }
}
/* The force on i alone, for a partner that another rank holds: that rank keeps the same
 * bond and adds -F to its own particle. The same arithmetic as SpamPairSpring's i half. */
static inline __attribute__((always_inline)) void SpamPairSpringOne(const int dim, SpamFields *f, double k, double r0, int i, const double dx[3], double r)
{
  const double c = k * (r0 - r) / r;
  for (int d = 0; d < dim; d++) f->acc[(size_t)i * dim + d] += c * dx[d] * f->minv[i];
}
#endif
