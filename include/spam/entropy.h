/* Entropy of the isentropic gas (Hoover & Hoover 2001, Eq. 22 with its sign corrected):
 * s = k (rho/m) ln[(e + <(v - <v>)^2>/2)^(D/2) / rho], summed over the particles or
 * integrated on a grid. Both need sim->pair.f.rho filled (the summed density of y). Both are
 * collective on sim->p.comm and give every rank the same S: the sum adds the ranks' sums of
 * per-particle terms; the grid adds the ranks' kernel sums at each point (density,
 * momentum, |v|^2) before the logarithm, which a sum of the ranks' entropies would get
 * wrong (ln of a part of the density). */
#ifndef SPAM_ENTROPY_H
#define SPAM_ENTROPY_H
#include <spam/sim.h>

PetscErrorCode SpamEntropySum(SpamSim *sim, const double *y, double *S);
PetscErrorCode SpamEntropyGrid(SpamSim *sim, const double *y, double spacing, double *S);
#endif
