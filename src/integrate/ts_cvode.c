/* CVODE as a PETSc TS type ("cvode"): variable-order Adams methods with a fixed-point
 * nonlinear solver (no Jacobian: the SPAM equations are not stiff at the steps accuracy
 * asks for). Like "arkode", TSStep takes one CVODE step towards ts->max_time. */
#include <petsc/private/tsimpl.h>
#include "ts_family.h"
#include <spam/errors.h>
#include <cvode/cvode.h>
#include <nvector/nvector_petsc.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

/* Vectors CVODE clones besides its history (SUNDIALS 6.4.1: weights, correction and five
 * temporaries) and the fixed-point solver's work, with a margin. */
#define SPAM_CVODE_WORK_VECTORS 12

typedef struct {
  SUNContext         sunctx;
  N_Vector           y;
  SUNNonlinearSolver nls;
  void              *mem;
  PetscInt           max_order; /* -cvode_max_order */
  PetscBool          stats;     /* -sundials_stats  */
} TS_SpamCVode;

/* The options of the cvode type, read in its setfromoptions (and listed by -help). */
PetscErrorCode SpamCVodeOptionsRead(PetscOptionItems *PetscOptionsObject, PetscInt *max_order, PetscBool *stats)
{
  char val[32];

  PetscFunctionBeginUser;
  PetscOptionsHeadBegin(PetscOptionsObject, "CVODE options (-ts_type cvode)");
  PetscCall(PetscOptionsInt("-cvode_max_order", "Largest Adams order of CVODE (1..12)", "README", *max_order, max_order, NULL));
  PetscCall(PetscOptionsBool("-sundials_stats", "Print CVODE's statistics table (CVodePrintAllStats) at the end of the run", "README", *stats, stats, NULL));
  PetscOptionsHeadEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, *max_order));
  if (*max_order < 1 || *max_order > 12) SPAM_BAD_INPUT("-cvode_max_order", val, "Adams orders are 1 to 12");
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetFromOptions_SpamCVode(TS ts, PetscOptionItems *PetscOptionsObject)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;
  char          type[64];
  PetscBool     set;

  PetscFunctionBeginUser;
  PetscCall(SpamCVodeOptionsRead(PetscOptionsObject, &cv->max_order, &cv->stats));
  /* CVODE varies its order and step together: it has no fixed-step mode to map
   * -ts_adapt_type none onto. */
  PetscCall(PetscOptionsGetString(NULL, NULL, "-ts_adapt_type", type, sizeof type, &set));
  if (set) SPAM_BAD_INPUT("-ts_adapt_type", type, "-ts_type cvode chooses its own steps and orders (its tolerances are -ts_rtol, -ts_atol); a fixed step: -ts_type arkode or rk with -ts_adapt_type none -ts_dt <step>");
  PetscFunctionReturn(0);
}

/* -sundials_stats (or force): CVodePrintAllStats, SUNDIALS' own table. */
static PetscErrorCode SundialsStats_SpamCVode(TS ts, FILE *file, PetscBool force)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;

  PetscFunctionBeginUser;
  if (cv->mem && (force || cv->stats)) PetscCallCV(CVodePrintAllStats(cv->mem, file, SUN_OUTPUTFORMAT_TABLE));
  PetscFunctionReturn(0);
}

