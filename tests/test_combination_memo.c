/* The integrator's shortcuts at a fixed step (det_combination.c, error_norm.c):
 * (a) the memo of the last combination: armed, a combination the solution vector already
 *     holds (same nonzero terms, no vector written since) is not computed again; a changed
 *     term, a write to a term or to the result through the Vec interface, a different
 *     coefficient, or a disarmed memo compute it; the sums are those of the plain loop;
 * (b) the norm of zero weights is 0 without a read of x, and the attached norm otherwise.
 * The check that the memo skipped: the result's array is changed behind PETSc's back (no
 * state raised), which a skipped combination leaves as it is. */
#include <spam/integrator.h>
#include <spam/error_norm.h>
#include <nvector/nvector_petsc.h>
#include "test_util.h"

#define N 37 /* not a multiple of the combination's blocks or vector widths */

static void Fill(Vec v, double a)
{
  PetscScalar *x;
  PetscCallAbort(PETSC_COMM_SELF, VecGetArray(v, &x));
  for (int i = 0; i < N; i++) x[i] = a + 0.37 * i - 1e-3 * i * i;
  PetscCallAbort(PETSC_COMM_SELF, VecRestoreArray(v, &x));
}

/* y's first entry written without the Vec interface (no state raised). */
static double Poke(Vec v, double value)
{
  PetscScalar *x;
  double       old;
  PetscCallAbort(PETSC_COMM_SELF, VecGetArrayRead(v, (const PetscScalar **)&x));
  old  = x[0];
  x[0] = value;
  PetscCallAbort(PETSC_COMM_SELF, VecRestoreArrayRead(v, (const PetscScalar **)&x));
  return old;
}

static double First(Vec v)
{
  const PetscScalar *x;
  double             a;
  PetscCallAbort(PETSC_COMM_SELF, VecGetArrayRead(v, &x));
  a = x[0];
  PetscCallAbort(PETSC_COMM_SELF, VecRestoreArrayRead(v, &x));
  return a;
}

/* c0 f0 + c1 f1 + 1 y0 at entry 0, summed as the deterministic combination sums. */
static double Expected(const double *c, Vec f0, Vec f1, Vec y0)
{
  return c[0] * First(f0) + c[1] * First(f1) + c[2] * First(y0);
}

int main(int argc, char **argv)
{
  TestCount  tc = {0, 0};
  SUNContext ctx;
  Vec        Y, F0, F1, Y0, W;
  N_Vector   y, f0, f1, y0, w, X[4];
  double     c[4] = {0.25, -0.125, 1.0, 0.0};
  const double mark = 1234.5;

  PetscCall(TestInitialize(&argc, &argv));
  PetscCallAbort(PETSC_COMM_SELF, SUNContext_Create(NULL, &ctx) ? PETSC_ERR_LIB : 0);
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, N, &Y));
  PetscCall(VecDuplicate(Y, &F0));
  PetscCall(VecDuplicate(Y, &F1));
  PetscCall(VecDuplicate(Y, &Y0));
  PetscCall(VecDuplicate(Y, &W));
  Fill(F0, 1.0);
  Fill(F1, -2.0);
  Fill(Y0, 0.5);
  y  = N_VMake_Petsc(Y, ctx);
  f0 = N_VMake_Petsc(F0, ctx);
  f1 = N_VMake_Petsc(F1, ctx);
  y0 = N_VMake_Petsc(Y0, ctx);
  w  = N_VMake_Petsc(W, ctx);
  PetscCall(SpamNVectorDeterministic(y));
  X[0] = f0, X[1] = f1, X[2] = y0, X[3] = y; /* the last term's coefficient is zero */

  /* (a) */
  PetscCall(SpamNVectorCombinationArm(y, PETSC_TRUE));
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == Expected(c, F0, F1, Y0), "armed: the first combination is computed, the sum of the plain loop");
  Poke(Y, mark);
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == mark, "armed: the same combination again is skipped (y holds it)");
  Fill(F1, 3.0); /* F1 written through the Vec interface */
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == Expected(c, F0, F1, Y0), "a term written since: computed again");
  Fill(Y, 7.0); /* the result written since */
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == Expected(c, F0, F1, Y0), "the result written since: computed again");
  Poke(Y, mark);
  c[1] = -0.25;
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == Expected(c, F0, F1, Y0), "another coefficient: computed");
  Poke(Y, mark);
  X[1] = y0, X[2] = f1;
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == c[0] * First(F0) + c[1] * First(Y0) + c[2] * First(F1), "other vectors: computed");
  X[1] = f1, X[2] = y0;
  c[3] = 0.5; /* y itself a term: its new values are not the combination of its own */
  (void)N_VLinearCombination(4, c, X, y);
  Poke(Y, mark);
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) != mark, "y among the terms: never skipped");
  c[3] = 0.0;
  (void)N_VLinearCombination(4, c, X, y);
  PetscCall(SpamNVectorCombinationArm(y, PETSC_FALSE));
  Poke(Y, mark);
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == Expected(c, F0, F1, Y0), "disarmed: computed");
  PetscCall(SpamNVectorCombinationArm(y, PETSC_TRUE));
  Poke(Y, mark);
  TestCheck(&tc, N_VLinearCombination(4, c, X, y) == 0 && First(Y) == Expected(c, F0, F1, Y0), "armed again: the memo starts empty");

  /* (b) */
  PetscCall(SpamErrorNormZeroWeights(y, SPAM_ERROR_NORM_RMS, PETSC_FALSE));
  PetscCall(VecSet(W, 0.0));
  Poke(Y, NAN); /* a norm that read x would be NaN */
  TestCheck(&tc, N_VWrmsNorm(y, w) == 0.0, "zero weights: norm 0, x not read");
  Fill(Y, 1.0);
  PetscCall(VecSet(W, 2.0));
  TestCheck(&tc, N_VWrmsNorm(y, w) == N_VWrmsNorm_Petsc(y, w), "nonzero weights: SUNDIALS' rms norm (%g)", (double)N_VWrmsNorm_Petsc(y, w));
  PetscCall(SpamErrorNormZeroWeights(y, SPAM_ERROR_NORM_RMS, PETSC_TRUE));
  TestCheck(&tc, N_VWrmsNorm(y, w) == SpamNVReproducibleWrmsNorm_Petsc(y, w), "nonzero weights, -reproducible: the reproducible norm");

  N_VDestroy(y);
  N_VDestroy(f0);
  N_VDestroy(f1);
  N_VDestroy(y0);
  N_VDestroy(w);
  PetscCall(VecDestroy(&Y));
  PetscCall(VecDestroy(&F0));
  PetscCall(VecDestroy(&F1));
  PetscCall(VecDestroy(&Y0));
  PetscCall(VecDestroy(&W));
  SUNContext_Free(&ctx);
  {
    const int rc = TestFinish(&tc);
    PetscCall(TestFinalize());
    return rc;
  }
}
