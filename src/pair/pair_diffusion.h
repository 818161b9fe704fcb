/* Viscosity and conduction as pair Laplacians, in one pass (the flow scheme's diffusion
 * form "pair"):
 *   dv_i/dt += sum_j m_j (eta_i + eta_j) N_ij g_ij (v_i - v_j) / (rho_i rho_j)
 *   de_i/dt += sum_j m_j (kappa_i + kappa_j) N_ij g_ij (T_i - T_j) / (rho_i rho_j)
 * with g_ij = w'(r)/r (grad_i w_ij = g dx), after Brookshaw (1985) for conduction and
 * Morris, Fox and Zhu (1997) for the shear viscosity: 2 sum_j V_j (f_i - f_j) g_ij is the
 * Laplacian of f to second order in a smooth field. N_ij = (N_i + N_j)/2 with
 * N_i = -D / tr M_i (M the SPAM gradient's moment, -I in the continuum limit) makes the
 * Laplacian of a quadratic field exact on the particles' own arrangement: without it the
 * convection cell's lattice (Lucy, h = 3) conducts 4 % less than kappa.
 *
 * Why a second form: the gradient form (grad v, then the divergence of the stress) has a
 * null space at the particle scale. A velocity or temperature that alternates from one
 * particle to the next has zero SPAM gradient at every particle, so it is never damped.
 * Where pressure dominates viscosity and the flow scheme has taken the pressure's
 * stiffness away, that noise is fed by the heat flux and the particles' rearrangement and
 * stays: in the convection cell's conduction state at 0.1 Ra_c the particles keep about
 * the seed's kinetic energy for thousands of time units. The pair form damps every pair's
 * relative velocity and temperature.
 *
 * The pair form conserves momentum and energy pair by pair: the force is antisymmetric and
 * its work, (v_j - v_i).F / 2 to each particle, heats both (F is along -(v_i - v_j)); the
 * heat rates m_i de_i and m_j de_j cancel. The force runs along v_i - v_j, not along the
 * pair's axis, so it does not conserve angular momentum exactly. */
#ifndef SPAM_PAIR_DIFFUSION_H
#define SPAM_PAIR_DIFFUSION_H
#include <spam/fields.h>

/* The pair's factor N_ij g_ij / (rho_i rho_j). */
static inline __attribute__((always_inline)) double SpamPairDiffusionFactor(const SpamFields *f, int i, int j, double g)
{
  return 0.5 * (f->lapn[i] + f->lapn[j]) * g / (f->rho[i] * f->rho[j]);
}

/* Adds the viscous pair force on i (constant eta) to F. */
static inline __attribute__((always_inline)) void SpamPairViscousDiffusion(const int dim, const SpamFields *f, int i, int j, double eta, double k, double F[3])
{
  const double c = 2.0 * eta * k * f->m[i] * f->m[j];
  for (int d = 0; d < dim; d++) F[d] += c * (f->v[(size_t)i * dim + d] - f->v[(size_t)j * dim + d]);
}

/* The conducted heat rate into qdot (constant kappa), apart from the work as the
 * gradient form's. */
static inline __attribute__((always_inline)) void SpamPairHeatDiffusion(SpamFields *f, int i, int j, double kappa, double k)
{
  const double q = 2.0 * kappa * k * (f->T[i] - f->T[j]);
  f->qdot[i] += f->m[j] * q;
  f->qdot[j] -= f->m[i] * q;
}

/* The conducted heat rate made exact for a linear temperature on any arrangement
 * (-conduction_linear). The pair Laplacian conducts a linear T exactly only where the
 * arrangement's first moment sum_j V_j g_ij (x_i - x_j) vanishes (a symmetric lattice).
 * Where the particles have moved it does not, and the conduction state's heat flux, read
 * through it, heats or cools particles by the flux times that moment: in the convection
 * cell (flow scheme, 0.9 Ra_c) this heating fed the roll at about its whole growth rate,
 * and the roll grew below onset. Each side subtracts its own first-order part,
 *   de_i/dt += sum_j m_j 2 kappa N_ij g_ij (T_i - T_j - G_i . (x_i - x_j)) / (rho_i rho_j),
 * G the kernel-gradient-corrected grad T (-M^-1 times the SPAM gradient: exact for linear
 * T), as in the corrected Laplacians of Fatehi and Manzari (2011); the Laplacian of a
 * quadratic stays exact. The two sides no longer cancel: the plain pair form goes into
 * qdot (the walls' books read it there: what crosses a wall is the plain form's
 * exchange with the images), each side's correction into qlin, which the flow scheme's
 * book carries. A mirror image (own_j = 0) takes no correction: its side is the wall's.
 * A periodic ghost slot (own_j = 1) takes its source's G, gathered, and its side is
 * folded onto the source. Another rank's particle (own_j = 0) takes its side on its own
 * rank, where the same pair is computed from the other end with the same operands (the
 * halo carries G to the remote slots with the other gathered fields). */
static inline __attribute__((always_inline)) void SpamPairHeatDiffusionLinear(const int dim, SpamFields *f, int i, int j, double kappa, double k, const double dx[3], int own_j)
{
  const double *Gi = f->heat + (size_t)i * dim, *Gj = f->heat + (size_t)j * dim, c = 2.0 * kappa * k;
  double        si = 0.0, sj = 0.0;
  SpamPairHeatDiffusion(f, i, j, kappa, k);
  for (int d = 0; d < dim; d++) si += Gi[d] * dx[d];
  f->qlin[i] -= f->m[j] * c * si;
  if (!own_j) return;
  for (int d = 0; d < dim; d++) sj += Gj[d] * dx[d];
  f->qlin[j] += f->m[i] * c * sj;
}
#endif
