/* Canonical full rows of the neighbour list (-reproducible): each local particle lists
 * every partner within the list range -- local particles, periodic images and other
 * ranks' particles alike -- sorted by the partner's key (gid, image shift). A pass that
 * sums a row in row order, with no Newton update of the partner, then adds the same
 * terms in the same order whichever rank holds the partner, whether it is a local
 * particle or a ghost slot, and whichever thread takes the row: its bits do not depend on
 * the decomposition or on -threads. Every separation is u_i - u_j of two slots with no
 * minimum image (periodic directions are ghost images), the same expression on every
 * rank count (the remote slots hold the owner's u plus s L, as a local image does).
 *
 * The rows are built in two passes over the cells (count, then fill and sort), each row
 * by one thread, so the list is the same for any thread count; the second pass sorts a
 * row by a bottom-up merge sort (rows hold 25-30 partners in 2D, 150 in 3D: an insertion
 * sort of a row in random order would cost ~n^2/4 moves). */
#include <spam/neighbours.h>
#include <limits.h>
#include <string.h>
#include <omp.h>

PetscErrorCode SpamNeighboursSetCanonical(SpamNeighbours *nl, const PetscInt64 *gid)
{
  PetscFunctionBeginUser;
  PetscCheck(nl->builds == 0, PETSC_COMM_SELF, PETSC_ERR_ORDER, "set the canonical rows before the first build");
  PetscCheck(gid || nl->n == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "canonical rows need the particles' global ids");
  nl->canonical = PETSC_TRUE;
  nl->gid       = gid;
  PetscCall(PetscMalloc1(nl->n + 1, &nl->cstart));
  nl->cstart[0] = 0;
  PetscFunctionReturn(0);
}

/* Room for the keys and the gid buffer of every slot (at builds only). */
static PetscErrorCode GrowKeys(SpamNeighbours *nl, int slots)
{
  PetscFunctionBeginUser;
  if (slots <= nl->kcap) PetscFunctionReturn(0);
  PetscCall(PetscFree2(nl->key, nl->gidbuf));
  nl->kcap = slots + slots / 4 + 16;
  PetscCall(PetscMalloc2(nl->kcap, &nl->key, nl->kcap, &nl->gidbuf));
  PetscFunctionReturn(0);
}

/* Sign of a ghost's shift along d: the image s_d in {-1, 0, 1}. */
static int ShiftSign(double shift)
{
  return (shift > 0.0) - (shift < 0.0);
}

/* The key of every slot: gid * 27 + image code. A local particle is its own image (13);
 * a local ghost is its source's periodic image; a remote slot's gid arrives from its
 * owner through the halo (as a double: exact below 2^53) with the shift of the halo. */
static PetscErrorCode SlotKeys(SpamNeighbours *nl)
{
  const SpamGhosts *g  = &nl->ghosts;
  const SpamHalo   *h  = &g->halo;
  const int         n  = nl->n;
  const int         nr = g->n - g->nlocal;

  PetscFunctionBeginUser;
  PetscCall(GrowKeys(nl, n + g->n + 1));
  for (int i = 0; i < n; i++) {
    PetscCheck(nl->gid[i] >= 0 && nl->gid[i] < ((PetscInt64)1 << 53) / 27, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "global id %" PetscInt64_FMT " out of the range of canonical keys", nl->gid[i]);
    nl->key[i]    = nl->gid[i] * 27 + SpamImageCode(0, 0, 0);
    nl->gidbuf[i] = (double)nl->gid[i];
  }
  for (int k = 0; k < g->nlocal; k++) {
    PetscCheck(g->kind[k] == SPAM_GHOST_PERIODIC, PETSC_COMM_SELF, PETSC_ERR_SUP, "canonical rows take periodic images only (no mirror walls)");
    nl->key[n + k] = nl->gid[g->src[k]] * 27 + SpamImageCode(ShiftSign(g->shift[0][k]), ShiftSign(g->shift[1][k]), ShiftSign(g->shift[2][k]));
  }
  PetscCall(SpamHaloForward(h, 1, nl->gidbuf, nl->gidbuf + n)); /* collective; nothing on one rank */
  for (int q = 0; q < nr; q++) {
    const signed char *s = h->ghost_shift[q];
    nl->key[n + g->nlocal + q] = (PetscInt64)nl->gidbuf[n + q] * 27 + SpamImageCode(s[0], s[1], s[2]);
  }
  PetscFunctionReturn(0);
}

