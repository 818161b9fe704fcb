/* Torque scaling of a pair force in two dimensions (PRE Sec. VIII): the pair torque
 * L_ij = x_ij F^y - y_ij F^x, and the force with its torque-carrying part (the component
 * perpendicular to r_ij) scaled by a factor. */
#ifndef SPAM_PAIR_TORQUE_H
#define SPAM_PAIR_TORQUE_H

static inline __attribute__((always_inline)) double SpamPairTorque(const double dx[3], const double F[3])
{
  return dx[0] * F[1] - dx[1] * F[0];
}

/* F <- F_par + factor F_perp, F_par along dx. */
static inline __attribute__((always_inline)) void SpamPairScaleTorque(const double dx[3], double r2, double factor, double F[3])
{
  const double along = (F[0] * dx[0] + F[1] * dx[1]) / r2;
  for (int d = 0; d < 2; d++) F[d] = along * dx[d] + factor * (F[d] - along * dx[d]);
}
#endif
