/* Decomposition and migration (decompose.h), run on 1, 2, 3 and 4 ranks. The Hilbert
 * curve visits every cell once, by face steps. Then, in 2D and 3D: every particle starts
 * on rank 0, in a lattice in one corner of a periodic box; the first migration cuts and
 * distributes them; random moves of up to 1.5 box lengths across the periodic faces
 * follow (migrated by the old cut: the imbalance it gives is printed), a re-cut, small
 * moves, no move, and a non-finite position on one rank. After each: the global count,
 * every gid exactly once, each particle's state and mass (functions of its gid) with it,
 * each particle on the owner of its cell, the local order sorted by (cell, gid), X and
 * the scratch of the new size, and after a cut the counts within one cell of N/P. On two
 * ranks the time of a migration of 10^5 particles is printed (not asserted). */
#include <spam/decompose.h>
#include <spam/kernel.h>
#include <stdarg.h>
#include "test_util.h"

typedef struct {
  TestCount   count;
  MPI_Comm    comm;
  PetscMPIInt rank, size;
} Ctx;

/* A check that holds on every rank (ok_here is this rank's part), printed once by rank 0. */
#define Check(t, ok_here, ...) TestCheckAll((t)->comm, &(t)->count, (ok_here), __VA_ARGS__)

/* ---- The curve: a bijection of the 2^bits cube onto 0 .. 2^(dim bits) - 1 whose
 * consecutive cells share a face. */
static PetscErrorCode CheckHilbert(Ctx *t, int dim, int bits)
{
  SpamCellGrid g     = {dim, {1, 1, 1}, bits};
  const int    side  = 1 << bits;
  const long   cells = dim == 2 ? (long)side * side : (long)side * side * side;
  int         *at;
  long         bad_key = 0, unvisited = 0, jumps = 0;

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) g.ncell[d] = side;
  PetscCall(PetscMalloc1(3 * cells, &at));
  for (long k = 0; k < 3 * cells; k++) at[k] = -1;
  for (long k = 0; k < cells; k++) {
    const int      c[3] = {(int)(k % side), (int)(k / side % side), dim == 3 ? (int)(k / side / side) : 0};
    const uint64_t key  = SpamCellHilbertKey(&g, c);
    if (key >= (uint64_t)cells || at[3 * key] >= 0) bad_key++;
    else
      for (int d = 0; d < 3; d++) at[3 * key + d] = c[d];
  }
  for (long k = 0; k < cells; k++) {
    unvisited += at[3 * k] < 0;
    if (k > 0) {
      int step = 0;
      for (int d = 0; d < 3; d++) step += abs(at[3 * k + d] - at[3 * (k - 1) + d]);
      jumps += step != 1;
    }
  }
  PetscCall(Check(t, bad_key == 0 && unvisited == 0 && jumps == 0, "Hilbert curve %dD, %d cells a side: %ld keys out of range or repeated, %ld cells unvisited, %ld steps that are not to a face neighbour", dim, side, bad_key, unvisited, jumps));
  PetscCall(PetscFree(at));
  PetscFunctionReturn(0);
}

/* ---- The particles: a lattice of side^dim sites at spacing 1 in the corner of a
 * periodic box [0, L)^dim, all on rank 0. The state is a function of the gid: lattice
 * site (plus the moves made so far), velocity gid + d/4, mass 1 + gid/1024 (all exact). */
typedef struct {
  int      dim, side, moves; /* moves applied: bit 0 the large random, bit 1 the small */
  double   L, h;
  PetscInt N;
} Scene;

static double Uniform(PetscInt64 gid, int d, int round)
{
  uint64_t s = (uint64_t)gid * 7919u + (uint64_t)d * 104729u + (uint64_t)round * 1299709u;
  return TestUniform(&s);
}

/* Position of particle gid after the moves: round 1 up to 1.5 L in each direction
 * (across the periodic faces, unwrapped), round 2 up to h/2. */
static double PositionOf(const Scene *s, PetscInt64 gid, int d)
{
  PetscInt64 site = gid;
  double     x;
  for (int k = 0; k < d; k++) site /= s->side;
  x = (double)(site % s->side) + 0.5;
  if (s->moves & 1) x += 1.5 * s->L * (2.0 * Uniform(gid, d, 1) - 1.0);
  if (s->moves & 2) x += 0.5 * s->h * (2.0 * Uniform(gid, d, 2) - 1.0);
  return x;
}
static double VelocityOf(PetscInt64 gid, int d) { return (double)gid + 0.25 * d; }
static double MassOf(PetscInt64 gid) { return 1.0 + (double)gid / 1024.0; }

