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
  /* Mirror walls (zero without): the books integrated with the state (work, heat into the
   * fluid and the impulse given it, where the model has the energy equation), and what
   * each wall gives at this state (an RHS evaluation at the output time). */
  double        wall_work, wall_heat, wall_impulse[3];
  SpamWallRates wall;
  /* What the outside gave the system since t = 0: energy (the walls' work and heat) and
   * momentum (their impulse and gravity's M g t). The drifts are measured net of them. */
  double        energy_in, momentum_in[3];
  /* The energy the gas flow scheme's laws gave the particles (gas_flow.h: its book in the
   * state, 0 without), counted in energy_in so that the drift measures the integration. */
  double        scheme_energy;
} SpamDiagnostics;

typedef struct {
  double    grid_spacing;           /* <= 0 turns the grid estimate off               */
  PetscBool entropy;
  PetscBool entropy_gas;            /* the gas's sum estimate (-diag_entropy given)   */
} SpamDiagnosticsOptions;

/* Evaluates every diagnostic of state y (raw array) at time t. */
PetscErrorCode SpamDiagnosticsCompute(SpamSim *sim, const SpamDiagnosticsOptions *o, double t, const double *y, SpamDiagnostics *d);

/* The walls' part of d at state y (nothing without walls): the books and the rates. */
PetscErrorCode SpamWallDiagnostics(SpamSim *sim, const double *y, SpamDiagnostics *d);
/* The walls' columns of timeseries.csv for this run ("" without walls): a leading comma,
 * then wall_work, wall_heat, wall_impulse_x.. (books) and per wall face F wall_F_fx..,
 * wall_F_work_rate, wall_F_heat_rate. */
void SpamWallColumns(const SpamSim *sim, char *buf, size_t len);
/* The values of those columns (same order) from d. */
void SpamWallValues(const SpamSim *sim, const SpamDiagnostics *d, char *buf, size_t len);
#endif
