/* The halo of a Hilbert-cut 3D gas as spam-ark's own code makes it: what each rank
 * receives and sends per exchange, to check the on-paper model of bench/halo_model.py
 * (bench/README.md, "Multi-rank runs: halo volume and messages").
 *
 *   mpiexec -n P ./build/bench/halo_census [-side n] [-h 3] [-skin 0.3] [-reps 5]
 *     side^3 particles on a jittered unit lattice filling a periodic cube of edge n
 *     (density 1), all made on rank 0, distributed by SpamSimMigrate (the Hilbert cut of
 *     decompose.c), then a neighbour list with the halo of SpamHalo over the ranks, as the
 *     gas path of the program builds it. Per rank: particles, remote ghosts (received per
 *     exchange), items sent, the ranks it receives from and sends to (one message each per
 *     exchange), its bounding box, pairs; the selection's cells (halo_select.c: the cells it
 *     occupies, each tested against every other rank's box; the cells it sent, to how many
 *     ranks; the cells it received) and its CPU time of a selection (median over -reps);
 *     the halo formula on the ranks' cut, halo_cells_formula (as halo_cells of -geometry
 *     below, with the cut's own keys, within h + skin - inset, -inset 0.4 for this lattice);
 *     and the medians over -reps of the slowest rank's time of a halo selection (the list
 *     build's share) and of one forward exchange of 3 and of 1 value per ghost.
 *   ./build/bench/halo_census -geometry -side n -pieces P [-h 3] [-skin 0.3] [-inset 0] [-samples 3]
 *     one process, no particles: the same cut of the cells of that cube into P pieces of
 *     equal count (a uniform gas: every cell holds the same number). Per piece: its
 *     bounding box and the pieces with a cell within rc = h + skin of that box (ranks_from,
 *     ranks_to: what a selection by bounding boxes would use); its surface (the cell faces
 *     it shares with other pieces, which sets the pairs it has across ranks); the halo of
 *     the selection by cells, halo_cells: the volume of the other pieces within rc - inset
 *     of the piece (sampled at -samples^3 points per cell near a cut; at density 1 the
 *     remote ghosts), and the pieces that volume lies in (ranks_from_cells, ranks_to_cells);
 *     and the selection's cells on its grid (cells at least rc wide): those the piece
 *     occupies, those it sends (its cells clipped to its box, within rc of another piece's
 *     box), to how many ranks, and those it receives. This is what the model uses for N up
 *     to 10^8 and P up to 1000.
 *
 * Both print one JSON object on standard output (rank 0). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <time.h>
#include <spam/sim.h>
#include <spam/neighbours.h>
#include <petsctime.h>

typedef struct {
  PetscInt  side, reps, pieces, samples;
  PetscReal h, skin, inset;
  PetscBool geometry;
} Args;

static PetscErrorCode ReadArgs(Args *a)
{
  PetscFunctionBeginUser;
  a->side = 32, a->reps = 5, a->pieces = 8, a->samples = 3, a->h = 3.0, a->skin = 0.3, a->inset = 0.0, a->geometry = PETSC_FALSE;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "halo_census: the halo of a Hilbert-cut 3D gas", "bench/README.md");
  PetscCall(PetscOptionsInt("-side", "lattice sites per edge (side^3 particles, density 1)", NULL, a->side, &a->side, NULL));
  PetscCall(PetscOptionsReal("-h", "Lucy range h (lattice spacings)", NULL, a->h, &a->h, NULL));
  PetscCall(PetscOptionsReal("-skin", "list skin (the program's default is 0.1 h)", NULL, a->skin, &a->skin, NULL));
  PetscCall(PetscOptionsInt("-reps", "timed repetitions (median reported)", NULL, a->reps, &a->reps, NULL));
  PetscCall(PetscOptionsBool("-geometry", "cut the cells only, in one process, into -pieces pieces", NULL, a->geometry, &a->geometry, NULL));
  PetscCall(PetscOptionsInt("-pieces", "pieces of the -geometry cut", NULL, a->pieces, &a->pieces, NULL));
  PetscCall(PetscOptionsInt("-samples", "sample points per cell edge of the halo formula's volume", NULL, a->samples, &a->samples, NULL));
  PetscCall(PetscOptionsReal("-inset", "how far inside its cells' faces a piece's outermost particles sit: the halo formula counts the volume within h + skin - inset", NULL, a->inset, &a->inset, NULL));
  PetscOptionsEnd();
  PetscCheck(a->side >= 2 && a->side <= 2000 && a->h > 0 && a->skin >= 0 && a->reps >= 1 && a->pieces >= 1 && a->samples >= 1 && a->samples <= 16 && a->inset >= 0 && a->inset < a->h + a->skin, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "need 2 <= -side <= 2000, -h > 0, -skin >= 0, -reps >= 1, -pieces >= 1, 1 <= -samples <= 16, 0 <= -inset < h + skin");
  PetscFunctionReturn(0);
}

static int CompareDoubles(const void *a, const void *b)
{
  const double p = *(const double *)a, q = *(const double *)b;
  return (p > q) - (p < q);
}

/* A fixed jitter in [-0.1, 0.1) per (site, direction): no site sits on a cell face. */
static double Jitter(PetscInt64 site, int d)
{
  uint64_t z = (uint64_t)site * 3u + (uint64_t)d + 0x9e3779b97f4a7c15ull;
  z          = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z          = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return 0.2 * ((double)(z >> 11) / 9007199254740992.0 - 0.5);
}

