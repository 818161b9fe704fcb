/* von Neumann-Richtmyer artificial viscosity per particle (PRE Sec. IV: "an analog of von
 * Neumann's artificial viscosity"): a bulk pressure under compression only,
 *   q_i = rho_i [beta (h div v)^2 - alpha c h div v]  for div v < 0, else 0,
 * subtracted from the diagonal of sigma/rho^2, so that it resists the approach of
 * particles (the clumping of the tensile instability) and heats through de/dt. */
#include <spam/physics.h>

void SpamViscosityVonNeumann(const SpamSim *sim, const double *gradv, double *qs)
{
  const SpamSolidParams *s = &sim->model.solid;
  const double           h = sim->model.kernel.h;

  for (PetscInt i = 0; i < sim->n; i++) {
    const double div = gradv[4 * i] + gradv[4 * i + 3];
    if (div >= 0.0) continue;
    const double q = sim->rho[i] * (s->visc_beta * h * h * div * div - s->visc_alpha * s->sound_speed * h * div);
    qs[3 * i] -= q / (sim->rho[i] * sim->rho[i]);
    qs[3 * i + 2] -= q / (sim->rho[i] * sim->rho[i]);
  }
}
