/* What the arkode and cvode types report beyond the loop's statistics: SUNDIALS' own
 * statistics table (-sundials_stats, -ts_view), and, with -help, the options of the
 * SUNDIALS type not chosen (PETSc lists only the chosen type's). */
#include <petsc/private/tsimpl.h> /* PetscTryMethod, ts->adapt->monitor */
#include <spam/integrator.h>

PetscErrorCode SpamTSSundialsStats(TS ts, FILE *file, PetscBool force)
{
  PetscFunctionBeginUser;
  PetscTryMethod(ts, "SpamTSSundialsStats_C", (TS, FILE *, PetscBool), (ts, file, force));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSSundialsHelp(TS ts, const SpamRunOptions *o)
{
  PetscBool arkode, cvode;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSARKODE, &arkode));
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSCVODE, &cvode));
  PetscOptionsBegin(PetscObjectComm((PetscObject)ts), NULL, "Options of the SUNDIALS TS type not chosen", "TS");
  if (!arkode) {
    SpamArkodeSettings s;
    PetscCall(SpamArkodeOptionsRead(PetscOptionsObject, o, &s));
  }
  if (!cvode) {
    PetscInt  order = 12;
    PetscBool stats = PETSC_FALSE;
    PetscCall(SpamCVodeOptionsRead(PetscOptionsObject, &order, &stats));
  }
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* -ts_adapt_monitor for the types whose step never consults PETSc's adaptor (arkode and
 * cvode choose their own steps, basicsymplectic takes the fixed step): the loop reports
 * each accepted step here, in the adaptor monitor's place and style. */
PetscErrorCode SpamTSAdaptMonitorSelf(TS ts, long step, double t0, double dt, long rejected)
{
  TSType    type;
  PetscBool own, symp;

  PetscFunctionBeginUser;
  if (!ts->adapt || !ts->adapt->monitor) PetscFunctionReturn(0);
  PetscCall(TSGetType(ts, &type));
  own  = (PetscBool)(!strcmp(type, SPAM_TSARKODE) || !strcmp(type, SPAM_TSCVODE));
  symp = (PetscBool)!strcmp(type, TSBASICSYMPLECTIC);
  if (!own && !symp) PetscFunctionReturn(0); /* PETSc's adaptor reports these itself */
  PetscCall(PetscViewerASCIIPrintf(ts->adapt->monitor, "    TSAdapt %s (%s) step %3ld accepted t=%-11g + %10.3e rejected so far %ld\n", type, own ? "own controller" : "fixed step", step, t0, dt, rejected));
  PetscFunctionReturn(0);
}
