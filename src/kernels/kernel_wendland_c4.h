/* Wendland's C4 kernel (Wendland 1995; Dehnen & Aly 2012, Table 1).
 *   1D: F = t^5 (1 + 5s + 8s^2)        F'/s = -14 t^4 (1 + 4s)      F'' = -14 t^3 (1 + 3s - 24s^2)
 *   3D: F = t^6 (1 + 6s + 35/3 s^2)    F'/s = -56/3 t^5 (1 + 5s)    F'' = -56/3 t^4 (1 + 4s - 35s^2)
 * (2D uses the 3D function.) Each function returns c times F, G = (F'/s) / cgrad or
 * H = F'' / cgrad, cgrad the factor shown, c multiplied first. Included by
 * kernel_shape.h. */
#ifndef SPAM_KERNEL_WENDLAND_C4_H
#define SPAM_KERNEL_WENDLAND_C4_H

SPAM_INLINE double SpamWendlandC4F(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s), t2 = t * t;
  if (dim == 1) return c * (1.0 + s * (5.0 + 8.0 * s)) * (t2 * t2) * t;
  return c * (1.0 + s * (6.0 + (35.0 / 3.0) * s)) * (t2 * t2) * t2;
}

SPAM_INLINE double SpamWendlandC4G(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s), t2 = t * t;
  if (dim == 1) return c * (1.0 + 4.0 * s) * (t2 * t2);
  return c * (1.0 + 5.0 * s) * (t2 * t2) * t;
}

SPAM_INLINE double SpamWendlandC4H(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s), t2 = t * t;
  if (dim == 1) return c * (1.0 + s * (3.0 - 24.0 * s)) * t2 * t;
  return c * (1.0 + s * (4.0 - 35.0 * s)) * (t2 * t2);
}

/* Wendland's C4 kernel: normalisation C_D (Dehnen & Aly 2012, Table 1) and smoothness
 * at r = h (the factor t^5 in 1D, t^6 in 2D and 3D). */
static inline SpamKernelShapeInfo SpamWendlandC4Info(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 3.0 / 2.0 : dim == 2 ? 9.0 / SPAM_PI : 495.0 / (32.0 * SPAM_PI),
    .cgrad  = dim == 1 ? -14.0 : -56.0 / 3.0,
    .smooth = dim == 1 ? 4 : 5,
    .fourier_positive = 1, /* Wendland's functions are positive definite in D <= 3 */
  };
  return d;
}
#endif
