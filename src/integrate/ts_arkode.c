/* ARKODE ERKStep as a PETSc TS type ("arkode"). ERKStep keeps its own step controller,
 * error weights and stop time; TSStep takes one ERKStep step towards ts->max_time and
 * reports the time, the step and the rejections back to the TS, so that the one TSStep
 * loop of spam-ark drives it like any PETSc method. */
#include <petsc/private/tsimpl.h>
#include "ts_family.h"
#include <spam/errors.h>
#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_petsc.h>

/* ERKStep 6.4.1 allocates, besides a vector per stage, 7 work vectors and 3 for its
 * interpolant (massif of a Dormand-Prince run: 17 in all). */
#define SPAM_ERK_WORK_VECTORS 10

/* Which of ERKStep's vectors holds what, learnt from its copies (TrackedScale). */
typedef struct {
  N_Vector y;    /* the solution (the TS's X), ERKStep's output and stage sum   */
  N_Vector yn;   /* ERKStep's state at the step's end: a copy of y             */
  N_Vector yold; /* the Hermite interpolant's y at the step's start: of yn      */
} SpamArkodeCopies;

typedef struct {
  SUNContext           sunctx;
  N_Vector             y;
  SpamArkodeCopies     copies;
  PetscContainer       copies_c;  /* composed on every vector (nvector_unwritten.c)   */
  void                *mem;
  SpamArkodeSettings   set;       /* the type's options (arkode_options.c)            */
  SpamArkodeController ctl;       /* the step controller (arkode_controller.c)        */
  int                  last_flag; /* ERKStepEvolve's return of the last step          */
} TS_SpamARKode;

/* The controller is always our copy of ARKODE's (arkode_controller.c), never the built-in
 * one, so that a run with checkpoints takes the steps of a run without. */
static PetscErrorCode ConfigureController(void *mem, const SpamArkodeSettings *o, SpamArkodeController *ctl)
{
  PetscFunctionBeginUser;
  if (o->fixed_step > 0) {
    PetscCallARK(ERKStepSetFixedStep(mem, o->fixed_step));
    PetscFunctionReturn(0);
  }
  PetscCall(SpamArkodeControllerSetUp(ctl, o, mem));
  if (o->safety > 0) PetscCallARK(ERKStepSetSafetyFactor(mem, o->safety));
  if (o->max_growth > 0) PetscCallARK(ERKStepSetMaxGrowth(mem, o->max_growth));
  if (o->max_first_growth > 0) PetscCallARK(ERKStepSetMaxFirstGrowth(mem, o->max_first_growth));
  if (o->max_efail_growth > 0) PetscCallARK(ERKStepSetMaxEFailGrowth(mem, o->max_efail_growth));
  PetscFunctionReturn(0);
}

/* ERKStep in SUNDIALS 6.4.1 reuses the derivative of the last stage as the first stage of
 * the next step whenever that stage sits at c = 1, even when the stage is not the new
 * solution (its row of A differs from b). Tables built that way then lose their order:
 * measured on an anharmonic oscillator with fixed steps 0.4/0.2/0.1, Verner 6(5) runs at
 * order 3.1-3.3, Sayfy-Aburub 4 at 2.0, ARK5(4)8L[2]SA at 3.4, while the same coefficients
 * in a plain RK loop give their nominal orders. Our right-hand side does not depend on t,
 * so moving that stage's time to 1 - 1e-6 changes nothing but the reuse. True FSAL tables
 * (Dormand-Prince: last row = b) keep the reuse. */
PetscErrorCode SpamArkodeLoadTable(const char *name, ARKodeButcherTable *B)
{
  PetscBool fsal = PETSC_TRUE;
  int       s;

  PetscFunctionBeginUser;
  *B = ARKodeButcherTable_LoadERKByName(name);
  PetscCheck(*B, PETSC_COMM_SELF, PETSC_ERR_LIB, "ARKodeButcherTable_LoadERKByName(%s) failed", name);
  s = (*B)->stages;
  for (int j = 0; j < s; j++)
    if ((*B)->A[s - 1][j] != (*B)->b[j]) fsal = PETSC_FALSE;
  if (!fsal && PetscAbsReal((*B)->c[s - 1] - 1.0) < 1e-8) (*B)->c[s - 1] = 1.0 - 1e-6;
  PetscFunctionReturn(0);
}

