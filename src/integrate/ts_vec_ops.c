/* Vec operations replaced for a TS implementation: rk's maxpy summed in index order
 * (det_combination.c) and basicsymplectic's cached sub-vectors (subvector_cached.c).
 * PETSc 3.18 names only duplicate, view and load among the VecOperation values of
 * VecSetOperation, so maxpy and getsubvector can be set only through the private table;
 * this is the one file outside the TS types' own implementations that includes a PETSc
 * private header for it. The replacing functions themselves use the public API. */
#include <petsc/private/vecimpl.h>
#include "ts_vec_ops.h"

#define SPAM_VEC_OPS "spam_vec_ops"

/* The vector type's own duplicate and what replaces its operations. */
typedef struct {
  PetscErrorCode (*duplicate)(Vec, Vec *);
  const SpamVecOps *ops;
} Replaced;

static PetscErrorCode FreeReplaced(void *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(p));
  PetscFunctionReturn(0);
}

/* VecDuplicate_Seq (unlike VecDuplicate_MPI) does not copy the ops table, so the TS's work
 * vectors of a one-rank run would lose the replaced operations: duplicates get them here. */
static PetscErrorCode DuplicateReplaced(Vec X, Vec *Y)
{
  PetscContainer c;
  Replaced      *r;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)X, SPAM_VEC_OPS, (PetscObject *)&c));
  PetscCheck(c, PetscObjectComm((PetscObject)X), PETSC_ERR_PLIB, "vector lost its own duplicate");
  PetscCall(PetscContainerGetPointer(c, (void **)&r));
  PetscCall(r->duplicate(X, Y));
  PetscCall(SpamVecReplaceOps(*Y, r->ops));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamVecReplaceOps(Vec X, const SpamVecOps *ops)
{
  PetscContainer c;
  Replaced      *r;

  PetscFunctionBeginUser;
  /* Done already, or an MPI duplicate, which copies the ops and the composed objects. */
  if (X->ops->duplicate == DuplicateReplaced) {
    PetscCall(PetscObjectQuery((PetscObject)X, SPAM_VEC_OPS, (PetscObject *)&c));
    PetscCheck(c, PetscObjectComm((PetscObject)X), PETSC_ERR_PLIB, "vector lost its own duplicate");
    PetscCall(PetscContainerGetPointer(c, (void **)&r));
    PetscCheck(r->ops == ops, PetscObjectComm((PetscObject)X), PETSC_ERR_PLIB, "a vector's operations replaced twice, for two TS types");
    PetscFunctionReturn(0);
  }
  PetscCall(PetscNew(&r));
  r->duplicate = X->ops->duplicate;
  r->ops       = ops;
  PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)X), &c));
  PetscCall(PetscContainerSetPointer(c, r));
  PetscCall(PetscContainerSetUserDestroy(c, FreeReplaced));
  PetscCall(PetscObjectCompose((PetscObject)X, SPAM_VEC_OPS, (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  X->ops->duplicate = DuplicateReplaced;
  if (ops->maxpy) X->ops->maxpy = ops->maxpy;
  if (ops->getsubvector) X->ops->getsubvector = ops->getsubvector;
  if (ops->restoresubvector) X->ops->restoresubvector = ops->restoresubvector;
  PetscFunctionReturn(0);
}
