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
#include <petsc/private/petscimpl.h> /* PetscObjectStateGet */
#include <spam/integrator.h>
#include <nvector/nvector_petsc.h>
#include "ts_vec_ops.h"

#define BLOCK    512 /* 4 KiB of doubles: stays in L1 with the vectors' streams */
#define MAX_VEC  32  /* ERKStep's largest: 13 stages + y_n; PETSc's rk: 13 stages */
#define MEMO_KEY "SpamCombinationMemo"

/* The last combination written into the solution vector, while ERKStep alone writes it
 * (armed: inside one ERKStepEvolve, see SpamNVectorCombinationArm). An FSAL table's last
 * stage Y_s and the solution y_n+1 are the same combination (above), both written into
 * ERKStep's ycur, which is the solution vector, with one right-hand side between them that
 * only reads ycur and writes the stage derivative whose coefficient is zero. So the
 * second is already there: a pass reading s vectors and writing one, at N = 65536 in 2D
 * a sixth of the integrator's cache misses, skipped. The memo holds the terms (nonzero
 * coefficients, vectors) and the PETSc object states of the vectors and of the result
 * after it was written: any write through the Vec interface since (VecRestoreArray and
 * the like raise the state) makes it miss. */
typedef struct {
  PetscBool        armed;
  Vec              z; /* where the last combination went (NULL: none recorded) */
  int              k;
  double           c[MAX_VEC];
  Vec              x[MAX_VEC];
  PetscObjectState xs[MAX_VEC], zs;
} CombinationMemo;

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

/* The armed memo composed on z (NULL: none, or not armed). */
static PetscErrorCode MemoOf(Vec z, CombinationMemo **m)
{
  PetscContainer c = NULL;

  PetscFunctionBeginUser;
  *m = NULL;
  PetscCall(PetscObjectQuery((PetscObject)z, MEMO_KEY, (PetscObject *)&c));
  if (c) PetscCall(PetscContainerGetPointer(c, (void **)m));
  if (*m && !(*m)->armed) *m = NULL;
  PetscFunctionReturn(0);
}

/* The nonzero terms of a combination into m's c and x (m->k of them) with their states. */
static PetscErrorCode MemoTerms(int nvec, const realtype *c, N_Vector *X, CombinationMemo *m)
{
  PetscFunctionBeginUser;
  m->k = 0;
  for (int j = 0; j < nvec; j++)
    if (c[j] != 0.0) {
      m->c[m->k] = c[j];
      m->x[m->k] = N_VGetVector_Petsc(X[j]);
      PetscCall(PetscObjectStateGet((PetscObject)m->x[m->k], &m->xs[m->k]));
      m->k++;
    }
  PetscFunctionReturn(0);
}

/* Whether z holds sum_j c_j X_j already: the memo's last combination, same terms, the
 * same states of every vector. */
static PetscErrorCode MemoHolds(const CombinationMemo *m, int nvec, const realtype *c, N_Vector *X, Vec z, PetscBool *holds)
{
  CombinationMemo  now;
  PetscObjectState zs;

  PetscFunctionBeginUser;
  *holds = PETSC_FALSE;
  if (m->z != z) PetscFunctionReturn(0);
  PetscCall(PetscObjectStateGet((PetscObject)z, &zs));
  if (zs != m->zs) PetscFunctionReturn(0);
  PetscCall(MemoTerms(nvec, c, X, &now));
  if (now.k != m->k) PetscFunctionReturn(0);
  for (int j = 0; j < m->k; j++)
    if (now.c[j] != m->c[j] || now.x[j] != m->x[j] || now.xs[j] != m->xs[j]) PetscFunctionReturn(0);
  *holds = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* After z = sum_j c_j X_j was written: its terms, unless z is one of them (then z's new
 * values are not the combination of its own). */
static PetscErrorCode MemoRecord(CombinationMemo *m, int nvec, const realtype *c, N_Vector *X, Vec z)
{
  PetscFunctionBeginUser;
  m->z = NULL;
  PetscCall(MemoTerms(nvec, c, X, m));
  for (int j = 0; j < m->k; j++)
    if (m->x[j] == z) PetscFunctionReturn(0);
  PetscCall(PetscObjectStateGet((PetscObject)z, &m->zs));
  m->z = z;
  PetscFunctionReturn(0);
}

/* N_VLinearCombination: z = sum_j c_j X_j (ERKStep's stages, solution and error). */
static PetscErrorCode LinearCombination(int nvec, const realtype *c, N_Vector *X, N_Vector z)
{
  Vec                zv = N_VGetVector_Petsc(z);
  const PetscScalar *x[MAX_VEC];
  PetscScalar       *za;
  PetscInt           n;
  CombinationMemo   *memo;

  PetscFunctionBeginUser;
  PetscCheck(nvec >= 1 && nvec <= MAX_VEC, PETSC_COMM_SELF, PETSC_ERR_SUP, "linear combination of %d vectors (1 to %d supported)", nvec, MAX_VEC);
  PetscCall(MemoOf(zv, &memo));
  if (memo) {
    PetscBool holds;
    PetscCall(MemoHolds(memo, nvec, c, X, zv, &holds));
    if (holds) PetscFunctionReturn(0);
  }
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
  if (memo) PetscCall(MemoRecord(memo, nvec, c, X, zv));
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

PetscErrorCode SpamNVectorCombinationArm(N_Vector y, PetscBool armed)
{
  Vec             yv = N_VGetVector_Petsc(y);
  PetscContainer  c  = NULL;
  CombinationMemo *m = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)yv, MEMO_KEY, (PetscObject *)&c));
  if (!c) {
    PetscCall(PetscNew(&m));
    PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &c));
    PetscCall(PetscContainerSetPointer(c, m));
    PetscCall(PetscContainerSetUserDestroy(c, PetscContainerUserDestroyDefault));
    PetscCall(PetscObjectCompose((PetscObject)yv, MEMO_KEY, (PetscObject)c));
    PetscCall(PetscContainerDestroy(&c)); /* the Vec holds it */
  } else PetscCall(PetscContainerGetPointer(c, (void **)&m));
  m->armed = armed;
  m->z     = NULL;
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
