/* Closest-approach reflection on random pairs: momentum and kinetic energy are unchanged
 * to round-off, every reflected pair closer than dmin is receding afterwards, and a second
 * pass reflects nothing when no pair has two close partners. */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

int main(int argc, char **argv)
{
  TestCount       c = {0, 0};
  SpamSolidParams sp;
  SpamParticles   p;
  SpamModel       m;
  SpamSim         sim;
  uint64_t        seed = 3;
  PetscScalar    *y;
  PetscInt        n1, n2;
  double          p0[2] = {0, 0}, p1[2] = {0, 0}, k0 = 0, k1 = 0;

  PetscCall(TestInitialize(&argc, &argv));
  SpamSolidDefaults(&sp);
  PetscCall(SpamParticlesAllocate(2, 100, &p));
  PetscCall(SpamParticlesAllocateFields(&p));
  for (PetscInt i = 0; i < 50; i++) { /* 50 well separated pairs at distance 0.3 */
    const double cx = 4.0 * (double)(i % 10), cy = 4.0 * (double)(i / 10), a = 6.3 * TestUniform(&seed);
    p.x[4 * i] = cx, p.x[4 * i + 1] = cy;
    p.x[4 * i + 2] = cx + 0.3 * cos(a), p.x[4 * i + 3] = cy + 0.3 * sin(a);
    for (int k = 0; k < 4; k++) p.v[4 * i + k] = TestUniform(&seed) - 0.5;
  }
  for (PetscInt i = 0; i < p.n; i++) p.rho[i] = sp.rho0;
  p.mass = 1.0;
  SpamParticlesOpenBox(&p, 4.0);
  PetscCall(SpamTestModelSolid(2, 3.0, &sp, &m));
  PetscCall(SpamKernelLucyInit(2, 1.0, &m.kernel)); /* neighbour range 1: only the pairs meet */
  PetscCall(SpamSimCreate(PETSC_COMM_WORLD, &m, &p.box, p.n, 0.1, &sim));
  PetscCall(SpamSimFill(&sim, p.x, p.v, NULL));
  PetscCall(SpamSimFillFields(&sim, &p));
  PetscCall(SpamSimSetUp(&sim));
  PetscCall(VecGetArray(sim.p.X, &y));
  for (PetscInt i = 0; i < p.n; i++)
    for (int d = 0; d < 2; d++) p0[d] += y[i * sim.model.layout.nvar + sim.model.layout.v + d], k0 += 0.5 * PetscSqr(y[i * sim.model.layout.nvar + sim.model.layout.v + d]);
  PetscCall(SpamClosestApproachReflect(&sim, y, 0.5, &n1));
  for (PetscInt i = 0; i < p.n; i++)
    for (int d = 0; d < 2; d++) p1[d] += y[i * sim.model.layout.nvar + sim.model.layout.v + d], k1 += 0.5 * PetscSqr(y[i * sim.model.layout.nvar + sim.model.layout.v + d]);
  TestCheck(&c, n1 > 10 && n1 < 40, "%d of 50 random pairs were approaching and reflected", (int)n1);
  TestCheck(&c, fabs(p1[0] - p0[0]) + fabs(p1[1] - p0[1]) < 1e-13, "momentum kept: (%.2e, %.2e)", p1[0] - p0[0], p1[1] - p0[1]);
  TestCheck(&c, fabs(k1 - k0) < 1e-13 * k0, "kinetic energy kept: %.2e of %.4f", k1 - k0, k0);
  PetscCall(SpamClosestApproachReflect(&sim, y, 0.5, &n2));
  TestCheck(&c, n2 == 0, "a second pass finds no approaching pair (%d)", (int)n2);
  PetscCall(SpamClosestApproachReflect(&sim, y, 0.2, &n2));
  TestCheck(&c, n2 == 0, "pairs beyond dmin are untouched (%d)", (int)n2);
  PetscCall(VecRestoreArray(sim.p.X, &y));
  PetscCall(SpamParticlesFree(&p));
  PetscCall(SpamSimDestroy(&sim));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