static SpamBox CubeBox(PetscInt side)
{
  SpamBox box = {3, {0, 0, 0}, {(double)side, (double)side, (double)side}, {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}};
  return box;
}

/* The gas, all on rank 0 (as a scene makes it before the first migration). */
static PetscErrorCode MakeSim(MPI_Comm comm, const Args *a, SpamSim *sim)
{
  const SpamBox box = CubeBox(a->side);
  SpamKernel    kern;
  SpamModel     model;
  PetscMPIInt   rank;
  PetscInt      n = a->side * a->side * a->side;
  double       *x, *v;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank) n = 0;
  PetscCall(SpamKernelLucyInit(3, a->h, &kern));
  PetscCall(SpamModelIsentropeSetUp(3, &kern, 1.0, 5.0 / 3.0, 0.6, &model)); /* the 3D expansion's gas */
  PetscCall(SpamSimCreate(comm, &model, &box, n, a->skin, sim));
  PetscCall(PetscCalloc2(3 * (size_t)n + 1, &x, 3 * (size_t)n + 1, &v));
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt site[3] = {i % a->side, (i / a->side) % a->side, i / (a->side * a->side)};
    for (int d = 0; d < 3; d++) x[3 * i + d] = (double)site[d] + 0.5 + Jitter(i, d);
  }
  PetscCall(SpamSimFill(sim, x, v, NULL));
  PetscCall(PetscFree2(x, v));
  PetscCall(SpamSimSetUp(sim));
  PetscFunctionReturn(0);
}

/* Copies this rank's positions out of the state (after the migration). */
static PetscErrorCode LocalPositions(const SpamSim *sim, double **x)
{
  const SpamLayout  *l = &sim->model.layout;
  const PetscScalar *y;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(3 * (size_t)sim->p.n + 1, x));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < 3; d++) (*x)[3 * i + d] = y[(size_t)i * l->nvar + l->x + d];
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* This thread's CPU time, seconds: a rank's own work in a selection, without the time it
 * stood descheduled on the oversubscribed cores (the census runs up to 8 ranks on 2). */
static double CpuSeconds(void)
{
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Wall time of the slowest rank. */
static PetscErrorCode SlowestSince(MPI_Comm comm, PetscLogDouble t0, double *s)
{
  PetscLogDouble t1;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t1));
  *s = t1 - t0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, s, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

/* Medians over reps of a halo selection, a forward exchange of positions and one of a
 * scalar (the slowest rank's wall times): t[0], t[1], t[2]; and t[3], this rank's CPU time
 * of a selection (median), which the model's fit of the selection's cost uses. The
 * selection is made again at the same positions, so the halo stays what the list holds. */
