/* The record of a run as data: how it ended, the options it ran with and what it
 * measured. The time loop (integrate) fills it; the summary and the output checks (io)
 * read it, so it lives apart from both. */
#ifndef SPAM_RUN_RECORD_H
#define SPAM_RUN_RECORD_H
#include <spam/output.h>

/* The norm of the weighted error estimate (-error_norm; error_norm.h says what each means). */
typedef enum { SPAM_ERROR_NORM_RMS, SPAM_ERROR_NORM_MAX } SpamErrorNorm;

/* How a run ended: done (ok or at the step limit), blown up, stopped by SIGINT/SIGTERM
 * (outputs complete at the time reached), or failed (a write or library failure). */
typedef enum { SPAM_STATUS_OK, SPAM_STATUS_MAX_STEPS, SPAM_STATUS_UNSTABLE, SPAM_STATUS_INTERRUPTED, SPAM_STATUS_FAILED } SpamStatus;

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
  PetscBool quiet;           /* only the last line: no start line, no progress lines      */
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

#endif
