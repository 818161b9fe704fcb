/* Options of a run: integrator, tolerances, end time and outputs. */
#include <spam/run.h>
#include <spam/errors.h>

/* The explicit Butcher tables built into ARKODE 6.4 (ERKStep accepts them by name). */
static const char *const ArkodeTables[] = {
  "ARKODE_HEUN_EULER_2_1_2", "ARKODE_BOGACKI_SHAMPINE_4_2_3", "ARKODE_ARK324L2SA_ERK_4_2_3", "ARKODE_ZONNEVELD_5_3_4", "ARKODE_ARK436L2SA_ERK_6_3_4", "ARKODE_SAYFY_ABURUB_6_3_4", "ARKODE_CASH_KARP_6_4_5", "ARKODE_FEHLBERG_6_4_5",
  "ARKODE_DORMAND_PRINCE_7_4_5", "ARKODE_ARK548L2SA_ERK_8_4_5", "ARKODE_VERNER_8_5_6", "ARKODE_FEHLBERG_13_7_8", "ARKODE_KNOTH_WOLKE_3_3", "ARKODE_ARK437L2SA_ERK_7_3_4", "ARKODE_ARK548L2SAb_ERK_8_4_5"};
static const char *const ArkodeAdapt[] = {"pid", "pi", "i", "expgus", "impgus"};

