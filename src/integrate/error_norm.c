/* -error_norm: the norm of the weighted error estimate, the same for every adaptive
 * method. ARKODE and CVODE compute it as N_VWrmsNorm(error, weights), so the max norm is
 * that vector operation replaced; PETSc's adaptor has it as its weighted norm type.
 * Under -reproducible the rms norm is replaced too, by one whose bits do not depend on
 * how the vector is split over ranks (SUNDIALS' sums each rank's part, then adds the
 * partial sums: another split, other roundings, other step sizes). */
#include <spam/error_norm.h>
#include <spam/errors.h>
#include "ts_family.h"
#include <nvector/nvector_petsc.h>
#include <stdint.h>
#include <string.h>

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

/* Local maximum of the terms t_i = (x_i w_i)^2, and whether one is NaN (2) or infinite (1). */
static void LargestTerm(PetscInt n, const PetscScalar *xa, const PetscScalar *wa, double mx[2])
{
  mx[0] = mx[1] = 0.0;
  for (PetscInt i = 0; i < n; i++) {
    const double t = xa[i] * wa[i], t2 = t * t;
    if (isnan(t2)) mx[1] = 2.0;
    else if (isinf(t2)) mx[1] = PetscMax(mx[1], 1.0);
    else mx[0] = PetscMax(mx[0], t2);
  }
}

/* The shift that puts the largest term tmax (> 0) of N at under 2^62 / (N + 1) units: N
 * rounded terms then sum below 2^62, so the int64 sum cannot overflow. */
static int FixedPointShift(double tmax, PetscInt N)
{
  int e;
  (void)frexp(tmax, &e); /* tmax < 2^e */
  return 62 - e - (int)ceil(log2((double)N + 1.0));
}

realtype SpamNVReproducibleWrmsNorm_Petsc(N_Vector x, N_Vector w)
{
  Vec                X = N_VGetVector_Petsc(x), W = N_VGetVector_Petsc(w);
  MPI_Comm           comm = PetscObjectComm((PetscObject)X);
  const PetscScalar *xa, *wa;
  PetscInt           n, N;
  double             mx[2], all[2];
  int64_t            sum[2] = {0, 0}, total[2]; /* the fixed-point sum, failed ranks */
  int                shift;

  /* No error return, as for the max norm: NaN makes the error test reject the step. */
  if (VecGetLocalSize(X, &n) || VecGetSize(X, &N) || VecGetArrayRead(X, &xa)) return NAN;
  if (VecGetArrayRead(W, &wa)) {
    (void)VecRestoreArrayRead(X, &xa);
    return NAN;
  }
  LargestTerm(n, xa, wa, mx);
  /* Collective calls below are made on every rank whatever it found, so none waits. */
  if (MPI_Allreduce(mx, all, 2, MPI_DOUBLE, MPI_MAX, comm) != MPI_SUCCESS) all[1] = 2.0;
  shift = all[0] > 0.0 ? FixedPointShift(all[0], N) : 0;
  for (PetscInt i = 0; i < n && all[0] > 0.0 && all[1] == 0.0; i++) {
    const double t = xa[i] * wa[i];
    sum[0] += (int64_t)llrint(ldexp(t * t, shift));
  }
  if (VecRestoreArrayRead(W, &wa) || VecRestoreArrayRead(X, &xa)) sum[1] = 1;
  /* Integer addition is exact and associative: the same total in any order and split. */
  if (MPI_Allreduce(sum, total, 2, MPI_INT64_T, MPI_SUM, comm) != MPI_SUCCESS || total[1] > 0) return NAN;
  if (all[1] > 1.0) return NAN;
  if (all[1] > 0.0) return INFINITY;
  if (all[0] == 0.0 || N == 0) return 0.0;
  return sqrt(ldexp((double)total[0], -shift) / (double)N);
}

PetscErrorCode SpamErrorNormAttach(N_Vector y, SpamErrorNorm norm, PetscBool reproducible)
{
  PetscFunctionBeginUser;
  if (norm == SPAM_ERROR_NORM_RMS && !reproducible) PetscFunctionReturn(0); /* SUNDIALS' own */
  /* The max norm is partition-independent as it is (a max is exact in any order). */
  y->ops->nvwrmsnorm = norm == SPAM_ERROR_NORM_MAX ? SpamNVWeightedMaxNorm_Petsc : SpamNVReproducibleWrmsNorm_Petsc;
  /* Without the fused array form SUNDIALS applies nvwrmsnorm to each vector in turn. */
  y->ops->nvwrmsnormvectorarray = NULL;
  PetscFunctionReturn(0);
}