#define SCAN_CHUNK 256 /* candidates whose distances one loop computes */

/* Squared separations of local i and the cell-ordered candidates k0 .. k0 + m - 1 into
 * r2[] (i itself, if among them, at infinity): contiguous reads of the positions in cell
 * order, a loop the compiler vectorises (dim is a literal at each call). */
static inline __attribute__((always_inline)) void LocalDistances(const int dim, const SpamNeighbours *nl, int i, int k0, int m, double *r2)
{
  const double *u0 = nl->ucell[0] + k0, *u1 = dim > 1 ? nl->ucell[1] + k0 : u0, *u2 = dim > 2 ? nl->ucell[2] + k0 : u0;
  const double  x = nl->u[0][i], y = dim > 1 ? nl->u[1][i] : 0.0, z = dim > 2 ? nl->u[2][i] : 0.0;
  for (int c = 0; c < m; c++) {
    const double dx = x - u0[c], dy = dim > 1 ? y - u1[c] : 0.0, dz = dim > 2 ? z - u2[c] : 0.0;
    r2[c]           = dx * dx + dy * dy + dz * dz;
  }
  if (nl->slot[i] >= k0 && nl->slot[i] < k0 + m) r2[nl->slot[i] - k0] = INFINITY;
}

/* Squared separation of local i and ghost slot j. */
static inline double GhostDist2(const SpamNeighbours *nl, int i, int j)
{
  double r2 = 0.0;
  for (int d = 0; d < nl->dim; d++) {
    const double dx = nl->u[d][i] - nl->u[d][j];
    r2 += dx * dx;
  }
  return r2;
}

/* The partners of local i within the list range, in cell order (local particles of each
 * run of adjacent cells, then its ghosts), written to row[] when row is not NULL (which needs room
 * for SCAN_CHUNK entries beyond them: the writes are branchless, each candidate is
 * written and the count moves on for a hit); returns how many. */
static inline __attribute__((always_inline)) int ScanRowDim(const int dim, const SpamNeighbours *nl, int i, int *row)
{
  int       adj[27], r0[27], r1[27], nr = 0, m = 0;
  double    r2[SCAN_CHUNK];
  const int na = SpamNeighboursAdjacentCells(nl, &nl->lbox, nl->cell_of[i], adj);

  /* Cells of consecutive indices are contiguous in cell_list (and in the ghosts' list):
   * one range each (3 in 2D, 9 in 3D instead of 9 and 27 cells). */
  for (int a = 0; a < na; a++) {
    if (nr > 0 && adj[a] == adj[a - 1] + 1) r1[nr - 1] = adj[a] + 1;
    else {
      r0[nr]   = adj[a];
      r1[nr++] = adj[a] + 1;
    }
  }
  for (int a = 0; a < nr; a++) {
    const int kend = nl->cell_start[r1[a]];
    for (int k0 = nl->cell_start[r0[a]]; k0 < kend; k0 += SCAN_CHUNK) {
      const int mk = PetscMin(SCAN_CHUNK, kend - k0);
      LocalDistances(dim, nl, i, k0, mk, r2);
      if (row)
        for (int q = 0; q < mk; q++) {
          row[m] = nl->cell_list[k0 + q];
          m += r2[q] < nl->rc2;
        }
      else
        for (int q = 0; q < mk; q++) m += r2[q] < nl->rc2;
    }
    if (!nl->ghosts.n) continue;
    for (int q = nl->gcell_start[r0[a]]; q < nl->gcell_start[r1[a]]; q++) {
      const int j = nl->n + nl->gcell_list[q];
      if (!(GhostDist2(nl, i, j) < nl->rc2)) continue;
      if (row) row[m] = j;
      m++;
    }
  }
  return m;
}

static int ScanRow(const SpamNeighbours *nl, int i, int *row)
{
  switch (nl->dim) {
  case 1: return ScanRowDim(1, nl, i, row);
  case 2: return ScanRowDim(2, nl, i, row);
  default: return ScanRowDim(3, nl, i, row);
  }
}

#define SORT_RUN 8 /* runs of this length are sorted by insertion first */

/* Merges the sorted halves a[lo, mid) and a[mid, hi) into out[lo, hi) by key. */
static void Merge(const PetscInt64 *key, const int *a, int lo, int mid, int hi, int *out)
{
  int p = lo, q = mid, o = lo;
  while (p < mid && q < hi) out[o++] = key[a[q]] < key[a[p]] ? a[q++] : a[p++];
  while (p < mid) out[o++] = a[p++];
  while (q < hi) out[o++] = a[q++];
}

