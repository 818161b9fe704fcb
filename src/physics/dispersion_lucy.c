/* Plane waves of the linearised SPAM elastic solid on the perfect triangular lattice.
 *
 * About a lattice at rest with zero stress and density rho0, perturbations ~ exp(i k.r_i)
 * obey (first order; rho_ij = rho0; the stress is zero, so the density, the R0/R1/R2
 * choice and the rotation terms enter only at second order):
 *   grad v  = -i (m/rho0) G (x) V,        G(k) = sum_l sin(k.l) (w'/r)(|l|) l,
 *   dV/dt   = -i (m/rho0^2) G . S,        dS/dt = lambda tr(grad v) I + eta (grad v + grad v^T),
 * the sum over lattice vectors l with |l| < h. Hence
 *   d2V/dt2 = -(m^2/rho0^3) [(lambda + eta)(G.V) G + eta |G|^2 V],
 * whose modes are transverse (V perpendicular to G), omega^2 = eta m^2 |G|^2 / rho0^3, and
 * longitudinal (V along G), omega^2 = (lambda + 2 eta) m^2 |G|^2 / rho0^3. For small k,
 * G -> -n k (n the number density, since the lattice sum of (w'/r) l l^T tends to -n I),
 * which gives the continuum speeds sqrt(eta/rho0) and sqrt((lambda + 2 eta)/rho0) when
 * rho0 = m n. */
#include <spam/physics.h>

void SpamLatticeGradientSum(double h, double a, const double k[2], double G[2])
{
  SpamKernel   ker;
  const int    nmax = (int)ceil(h / a) + 2;
  const double ry   = 0.5 * sqrt(3.0) * a;

  G[0] = G[1] = 0.0;
  (void)SpamKernelLucyInit(2, h, &ker);
  for (int row = -nmax; row <= nmax; row++)
    for (int col = -nmax; col <= nmax; col++) {
      const double l[2] = {a * (col + 0.5 * row), ry * row};
      const double r2   = l[0] * l[0] + l[1] * l[1];
      if (r2 == 0.0 || r2 >= ker.h2) continue;
      const double c = sin(k[0] * l[0] + k[1] * l[1]) * SpamKernelDWOverR(&ker, r2);
      G[0] += c * l[0];
      G[1] += c * l[1];
    }
}

void SpamDispersionLucy(double h, double a, double mass, double rho0, double lambda, double eta, const double k[2], double *omega_t, double *omega_l)
{
  double G[2], g2;

  SpamLatticeGradientSum(h, a, k, G);
  g2       = G[0] * G[0] + G[1] * G[1];
  *omega_t = sqrt(eta * mass * mass * g2 / (rho0 * rho0 * rho0));
  *omega_l = sqrt((lambda + 2.0 * eta) * mass * mass * g2 / (rho0 * rho0 * rho0));
}