static PetscErrorCode MakeSim(const Ctx *t, Scene *s, SpamSim *sim)
{
  SpamBox    box = {s->dim, {0, 0, 0}, {s->L, s->L, s->L}, {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}};
  SpamKernel kern;
  SpamModel  model;
  PetscInt   n = 1;
  double    *x, *v, *m;

  PetscFunctionBeginUser;
  for (int d = 0; d < s->dim; d++) n *= s->side;
  s->N = n;
  if (t->rank) n = 0;
  PetscCall(SpamKernelLucyInit(s->dim, s->h, &kern));
  PetscCall(SpamModelIsentropeSetUp(s->dim, &kern, 1.0, 2.0, 0.5, &model));
  PetscCall(SpamSimCreate(t->comm, &model, &box, n, 0.1 * s->h, sim));
  PetscCall(PetscMalloc3((size_t)n * s->dim + 1, &x, (size_t)n * s->dim + 1, &v, n + 1, &m));
  for (PetscInt i = 0; i < n; i++) { /* on rank 0 the gids are 0 .. n-1 */
    for (int d = 0; d < s->dim; d++) {
      x[i * s->dim + d] = PositionOf(s, i, d);
      v[i * s->dim + d] = VelocityOf(i, d);
    }
    m[i] = MassOf(i);
  }
  PetscCall(SpamSimFill(sim, x, v, m));
  PetscCall(PetscFree3(x, v, m));
  PetscCall(SpamSimSetUp(sim));
  PetscFunctionReturn(0);
}

/* Moves every particle to where PositionOf says after s->moves rounds. */
static PetscErrorCode ApplyMoves(const Scene *s, SpamSim *sim)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < s->dim; d++) y[(size_t)i * l->nvar + l->x + d] = PositionOf(s, sim->p.gid[i], d);
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

static int CompareKeys(const void *a, const void *b)
{
  const uint64_t p = *(const uint64_t *)a, q = *(const uint64_t *)b;
  return (p > q) - (p < q);
}

/* Largest number of particles in one cell: after a migration every cell is on one rank. */
static PetscErrorCode LargestCell(const SpamSim *sim, const SpamDecomp *dec, const double *y, PetscInt64 *cmax)
{
  uint64_t  *key;
  PetscInt64 run = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(sim->p.n + 1, &key));
  for (PetscInt i = 0; i < sim->p.n; i++) key[i] = SpamDecompKey(dec, y + (size_t)i * sim->model.layout.nvar + sim->model.layout.x);
  qsort(key, (size_t)sim->p.n, sizeof *key, CompareKeys);
  *cmax = 0;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    run   = i > 0 && key[i] == key[i - 1] ? run + 1 : 1;
    *cmax = PetscMax(*cmax, run);
  }
  PetscCall(PetscFree(key));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, cmax, 1, MPIU_INT64, MPI_MAX, sim->p.comm));
  PetscFunctionReturn(0);
}

/* Every gid 0 .. N-1 exactly once over the ranks. */
static PetscErrorCode GidsOnce(Ctx *t, const SpamSim *sim, PetscInt N, const char *when)
{
  PetscMPIInt *cnt, *off, n = (PetscMPIInt)sim->p.n;
  PetscInt64  *all;
  PetscInt    *seen;
  long         missing = 0, twice = 0, outside = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(t->size, &cnt, t->size, &off, N + 1, &all, N + 1, &seen));
  PetscCallMPI(MPI_Allgather(&n, 1, MPI_INT, cnt, 1, MPI_INT, t->comm));
  off[0] = 0;
  for (int r = 1; r < t->size; r++) off[r] = off[r - 1] + cnt[r - 1];
  if (off[t->size - 1] + cnt[t->size - 1] == N) {
    PetscCallMPI(MPI_Allgatherv(sim->p.gid, n, MPIU_INT64, all, cnt, off, MPIU_INT64, t->comm));
    PetscCall(PetscArrayzero(seen, N));
    for (PetscInt k = 0; k < N; k++) {
      if (all[k] < 0 || all[k] >= N) outside++;
      else seen[all[k]]++;
    }
    for (PetscInt g = 0; g < N; g++) {
      missing += seen[g] == 0;
      twice += seen[g] > 1;
    }
  } else missing = -1;
  PetscCall(Check(t, missing == 0 && twice == 0 && outside == 0, "%s: global count %ld of %ld; every gid once: %ld missing, %ld repeated, %ld out of range", when, (long)(off[t->size - 1] + cnt[t->size - 1]), (long)N, missing, twice, outside));
  PetscCall(PetscFree4(cnt, off, all, seen));
  PetscFunctionReturn(0);
}