/* Sorts the slots row[0, m) by their keys (unique within a row: a partner image occurs
 * once); tmp has room for m. */
static void SortRow(const PetscInt64 *key, int *row, int m, int *tmp)
{
  int *src = row, *dst = tmp;

  for (int r0 = 0; r0 < m; r0 += SORT_RUN) {
    const int r1 = PetscMin(r0 + SORT_RUN, m);
    for (int a = r0 + 1; a < r1; a++) {
      const int t = row[a];
      int       b = a - 1;
      while (b >= r0 && key[row[b]] > key[t]) {
        row[b + 1] = row[b];
        b--;
      }
      row[b + 1] = t;
    }
  }
  for (int w = SORT_RUN; w < m; w *= 2) {
    for (int lo = 0; lo < m; lo += 2 * w) Merge(key, src, lo, PetscMin(lo + w, m), PetscMin(lo + 2 * w, m), dst);
    int *t = src;
    src    = dst;
    dst    = t;
  }
  if (src != row) memcpy(row, src, (size_t)m * sizeof(int));
}

/* Room for the rows (total entries) and each thread's scratch: a row as the scan writes
 * it (longest + SCAN_CHUNK) and the merge sort's second buffer, csort_row each. */
static PetscErrorCode ReserveRows(SpamNeighbours *nl, size_t total, int longest)
{
  PetscFunctionBeginUser;
  PetscCheck(total <= (size_t)INT_MAX, PETSC_COMM_SELF, PETSC_ERR_MEM, "the canonical rows would hold more than %d entries (%zu needed)", INT_MAX, total);
  if (total + 1 > nl->ccap) {
    nl->ccap = PetscMin(total + total / 4 + 64, (size_t)INT_MAX);
    PetscCall(PetscFree(nl->cnbr));
    PetscCall(PetscMalloc1(nl->ccap, &nl->cnbr));
    nl->grows++;
  }
  if (longest + SCAN_CHUNK > nl->csort_row) {
    nl->csort_row = longest + longest / 4 + SCAN_CHUNK + 16;
    PetscCall(PetscFree(nl->csort));
    PetscCall(PetscMalloc1(2 * (size_t)nl->threads * nl->csort_row, &nl->csort));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursBuildCanonical(SpamNeighbours *nl)
{
  const int n = nl->n, T = nl->threads;
  int       longest = 0;

  PetscFunctionBeginUser;
  if (!SpamNeighboursCanonical(nl)) PetscFunctionReturn(0);
  for (int d = 0; d < nl->dim; d++) PetscCheck(!nl->lbox.periodic[d], PETSC_COMM_SELF, PETSC_ERR_ORDER, "canonical rows need every periodic direction as ghost images (direction %d is the minimum image's)", d);
  PetscCall(SlotKeys(nl));
#pragma omp parallel for if (T > 1) num_threads(T) schedule(static) reduction(max : longest)
  for (int i = 0; i < n; i++) {
    nl->cstart[i + 1] = ScanRow(nl, i, NULL);
    longest           = PetscMax(longest, nl->cstart[i + 1]);
  }
  nl->cstart[0] = 0;
  {
    size_t total = 0;
    for (int i = 0; i < n; i++) {
      total += (size_t)nl->cstart[i + 1];
      PetscCheck(total <= (size_t)INT_MAX, PETSC_COMM_SELF, PETSC_ERR_MEM, "the canonical rows would hold more than %d entries", INT_MAX);
      nl->cstart[i + 1] = (int)total;
    }
    PetscCall(ReserveRows(nl, total, longest));
    nl->ncpairs = total;
  }
#pragma omp parallel num_threads(T) if (T > 1)
  {
    int *scan = nl->csort + 2 * (size_t)omp_get_thread_num() * nl->csort_row, *tmp = scan + nl->csort_row;
#pragma omp for schedule(static)
    for (int i = 0; i < n; i++) {
      const int m = nl->cstart[i + 1] - nl->cstart[i];
      (void)ScanRow(nl, i, scan);
      SortRow(nl->key, scan, m, tmp);
      memcpy(nl->cnbr + nl->cstart[i], scan, (size_t)m * sizeof(int));
    }
  }
  PetscFunctionReturn(0);
}