#define SPAM_COPIES_KEY "SpamArkodeCopies"

/* N_VScale with a record of ERKStep's whole copies (c = 1) between its vectors. ERKStep
 * 6.4.1 copies y into its yn when it starts and at the end of each step, and its Hermite
 * interpolant copies yn into its yold before yn takes the new step's end; its other copies
 * (yn into y, a stage into another) name neither pair. So after a step yold holds the
 * state the step started from, which the run loop's last_good snapshot is written from
 * (SpamTSLastGood): a state vector the loop no longer keeps a copy of. */
static void TrackedScale(realtype c, N_Vector x, N_Vector z)
{
  PetscContainer    cont = NULL;
  SpamArkodeCopies *k    = NULL;

  N_VScale_Petsc(c, x, z);
  if (c != 1.0 || x == z) return;
  if (PetscObjectQuery((PetscObject)N_VGetVector_Petsc(z), SPAM_COPIES_KEY, (PetscObject *)&cont) || !cont) return;
  if (PetscContainerGetPointer(cont, (void **)&k) || !k || z == k->y) return;
  if (x == k->y) k->yn = z;
  else if (x == k->yn) k->yold = z;
}

/* Every vector of ERKStep shares y's record: clones carry the composed container. */
static PetscErrorCode TrackCopies(TS_SpamARKode *ark, N_Vector y)
{
  PetscFunctionBeginUser;
  ark->copies = (SpamArkodeCopies){y, NULL, NULL};
  if (!ark->copies_c) {
    PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &ark->copies_c));
    PetscCall(PetscContainerSetPointer(ark->copies_c, &ark->copies));
  }
  PetscCall(PetscObjectCompose((PetscObject)N_VGetVector_Petsc(y), SPAM_COPIES_KEY, (PetscObject)ark->copies_c));
  y->ops->nvscale = TrackedScale;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetUp_SpamARKode(TS ts)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;
  SpamTsApp     *app;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCheck(app, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the arkode TS needs a SpamTsApp application context");
  PetscCallARK(SUNContext_Create((void *)&app->sim->p.comm, &ark->sunctx));
  ark->y = N_VMake_Petsc(ts->vec_sol, ark->sunctx);
  PetscCheck(ark->y, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VMake_Petsc failed");
  /* Fused operations: a combination of k vectors is one pass over memory instead of k
   * (clones inherit the setting); the linear combination itself is replaced below. */
  PetscCheck(N_VEnableFusedOps_Petsc(ark->y, SUNTRUE) == 0, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VEnableFusedOps_Petsc failed");
  PetscCall(SpamErrorNormAttach(ark->y, app->o->error_norm, app->sim->pair.reproducible)); /* -error_norm: cloned with y */
  if (ark->set.fixed_step > 0 && !app->o->classic_weights) PetscCall(SpamErrorNormZeroWeights(ark->y, app->o->error_norm, app->sim->pair.reproducible)); /* weights.c's zeros */
  /* Stages and solution summed term by term (det_combination.c): an FSAL table's last
   * stage is then y_n+1 bit for bit, which a restart needs. */
  PetscCall(SpamNVectorDeterministic(ark->y));
  SpamNVectorCloneUnwritten(ark->y);
  PetscCall(TrackCopies(ark, ark->y));
  {
    ARKodeButcherTable B;
    PetscCall(SpamArkodeLoadTable(ark->set.table, &B));
    PetscCall(SpamNVectorReserve(ts->vec_sol, (PetscInt)B->stages + SPAM_ERK_WORK_VECTORS));
    ARKodeButcherTable_Free(B);
  }
  ark->mem = ERKStepCreate(SpamSundialsRhs, ts->ptime, ark->y, ark->sunctx);
  PetscCheck(ark->mem, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "ERKStepCreate failed");
  PetscCallARK(ERKStepSetUserData(ark->mem, app));
  PetscCallARK(ERKStepSetErrHandlerFn(ark->mem, SpamSundialsErrHandler, app));
  {
    ARKodeButcherTable B;
    PetscCall(SpamArkodeLoadTable(ark->set.table, &B));
    PetscCallARK(ERKStepSetTable(ark->mem, B)); /* ERKStep keeps a copy */
    ARKodeButcherTable_Free(B);
  }
  if (app->o->classic_weights) PetscCallARK(ERKStepSStolerances(ark->mem, app->o->rtol, app->o->atol));
  else PetscCallARK(ERKStepWFtolerances(ark->mem, SpamErrorWeights));
  app->w.fixed_step = ark->set.fixed_step > 0; /* no error test: zero weights (weights.c) */
  app->w.zeroed     = NULL;
  PetscCallARK(ERKStepSetMaxNumSteps(ark->mem, -1)); /* the loop counts steps itself */
  /* -ts_max_reject means the same for every method: rejections of one step before it fails. */
  if (ts->max_reject > 0) PetscCallARK(ERKStepSetMaxErrTestFails(ark->mem, (int)ts->max_reject));
  PetscCall(ConfigureController(ark->mem, &ark->set, &ark->ctl));
  if (ark->set.fixed_step <= 0 && app->o->dt_first > 0) PetscCallARK(ERKStepSetInitStep(ark->mem, app->o->dt_first));
  if (ark->set.fixed_step <= 0 && (app->o->cfl > 0 || app->o->force > 0)) {
    PetscCallARK(ERKStepSetStabilityFn(ark->mem, SpamSundialsStability, app));
    PetscCallARK(ERKStepSetCFLFraction(ark->mem, SPAM_ARK_CFL_FRACTION));
  }
  app->self_stepping = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSStep_SpamARKode(TS ts)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;
  SpamTsApp     *app;
  realtype       tret, h;
  long           netf;
  int            flag;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  /* The state jumped between steps (TSRestartStep): drop the FSAL stage and step history. */
  if (ts->steprestart && ts->steps > 0) PetscCallARK(ERKStepReset(ark->mem, ts->ptime, ark->y));
  ts->steprestart = PETSC_FALSE;
  PetscCallARK(ERKStepSetStopTime(ark->mem, ts->max_time)); /* set again after each stop */
  /* Inside the step only ERKStep writes y (the right-hand side reads it): the memo of its
   * last combination holds there, and is dropped outside, where the loop may write X. */
  PetscCall(SpamNVectorCombinationArm(ark->y, PETSC_TRUE));
  flag           = ERKStepEvolve(ark->mem, ts->max_time, ark->y, &tret, ARK_ONE_STEP);
  ark->last_flag = flag;
  PetscCall(SpamNVectorCombinationArm(ark->y, PETSC_FALSE));
  PetscCall(app->perr);
  if (flag < 0) {
    SpamSundialsFailure(app, "ERKStepEvolve", ERKStepGetReturnFlagName, flag);
    ts->reason = TS_DIVERGED_STEP_REJECTED;
    PetscFunctionReturn(0);
  }
  PetscCallARK(ERKStepGetLastStep(ark->mem, &h));
  PetscCallARK(ERKStepGetNumErrTestFails(ark->mem, &netf));
  ts->ptime     = tret;
  ts->time_step = h;
  ts->reject    = (PetscInt)netf;
  PetscFunctionReturn(0);
}

/* Dense output (TSInterpolate): ERKStep's Hermite interpolant of the last step into X,
 * leaving ERKStep's own state and history alone. Its degree is min(5, order - 1); degrees
 * 4 and 5 cost one and two right-hand sides per step with an output in it. */
static PetscErrorCode TSInterpolate_SpamARKode(TS ts, PetscReal t, Vec X)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;
  N_Vector       x   = N_VMake_Petsc(X, ark->sunctx);
  SpamTsApp     *app;
  int            flag;

  PetscFunctionBeginUser;
  PetscCheck(x, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VMake_Petsc failed");
  PetscCall(TSGetApplicationContext(ts, &app));
  flag = ERKStepGetDky(ark->mem, t, 0, x);
  N_VDestroy(x);
  PetscCall(app->perr);
  PetscCall(SpamCheckArkode(flag, "ERKStepGetDky"));
  PetscFunctionReturn(0);
}

/* The particles moved between ranks (a migration): the solution is the new X, of another
 * local length. ERKStepResize re-makes ERKStep's vectors from it and keeps the step, the
 * error history and the counters; it evaluates f(t, y) again at the next step (the first
 * stage is not carried over). */
PetscErrorCode SpamTSARKodeResize(TS ts, Vec X)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;
  SpamTsApp     *app;
  N_Vector       y;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCall(TSSetSolution(ts, X));
  y = N_VMake_Petsc(X, ark->sunctx);
  PetscCheck(y, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VMake_Petsc failed");
  PetscCheck(N_VEnableFusedOps_Petsc(y, SUNTRUE) == 0, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VEnableFusedOps_Petsc failed");
  PetscCall(SpamErrorNormAttach(y, app->o->error_norm, app->sim->pair.reproducible));
  PetscCall(SpamNVectorDeterministic(y));
  SpamNVectorCloneUnwritten(y);
  app->w.zeroed = NULL; /* new weights to zero (weights.c), whatever their address */
  PetscCall(TrackCopies(ark, y)); /* ERKStepResize copies y into its new yn (the old X is gone) */
  PetscCallARK(ERKStepResize(ark->mem, y, 1.0, ts->ptime, NULL, NULL));
  N_VDestroy(ark->y);
  ark->y = y;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSReset_SpamARKode(TS ts)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;

  PetscFunctionBeginUser;
  if (ark->mem) ERKStepFree(&ark->mem);
  if (ark->y) N_VDestroy(ark->y); /* X may be gone already: its container goes with it */
  ark->y       = NULL;
  ark->copies  = (SpamArkodeCopies){NULL, NULL, NULL};
  PetscCall(PetscContainerDestroy(&ark->copies_c));
  if (ark->sunctx) PetscCallARK(SUNContext_Free(&ark->sunctx));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSDestroy_SpamARKode(TS ts)
{
  PetscFunctionBeginUser;
  PetscCall(TSReset_SpamARKode(ts));
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "SpamTSSundialsStats_C", NULL));
  PetscCall(PetscFree(ts->data));
  PetscFunctionReturn(0);
}

/* -ts_view: the table and controller, and ERKStep's statistics table. */
static PetscErrorCode TSView_SpamARKode(TS ts, PetscViewer viewer)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;
  PetscBool      ascii;
  FILE          *fd;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) PetscFunctionReturn(0);
  if (ark->set.fixed_step > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "  ARKODE ERKStep, table %s, fixed step %g\n", ark->set.table, ark->set.fixed_step));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "  ARKODE ERKStep, table %s, controller %s\n", ark->set.table, ark->set.adapt));
  if (!ark->mem) PetscFunctionReturn(0);
  PetscCall(PetscViewerFlush(viewer));
  PetscCall(PetscViewerASCIIGetPointer(viewer, &fd));
  PetscCallARK(ERKStepPrintAllStats(ark->mem, fd, SUN_OUTPUTFORMAT_TABLE));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetFromOptions_SpamARKode(TS ts, PetscOptionItems *PetscOptionsObject)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;
  SpamTsApp     *app;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCheck(app, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the arkode TS needs a SpamTsApp application context before TSSetFromOptions");
  PetscCall(SpamArkodeOptionsRead(PetscOptionsObject, app->o, PETSC_TRUE, &ark->set));
  PetscCall(SpamArkodeAdaptType(app->o, SPAM_TSARKODE, &ark->set));
  PetscFunctionReturn(0);
}

