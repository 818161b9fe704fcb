/* Spring bonds across ranks (springs_bonds.c), on 1, 2 and 3 ranks. A hexagon of 5 shells
 * (91 particles) with positions perturbed by up to 0.02 is bonded at set-up on rank 0
 * (pairs closer than 1.1: the nearest neighbours) and distributed. A run never migrates
 * the springs again (the model builds no list after set-up), but the bonds must survive
 * any migration: here the body is turned a quarter turn, then 200 degrees more, and
 * migrated by the cut in force after each turn, so that particles change rank with bonds
 * whose partners are on other ranks (records with remote partners packed again). After
 * each stage, on every rank:
 *   - the bonds over all ranks, a local pair once and a bond with a remote partner half on
 *     each of its two ranks, are the reference count (on 2 and 3 ranks some are remote);
 *   - each local particle's acceleration equals the sum over its reference bonds computed
 *     here by gid, from positions that every rank knows (a function of the gid), within
 *     6 k (16 eps U): a particle has at most 6 bonds, each force k (r0 - r) with r
 *     rounded in box-local coordinates of size up to U (the box edge); a bond lost or
 *     counted twice changes it by k |r0 - r|, about 1e-2 here;
 *   - the potential energy (the model's diagnostics, reduced) equals the direct sum within
 *     the sum over bonds of k |r0 - r| 16 eps U plus its own rounding. */
#include <spam/physics.h>
#include <spam/decompose.h>
#include <spam/scene.h>
#include "test_util.h"

#define SHELLS 5
#define BOND_RANGE 1.1
#define BOX_EDGE 20.0

typedef struct {
  TestCount   count;
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  PetscInt    N;
  double     *x0;    /* [N * 2] perturbed lattice at set-up, by gid                */
  int        *bond;  /* [nbond * 2] reference bonds (gid pairs) of x0 within range */
  int         nbond;
  double      angle; /* the body's turn so far                                      */
} Ctx;

#define Check(t, ok_here, ...) TestCheckAll((t)->comm, &(t)->count, (ok_here), __VA_ARGS__)

static void PositionOf(const Ctx *t, PetscInt64 g, double p[2])
{
  const double c = cos(t->angle), s = sin(t->angle), *q = t->x0 + 2 * g;
  p[0] = c * q[0] - s * q[1];
  p[1] = s * q[0] + c * q[1];
}

/* The perturbed lattice and its bonds, the same on every rank. */
static PetscErrorCode MakeReference(Ctx *t)
{
  PetscFunctionBeginUser;
  t->N = 1 + 3 * SHELLS + 3 * SHELLS * SHELLS;
  PetscCall(PetscMalloc2(2 * t->N, &t->x0, 6 * t->N, &t->bond));
  (void)SpamLatticeHexagon(SHELLS, 1.0, t->x0);
  for (PetscInt g = 0; g < t->N; g++) {
    uint64_t s = (uint64_t)g * 7919u + 17u;
    for (int d = 0; d < 2; d++) t->x0[2 * g + d] += 0.04 * (TestUniform(&s) - 0.5);
  }
  t->nbond = 0;
  for (PetscInt a = 0; a < t->N; a++)
    for (PetscInt b = a + 1; b < t->N; b++) {
      const double dx = t->x0[2 * a] - t->x0[2 * b], dy = t->x0[2 * a + 1] - t->x0[2 * b + 1];
      if (dx * dx + dy * dy < BOND_RANGE * BOND_RANGE) {
        t->bond[2 * t->nbond]     = (int)a;
        t->bond[2 * t->nbond + 1] = (int)b;
        t->nbond++;
      }
    }
  PetscFunctionReturn(0);
}

