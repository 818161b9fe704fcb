/* Cost of spam-ark's deterministic linear combinations (src/integrate/det_combination.c)
 * against their peers measured in the same run on the same vectors: N_Vector_Petsc's fused
 * N_VLinearCombination (one VecMAXPY) as ERKStep calls it for Dormand-Prince's solution
 * (7 nonzero of 8 terms), and PETSc's VecMAXPY as rk 5dp calls it (6 of 7 terms).
 *   ./build/bench/bench_combination [-n entries] [-reps R]
 * Default n = 65536: the state of a 2-D run of 16384 particles (x, v). Each timing is the
 * median of R rounds of 20 calls, the two candidates alternating within a round. */
#include <spam/integrator.h>
#include <nvector/nvector_petsc.h>
#include <petsctime.h>

#define NTERM 8

static int CompareDouble(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Median seconds per call of N_VLinearCombination into z (whose ops decide the kernel). */
static double TimeNV(N_Vector *X, N_Vector z, const realtype *c, int nvec, PetscLogDouble *t)
{
  PetscLogDouble t0, t1;
  PetscTime(&t0);
  for (int k = 0; k < 20; k++) N_VLinearCombination(nvec, (realtype *)c, X, z);
  PetscTime(&t1);
  *t = (t1 - t0) / 20;
  return *t;
}

static double TimeMAXPY(Vec y, Vec *X, const PetscScalar *a, PetscInt nv, PetscLogDouble *t)
{
  PetscLogDouble t0, t1;
  PetscTime(&t0);
  for (int k = 0; k < 20; k++) {
    if (VecMAXPY(y, nv, a, X)) return -1;
    if (VecScale(y, 0.5)) return -1; /* keep the values bounded */
  }
  PetscTime(&t1);
  *t = (t1 - t0) / 20;
  return *t;
}

int main(int argc, char **argv)
{
  PetscInt       n = 65536, reps = 41;
  SUNContext     sctx;
  Vec            V[NTERM], Zp, Zd, Yp, Yd;
  N_Vector       X[NTERM], zp, zd;
  realtype       c[NTERM]     = {0.091, 0, 0.449, 0.651, -0.322, 0.131, 0, 1.0}; /* DP5 b (h = 1) and y_n */
  PetscScalar    a[NTERM - 1] = {0.091, 0, 0.449, 0.651, -0.322, 0.131, 0};
  double        *tn[2], *tm[2];
  PetscLogDouble t;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-n", &n, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-reps", &reps, NULL));
  PetscCall(SUNContext_Create(NULL, &sctx));
  for (int j = 0; j < NTERM; j++) {
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, n, &V[j]));
    PetscCall(VecSetRandom(V[j], NULL));
    X[j] = N_VMake_Petsc(V[j], sctx);
  }
  PetscCall(VecDuplicate(V[0], &Zp));
  PetscCall(VecDuplicate(V[0], &Zd));
  PetscCall(VecDuplicate(V[0], &Yp));
  PetscCall(VecDuplicate(V[0], &Yd));
  PetscCall(VecSet(Yp, 1.0));
  PetscCall(VecSet(Yd, 1.0));
  PetscCall(SpamVecDeterministicMAXPY(Yd));
  zp = N_VMake_Petsc(Zp, sctx);
  zd = N_VMake_Petsc(Zd, sctx);
  PetscCheck(N_VEnableFusedOps_Petsc(zp, SUNTRUE) == 0 && N_VEnableFusedOps_Petsc(zd, SUNTRUE) == 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "fused ops");
  PetscCall(SpamNVectorDeterministic(zd));
  for (int k = 0; k < 2; k++) PetscCall(PetscMalloc2(reps, &tn[k], reps, &tm[k]));
  for (PetscInt r = 0; r < reps; r++) {
    tn[0][r] = TimeNV(X, zp, c, NTERM, &t);
    tn[1][r] = TimeNV(X, zd, c, NTERM, &t);
    tm[0][r] = TimeMAXPY(Yp, V, a, NTERM - 1, &t);
    tm[1][r] = TimeMAXPY(Yd, V, a, NTERM - 1, &t);
  }
  for (int k = 0; k < 2; k++) {
    qsort(tn[k], (size_t)reps, sizeof(double), CompareDouble);
    qsort(tm[k], (size_t)reps, sizeof(double), CompareDouble);
  }
  {
    const double mn0 = tn[0][reps / 2], mn1 = tn[1][reps / 2], mm0 = tm[0][reps / 2], mm1 = tm[1][reps / 2];
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "n = %" PetscInt_FMT ", median of %" PetscInt_FMT " rounds\n", n, reps));
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "N_VLinearCombination 8 terms: PETSc fused %.1f us, deterministic %.1f us, ratio det/fused %.2f\n", 1e6 * mn0, 1e6 * mn1, mn1 / mn0));
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "VecMAXPY 7 terms (+ VecScale): PETSc %.1f us, deterministic %.1f us, ratio det/PETSc %.2f\n", 1e6 * mm0, 1e6 * mm1, mm1 / mm0));
  }
  for (int k = 0; k < 2; k++) PetscCall(PetscFree2(tn[k], tm[k]));
  for (int j = 0; j < NTERM; j++) {
    N_VDestroy(X[j]);
    PetscCall(VecDestroy(&V[j]));
  }
  N_VDestroy(zp);
  N_VDestroy(zd);
  PetscCall(VecDestroy(&Zp));
  PetscCall(VecDestroy(&Zd));
  PetscCall(VecDestroy(&Yp));
  PetscCall(VecDestroy(&Yd));
  PetscCall(SUNContext_Free(&sctx));
  PetscCall(PetscFinalize());
  return 0;
}