/* State, mass, owner, order and sizes of every local particle. */
static PetscErrorCode Consistent(Ctx *t, const Scene *s, const SpamSim *sim, const SpamDecomp *dec, const char *when)
{
  const SpamLayout  *l = &sim->model.layout;
  const PetscScalar *y;
  PetscInt           lsize, gsize, swarm_n;
  long               wrong_state = 0, wrong_mass = 0, misplaced = 0, unsorted = 0, at_row = 0;
  uint64_t           prev = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double  *p = y + (size_t)i * l->nvar;
    const PetscInt64 g = sim->p.gid[i];
    int            c[3];
    uint64_t       key;
    for (int d = 0; d < s->dim; d++) wrong_state += p[l->x + d] != PositionOf(s, g, d) || p[l->v + d] != VelocityOf(g, d);
    wrong_mass += sim->pair.f.m[i] != MassOf(g) || (sim->pair.f.minv && sim->pair.f.minv[i] != 1.0 / MassOf(g));
    misplaced += SpamDecompOwner(dec, SpamDecompKey(dec, p + l->x)) != t->rank;
    SpamCellOf(&dec->grid, &sim->geo.box, p + l->x, c);
    key = SpamCellHilbertKey(&dec->grid, c);
    if (i > 0) unsorted += key < prev || (key == prev && g <= sim->p.gid[i - 1]);
    prev = key;
    if (i > 0) at_row += sim->p.gid[SpamSimAtRow(sim, i)] <= sim->p.gid[SpamSimAtRow(sim, i - 1)];
  }
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(VecGetLocalSize(sim->p.X, &lsize));
  PetscCall(VecGetSize(sim->p.X, &gsize));
  PetscCall(DMSwarmGetLocalSize(sim->p.swarm, &swarm_n));
  {
    long bad[5] = {wrong_state, wrong_mass, misplaced, unsorted, at_row};
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, bad, 5, MPI_LONG, MPI_SUM, t->comm));
    PetscCall(Check(t, bad[0] == 0 && bad[1] == 0, "%s: state and mass travelled with the gid (%ld state values, %ld masses differ)", when, bad[0], bad[1]));
    PetscCall(Check(t, bad[2] == 0, "%s: every particle on the owner of its cell (%ld misplaced)", when, bad[2]));
    PetscCall(Check(t, bad[3] == 0 && bad[4] == 0, "%s: local order sorted by (cell, gid), at_row in gid order (%ld, %ld out of order)", when, bad[3], bad[4]));
  }
  PetscCall(Check(t, swarm_n == sim->p.n && lsize == sim->p.n * l->nvar && gsize == s->N * l->nvar && sim->pair.f.n == sim->p.n && sim->pair.nl.n == sim->p.n && sim->p.nglobal == s->N,
                  "%s: X, fields and list have the new local size (rank 0: swarm %ld, sim %ld, X %ld/%ld, fields %d, list %d)", when, (long)swarm_n, (long)sim->p.n, (long)lsize, (long)gsize, sim->pair.f.n, sim->pair.nl.n));
  PetscFunctionReturn(0);
}

/* After a cut: each count within one cell of N/P. The cut ends each piece at the cell
 * boundary nearer its target floor(r N / P), within half the straddling cell's count
 * cmax/2, so a piece is within cmax/2 + cmax/2 + 1 (the floor) of N/P. */
static PetscErrorCode Balanced(Ctx *t, const Scene *s, const SpamSim *sim, const SpamDecomp *dec, const char *when)
{
  const PetscScalar *y;
  PetscInt64         cmax;
  const double       mean = (double)s->N / t->size, dev = PetscAbsReal((double)sim->p.n - mean);
  double             maxdev;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(LargestCell(sim, dec, y, &cmax));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCallMPI(MPI_Allreduce(&dev, &maxdev, 1, MPI_DOUBLE, MPI_MAX, t->comm));
  PetscCall(Check(t, dev <= (double)cmax + 1.0, "%s: counts within one cell of N/P = %.1f: largest deviation %.1f <= %ld + 1 (the fullest cell)", when, mean, maxdev, (long)cmax));
  PetscFunctionReturn(0);
}

