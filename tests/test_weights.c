/* Error weights: positions against h, so a translation leaves every weight unchanged
 * bit for bit; velocities against max(|v|, c0). */
#include <spam/weights.h>
#include <nvector/nvector_petsc.h>
#include "test_util.h"

int main(int argc, char **argv)
{
  TestCount      c = {0, 0};
  const int      n = 200;
  SpamBox        b = {2, {0, 0, 0}, {20, 20, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  SpamSim        sim;
  SpamWeightsCtx w;
  SUNContext     sunctx;
  double         x[400], v[400];
  uint64_t       seed = 3;
  Vec            Y, W0, W1;
  N_Vector       y, w0, w1;
  PetscBool      same;
  const PetscScalar *a;

  PetscCall(TestInitialize(&argc, &argv));
  for (int i = 0; i < 2 * n; i++) {
    x[i] = 20.0 * TestUniform(&seed);
    v[i] = TestUniform(&seed) - 0.5;
  }
  PetscCall(TestMakeSim(&b, 3.0, 2.0, n, x, v, &sim));
  w.sim = &sim, w.rtol = 1e-6, w.atol = 1e-9, w.vscale = 0.3;
  PetscCall(SUNContext_Create(NULL, &sunctx));
  PetscCall(VecDuplicate(sim.p.X, &Y));
  PetscCall(VecDuplicate(sim.p.X, &W0));
  PetscCall(VecDuplicate(sim.p.X, &W1));
  y  = N_VMake_Petsc(Y, sunctx);
  w0 = N_VMake_Petsc(W0, sunctx);
  w1 = N_VMake_Petsc(W1, sunctx);
  PetscCall(VecCopy(sim.p.X, Y));
  TestCheck(&c, SpamErrorWeights(y, w0, &w) == 0, "weights evaluate");
  {
    PetscScalar *ya;
    PetscCall(VecGetArray(Y, &ya));
    for (int i = 0; i < n; i++) ya[4 * i] += 1000.0;
    PetscCall(VecRestoreArray(Y, &ya));
  }
  TestCheck(&c, SpamErrorWeights(y, w1, &w) == 0, "weights evaluate after a shift by 1000");
  PetscCall(VecEqual(W0, W1, &same));
  TestCheck(&c, same, "every weight is bitwise identical after the shift");
  PetscCall(VecGetArrayRead(W0, &a));
  const double speed = sqrt(v[0] * v[0] + v[1] * v[1]);
  TestCheck(&c, a[0] == 1.0 / (1e-6 * 3.0 + 1e-9) && a[2] == 1.0 / (1e-6 * PetscMax(speed, 0.3) + 1e-9), "position weight 1/(rtol h + atol) = %g, velocity weight 1/(rtol max(|v|, c0) + atol) = %g", a[0], a[2]);
  PetscCall(VecRestoreArrayRead(W0, &a));
  N_VDestroy(y);
  N_VDestroy(w0);
  N_VDestroy(w1);
  PetscCall(VecDestroy(&Y));
  PetscCall(VecDestroy(&W0));
  PetscCall(VecDestroy(&W1));
  PetscCall(SUNContext_Free(&sunctx));
  PetscCall(SpamSimDestroy(&sim));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
