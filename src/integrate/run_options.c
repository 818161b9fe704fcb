/* Options of a run: integrator, tolerances, end time and outputs. */
#include <spam/run.h>
#include <spam/errors.h>
#include <float.h>

/* Cap on what one run may write: the count of rows follows from the end time and the
 * interval, so a tiny interval is refused before anything is written. (The snapshot count
 * is capped by -snapshot_max, in output_options.c.) */
#define MAX_OUTPUT_ROWS 1000000.0
/* The entropy grid integral samples every cell at every output row. */
#define MAX_GRID_CELLS 1e8
/* A step bound below this fraction of its time scale would need over a million steps per
 * crossing of h (-step_cfl, -step_force are dimensionless). */
#define MIN_BOUND_FRACTION 1e-6

/* How a refusal names a value: the option as the user typed it, or (from: the checkpoint
 * entry it was read from, "checkpoint PATH: entry 'loop'") that entry and the option it
 * stands for, with the value as stored. */
static PetscErrorCode Name(const char *opt, const char *from, double v, char *name, size_t nlen, char *val, size_t vlen)
{
  PetscFunctionBeginUser;
  if (from) {
    (void)snprintf(name, nlen, "%s (its %s)", from, opt);
    (void)snprintf(val, vlen, "%.17g", v);
  } else {
    (void)snprintf(name, nlen, "%s", opt);
    PetscCall(SpamOptionText(opt, v, val, vlen));
  }
  PetscFunctionReturn(0);
}

