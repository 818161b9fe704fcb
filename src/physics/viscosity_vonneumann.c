/* von Neumann-Richtmyer artificial viscosity per particle (PRE Sec. IV: "an analog of von
 * Neumann's artificial viscosity"): a bulk pressure under compression only,
 *   q_i = rho_i [beta (h div v)^2 - alpha c h div v]  for div v < 0, else 0,
 * subtracted from the diagonal of sigma/rho^2, so that it resists the approach of
 * particles (the clumping of the tensile instability) and heats through de/dt. */
#include <spam/stress.h>

void SpamVonNeumannViscosity(int dim, double alpha, double beta, double c, double h, const double *g, double rho, double *q)
{
  double div = 0.0;

  for (int a = 0; a < dim; a++) div += g[a * dim + a];
  if (div >= 0.0) return;
  const double p = rho * (beta * h * h * div * div - alpha * c * h * div) / (rho * rho);
  for (int a = 0; a < dim; a++) q[a * dim + a] -= p;
}
