/* A test-only kernel, test_tent: F = (1 + 2s) t^2, t = 1 - s, the same shape in 1, 2 and
 * 3D. F' = -6 s t, so G = F'/s / cgrad = t with cgrad = -6, and H = F'' / cgrad = 1 - 2s
 * inside the support. F and F' vanish at s = 1, F'' does not (smoothness 1). Not a kernel
 * for runs: a shape unlike every real one, so that a walk that ran another kernel's shape
 * instead would give other sums. Included by kernel_list.h through SPAM_KERNEL_EXTRA_HEADER. */
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
#endif
