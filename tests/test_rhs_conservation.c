/* The right-hand side conserves momentum to round-off, and the energy it implies is
 * constant: dE/dt = sum m v.a + sum m (de/drho) drho/dt = 0, with drho/dt from the
 * continuity sum m sum_j (v_i - v_j).grad_i w_ij evaluated here by brute force. */
#include <spam/sim.h>
#include "test_util.h"

static double DensityRateBruteForce(const SpamSim *sim, const double *y, int i)
{
  const SpamLayout *l = &sim->model.layout;
  const int         dim = sim->model.dim, nv = l->nvar;
  double            rate = 0.0;
  for (int j = 0; j < sim->p.n; j++) {
    double dx[3], r2 = 0.0, dv = 0.0;
    if (j == i) continue;
    for (int d = 0; d < dim; d++) {
      dx[d] = SpamBoxMinImage(SpamBoxLocal(&sim->geo.box, d, y[i * nv + d]) - SpamBoxLocal(&sim->geo.box, d, y[j * nv + d]), sim->geo.box.len[d], 0.5 * sim->geo.box.len[d], sim->geo.box.periodic[d]);
      r2 += dx[d] * dx[d];
    }
    const double g = SpamKernelDWOverR(&sim->model.kernel, r2);
    for (int d = 0; d < dim; d++) dv += (y[i * nv + l->v + d] - y[j * nv + l->v + d]) * g * dx[d];
    rate += sim->model.mass * dv;
  }
  return rate;
}

static PetscErrorCode Case(TestCount *c, int dim, double gamma, PetscBool periodic, uint64_t seed)
{
  const int    n = dim == 1 ? 60 : dim == 2 ? 400 : 500;
  const double h = dim == 1 ? 4.0 : 3.0, side = dim == 1 ? 60.0 : dim == 2 ? 20.0 : 8.0;
  SpamBox      b = {dim, {-1, 2, 3}, {0, 0, 0}, {periodic, periodic, periodic}};
  SpamSim      sim;
  double      *x, *v, *ydot, p[3] = {0, 0, 0}, pabs = 0.0, power = 0.0, work = 0.0, scale = 0.0;
  PetscInt     bad;
  const PetscScalar *y;

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) b.len[d] = side;
  PetscCall(PetscMalloc2((size_t)n * dim, &x, (size_t)n * dim, &v));
  for (int i = 0; i < n * dim; i++) {
    x[i] = b.lo[i % dim] + side * TestUniform(&seed);
    v[i] = TestUniform(&seed) - 0.5;
  }
  PetscCall(TestMakeSim(&b, h, gamma, n, x, v, &sim));
  PetscCall(PetscMalloc1((size_t)n * 2 * dim, &ydot));
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  PetscCall(SpamDensitySummation(&sim, y, &bad));
  PetscCall(SpamRhs(&sim, y, ydot, &bad));
  if (sim.model.density_free) PetscCall(SpamDensitySummation(&sim, y, &bad));
  for (int i = 0; i < n; i++) {
    const double dedrho = sim.model.eos.kappa * pow(sim.pair.f.rho[i], gamma - 2.0); /* P/rho^2 */
    const double rate   = dedrho * DensityRateBruteForce(&sim, y, i);
    for (int d = 0; d < dim; d++) {
      const double a = ydot[i * 2 * dim + dim + d];
      p[d] += sim.model.mass * a;
      pabs += sim.model.mass * fabs(a);
      power += sim.model.mass * y[i * 2 * dim + dim + d] * a;
      scale += sim.model.mass * fabs(y[i * 2 * dim + dim + d] * a);
    }
    work += sim.model.mass * rate;
    scale += sim.model.mass * fabs(rate);
  }
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  const double pnorm = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  TestCheck(c, pnorm < 1e-13 * pabs, "D=%d gamma=%g %s: |sum m a| / sum m|a| = %.2e (< 1e-13)", dim, gamma, periodic ? "periodic" : "open", pnorm / pabs);
  TestCheck(c, fabs(power + work) < 1e-12 * scale, "D=%d gamma=%g %s: dE/dt = %.2e relative to its terms (< 1e-12)", dim, gamma, periodic ? "periodic" : "open", fabs(power + work) / scale);
  PetscCall(PetscFree(ydot));
  PetscCall(PetscFree2(x, v));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};
  PetscCall(TestInitialize(&argc, &argv));
  for (int dim = 1; dim <= 3; dim++) {
    for (int per = 0; per < 2; per++) {
      PetscCall(Case(&c, dim, 1.0 + 2.0 / dim, (PetscBool)per, 7 + dim + 10 * per)); /* the ideal-gas isentrope */
      PetscCall(Case(&c, dim, 2.0, (PetscBool)per, 70 + dim + 10 * per));            /* density-free force pass */
      PetscCall(Case(&c, dim, 1.4, (PetscBool)per, 700 + dim + 10 * per));           /* a general exponent    */
    }
  }
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