/* The scene as spam-ark makes it: all particles on rank 0, set up there, distributed. */
static PetscErrorCode MakeSim(const Ctx *t, SpamSim *sim)
{
  SpamBox   box = {2, {-0.5 * BOX_EDGE, -0.5 * BOX_EDGE, 0}, {BOX_EDGE, BOX_EDGE, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
  SpamModel model;
  PetscInt  n = t->rank ? 0 : t->N;
  double   *v;

  PetscFunctionBeginUser;
  PetscCall(SpamModelSpringsSetUp(2, 2.0, 1.0, 1.0, 1.0, BOND_RANGE, &model));
  PetscCall(SpamSimCreate(t->comm, &model, &box, n, 0.2, sim));
  PetscCall(PetscCalloc1(2 * n + 1, &v));
  PetscCall(SpamSimFill(sim, t->x0, v, NULL)); /* on rank 0 the gids are 0 .. N-1 */
  PetscCall(PetscFree(v));
  PetscCall(SpamSimSetUp(sim));
  PetscCall(sim->model.setup(sim));
  PetscCall(SpamSimDistribute(sim));
  PetscFunctionReturn(0);
}

/* Every local particle to where the body's turn puts it. */
static PetscErrorCode Turn(Ctx *t, SpamSim *sim, double angle)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;

  PetscFunctionBeginUser;
  t->angle += angle;
  PetscCall(VecGetArray(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++) PositionOf(t, sim->p.gid[i], y + (size_t)i * l->nvar + l->x);
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* Acceleration of particle g over its reference bonds, and the bond's force scale. */
static void ReferenceAccel(const Ctx *t, PetscInt64 g, double a[2])
{
  double p[2], q[2];

  a[0] = a[1] = 0.0;
  PositionOf(t, g, p);
  for (int b = 0; b < t->nbond; b++) {
    const int me = t->bond[2 * b] == g ? 0 : t->bond[2 * b + 1] == g ? 1 : -1;
    double    dx[2], r;
    if (me < 0) continue;
    PositionOf(t, t->bond[2 * b + 1 - me], q);
    dx[0] = p[0] - q[0];
    dx[1] = p[1] - q[1];
    r     = sqrt(dx[0] * dx[0] + dx[1] * dx[1]);
    for (int d = 0; d < 2; d++) a[d] += (1.0 - r) / r * dx[d];
  }
}

/* The bond count over all ranks (remote bonds half on each rank), and the remote ones. */
static PetscErrorCode CheckCount(Ctx *t, const SpamSim *sim, const char *when)
{
  const SpamPhysicsScratch *ps = sim->ps;
  double                    c[2] = {0, 0}; /* bonds, remote entries */

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int b = ps->bond_start[i]; b < ps->bond_start[i + 1]; b++) {
      const PetscBool remote = (PetscBool)(ps->bond_nbr[b] >= sim->p.n);
      c[0] += remote ? 0.5 : 1.0;
      c[1] += remote;
    }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, c, 2, MPI_DOUBLE, MPI_SUM, t->comm));
  PetscCall(Check(t, c[0] == t->nbond && (t->size == 1) == (c[1] == 0), "%s, %d ranks: %g bonds over all ranks (reference %d), %g kept across ranks (by both)", when, t->size, c[0], t->nbond, c[1] / 2));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckForces(Ctx *t, SpamSim *sim, const char *when)
{
  const SpamLayout  *l   = &sim->model.layout;
  const double       eps = PETSC_MACHINE_EPSILON, tol = 6.0 * 16.0 * eps * BOX_EDGE;
  const PetscScalar *y;
  double            *ydot, worst = 0.0;
  PetscInt           bad;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1((size_t)sim->p.n * l->nvar + 1, &ydot));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamRhs(sim, y, ydot, &bad));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    double a[2];
    ReferenceAccel(t, sim->p.gid[i], a);
    for (int d = 0; d < 2; d++) worst = PetscMax(worst, fabs(ydot[(size_t)i * l->nvar + l->v + d] - a[d]));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, t->comm));
  PetscCall(Check(t, bad < 0 && worst <= tol, "%s, %d ranks: accelerations within %.1e of the direct sum over the reference bonds (bound 6 k 16 eps U = %.1e)", when, t->size, worst, tol));
  PetscCall(PetscFree(ydot));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckEnergy(Ctx *t, SpamSim *sim, const char *when)
{
  const double       eps = PETSC_MACHINE_EPSILON;
  const PetscScalar *y;
  SpamModelDiag      diag;
  double             pe = 0.0, tol = 0.0;

  PetscFunctionBeginUser;
  for (int b = 0; b < t->nbond; b++) {
    double p[2], q[2], r;
    PositionOf(t, t->bond[2 * b], p);
    PositionOf(t, t->bond[2 * b + 1], q);
    r = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]));
    pe += 0.5 * (1.0 - r) * (1.0 - r);
    tol += fabs(1.0 - r) * 16.0 * eps * BOX_EDGE;
  }
  tol += t->nbond * eps * pe;
  PetscCall(PetscMemzero(&diag, sizeof diag));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(sim->model.diag(sim, y, &diag));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(Check(t, fabs(diag.internal - pe) <= tol, "%s, %d ranks: potential energy %.15e, direct sum %.15e: difference %.1e (bound %.1e)", when, t->size, diag.internal, pe, fabs(diag.internal - pe), tol));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckAll(Ctx *t, SpamSim *sim, const char *when)
{
  PetscFunctionBeginUser;
  PetscCall(CheckCount(t, sim, when));
  PetscCall(CheckForces(t, sim, when));
  PetscCall(CheckEnergy(t, sim, when));
  PetscFunctionReturn(0);
}

/* A turn of the body, then a migration by the cut in force; some particles must move. */
static PetscErrorCode TurnAndMigrate(Ctx *t, SpamSim *sim, double angle, const char *when)
{
  SpamMigrateInfo info;

  PetscFunctionBeginUser;
  PetscCall(Turn(t, sim, angle));
  if (t->size == 1) PetscFunctionReturn(0); /* one rank: nothing to migrate */
  PetscCall(SpamSimMigrate(sim, sim->geo.dec, &info));
  PetscCall(Check(t, info.moved > 0 && info.bad < 0, "%s, %d ranks: %ld particles changed rank", when, t->size, (long)info.moved));
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(Ctx *t)
{
  SpamSim sim;

  PetscFunctionBeginUser;
  PetscCall(MakeReference(t));
  PetscCall(MakeSim(t, &sim));
  PetscCall(CheckAll(t, &sim, "first distribution"));
  PetscCall(TurnAndMigrate(t, &sim, 0.5 * PETSC_PI, "a quarter turn"));
  PetscCall(CheckAll(t, &sim, "a quarter turn"));
  PetscCall(TurnAndMigrate(t, &sim, 200.0 * PETSC_PI / 180.0, "200 degrees more"));
  PetscCall(CheckAll(t, &sim, "200 degrees more"));
  PetscCall(SpamSimDestroy(&sim));
  PetscCall(PetscFree2(t->x0, t->bond));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  Ctx t;

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(PetscMemzero(&t, sizeof t));
  t.comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_rank(t.comm, &t.rank));
  PetscCallMPI(MPI_Comm_size(t.comm, &t.size));
  PetscCall(Run(&t));
  PetscCall(TestFinalize());
  if (t.rank == 0) return TestFinish(&t.count);
  return t.count.failed ? 1 : 0;
}
