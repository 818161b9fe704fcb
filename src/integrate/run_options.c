/* Options of a run: integrator, tolerances, end time and outputs. */
#include <spam/run.h>
#include <spam/errors.h>
#include <float.h>

/* The explicit Butcher tables built into ARKODE 6.4 (ERKStep accepts them by name). */
static const char *const ArkodeTables[] = {
  "ARKODE_HEUN_EULER_2_1_2", "ARKODE_BOGACKI_SHAMPINE_4_2_3", "ARKODE_ARK324L2SA_ERK_4_2_3", "ARKODE_ZONNEVELD_5_3_4", "ARKODE_ARK436L2SA_ERK_6_3_4", "ARKODE_SAYFY_ABURUB_6_3_4", "ARKODE_CASH_KARP_6_4_5", "ARKODE_FEHLBERG_6_4_5",
  "ARKODE_DORMAND_PRINCE_7_4_5", "ARKODE_ARK548L2SA_ERK_8_4_5", "ARKODE_VERNER_8_5_6", "ARKODE_FEHLBERG_13_7_8", "ARKODE_KNOTH_WOLKE_3_3", "ARKODE_ARK437L2SA_ERK_7_3_4", "ARKODE_ARK548L2SAb_ERK_8_4_5"};
static const char *const ArkodeAdapt[] = {"pid", "pi", "i", "expgus", "impgus"};

/* Cap on what one run may write: the count of rows follows from the end time and the
 * interval, so a tiny interval is refused before anything is written. (The snapshot count
 * is capped by -snapshot_max, in output_options.c.) */
#define MAX_OUTPUT_ROWS 1000000.0
/* The entropy grid integral samples every cell at every output row. */
#define MAX_GRID_CELLS 1e8
/* A step bound below this fraction of its time scale would need over a million steps per
 * crossing of h (-step_cfl, -step_force are dimensionless). */
#define MIN_BOUND_FRACTION 1e-6

/* v must be finite and >= lo (> lo when lo_open); a subnormal positive value is "too small". */
static PetscErrorCode CheckRange(const char *opt, double v, double lo, PetscBool lo_open, const char *what)
{
  char val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, v, val, sizeof val));
  if (!isfinite(v) || v < lo || (lo_open && v == lo)) SPAM_BAD_INPUT(opt, val, "%s", what);
  if (v != 0.0 && fabs(v) < DBL_MIN) SPAM_BAD_INPUT(opt, val, "too small (subnormal): %s", what);
  PetscFunctionReturn(0);
}

/* Zero (ARKODE's default) or a finite value in (lo, hi) (hi included when hi_closed). */
static PetscErrorCode CheckController(const char *opt, double v, double lo, double hi, PetscBool hi_closed, const char *what)
{
  char val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, v, val, sizeof val));
  if (v == 0.0) PetscFunctionReturn(0);
  if (!isfinite(v) || !(v > lo) || v > hi || (!hi_closed && v == hi)) SPAM_BAD_INPUT(opt, val, "%s (0: ARKODE's default)", what);
  PetscFunctionReturn(0);
}

