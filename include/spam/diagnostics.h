/* Global diagnostics of the state, reduced over all ranks. */
#ifndef SPAM_DIAGNOSTICS_H
#define SPAM_DIAGNOSTICS_H
#include <spam/sim.h>

typedef struct {
  double t;
  double mass, p[3], l[3];          /* momentum and angular momentum (about the origin of
                                       the box-local frame; l[2] only in 2D)          */
  double kinetic, internal, total;
  double gyration;                  /* radius of gyration about the centre of mass     */
  double entropy_sum, entropy_grid; /* S/k: particle sum and grid integration          */
} SpamDiagnostics;

typedef struct {
  double    grid_spacing;           /* <= 0 turns the grid estimate off               */
  PetscBool entropy;
} SpamDiagnosticsOptions;

/* Evaluates every diagnostic of state y (raw array) at time t. */
PetscErrorCode SpamDiagnosticsCompute(SpamSim *sim, const SpamDiagnosticsOptions *o, double t, const double *y, SpamDiagnostics *d);

/* Entropy of Hoover & Hoover (2001) Eq. 22 with its sign corrected:
 * s = k (rho/m) ln[(e + <(v - <v>)^2>/2)^(D/2) / rho]. Needs sim->rho filled. */
PetscErrorCode SpamEntropySum(SpamSim *sim, const double *y, double *S);
PetscErrorCode SpamEntropyGrid(SpamSim *sim, const double *y, double spacing, double *S);
#endif
