/* SPAM's initial stress of the plane wave (src/scenes/planewave_stress.c):
 *  - a sine displacement on the 24 x 24 crystal has SPAM strain -(m/rho0) G(k) A cos(k y0)
 *    with G the lattice sum of the linearised analysis (dispersion_lucy.c), so its stress
 *    is the continuum stress times omega_spam / omega_continuum; the stress, density and
 *    energy follow Hooke's law, rho0/(1 + div) and sigma:eps/(2 rho0);
 *  - for a random displacement, the lattice index arithmetic (periodic images unfolded)
 *    agrees with a brute-force sum over all particles and images, also in boxes shorter
 *    than 2h where a particle meets several images of another, and so does the summed
 *    density. Bounds: round-off, 1e-12 of the largest term. */
#include <spam/planewave_stress.h>
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

static const double lam = 0.4330127018922193, eta = 0.4330127018922193, h = 3.0;

/* One sine mode on nx x ny: max |sigma - expected| / max |expected| and the same for e, rho. */
static PetscErrorCode SineMode(TestCount *c, PetscBool longitudinal)
{
  const PetscInt nx = 24, ny = 24, n = nx * ny;
  const double   rho0 = sqrt(4.0 / 3.0), A = 0.01, ly = 0.5 * sqrt(3.0) * ny, k = 2.0 * PETSC_PI / ly, kv[2] = {0.0, k};
  double        *x0, *u, *sig, *rho, *e, G[2], wt, wl, err = 0.0, erho = 0.0, ee = 0.0, smax = 0.0;
  SpamKernel     ker;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelLucyInit(2, h, &ker));
  PetscCall(PetscMalloc5(2 * n, &x0, 2 * n, &u, 3 * n, &sig, n, &rho, n, &e));
  SpamLatticeTriangular(nx, ny, 1.0, x0);
  for (PetscInt i = 0; i < n; i++) {
    u[2 * i]     = longitudinal ? 0.0 : A * sin(k * x0[2 * i + 1]);
    u[2 * i + 1] = longitudinal ? A * sin(k * x0[2 * i + 1]) : 0.0;
  }
  {
    const SpamDisplacedLattice L = {nx, ny, 1.0, x0, u, 1.0, lam, eta};
    SpamPlanewaveStressSpam(&ker, &L, rho0, sig, rho, e);
  }
  SpamLatticeGradientSum(h, 1.0, kv, G);
  SpamDispersionLucy(h, 1.0, 1.0, rho0, lam, eta, kv, &wt, &wl);
  for (PetscInt i = 0; i < n; i++) {
    const double g = -G[1] / rho0 * A * cos(k * x0[2 * i + 1]);
    const double want[3] = {longitudinal ? lam * g : 0.0, longitudinal ? 0.0 : eta * g, longitudinal ? (lam + 2.0 * eta) * g : 0.0};
    const double wrho = longitudinal ? rho0 / (1.0 + g) : rho0, we = 0.5 * (longitudinal ? lam + 2.0 * eta : eta) * g * g / rho0;
    for (int q = 0; q < 3; q++) {
      err  = PetscMax(err, fabs(sig[3 * i + q] - want[q]));
      smax = PetscMax(smax, fabs(want[q]));
    }
    erho = PetscMax(erho, fabs(rho[i] - wrho) / rho0);
    ee   = PetscMax(ee, fabs(e[i] - we));
  }
  {
    const char  *name  = longitudinal ? "longitudinal" : "transverse";
    const double ratio = -G[1] / rho0 / k, omega = longitudinal ? wl / (k * sqrt((lam + 2.0 * eta) / rho0)) : wt / (k * sqrt(eta / rho0));
    TestCheck(c, err < 1e-12 * smax, "%s sine, 24 x 24: stress vs Hooke of -(m/rho0) G(k) A cos(k y0): max error %.2e of %.2e", name, err, smax);
    TestCheck(c, erho < 1e-14 && ee < 1e-12 * 0.5 * smax * smax / rho0, "%s sine: density rho0/(1 + div) to %.1e, energy sigma:eps/(2 rho0) to %.1e", name, erho, ee);
    TestCheck(c, fabs(ratio / omega - 1.0) < 1e-12 && ratio < 0.96 && ratio > 0.95, "%s sine: SPAM / continuum strain %.10f = omega_spam / omega_continuum %.10f", name, ratio, omega);
  }
  PetscCall(PetscFree5(x0, u, sig, rho, e));
  PetscFunctionReturn(0);
}

