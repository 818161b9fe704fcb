/* An exact start state for the retry of a rejected PETSc rk step.
 *
 * TSStep_RK (PETSc 3.18.5, rk.c) forms y_n+1 in the solution vector itself and, when the
 * adaptor rejects the step, TSRollBack_RK subtracts h sum_j b_j k_j again: y_n' = y_n
 * only to rounding. The retry then starts from y_n'. In a continuing run its first stage
 * is still the FSAL derivative f(y_n) of the previous step, while a run restarted at y_n
 * (a new TS has no FSAL stage: ts->steprestart) computes f(y_n') there: a rejection as the
 * first step after a restart parted the two runs. Restoring y_n itself before the retry
 * makes both start the retry from y_n with stage f(y_n) (the restarted run computes it
 * again), so rk + basic restarts bit for bit even then. The hook is TSSetPreStage, which
 * TSStep_RK calls at the top of every stage, before stage 0 copies the solution; it costs
 * one copy of the state per step.
 *
 * One more difference remains in the first step after a restart (TSStep_RK reuses no FSAL
 * stage after ts->steprestart): its retry evaluates f(y_n) again, and spam-ark's
 * right-hand side is not a pure function of y: a neighbour list rebuilt during the
 * rejected attempt sums the pairs in another order. The continuing run's retry reuses the
 * f(y_n) it had. So a retry leaves stage 0's derivative as the first attempt computed it
 * (TSStep_RK writes stage 0 into the same vector every attempt and a rollback does not
 * touch it): both runs then retry with the same bits. */
#include <spam/integrator.h>

/* Stage 0 sits at the step's start (c_0 = 0): the first attempt of a step records the
 * state, an attempt of the same step after a rejection gets it back. */
static PetscErrorCode RestoreStepStart(TS ts, PetscReal stage_time)
{
  SpamTsApp *app;
  PetscReal  t;
  PetscInt   step, reject;
  Vec        X;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCall(TSGetTime(ts, &t));
  app->stage0 = 0;
  if (stage_time != t) PetscFunctionReturn(0);
  PetscCall(TSGetStepNumber(ts, &step));
  PetscCall(TSGetStepRejections(ts, &reject));
  PetscCall(TSGetSolution(ts, &X));
  if (step == app->ystart_step && t == app->ystart_t && reject > app->ystart_reject) {
    PetscCall(VecCopy(app->ystart, X));
    app->stage0 = 2;
  } else {
    PetscCall(VecCopy(X, app->ystart));
    app->stage0  = 1;
    app->f0_kept = PETSC_FALSE;
  }
  app->ystart_step   = step;
  app->ystart_t      = t;
  app->ystart_reject = reject;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSRKExactRollback(TS ts, SpamTsApp *app)
{
  Vec X;

  PetscFunctionBeginUser;
  PetscCall(TSGetSolution(ts, &X));
  if (!app->ystart) PetscCall(VecDuplicate(X, &app->ystart));
  app->ystart_step = -1; /* nothing recorded yet */
  PetscCall(TSSetPreStage(ts, RestoreStepStart));
  PetscFunctionReturn(0);
}

PetscBool SpamTSRKKeepStageZero(SpamTsApp *app)
{
  const PetscBool keep = (PetscBool)(app->stage0 == 2 && app->f0_kept);
  if (keep) app->stage0 = 0;
  return keep;
}

void SpamTSRKEvaluated(SpamTsApp *app)
{
  if (app->stage0 == 1) app->f0_kept = PETSC_TRUE;
  app->stage0 = 0;
}