/* -sundials_stats (or force): ERKStepPrintAllStats, SUNDIALS' own table. */
static PetscErrorCode SundialsStats_SpamARKode(TS ts, FILE *file, PetscBool force)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;

  PetscFunctionBeginUser;
  if (ark->mem && (force || ark->set.sundials_stats)) PetscCallARK(ERKStepPrintAllStats(ark->mem, file, SUN_OUTPUTFORMAT_TABLE));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSARKodeGetSettings(TS ts, const SpamArkodeSettings **s)
{
  PetscBool arkode;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSARKODE, &arkode));
  if (arkode) *s = &((TS_SpamARKode *)ts->data)->set;
  else PetscCall(SpamTSARKodeImexGetSettings(ts, s));
  PetscFunctionReturn(0);
}

/* The arkode TS's data, set up (ERKStep created): an error for another type. */
static PetscErrorCode SetUpArkode(TS ts, TS_SpamARKode **ark)
{
  PetscBool arkode;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSARKODE, &arkode));
  PetscCheck(arkode, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_WRONG, "not an arkode TS");
  PetscCall(TSSetUp(ts));
  *ark = (TS_SpamARKode *)ts->data;
  PetscCheck((*ark)->mem, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the arkode TS has no ERKStep");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSARKodeGetHistory(TS ts, SpamArkodeHistory *h)
{
  TS_SpamARKode *ark = NULL;
  long           nst;

  PetscFunctionBeginUser;
  PetscCall(SetUpArkode(ts, &ark));
  if (ark->set.fixed_step <= 0) PetscCall(SpamArkodeControllerGet(&ark->ctl, h));
  else { /* fixed steps: no history; the step is the option */
    PetscCallARK(ERKStepGetNumSteps(ark->mem, &nst));
    h->h_next   = ark->set.fixed_step;
    h->ehist[0] = h->ehist[1] = 1.0;
    h->hhist[0] = h->hhist[1] = 0.0;
    h->accepted = ark->ctl.saved.accepted + nst;
  }
  PetscFunctionReturn(0);
}

/* ERKStep starts again from the TS's time and solution (it was created from the values
 * they had at TSSetUp), forgetting its counters and history, which the controller then
 * supplies. The TS's own restart flag is cleared: a restart of the TS's step (TSStep's
 * ERKStepReset) would only do again what is done here. */
PetscErrorCode SpamTSARKodeSetHistory(TS ts, const SpamArkodeHistory *h)
{
  TS_SpamARKode *ark = NULL;

  PetscFunctionBeginUser;
  PetscCall(SetUpArkode(ts, &ark));
  PetscCallARK(ERKStepReInit(ark->mem, SpamSundialsRhs, ts->ptime, ark->y));
  if (ark->set.fixed_step <= 0) PetscCall(SpamArkodeControllerResume(&ark->ctl, h));
  else ark->ctl.saved.accepted = h->accepted;
  ts->time_step   = h->h_next;
  ts->steprestart = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSARKodeCheckpointable(TS ts, PetscBool *ok)
{
  PetscBool      arkode;
  TS_SpamARKode *ark = NULL;
  realtype       t, hnext;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSARKODE, &arkode));
  if (!arkode) PetscFunctionReturn(0);
  PetscCall(SetUpArkode(ts, &ark));
  if (ark->set.fixed_step > 0) PetscFunctionReturn(0); /* ERKStep's fixed step is not clamped */
  if (ark->last_flag == ARK_TSTOP_RETURN) {
    *ok = PETSC_FALSE;
    PetscFunctionReturn(0);
  }
  PetscCallARK(ERKStepGetCurrentTime(ark->mem, &t));
  PetscCallARK(ERKStepGetCurrentStep(ark->mem, &hnext));
  /* A clamped step is (tstop - t)(1 - 4 eps): it ends within 1e-12 of tstop. */
  *ok = (PetscBool)(t + hnext < ts->max_time - 1e-12 * PetscAbsReal(ts->max_time));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSCreate_ARKode(TS ts)
{
  TS_SpamARKode *ark = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ark));
  /* The defaults, for a TS that never reads its options (TSSetFromOptions sets them). */
  PetscCall(PetscStrncpy(ark->set.table, "ARKODE_DORMAND_PRINCE_7_4_5", sizeof ark->set.table));
  PetscCall(PetscStrncpy(ark->set.adapt, "pid", sizeof ark->set.adapt));
  ts->data                = (void *)ark;
  ts->ops->setfromoptions = TSSetFromOptions_SpamARKode;
  ts->ops->setup          = TSSetUp_SpamARKode;
  ts->ops->step           = TSStep_SpamARKode;
  ts->ops->reset          = TSReset_SpamARKode;
  ts->ops->destroy        = TSDestroy_SpamARKode;
  ts->ops->view           = TSView_SpamARKode;
  ts->ops->interpolate    = TSInterpolate_SpamARKode;
  ts->default_adapt_type  = TSADAPTNONE; /* ERKStep adapts by itself */
  ts->usessnes            = PETSC_FALSE;
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "SpamTSSundialsStats_C", SundialsStats_SpamARKode));
  PetscFunctionReturn(0);
}