static PetscErrorCode TimeHalo(MPI_Comm comm, const Args *a, SpamNeighbours *nl, double t[4])
{
  SpamHalo      *h   = &nl->ghosts.halo;
  const SpamBox  box = CubeBox(a->side);
  double        *dst[3], *scalar, *field, *s[4], c0;
  PetscLogDouble t0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc5(h->nghost + 1, &dst[0], h->nghost + 1, &dst[1], h->nghost + 1, &dst[2], h->nghost + 1, &scalar, nl->n + 1, &field));
  for (int k = 0; k < 4; k++) PetscCall(PetscMalloc1(a->reps, &s[k]));
  for (int i = 0; i < nl->n; i++) field[i] = i;
  for (PetscInt r = 0; r < a->reps; r++) {
    PetscCallMPI(MPI_Barrier(comm));
    PetscCall(PetscTime(&t0));
    c0 = CpuSeconds();
    PetscCall(SpamHaloSelect(h, &box, nl->ghosts.periodic, nl->n, nl->u, nl->cutoff + nl->skin));
    s[3][r] = CpuSeconds() - c0;
    PetscCall(SlowestSince(comm, t0, &s[0][r]));
    PetscCallMPI(MPI_Barrier(comm));
    PetscCall(PetscTime(&t0));
    PetscCall(SpamHaloForwardPositions(h, 3, nl->u, dst));
    PetscCall(SlowestSince(comm, t0, &s[1][r]));
    PetscCallMPI(MPI_Barrier(comm));
    PetscCall(PetscTime(&t0));
    PetscCall(SpamHaloForward(h, 1, field, scalar));
    PetscCall(SlowestSince(comm, t0, &s[2][r]));
  }
  for (int k = 0; k < 4; k++) {
    qsort(s[k], (size_t)a->reps, sizeof(double), CompareDoubles);
    t[k] = s[k][a->reps / 2];
    PetscCall(PetscFree(s[k]));
  }
  PetscCall(PetscFree5(dst[0], dst[1], dst[2], scalar, field));
  PetscFunctionReturn(0);
}

#define NREC 21 /* n, remote ghosts, items, from, to, pairs, ghost pairs, box lo[3] hi[3], local ghosts, builds,
                    occupied cells, cells sent, ranks sent cells, cells received, select CPU s, selection cells per edge */

/* This rank's record of the halo, in the order of the JSON keys below. The selection's
 * cells (halo_select.c, kept in h->sel after the last selection): the cells this rank
 * occupies (each tested against every other rank's box), the (cell, rank) pairs it sent
 * and to how many ranks, the cells it received. */
static void Record(const SpamNeighbours *nl, double cpu_s, double rec[NREC])
{
  const SpamHalo *h    = &nl->ghosts.halo;
  int             from = 0, to = 0, cells_to = 0;
  double          sent = 0.0;

  for (int r = 0; h->active && r < h->size; r++) {
    from += h->rcount[r] > 0;
    to += h->scount[r] > 0;
    cells_to += h->sel.scnt[r] > 0;
    sent += h->sel.scnt[r];
  }
  rec[0] = nl->n, rec[1] = h->nghost, rec[2] = h->nitems, rec[3] = from, rec[4] = to;
  rec[5] = (double)nl->npairs, rec[6] = (double)nl->ngpairs;
  for (int k = 0; k < 6; k++) rec[7 + k] = h->active ? h->boxes[6 * (size_t)h->rank + k] : 0.0; /* lo[3], hi[3] */
  rec[13] = nl->ghosts.nlocal, rec[14] = (double)nl->builds;
  rec[15] = h->active ? h->sel.nocc : 0, rec[16] = sent, rec[17] = cells_to, rec[18] = h->active ? h->sel.rcoff[h->size] : 0;
  rec[19] = cpu_s, rec[20] = h->active ? PetscMax(1.0, PetscFloorReal(h->len[0] / (nl->cutoff + nl->skin))) : 0; /* as MakeGrid */
}

static PetscErrorCode PrintRanks(MPI_Comm comm, const Args *a, const SpamNeighbours *nl, const double t[4], double imbalance, const double *formula)
{
  static const char *key[NREC] = {"n", "remote_ghosts", "items_sent", "ranks_from", "ranks_to", "pairs", "ghost_pairs", "lo_x", "lo_y", "lo_z", "hi_x", "hi_y", "hi_z", "local_ghosts", "builds",
                                  "occupied_cells", "cells_sent", "ranks_sent_cells", "cells_received", "select_cpu_s", "select_cells_per_edge"};
  PetscMPIInt        rank, size;
  double             mine[NREC], *all = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  Record(nl, t[3], mine);
  if (!rank) PetscCall(PetscMalloc1((size_t)NREC * size, &all));
  PetscCallMPI(MPI_Gather(mine, NREC, MPI_DOUBLE, all, NREC, MPI_DOUBLE, 0, comm));
  if (rank) PetscFunctionReturn(0);
  printf("{\"mode\": \"ranks\", \"side\": %d, \"N\": %d, \"P\": %d, \"h\": %.17g, \"skin\": %.17g, \"imbalance\": %.6f,\n", (int)a->side, (int)(a->side * a->side * a->side), size, (double)a->h, (double)a->skin, imbalance);
  printf(" \"select_s\": %.6e, \"forward3_s\": %.6e, \"forward1_s\": %.6e, \"reps\": %d,\n \"ranks\": [\n", t[0], t[1], t[2], (int)a->reps);
  for (int r = 0; r < size; r++) {
    printf("  {");
    for (int k = 0; k < NREC; k++) printf("\"%s\": %.17g, ", key[k], all[(size_t)NREC * r + k]);
    printf("\"halo_cells_formula\": %.17g}%s\n", formula[r], r + 1 < size ? "," : "");
  }
  printf(" ]}\n");
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}

