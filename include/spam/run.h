/* Running a simulation: integrator options, the time loop, and its result. */
#ifndef SPAM_RUN_H
#define SPAM_RUN_H
#include <spam/output.h>
#include <spam/error_norm.h>

/* How a run ended: done (ok or at the step limit), blown up, stopped by SIGINT/SIGTERM
 * (outputs complete at the time reached), or failed (a write or library failure). */
typedef enum { SPAM_STATUS_OK, SPAM_STATUS_MAX_STEPS, SPAM_STATUS_UNSTABLE, SPAM_STATUS_INTERRUPTED, SPAM_STATUS_FAILED } SpamStatus;

/* Default of -migrate_interval. A migration after 2 ranks' particles moved up to h/2 took
 * about 7 RHS evaluations of the same particles (decompose.h), and the expansion builds its
 * list about every 3 evaluations: every 20 builds costs about 7 / 60, a tenth of the run,
 * while the fastest particles have moved at most 10 skins (each build follows a move of
 * skin/2), a few cells, so the halo of a rank's bounding box grows by little. */
#define SPAM_MIGRATE_INTERVAL_DEFAULT 20
/* A migration comes sooner, at a list build, once the largest halo has grown by this
 * factor since the last one (loop_migrate.c). */
#define SPAM_MIGRATE_HALO_GROWTH 1.5

typedef struct {
  /* time */
  double   t_end, dt_first, fixed_step;
  PetscInt max_steps;
  /* error control (the arkode and cvode types read their own options: integrator.h) */
  double   rtol, atol;
  PetscBool classic_weights; /* ARKODE's own rtol|y| + atol weights (for comparison)   */
  SpamErrorNorm error_norm;  /* -error_norm: rms or max of the weighted error, every method */
  /* physical step bound (off when 0): dt <= cfl h / c_max and dt <= force sqrt(h / |a|max) */
  double   cfl, force;
  /* failure detection */
  double   dt_min;           /* a step below this is a failure (0: t_end * 1e-12)      */
  double   energy_growth;    /* KE above this many times the energy scale is a blow-up */
  /* output */
  char     output_dir[PETSC_MAX_PATH_LEN];
  char     initial_csv[PETSC_MAX_PATH_LEN], final_csv[PETSC_MAX_PATH_LEN];
  double   output_interval, snapshot_interval;
  PetscBool monitor, hdf5, csv;
  PetscBool output_stop;     /* cut steps to land on output times instead of interpolating */
  SpamDiagnosticsOptions diag;
  /* checkpoints (checkpoint.h): every this much simulated time / wall-clock time (0: off),
   * and the checkpoint a run continues from ("" : a new run) */
  double   checkpoint_interval, checkpoint_wall;
  char     restart[PETSC_MAX_PATH_LEN];
  PetscBool output_interval_set, snapshot_interval_set; /* given, not defaulted */
  PetscInt  migrate_interval; /* several ranks: list builds between migrations (0: none) */
} SpamRunOptions;

typedef struct {
  SpamStatus status;
  char       reason[256];
  int        signal;                 /* SIGINT or SIGTERM when interrupted, else 0     */
  double     t;
  long       steps, attempts, rejected, rhs_evals, limited;
  long       jumps, jump_steps;      /* post-step jumps (reflections), steps with any */
  char       method[96], adapt[32];  /* e.g. "rk 5dp", "basic"; fixed steps: "none"   */
  double     fixed_dt;               /* the fixed step, or 0 when adaptive            */
  double     wall;
  SpamDiagnostics first, last;
  double     energy_drift_max, momentum_drift_max, angmom_drift_max;
  double     momentum_scale, angmom_scale;
  double     energy_scale;           /* the blow-up bound's unit: see time_loop.c       */
  char       output_mode[16];        /* interpolated, stopped or steps (integrator.h)   */
  char       output_mode_reason[200];/* why not interpolated ("" when interpolated)     */
  long       interpolated_rows;      /* rows (and snapshots) written from the interpolant */
  long       interpolation_rhs_evals;/* RHS evaluations the interpolant made (not in rhs_evals) */
  /* checkpoints written by this run: count, size of the last (bytes), its write time (s) */
  long       checkpoints;
  double     checkpoint_bytes, checkpoint_write;
  /* a restart: the checkpoint continued, its time and step, whether the method goes on bit
   * for bit (and why not), and the RHS evaluations the restart made that the
   * uninterrupted run did not (the derivative at the restart state, which it had kept;
   * not in rhs_evals) */
  char       restart_from[PETSC_MAX_PATH_LEN];
  double     restart_t;
  long       restart_step, restart_rhs_evals;
  PetscBool  restart_exact;
  char       restart_why[160];
  /* ranks: how many; migrations between steps and the particles they moved; max/mean of
   * the particle counts at the end; largest count of other ranks' particles a rank holds
   * as ghosts at the end (the halo) */
  int        ranks;
  long       migrations;
  double     migrated, imbalance, halo_max;
} SpamRunResult;

/* Reads and validates every run option; sim gives scene defaults (end time). */
PetscErrorCode SpamRunOptionsParse(const SpamSim *sim, SpamRunOptions *o);
/* The output and snapshot intervals of o checked as the options are (finite, not negative,
 * at most a million rows up to o->t_end); from: NULL for the options, or the checkpoint
 * entry the intervals were read from ("checkpoint PATH: entry 'loop'"), which a refusal
 * then names. */
PetscErrorCode SpamRunOptionsCheckIntervals(const SpamRunOptions *o, const char *from);
/* Reads -output_overwrite, -snapshot_max and -grid_interval; refuses a snapshot interval
 * that would write more than -snapshot_max snapshots and a grid spacing that is negative,
 * not finite, gives too many points over sim's box or has no snapshot times to be written
 * at. Call before the set-up ends (see main.c). */
PetscErrorCode SpamOutputOptionsParse(const SpamSim *sim, const SpamRunOptions *ro, SpamOutputOptions *o);
/* The snapshot count of ro's interval up to ro->t_end against -snapshot_max, and the grid
 * fields against the snapshot times, as SpamOutputOptionsParse checks them; from as for
 * SpamRunOptionsCheckIntervals. */
PetscErrorCode SpamOutputOptionsCheckSnapshots(const SpamSim *sim, const SpamRunOptions *ro, const SpamOutputOptions *o, const char *from);

/* Per-step monitor line and the progress line with ETA. */
PetscErrorCode SpamMonitorStep(const SpamSim *sim, const SpamProgress *p);
PetscErrorCode SpamMonitorProgress(const SpamSim *sim, const SpamRunOptions *o, const SpamProgress *p, const SpamRunResult *r);
/* Drifts of the conserved quantities between two diagnostics. */
void SpamRunUpdateDrifts(const SpamDiagnostics *d, SpamRunResult *r);
PetscErrorCode SpamSummaryWrite(SpamOutput *out, const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r);
/* The exit code of a run that ended with result r (see errors.h; 128 + signal when
 * interrupted, as a shell reports a process a signal ended). */
int SpamRunExitCode(const SpamRunResult *r);
#endif