/* The arkode row of the table of methods (ts_family.h). */
static PetscErrorCode DescribeARKode(TS ts, const char **sub, char *adapt, size_t alen, double *fixed_dt)
{
  const SpamArkodeSettings *s = &((TS_SpamARKode *)ts->data)->set;

  PetscFunctionBeginUser;
  *sub      = s->table;
  *fixed_dt = s->fixed_step;
  PetscCall(PetscStrncpy(adapt, s->fixed_step > 0 ? "none" : s->adapt, alen));
  PetscFunctionReturn(0);
}

static PetscErrorCode HelpARKode(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o)
{
  SpamArkodeSettings s;

  PetscFunctionBeginUser;
  PetscCall(SpamArkodeOptionsRead(PetscOptionsObject, o, PETSC_TRUE, &s));
  PetscFunctionReturn(0);
}

/* ERKStep's controller history and the step it proposes next. */
static PetscErrorCode CkPutARKode(TS ts, const SpamTsApp *app, SpamCkFile *c, PetscReal *dt)
{
  SpamArkodeHistory h;

  PetscFunctionBeginUser;
  if (!app->self_stepping) PetscFunctionReturn(0); /* never set up: nothing stepped */
  PetscCall(SpamTSARKodeGetHistory(ts, &h));
  {
    const double v[5] = {h.h_next, h.ehist[0], h.ehist[1], h.hhist[0], h.hhist[1]};
    PetscCall(SpamCkPutReal(c, "arkode_history", 5, v));
  }
  PetscCall(SpamCkPutLong(c, "arkode_accepted", h.accepted));
  *dt = h.h_next;
  PetscFunctionReturn(0);
}

