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
 * A row is sorted by a bottom-up merge sort (rows hold 30-35 partners in 2D, about 90 in
 * 3D: an insertion sort of a row in random order would cost ~n^2/4 moves). */
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
  PetscCall(PetscMalloc2(nl->n + 1, &nl->cstart, nl->n + 1, &nl->ccur));
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

/* Squared separation of local i and slot j (no minimum image: see the top). */
static inline double Dist2(const SpamNeighbours *nl, int i, int j)
{
  double r2 = 0.0;
  for (int d = 0; d < nl->dim; d++) {
    const double dx = nl->u[d][i] - nl->u[d][j];
    r2 += dx * dx;
  }
  return r2;
}

/* The ghost slots within the list range of local i, from the ghosts binned in its
 * adjacent cells, written to row[] when row is not NULL; returns how many. */
static int GhostPartners(const SpamNeighbours *nl, int i, int *row)
{
  int adj[27], m = 0;

  if (!nl->ghosts.n) return 0;
  const int na = SpamNeighboursAdjacentCells(nl, &nl->lbox, nl->cell_of[i], adj);
  for (int a = 0; a < na; a++)
    for (int q = nl->gcell_start[adj[a]]; q < nl->gcell_start[adj[a] + 1]; q++) {
      const int j = nl->n + nl->gcell_list[q];
      if (!(Dist2(nl, i, j) < nl->rc2)) continue;
      if (row) row[m] = j;
      m++;
    }
  return m;
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

/* Room for the rows (total entries) and each thread's merge-sort scratch (longest row). */
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
  if (longest > nl->csort_row) {
    nl->csort_row = longest + longest / 4 + 16;
    PetscCall(PetscFree(nl->csort));
    PetscCall(PetscMalloc1((size_t)nl->threads * nl->csort_row, &nl->csort));
  }
  PetscFunctionReturn(0);
}

/* The rows in three parts: the local partners are the half list's pairs (found once, at
 * the same positions with the same rc test) entered in both rows -- a scan of the cells
 * would test every local candidate twice over, four times the half list's work in 3D --,
 * then each row's ghost partners from the binned ghosts, then each row sorted by key. Row
 * i's entries before sorting depend on the half list only, which is the same for any
 * thread count; after sorting they are unique (a partner image occurs once). */
PetscErrorCode SpamNeighboursBuildCanonical(SpamNeighbours *nl)
{
  const int n = nl->n, T = nl->threads;
  int      *at = nl->ccur, longest = 0;

  PetscFunctionBeginUser;
  if (!SpamNeighboursCanonical(nl)) PetscFunctionReturn(0);
  for (int d = 0; d < nl->dim; d++) PetscCheck(!nl->lbox.periodic[d], PETSC_COMM_SELF, PETSC_ERR_ORDER, "canonical rows need every periodic direction as ghost images (direction %d is the minimum image's)", d);
  PetscCall(SlotKeys(nl));
  /* Counts: ghost partners (at[i]), own half row, and the half rows i appears in. */
#pragma omp parallel for if (T > 1) num_threads(T) schedule(static)
  for (int i = 0; i < n; i++) at[i] = GhostPartners(nl, i, NULL);
  for (int i = 0; i < n; i++) nl->cstart[i + 1] = at[i] + nl->start[i + 1] - nl->start[i];
  for (size_t p = 0; p < nl->npairs; p++) nl->cstart[nl->nbr[p] + 1]++;
  nl->cstart[0] = 0;
  {
    size_t total = 0;
    for (int i = 0; i < n; i++) {
      const int m = nl->cstart[i + 1];
      longest     = PetscMax(longest, m);
      total += (size_t)m;
      PetscCheck(total <= (size_t)INT_MAX, PETSC_COMM_SELF, PETSC_ERR_MEM, "the canonical rows would hold more than %d entries", INT_MAX);
      nl->cstart[i + 1] = (int)total;
    }
    PetscCall(ReserveRows(nl, total, longest));
    nl->ncpairs = total;
  }
  /* Local partners: each half-list pair into both rows (serial: rows receive from others). */
  for (int i = 0; i < n; i++) at[i] = nl->cstart[i];
  for (int i = 0; i < n; i++)
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j = nl->nbr[p];
      nl->cnbr[at[i]++] = j;
      nl->cnbr[at[j]++] = i;
    }
#pragma omp parallel num_threads(T) if (T > 1)
  {
    int *tmp = nl->csort + (size_t)omp_get_thread_num() * nl->csort_row;
#pragma omp for schedule(static)
    for (int i = 0; i < n; i++) {
      int *row = nl->cnbr + nl->cstart[i];
      (void)GhostPartners(nl, i, nl->cnbr + at[i]);
      SortRow(nl->key, row, nl->cstart[i + 1] - nl->cstart[i], tmp);
    }
  }
  PetscFunctionReturn(0);
}
