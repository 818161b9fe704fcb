/* VecGetSubVector without a new VecScatter per call. PETSc's basicsymplectic takes the
 * position and velocity parts of its solution and update vectors four times a step;
 * on the packed state [x v] those index sets are not contiguous, so the default
 * implementation creates (and destroys) a sub-vector and a VecScatter every time: 800
 * SFSetUp calls in 200 Verlet steps, a third of the step time at N = 16384. Here the
 * sub-vector and its scatter are made once per (vector, index set), composed on the
 * vector, and reused. */
#include <spam/integrator.h>
#include "ts_vec_ops.h"

#define SPAM_SUBVEC_SCATTER "spam_subvector_scatter"

static PetscErrorCode CacheName(IS is, char *name, size_t len)
{
  PetscObjectId id;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetId((PetscObject)is, &id));
  PetscCall(PetscSNPrintf(name, len, "spam_subvector_%" PetscInt64_FMT, (PetscInt64)id));
  PetscFunctionReturn(0);
}

/* The cached sub-vector of X for is (made on first use) and its scatter. */
static PetscErrorCode Cached(Vec X, IS is, Vec *Z, VecScatter *sc)
{
  char name[64];

  PetscFunctionBeginUser;
  PetscCall(CacheName(is, name, sizeof name));
  PetscCall(PetscObjectQuery((PetscObject)X, name, (PetscObject *)Z));
  if (!*Z) {
    Vec        sub;
    VecScatter s;
    PetscInt   n, bs;
    PetscCall(ISGetLocalSize(is, &n));
    PetscCall(ISGetBlockSize(is, &bs));
    PetscCall(VecCreate(PetscObjectComm((PetscObject)X), &sub));
    PetscCall(VecSetSizes(sub, n, PETSC_DECIDE));
    PetscCall(VecSetBlockSize(sub, bs));
    PetscCall(VecSetType(sub, VECSTANDARD));
    PetscCall(VecScatterCreate(X, is, sub, NULL, &s));
    PetscCall(PetscObjectCompose((PetscObject)sub, SPAM_SUBVEC_SCATTER, (PetscObject)s));
    PetscCall(VecScatterDestroy(&s));
    PetscCall(PetscObjectCompose((PetscObject)X, name, (PetscObject)sub));
    PetscCall(VecDestroy(&sub)); /* X's composition holds it */
    PetscCall(PetscObjectQuery((PetscObject)X, name, (PetscObject *)Z));
  }
  PetscCall(PetscObjectQuery((PetscObject)*Z, SPAM_SUBVEC_SCATTER, (PetscObject *)sc));
  PetscFunctionReturn(0);
}

static PetscErrorCode GetSubVectorCached(Vec X, IS is, Vec *Y)
{
  VecScatter sc;

  PetscFunctionBeginUser;
  PetscCall(Cached(X, is, Y, &sc));
  PetscCall(VecScatterBegin(sc, X, *Y, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, X, *Y, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

/* Always copies the part back: a copy of the sub-vector costs less than tracking its
 * state, and X's part is changed only through the sub-vector while it is out (the way
 * basicsymplectic uses it). */
static PetscErrorCode RestoreSubVectorCached(Vec X, IS is, Vec *Y)
{
  Vec        Z;
  VecScatter sc;

  PetscFunctionBeginUser;
  PetscCall(Cached(X, is, &Z, &sc));
  PetscCheck(Z == *Y, PetscObjectComm((PetscObject)X), PETSC_ERR_ARG_WRONG, "restoring a sub-vector that was not taken from this vector and index set");
  PetscCall(VecScatterBegin(sc, Z, X, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(sc, Z, X, INSERT_VALUES, SCATTER_REVERSE));
  *Y = NULL;
  PetscFunctionReturn(0);
}

/* basicsymplectic's vectors: the state vector and its duplicates (the TS's update
 * vector), through ts_vec_ops.c. */
PetscErrorCode SpamVecCacheSubVectors(Vec X)
{
  static const SpamVecOps ops = {.getsubvector = GetSubVectorCached, .restoresubvector = RestoreSubVectorCached};

  PetscFunctionBeginUser;
  PetscCall(SpamVecReplaceOps(X, &ops));
  PetscFunctionReturn(0);
}