/* Without its history ERKStep would not be re-initialised at the checkpoint's time. */
static PetscErrorCode CkCheckARKode(const SpamCkFile *c, const char *path)
{
  PetscFunctionBeginUser;
  if (!SpamCkHas(c, "arkode_history")) SPAM_BAD_INPUT("-restart", path, "has no entry 'arkode_history' (ERKStep's controller), which a run of -ts_type arkode writes");
  PetscFunctionReturn(0);
}

/* ERKStep starts fresh here, at the TS's time: a jump pending at the checkpoint still
 * drops the history. */
static PetscErrorCode CkApplyARKode(TS ts, const SpamCkFile *c, double h_next, PetscBool pending)
{
  const double     *v;
  long              accepted;
  SpamArkodeHistory h;

  PetscFunctionBeginUser;
  (void)h_next; /* the history's own */
  PetscCall(SpamCkGetReal(c, "arkode_history", 5, &v));
  PetscCall(SpamCkGetLong(c, "arkode_accepted", &accepted));
  h.h_next   = v[0];
  h.ehist[0] = v[1];
  h.ehist[1] = v[2];
  h.hhist[0] = v[3];
  h.hhist[1] = v[4];
  h.accepted = accepted;
  PetscCall(SpamTSARKodeSetHistory(ts, &h));
  ts->steprestart = pending ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* ERKStep keeps f(y_n) of the step it continues (first same as last). */
static PetscErrorCode CkReusesARKode(TS ts, const SpamCkFile *c, PetscBool *reused)
{
  (void)ts;
  (void)c;
  *reused = PETSC_TRUE;
  return 0;
}

/* The state the last step started from: after a failed step ERKStep has put it back into
 * X (its yn, the last accepted state); after an accepted step it is the interpolant's
 * yold. NULL when ERKStep's copies were not seen (another SUNDIALS): the loop keeps its
 * own then (SpamTSKeepsLastGood). */
static PetscErrorCode LastGoodARKode(TS ts, PetscBool accepted, Vec *good)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;

  PetscFunctionBeginUser;
  *good = NULL;
  if (!ark->mem || !ark->copies.yn) PetscFunctionReturn(0);
  if (!accepted) *good = ts->vec_sol;
  else if (ark->copies.yold) *good = N_VGetVector_Petsc(ark->copies.yold);
  PetscFunctionReturn(0);
}