/* 1 if every weight of w is zero on every rank, 0 if not, -1 on an error. The weights of a
 * fixed step are pages given back (zero_pages.c): reading them reads the kernel's one zero
 * page, from the cache. */
static int AllZero(N_Vector w)
{
  Vec                W    = N_VGetVector_Petsc(w);
  MPI_Comm           comm = PetscObjectComm((PetscObject)W);
  const PetscScalar *wa;
  PetscInt           n;
  uint64_t           bits = 0; /* the OR of the weights' bits but their signs: a loop that vectorises */
  int                nonzero, any;
  PetscMPIInt        size;

  if (VecGetLocalSize(W, &n) || VecGetArrayRead(W, &wa)) return -1;
  for (PetscInt i = 0; i < n; i++) {
    uint64_t b;
    memcpy(&b, wa + i, sizeof b);
    bits |= b << 1; /* +0.0 and -0.0 are zero; NaN, infinities, subnormals are not */
  }
  nonzero = bits != 0;
  if (VecRestoreArrayRead(W, &wa) || MPI_Comm_size(comm, &size) != MPI_SUCCESS) return -1;
  if (size > 1 && MPI_Allreduce(&nonzero, &any, 1, MPI_INT, MPI_LOR, comm) != MPI_SUCCESS) return -1;
  return !(size > 1 ? any : nonzero);
}

static realtype ZeroOr(N_Vector x, N_Vector w, realtype (*norm)(N_Vector, N_Vector))
{
  const int zero = AllZero(w);
  return zero < 0 ? NAN : zero ? 0.0 : norm(x, w);
}

static realtype ZeroOrRms(N_Vector x, N_Vector w)
{
  return ZeroOr(x, w, N_VWrmsNorm_Petsc);
}

static realtype ZeroOrMax(N_Vector x, N_Vector w)
{
  return ZeroOr(x, w, SpamNVWeightedMaxNorm_Petsc);
}

static realtype ZeroOrReproducible(N_Vector x, N_Vector w)
{
  return ZeroOr(x, w, SpamNVReproducibleWrmsNorm_Petsc);
}

PetscErrorCode SpamErrorNormZeroWeights(N_Vector y, SpamErrorNorm norm, PetscBool reproducible)
{
  PetscFunctionBeginUser;
  y->ops->nvwrmsnorm            = norm == SPAM_ERROR_NORM_MAX ? ZeroOrMax : reproducible ? ZeroOrReproducible : ZeroOrRms;
  y->ops->nvwrmsnormvectorarray = NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamErrorNormSetTS(TS ts, SpamErrorNorm norm)
{
  const NormType want = norm == SPAM_ERROR_NORM_MAX ? NORM_INFINITY : NORM_2;
  const SpamTSFamily *f;
  TSAdapt             adapt;
  NormType            have;
  PetscBool           given, none;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->steps == SPAM_TS_STEPS_OWN) PetscFunctionReturn(0); /* their vectors carry the norm */
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(PetscObjectTypeCompare((PetscObject)adapt, TSADAPTNONE, &none));
  /* PETSc 3.18 has no setter for the adaptor's norm type, only the option (which, without
   * an adaptor, the check of unused options refuses as such). */
  PetscCall(PetscOptionsHasName(NULL, NULL, "-ts_adapt_wnormtype", &given));
  given = (PetscBool)(given && !none);
  PetscCall(SpamTSAdaptNormType(ts, &have, NULL));
  if (given && have != want) SPAM_BAD_INPUT("-ts_adapt_wnormtype", NormTypes[have], "disagrees with -error_norm %s (NORM_2 is rms, INFINITY is max): give -error_norm alone, it sets the norm of every adaptive method", SpamErrorNormNames[norm]);
  PetscCall(SpamTSAdaptNormType(ts, NULL, &want));
  PetscFunctionReturn(0);
}
