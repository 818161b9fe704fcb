/* The options of the arkode TS type, read by its setfromoptions as PETSc's own types read
 * theirs (so -help lists them under the TS options with their defaults), and checked: a
 * bad value is one line of bad input. -ts_adapt_type none with -ts_dt fixes the step, as
 * for PETSc's methods; any other -ts_adapt_type is refused (ERKStep's controller is
 * -arkode_adapt). */
#include <spam/integrator.h>
#include <spam/errors.h>
#include <float.h>

/* The explicit Butcher tables built into ARKODE 6.4 (ERKStep accepts them by name). */
static const char *const ArkodeTables[] = {
  "ARKODE_HEUN_EULER_2_1_2", "ARKODE_BOGACKI_SHAMPINE_4_2_3", "ARKODE_ARK324L2SA_ERK_4_2_3", "ARKODE_ZONNEVELD_5_3_4", "ARKODE_ARK436L2SA_ERK_6_3_4", "ARKODE_SAYFY_ABURUB_6_3_4", "ARKODE_CASH_KARP_6_4_5", "ARKODE_FEHLBERG_6_4_5",
  "ARKODE_DORMAND_PRINCE_7_4_5", "ARKODE_ARK548L2SA_ERK_8_4_5", "ARKODE_VERNER_8_5_6", "ARKODE_FEHLBERG_13_7_8", "ARKODE_KNOTH_WOLKE_3_3", "ARKODE_ARK437L2SA_ERK_7_3_4", "ARKODE_ARK548L2SAb_ERK_8_4_5"};
static const char *const ArkodeAdapt[] = {"pid", "pi", "i", "expgus", "impgus"};

int SpamArkodeAdaptMethod(const char *name)
{
  for (int k = 0; k < 5; k++)
    if (!strcmp(name, ArkodeAdapt[k])) return k;
  return -1;
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

/* The fixed step: zero (adaptive) or a finite step not below the run's step floor (a step
 * below it would be reported as a collapse at once). */
static PetscErrorCode CheckFixedStep(const char *opt, double dt, const SpamRunOptions *o)
{
  const double floor = o->dt_min > 0 ? o->dt_min : 1e-12 * o->t_end;
  char         val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, dt, val, sizeof val));
  if (!isfinite(dt) || dt < 0) SPAM_BAD_INPUT(opt, val, "must be zero (adaptive) or positive");
  if (dt != 0.0 && dt < DBL_MIN) SPAM_BAD_INPUT(opt, val, "too small (subnormal): must be zero (adaptive) or positive");
  if (o->t_end > 0 && dt > 0 && dt < floor) SPAM_BAD_INPUT(opt, val, "below the run's step floor %.6g (-unstable_dt_min, default 1e-12 -ts_max_time)", floor);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckArkode(const SpamArkodeSettings *s, const SpamRunOptions *o, PetscBool erk)
{
  PetscFunctionBeginUser;
  if (erk) PetscCall(SpamCheckAllowed("-arkode_table", s->table, ArkodeTables, 15));
  PetscCall(SpamCheckAllowed("-arkode_adapt", s->adapt, ArkodeAdapt, 5));
  PetscCall(CheckFixedStep("-arkode_fixed_step", s->fixed_step, o));
  /* ARKODE 6.4 silently falls back to its default outside these ranges, or fails later. */
  PetscCall(CheckController("-arkode_safety", s->safety, 0.0, 1.0, PETSC_FALSE, "must be a safety factor between 0 and 1"));
  PetscCall(CheckController("-arkode_max_growth", s->max_growth, 1.0, PETSC_INFINITY, PETSC_FALSE, "must be a finite growth factor greater than 1"));
  PetscCall(CheckController("-arkode_max_first_growth", s->max_first_growth, 1.0, PETSC_INFINITY, PETSC_FALSE, "must be a finite growth factor greater than 1"));
  PetscCall(CheckController("-arkode_max_efail_growth", s->max_efail_growth, 0.0, 1.0, PETSC_TRUE, "must be a step factor in (0, 1]"));
  {
    char val[128];
    PetscCall(SpamOptionText("-arkode_adapt_params", 0.0, val, sizeof val));
    if (s->n_adapt_params != 0 && s->n_adapt_params != 3) SPAM_BAD_INPUT("-arkode_adapt_params", val, "takes exactly 3 values k1,k2,k3 (%" PetscInt_FMT " given)", s->n_adapt_params);
    for (int k = 0; k < s->n_adapt_params; k++)
      if (!isfinite(s->adapt_params[k])) SPAM_BAD_INPUT("-arkode_adapt_params", val, "the gains must be finite numbers");
  }
  PetscFunctionReturn(0);
}

