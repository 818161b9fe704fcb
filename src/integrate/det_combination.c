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
 * Speed: the nonzero terms are taken four at a time in one pass, a = a + c0 x0 + c1 x1 +
 * c2 x2 + c3 x3, which C evaluates left to right: the same operations in the same order
 * as adding one term after the other, so the grouping changes nothing in the result, and
 * a vector is read once. The passes run over blocks of BLOCK entries held in an L1-sized
 * buffer, so that z may be one of the terms. No contraction of a + c x into an FMA
 * (-ffp-contract=off, CMakeLists.txt), so vectorised loops and scalar remainders agree bit
 * for bit whatever -march. */
#include <spam/integrator.h>
#include <nvector/nvector_petsc.h>
#include "ts_vec_ops.h"

#define BLOCK   512 /* 4 KiB of doubles: stays in L1 with the vectors' streams */
#define MAX_VEC 32  /* ERKStep's largest: 13 stages + y_n; PETSc's rk: 13 stages */

/* a = [a +] c[0] x[0] + ... + c[k-1] x[k-1] over entries lo..lo+n-1 of the x, added left
 * to right (k = 1 to 4); init: a is not read. */
static void AddGroup(PetscInt n, double *restrict a, int k, const double *c, const double *const *x, PetscInt lo, PetscBool init)
{
  const double *restrict x0 = x[0] + lo, *restrict x1 = x[k > 1] + lo, *restrict x2 = x[2 * (k > 2)] + lo, *restrict x3 = x[3 * (k > 3)] + lo;
  const double           c0 = c[0], c1 = c[k > 1], c2 = c[2 * (k > 2)], c3 = c[3 * (k > 3)];

  switch (k + (init ? 4 : 0)) {
  case 1: for (PetscInt i = 0; i < n; i++) a[i] = a[i] + c0 * x0[i]; break;
  case 2: for (PetscInt i = 0; i < n; i++) a[i] = a[i] + c0 * x0[i] + c1 * x1[i]; break;
  case 3: for (PetscInt i = 0; i < n; i++) a[i] = a[i] + c0 * x0[i] + c1 * x1[i] + c2 * x2[i]; break;
  case 4: for (PetscInt i = 0; i < n; i++) a[i] = a[i] + c0 * x0[i] + c1 * x1[i] + c2 * x2[i] + c3 * x3[i]; break;
  case 5: for (PetscInt i = 0; i < n; i++) a[i] = c0 * x0[i]; break;
  case 6: for (PetscInt i = 0; i < n; i++) a[i] = c0 * x0[i] + c1 * x1[i]; break;
  case 7: for (PetscInt i = 0; i < n; i++) a[i] = c0 * x0[i] + c1 * x1[i] + c2 * x2[i]; break;
  default: for (PetscInt i = 0; i < n; i++) a[i] = c0 * x0[i] + c1 * x1[i] + c2 * x2[i] + c3 * x3[i]; break;
  }
}

/* z = [z +] sum_j c_j x_j, entry by entry in index order, zero c_j skipped. The result of
 * a block is written only after all its terms are read, so z may be one of the x_j. */
static void Combine(PetscInt n, int nvec, const double *c, const double *const *x, PetscBool accumulate, double *z)
{
  double        a[BLOCK], cs[MAX_VEC];
  const double *xs[MAX_VEC];
  int           k = 0;

  for (int j = 0; j < nvec; j++)
    if (c[j] != 0.0) cs[k] = c[j], xs[k++] = x[j];
  for (PetscInt lo = 0; lo < n; lo += BLOCK) {
    const PetscInt len  = PetscMin(BLOCK, n - lo);
    PetscBool      init = (PetscBool)!accumulate;
    if (accumulate)
      for (PetscInt i = 0; i < len; i++) a[i] = z[lo + i];
    else if (k == 0)
      for (PetscInt i = 0; i < len; i++) a[i] = 0.0;
    for (int g = 0; g < k; g += 4) {
      AddGroup(len, a, PetscMin(4, k - g), cs + g, xs + g, lo, init);
      init = PETSC_FALSE;
    }
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

/* rk's vectors: maxpy replaced on the state vector and its duplicates (ts_vec_ops.c). */
PetscErrorCode SpamVecDeterministicMAXPY(Vec X)
{
  static const SpamVecOps ops = {.maxpy = MAXPYDet};

  PetscFunctionBeginUser;
  PetscCall(SpamVecReplaceOps(X, &ops));
  PetscFunctionReturn(0);
}
