/* Wendland's C2 kernel (Wendland 1995; Dehnen & Aly 2012, Table 1). The 1D function is
 * the lower-degree one, (1 + 3s) t^3, which is Lucy's; 2D and 3D share (1 + 4s) t^4.
 *   1D: F = t^3 (1 + 3s)   F'/s = -12 t^2            F'' = -12 t (1 - 3s)
 *   3D: F = t^4 (1 + 4s)   F'/s = -20 t^3            F'' = -20 t^2 (1 - 4s)
 * Each function returns c times F, G = (F'/s) / cgrad or
 * H = F'' / cgrad, cgrad the factor shown, c multiplied first. Included by
 * kernel_shape.h. */
#ifndef SPAM_KERNEL_WENDLAND_C2_H
#define SPAM_KERNEL_WENDLAND_C2_H

SPAM_INLINE double SpamWendlandC2F(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s);
  if (dim == 1) return c * (1.0 + 3.0 * s) * t * t * t;
  return c * (1.0 + 4.0 * s) * (t * t) * (t * t);
}

SPAM_INLINE double SpamWendlandC2G(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s);
  if (dim == 1) return c * t * t;
  return c * t * t * t;
}

SPAM_INLINE double SpamWendlandC2H(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s);
  if (dim == 1) return c * t * (1.0 - 3.0 * s);
  return c * (t * t) * (1.0 - 4.0 * s);
}

/* Wendland's C2 kernel: normalisation C_D (Dehnen & Aly 2012, Table 1) and smoothness
 * at r = h (the factor t^3 in 1D, t^4 in 2D and 3D). */
static inline SpamKernelShapeInfo SpamWendlandC2Info(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 5.0 / 4.0 : dim == 2 ? 7.0 / SPAM_PI : 21.0 / (2.0 * SPAM_PI),
    .cgrad  = dim == 1 ? -12.0 : -20.0,
    .smooth = dim == 1 ? 2 : 3,
    .fourier_positive = 1, /* Wendland's functions are positive definite in D <= 3 */
  };
  return d;
}
#endif
