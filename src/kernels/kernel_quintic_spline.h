/* The quintic B-spline M6 (Schoenberg 1946; Morris 1996), rescaled so that its support
 * is h and F(0) = 1: with q = 3r/h = 3s the usual (3 - q)^5_+ - 6 (2 - q)^5_+ + 15 (1 - q)^5_+
 * is 3^5 P(s), P(0) = 66/243, and F = P / P(0):
 *   P = t^5 - 6 a^5 + 15 b^5,  t = (1 - s)_+,  a = (2/3 - s)_+,  b = (1/3 - s)_+,
 *   P' = -5 (t^4 - 6 a^4 + 15 b^4),  P'' = -5 (-4 t^3 + 24 a^3 - 60 b^3).
 * Below s = 1/3 the bracket of P' is s (8/9 - 8 s^2 + 10 s^3), so G is that polynomial
 * there and (t^4 - 6 a^4) / s above, chosen by a select with the divisor kept >= 1/3.
 * G = (F'/s) / cgrad and H = F'' / cgrad with cgrad = -5 / P(0) = -405/22. The same shape
 * in every dimension; each function returns c times G, H or F. Included by kernel_shape.h. */
#ifndef SPAM_KERNEL_QUINTIC_SPLINE_H
#define SPAM_KERNEL_QUINTIC_SPLINE_H

SPAM_INLINE double SpamQuinticSplineF(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s), a = SpamKernelEdge(1.5 * s) * (2.0 / 3.0), b = SpamKernelEdge(3.0 * s) * (1.0 / 3.0);
  const double t2 = t * t, a2 = a * a, b2 = b * b;
  return c * (243.0 / 66.0) * (t2 * t2 * t - 6.0 * (a2 * a2 * a) + 15.0 * (b2 * b2 * b));
}

SPAM_INLINE double SpamQuinticSplineG(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s), a = SpamKernelEdge(1.5 * s) * (2.0 / 3.0), t2 = t * t, a2 = a * a;
  const double inner = 8.0 / 9.0 + s * s * (10.0 * s - 8.0), outer = (t2 * t2 - 6.0 * (a2 * a2)) / (s > 1.0 / 3.0 ? s : 1.0 / 3.0);
  return c * (s < 1.0 / 3.0 ? inner : outer);
}

SPAM_INLINE double SpamQuinticSplineH(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s), a = SpamKernelEdge(1.5 * s) * (2.0 / 3.0), b = SpamKernelEdge(3.0 * s) * (1.0 / 3.0);
  return c * (-4.0 * (t * t * t) + 24.0 * (a * a * a) - 60.0 * (b * b * b));
}

/* The quintic spline M6 with support h and F(0) = 1: C_D = sigma_D 3^D 66 from the usual
 * sigma_D = 1/120, 7/(478 pi), 1/(120 pi) for support 3 h' (h' = h/3), 66 being the usual
 * bracket at q = 0. C^4 at r = h (the factor t^5). */
static inline SpamKernelShapeInfo SpamQuinticSplineInfo(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 33.0 / 20.0 : dim == 2 ? 2079.0 / (239.0 * SPAM_PI) : 297.0 / (20.0 * SPAM_PI),
    .cgrad  = -405.0 / 22.0,
    .smooth = 4,
    .fourier_positive = 0, /* the B-splines' transforms change sign (Dehnen and Aly 2012) */
  };
  return d;
}
#endif