/* -ts_adapt_type (validated by ts_create.c): none fixes the step to -ts_dt; the PETSc
 * adaptors cannot drive ERKStep, whose controller is -arkode_adapt. */
PetscErrorCode SpamArkodeAdaptType(const SpamRunOptions *o, const char *type_name, SpamArkodeSettings *s)
{
  char      type[64] = "";
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-ts_adapt_type", type, sizeof type, &set));
  if (!set) PetscFunctionReturn(0);
  if (strcmp(type, TSADAPTNONE)) SPAM_BAD_INPUT("-ts_adapt_type", type, "-ts_type %s takes none (a fixed step -ts_dt) or ARKODE's own controller, -arkode_adapt", type_name);
  if (!(o->dt_first > 0)) SPAM_BAD_INPUT("-ts_adapt_type", type, "a fixed step needs -ts_dt <step> (or use -arkode_fixed_step)");
  if (s->fixed_step > 0 && s->fixed_step != o->dt_first) {
    char val[128];
    PetscCall(SpamOptionText("-arkode_fixed_step", s->fixed_step, val, sizeof val));
    SPAM_BAD_INPUT("-arkode_fixed_step", val, "and -ts_adapt_type none -ts_dt %.17g ask for two fixed steps: give one", o->dt_first);
  }
  s->fixed_step = o->dt_first;
  s->fixed_by_ts = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamArkodeOptionsRead(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o, PetscBool erk, SpamArkodeSettings *s)
{
  PetscReal gains[16] = {0}; /* room for too many values, so that a wrong count is seen */
  PetscInt  ngains    = 16;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof *s));
  PetscCall(PetscStrncpy(s->table, erk ? "ARKODE_DORMAND_PRINCE_7_4_5" : "", sizeof s->table));
  PetscCall(PetscStrncpy(s->adapt, "pid", sizeof s->adapt));
  PetscOptionsHeadBegin(PetscOptionsObject, erk ? "ARKODE ERKStep options (-ts_type arkode)" : "ARKODE ARKStep step options (-ts_type arkode_imex)");
  if (erk) PetscCall(PetscOptionsString("-arkode_table", "Explicit Butcher table of ERKStep", "README", s->table, s->table, sizeof s->table, NULL));
  PetscCall(PetscOptionsString("-arkode_adapt", "Step controller: pid, pi, i, expgus, impgus", "README", s->adapt, s->adapt, sizeof s->adapt, NULL));
  PetscCall(PetscOptionsReal("-arkode_fixed_step", "Fixed step size (0: adaptive; -ts_adapt_type none -ts_dt <step> is the same)", "README", s->fixed_step, &s->fixed_step, NULL));
  PetscCall(PetscOptionsReal("-arkode_safety", "Step safety factor (0: ARKODE default)", "README", s->safety, &s->safety, NULL));
  PetscCall(PetscOptionsReal("-arkode_max_growth", "Largest step growth factor (0: ARKODE default)", "README", s->max_growth, &s->max_growth, NULL));
  PetscCall(PetscOptionsReal("-arkode_max_first_growth", "Largest growth after the first step (0: ARKODE default)", "README", s->max_first_growth, &s->max_first_growth, NULL));
  PetscCall(PetscOptionsReal("-arkode_max_efail_growth", "Step factor after an error-test failure (0: ARKODE default)", "README", s->max_efail_growth, &s->max_efail_growth, NULL));
  PetscCall(PetscOptionsRealArray("-arkode_adapt_params", "Controller gains k1,k2,k3 (default: ARKODE's for the controller)", "README", gains, &ngains, NULL));
  PetscCall(PetscOptionsBool("-sundials_stats", "Print ARKODE's statistics table (PrintAllStats) at the end of the run", "README", s->sundials_stats, &s->sundials_stats, NULL));
  PetscOptionsHeadEnd();
  s->n_adapt_params = ngains;
  for (int k = 0; k < 3; k++) s->adapt_params[k] = gains[k];
  PetscCall(CheckArkode(s, o, erk));
  PetscFunctionReturn(0);
}
