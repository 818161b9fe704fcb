/* The Vec operations that a TS implementation replaces on its state vector, and the one
 * place that writes them into PETSc's private operations table (ts_vec_ops.c). */
#ifndef SPAM_TS_VEC_OPS_H
#define SPAM_TS_VEC_OPS_H
#include <petscvec.h>

/* The operations to replace; NULL keeps the vector type's own. Kept by pointer: static
 * storage. */
typedef struct {
  PetscErrorCode (*maxpy)(Vec y, PetscInt n, const PetscScalar *alpha, Vec *x);
  PetscErrorCode (*getsubvector)(Vec X, IS is, Vec *Y);
  PetscErrorCode (*restoresubvector)(Vec X, IS is, Vec *Y);
} SpamVecOps;

/* Replaces ops on X and on every vector duplicated from it later (the TS's stage and work
 * vectors). Again with the same ops: nothing; with other ops: an error (no TS type needs
 * two sets). */
PetscErrorCode SpamVecReplaceOps(Vec X, const SpamVecOps *ops);
#endif