/* The imbalance the migration reports is max/mean of the counts now held. */
static PetscErrorCode ImbalanceMeasured(Ctx *t, const Scene *s, const SpamSim *sim, const SpamMigrateInfo *info, const char *when)
{
  PetscInt64 n = sim->p.n, max;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&n, &max, 1, MPIU_INT64, MPI_MAX, t->comm));
  PetscCall(Check(t, info->imbalance == (double)max * t->size / (double)s->N, "%s: imbalance (max/mean) %.4f as reported (%.4f)", when, (double)max * t->size / (double)s->N, info->imbalance));
  PetscFunctionReturn(0);
}

/* Sent and received add up to the moved count on every rank. */
static PetscErrorCode Traffic(Ctx *t, const SpamMigrateInfo *info, PetscInt n_before, const SpamSim *sim, const char *when)
{
  PetscInt64 sr[2] = {info->sent, info->received};

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sr, 2, MPIU_INT64, MPI_SUM, t->comm));
  PetscCall(Check(t, sr[0] == info->moved && sr[1] == info->moved && info->resized == (sim->p.n != n_before), "%s: %ld moved, %ld sent, %ld received; resized flag as the count changed", when, (long)info->moved, (long)sr[0], (long)sr[1]));
  PetscFunctionReturn(0);
}

static PetscErrorCode Migrate(Ctx *t, const Scene *s, SpamSim *sim, SpamDecomp *dec, SpamMigrateInfo *info, const char *when)
{
  const PetscInt n_before = sim->p.n;

  PetscFunctionBeginUser;
  PetscCall(SpamSimMigrate(sim, dec, info));
  PetscCall(Check(t, info->bad == -1, "%s: no bad position", when));
  PetscCall(GidsOnce(t, sim, s->N, when));
  PetscCall(Consistent(t, s, sim, dec, when));
  PetscCall(Traffic(t, info, n_before, sim, when));
  PetscCall(ImbalanceMeasured(t, s, sim, info, when));
  PetscFunctionReturn(0);
}

/* A non-finite position on the last rank that holds particles: every rank learns the
 * gid, nobody hangs, nothing changes. */
static PetscErrorCode NonFinite(Ctx *t, const Scene *s, SpamSim *sim, SpamDecomp *dec)
{
  const SpamLayout *l = &sim->model.layout;
  PetscMPIInt       holder = sim->p.n > 0 ? t->rank : -1, last;
  PetscInt64        planted = -1, agreed[2];
  PetscInt          n_before = sim->p.n;
  SpamMigrateInfo   info;
  PetscScalar      *y;
  double            keep = 0.0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&holder, &last, 1, MPI_INT, MPI_MAX, t->comm));
  PetscCall(VecGetArray(sim->p.X, &y));
  if (t->rank == last) {
    planted = sim->p.gid[0];
    keep    = y[l->x];
    y[l->x] = NAN;
  }
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &planted, 1, MPIU_INT64, MPI_MAX, t->comm));
  PetscCall(SpamSimMigrate(sim, dec, &info));
  agreed[0] = info.bad;
  agreed[1] = -info.bad;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, agreed, 2, MPIU_INT64, MPI_MAX, t->comm));
  PetscCall(Check(t, info.bad == planted && agreed[0] == -agreed[1] && !info.changed && sim->p.n == n_before, "%dD non-finite x of gid %ld on rank %d only: every rank reports bad gid %ld, nothing changed", s->dim, (long)planted, last, (long)info.bad));
  PetscCall(VecGetArray(sim->p.X, &y));
  if (t->rank == last) y[l->x] = keep;
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

