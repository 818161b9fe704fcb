/* The shapes of the smoothing kernels, for the pair loops:
 *   w(r) = wnorm F(s),  w'(r)/r = gnorm G(s),  w''(r) = gnorm H(s),  s = r/h,
 * with wnorm = C_D h^-D and gnorm = cgrad C_D h^-(D+2) set by SpamKernelCreate.
 *
 * kind and dim are literals where the pair loops call these, so each switch below folds
 * to the one kernel's arithmetic. Every function is defined for all s >= 0 and is exactly
 * zero for s >= 1 without a branch the vectoriser cannot turn into a select: the factor
 * t = 1 - s is clamped at zero (SpamKernelEdge), the spline pieces are clamped the same
 * way, and near s = 0, where G would be F'/s, a select picks a polynomial instead of
 * dividing by s. Each kernel's functions live in its own header, included by kernel_list.h,
 * with its SpamPrefixInfo (normalisation, cgrad, smoothness).
 *
 * spam/kernel.h includes this file (for SpamKernelW and SpamKernelDWOverR); including
 * kernel.h first, above the guard, lets a pair loop include either in either order. */
#include <spam/kernel.h>
#ifndef SPAM_KERNEL_SHAPE_H
#define SPAM_KERNEL_SHAPE_H

#ifndef SPAM_INLINE
#define SPAM_INLINE static inline __attribute__((always_inline))
#endif

/* (1 - x)_+: the factor that makes a kernel vanish at and beyond its edge. */
SPAM_INLINE double SpamKernelEdge(double x)
{
  const double t = 1.0 - x;
  return t > 0.0 ? t : 0.0;
}

#ifndef SPAM_PI
#define SPAM_PI 3.14159265358979323846
#endif

/* What a kernel's header tells SpamKernelCreate besides its shape, for one dimension D:
 * the normalisation C_D, the factor cgrad of F'(s)/s = cgrad G(s), and the smoothness at
 * r = h. Every shape has F(0) = 1 (to round-off), so that wnorm = w(0), which the density
 * passes add as each particle's own term. Its kind and name are its row's in
 * kernel_list.h. */
typedef struct {
  double cnorm;  /* C_D: the integral of C_D F(|x|) over D-space is one */
  double cgrad;  /* F'(s)/s = cgrad G(s)                                 */
  int    smooth; /* derivatives of w continuous at r = h                 */
  int    fourier_positive; /* its Fourier transform is positive in D: no pairing */
} SpamKernelShapeInfo;

#include <kernels/kernel_list.h> /* the kernels' headers: shapes and SpamPrefixInfo */

/* c F(s), c G(s), c H(s), the scale c multiplied first. A pair loop passes its prefactor
 * as c (m wnorm for the density, the pressure factor times gnorm for the force): with
 * Lucy's kernel that is exactly the arithmetic the loops had, so their numbers do not
 * change in the last bit. One case per row of kernel_list.h. A kind comes only from that
 * list (SpamKernelCreate), so the default is never taken; if it were, NaN would spoil
 * every sum it entered rather than pass for another kernel's shape. */
#define SPAM_KERNEL_SHAPE_CASE(Which, KIND, name, Prefix) \
  case SPAM_KERNEL_##KIND: return Spam##Prefix##Which(dim, c, s);

SPAM_INLINE double SpamKernelShapeScaledF(const int kind, const int dim, double c, double s)
{
  switch (kind) {
    SPAM_KERNEL_LIST(SPAM_KERNEL_SHAPE_CASE, F)
  default: return NAN;
  }
}

SPAM_INLINE double SpamKernelShapeScaledG(const int kind, const int dim, double c, double s)
{
  switch (kind) {
    SPAM_KERNEL_LIST(SPAM_KERNEL_SHAPE_CASE, G)
  default: return NAN;
  }
}

SPAM_INLINE double SpamKernelShapeScaledH(const int kind, const int dim, double c, double s)
{
  switch (kind) {
    SPAM_KERNEL_LIST(SPAM_KERNEL_SHAPE_CASE, H)
  default: return NAN;
  }
}
#undef SPAM_KERNEL_SHAPE_CASE

/* w = wnorm F(s); F(0) = 1. (1.0 times x is x: F is the scaled form's arithmetic.) */
SPAM_INLINE double SpamKernelShapeF(const int kind, const int dim, double s)
{
  return SpamKernelShapeScaledF(kind, dim, 1.0, s);
}

/* w'(r)/r = gnorm G(s); finite at s = 0, where it is w''(0)/gnorm. */
SPAM_INLINE double SpamKernelShapeG(const int kind, const int dim, double s)
{
  return SpamKernelShapeScaledG(kind, dim, 1.0, s);
}

/* w''(r) = gnorm H(s) (the linearised analyses and the tests). */
SPAM_INLINE double SpamKernelShapeH(const int kind, const int dim, double s)
{
  return SpamKernelShapeScaledH(kind, dim, 1.0, s);
}
#endif
