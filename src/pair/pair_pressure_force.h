/* The isentropic gas's pair force (Hoover & Hoover 2001, Eq. 8, with unequal masses):
 *   dv_i/dt = -sum_j m_j [(P/rho^2)_i + (P/rho^2)_j] grad_i w_ij,
 * and the opposite term m_i [...] for j, so that m_i dv_i + m_j dv_j = 0. q = P/rho^2.
 * The one coding of the law for every traversal: with grad_i w_ij = gnorm G(s) (u_i - u_j),
 * particle i's term is f (u_i - u_j) with the factor
 *   f = (c (q_i + q_j)) G(s),  c = -m gnorm when every particle has the mass m,
 * else c = -gnorm and the terms m_j f (u_i - u_j) for i, -m_i f (u_i - u_j) for j. */
#ifndef SPAM_PAIR_PRESSURE_FORCE_H
#define SPAM_PAIR_PRESSURE_FORCE_H
#include "../kernels/kernel_shape.h"

static inline __attribute__((always_inline)) double SpamPairPressureFactor(const int kind, const int dim, double c, double qi, double qj, double s)
{
  return SpamKernelShapeScaledG(kind, dim, c * (qi + qj), s);
}
#endif