static PetscErrorCode Corner(Ctx *t, int dim, int side)
{
  Scene           s = {dim, side, 0, 64.0, 2.0, 0};
  SpamSim         sim;
  SpamDecomp      dec;
  SpamMigrateInfo info;
  char            when[96];

  PetscFunctionBeginUser;
  PetscCall(MakeSim(t, &s, &sim));
  PetscCall(SpamDecompCreate(sim.p.comm, &sim.geo.box, sim.model.kernel.h, 0.0, &dec));
  PetscCall(Check(t, dec.recut_above == SPAM_RECUT_ABOVE_DEFAULT, "%dD: recut threshold defaults to %.2f", dim, SPAM_RECUT_ABOVE_DEFAULT));

  PetscCall(PetscSNPrintf(when, sizeof when, "%dD N = %ld, first cut from rank 0", dim, (long)s.N));
  PetscCall(Migrate(t, &s, &sim, &dec, &info, when));
  PetscCall(Check(t, info.recut && info.changed && info.imbalance_before == t->size, "%s: cut made, imbalance before %.3f (all on rank 0: P), after %.4f", when, info.imbalance_before, info.imbalance));
  PetscCall(Balanced(t, &s, &sim, &dec, when));

  /* Random moves of up to 1.5 L, migrated by the old cut (no re-cut allowed): the
   * corner's cut leaves most of the box to the last rank. */
  s.moves = 1;
  PetscCall(ApplyMoves(&s, &sim));
  dec.recut_above = PETSC_MAX_REAL;
  PetscCall(PetscSNPrintf(when, sizeof when, "%dD moves up to 1.5 L, old cut", dim));
  PetscCall(Migrate(t, &s, &sim, &dec, &info, when));
  PetscCall(Check(t, !info.recut && dec.cuts == 1 && (t->size == 1 || info.imbalance > SPAM_RECUT_ABOVE_DEFAULT), "%s: no re-cut at an infinite threshold; imbalance %.4f after the moves (above the default threshold %.2f on more than one rank)", when, info.imbalance, SPAM_RECUT_ABOVE_DEFAULT));
  if (t->size > 1) TestReading(t->comm, "imbalance_after_moves", info.imbalance);

  /* The default threshold: the imbalance asks for a re-cut. */
  dec.recut_above = SPAM_RECUT_ABOVE_DEFAULT;
  PetscCall(PetscSNPrintf(when, sizeof when, "%dD re-cut at threshold %.2f", dim, SPAM_RECUT_ABOVE_DEFAULT));
  PetscCall(Migrate(t, &s, &sim, &dec, &info, when));
  if (t->size > 1) {
    PetscCall(Check(t, info.recut && dec.cuts == 2 && info.imbalance_before > dec.recut_above, "%s: re-cut triggered by imbalance %.4f, after it %.4f", when, info.imbalance_before, info.imbalance));
    TestReading(t->comm, "imbalance_after_recut", info.imbalance);
    PetscCall(Balanced(t, &s, &sim, &dec, when));
  } else PetscCall(Check(t, !info.recut && !info.changed, "%s: one rank: imbalance %.1f, no re-cut and nothing to do", when, info.imbalance_before));

  /* Small moves (up to h/2): some particles cross to a neighbour rank, no re-cut. */
  s.moves = 1 | 2;
  PetscCall(ApplyMoves(&s, &sim));
  PetscCall(PetscSNPrintf(when, sizeof when, "%dD moves up to h/2", dim));
  PetscCall(Migrate(t, &s, &sim, &dec, &info, when));
  PetscCall(Check(t, !info.recut && info.changed && (t->size == 1 || info.moved > 0), "%s: no re-cut (imbalance %.4f), %ld particles changed rank", when, info.imbalance, (long)info.moved));

  /* No move: nothing to do. */
  PetscCall(PetscSNPrintf(when, sizeof when, "%dD no move", dim));
  PetscCall(Migrate(t, &s, &sim, &dec, &info, when));
  PetscCall(Check(t, !info.changed && !info.resized && info.moved == 0, "%s: nothing moved or re-sorted", when));

  PetscCall(NonFinite(t, &s, &sim, &dec));
  PetscCall(SpamDecompDestroy(&dec));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

/* Wall time of a migration on the slowest rank. */
static PetscErrorCode TimeMigration(const Ctx *t, SpamSim *sim, SpamDecomp *dec, SpamMigrateInfo *info, double *seconds)
{
  double t0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Barrier(t->comm));
  t0 = MPI_Wtime();
  PetscCall(SpamSimMigrate(sim, dec, info));
  *seconds = MPI_Wtime() - t0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, seconds, 1, MPI_DOUBLE, MPI_MAX, t->comm));
  PetscFunctionReturn(0);
}

