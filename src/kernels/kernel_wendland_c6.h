/* Wendland's C6 kernel (Wendland 1995; Dehnen & Aly 2012, Table 1).
 *   1D: F = t^7 (1 + 7s + 19s^2 + 21s^3)   F'/s = -6 t^6 (3 + 18s + 35s^2)
 *                                           F''  = -6 t^5 (3 + 15s - 39s^2 - 315s^3)
 *   3D: F = t^8 (1 + 8s + 25s^2 + 32s^3)   F'/s = -22 t^7 (1 + 7s + 16s^2)
 *                                           F''  = -22 t^6 (1 + 6s - 15s^2 - 160s^3)
 * (2D uses the 3D function.) Each function returns c times F, G = (F'/s) / cgrad or
 * H = F'' / cgrad, cgrad the factor shown, c multiplied first. Included by
 * kernel_shape.h. */
#ifndef SPAM_KERNEL_WENDLAND_C6_H
#define SPAM_KERNEL_WENDLAND_C6_H

SPAM_INLINE double SpamWendlandC6F(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s), t2 = t * t, t4 = t2 * t2;
  if (dim == 1) return c * (1.0 + s * (7.0 + s * (19.0 + 21.0 * s))) * t4 * t2 * t;
  return c * (1.0 + s * (8.0 + s * (25.0 + 32.0 * s))) * t4 * t4;
}

SPAM_INLINE double SpamWendlandC6G(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s), t2 = t * t, t4 = t2 * t2;
  if (dim == 1) return c * (3.0 + s * (18.0 + 35.0 * s)) * t4 * t2;
  return c * (1.0 + s * (7.0 + 16.0 * s)) * t4 * t2 * t;
}

SPAM_INLINE double SpamWendlandC6H(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s), t2 = t * t, t4 = t2 * t2;
  if (dim == 1) return c * (3.0 + s * (15.0 - s * (39.0 + 315.0 * s))) * t4 * t;
  return c * (1.0 + s * (6.0 - s * (15.0 + 160.0 * s))) * t4 * t2;
}

/* Wendland's C6 kernel: normalisation C_D (Dehnen & Aly 2012, Table 1) and smoothness
 * at r = h (the factor t^7 in 1D, t^8 in 2D and 3D). */
static inline SpamKernelShapeInfo SpamWendlandC6Info(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 55.0 / 32.0 : dim == 2 ? 78.0 / (7.0 * SPAM_PI) : 1365.0 / (64.0 * SPAM_PI),
    .cgrad  = dim == 1 ? -6.0 : -22.0,
    .smooth = dim == 1 ? 6 : 7,
    .fourier_positive = 1, /* Wendland's functions are positive definite in D <= 3 */
  };
  return d;
}
#endif