static PetscErrorCode SampledHalo(const SpamCellGrid *g, double w, double rs, int k, const int *owner, int P, double *halo, unsigned char *near);

/* The halo the selection by cells makes for the cut the ranks hold (dec's keys), at
 * density 1: each piece's cells dilated by rc - inset (SampledHalo), on every rank. */
static PetscErrorCode CutHalo(const SpamDecomp *dec, const Args *a, double *halo)
{
  const SpamCellGrid *g  = &dec->grid;
  const int           nc = g->ncell[0] * g->ncell[1] * g->ncell[2], P = dec->nranks;
  int                *owner;
  unsigned char      *near;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(nc, &owner, (size_t)P * P, &near));
  for (int c = 0; c < nc; c++) {
    const int      ijk[3] = {c % g->ncell[0], (c / g->ncell[0]) % g->ncell[1], c / (g->ncell[0] * g->ncell[1])};
    const uint64_t key    = SpamCellHilbertKey(g, ijk);
    int            r      = 0;
    while (r + 1 < P && dec->cut[r + 1] <= key) r++;
    owner[c] = r;
  }
  PetscCall(SampledHalo(g, a->side / (double)g->ncell[0], a->h + a->skin - a->inset, (int)a->samples, owner, P, halo, near));
  PetscCall(PetscFree2(owner, near));
  PetscFunctionReturn(0);
}

static PetscErrorCode Ranks(MPI_Comm comm, const Args *a)
{
  const SpamBox   box = CubeBox(a->side);
  SpamSim         sim;
  SpamDecomp      dec;
  SpamMigrateInfo info;
  SpamNeighbours  nl;
  PetscInt        bad;
  double         *x, t[4], *halo;

  PetscFunctionBeginUser;
  PetscCall(MakeSim(comm, a, &sim));
  PetscCall(SpamDecompCreate(sim.p.comm, &sim.geo.box, sim.model.kernel.h, 0.0, &dec));
  PetscCall(SpamSimMigrate(&sim, &dec, &info));
  PetscCall(PetscMalloc1(dec.nranks, &halo));
  PetscCall(CutHalo(&dec, a, halo));
  PetscCall(LocalPositions(&sim, &x));
  PetscCall(SpamNeighboursCreate((int)sim.p.n, &box, a->h, a->skin, &nl));
  PetscCall(SpamNeighboursSetComm(&nl, comm));
  PetscCall(SpamNeighboursUpdate(&nl, &box, x, 3, PETSC_TRUE, &bad));
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "non-finite position in the census lattice");
  PetscCall(TimeHalo(comm, a, &nl, t));
  PetscCall(PrintRanks(comm, a, &nl, t, info.imbalance, halo));
  PetscCall(PetscFree(halo));
  PetscCall(SpamNeighboursDestroy(&nl));
  PetscCall(PetscFree(x));
  PetscCall(SpamDecompDestroy(&dec));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

/* ---- -geometry: the cut of the cells alone ---- */

typedef struct {
  uint64_t key;
  int      cell;
} KeyCell;

static int CompareKeyCells(const void *a, const void *b)
{
  const KeyCell *p = a, *q = b;
  return (p->key > q->key) - (p->key < q->key);
}

/* Distance from the interval [a0, a1] to [b0, b1] (0 when they overlap). */
static double IntervalGap(double a0, double a1, double b0, double b1)
{
  return PetscMax(0.0, PetscMax(b0 - a1, a0 - b1));
}

/* The cells along the curve, and owner[c] of each: pieces of equal cell count (a uniform
 * gas), each ending at the cell boundary nearest its target as SpamDecompCut does. */
