/* The TS state spam-ark needs and PETSc 3.18 keeps private: the restart flag a state jump
 * leaves, the adaptor's weighted-norm type (which has no setter, only its option) and the
 * adaptor monitor's viewer. Outside the TS implementations of arkode and cvode, this is the
 * one file that reads PETSc's TS internals. */
#include <petsc/private/tsimpl.h>
#include "ts_family.h"

/* A state jump (TSRestartStep) waits to drop the method's history: a checkpoint taken now
 * must say so, and ERKStep's stop-time clamp waits with it. A PETSc method that followed a
 * migration was reset onto the new vector (TSReset, then its first stage evaluated anew):
 * it keeps nothing a restart could miss, a jump before it included. */
PetscErrorCode SpamTSJumpPending(TS ts, PetscBool followed, PetscBool *pending)
{
  const SpamTSFamily *f;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  *pending = (PetscBool)(ts->steprestart && ts->steps > 0 && !(followed && (f->follow == SPAM_TS_FOLLOW_RESET_FIXED || f->follow == SPAM_TS_FOLLOW_CARRY)));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSAdaptNormType(TS ts, NormType *have, const NormType *want)
{
  TSAdapt adapt;

  PetscFunctionBeginUser;
  PetscCall(TSGetAdapt(ts, &adapt));
  if (have) *have = adapt->wnormtype;
  if (want) adapt->wnormtype = *want;
  PetscFunctionReturn(0);
}

PetscViewer SpamTSAdaptMonitorViewer(TS ts)
{
  return ts->adapt ? ts->adapt->monitor : NULL;
}
