/* -error_norm: the norm of the weighted error estimate, the same for every adaptive
 * method. ARKODE and CVODE compute it as N_VWrmsNorm(error, weights), so the max norm is
 * that vector operation replaced; PETSc's adaptor has it as its weighted norm type. */
#include <petsc/private/tsimpl.h>
#include <spam/error_norm.h>
#include <spam/errors.h>
#include <spam/integrator.h>
#include <nvector/nvector_petsc.h>

const char *const SpamErrorNormNames[] = {"rms", "max"};

PetscErrorCode SpamErrorNormOptions(MPI_Comm comm, SpamErrorNorm *norm)
{
  char name[16] = "rms";

  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, NULL, "Error norm of the adaptive methods (arkode, cvode, and rk/ssp/euler under an active -ts_adapt_type)", "spam-ark");
  PetscCall(PetscOptionsString("-error_norm", "Norm of the weighted local error held to 1: rms or max (every particle within its tolerance)", "README", name, name, sizeof name, NULL));
  PetscOptionsEnd();
  PetscCall(SpamCheckAllowed("-error_norm", name, SpamErrorNormNames, 2));
  *norm = strcmp(name, "max") ? SPAM_ERROR_NORM_RMS : SPAM_ERROR_NORM_MAX;
  PetscFunctionReturn(0);
}

realtype SpamNVWeightedMaxNorm_Petsc(N_Vector x, N_Vector w)
{
  Vec                X = N_VGetVector_Petsc(x), W = N_VGetVector_Petsc(w);
  const PetscScalar *xa, *wa;
  PetscInt           n;
  PetscReal          local = 0.0, global;

  /* A norm has no error return: NaN fails every comparison with 1, so the error test
   * rejects the step and the run ends with SUNDIALS' failure, not a wrong acceptance. */
  if (VecGetLocalSize(X, &n) || VecGetArrayRead(X, &xa)) return NAN;
  if (VecGetArrayRead(W, &wa)) {
    (void)VecRestoreArrayRead(X, &xa);
    return NAN;
  }
  for (PetscInt i = 0; i < n; i++) local = PetscMax(local, PetscAbsScalar(xa[i] * wa[i]));
  if (VecRestoreArrayRead(W, &wa) || VecRestoreArrayRead(X, &xa)) return NAN;
  if (MPI_Allreduce(&local, &global, 1, MPIU_REAL, MPIU_MAX, PetscObjectComm((PetscObject)X)) != MPI_SUCCESS) return NAN;
  return global;
}

PetscErrorCode SpamErrorNormAttach(N_Vector y, SpamErrorNorm norm)
{
  PetscFunctionBeginUser;
  if (norm == SPAM_ERROR_NORM_RMS) PetscFunctionReturn(0); /* SUNDIALS' own */
  y->ops->nvwrmsnorm = SpamNVWeightedMaxNorm_Petsc;
  /* Without the fused array form SUNDIALS applies nvwrmsnorm to each vector in turn. */
  y->ops->nvwrmsnormvectorarray = NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamErrorNormSetTS(TS ts, SpamErrorNorm norm)
{
  const NormType want = norm == SPAM_ERROR_NORM_MAX ? NORM_INFINITY : NORM_2;
  TSType         type;
  TSAdapt        adapt;
  PetscBool      given, none;

  PetscFunctionBeginUser;
  PetscCall(TSGetType(ts, &type));
  if (!strcmp(type, SPAM_TSARKODE) || !strcmp(type, SPAM_TSCVODE)) PetscFunctionReturn(0);
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(PetscObjectTypeCompare((PetscObject)adapt, TSADAPTNONE, &none));
  /* PETSc 3.18 has no setter for the adaptor's norm type, only the option (which, without
   * an adaptor, the check of unused options refuses as such). */
  PetscCall(PetscOptionsHasName(NULL, NULL, "-ts_adapt_wnormtype", &given));
  given = (PetscBool)(given && !none);
  if (given && adapt->wnormtype != want) SPAM_BAD_INPUT("-ts_adapt_wnormtype", NormTypes[adapt->wnormtype], "disagrees with -error_norm %s (NORM_2 is rms, INFINITY is max): give -error_norm alone, it sets the norm of every adaptive method", SpamErrorNormNames[norm]);
  adapt->wnormtype = want;
  PetscFunctionReturn(0);
}
