/* One neighbour-list update and one placement of the ghost slots' positions (the halo's
 * exchange of positions on several ranks) per right-hand side, on every path: the tensor
 * path (a Taylor-Green-like gas: periodic square lattice, summed density, gamma = 2,
 * Newtonian viscosity, as options/taylor-green.opts) and the isentropic gas (the
 * expansion's model), each with the periodic directions made by the minimum image and by
 * ghost images, and the gas also under -reproducible; on one rank and, under mpiexec,
 * with the particles distributed over the ranks (every rank then has ghost slots: the
 * halo). K evaluations of SpamRhs at moving positions (one of them far enough for a
 * rebuild) must add K to the list's update count and, where there are ghost slots, K to
 * its placement count, and the RHS's own counters (summary.json reports them) must say
 * the same: a pass that updates the list again (the summed density of the tensor path
 * did) or places the ghosts twice fails. */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

#define SIDE 24  /* lattice sites per direction, spacing 1 */
#define H    3.0 /* kernel range, as the scenes' -h 3     */
#define K    6   /* evaluations                           */

typedef struct {
  const char *name;
  PetscBool   tensor, ghosts, reproducible;
} Case;

/* The lattice, jittered by a tenth of the spacing so that no pair sits on a cell face. */
static void Lattice(double *x, uint64_t *seed)
{
  for (int i = 0; i < SIDE * SIDE; i++) {
    x[2 * i]     = (i % SIDE) + 0.5 + 0.1 * (TestUniform(seed) - 0.5);
    x[2 * i + 1] = (i / SIDE) + 0.5 + 0.1 * (TestUniform(seed) - 0.5);
  }
}

static PetscErrorCode MakeModel(const Case *c, SpamModel *m)
{
  SpamKernel k;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelCreate("lucy", 2, H, &k));
  if (c->tensor) {
    SpamSolidParams sp;
    SpamSolidDefaults(&sp);
    sp.material   = SPAM_MATERIAL_GAS;
    sp.density    = SPAM_DENSITY_SUMMATION;
    sp.gamma      = 2.0;
    sp.gas_e0     = 1e-4;
    sp.rho0       = 1.0;
    sp.shear_visc = 2.0;
    PetscCall(SpamModelSolidSetUp(2, &k, 1.0, &sp, m));
  } else PetscCall(SpamModelIsentropeSetUp(2, &k, 1.0, 1.4, 1.0 / 1.4, m));
  PetscFunctionReturn(0);
}

static PetscErrorCode RunCase(TestCount *tc, const Case *c)
{
  const int   n   = SIDE * SIDE;
  SpamBox     box = {2, {0, 0, 0}, {SIDE, SIDE, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  SpamModel   model;
  SpamSim     sim;
  double      x[2 * SIDE * SIDE], v[2 * SIDE * SIDE], *ydot;
  uint64_t    seed = 17;
  PetscScalar *y;
  long         u0, p0, b0;
  PetscMPIInt  rank, size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  Lattice(x, &seed);
  for (int i = 0; i < 2 * n; i++) v[i] = 0.01 * (TestUniform(&seed) - 0.5);
  PetscCall(MakeModel(c, &model));
  /* rank 0 holds the scene until the distribution, as scene.c does */
  PetscCall(SpamSimCreate(PETSC_COMM_WORLD, &model, &box, rank ? 0 : n, 0.1 * H, &sim));
  sim.pair.periodic_ghosts = c->ghosts;
  sim.pair.reproducible    = c->reproducible;
  PetscCall(SpamSimFill(&sim, x, v, NULL));
  PetscCall(SpamSimSetUp(&sim));
  if (sim.model.setup) PetscCall(sim.model.setup(&sim));
  PetscCall(SpamSimDistribute(&sim));
  PetscCall(PetscMalloc1((size_t)sim.p.n * sim.model.layout.nvar + 1, &ydot));
  u0 = sim.pair.nl.updates;
  p0 = sim.pair.nl.placements;
  b0 = sim.pair.nl.builds;
  PetscCall(VecGetArray(sim.p.X, &y));
  for (int e = 0; e < K; e++) {
    const SpamLayout *l = &sim.model.layout;
    PetscInt          bad;
    /* moves of a twentieth of the skin, and at e = 3 of the whole skin: a rebuild */
    for (PetscInt i = 0; i < sim.p.n; i++)
      for (int d = 0; d < 2; d++) y[(size_t)i * l->nvar + l->x + d] += (e == 3 ? 1.0 : 0.05) * 0.1 * H * (TestUniform(&seed) - 0.5);
    PetscCall(SpamRhs(&sim, y, ydot, &bad));
    TestCheck(tc, bad < 0, "%s: evaluation %d finite", c->name, e);
  }
  PetscCall(VecRestoreArray(sim.p.X, &y));
  {
    const SpamRhsStats *st = &sim.run.stats;
    const long du = sim.pair.nl.updates - u0, dp = sim.pair.nl.placements - p0, db = sim.pair.nl.builds - b0, want = c->ghosts || c->reproducible || size > 1 ? K : 0;
    TestCheck(tc, du == K, "%s, rank %d of %d: %ld list updates for %d right-hand sides (one each)", c->name, rank, size, du, K);
    TestCheck(tc, dp == want, "%s, rank %d of %d: %ld placements of the ghost positions (the halo's exchange on ranks) for %d right-hand sides (%ld: %s)", c->name, rank, size, dp, K, want, want ? "one each" : "no ghost slots");
    TestCheck(tc, db >= 1 && db < K, "%s, rank %d of %d: %ld list builds among them (the large move rebuilds, the small ones keep the list)", c->name, rank, size, db);
    TestCheck(tc, st->counted == K && st->list_updates == du && st->ghost_placements == dp, "%s, rank %d of %d: the RHS counted %ld evaluations, %ld list updates, %ld ghost placements", c->name, rank, size, st->counted, st->list_updates, st->ghost_placements);
  }
  PetscCall(PetscFree(ydot));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount  c       = {0, 0};
  const Case cases[] = {
    {"tensor gas (taylor-green), minimum image", PETSC_TRUE, PETSC_FALSE, PETSC_FALSE},
    {"tensor gas (taylor-green), ghost images", PETSC_TRUE, PETSC_TRUE, PETSC_FALSE},
    {"isentropic gas, minimum image", PETSC_FALSE, PETSC_FALSE, PETSC_FALSE},
    {"isentropic gas, ghost images", PETSC_FALSE, PETSC_TRUE, PETSC_FALSE},
    {"isentropic gas, -reproducible", PETSC_FALSE, PETSC_FALSE, PETSC_TRUE},
  };

  PetscCall(TestInitialize(&argc, &argv));
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) PetscCall(RunCase(&c, &cases[k]));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
