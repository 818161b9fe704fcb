/* The cubic B-spline M4 (Monaghan & Lattanzio 1985), rescaled so that its support is h:
 * with q = 2r/h = 2s the usual (1/4)[(2 - q)^3_+ - 4 (1 - q)^3_+] is
 *   F = 2 t^3 - b^3,  t = (1 - s)_+,  b = (1 - 2s)_+        (1 - 6s^2 + 6s^3 for s < 1/2)
 *   F' = -6 (t^2 - b^2),  F'' = -6 (4b - 2t).
 * F'/s tends to -12 at s = 0, so G is the polynomial 2 - 3s below s = 1/2 and t^2 / s
 * above, chosen by a select with the divisor kept >= 1/2. G = (F'/s) / -6, H = F'' / -6.
 * Each function returns c times G, H or F. The shape is the same in every dimension. Included by kernel_shape.h. */
#ifndef SPAM_KERNEL_CUBIC_SPLINE_H
#define SPAM_KERNEL_CUBIC_SPLINE_H

SPAM_INLINE double SpamCubicSplineF(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s), b = SpamKernelEdge(2.0 * s);
  return c * (2.0 * (t * t * t) - b * b * b);
}

SPAM_INLINE double SpamCubicSplineG(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s), inner = 2.0 - 3.0 * s, outer = t * t / (s > 0.5 ? s : 0.5);
  return c * (s < 0.5 ? inner : outer);
}

SPAM_INLINE double SpamCubicSplineH(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s), b = SpamKernelEdge(2.0 * s);
  return c * (4.0 * b - 2.0 * t);
}

/* The cubic spline M4 with support h: C_D = sigma_D 2^D from the usual sigma_D = 2/3,
 * 10/(7 pi), 1/pi for support 2 h' (h' = h/2). C^2 at r = h (the factor t^3). */
static inline SpamKernelShapeInfo SpamCubicSplineInfo(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 4.0 / 3.0 : dim == 2 ? 40.0 / (7.0 * SPAM_PI) : 8.0 / SPAM_PI,
    .cgrad  = -6.0,
    .smooth = 2,
    .fourier_positive = 0, /* the B-splines' transforms change sign (Dehnen and Aly 2012) */
  };
  return d;
}
#endif
