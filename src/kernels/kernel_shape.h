/* TEMPORARY (replaced by the kernels branch): Lucy's shape only. */
#ifndef SPAM_KERNEL_SHAPE_H
#define SPAM_KERNEL_SHAPE_H
#include <spam/kernel.h>
#ifndef SPAM_INLINE
#define SPAM_INLINE static inline __attribute__((always_inline))
#endif
SPAM_INLINE double SpamKernelShapeF(const int kind, const int dim, double s)
{
  double t = 1.0 - s;
  (void)kind; (void)dim;
  t = t > 0.0 ? t : 0.0;
  return (1.0 + 3.0 * s) * t * t * t;
}
SPAM_INLINE double SpamKernelShapeG(const int kind, const int dim, double s)
{
  double t = 1.0 - s;
  (void)kind; (void)dim;
  t = t > 0.0 ? t : 0.0;
  return t * t;
}
#endif
