/* Running a simulation: integrator options, the time loop, and its result. */
#ifndef SPAM_RUN_H
#define SPAM_RUN_H
#include <spam/output.h>

typedef enum { SPAM_STATUS_OK, SPAM_STATUS_MAX_STEPS, SPAM_STATUS_UNSTABLE } SpamStatus;

typedef struct {
  /* time */
  double   t_end, dt_first, fixed_step;
  PetscInt max_steps;
  /* error control */
  double   rtol, atol, safety, max_growth;
  char     table[64], adapt[16];
  PetscBool classic_weights; /* ARKODE's own rtol|y| + atol weights (for comparison)   */
  /* output */
  char     output_dir[PETSC_MAX_PATH_LEN];
  char     initial_csv[PETSC_MAX_PATH_LEN], final_csv[PETSC_MAX_PATH_LEN];
  double   output_interval, snapshot_interval;
  PetscBool monitor, hdf5, csv;
  SpamDiagnosticsOptions diag;
} SpamRunOptions;

typedef struct {
  SpamStatus status;
  char       reason[256];
  double     t;
  long       steps, attempts, rejected, rhs_evals;
  double     wall;
  SpamDiagnostics first, last;
  double     energy_drift_max, momentum_drift_max, angmom_drift_max;
  double     momentum_scale, angmom_scale;
} SpamRunResult;

/* Reads and validates every run option; sim gives scene defaults (end time). */
PetscErrorCode SpamRunOptionsParse(const SpamSim *sim, SpamRunOptions *o);
/* Integrates with ARKODE ERKStep to t_end, writing outputs as it goes. */
PetscErrorCode SpamRunArkode(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, SpamRunResult *r);
/* Per-step monitor line and the progress line with ETA. */
PetscErrorCode SpamMonitorStep(const SpamSim *sim, const SpamProgress *p);
PetscErrorCode SpamMonitorProgress(const SpamSim *sim, const SpamRunOptions *o, const SpamProgress *p, const SpamRunResult *r);
/* Drifts of the conserved quantities between two diagnostics. */
void SpamRunUpdateDrifts(const SpamDiagnostics *d, SpamRunResult *r);
PetscErrorCode SpamSummaryWrite(const SpamOutput *out, const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r);
#endif
