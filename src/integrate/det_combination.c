/* Linear combinations whose result does not depend on how many vectors they have.
 *
 * Why: an FSAL table (Dormand-Prince) forms its last stage Y_s = y_n + h sum_j A[s][j] k_j
 * and the new solution y_n+1 = y_n + h sum_j b_j k_j with the same coefficients (A[s] = b,
 * the last b is 0), and reuses f(Y_s) as the first stage of the next step. ERKStep and
 * PETSc's rk form both with one fused call of a different length (ERKStep: 7 and 8
 * vectors; rk: 6 and 7), and PETSc's VecMAXPY groups vectors in fours, so Y_s and
 * y_n+1 differ in the last bits. A restarted run computes f(y_n+1) where the continuing
 * run reuses f(Y_s): the runs part. Here a zero coefficient is skipped and the terms are
 * added one after the other in index order, so Y_s and y_n+1 are the same bits.
 *
 * Speed: the terms are added over blocks of BLOCK entries held in an L1-sized buffer, one
 * vector at a time, so each inner loop is a plain a[i] += c x[i] that gcc vectorises and
 * every vector is still read once. Each entry sees the same operations in the same order
 * whatever its block or position, and ISO C mode (-std=c11) keeps gcc from contracting
 * a + c x into an FMA, so vectorised and scalar remainders agree bit for bit. */
#include <petsc/private/vecimpl.h> /* X->ops->maxpy: PETSc 3.18 has no public VECOP_MAXPY */
#include <spam/integrator.h>
#include <nvector/nvector_petsc.h>

#define BLOCK   512 /* 4 KiB of doubles: stays in L1 with the vectors' streams */
#define MAX_VEC 32  /* ERKStep's largest: 13 stages + y_n; PETSc's rk: 13 stages */

static void ScaleInto(PetscInt n, double *restrict a, double c, const double *restrict x)
{
  for (PetscInt i = 0; i < n; i++) a[i] = c * x[i];
}

static void AddScaled(PetscInt n, double *restrict a, double c, const double *restrict x)
{
  for (PetscInt i = 0; i < n; i++) a[i] += c * x[i];
}

/* z = [z +] sum_j c_j x_j, entry by entry in index order, zero c_j skipped. The result of
 * a block is written only after all its terms are read, so z may be one of the x_j. */
static void Combine(PetscInt n, int nvec, const double *c, const double *const *x, PetscBool accumulate, double *z)
{
  double a[BLOCK];

  for (PetscInt lo = 0; lo < n; lo += BLOCK) {
    const PetscInt len   = PetscMin(BLOCK, n - lo);
    PetscBool      empty = PETSC_TRUE;
    if (accumulate) {
      for (PetscInt i = 0; i < len; i++) a[i] = z[lo + i];
      empty = PETSC_FALSE;
    }
    for (int j = 0; j < nvec; j++) {
      if (c[j] == 0.0) continue;
      if (empty) ScaleInto(len, a, c[j], x[j] + lo);
      else AddScaled(len, a, c[j], x[j] + lo);
      empty = PETSC_FALSE;
    }
    if (empty)
      for (PetscInt i = 0; i < len; i++) a[i] = 0.0;
    for (PetscInt i = 0; i < len; i++) z[lo + i] = a[i];
  }
}

/* N_VLinearCombination: z = sum_j c_j X_j (ERKStep's stages, solution and error). */
static PetscErrorCode LinearCombination(int nvec, const realtype *c, N_Vector *X, N_Vector z)
{
  Vec                zv = N_VGetVector_Petsc(z);
  const PetscScalar *x[MAX_VEC];
  PetscScalar       *za;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCheck(nvec >= 1 && nvec <= MAX_VEC, PETSC_COMM_SELF, PETSC_ERR_SUP, "linear combination of %d vectors (1 to %d supported)", nvec, MAX_VEC);
  PetscCall(VecGetLocalSize(zv, &n));
  PetscCall(VecGetArray(zv, &za));
  for (int j = 0; j < nvec; j++) {
    if (X[j] == z) x[j] = za; /* z among the terms: its own array, read before written */
    else PetscCall(VecGetArrayRead(N_VGetVector_Petsc(X[j]), &x[j]));
  }
  Combine(n, nvec, c, x, PETSC_FALSE, za);
  for (int j = 0; j < nvec; j++)
    if (X[j] != z) PetscCall(VecRestoreArrayRead(N_VGetVector_Petsc(X[j]), &x[j]));
  PetscCall(VecRestoreArray(zv, &za));
  PetscFunctionReturn(0);
}