static PetscErrorCode CutCells(const SpamCellGrid *g, int P, int *owner, int (*lo)[3], int (*hi)[3], int *cells)
{
  const int nc = g->ncell[0] * g->ncell[1] * g->ncell[2];
  KeyCell  *kc;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nc, &kc));
  for (int c = 0; c < nc; c++) {
    const int ijk[3] = {c % g->ncell[0], (c / g->ncell[0]) % g->ncell[1], c / (g->ncell[0] * g->ncell[1])};
    kc[c]            = (KeyCell){SpamCellHilbertKey(g, ijk), c};
  }
  qsort(kc, (size_t)nc, sizeof *kc, CompareKeyCells);
  for (int r = 0; r < P; r++) {
    const int c0 = (int)(((long long)r * nc + P / 2) / P), c1 = (int)(((long long)(r + 1) * nc + P / 2) / P);
    cells[r] = c1 - c0;
    for (int d = 0; d < 3; d++) lo[r][d] = INT_MAX, hi[r][d] = -1;
    for (int q = c0; q < c1; q++) {
      const int c = kc[q].cell, ijk[3] = {c % g->ncell[0], (c / g->ncell[0]) % g->ncell[1], c / (g->ncell[0] * g->ncell[1])};
      owner[c] = r;
      for (int d = 0; d < 3; d++) lo[r][d] = PetscMin(lo[r][d], ijk[d]), hi[r][d] = PetscMax(hi[r][d], ijk[d]);
    }
  }
  PetscCall(PetscFree(kc));
  PetscFunctionReturn(0);
}

/* The pieces with a cell within rc of piece r's bounding box (periodic images included):
 * from[r] of them, and to[o] += 1 for each. stamp[o] == r marks o as counted for r. */
static void Neighbours(const SpamCellGrid *g, const double w[3], double rc, const int *owner, int r, const int lo[3], const int hi[3], int *stamp, int *from, int *to)
{
  int e[3], span[3];
  for (int d = 0; d < 3; d++) {
    e[d]    = (int)ceil(rc / w[d]);
    span[d] = hi[d] - lo[d] + 1 + 2 * e[d] >= g->ncell[d]; /* the scan wraps all round */
  }
  for (int k = span[2] ? 0 : lo[2] - e[2]; k <= (span[2] ? g->ncell[2] - 1 : hi[2] + e[2]); k++)
    for (int j = span[1] ? 0 : lo[1] - e[1]; j <= (span[1] ? g->ncell[1] - 1 : hi[1] + e[1]); j++)
      for (int i = span[0] ? 0 : lo[0] - e[0]; i <= (span[0] ? g->ncell[0] - 1 : hi[0] + e[0]); i++) {
        const int u[3] = {i, j, k};
        int       c = 0, mult = 1;
        double    gap2 = 0.0;
        for (int d = 0; d < 3; d++) {
          const int    m = ((u[d] % g->ncell[d]) + g->ncell[d]) % g->ncell[d];
          const double L = g->ncell[d] * w[d];
          double       gp = IntervalGap(u[d] * w[d], (u[d] + 1) * w[d], lo[d] * w[d], (hi[d] + 1) * w[d]);
          if (span[d]) gp = PetscMin(gp, PetscMin(IntervalGap(u[d] * w[d] - L, (u[d] + 1) * w[d] - L, lo[d] * w[d], (hi[d] + 1) * w[d]), IntervalGap(u[d] * w[d] + L, (u[d] + 1) * w[d] + L, lo[d] * w[d], (hi[d] + 1) * w[d])));
          gap2 += gp * gp;
          c += m * mult;
          mult *= g->ncell[d];
        }
        {
          const int o = owner[c];
          if (o == r || stamp[o] == r || !(gap2 < rc * rc)) continue;
          stamp[o] = r;
          from[r]++;
          to[o]++;
        }
      }
}

/* Each piece's surface: the faces between its cells and other pieces' (periodic). */
static void Surfaces(const SpamCellGrid *g, const double w[3], const int *owner, double *surface)
{
  const int nc = g->ncell[0] * g->ncell[1] * g->ncell[2];
  for (int c = 0; c < nc; c++) {
    const int ijk[3] = {c % g->ncell[0], (c / g->ncell[0]) % g->ncell[1], c / (g->ncell[0] * g->ncell[1])}, stride[3] = {1, g->ncell[0], g->ncell[0] * g->ncell[1]};
    for (int d = 0; d < 3; d++) {
      const int    nb   = c + ((ijk[d] + 1) % g->ncell[d] - ijk[d]) * stride[d];
      const double area = w[(d + 1) % 3] * w[(d + 2) % 3];
      if (owner[nb] == owner[c]) continue;
      surface[owner[c]] += area;
      surface[owner[nb]] += area;
    }
  }
}

