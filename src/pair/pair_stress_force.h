/* The pair force of the tensor path and what it does (CiSE Eqs. 13-14; PRE Sec. II):
 *   F_ij = m_i m_j [(sigma/rho^2)_i + (sigma/rho^2)_j].grad_i w_ij = -F_ji,
 *   dv_i/dt += F_ij / m_i,  dv_j/dt -= F_ij / m_j,
 *   de/dt: each particle takes half the pair's work, (v_j - v_i).F_ij / (2 m),
 *   drho_i/dt += m_j (u_i - u_j).grad_i w_ij (continuity; u = v or dr/dt), and alike for j,
 * plus Monaghan's artificial viscosity of an approaching pair (v_ij.r_ij < 0), a central
 * extra pressure Pi_ij = (-alpha c h mu + beta mu^2) / rho_ij, mu = h v_ij.r_ij/(r^2 + 0.01h^2),
 * entering as F_ij -= m_i m_j Pi_ij grad_i w_ij. */
#ifndef SPAM_PAIR_STRESS_FORCE_H
#define SPAM_PAIR_STRESS_FORCE_H
#include <spam/fields.h>

/* F = m_i m_j (Q_i + Q_j) dx g, Q = sigma/rho^2 stored dim x dim. */
static inline __attribute__((always_inline)) void SpamPairStressForce(const int dim, const SpamFields *f, int i, int j, const double dx[3], double g, double F[3])
{
  const double *qi = f->qs + (size_t)i * dim * dim, *qj = f->qs + (size_t)j * dim * dim, c = f->m[i] * f->m[j] * g;
  for (int a = 0; a < 3; a++) F[a] = 0.0;
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) F[a] += c * (qi[a * dim + b] + qj[a * dim + b]) * dx[b];
}

/* Monaghan's Pi_ij (0 for a receding pair). */
static inline __attribute__((always_inline)) double SpamPairMonaghan(const int dim, double alpha, double beta, double c, double h, const double dx[3], const double *vi, const double *vj, double r2, double rho_ij)
{
  double vr = 0.0;
  for (int d = 0; d < dim; d++) vr += (vi[d] - vj[d]) * dx[d];
  if (vr >= 0.0) return 0.0;
  const double mu = h * vr / (r2 + 0.01 * h * h);
  return (-alpha * c * mu + beta * mu * mu) / rho_ij;
}

/* Applies F to both particles: accelerations, energies (half the work each) and, with
 * continuity, the density rates. */
static inline __attribute__((always_inline)) void SpamPairApplyForce(const int dim, SpamFields *f, int i, int j, const double dx[3], double g, const double F[3], int continuity)
{
  const double *vi = f->v + (size_t)i * dim, *vj = f->v + (size_t)j * dim;
  double        work = 0.0, rhod = 0.0;
  for (int d = 0; d < dim; d++) {
    work += 0.5 * (vj[d] - vi[d]) * F[d];
    f->acc[(size_t)i * dim + d] += F[d] * f->minv[i];
    f->acc[(size_t)j * dim + d] -= F[d] * f->minv[j];
    if (continuity) rhod += g * (f->uc[(size_t)i * dim + d] - f->uc[(size_t)j * dim + d]) * dx[d];
  }
  f->edot[i] += work * f->minv[i];
  f->edot[j] += work * f->minv[j];
  if (continuity) {
    f->rhodot[i] += f->m[j] * rhod;
    f->rhodot[j] += f->m[i] * rhod;
  }
}
#endif
