/* w'(r) and w''(r) of any kernel from its shapes: w' = (w'/r) r = gnorm h s G(s) and
 * w'' = gnorm H(s) (for Lucy the arithmetic of the former kernel_lucy.c). Out of line:
 * the tests and the linearised analyses call them, no pair loop. */
#include <spam/kernel.h>

double SpamKernelDW(const SpamKernel *k, double r)
{
  if (r >= k->h) return 0.0;
  const double s = r * k->hinv;
  return SpamKernelShapeScaledG(k->kind, k->dim, k->gnorm * k->h * s, s);
}

double SpamKernelD2W(const SpamKernel *k, double r)
{
  if (r >= k->h) return 0.0;
  return SpamKernelShapeScaledH(k->kind, k->dim, k->gnorm, r * k->hinv);
}