/* ---- -geometry: the halo the cell-based selection (halo_select.c) makes ---- */

/* The periodic gap from [a0, a1] to [b0, b1] in a ring of length L. */
static double RingGap(double a0, double a1, double b0, double b1, double L)
{
  return PetscMin(IntervalGap(a0, a1, b0, b1), PetscMin(IntervalGap(a0 - L, a1 - L, b0, b1), IntervalGap(a0 + L, a1 + L, b0, b1)));
}

/* The volume of other pieces within rs of each piece (halo[r]; a uniform gas of density 1
 * makes it the remote ghosts), and which pieces that volume lies in (near[r * P + s]). Each
 * cell that has another piece's cell within reach is sampled at k^3 points, one at a
 * hashed place in each cell of a k x k x k split (a fixed lattice of points would sit at
 * fixed distances from the cell faces and miss or double whole layers of the halo); a point
 * in piece s counts once for every other piece r with a cell within rs of it. The cells a
 * sub-cell can reach (a superset of its points') are listed once per sub-cell. */
static PetscErrorCode SampledHalo(const SpamCellGrid *g, double w, double rs, int k, const int *owner, int P, double *halo, unsigned char *near)
{
  const int    n = g->ncell[0], e = (int)ceil(rs / w), span = 2 * e + 1, npt = k * k * k;
  const double sw = w / k;
  int         *list, *start, m = 0;
  long        *stamp;
  long         tag = 0;

  PetscFunctionBeginUser;
  PetscCheck(e <= 4, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "the halo reaches %d cells", e);
  PetscCall(PetscMalloc3((size_t)npt * span * span * span, &list, npt + 1, &start, P, &stamp));
  for (int r = 0; r < P; r++) stamp[r] = -1;
  for (int q = 0; q < npt; q++) { /* the cells within rs of sub-cell q */
    const int sub[3] = {q % k, (q / k) % k, q / (k * k)};
    start[q]         = m;
    for (int c = -e; c <= e; c++)
      for (int b = -e; b <= e; b++)
        for (int a = -e; a <= e; a++) {
          const int o[3] = {a, b, c};
          double    gap2 = 0.0;
          for (int d = 0; d < 3; d++) gap2 += PetscSqr(IntervalGap(sub[d] * sw, (sub[d] + 1) * sw, o[d] * w, (o[d] + 1) * w));
          if ((a || b || c) && gap2 < rs * rs) list[m++] = a + e + span * (b + e + span * (c + e));
        }
  }
  start[npt] = m;
  for (int r = 0; r < P; r++) halo[r] = 0.0;
  for (int cz = 0; cz < n; cz++)
    for (int cy = 0; cy < n; cy++)
      for (int cx = 0; cx < n; cx++) {
        const int s = owner[cx + n * (cy + n * cz)];
        int       nb[9 * 9 * 9], mixed = 0;
        for (int c = -e; c <= e; c++)
          for (int b = -e; b <= e; b++)
            for (int a = -e; a <= e; a++) {
              const int o = owner[(cx + a + n) % n + n * ((cy + b + n) % n + n * ((cz + c + n) % n))];
              nb[a + e + span * (b + e + span * (c + e))] = o;
              mixed |= o != s;
            }
        if (!mixed) continue;
        for (int q = 0; q < npt; q++, tag++) {
          const PetscInt64 id = ((PetscInt64)(cx + n * (cy + n * cz))) * npt + q;
          double           x[3];
          for (int d = 0; d < 3; d++) x[d] = ((q / (d == 0 ? 1 : d == 1 ? k : k * k)) % k + 0.5 + 5.0 * Jitter(id, d)) * sw;
          for (int j = start[q]; j < start[q + 1]; j++) {
            const int r = nb[list[j]], o[3] = {list[j] % span - e, (list[j] / span) % span - e, list[j] / (span * span) - e};
            double    gap2 = 0.0;
            if (r == s || stamp[r] == tag) continue;
            for (int d = 0; d < 3; d++) gap2 += PetscSqr(IntervalGap(x[d], x[d], o[d] * w, (o[d] + 1) * w));
            if (!(gap2 < rs * rs)) continue;
            stamp[r] = tag;
            halo[r] += w * w * w / npt;
            near[(size_t)r * P + s] = 1;
          }
        }
      }
  PetscCall(PetscFree3(list, start, stamp));
  PetscFunctionReturn(0);
}

