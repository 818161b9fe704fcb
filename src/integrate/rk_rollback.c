/* The retry of a rejected PETSc rk step keeps the first attempt's f(y_n), so that a run
 * restarted from a checkpoint retries with the bits of the uninterrupted run.
 *
 * TSStep_RK (PETSc 3.18.5, rk.c) reuses the last stage's derivative of the previous step as
 * its stage 0 (FSAL), except right after ts->steprestart, which a new TS has. When the
 * adaptor rejects a step, TSRollBack_RK subtracts h sum_j b_j k_j from the solution again
 * (y_n' = y_n only to rounding, but the same bits in both runs) and the retry starts from
 * y_n'. The continuing run keeps its stage 0 derivative f(y_n); the restarted run, without
 * FSAL in its first step, evaluates stage 0 again at y_n' -- and spam-ark's right-hand side
 * is not even a pure function of y (a neighbour list rebuilt during the rejected attempt
 * sums the pairs in another order). Measured on test_erk_restart's gas: 3 of 4 restart
 * points bitwise, the fourth parted when its first step was rejected.
 *
 * So a retry does not evaluate stage 0 at all: TSStep_RK writes stage 0's derivative into
 * the same vector at every attempt and a rollback leaves it alone, so it still holds the
 * first attempt's f(y_n), which is what the continuing run uses. TSSetPreStage's hook marks
 * stage 0 (c_0 = 0: the stage at the step's start) of a first attempt or of a retry; the
 * right-hand side (ts_create.c) asks SpamTSRKKeepStageZero before evaluating. */
#include <spam/integrator.h>

enum { STAGE_OTHER = 0, STAGE0_FIRST = 1, STAGE0_RETRY = 2 };

static PetscErrorCode MarkStageZero(TS ts, PetscReal stage_time)
{
  SpamTsApp *app;
  PetscReal  t;
  PetscInt   step, reject;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCall(TSGetTime(ts, &t));
  app->stage0 = STAGE_OTHER;
  if (stage_time != t) PetscFunctionReturn(0);
  PetscCall(TSGetStepNumber(ts, &step));
  PetscCall(TSGetStepRejections(ts, &reject));
  if (step == app->retry_step && t == app->retry_t && reject > app->retry_reject) app->stage0 = STAGE0_RETRY;
  else {
    app->stage0  = STAGE0_FIRST;
    app->f0_kept = PETSC_FALSE;
  }
  app->retry_step   = step;
  app->retry_t      = t;
  app->retry_reject = reject;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSRKKeepFirstStage(TS ts, SpamTsApp *app)
{
  PetscFunctionBeginUser;
  app->retry_step = -1; /* no step seen yet */
  PetscCall(TSSetPreStage(ts, MarkStageZero));
  PetscFunctionReturn(0);
}

PetscBool SpamTSRKKeepStageZero(SpamTsApp *app)
{
  const PetscBool keep = (PetscBool)(app->stage0 == STAGE0_RETRY && app->f0_kept);
  if (keep) app->stage0 = STAGE_OTHER;
  return keep;
}

void SpamTSRKEvaluated(SpamTsApp *app)
{
  if (app->stage0 == STAGE0_FIRST) app->f0_kept = PETSC_TRUE;
  app->stage0 = STAGE_OTHER;
}
