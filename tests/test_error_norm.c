/* -error_norm max as the WRMS-norm operation of a PETSc N_Vector (error_norm.c): for any
 * vector of L components, rms <= max <= sqrt(L) rms, with the bounds reached by a uniform
 * |x_i w_i| (equal) and by one nonzero component (max = sqrt(L) rms: an error at one
 * particle that the rms norm sees sqrt(L) times smaller). The operation must survive
 * SUNDIALS' cloning (the integrators' work vectors are clones) and its fused array form. */
#include <spam/error_norm.h>
#include <nvector/nvector_petsc.h>
#include <float.h>
#include "test_util.h"

#define L 4096 /* components: 1024 particles of a 2D gas (x, y, vx, vy) */

static PetscErrorCode Fill(N_Vector v, const double *a)
{
  PetscScalar *p;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayWrite(N_VGetVector_Petsc(v), &p));
  for (int i = 0; i < L; i++) p[i] = a[i];
  PetscCall(VecRestoreArrayWrite(N_VGetVector_Petsc(v), &p));
  PetscFunctionReturn(0);
}

static int Close(double a, double b) { return fabs(a - b) <= 8.0 * DBL_EPSILON * fabs(b); }

int main(int argc, char **argv)
{
  TestCount  c = {0, 0};
  SUNContext sunctx;
  Vec        X, W;
  N_Vector   x, w, xc;
  uint64_t   seed = 11;
  static double xa[L], wa[L];
  realtype   rms, max, nrm[2] = {-1.0, -1.0};
  N_Vector   xs[2], ws[2];

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(SUNContext_Create(NULL, &sunctx));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, L, &X));
  PetscCall(VecDuplicate(X, &W));
  x = N_VMake_Petsc(X, sunctx);
  w = N_VMake_Petsc(W, sunctx);
  TestCheck(&c, N_VEnableFusedOps_Petsc(x, SUNTRUE) == 0, "fused operations enabled, as the arkode and cvode TS types do");
  /* Weights as the integrators' 1/(rtol scale + atol): spread over three decades. */
  for (int i = 0; i < L; i++) wa[i] = pow(10.0, 3.0 * TestUniform(&seed));
  PetscCall(Fill(w, wa));

  PetscCall(SpamErrorNormAttach(x, SPAM_ERROR_NORM_RMS, PETSC_FALSE));
  TestCheck(&c, x->ops->nvwrmsnorm == N_VWrmsNorm_Petsc, "-error_norm rms keeps SUNDIALS' own WRMS norm");

  /* One component: e at i = 1234, in units of its weight. */
  for (int i = 0; i < L; i++) xa[i] = 0.0;
  xa[1234] = -2.5 / wa[1234];
  PetscCall(Fill(x, xa));
  rms = N_VWrmsNorm(x, w);
  PetscCall(SpamErrorNormAttach(x, SPAM_ERROR_NORM_MAX, PETSC_FALSE));
  max = N_VWrmsNorm(x, w);
  TestCheck(&c, Close(max, 2.5) && Close(rms * sqrt((double)L), max), "error at one component: max %.17g = 2.5, rms sqrt(L) %.17g = max (the rms norm sees it sqrt(%d) times smaller)", max, rms * sqrt((double)L), L);

  /* The same error spread evenly: |x_i w_i| = 2.5 with random signs. */
  for (int i = 0; i < L; i++) xa[i] = (TestUniform(&seed) < 0.5 ? -2.5 : 2.5) / wa[i];
  PetscCall(Fill(x, xa));
  max = N_VWrmsNorm(x, w);
  TestCheck(&c, Close(max, 2.5) && Close(N_VWrmsNorm_Petsc(x, w), 2.5), "uniform |x_i w_i| = 2.5: max %.17g and rms %.17g equal", max, N_VWrmsNorm_Petsc(x, w));

  /* Any vector: rms <= max <= sqrt(L) rms, and max is the largest |x_i w_i|. */
  {
    double big = 0.0;
    for (int i = 0; i < L; i++) {
      xa[i] = (TestUniform(&seed) - 0.5) / wa[i];
      big   = PetscMax(big, fabs(xa[i] * wa[i]));
    }
    PetscCall(Fill(x, xa));
    max = N_VWrmsNorm(x, w);
    rms = N_VWrmsNorm_Petsc(x, w);
    TestCheck(&c, max == big && rms <= max && max <= sqrt((double)L) * rms, "random vector: max %.6g = largest |x_i w_i| %.6g, rms %.6g <= max <= sqrt(L) rms", max, big, rms);

    /* The integrators' work vectors are clones of y: they must carry the max norm. */
    xc = N_VClone(x);
    PetscCall(VecCopy(X, N_VGetVector_Petsc(xc)));
    TestCheck(&c, N_VWrmsNorm(xc, w) == big, "a clone of the vector computes the max norm too (%.6g)", N_VWrmsNorm(xc, w));
    /* The fused array form (used by SUNDIALS packages on several vectors at once) must not
     * bypass it. */
    xs[0] = x, xs[1] = xc, ws[0] = w, ws[1] = w;
    {
      const int flag = N_VWrmsNormVectorArray(2, xs, ws, nrm); /* before the check reads nrm */
      TestCheck(&c, flag == 0 && nrm[0] == big && nrm[1] == big, "N_VWrmsNormVectorArray gives the max norm of each vector (%.6g, %.6g)", nrm[0], nrm[1]);
    }
    N_VDestroy(xc);
  }

  N_VDestroy(x);
  N_VDestroy(w);
  PetscCall(VecDestroy(&X));
  PetscCall(VecDestroy(&W));
  PetscCall(SUNContext_Free(&sunctx));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