/* The count of items t_end / interval must stay within max. */
static PetscErrorCode CheckCount(const char *opt, double interval, double t_end, double max, const char *what)
{
  char val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, interval, val, sizeof val));
  if (interval > 0 && t_end > 0 && !(t_end / interval <= max)) SPAM_BAD_INPUT(opt, val, "would write %.3g %s to -ts_max_time %.6g; at most %.0f: use an interval of at least %.6g (or 0: none)", t_end / interval, what, t_end, max, t_end / max);
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
  PetscCall(CheckRange("-arkode_fixed_step", o->fixed_step, 0.0, PETSC_FALSE, "must be zero (adaptive) or positive"));
  if (o->t_end > 0) {
    PetscCall(CheckStep("-ts_dt", o->dt_first, floor));
    PetscCall(CheckStep("-arkode_fixed_step", o->fixed_step, floor));
  }
  PetscCall(CheckRange("-output_interval", o->output_interval, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckRange("-snapshot_interval", o->snapshot_interval, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckCount("-output_interval", o->output_interval, o->t_end, MAX_OUTPUT_ROWS, "diagnostics rows"));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckArkode(const SpamRunOptions *o)
{
  PetscFunctionBeginUser;
  PetscCall(SpamCheckAllowed("-arkode_table", o->table, ArkodeTables, 15));
  PetscCall(SpamCheckAllowed("-arkode_adapt", o->adapt, ArkodeAdapt, 5));
  /* ARKODE 6.4 silently falls back to its default outside these ranges, or fails later. */
  PetscCall(CheckController("-arkode_safety", o->safety, 0.0, 1.0, PETSC_FALSE, "must be a safety factor between 0 and 1"));
  PetscCall(CheckController("-arkode_max_growth", o->max_growth, 1.0, PETSC_INFINITY, PETSC_FALSE, "must be a finite growth factor greater than 1"));
  PetscCall(CheckController("-arkode_max_first_growth", o->max_first_growth, 1.0, PETSC_INFINITY, PETSC_FALSE, "must be a finite growth factor greater than 1"));
  PetscCall(CheckController("-arkode_max_efail_growth", o->max_efail_growth, 0.0, 1.0, PETSC_TRUE, "must be a step factor in (0, 1]"));
  {
    char val[128];
    PetscCall(SpamOptionText("-arkode_adapt_params", 0.0, val, sizeof val));
    if (o->n_adapt_params != 0 && o->n_adapt_params != 3) SPAM_BAD_INPUT("-arkode_adapt_params", val, "takes exactly 3 values k1,k2,k3 (%" PetscInt_FMT " given)", o->n_adapt_params);
    for (int k = 0; k < o->n_adapt_params; k++)
      if (!isfinite(o->adapt_params[k])) SPAM_BAD_INPUT("-arkode_adapt_params", val, "the gains must be finite numbers");
  }
  PetscFunctionReturn(0);
}

/* The grid of the entropy integral: cells counted in double, so a tiny spacing cannot
 * overflow the count. */
static PetscErrorCode CheckGrid(const SpamSim *sim, const SpamRunOptions *o)
{
  double cells = 1.0;
  char   val[128];

  PetscFunctionBeginUser;
  PetscCall(CheckRange("-diag_grid_spacing", o->diag.grid_spacing, 0.0, PETSC_FALSE, "must be zero (off) or a positive spacing"));
  if (!(o->diag.entropy && o->diag.grid_spacing > 0)) PetscFunctionReturn(0);
  for (int d = 0; d < sim->box.dim; d++) cells *= PetscMax(1.0, ceil(sim->box.len[d] / o->diag.grid_spacing));
  PetscCall(SpamOptionText("-diag_grid_spacing", o->diag.grid_spacing, val, sizeof val));
  if (!(cells <= MAX_GRID_CELLS)) SPAM_BAD_INPUT("-diag_grid_spacing", val, "the box would hold %.3g grid cells, at most %.0e (sampled at every output row)", cells, MAX_GRID_CELLS);
  PetscFunctionReturn(0);
}

int SpamArkodeAdaptMethod(const char *name);
int SpamArkodeAdaptMethod(const char *name)
{
  for (int k = 0; k < 5; k++)
    if (!strcmp(name, ArkodeAdapt[k])) return k;
  return -1;
}

PetscErrorCode SpamRunOptionsParse(const SpamSim *sim, SpamRunOptions *o)
{
  char      type[64] = "arkode";
  PetscBool help, arkode, cvode;

  PetscFunctionBeginUser;
  /* The -arkode_* and -cvode_* options are read only for their method (all with -help), so
   * the end of set-up refuses them under another one. ts_create.c validates -ts_type. */
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-ts_type", type, sizeof type, NULL));
  arkode = (PetscBool)(help || !strcmp(type, "arkode"));
  cvode  = (PetscBool)(help || !strcmp(type, "cvode"));
  PetscCall(PetscMemzero(o, sizeof *o));
  o->t_end             = sim->scene.t_end_default;
  o->max_steps         = 1000000000;
  o->rtol              = 1e-6;
  o->atol              = 1e-9;
  o->safety            = 0.0; /* 0: ARKODE's default */
  o->max_growth        = 0.0;
  o->cvode_max_order   = 12;
  o->energy_growth     = 10.0;
  o->hdf5              = PETSC_TRUE;
  o->csv               = PETSC_TRUE;
  o->diag.entropy      = PETSC_TRUE;
  o->diag.grid_spacing = 1.0;
  PetscCall(PetscStrncpy(o->table, "ARKODE_DORMAND_PRINCE_7_4_5", sizeof o->table));
  PetscCall(PetscStrncpy(o->adapt, "pid", sizeof o->adapt));
  PetscCall(PetscStrncpy(o->output_dir, "./out", sizeof o->output_dir));
  PetscOptionsBegin(sim->comm, NULL, "Time integration: -ts_type arkode (default), cvode, rk, ssp, euler, basicsymplectic; PETSc's own -ts_* options are listed under TS", "spam-ark");
  PetscCall(PetscOptionsReal("-ts_max_time", "End time (default: the scene's, 2 sound traversal times for expansion)", "README", o->t_end, &o->t_end, NULL));
  PetscCall(PetscOptionsInt("-ts_max_steps", "Stop after this many steps", "README", o->max_steps, &o->max_steps, NULL));
  PetscCall(PetscOptionsReal("-ts_dt", "First step of adaptive methods, the step of fixed-step TS methods (0: arkode/cvode estimate it, TS methods take 0.05 h/c0)", "README", o->dt_first, &o->dt_first, NULL));
  PetscCall(PetscOptionsReal("-ts_rtol", "Relative tolerance (positions are weighed against h)", "README", o->rtol, &o->rtol, NULL));
  PetscCall(PetscOptionsReal("-ts_atol", "Absolute tolerance", "README", o->atol, &o->atol, NULL));
  if (cvode) PetscCall(PetscOptionsInt("-cvode_max_order", "Largest Adams order of CVODE (1..12)", "README", o->cvode_max_order, &o->cvode_max_order, NULL));
  PetscCall(PetscOptionsReal("-step_cfl", "CFL bound dt <= C h / c_max on adaptive steps (0: off)", "README", o->cfl, &o->cfl, NULL));
  PetscCall(PetscOptionsReal("-step_force", "Force bound dt <= C' sqrt(h / |a|max) on adaptive steps (0: off)", "README", o->force, &o->force, NULL));
  PetscCall(PetscOptionsReal("-unstable_dt_min", "A step below this is a failure (0: 1e-12 t_end)", "README", o->dt_min, &o->dt_min, NULL));
  PetscCall(PetscOptionsReal("-unstable_energy_growth", "Kinetic energy above this many times the initial energy is a failure (0: off)", "README", o->energy_growth, &o->energy_growth, NULL));
  if (arkode) PetscCall(PetscOptionsString("-arkode_table", "Explicit Butcher table of ERKStep", "README", o->table, o->table, sizeof o->table, NULL));
  if (arkode) PetscCall(PetscOptionsString("-arkode_adapt", "Step controller: pid, pi, i, expgus, impgus", "README", o->adapt, o->adapt, sizeof o->adapt, NULL));
  if (arkode) PetscCall(PetscOptionsReal("-arkode_fixed_step", "Fixed step size (0: adaptive)", "README", o->fixed_step, &o->fixed_step, NULL));
  if (arkode) PetscCall(PetscOptionsReal("-arkode_safety", "Step safety factor (0: ARKODE default)", "README", o->safety, &o->safety, NULL));
  if (arkode) PetscCall(PetscOptionsReal("-arkode_max_growth", "Largest step growth factor (0: ARKODE default)", "README", o->max_growth, &o->max_growth, NULL));
  if (arkode) PetscCall(PetscOptionsReal("-arkode_max_first_growth", "Largest growth after the first step (0: ARKODE default)", "README", o->max_first_growth, &o->max_first_growth, NULL));
  if (arkode) PetscCall(PetscOptionsReal("-arkode_max_efail_growth", "Step factor after an error-test failure (0: ARKODE default)", "README", o->max_efail_growth, &o->max_efail_growth, NULL));
  {
    PetscReal gains[16] = {0}; /* room for too many values, so that a wrong count is seen */
    PetscInt  ngains    = 16;
    if (arkode) PetscCall(PetscOptionsRealArray("-arkode_adapt_params", "Controller gains k1,k2,k3 (default: ARKODE's for the controller)", "README", gains, &ngains, NULL));
    else ngains = 0;
    o->n_adapt_params = ngains;
    for (int k = 0; k < 3; k++) o->adapt_params[k] = gains[k];
  }
  PetscCall(PetscOptionsBool("-arkode_classic_weights", "Use ARKODE's rtol|y|+atol weights (not translation invariant; for comparison)", "README", o->classic_weights, &o->classic_weights, NULL));
  PetscCall(PetscOptionsString("-output_dir", "Directory for timeseries.csv, steps.csv, summary.json and snapshots", "README", o->output_dir, o->output_dir, sizeof o->output_dir, NULL));
  o->output_interval   = o->t_end / 100.0;
  o->snapshot_interval = o->t_end / 8.0;
  PetscCall(PetscOptionsReal("-output_interval", "Time between diagnostics rows (default end time / 100; 0: start and end only)", "README", o->output_interval, &o->output_interval, NULL));
  PetscCall(PetscOptionsReal("-snapshot_interval", "Time between particle snapshots (default end time / 8; 0: none)", "README", o->snapshot_interval, &o->snapshot_interval, NULL));
  PetscCall(PetscOptionsBool("-snapshot_hdf5", "Write HDF5 + XDMF snapshots (ParaView)", "README", o->hdf5, &o->hdf5, NULL));
  PetscCall(PetscOptionsBool("-snapshot_csv", "Write CSV snapshots (chart scripts)", "README", o->csv, &o->csv, NULL));
  PetscCall(PetscOptionsBool("-monitor", "Print a line per step", "README", o->monitor, &o->monitor, NULL));
  PetscCall(PetscOptionsBool("-output_stop", "Cut steps to land on every output time instead of writing the outputs from the method's interpolant", "README", o->output_stop, &o->output_stop, NULL));
  PetscCall(PetscOptionsBool("-diag_entropy", "Compute the entropy estimates", "README", o->diag.entropy, &o->diag.entropy, NULL));
  PetscCall(PetscOptionsReal("-diag_grid_spacing", "Grid spacing of the entropy integral (0: off)", "README", o->diag.grid_spacing, &o->diag.grid_spacing, NULL));
  PetscCall(PetscOptionsString("-initial_csv", "Also write the initial particles to this CSV (file-scene format)", "README", o->initial_csv, o->initial_csv, sizeof o->initial_csv, NULL));
  PetscCall(PetscOptionsString("-final_csv", "Also write the final particles to this CSV (file-scene format)", "README", o->final_csv, o->final_csv, sizeof o->final_csv, NULL));
  PetscOptionsEnd();
  PetscCall(CheckArkode(o));
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
  PetscCall(CheckGrid(sim, o));
  {
    char     val[32];
    PetscInt reject = 10;
    PetscBool set;
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, o->cvode_max_order));
    if (o->cvode_max_order < 1 || o->cvode_max_order > 12) SPAM_BAD_INPUT("-cvode_max_order", val, "Adams orders are 1 to 12");
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
