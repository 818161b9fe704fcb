/* Newtonian viscosity: shear viscosity eta_s on the traceless strain rate and bulk
 * viscosity eta_b on the divergence, in D dimensions,
 *   sigma_v = eta_s (G + G^T - (2/D) (div v) I) + eta_b (div v) I,
 * added to the stress of the tensor path (a gas, or a Kelvin-Voigt solid). It enters the
 * pair force like any stress, so the energy equation turns its work into heat. */
#include <spam/stress.h>

void SpamNewtonianViscosity(int dim, double eta_s, double eta_b, const double *g, double rho, double *q)
{
  const double r2 = rho * rho;
  double       div = 0.0;

  for (int a = 0; a < dim; a++) div += g[a * dim + a];
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) {
      double s = eta_s * (g[a * dim + b] + g[b * dim + a]);
      if (a == b) s += (eta_b - 2.0 * eta_s / dim) * div;
      q[a * dim + b] += s / r2;
    }
}