/* -ts_view: the method and CVODE's statistics table. */
static PetscErrorCode TSView_SpamCVode(TS ts, PetscViewer viewer)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;
  PetscBool     ascii;
  FILE         *fd;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) PetscFunctionReturn(0);
  PetscCall(PetscViewerASCIIPrintf(viewer, "  CVODE Adams, fixed-point iteration, largest order %" PetscInt_FMT "\n", cv->max_order));
  if (!cv->mem) PetscFunctionReturn(0);
  PetscCall(PetscViewerFlush(viewer));
  PetscCall(PetscViewerASCIIGetPointer(viewer, &fd));
  PetscCall(SundialsStats_SpamCVode(ts, fd, PETSC_TRUE));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetUp_SpamCVode(TS ts)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;
  SpamTsApp    *app;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCheck(app, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the cvode TS needs a SpamTsApp application context");
  PetscCallCV(SUNContext_Create((void *)&app->sim->p.comm, &cv->sunctx));
  cv->y = N_VMake_Petsc(ts->vec_sol, cv->sunctx);
  PetscCheck(cv->y, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VMake_Petsc failed");
  /* Fused operations: a stage or history combination of k vectors is one VecMAXPY pass
   * instead of k VecAXPY passes over memory (clones inherit the setting). */
  PetscCheck(N_VEnableFusedOps_Petsc(cv->y, SUNTRUE) == 0, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VEnableFusedOps_Petsc failed");
  PetscCall(SpamErrorNormAttach(cv->y, app->o->error_norm, app->sim->pair.reproducible)); /* -error_norm: cloned with y */
  /* The memory for CVODE's vectors (the Nordsieck history of max_order + 1 and its work)
   * asked for once, so that a run short of memory ends with its one-line error. */
  PetscCall(SpamNVectorReserve(ts->vec_sol, cv->max_order + 1 + SPAM_CVODE_WORK_VECTORS));
  cv->mem = CVodeCreate(CV_ADAMS, cv->sunctx);
  PetscCheck(cv->mem, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "CVodeCreate failed");
  PetscCallCV(CVodeInit(cv->mem, SpamSundialsRhs, ts->ptime, cv->y));
  PetscCallCV(CVodeSetUserData(cv->mem, app));
  PetscCallCV(CVodeSetErrHandlerFn(cv->mem, SpamSundialsErrHandler, app));
  if (app->o->classic_weights) PetscCallCV(CVodeSStolerances(cv->mem, app->o->rtol, app->o->atol));
  else PetscCallCV(CVodeWFtolerances(cv->mem, SpamErrorWeights));
  cv->nls = SUNNonlinSol_FixedPoint(cv->y, 0, cv->sunctx);
  PetscCheck(cv->nls, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "SUNNonlinSol_FixedPoint failed");
  PetscCallCV(CVodeSetNonlinearSolver(cv->mem, cv->nls));
  PetscCallCV(CVodeSetMaxOrd(cv->mem, (int)cv->max_order));
  PetscCallCV(CVodeSetMaxNumSteps(cv->mem, -1)); /* the loop counts steps itself */
  /* -ts_max_reject means the same for every method: rejections of one step before it fails. */
  if (ts->max_reject > 0) {
    PetscCallCV(CVodeSetMaxErrTestFails(cv->mem, (int)ts->max_reject));
    PetscCallCV(CVodeSetMaxConvFails(cv->mem, (int)ts->max_reject));
  }
  if (app->o->dt_first > 0) PetscCallCV(CVodeSetInitStep(cv->mem, app->o->dt_first));
  app->self_stepping = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSStep_SpamCVode(TS ts)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;
  SpamTsApp    *app;
  realtype      tret, h;
  long          netf, ncfn;
  int           flag;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  /* The state jumped between steps (TSRestartStep): the Adams history is void, start again. */
  if (ts->steprestart && ts->steps > 0) PetscCallCV(CVodeReInit(cv->mem, ts->ptime, cv->y));
  ts->steprestart = PETSC_FALSE;
  PetscCallCV(CVodeSetStopTime(cv->mem, ts->max_time));
  /* CVODE has no stability function: the physical bound, computed by the loop, caps the step. */
  PetscCallCV(CVodeSetMaxStep(cv->mem, isfinite(app->bound) ? app->bound : 0.0));
  flag = CVode(cv->mem, ts->max_time, cv->y, &tret, CV_ONE_STEP);
  PetscCall(app->perr);
  if (flag < 0) {
    SpamSundialsFailure(app, "CVode", CVodeGetReturnFlagName, flag);
    ts->reason = TS_DIVERGED_STEP_REJECTED;
    PetscFunctionReturn(0);
  }
  PetscCallCV(CVodeGetLastStep(cv->mem, &h));
  PetscCallCV(CVodeGetNumErrTestFails(cv->mem, &netf));
  PetscCallCV(CVodeGetNumNonlinSolvConvFails(cv->mem, &ncfn));
  ts->ptime     = tret;
  ts->time_step = h;
  ts->reject    = (PetscInt)(netf + ncfn);
  PetscFunctionReturn(0);
}

/* Dense output (TSInterpolate): CVODE's interpolating polynomial of the current Adams
 * order into X, from the history CVODE keeps anyway (no right-hand side, no change to it). */
static PetscErrorCode TSInterpolate_SpamCVode(TS ts, PetscReal t, Vec X)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;
  N_Vector      x  = N_VMake_Petsc(X, cv->sunctx);
  int           flag;

  PetscFunctionBeginUser;
  PetscCheck(x, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VMake_Petsc failed");
  flag = CVodeGetDky(cv->mem, t, 0, x);
  N_VDestroy(x);
  PetscCall(SpamCheckCvode(flag, "CVodeGetDky"));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSReset_SpamCVode(TS ts)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;

  PetscFunctionBeginUser;
  if (cv->mem) CVodeFree(&cv->mem);
  if (cv->nls) PetscCallCV(SUNNonlinSolFree(cv->nls));
  cv->nls = NULL;
  if (cv->y) N_VDestroy(cv->y);
  cv->y = NULL;
  if (cv->sunctx) PetscCallCV(SUNContext_Free(&cv->sunctx));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSDestroy_SpamCVode(TS ts)
{
  PetscFunctionBeginUser;
  PetscCall(TSReset_SpamCVode(ts));
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "SpamTSSundialsStats_C", NULL));
  PetscCall(PetscFree(ts->data));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSCreate_CVode(TS ts)
{
  TS_SpamCVode *cv;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&cv));
  cv->max_order          = 12;
  ts->data               = (void *)cv;
  ts->ops->setfromoptions = TSSetFromOptions_SpamCVode;
  ts->ops->view          = TSView_SpamCVode;
  ts->ops->setup         = TSSetUp_SpamCVode;
  ts->ops->step          = TSStep_SpamCVode;
  ts->ops->reset         = TSReset_SpamCVode;
  ts->ops->destroy       = TSDestroy_SpamCVode;
  ts->ops->interpolate   = TSInterpolate_SpamCVode;
  ts->default_adapt_type = TSADAPTNONE; /* CVODE adapts step and order by itself */
  ts->usessnes           = PETSC_FALSE;
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "SpamTSSundialsStats_C", SundialsStats_SpamCVode));
  PetscFunctionReturn(0);
}