/* v must be finite and >= lo (> lo when lo_open); a subnormal positive value is "too small". */
static PetscErrorCode CheckRangeFrom(const char *opt, const char *from, double v, double lo, PetscBool lo_open, const char *what)
{
  char name[PETSC_MAX_PATH_LEN + 128], val[128];

  PetscFunctionBeginUser;
  PetscCall(Name(opt, from, v, name, sizeof name, val, sizeof val));
  if (!isfinite(v) || v < lo || (lo_open && v == lo)) SPAM_BAD_INPUT(name, val, "%s", what);
  if (v != 0.0 && fabs(v) < DBL_MIN) SPAM_BAD_INPUT(name, val, "too small (subnormal): %s", what);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckRange(const char *opt, double v, double lo, PetscBool lo_open, const char *what)
{
  PetscFunctionBeginUser;
  PetscCall(CheckRangeFrom(opt, NULL, v, lo, lo_open, what));
  PetscFunctionReturn(0);
}

/* The count of items t_end / interval must stay within max. */
static PetscErrorCode CheckCountFrom(const char *opt, const char *from, double interval, double t_end, double max, const char *what)
{
  char name[PETSC_MAX_PATH_LEN + 128], val[128];

  PetscFunctionBeginUser;
  PetscCall(Name(opt, from, interval, name, sizeof name, val, sizeof val));
  if (interval > 0 && t_end > 0 && !(t_end / interval <= max)) SPAM_BAD_INPUT(name, val, "would write %.3g %s to -ts_max_time %.6g; at most %.0f: use an interval of at least %.6g (or 0: none)", t_end / interval, what, t_end, max, t_end / max);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckCount(const char *opt, double interval, double t_end, double max, const char *what)
{
  PetscFunctionBeginUser;
  PetscCall(CheckCountFrom(opt, NULL, interval, t_end, max, what));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRunOptionsCheckIntervals(const SpamRunOptions *o, const char *from)
{
  PetscFunctionBeginUser;
  PetscCall(CheckRangeFrom("-output_interval", from, o->output_interval, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckRangeFrom("-snapshot_interval", from, o->snapshot_interval, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckCountFrom("-output_interval", from, o->output_interval, o->t_end, MAX_OUTPUT_ROWS, "diagnostics rows"));
  PetscFunctionReturn(0);
}

/* A given step below the run's step floor would be reported as a collapse at once. */
static PetscErrorCode CheckStep(const char *opt, double dt, double floor)
{
  char val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, dt, val, sizeof val));
  if (dt > 0 && dt < floor) SPAM_BAD_INPUT(opt, val, "below the run's step floor %.6g (-unstable_dt_min, default 1e-12 -ts_max_time)", floor);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckTimes(const SpamRunOptions *o)
{
  double floor;
  char   val[128];

  PetscFunctionBeginUser;
  PetscCall(CheckRange("-ts_max_time", o->t_end, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(SpamOptionText("-ts_max_time", o->t_end, val, sizeof val));
  /* The step floor 1e-12 t_end must itself be a normal number. */
  if (o->t_end > 0 && !(1e-12 * o->t_end >= DBL_MIN)) SPAM_BAD_INPUT("-ts_max_time", val, "too small: the step floor 1e-12 t_end would be subnormal; t_end must be 0 or at least %.3g", DBL_MIN * 1e12);
  PetscCall(CheckRange("-unstable_dt_min", o->dt_min, 0.0, PETSC_FALSE, "must be zero (default) or positive"));
  floor = o->dt_min > 0 ? o->dt_min : 1e-12 * o->t_end;
  PetscCall(CheckRange("-ts_dt", o->dt_first, 0.0, PETSC_FALSE, "must be zero (estimate) or positive"));
  if (o->t_end > 0) {
    PetscCall(CheckStep("-ts_dt", o->dt_first, floor));
  }
  PetscCall(SpamRunOptionsCheckIntervals(o, NULL));
  PetscFunctionReturn(0);
}

/* The grid of the entropy integral: cells counted in double, so a tiny spacing cannot
 * overflow the count. */
static PetscErrorCode CheckGrid(const SpamGeometry *geo, const SpamRunOptions *o)
{
  double cells = 1.0;
  char   val[128];

  PetscFunctionBeginUser;
  PetscCall(CheckRange("-diag_grid_spacing", o->diag.grid_spacing, 0.0, PETSC_FALSE, "must be zero (off) or a positive spacing"));
  if (!(o->diag.entropy && o->diag.grid_spacing > 0)) PetscFunctionReturn(0);
  for (int d = 0; d < geo->box.dim; d++) cells *= PetscMax(1.0, ceil(geo->box.len[d] / o->diag.grid_spacing));
  PetscCall(SpamOptionText("-diag_grid_spacing", o->diag.grid_spacing, val, sizeof val));
  if (!(cells <= MAX_GRID_CELLS)) SPAM_BAD_INPUT("-diag_grid_spacing", val, "the box would hold %.3g grid cells, at most %.0e (sampled at every output row)", cells, MAX_GRID_CELLS);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRunOptionsParse(const SpamSim *sim, SpamRunOptions *o)
{
  PetscBool restart = PETSC_FALSE, entropy_set = PETSC_FALSE, grid_set = PETSC_FALSE;

  PetscFunctionBeginUser;
  /* The -arkode_* and -cvode_* options are the arkode and cvode TS types' own, read by
   * their setfromoptions (arkode_options.c, ts_cvode.c). */
  PetscCall(PetscMemzero(o, sizeof *o));
  o->t_end             = sim->out.scene.t_end_default;
  o->max_steps         = 1000000000;
  o->rtol              = 1e-6;
  o->atol              = 1e-9;
  o->energy_growth     = 10.0;
  o->migrate_interval  = SPAM_MIGRATE_INTERVAL_DEFAULT;
  o->hdf5              = PETSC_TRUE;
  o->csv               = PETSC_TRUE;
  o->diag.entropy      = PETSC_TRUE;
  o->diag.grid_spacing = 1.0;
  PetscCall(PetscStrncpy(o->output_dir, "./out", sizeof o->output_dir));
  PetscOptionsBegin(sim->p.comm, NULL, "Time integration: -ts_type arkode (default), arkode_imex, cvode, rk, ssp, euler, basicsymplectic, block_kdk; PETSc's own -ts_* options are listed under TS", "spam-ark");
  PetscCall(PetscOptionsReal("-ts_max_time", "End time (default: the scene's, 2 sound traversal times for expansion)", "README", o->t_end, &o->t_end, NULL));
  PetscCall(PetscOptionsInt("-ts_max_steps", "Stop after this many steps", "README", o->max_steps, &o->max_steps, NULL));
  PetscCall(PetscOptionsReal("-ts_dt", "First step of adaptive methods, the step of fixed-step TS methods (0: arkode/cvode estimate it, TS methods take 0.05 h/c0)", "README", o->dt_first, &o->dt_first, NULL));
  PetscCall(PetscOptionsReal("-ts_rtol", "Relative tolerance (positions are weighed against h)", "README", o->rtol, &o->rtol, NULL));
  PetscCall(PetscOptionsReal("-ts_atol", "Absolute tolerance", "README", o->atol, &o->atol, NULL));
  PetscCall(PetscOptionsReal("-step_cfl", "CFL bound dt <= C h / c_max on adaptive steps (0: off)", "README", o->cfl, &o->cfl, NULL));
  PetscCall(PetscOptionsReal("-step_force", "Force bound dt <= C' sqrt(h / |a|max) on adaptive steps (0: off)", "README", o->force, &o->force, NULL));
  PetscCall(PetscOptionsReal("-unstable_dt_min", "A step below this is a failure (0: 1e-12 t_end)", "README", o->dt_min, &o->dt_min, NULL));
  PetscCall(PetscOptionsReal("-unstable_energy_growth", "Kinetic energy above this many times the initial energy is a failure (0: off)", "README", o->energy_growth, &o->energy_growth, NULL));
  PetscCall(PetscOptionsBool("-arkode_classic_weights", "Use ARKODE's rtol|y|+atol weights (not translation invariant; for comparison)", "README", o->classic_weights, &o->classic_weights, NULL));
  PetscCall(PetscOptionsString("-output_dir", "Directory for timeseries.csv, steps.csv, summary.json and snapshots", "README", o->output_dir, o->output_dir, sizeof o->output_dir, NULL));
  o->output_interval   = o->t_end / 100.0;
  o->snapshot_interval = o->t_end / 8.0;
  PetscCall(PetscOptionsReal("-output_interval", "Time between diagnostics rows (default end time / 100; 0: start and end only)", "README", o->output_interval, &o->output_interval, &o->output_interval_set));
  PetscCall(PetscOptionsReal("-snapshot_interval", "Time between particle snapshots (default end time / 8; 0: none)", "README", o->snapshot_interval, &o->snapshot_interval, &o->snapshot_interval_set));
  PetscCall(PetscOptionsBool("-snapshot_hdf5", "Write HDF5 + XDMF snapshots (ParaView)", "README", o->hdf5, &o->hdf5, NULL));
  PetscCall(PetscOptionsBool("-snapshot_csv", "Write CSV snapshots (chart scripts)", "README", o->csv, &o->csv, NULL));
  PetscCall(PetscOptionsBool("-monitor", "Print a line per step", "README", o->monitor, &o->monitor, NULL));
  PetscCall(PetscOptionsBool("-quiet", "Print only the run's last line (no start line, no progress line at each output time)", "README", o->quiet, &o->quiet, NULL));
  PetscCall(PetscOptionsBool("-output_stop", "Cut steps to land on every output time instead of writing the outputs from the method's interpolant", "README", o->output_stop, &o->output_stop, NULL));
  PetscCall(PetscOptionsBool("-diag_entropy", "Compute the entropy estimates (the isentrope's by default; the gas's particle sum, with its own e_i, when given)", "README", o->diag.entropy, &o->diag.entropy, &entropy_set));
  PetscCall(PetscOptionsReal("-diag_grid_spacing", "Grid spacing of the entropy integral (0: off)", "README", o->diag.grid_spacing, &o->diag.grid_spacing, &grid_set));
  PetscCall(PetscOptionsString("-initial_csv", "Also write the initial particles to this CSV (file-scene format)", "README", o->initial_csv, o->initial_csv, sizeof o->initial_csv, NULL));
  PetscCall(PetscOptionsString("-final_csv", "Also write the final particles to this CSV (file-scene format)", "README", o->final_csv, o->final_csv, sizeof o->final_csv, NULL));
  PetscCall(PetscOptionsReal("-checkpoint_interval", "Write OUTPUT_DIR/checkpoint.h5 every this much simulated time (0: off; one is always written on SIGINT/SIGTERM)", "README", o->checkpoint_interval, &o->checkpoint_interval, NULL));
  PetscCall(PetscOptionsReal("-checkpoint_wall", "Write OUTPUT_DIR/checkpoint.h5 every this many wall-clock seconds (0: off)", "README", o->checkpoint_wall, &o->checkpoint_wall, NULL));
  PetscCall(PetscOptionsInt("-migrate_interval", "On several ranks: neighbour-list builds between migrations of the particles to the owners of their cells, sooner when the halo grew by half (0: only at the start)", "README", o->migrate_interval, &o->migrate_interval, NULL));
  PetscCall(PetscOptionsString("-restart", "Continue the run saved in this checkpoint (its options must be the same but for outputs and the end)", "README", o->restart, o->restart, sizeof o->restart, &restart));
  PetscOptionsEnd();
  if (restart && !o->restart[0]) SPAM_BAD_INPUT("-restart", "", "names no file: give the checkpoint to continue from (OUTPUT_DIR/checkpoint.h5)");
  PetscCall(SpamErrorNormOptions(sim->p.comm, &o->error_norm));
  PetscCall(CheckTimes(o));
  PetscCall(CheckRange("-ts_rtol", o->rtol, 0.0, PETSC_TRUE, "a tolerance must be positive"));
  PetscCall(CheckRange("-ts_atol", o->atol, 0.0, PETSC_TRUE, "a tolerance must be positive"));
  PetscCall(CheckRange("-step_cfl", o->cfl, 0.0, PETSC_FALSE, "must be zero (off) or positive"));
  PetscCall(CheckRange("-step_force", o->force, 0.0, PETSC_FALSE, "must be zero (off) or positive"));
  PetscCall(CheckRange("-unstable_energy_growth", o->energy_growth, 0.0, PETSC_FALSE, "must be zero (off) or positive"));
  {
    char val[128];
    PetscCall(SpamOptionText("-step_cfl", o->cfl, val, sizeof val));
    if (o->cfl > 0 && o->cfl < MIN_BOUND_FRACTION) SPAM_BAD_INPUT("-step_cfl", val, "too small: must be 0 (off) or at least %g (over a million steps per sound crossing of h below that)", MIN_BOUND_FRACTION);
    PetscCall(SpamOptionText("-step_force", o->force, val, sizeof val));
    if (o->force > 0 && o->force < MIN_BOUND_FRACTION) SPAM_BAD_INPUT("-step_force", val, "too small: must be 0 (off) or at least %g", MIN_BOUND_FRACTION);
  }
  PetscCall(CheckGrid(&sim->geo, o));
  /* The gas's estimate, asked for: the particle sum with each particle's e_i. Off by
   * default, so that the gas's outputs and costs stay as they were. */
  o->diag.entropy_gas = (PetscBool)(sim->model.tensor && sim->model.solid.material == SPAM_MATERIAL_GAS && o->diag.entropy && entropy_set);
  if (o->diag.entropy_gas && grid_set && o->diag.grid_spacing > 0) {
    char val[128];
    PetscCall(SpamOptionText("-diag_grid_spacing", o->diag.grid_spacing, val, sizeof val));
    SPAM_BAD_INPUT("-diag_grid_spacing", val, "the gas's entropy is the particle sum only (its grid estimate would need e interpolated): give 0");
  }
  {
    char val[32];
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, o->migrate_interval));
    if (o->migrate_interval < 0) SPAM_BAD_INPUT("-migrate_interval", val, "must be zero (migrate only at the start) or a positive number of list builds");
  }
  PetscCall(CheckRange("-checkpoint_interval", o->checkpoint_interval, 0.0, PETSC_FALSE, "must be zero (off) or a positive time"));
  PetscCall(CheckRange("-checkpoint_wall", o->checkpoint_wall, 0.0, PETSC_FALSE, "must be zero (off) or a positive number of seconds"));
  PetscCall(CheckCount("-checkpoint_interval", o->checkpoint_interval, o->t_end, MAX_OUTPUT_ROWS, "checkpoints"));
  {
    char     val[32];
    PetscInt reject = 10;
    PetscBool set;
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, o->max_steps));
    if (o->max_steps < 0) SPAM_BAD_INPUT("-ts_max_steps", val, "must be zero or positive");
    /* PETSc's own option (TSSetFromOptions reads it; -1 would mean unlimited there and
     * ERKStep's default here): a count of at least 1 means the same for every method. */
    PetscCall(PetscOptionsGetInt(NULL, NULL, "-ts_max_reject", &reject, &set));
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, reject));
    if (set && reject < 1) SPAM_BAD_INPUT("-ts_max_reject", val, "must be at least 1 (rejections of one step before the run fails)");
  }
  PetscFunctionReturn(0);
}
