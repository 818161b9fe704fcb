/* Gradients of the tensor path, each pair term the same for i and j (both factors change
 * sign), weighted by the other particle's mass:
 *   velocity (CiSE Eq. 18, PRE sign fixed):
 *     (grad v)_i^{ab} = dv^b/dx^a = sum_j m_j (v_j - v_i)^b (grad_i w_ij)^a / rho_ij,
 *   temperature (CiSE Eq. 19):  (grad T)_i = sum_j m_j (T_j - T_i) grad_i w_ij / rho_ij,
 * with grad_i w_ij = g dx and rho_ij the arithmetic or geometric pair mean. The velocity
 * gradient takes a factor per side (c_i = g / rho_i, c_j = g / rho_j for the form over each
 * particle's own density). */
#ifndef SPAM_PAIR_GRADIENTS_H
#define SPAM_PAIR_GRADIENTS_H
#include <spam/fields.h>
#include <math.h>

static inline __attribute__((always_inline)) double SpamPairMeanDensity(int geometric, double ri, double rj)
{
  return geometric ? sqrt(ri * rj) : 0.5 * (ri + rj);
}

static inline __attribute__((always_inline)) void SpamPairVelocityGradient(const int dim, SpamFields *f, int i, int j, const double dx[3], double ci, double cj)
{
  const double *vi = f->v + (size_t)i * dim, *vj = f->v + (size_t)j * dim;
  double       *gi = f->gradv + (size_t)i * dim * dim, *gj = f->gradv + (size_t)j * dim * dim;
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++) {
      const double ti = ci * (vj[b] - vi[b]) * dx[a], tj = cj * (vj[b] - vi[b]) * dx[a]; /* ci == cj: the one-factor sums, bit for bit */
      gi[a * dim + b] += f->m[j] * ti;
      gj[a * dim + b] += f->m[i] * tj;
    }
}

static inline __attribute__((always_inline)) void SpamPairTemperatureGradient(const int dim, SpamFields *f, int i, int j, const double dx[3], double c)
{
  const double t = c * (f->T[j] - f->T[i]);
  for (int a = 0; a < dim; a++) {
    f->heat[(size_t)i * dim + a] += f->m[j] * t * dx[a];
    f->heat[(size_t)j * dim + a] += f->m[i] * t * dx[a];
  }
}
#endif
