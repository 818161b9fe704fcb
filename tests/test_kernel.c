/* Lucy's kernel: normalisation, gradient, smoothness at the edge of its support. */
#include <spam/kernel.h>
#include "test_util.h"

/* Integral of w over D-space as a radial integral, by 5-point Gauss-Legendre on 16
 * panels: exact for the degree-6 polynomial integrand up to round-off. */
static double Normalisation(const SpamKernel *k)
{
  static const double xg[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  static const double wg[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
  const int           panels = 16;
  const double        a      = k->h / panels;
  double              sum    = 0.0;
  for (int p = 0; p < panels; p++) {
    for (int g = 0; g < 5; g++) {
      const double r     = a * (p + 0.5 * (xg[g] + 1.0));
      const double shell = k->dim == 1 ? 2.0 : k->dim == 2 ? 2.0 * 3.14159265358979323846 * r : 4.0 * 3.14159265358979323846 * r * r;
      sum += 0.5 * a * wg[g] * shell * SpamKernelW(k, r * r);
    }
  }
  return sum;
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  for (int dim = 1; dim <= 3; dim++) {
    for (double h = 1.5; h <= 6.0; h *= 2.0) {
      SpamKernel k;
      double     maxerr = 0.0, gmax = 0.0;
      PetscCall(SpamKernelLucyInit(dim, h, &k));
      const double norm = Normalisation(&k);
      TestCheck(&c, fabs(norm - 1.0) < 1e-10, "D=%d h=%g: integral of w = %.15f (|err| < 1e-10)", dim, h, norm);
      /* Gradient against a central difference: O(delta^2) truncation ~ 1e-10 of w'. */
      for (int s = 1; s < 100; s++) {
        const double r = h * s / 100.0, delta = 1e-5 * h;
        const double fd = (SpamKernelW(&k, (r + delta) * (r + delta)) - SpamKernelW(&k, (r - delta) * (r - delta))) / (2.0 * delta);
        const double an = SpamKernelDWOverR(&k, r * r) * r;
        maxerr          = PetscMax(maxerr, fabs(fd - an));
        gmax            = PetscMax(gmax, fabs(an));
        /* second derivative likewise from w' */
        const double fd2 = (SpamKernelDW(&k, r + delta) - SpamKernelDW(&k, r - delta)) / (2.0 * delta);
        maxerr           = PetscMax(maxerr, fabs(fd2 - SpamKernelD2W(&k, r)) * h);
      }
      TestCheck(&c, maxerr < 1e-7 * gmax, "D=%d h=%g: w' and w'' match central differences (max err %.2e, max |w'| %.2e)", dim, h, maxerr, gmax);
      TestCheck(&c, SpamKernelDWOverR(&k, 0.0) * 0.0 == 0.0 && SpamKernelDW(&k, 0.0) == 0.0, "D=%d h=%g: grad w vanishes at r = 0 (no self force)", dim, h);
      /* Continuity at r = h: w ~ eps^3, w' ~ eps^2, w'' ~ eps as r -> h, and all vanish beyond. */
      const double eps = 1e-4, r = h * (1.0 - eps);
      const double w = SpamKernelW(&k, r * r) / k.wnorm, w1 = SpamKernelDW(&k, r) * h / k.wnorm, w2 = SpamKernelD2W(&k, r) * h * h / k.wnorm;
      TestCheck(&c, fabs(w) <= 4.0 * eps * eps * eps * 1.01 && fabs(w1) <= 12.0 * eps * eps * 1.01 && fabs(w2) <= 24.0 * eps * 1.01, "D=%d h=%g: w, w', w'' -> 0 at r = h (scaled %.1e %.1e %.1e at 1-1e-4)", dim, h, w, w1, w2);
      TestCheck(&c, SpamKernelW(&k, h * h) == 0.0 && SpamKernelDW(&k, h) == 0.0 && SpamKernelD2W(&k, h) == 0.0 && SpamKernelW(&k, 4 * h * h) == 0.0, "D=%d h=%g: w, w', w'' are zero for r >= h", dim, h);
    }
  }
  PetscCall(PetscFinalize());
  return TestFinish(&c);
}
