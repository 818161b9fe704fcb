/* A test-only kernel, test_tent: F = (1 + 2s) t^2, t = 1 - s, the same shape in 1, 2 and
 * 3D. F' = -6 s t, so G = F'/s / cgrad = t with cgrad = -6, and H = F'' / cgrad = 1 - 2s
 * inside the support. F and F' vanish at s = 1, F'' does not (smoothness 1). Not a kernel
 * for runs: a shape unlike every real one, so that a walk that ran another kernel's shape
 * instead would give other sums. Included by kernel_list.h through SPAM_KERNEL_EXTRA_HEADER
 * in test_kernel_extra only. */
#ifndef SPAM_KERNEL_TEST_TENT_H
#define SPAM_KERNEL_TEST_TENT_H

SPAM_INLINE double SpamTestTentF(const int dim, double c, double s)
{
  const double t = SpamKernelEdge(s);
  (void)dim;
  return c * (1.0 + 2.0 * s) * t * t;
}

SPAM_INLINE double SpamTestTentG(const int dim, double c, double s)
{
  (void)dim;
  return c * SpamKernelEdge(s);
}

SPAM_INLINE double SpamTestTentH(const int dim, double c, double s)
{
  (void)dim;
  return s < 1.0 ? c * (1.0 - 2.0 * s) : 0.0;
}

/* The test-only kernel test_tent: C_D from the integral of F = (1 + 2s)(1 - s)^2 over the
 * unit D-ball (1D: 2 * 1/2, 2D: 2 pi * 3/20, 3D: 4 pi * 1/15), cgrad = -6, smoothness 1. */
static inline SpamKernelShapeInfo SpamTestTentInfo(const int dim)
{
  const SpamKernelShapeInfo d = {
    .cnorm  = dim == 1 ? 1.0 : dim == 2 ? 10.0 / (3.0 * SPAM_PI) : 15.0 / (4.0 * SPAM_PI),
    .cgrad  = -6.0,
    .smooth = 1,
    .fourier_positive = 0, /* not known: the shift takes Wendland C2's */
  };
  return d;
}
#endif
