/* The linearised SPAM dispersion relation on the perfect triangular lattice tends to the
 * continuum sound speeds c_T = sqrt(3/8), c_L = sqrt(9/8) (lambda = eta = sqrt(3)/4,
 * rho0 = sqrt(4/3)) as the wavelength grows and h/a grows:
 *  - at fixed h the speed approaches its long-wave value with an error falling like k^2;
 *  - that long-wave value differs from the continuum by the lattice-sum error of the
 *    kernel's second moment, sum_l (w'/r) l l^T versus -n I: -0.76% at the PRE's h = 3,
 *    and within 2e-3 for h >= 6, 2e-4 at h = 12 (it oscillates as shells enter the range);
 *  - omega_L/omega_T = sqrt 3 at every k; long waves do not depend on the direction. */
#include <spam/physics.h>
#include "test_util.h"

static const double lam = 0.4330127018922193, eta = 0.4330127018922193;

static double SpeedT(double h, double lw, double *ratio)
{
  const double k = 2.0 * PETSC_PI / lw, kv[2] = {0.0, k};
  double       wt, wl;
  SpamDispersionLucy(h, 1.0, 1.0, sqrt(4.0 / 3.0), lam, eta, kv, &wt, &wl);
  if (ratio) *ratio = wl / wt;
  return wt / k;
}

int main(int argc, char **argv)
{
  TestCount    c  = {0, 0};
  const double cT = sqrt(3.0 / 8.0);

  PetscCall(TestInitialize(&argc, &argv));
  {
    const double cinf = SpeedT(3.0, 1e7, NULL);
    double       prev = 0.0, ratio;
    for (double lw = 25.0; lw <= 2.6e3; lw *= 10.0) {
      const double err = fabs(SpeedT(3.0, lw, &ratio) / cinf - 1.0);
      TestCheck(&c, fabs(ratio - sqrt(3.0)) < 1e-12, "h 3, wavelength %g: omega_L/omega_T = %.15f (sqrt 3)", lw, ratio);
      if (prev > 0.0) TestCheck(&c, err < 0.02 * prev && err > 0.005 * prev, "h 3, wavelength %g: |c_T/c_T(long) - 1| = %.3e, previous %.3e: falls like k^2 (x 1/100)", lw, err, prev);
      prev = err;
    }
    TestCheck(&c, fabs(cinf / cT - 1.0) < 1e-2, "h 3: long-wave c_T = %.6f vs continuum %.6f (lattice-sum error %.2e < 1e-2)", cinf, cT, cinf / cT - 1.0);
  }
  for (double h = 6.0; h <= 12.0; h += 2.0) {
    const double err = SpeedT(h, 1e7, NULL) / cT - 1.0;
    TestCheck(&c, fabs(err) < (h < 12.0 ? 2e-3 : 2e-4), "h %g: long-wave c_T / sqrt(3/8) - 1 = %.2e", h, err);
  }
  {
    /* The PRE crystal: wavelength 24 sqrt(3/4); SPAM is slower than the continuum. */
    const double k = 2.0 * PETSC_PI / (24.0 * sqrt(0.75)), kv[2] = {0.0, k};
    double       wt, wl;
    SpamDispersionLucy(3.0, 1.0, 1.0, sqrt(4.0 / 3.0), lam, eta, kv, &wt, &wl);
    TestCheck(&c, wt / k < cT && wt / k > 0.9 * cT, "PRE crystal: c_T = %.6f below continuum %.6f (period %.4f)", wt / k, cT, 2.0 * PETSC_PI / wt);
  }
  {
    /* Direction independence at long wavelength. */
    const double k = 2.0 * PETSC_PI / 2000.0;
    double       w0, w1, l0, l1;
    const double ka[2] = {k, 0.0}, kb[2] = {k * cos(0.3), k * sin(0.3)};
    SpamDispersionLucy(3.0, 1.0, 1.0, sqrt(4.0 / 3.0), lam, eta, ka, &w0, &l0);
    SpamDispersionLucy(3.0, 1.0, 1.0, sqrt(4.0 / 3.0), lam, eta, kb, &w1, &l1);
    TestCheck(&c, fabs(w1 / w0 - 1.0) < 1e-6, "long waves along x and at 0.3 rad: omega ratio %.10f", w1 / w0);
  }
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