/* Wall time of one right-hand side of the local particles on the slowest rank. */
static PetscErrorCode TimeRhs(const Ctx *t, SpamSim *sim, double *ydot, double *seconds)
{
  PetscScalar *y;
  PetscInt     bad;
  double       t0;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  PetscCallMPI(MPI_Barrier(t->comm));
  t0 = MPI_Wtime();
  PetscCall(SpamRhs(sim, y, ydot, &bad));
  *seconds = MPI_Wtime() - t0;
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, seconds, 1, MPI_DOUBLE, MPI_MAX, t->comm));
  PetscFunctionReturn(0);
}

/* Every particle moved by up to h/2 in each direction (a new draw per round). */
static PetscErrorCode Jiggle(const Scene *s, SpamSim *sim, int round)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < s->dim; d++) y[(size_t)i * l->nvar + l->x + d] += 0.5 * s->h * (2.0 * Uniform(sim->p.gid[i], d, round) - 1.0);
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

static int CompareDoubles(const void *a, const void *b)
{
  const double p = *(const double *)a, q = *(const double *)b;
  return (p > q) - (p < q);
}

/* About 10^5 particles (a 2D lattice of 316^2 in the corner of a 1024^2 box) on two
 * ranks: the first distribution from rank 0, then migrations after moves of up to h/2
 * (the step-boundary case), each against a right-hand side of the same particles timed
 * in between (this machine's cores are shared: the medians and minima of 5 rounds). */
static PetscErrorCode Timing(Ctx *t)
{
  enum { ROUNDS = 5 };
  Scene           s = {2, 316, 0, 1024.0, 2.0, 0};
  SpamSim         sim;
  SpamDecomp      dec;
  SpamMigrateInfo first, later;
  double          t_first, t_mig[ROUNDS], t_rhs[ROUNDS], *ydot;
  PetscInt64      moved = 0;

  PetscFunctionBeginUser;
  PetscCall(MakeSim(t, &s, &sim));
  PetscCall(SpamDecompCreate(sim.p.comm, &sim.geo.box, sim.model.kernel.h, 0.0, &dec));
  PetscCall(TimeMigration(t, &sim, &dec, &first, &t_first));
  PetscCall(PetscMalloc1((size_t)(s.N / 2 + 1000) * sim.model.layout.nvar, &ydot));
  for (int k = 0; k < ROUNDS; k++) {
    PetscCall(Jiggle(&s, &sim, 10 + k));
    PetscCall(TimeMigration(t, &sim, &dec, &later, &t_mig[k]));
    PetscCheck(sim.p.n <= s.N / 2 + 1000, PETSC_COMM_SELF, PETSC_ERR_PLIB, "rank %d holds %ld particles", t->rank, (long)sim.p.n);
    PetscCall(TimeRhs(t, &sim, ydot, &t_rhs[k]));
    moved += later.moved;
  }
  PetscCall(PetscFree(ydot));
  qsort(t_mig, ROUNDS, sizeof *t_mig, CompareDoubles);
  qsort(t_rhs, ROUNDS, sizeof *t_rhs, CompareDoubles);
  if (t->rank == 0)
    printf("timing, %ld particles on %d ranks: first distribution from rank 0 (%ld moved) %.4f s; after moves up to h/2 (%.0f moved on average): migration median %.4f s (min %.4f), "
           "one RHS of the local particles median %.4f s (min %.4f): a migration costs %.2f RHS evaluations (ratio of medians)\n",
           (long)s.N, t->size, (long)first.moved, t_first, (double)moved / ROUNDS, t_mig[ROUNDS / 2], t_mig[0], t_rhs[ROUNDS / 2], t_rhs[0], t_mig[ROUNDS / 2] / t_rhs[ROUNDS / 2]);
  PetscCall(SpamDecompDestroy(&dec));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  Ctx t = {{0, 0}, MPI_COMM_NULL, 0, 1};

  PetscCall(TestInitialize(&argc, &argv));
  t.comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_rank(t.comm, &t.rank));
  PetscCallMPI(MPI_Comm_size(t.comm, &t.size));
  PetscCall(CheckHilbert(&t, 2, 4));
  PetscCall(CheckHilbert(&t, 3, 3));
  PetscCall(Corner(&t, 2, 40));
  PetscCall(Corner(&t, 3, 16));
  if (t.size == 2) PetscCall(Timing(&t));
  PetscCall(TestFinalize());
  if (t.rank == 0) return TestFinish(&t.count);
  return t.count.failed ? 1 : 0;
}
