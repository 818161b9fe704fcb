/* Lucy's kernel (Lucy 1977): F = (1 + 3s) t^3, t = 1 - s, the same shape in 1, 2 and 3D.
 * Its w'(r)/r is -12 (1 - s)^2: G = t^2 with the factor -12 in gnorm. Each function returns
 * c times the shape, c multiplied first: c (1 + 3s) t t t and c t t are the very operations
 * the pair loops and evaluators had, so every number made with Lucy's kernel stays the
 * same bit for bit. Included by kernel_shape.h, which defines SPAM_INLINE and
 * SpamKernelEdge. */
#ifndef SPAM_KERNEL_LUCY_H
#define SPAM_KERNEL_LUCY_H

SPAM_INLINE double SpamLucyF(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s);
  return c * (1.0 + 3.0 * s) * t * t * t;
}

SPAM_INLINE double SpamLucyG(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s);
  return c * t * t;
}

/* F''(s) / -12 = t (1 - 3s). */
SPAM_INLINE double SpamLucyH(const int dim, double c, double s)
{
  (void)dim; /* the same shape in every dimension */
  const double t = SpamKernelEdge(s);
  return c * t * (1.0 - 3.0 * s);
}

/* Lucy's kernel: normalisation C_D in 1, 2 and 3D and smoothness at r = h. */
static inline SpamKernelShapeInfo SpamLucyInfo(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 5.0 / 4.0 : dim == 2 ? 5.0 / SPAM_PI : 105.0 / (16.0 * SPAM_PI),
    .cgrad  = -12.0,
    .smooth = 2, /* t^3: w, w', w'' vanish at h and w''' = 6 C_D / h^(D+3) does not: the force is C^1 */
    .fourier_positive = dim == 1, /* Wendland C2's shape in 1D; negative in 2D and 3D (Dehnen and Aly 2012) */
  };
  return d;
}
#endif