/* A restart: CVODE starts at order 1 from the checkpoint's state; its first step is the
 * step the checkpointed run was about to take (its history cannot be set: checkpoint.h). */
PetscErrorCode SpamTSCVodeSetInitStep(TS ts, double h)
{
  TS_SpamCVode *cv = (TS_SpamCVode *)ts->data;

  PetscFunctionBeginUser;
  PetscCheck(cv->mem, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the cvode TS is not set up");
  PetscCallCV(CVodeSetInitStep(cv->mem, h));
  PetscFunctionReturn(0);
}

/* The cvode row of the table of methods (ts_family.h). */
static PetscErrorCode DescribeCVode(TS ts, const char **sub, char *adapt, size_t alen, double *fixed_dt)
{
  PetscFunctionBeginUser;
  (void)ts;
  *sub      = "adams";
  *fixed_dt = 0.0;
  PetscCall(PetscStrncpy(adapt, "cvode", alen));
  PetscFunctionReturn(0);
}

static PetscErrorCode HelpCVode(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o)
{
  PetscInt  order = 12;
  PetscBool stats = PETSC_FALSE;

  PetscFunctionBeginUser;
  (void)o;
  PetscCall(SpamCVodeOptionsRead(PetscOptionsObject, &order, &stats));
  PetscFunctionReturn(0);
}

/* CVODE takes its initial time when it is made: a set-up TS (the option checks may have
 * set it up at t = 0) makes it again at the checkpoint's. */
static PetscErrorCode CkBeforeSetUpCVode(TS ts)
{
  PetscFunctionBeginUser;
  if (ts->setupcalled) {
    PetscCall(TSReset_SpamCVode(ts));
    ts->setupcalled = PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CkApplyCVode(TS ts, const SpamCkFile *c, double h_next, PetscBool pending)
{
  PetscFunctionBeginUser;
  (void)c;
  (void)pending;
  if (h_next > 0) PetscCall(SpamTSCVodeSetInitStep(ts, h_next));
  PetscFunctionReturn(0);
}

static const SpamTSOption OptionsCVode[] = {{"cvode_max_order", PETSC_TRUE, PETSC_FALSE}, {"sundials_stats", PETSC_FALSE, PETSC_FALSE}, {NULL, PETSC_FALSE, PETSC_FALSE}};

const SpamTSFamily SpamTSFamilyCVode = {
  .options           = OptionsCVode,
  .type              = SPAM_TSCVODE,
  .adapt_default     = TSADAPTNONE,
  .steps             = SPAM_TS_STEPS_OWN,
  .follow            = SPAM_TS_FOLLOW_NONE,
  .bound_as_max_step = PETSC_TRUE,
  .restart_inexact   = "CVODE's Adams history (Nordsieck array, order, step history) cannot be set: it restarts at order 1",
  .interpolates      = SpamTSInterpolatesAlways,
  .describe          = DescribeCVode,
  .help_other        = HelpCVode,
  .ck_before_setup   = CkBeforeSetUpCVode,
  .ck_apply          = CkApplyCVode,
};