static PetscErrorCode KeepsLastGoodARKode(TS ts, PetscBool *yes)
{
  TS_SpamARKode *ark = (TS_SpamARKode *)ts->data;

  PetscFunctionBeginUser;
  *yes = (PetscBool)(ark->mem && ark->copies.yn); /* ERKStepCreate's copy of y was seen */
  PetscFunctionReturn(0);
}

/* A set-up ERKStep of a never-stepped TS cannot be resized: it is made again on X. */
static PetscErrorCode FollowPlacedARKode(TS ts, Vec X)
{
  PetscFunctionBeginUser;
  if (ts->setupcalled) PetscCall(TSReset(ts));
  PetscCall(TSSetSolution(ts, X));
  PetscFunctionReturn(0);
}

static const SpamTSOption OptionsARKode[] = {
  {"arkode_table", PETSC_TRUE, PETSC_FALSE},    {"arkode_fixed_step", PETSC_TRUE, PETSC_FALSE},     {"arkode_adapt", PETSC_TRUE, PETSC_TRUE},
  {"arkode_adapt_params", PETSC_TRUE, PETSC_TRUE}, {"arkode_safety", PETSC_TRUE, PETSC_TRUE},        {"arkode_max_growth", PETSC_TRUE, PETSC_TRUE},
  {"arkode_max_first_growth", PETSC_TRUE, PETSC_TRUE}, {"arkode_max_efail_growth", PETSC_TRUE, PETSC_TRUE}, {"sundials_stats", PETSC_FALSE, PETSC_FALSE},
  {NULL, PETSC_FALSE, PETSC_FALSE}};

const SpamTSFamily SpamTSFamilyARKode = {
  .options       = OptionsARKode,
  .type          = SPAM_TSARKODE,
  .adapt_default = TSADAPTNONE,
  .steps         = SPAM_TS_STEPS_OWN,
  .follow        = SPAM_TS_FOLLOW_RESIZE,
  .interpolates  = SpamTSInterpolatesAlways,
  .describe      = DescribeARKode,
  .help_other    = HelpARKode,
  .ck_put        = CkPutARKode,
  .ck_check      = CkCheckARKode,
  .ck_apply      = CkApplyARKode,
  .ck_reuses_f   = CkReusesARKode,
  .follow_placed = FollowPlacedARKode,
  .last_good     = LastGoodARKode,
  .keeps_last_good = KeepsLastGoodARKode,
};