/* The selection's grid (cells at least rc wide, as halo_select.c's MakeGrid) over the cut:
 * occ[r], the selection cells piece r occupies (each tested against the P - 1 other boxes);
 * sent[r], the (cell, rank) pairs it sends: its cells, clipped to its bounding box, within rc
 * of another piece's bounding box; cells_to[r], the ranks it sends cells to; recv[r], the
 * cells it receives. */
static PetscErrorCode SelectionCells(const SpamCellGrid *g, double w, double rc, double L, const int *owner, int P, const int (*lo)[3], const int (*hi)[3], double *occ, double *sent, int *cells_to, double *recv)
{
  const int n = g->ncell[0], nh = PetscMax(1, (int)(L / rc)), nhc = nh * nh * nh;
  const double wh = L / nh;
  int      *hstart, *hown, *stamp, m = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(nhc + 1, &hstart, 8 * (size_t)nhc + 27, &hown, P, &stamp));
  for (int r = 0; r < P; r++) stamp[r] = -1, occ[r] = sent[r] = recv[r] = 0, cells_to[r] = 0;
  for (int c = 0; c < nhc; c++) { /* the pieces in selection cell c: its owners' list */
    const int ijk[3] = {c % nh, (c / nh) % nh, c / (nh * nh)};
    int       d0[3], d1[3];
    hstart[c] = m;
    for (int d = 0; d < 3; d++) {
      d0[d] = (int)(ijk[d] * wh / w);
      d1[d] = PetscMin(n - 1, (int)ceil((ijk[d] + 1) * wh / w) - 1);
    }
    for (int z = d0[2]; z <= d1[2]; z++)
      for (int y = d0[1]; y <= d1[1]; y++)
        for (int x = d0[0]; x <= d1[0]; x++) {
          const int o = owner[x + n * (y + n * z)];
          if (stamp[o] == c) continue;
          stamp[o] = c;
          if (m + 1 > 8 * nhc + 27) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "more than 8 pieces per selection cell on average");
          hown[m++] = o;
          occ[o] += 1;
        }
  }
  hstart[nhc] = m;
  for (int r = 0; r < P; r++) stamp[r] = -1;
  for (int r = 0; r < P; r++) { /* the cells near r's box: what the others send r */
    double blo[3], bhi[3];
    int    i0[3], i1[3];
    for (int d = 0; d < 3; d++) {
      blo[d] = lo[r][d] * w, bhi[d] = (hi[r][d] + 1) * w;
      i0[d] = (int)floor((blo[d] - rc) / wh), i1[d] = (int)floor((bhi[d] + rc) / wh);
      if (i1[d] - i0[d] + 1 >= nh) i0[d] = 0, i1[d] = nh - 1;
    }
    for (int z = i0[2]; z <= i1[2]; z++)
      for (int y = i0[1]; y <= i1[1]; y++)
        for (int x = i0[0]; x <= i1[0]; x++) {
          const int u[3] = {(x % nh + nh) % nh, (y % nh + nh) % nh, (z % nh + nh) % nh}, c = u[0] + nh * (u[1] + nh * u[2]);
          for (int j = hstart[c]; j < hstart[c + 1]; j++) {
            const int o = hown[j];
            double    gap2 = 0.0;
            if (o == r) continue;
            for (int d = 0; d < 3; d++) { /* the cell clipped to o's box, against r's box */
              const double a0 = PetscMax(u[d] * wh, lo[o][d] * w), a1 = PetscMin((u[d] + 1) * wh, (hi[o][d] + 1) * w);
              gap2 += PetscSqr(RingGap(a0, a1, blo[d], bhi[d], L));
            }
            if (!(gap2 < rc * rc)) continue;
            sent[o] += 1, recv[r] += 1;
            if (stamp[o] != r) stamp[o] = r, cells_to[o]++;
          }
        }
  }
  PetscCall(PetscFree3(hstart, hown, stamp));
  PetscFunctionReturn(0);
}