static int NVLinearCombinationDet(int nvec, realtype *c, N_Vector *X, N_Vector z)
{
  return LinearCombination(nvec, c, X, z) ? -1 : 0;
}

PetscErrorCode SpamNVectorDeterministic(N_Vector y)
{
  PetscFunctionBeginUser;
  /* N_VCloneEmpty copies the ops table: ERKStep's stage and work vectors inherit it. */
  y->ops->nvlinearcombination = NVLinearCombinationDet;
  PetscFunctionReturn(0);
}

/* VecMAXPY: y = y + sum_j alpha_j x_j (rk's stages, solution and rollback). */
static PetscErrorCode MAXPYDet(Vec y, PetscInt nv, const PetscScalar *alpha, Vec *xv)
{
  const PetscScalar *x[MAX_VEC];
  PetscScalar       *ya;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCheck(nv <= MAX_VEC, PETSC_COMM_SELF, PETSC_ERR_SUP, "VecMAXPY of %" PetscInt_FMT " vectors (at most %d supported)", nv, MAX_VEC);
  PetscCall(VecGetLocalSize(y, &n));
  PetscCall(VecGetArray(y, &ya));
  for (PetscInt j = 0; j < nv; j++) {
    if (xv[j] == y) x[j] = ya;
    else PetscCall(VecGetArrayRead(xv[j], &x[j]));
  }
  Combine(n, (int)nv, alpha, x, PETSC_TRUE, ya);
  for (PetscInt j = 0; j < nv; j++)
    if (xv[j] != y) PetscCall(VecRestoreArrayRead(xv[j], &x[j]));
  PetscCall(VecRestoreArray(y, &ya));
  PetscFunctionReturn(0);
}

/* The duplicate of the vector type that a deterministic vector wraps. */
typedef struct {
  PetscErrorCode (*duplicate)(Vec, Vec *);
} DuplicateOf;

static PetscErrorCode FreeDuplicateOf(void *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(p));
  PetscFunctionReturn(0);
}

/* VecDuplicate_Seq (unlike VecDuplicate_MPI) does not copy the ops table, so the TS's work
 * vectors of a one-rank run would lose the deterministic maxpy: duplicates are made
 * deterministic here. (A composition also made by SpamVecCacheSubVectors chains: each
 * wrapper calls the duplicate it found.) */
static PetscErrorCode DuplicateDet(Vec X, Vec *Y)
{
  PetscContainer c;
  DuplicateOf   *d;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)X, "spam_det_duplicate", (PetscObject *)&c));
  PetscCheck(c, PetscObjectComm((PetscObject)X), PETSC_ERR_PLIB, "deterministic vector lost its duplicate");
  PetscCall(PetscContainerGetPointer(c, (void **)&d));
  PetscCall(d->duplicate(X, Y));
  PetscCall(SpamVecDeterministicMAXPY(*Y));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamVecDeterministicMAXPY(Vec X)
{
  PetscContainer c;
  DuplicateOf   *d;

  PetscFunctionBeginUser;
  /* Done already, or an MPI duplicate, which copies the ops and the composed objects. */
  if (X->ops->maxpy == MAXPYDet) PetscFunctionReturn(0);
  PetscCall(PetscNew(&d));
  d->duplicate = X->ops->duplicate;
  PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)X), &c));
  PetscCall(PetscContainerSetPointer(c, d));
  PetscCall(PetscContainerSetUserDestroy(c, FreeDuplicateOf));
  PetscCall(PetscObjectCompose((PetscObject)X, "spam_det_duplicate", (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  X->ops->maxpy     = MAXPYDet;
  X->ops->duplicate = DuplicateDet;
  PetscFunctionReturn(0);
}