/* Brute force: every particle j and every image within two boxes. */
static void BruteGradient(const SpamKernel *ker, const SpamDisplacedLattice *L, double rho_ref, PetscInt i, double g[4], double *rho)
{
  const PetscInt n = L->nx * L->ny;
  const double   lx = L->a * L->nx, ly = 0.5 * sqrt(3.0) * L->a * L->ny;

  g[0] = g[1] = g[2] = g[3] = 0.0;
  *rho = 0.0;
  for (PetscInt j = 0; j < n; j++)
    for (int sx = -2; sx <= 2; sx++)
      for (int sy = -2; sy <= 2; sy++) {
        const double l[2] = {L->x0[2 * i] - L->x0[2 * j] - sx * lx, L->x0[2 * i + 1] - L->x0[2 * j + 1] - sy * ly}, r2 = l[0] * l[0] + l[1] * l[1];
        *rho += L->mass * SpamKernelW(ker, r2);
        if (r2 == 0.0 || r2 >= ker->h2) continue;
        for (int a = 0; a < 2; a++)
          for (int b = 0; b < 2; b++) g[2 * a + b] += L->mass * SpamKernelDWOverR(ker, r2) / rho_ref * (L->u[2 * j + b] - L->u[2 * i + b]) * l[a];
      }
}

static PetscErrorCode RandomField(TestCount *c, PetscInt nx, PetscInt ny)
{
  const PetscInt n = nx * ny;
  const double   rho_ref = 1.2;
  double        *x0, *u, *sig, *rho, *e, err = 0.0, scale = 0.0, derr;
  uint64_t       seed = 12345;
  SpamKernel     ker;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelLucyInit(2, h, &ker));
  PetscCall(PetscMalloc5(2 * n, &x0, 2 * n, &u, 3 * n, &sig, n, &rho, n, &e));
  SpamLatticeTriangular(nx, ny, 1.0, x0);
  for (PetscInt k = 0; k < 2 * n; k++) u[k] = 0.2 * (TestUniform(&seed) - 0.5);
  {
    const SpamDisplacedLattice L = {nx, ny, 1.0, x0, u, 1.3, lam, eta};
    double                     rho_brute = 0.0;
    SpamPlanewaveStressSpam(&ker, &L, rho_ref, sig, rho, e);
    for (PetscInt i = 0; i < n; i++) {
      double g[4], want[3];
      BruteGradient(&ker, &L, rho_ref, i, g, &rho_brute);
      want[0] = lam * (g[0] + g[3]) + 2.0 * eta * g[0];
      want[1] = eta * (g[1] + g[2]);
      want[2] = lam * (g[0] + g[3]) + 2.0 * eta * g[3];
      for (int q = 0; q < 3; q++) {
        err   = PetscMax(err, fabs(sig[3 * i + q] - want[q]));
        scale = PetscMax(scale, fabs(want[q]));
      }
    }
    derr = fabs(SpamLatticeSummedDensity(&ker, &L) - rho_brute);
  }
  TestCheck(c, err < 1e-12 * scale, "random displacement, %" PetscInt_FMT " x %" PetscInt_FMT " (box %s 2h): stress vs brute force over all images, max error %.2e of %.2e", nx, ny, nx < 6 ? "shorter than" : "at least", err, scale);
  TestReading(PETSC_COMM_SELF, "random_stress_error", err);
  TestCheck(c, derr < 1e-13, "random displacement, %" PetscInt_FMT " x %" PetscInt_FMT ": summed lattice density vs brute force, error %.1e", nx, ny, derr);
  PetscCall(PetscFree5(x0, u, sig, rho, e));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(SineMode(&c, PETSC_FALSE));
  PetscCall(SineMode(&c, PETSC_TRUE));
  PetscCall(RandomField(&c, 8, 8));
  PetscCall(RandomField(&c, 4, 4));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
