/* Isentropic ideal gas P = kappa rho^gamma (the isentropes of the ideal gas have
 * gamma = 1 + 2/D). e = P/((gamma-1) rho) is the energy per unit mass. */
#ifndef SPAM_EOS_H
#define SPAM_EOS_H
#include <math.h>
#include <petscsys.h>

typedef struct {
  double gamma, kappa;
} SpamEosIsentrope;

static inline double SpamEosPOverRho2(const SpamEosIsentrope *q, double rho)
{
  return q->kappa * pow(rho, q->gamma - 2.0);
}
static inline double SpamEosEnergy(const SpamEosIsentrope *q, double rho)
{
  return q->kappa * pow(rho, q->gamma - 1.0) / (q->gamma - 1.0);
}
static inline double SpamEosSoundSpeed(const SpamEosIsentrope *q, double rho)
{
  return sqrt(q->gamma * q->kappa * pow(rho, q->gamma - 1.0));
}
/* True when P/rho^2 does not depend on rho (gamma = 2): the force then needs no density
 * (Hoover & Hoover 2001, Eq. 20). */
PetscBool SpamEosDensityFree(const SpamEosIsentrope *q);
#endif