static PetscErrorCode CheckRange(const char *opt, double v, double lo, PetscBool lo_open, const char *what)
{
  char val[64];

  PetscFunctionBeginUser;
  (void)snprintf(val, sizeof val, "%g", v);
  if (!isfinite(v) || v < lo || (lo_open && v == lo)) SPAM_BAD_INPUT(opt, val, "%s", what);
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
  PetscFunctionBeginUser;
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
  PetscCall(PetscOptionsInt("-cvode_max_order", "Largest Adams order of CVODE (1..12)", "README", o->cvode_max_order, &o->cvode_max_order, NULL));
  PetscCall(PetscOptionsReal("-step_cfl", "CFL bound dt <= C h / c_max on adaptive steps (0: off)", "README", o->cfl, &o->cfl, NULL));
  PetscCall(PetscOptionsReal("-step_force", "Force bound dt <= C' sqrt(h / |a|max) on adaptive steps (0: off)", "README", o->force, &o->force, NULL));
  PetscCall(PetscOptionsReal("-unstable_dt_min", "A step below this is a failure (0: 1e-12 t_end)", "README", o->dt_min, &o->dt_min, NULL));
  PetscCall(PetscOptionsReal("-unstable_energy_growth", "Kinetic energy above this many times the initial energy is a failure (0: off)", "README", o->energy_growth, &o->energy_growth, NULL));
  PetscCall(PetscOptionsString("-arkode_table", "Explicit Butcher table of ERKStep", "README", o->table, o->table, sizeof o->table, NULL));
  PetscCall(PetscOptionsString("-arkode_adapt", "Step controller: pid, pi, i, expgus, impgus", "README", o->adapt, o->adapt, sizeof o->adapt, NULL));
  PetscCall(PetscOptionsReal("-arkode_fixed_step", "Fixed step size (0: adaptive)", "README", o->fixed_step, &o->fixed_step, NULL));
  PetscCall(PetscOptionsReal("-arkode_safety", "Step safety factor (0: ARKODE default)", "README", o->safety, &o->safety, NULL));
  PetscCall(PetscOptionsReal("-arkode_max_growth", "Largest step growth factor (0: ARKODE default)", "README", o->max_growth, &o->max_growth, NULL));
  PetscCall(PetscOptionsReal("-arkode_max_first_growth", "Largest growth after the first step (0: ARKODE default)", "README", o->max_first_growth, &o->max_first_growth, NULL));
  PetscCall(PetscOptionsReal("-arkode_max_efail_growth", "Step factor after an error-test failure (0: ARKODE default)", "README", o->max_efail_growth, &o->max_efail_growth, NULL));
  o->n_adapt_params = 3;
  PetscCall(PetscOptionsRealArray("-arkode_adapt_params", "Controller gains k1,k2,k3 (default: ARKODE's for the controller)", "README", o->adapt_params, &o->n_adapt_params, NULL));
  PetscCall(PetscOptionsBool("-arkode_classic_weights", "Use ARKODE's rtol|y|+atol weights (not translation invariant; for comparison)", "README", o->classic_weights, &o->classic_weights, NULL));
  PetscCall(PetscOptionsString("-output_dir", "Directory for timeseries.csv, steps.csv, summary.json and snapshots", "README", o->output_dir, o->output_dir, sizeof o->output_dir, NULL));
  o->output_interval   = o->t_end / 100.0;
  o->snapshot_interval = o->t_end / 8.0;
  PetscCall(PetscOptionsReal("-output_interval", "Time between diagnostics rows (default end time / 100; 0: start and end only)", "README", o->output_interval, &o->output_interval, NULL));
  PetscCall(PetscOptionsReal("-snapshot_interval", "Time between particle snapshots (default end time / 8; 0: none)", "README", o->snapshot_interval, &o->snapshot_interval, NULL));
  PetscCall(PetscOptionsBool("-snapshot_hdf5", "Write HDF5 + XDMF snapshots (ParaView)", "README", o->hdf5, &o->hdf5, NULL));
  PetscCall(PetscOptionsBool("-snapshot_csv", "Write CSV snapshots (chart scripts)", "README", o->csv, &o->csv, NULL));
  PetscCall(PetscOptionsBool("-monitor", "Print a line per step", "README", o->monitor, &o->monitor, NULL));
  PetscCall(PetscOptionsBool("-diag_entropy", "Compute the entropy estimates", "README", o->diag.entropy, &o->diag.entropy, NULL));
  PetscCall(PetscOptionsReal("-diag_grid_spacing", "Grid spacing of the entropy integral (0: off)", "README", o->diag.grid_spacing, &o->diag.grid_spacing, NULL));
  PetscCall(PetscOptionsString("-initial_csv", "Also write the initial particles to this CSV (file-scene format)", "README", o->initial_csv, o->initial_csv, sizeof o->initial_csv, NULL));
  PetscCall(PetscOptionsString("-final_csv", "Also write the final particles to this CSV (file-scene format)", "README", o->final_csv, o->final_csv, sizeof o->final_csv, NULL));
  PetscOptionsEnd();
  PetscCall(SpamCheckAllowed("-arkode_table", o->table, ArkodeTables, 15));
  PetscCall(SpamCheckAllowed("-arkode_adapt", o->adapt, ArkodeAdapt, 5));
  PetscCall(CheckRange("-ts_max_time", o->t_end, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckRange("-ts_rtol", o->rtol, 0.0, PETSC_TRUE, "a tolerance must be positive"));
  PetscCall(CheckRange("-ts_atol", o->atol, 0.0, PETSC_TRUE, "a tolerance must be positive"));
  PetscCall(CheckRange("-ts_dt", o->dt_first, 0.0, PETSC_FALSE, "must be zero (estimate) or positive"));
  PetscCall(CheckRange("-arkode_fixed_step", o->fixed_step, 0.0, PETSC_FALSE, "must be zero (adaptive) or positive"));
  PetscCall(CheckRange("-output_interval", o->output_interval, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckRange("-snapshot_interval", o->snapshot_interval, 0.0, PETSC_FALSE, "must be zero or positive"));
  PetscCall(CheckRange("-step_cfl", o->cfl, 0.0, PETSC_FALSE, "must be zero (off) or positive"));
  PetscCall(CheckRange("-step_force", o->force, 0.0, PETSC_FALSE, "must be zero (off) or positive"));
  PetscCall(CheckRange("-unstable_dt_min", o->dt_min, 0.0, PETSC_FALSE, "must be zero (default) or positive"));
  PetscCall(CheckRange("-unstable_energy_growth", o->energy_growth, 0.0, PETSC_FALSE, "must be zero (off) or positive"));
  {
    char val[32];
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, o->cvode_max_order));
    if (o->cvode_max_order < 1 || o->cvode_max_order > 12) SPAM_BAD_INPUT("-cvode_max_order", val, "Adams orders are 1 to 12");
  }
  {
    char val[32];
    PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, o->max_steps));
    if (o->max_steps < 0) SPAM_BAD_INPUT("-ts_max_steps", val, "must be zero or positive");
  }
  PetscFunctionReturn(0);
}
