/* Global diagnostics of the state, reduced over all ranks. */
#ifndef SPAM_DIAGNOSTICS_H
#define SPAM_DIAGNOSTICS_H
#include <spam/sim.h>

typedef struct {
  double t;
  double mass, p[3], l[3];          /* momentum and angular momentum (about the origin of
                                       the box-local frame; l[2] only in 2D)          */
  double kinetic, internal, total; /* total = kinetic + internal + potential            */
  double potential;                 /* of uniform gravity, -sum m g.(x - box corner)   */
  double gyration;                  /* radius of gyration about the centre of mass     */
  double entropy_sum, entropy_grid; /* S/k: particle sum and grid integration          */
  /* Elastic solid and spring models (NaN or 0 where they do not apply):               */
  double torque;                    /* spurious torque sum_{i<j} Ldot_ij, unscaled      */
  int    nbody;                     /* connected bodies at set-up (0: not labelled)     */
  double lbody[2];                  /* Lz of bodies 0 and 1 about their own centres     */
  double gauss_singular;            /* RHS evaluations where Gauss's principle was singular */
} SpamDiagnostics;

typedef struct {
  double    grid_spacing;           /* <= 0 turns the grid estimate off               */
  PetscBool entropy;
} SpamDiagnosticsOptions;

/* Evaluates every diagnostic of state y (raw array) at time t. */
PetscErrorCode SpamDiagnosticsCompute(SpamSim *sim, const SpamDiagnosticsOptions *o, double t, const double *y, SpamDiagnostics *d);

#endif
