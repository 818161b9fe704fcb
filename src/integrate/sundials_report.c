/* What the arkode and cvode types report beyond the loop's statistics: SUNDIALS' own
 * statistics table (-sundials_stats, -ts_view), and, with -help, the options of the
 * SUNDIALS type not chosen (PETSc lists only the chosen type's). */
#include "ts_family.h"

PetscErrorCode SpamTSSundialsStats(TS ts, FILE *file, PetscBool force)
{
  PetscErrorCode (*stats)(TS, FILE *, PetscBool) = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQueryFunction((PetscObject)ts, "SpamTSSundialsStats_C", &stats));
  if (stats) PetscCall(stats(ts, file, force));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSSundialsHelp(TS ts, const SpamRunOptions *o)
{
  const SpamTSFamily *mine, *f;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &mine));
  PetscOptionsBegin(PetscObjectComm((PetscObject)ts), NULL, "Options of the TS types not chosen", "TS");
  for (int k = 0; (f = SpamTSFamilyAt(k)); k++)
    if (f != mine && f->help_other) PetscCall(f->help_other(PetscOptionsObject, o));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* -ts_adapt_monitor for the types whose step never consults PETSc's adaptor (arkode and
 * cvode choose their own steps, basicsymplectic takes the fixed step): the loop reports
 * each accepted step here, in the adaptor monitor's place and style. */
PetscErrorCode SpamTSAdaptMonitorSelf(TS ts, long step, double t0, double dt, long rejected)
{
  const SpamTSFamily *f;
  PetscViewer         monitor = SpamTSAdaptMonitorViewer(ts);

  PetscFunctionBeginUser;
  if (!monitor) PetscFunctionReturn(0);
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->steps == SPAM_TS_STEPS_ADAPTOR) PetscFunctionReturn(0); /* PETSc's adaptor reports these itself */
  PetscCall(PetscViewerASCIIPrintf(monitor, "    TSAdapt %s (%s) step %3ld accepted t=%-11g + %10.3e rejected so far %ld\n", f->type, f->steps == SPAM_TS_STEPS_OWN ? "own controller" : "fixed step", step, t0, dt, rejected));
  PetscFunctionReturn(0);
}