static PetscErrorCode Geometry(const Args *a)
{
  const SpamBox box = CubeBox(a->side);
  const int     P   = (int)a->pieces;
  SpamCellGrid  g;
  double        w[3];
  int          *owner, (*lo)[3], (*hi)[3], *cells, *stamp, *from, *to, *cells_to, *cfrom;
  double       *surface, *halo, *occ, *sent, *recv;
  unsigned char *near;

  PetscFunctionBeginUser;
  SpamCellGridInit(&box, a->h, &g);
  for (int d = 0; d < 3; d++) w[d] = box.len[d] / g.ncell[d];
  PetscCheck(P <= g.ncell[0] * g.ncell[1] * g.ncell[2], PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "%d pieces of %d cells", P, g.ncell[0] * g.ncell[1] * g.ncell[2]);
  PetscCall(PetscMalloc7(g.ncell[0] * g.ncell[1] * g.ncell[2], &owner, P, &lo, P, &hi, P, &cells, P, &stamp, P, &from, P, &to));
  PetscCall(CutCells(&g, P, owner, lo, hi, cells));
  for (int r = 0; r < P; r++) stamp[r] = -1, from[r] = to[r] = 0;
  for (int r = 0; r < P; r++) Neighbours(&g, w, a->h + a->skin, owner, r, lo[r], hi[r], stamp, from, to);
  PetscCall(PetscCalloc1(P, &surface));
  Surfaces(&g, w, owner, surface);
  PetscCall(PetscCalloc7(P, &halo, (size_t)P * P, &near, P, &occ, P, &sent, P, &recv, P, &cells_to, P, &cfrom));
  PetscCall(SampledHalo(&g, w[0], a->h + a->skin - a->inset, (int)a->samples, owner, P, halo, near));
  PetscCall(SelectionCells(&g, w[0], a->h + a->skin, box.len[0], owner, P, (const int(*)[3])lo, (const int(*)[3])hi, occ, sent, cells_to, recv));
  for (int r = 0; r < P; r++) { /* cfrom[r]: the pieces in r's halo; stamp[s]: the pieces whose halo s is in */
    cfrom[r] = 0, stamp[r] = 0;
  }
  for (int r = 0; r < P; r++)
    for (int s = 0; s < P; s++) cfrom[r] += near[(size_t)r * P + s], stamp[s] += near[(size_t)r * P + s];
  printf("{\"mode\": \"geometry\", \"side\": %d, \"N\": %.0f, \"P\": %d, \"h\": %.17g, \"skin\": %.17g, \"inset\": %.17g, \"samples\": %d, \"cells\": [%d, %d, %d], \"cell_width\": [%.17g, %.17g, %.17g], \"select_cells\": %d,\n \"pieces\": [\n", (int)a->side, pow((double)a->side, 3), P, (double)a->h, (double)a->skin, (double)a->inset, (int)a->samples,
         g.ncell[0], g.ncell[1], g.ncell[2], w[0], w[1], w[2], PetscMax(1, (int)(box.len[0] / (a->h + a->skin))));
  for (int r = 0; r < P; r++)
    printf("  {\"cells\": %d, \"lo\": [%.17g, %.17g, %.17g], \"hi\": [%.17g, %.17g, %.17g], \"ranks_from\": %d, \"ranks_to\": %d, \"surface\": %.17g, \"halo_cells\": %.17g, \"ranks_from_cells\": %d, \"ranks_to_cells\": %d, \"occupied_cells\": %.0f, \"cells_sent\": %.0f, \"ranks_sent_cells\": %d, \"cells_received\": %.0f}%s\n", cells[r], lo[r][0] * w[0], lo[r][1] * w[1], lo[r][2] * w[2], (hi[r][0] + 1) * w[0], (hi[r][1] + 1) * w[1], (hi[r][2] + 1) * w[2], from[r], to[r], surface[r], halo[r], cfrom[r], stamp[r], occ[r], sent[r], cells_to[r], recv[r], r + 1 < P ? "," : "");
  printf(" ]}\n");
  PetscCall(PetscFree7(owner, lo, hi, cells, stamp, from, to));
  PetscCall(PetscFree7(halo, near, occ, sent, recv, cells_to, cfrom));
  PetscCall(PetscFree(surface));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  Args        a;
  PetscMPIInt size;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(ReadArgs(&a));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  if (a.geometry) {
    PetscCheck(size == 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "-geometry runs in one process");
    PetscCall(Geometry(&a));
  } else PetscCall(Ranks(PETSC_COMM_WORLD, &a));
  PetscCall(PetscFinalize());
  return 0;
}
