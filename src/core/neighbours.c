/* Cell binning and the half Verlet list with a skin. */
#include <spam/neighbours.h>
#include <spam/huge_pages.h>
#include <spam/zero_pages.h>
#include <float.h>
#include <limits.h>
#include <string.h>

/* Most cells of a list: cell_start is indexed by int, and a cell array far larger than
 * the particle count only costs memory and a longer counting sort. Above the larger of
 * these the cells are made wider (never narrower than the list range, so the stencil
 * still finds every pair). */
#define SPAM_CELLS_MIN_CAP  1048576.0 /* 2^20 cells: 4 MB of cell_start */
#define SPAM_CELLS_PER_PART 64.0

/* Cells per direction: the edge over the list range rc, at least one, computed in
 * double; while their product exceeds the cap, the largest count is halved. */
static PetscErrorCode CellCounts(int n, const SpamBox *box, double rc, int ncell[3])
{
  const double cap = PetscMin(PetscMax(SPAM_CELLS_MIN_CAP, SPAM_CELLS_PER_PART * n), (double)(INT_MAX / 2));
  double       nc[3] = {1, 1, 1};

  PetscFunctionBeginUser;
  PetscCheck(rc > 0.0 && isfinite(rc), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "the list range %g must be positive and finite", rc);
  for (int d = 0; d < box->dim; d++) {
    PetscCheck(box->len[d] > 0.0 && isfinite(box->len[d]) && isfinite(box->lo[d]), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "box edge %d (corner %g, length %g) must be finite and positive", d, box->lo[d], box->len[d]);
    nc[d] = PetscMin(PetscMax(1.0, floor(box->len[d] / rc)), cap);
  }
  for (;;) {
    int big = 0;
    if (nc[0] * nc[1] * nc[2] <= cap) break;
    for (int d = 1; d < 3; d++)
      if (nc[d] > nc[big]) big = d;
    nc[big] = floor(0.5 * nc[big]);
  }
  for (int d = 0; d < 3; d++) ncell[d] = (int)nc[d];
  PetscFunctionReturn(0);
}

/* PetscCalloc for the large arrays: the zeros written after the huge-page advice. */
static PetscErrorCode ZeroedHuge(size_t count, size_t size, void **a)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMalloc(count * size, a));
  SpamAdviseHugePages(*a, count * size);
  PetscCall(PetscMemzero(*a, count * size));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursCreate(int n, const SpamBox *box, double cutoff, double skin, SpamNeighbours *nl)
{
  const double rc = cutoff + skin;

  PetscFunctionBeginUser;
  PetscCheck(n >= 0 && (double)n * 16.0 < (double)SIZE_MAX / sizeof(int), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "%d particles is out of range", n);
  for (int d = 0; d < box->dim; d++)
    PetscCheck(!box->periodic[d] || skin < 0.5 * box->len[d], PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "the neighbour skin %g must be below half the periodic edge %g", skin, box->len[d]);
  PetscCall(PetscMemzero(nl, sizeof *nl));
  nl->dim    = box->dim;
  nl->n      = n;
  nl->threads = 1;
  nl->cutoff = cutoff;
  nl->skin   = skin;
  nl->rc2    = rc * rc;
  nl->ncells = 1;
  PetscCall(CellCounts(n, box, rc, nl->ncell));
  for (int d = 0; d < 3; d++) {
    nl->cellw[d] = d < box->dim ? box->len[d] / nl->ncell[d] : 1.0;
    nl->ncells *= nl->ncell[d];
  }
  nl->cap = (size_t)PetscMax(n, 1) * 16;
  PetscCall(PetscMalloc5(n, &nl->cell_of, nl->ncells + 1, &nl->cell_start, n, &nl->cell_list, n + 1, &nl->start, n + 1, &nl->slot));
  PetscCall(PetscMalloc1(nl->cap, &nl->nbr));
  nl->nblk = (n + SPAM_ROW_BLOCK - 1) / SPAM_ROW_BLOCK;
  PetscCall(PetscMalloc2(nl->nblk + 1, &nl->blk_zero, nl->nblk + 1, &nl->blk_final));
  PetscCall(PetscCalloc1(n + 1, &nl->image));
  PetscCall(PetscMalloc1(n + 1, &nl->gstart));
  SpamZeroPages(nl->gstart, (size_t)(n + 1) * sizeof(int)); /* read by every pass, written only with ghost rows */
  /* the arrays that every right-hand side streams: huge pages before their first write
   * (not the pair rows, whose room is larger than what they hold: a huge page across the
   * end of the rows would make up to 2 MiB of unused room resident) */
  SpamAdviseHugePages(nl->cell_list, (size_t)n * sizeof(int));
  SpamAdviseHugePages(nl->start, (size_t)(n + 1) * sizeof(int));
  nl->lbox = *box;
  nl->im   = SpamBoxImage(box);
  nl->ucap = n + 1;
  for (int d = 0; d < 3; d++) nl->ucell[d] = NULL;
  for (int d = 0; d < box->dim; d++) {
    PetscCall(PetscMalloc1(n + 1, &nl->ucell[d]));
    SpamAdviseHugePages(nl->ucell[d], (size_t)(n + 1) * sizeof(double));
  }
  /* The box's directions only: an array for a direction the box lacks would be zeros
   * written and never needed (24 bytes a particle in 2D). */
  for (int d = 0; d < 3; d++) nl->u[d] = nl->xref[d] = nl->off[d] = NULL;
  for (int d = 0; d < box->dim; d++) {
    PetscCall(ZeroedHuge(n + 1, sizeof(double), (void **)&nl->u[d]));
    PetscCall(ZeroedHuge(n + 1, sizeof(double), (void **)&nl->xref[d]));
    PetscCall(ZeroedHuge(n + 1, sizeof(double), (void **)&nl->off[d]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursSetThreads(SpamNeighbours *nl, int threads)
{
  PetscFunctionBeginUser;
  PetscCheck(threads >= 1 && threads <= SPAM_MAX_THREADS, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "threads %d must be from 1 to %d", threads, SPAM_MAX_THREADS);
  PetscCheck(nl->builds == 0 && !nl->tbuf, PETSC_COMM_SELF, PETSC_ERR_ORDER, "set the threads before the first build");
  nl->threads = threads;
  if (threads == 1) PetscFunctionReturn(0);
  PetscCall(PetscCalloc1(threads, &nl->tbuf));
  for (int t = 0; t < threads; t++) {
    nl->tbuf[t].cap = nl->cap / (size_t)threads + 16;
    PetscCall(PetscMalloc1(nl->tbuf[t].cap, &nl->tbuf[t].nbr));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursDestroy(SpamNeighbours *nl)
{
  PetscFunctionBeginUser;
  for (int t = 0; nl->tbuf && t < nl->threads; t++) PetscCall(PetscFree(nl->tbuf[t].nbr));
  PetscCall(PetscFree(nl->tbuf));
  PetscCall(PetscFree5(nl->cell_of, nl->cell_start, nl->cell_list, nl->start, nl->slot));
  PetscCall(PetscFree(nl->nbr));
  PetscCall(PetscFree2(nl->blk_zero, nl->blk_final));
  PetscCall(PetscFree(nl->image));
  PetscCall(PetscFree(nl->gstart));
  PetscCall(PetscFree(nl->gnbr));
  PetscCall(PetscFree(nl->tstart));
  PetscCall(PetscFree(nl->trows));
  PetscCall(PetscFree2(nl->gcell_start, nl->gcell_list));
  PetscCall(PetscFree(nl->gcell_near));
  PetscCall(SpamGhostsDestroy(&nl->ghosts));
  PetscCall(PetscFree2(nl->cstart, nl->ccur));
  PetscCall(PetscFree(nl->cnbr));
  PetscCall(PetscFree(nl->csort));
  PetscCall(PetscFree2(nl->key, nl->gidbuf));
  for (int d = 0; d < 3; d++) PetscCall(PetscFree(nl->ucell[d]));
  for (int d = 0; d < 3; d++) {
    PetscCall(PetscFree(nl->u[d]));
    PetscCall(PetscFree(nl->xref[d]));
    PetscCall(PetscFree(nl->off[d]));
  }
  PetscFunctionReturn(0);
}

/* Cell coordinate along d; points outside an open box fall into the edge cells, which
 * keeps nearby points in adjacent cells. Clamped in floating point before the
 * conversion, which is undefined for NaN and out-of-range values: NaN fails the first
 * test and lands in cell 0 (positions are checked finite before a build; this keeps a
 * direct caller in range too). */
static int CellCoordinate(const SpamNeighbours *nl, int d, double u)
{
  const double c = floor(u / nl->cellw[d]);
  if (!(c >= 0.0)) return 0;
  if (c >= (double)(nl->ncell[d] - 1)) return nl->ncell[d] - 1;
  return (int)c;
}

int SpamNeighboursCellOf(const SpamNeighbours *nl, const SpamBox *box, const double *u)
{
  int c = 0;
  for (int d = box->dim - 1; d >= 0; d--) c = c * nl->ncell[d] + CellCoordinate(nl, d, u[d]);
  return c;
}

/* The distinct cell coordinates next to c along d (c itself included). With fewer than
 * three periodic cells the wrapped neighbours coincide, so every cell is listed once. */
static int AdjacentAlong(const SpamNeighbours *nl, const SpamBox *box, int d, int c, int *out)
{
  const int nc = nl->ncell[d];
  int       k  = 0;
  if (d >= box->dim) {
    out[k++] = 0;
  } else if (box->periodic[d] && nc < 3) {
    for (int a = 0; a < nc; a++) out[k++] = a;
  } else if (box->periodic[d]) {
    out[k++] = (c + nc - 1) % nc;
    out[k++] = c;
    out[k++] = (c + 1) % nc;
  } else {
    for (int a = PetscMax(0, c - 1); a <= PetscMin(nc - 1, c + 1); a++) out[k++] = a;
  }
  return k;
}

/* The cell coordinates of a cell index (x fastest). */
static void CellCoordinates(const SpamNeighbours *nl, int cell, int c[3])
{
  c[0] = cell % nl->ncell[0];
  c[1] = (cell / nl->ncell[0]) % nl->ncell[1];
  c[2] = cell / (nl->ncell[0] * nl->ncell[1]);
}

int SpamNeighboursAdjacentCells(const SpamNeighbours *nl, const SpamBox *box, int cell, int *adj)
{
  int c[3], a[3][3], na[3], k = 0;
  CellCoordinates(nl, cell, c);
  for (int d = 0; d < 3; d++) na[d] = AdjacentAlong(nl, box, d, c[d], a[d]);
  for (int z = 0; z < na[2]; z++)
    for (int y = 0; y < na[1]; y++)
      for (int x = 0; x < na[0]; x++) adj[k++] = (a[2][z] * nl->ncell[1] + a[1][y]) * nl->ncell[0] + a[0][x];
  return k;
}

/* Whether a particle in this cell can have a neighbour across a periodic face: its cell
 * touches that face (or the direction has fewer than three cells). The others' listed
 * separations u_i - u_j need no minimum image until the next build. */
static unsigned char CellSeesImage(const SpamNeighbours *nl, const SpamBox *box, int cell)
{
  int rem = cell;
  for (int d = 0; d < box->dim; d++) {
    const int nc = nl->ncell[d], c = rem % nc;
    rem /= nc;
    if (box->periodic[d] && (nc < 3 || c == 0 || c == nc - 1)) return 1;
  }
  return 0;
}

/* Counting sort of the particles by cell; within a cell, by index (deterministic). */
static void BinParticles(SpamNeighbours *nl, const SpamBox *box)
{
  /* The cells are found by all threads; the counting sort itself is serial. */
#pragma omp parallel for if (nl->threads > 1) num_threads(nl->threads) schedule(static)
  for (int i = 0; i < nl->n; i++) {
    double u[3] = {0.0, 0.0, 0.0};
    for (int d = 0; d < box->dim; d++) u[d] = nl->u[d][i];
    nl->cell_of[i] = SpamNeighboursCellOf(nl, box, u);
    nl->image[i]   = CellSeesImage(nl, box, nl->cell_of[i]);
  }
  for (int c = 0; c <= nl->ncells; c++) nl->cell_start[c] = 0;
  for (int i = 0; i < nl->n; i++) nl->cell_start[nl->cell_of[i] + 1]++;
  for (int c = 0; c < nl->ncells; c++) nl->cell_start[c + 1] += nl->cell_start[c];
  for (int i = 0; i < nl->n; i++) {
    const int k   = nl->cell_start[nl->cell_of[i]]++;
    nl->cell_list[k] = i;
    nl->slot[i]      = k;
  }
  for (int c = nl->ncells; c > 0; c--) nl->cell_start[c] = nl->cell_start[c - 1];
  nl->cell_start[0] = 0;
  /* Positions in cell order, so that a cell's candidates are read contiguously. */
  for (int d = 0; d < box->dim; d++) {
#pragma omp parallel for if (nl->threads > 1) num_threads(nl->threads) schedule(static)
    for (int k = 0; k < nl->n; k++) nl->ucell[d][k] = nl->u[d][nl->cell_list[k]];
  }
}

/* Room for `need` entries in b; grows by half when short (rare: at the first build, or
 * when the gas compresses), counted in grows. Never called inside a parallel region. */
static PetscErrorCode Reserve(SpamPairBuffer *b, size_t need, long *grows)
{
  PetscFunctionBeginUser;
  if (need <= b->cap) PetscFunctionReturn(0);
  /* Row starts are int: a list of more pairs could not be indexed. */
  PetscCheck(need <= (size_t)INT_MAX, PETSC_COMM_SELF, PETSC_ERR_MEM, "the neighbour list would hold more than %d pairs (%zu needed): the particles are too many or too densely packed for the kernel range", INT_MAX, need);
  b->cap = PetscMin(PetscMax(need, b->cap + b->cap / 2 + 16), (size_t)INT_MAX);
  PetscCall(PetscRealloc(b->cap * sizeof(int), &b->nbr));
  (*grows)++;
  PetscFunctionReturn(0);
}

#define SPAM_BUILD_CHUNK 256

/* Appends the candidates in the cell_list ranges [r0[a], r1[a]) that lie within the list
 * range of particle i. A first loop computes the squared distances of up to
 * SPAM_BUILD_CHUNK candidates, read contiguously in cell order (it vectorises); a second
 * appends them without a branch (every candidate is written, the count advances only
 * for a hit: a branch would be a coin flip). dim and img (the minimum image) are
 * literals at each call: one loop per combination. */
static inline __attribute__((always_inline)) size_t AppendRow(const int dim, const int img, const SpamNeighbours *nl, const SpamImage *im, int i, const int *r0, const int *r1, int nr, int *nbr, size_t np)
{
  double       r2[SPAM_BUILD_CHUNK];
  const double rc2 = nl->rc2;
  double       ui[3] = {0, 0, 0};
  for (int d = 0; d < dim; d++) ui[d] = nl->u[d][i];
  for (int a = 0; a < nr; a++) {
    for (int k0 = r0[a]; k0 < r1[a]; k0 += SPAM_BUILD_CHUNK) {
      const int     m  = PetscMin(SPAM_BUILD_CHUNK, r1[a] - k0);
      const int    *js = nl->cell_list + k0;
      const double *u0 = nl->ucell[0] + k0, *u1 = dim > 1 ? nl->ucell[1] + k0 : u0, *u2 = dim > 2 ? nl->ucell[2] + k0 : u0;
      for (int c = 0; c < m; c++) {
        const double dx = img ? SpamImageDelta(im, 0, ui[0] - u0[c]) : ui[0] - u0[c];
        const double dy = dim < 2 ? 0.0 : img ? SpamImageDelta(im, 1, ui[1] - u1[c]) : ui[1] - u1[c];
        const double dz = dim < 3 ? 0.0 : img ? SpamImageDelta(im, 2, ui[2] - u2[c]) : ui[2] - u2[c];
        r2[c]           = dx * dx + dy * dy + dz * dz;
      }
      for (int c = 0; c < m; c++) {
        nbr[np] = js[c];
        np += (size_t)(r2[c] < rc2);
      }
    }
  }
  return np;
}

/* The distance loop in AVX2 where the processor has it, as the pair passes (pair_pass.h's
 * SPAM_CLONES; the same bits: no contraction into FMAs): 4 candidates a vector instead of
 * 2. The sanitizer build (SPAM_ONE_ISA) compiles the baseline alone. */
#ifdef SPAM_ONE_ISA
#define SPAM_BUILD_CLONES
#else
#define SPAM_BUILD_CLONES __attribute__((target_clones("avx2", "default")))
#endif
SPAM_BUILD_CLONES static size_t AppendRowDim(int dim, const SpamNeighbours *nl, const SpamImage *im, int i, const int *r0, const int *r1, int nr, int *nbr, size_t np)
{
  const int img = nl->image[i];
  switch (dim) {
  case 1: return img ? AppendRow(1, 1, nl, im, i, r0, r1, nr, nbr, np) : AppendRow(1, 0, nl, im, i, r0, r1, nr, nbr, np);
  case 2: return img ? AppendRow(2, 1, nl, im, i, r0, r1, nr, nbr, np) : AppendRow(2, 0, nl, im, i, r0, r1, nr, nbr, np);
  default: return img ? AppendRow(3, 1, nl, im, i, r0, r1, nr, nbr, np) : AppendRow(3, 0, nl, im, i, r0, r1, nr, nbr, np);
  }
}

/* The 2D and 3D rows of particles whose cell sees no periodic image, in AVX2 intrinsics
 * where the processor has it: the distances of 4 candidates a vector and the hits packed
 * into the row by one byte shuffle (pshufb, from the comparison's 4-bit mask) and one
 * store, instead of a store, a compare and an add a candidate. The same rows, bit for bit:
 * the same differences, products and sums in the same order (no FMA; the 2D sum's + 0 * 0
 * of AppendRow leaves a sum of squares as it is), the same comparison, the same order of
 * hits. Velocity Verlet at N = 65536, 200 steps (51 builds, 43 % of the run's instructions
 * in them): 714 instructions a particle a build in AppendRowDim's AVX2 clone, 388 here with
 * the dispatch (callgrind). */
#if defined(__x86_64__) && !defined(SPAM_ONE_ISA)
#include <immintrin.h>
#define SPAM_APPEND_AVX2 1
/* For each 4-bit mask, the bytes of the set 32-bit lanes moved to the front. */
static const signed char pack4[16][16] = {{-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {4, 5, 6, 7, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 4, 5, 6, 7, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {8, 9, 10, 11, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 8, 9, 10, 11, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {4, 5, 6, 7, 8, 9, 10, 11, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, -1, -1, -1, -1},
                                            {12, 13, 14, 15, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 12, 13, 14, 15, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {4, 5, 6, 7, 12, 13, 14, 15, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 4, 5, 6, 7, 12, 13, 14, 15, -1, -1, -1, -1},
                                            {8, 9, 10, 11, 12, 13, 14, 15, -1, -1, -1, -1, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 8, 9, 10, 11, 12, 13, 14, 15, -1, -1, -1, -1},
                                            {4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, -1, -1, -1, -1},
                                            {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}};

static inline __attribute__((always_inline, target("avx2"))) size_t AppendRowAvx2(const int dim, const SpamNeighbours *nl, int i, const int *r0, const int *r1, int nr, int *nbr, size_t np)
{
  const double  rc2 = nl->rc2, ui0 = nl->u[0][i], ui1 = nl->u[1][i], ui2 = dim > 2 ? nl->u[2][i] : 0.0;
  const __m256d x = _mm256_set1_pd(ui0), y = _mm256_set1_pd(ui1), z = _mm256_set1_pd(ui2), r = _mm256_set1_pd(rc2);
  for (int a = 0; a < nr; a++) {
    int k = r0[a];
    for (; k + 4 <= r1[a]; k += 4) {
      const __m256d dx = _mm256_sub_pd(x, _mm256_loadu_pd(nl->ucell[0] + k)), dy = _mm256_sub_pd(y, _mm256_loadu_pd(nl->ucell[1] + k));
      __m256d       d2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
      if (dim > 2) {
        const __m256d dz = _mm256_sub_pd(z, _mm256_loadu_pd(nl->ucell[2] + k));
        d2               = _mm256_add_pd(d2, _mm256_mul_pd(dz, dz));
      }
      const int     m  = _mm256_movemask_pd(_mm256_cmp_pd(d2, r, _CMP_LT_OQ));
      const __m128i js = _mm_loadu_si128((const __m128i *)(nl->cell_list + k));
      _mm_storeu_si128((__m128i *)(nbr + np), _mm_shuffle_epi8(js, _mm_loadu_si128((const __m128i *)pack4[m])));
      np += (size_t)__builtin_popcount((unsigned)m);
    }
    for (; k < r1[a]; k++) {
      const double dx = ui0 - nl->ucell[0][k], dy = ui1 - nl->ucell[1][k], dz = dim > 2 ? ui2 - nl->ucell[2][k] : 0.0;
      nbr[np]         = nl->cell_list[k];
      np += (size_t)((dim > 2 ? dx * dx + dy * dy + dz * dz : dx * dx + dy * dy) < rc2);
    }
  }
  return np;
}

static __attribute__((target("avx2"))) size_t AppendRow2Avx2(const SpamNeighbours *nl, int i, const int *r0, const int *r1, int nr, int *nbr, size_t np)
{
  return AppendRowAvx2(2, nl, i, r0, r1, nr, nbr, np);
}

static __attribute__((target("avx2"))) size_t AppendRow3Avx2(const SpamNeighbours *nl, int i, const int *r0, const int *r1, int nr, int *nbr, size_t np)
{
  return AppendRowAvx2(3, nl, i, r0, r1, nr, nbr, np);
}
#endif

/* Row i's candidates appended: by the AVX2 packing above where it applies, else AppendRow. */
static size_t AppendRowAny(int dim, const SpamNeighbours *nl, const SpamImage *im, int i, const int *r0, const int *r1, int nr, int *nbr, size_t np)
{
#ifdef SPAM_APPEND_AVX2
  if (dim >= 2 && !nl->image[i] && __builtin_cpu_supports("avx2")) return dim == 2 ? AppendRow2Avx2(nl, i, r0, r1, nr, nbr, np) : AppendRow3Avx2(nl, i, r0, r1, nr, nbr, np);
#endif
  return AppendRowDim(dim, nl, im, i, r0, r1, nr, nbr, np);
}

/* Whether the half stencil below visits every adjacent pair of cells once: a periodic
 * direction needs three cells or more, or its neighbours -1 and +1 would coincide. */
static PetscBool HalfStencilValid(const SpamNeighbours *nl, const SpamBox *box)
{
  for (int d = 0; d < box->dim; d++)
    if (box->periodic[d] && nl->ncell[d] < 3) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* The half stencil of a cell: the cell itself, then the adjacent cells at offsets
 * (dz, dy, dx) after (0, 0, 0) in lexicographic order (one of each pair of opposite
 * offsets: 1 + 4 in 2D, 1 + 13 in 3D), as ranges of cell_list positions. Cells with
 * consecutive indices are contiguous in cell_list and merge into one range: in 2D the
 * stencil is two ranges away from periodic faces (the cell with its +x neighbour, and
 * the three cells of the row above), in 3D five. Range 0 starts with the cell itself. */
static int HalfStencilRanges(const SpamNeighbours *nl, const SpamBox *box, int cell, int *r0, int *r1)
{
  int c[3], nr = 0, last = -2;
  CellCoordinates(nl, cell, c);
  for (int dz = 0; dz <= (box->dim > 2); dz++)
    for (int dy = box->dim > 1 && dz > 0 ? -1 : 0; dy <= (box->dim > 1); dy++)
      for (int dx = dy > 0 || dz > 0 ? -1 : 0; dx <= 1; dx++) {
        const int o[3] = {dx, dy, dz};
        int       idx = 0, inside = 1;
        for (int d = 2; d >= 0; d--) {
          int a = c[d] + o[d];
          if (d < box->dim && box->periodic[d]) a = (a + nl->ncell[d]) % nl->ncell[d];
          inside &= a >= 0 && a < nl->ncell[d];
          idx = idx * nl->ncell[d] + a;
        }
        if (!inside) continue;
        if (idx == last + 1 && nr > 0) r1[nr - 1] = nl->cell_start[idx + 1];
        else {
          r0[nr]   = nl->cell_start[idx];
          r1[nr++] = nl->cell_start[idx + 1];
        }
        last = idx;
      }
  return nr;
}

/* The half stencils of the last few cells a run of rows met: the particles are in the
 * order of cells of width h, the list's cells are h + skin wide, so consecutive particles
 * go back and forth between a few list cells, and the ranges were found again at nearly
 * every row. */
#define SPAM_STENCIL_MEMO 4
typedef struct {
  int cell, nr, r0[14], r1[14];
} StencilMemo;

/* The rows from the half stencil: particle i takes the rest of its own cell after it
 * and the forward cells, so each pair is found once, in the row of either particle.
 * Against the full stencil with the j > i suffixes below, a build of N = 65536 took
 * 0.61 of the time (11.5 against 18.4 ms, five alternating runs).
 *
 * Both row builders append rows [i, i1) to b while it has room for the next row's
 * candidates, so that nothing is allocated inside a thread; start[r + 1] gets b's count
 * after row r. They return the first row not appended (i1 when all fitted) and the
 * room it needs in *need. */
static int AppendRowsHalf(SpamNeighbours *nl, const SpamBox *box, const SpamImage *im, int i, int i1, SpamPairBuffer *b, size_t *need)
{
  int          r0[14], r1[14], nr = 0, cell = -1, next = 0;
  StencilMemo memo[SPAM_STENCIL_MEMO];

  for (int k = 0; k < SPAM_STENCIL_MEMO; k++) memo[k].cell = -1;
  for (; i < i1; i++) {
    size_t cand = 0;
    if (nl->cell_of[i] != cell) {
      int k = 0;
      cell  = nl->cell_of[i];
      while (k < SPAM_STENCIL_MEMO && memo[k].cell != cell) k++;
      if (k == SPAM_STENCIL_MEMO) {
        k             = next;
        next          = (next + 1) % SPAM_STENCIL_MEMO;
        memo[k].cell  = cell;
        memo[k].nr    = HalfStencilRanges(nl, box, cell, memo[k].r0, memo[k].r1);
      }
      nr = memo[k].nr;
      memcpy(r0, memo[k].r0, (size_t)nr * sizeof *r0);
      memcpy(r1, memo[k].r1, (size_t)nr * sizeof *r1);
    }
    const int own = r0[0];
    r0[0]         = nl->slot[i] + 1;
    for (int a = 0; a < nr; a++) cand += (size_t)(r1[a] - r0[a]);
    if (b->n + cand > b->cap) {
      *need = b->n + cand;
      return i;
    }
    b->n             = AppendRowAny(box->dim, nl, im, i, r0, r1, nr, b->nbr, b->n);
    nl->start[i + 1] = (int)b->n;
    r0[0]            = own;
  }
  return i1;
}

/* First position in cell_list[k0, k1) holding a particle above i: a cell lists its
 * particles in increasing index, so the candidates j > i of a cell are a suffix. */
static int FirstAbove(const int *list, int k0, int k1, int i)
{
  while (k0 < k1) {
    const int mid = k0 + (k1 - k0) / 2;
    if (list[mid] > i) k1 = mid;
    else k0 = mid + 1;
  }
  return k0;
}

/* The rows from all adjacent cells, for boxes with fewer than three cells along a
 * periodic direction: particle i takes the candidates j > i, which are a suffix of each
 * cell. Along a run of particles in one cell i only grows, so the suffixes only move
 * forward; a new cell finds them by bisection. */
static int AppendRowsFull(SpamNeighbours *nl, const SpamBox *box, const SpamImage *im, int i, int i1, SpamPairBuffer *b, size_t *need)
{
  int adj[27], r0[27], r1[27], na = 0, cell = -1;

  for (; i < i1; i++) {
    const PetscBool fresh = nl->cell_of[i] != cell;
    size_t          cand  = 0;
    if (fresh) {
      cell = nl->cell_of[i];
      na   = SpamNeighboursAdjacentCells(nl, box, cell, adj);
      for (int a = 0; a < na; a++) r1[a] = nl->cell_start[adj[a] + 1];
    }
    for (int a = 0; a < na; a++) {
      if (fresh) r0[a] = FirstAbove(nl->cell_list, nl->cell_start[adj[a]], r1[a], i);
      else
        while (r0[a] < r1[a] && nl->cell_list[r0[a]] <= i) r0[a]++;
      cand += (size_t)(r1[a] - r0[a]);
    }
    if (b->n + cand > b->cap) {
      *need = b->n + cand;
      return i;
    }
    b->n             = AppendRowAny(box->dim, nl, im, i, r0, r1, na, b->nbr, b->n);
    nl->start[i + 1] = (int)b->n;
  }
  return i1;
}

/* The row builders work on a copy of b: the threads' buffers lie side by side, and
 * updating their counts in place would bounce one cache line between the cores. */
static int AppendRows(SpamNeighbours *nl, const SpamBox *box, const SpamImage *im, int i, int i1, SpamPairBuffer *b, size_t *need)
{
  SpamPairBuffer own = *b;
  const int      end = HalfStencilValid(nl, box) ? AppendRowsHalf(nl, box, im, i, i1, &own, need) : AppendRowsFull(nl, box, im, i, i1, &own, need);
  *b                 = own;
  return end;
}

/* One thread: the rows straight into the list, growing it when a row does not fit. */
static PetscErrorCode BuildRows(SpamNeighbours *nl, const SpamBox *box, const SpamImage *im)
{
  SpamPairBuffer b = {nl->nbr, nl->cap, 0};
  size_t         need;

  PetscFunctionBeginUser;
  for (int i = 0; i < nl->n;) {
    i = AppendRows(nl, box, im, i, nl->n, &b, &need);
    if (i < nl->n) PetscCall(Reserve(&b, need, &nl->grows));
  }
  nl->nbr    = b.nbr;
  nl->cap    = b.cap;
  nl->npairs = b.n;
  PetscFunctionReturn(0);
}

/* First row of build block t of T: n/T consecutive particles each (the pair counts are
 * not known before the build). */
static int BlockStart(const SpamNeighbours *nl, int T, int t)
{
  return (int)((size_t)nl->n * (size_t)t / (size_t)T);
}

/* T threads: thread t appends the rows of block t (n/T consecutive particles) to its own
 * buffer; a buffer that fills up is grown between parallel passes and its block
 * continued. The buffers are then copied into the list in block order and the row
 * starts shifted, so the list is the one a single thread builds. */
static PetscErrorCode BuildRowsThreaded(SpamNeighbours *nl, const SpamBox *box, const SpamImage *im)
{
  const int T = nl->threads;
  int       at[SPAM_MAX_THREADS], done;
  size_t    need[SPAM_MAX_THREADS], off[SPAM_MAX_THREADS + 1];

  PetscFunctionBeginUser;
  for (int t = 0; t < T; t++) {
    at[t]         = BlockStart(nl, T, t);
    nl->tbuf[t].n = 0;
  }
  do {
#pragma omp parallel for num_threads(T) schedule(static, 1)
    for (int t = 0; t < T; t++) {
      const int end = BlockStart(nl, T, t + 1);
      if (at[t] < end) at[t] = AppendRows(nl, box, im, at[t], end, &nl->tbuf[t], &need[t]);
    }
    done = 1;
    for (int t = 0; t < T; t++)
      if (at[t] < BlockStart(nl, T, t + 1)) {
        PetscCall(Reserve(&nl->tbuf[t], need[t], &nl->grows));
        done = 0;
      }
  } while (!done);
  off[0] = 0;
  for (int t = 0; t < T; t++) off[t + 1] = off[t] + nl->tbuf[t].n;
  {
    SpamPairBuffer b = {nl->nbr, nl->cap, 0};
    PetscCall(Reserve(&b, off[T], &nl->grows));
    nl->nbr = b.nbr;
    nl->cap = b.cap;
  }
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; t++) {
    const int i0 = BlockStart(nl, T, t), i1 = BlockStart(nl, T, t + 1);
    memcpy(nl->nbr + off[t], nl->tbuf[t].nbr, nl->tbuf[t].n * sizeof(int));
    for (int i = i0; i < i1; i++) nl->start[i + 1] += (int)off[t];
  }
  nl->npairs = off[T];
  PetscFunctionReturn(0);
}

/* SPAM_LIST_PAD entries of particle 0 after the n entries of a list of room *cap. */
PetscErrorCode SpamNeighboursPadList(int **nbr, size_t *cap, size_t n)
{
  PetscFunctionBeginUser;
  if (n + SPAM_LIST_PAD > *cap) {
    *cap = n + SPAM_LIST_PAD;
    PetscCall(PetscRealloc(*cap * sizeof(int), nbr));
  }
  for (size_t k = n; k < n + SPAM_LIST_PAD; k++) (*nbr)[k] = 0;
  PetscFunctionReturn(0);
}

/* The row blocks (neighbours.h) of the half list just built: a prefix maximum of the
 * particles the rows name (blk_zero) and a suffix minimum (blk_final), from one read of the
 * list. A block's rows that name nothing below their end leave blk_final at that end. */
static void RowBlocks(SpamNeighbours *nl)
{
  int ahead = 0, later = nl->n;

  for (int b = 0; b < nl->nblk; b++) {
    const int i0 = b * SPAM_ROW_BLOCK, i1 = PetscMin(nl->n, i0 + SPAM_ROW_BLOCK);
    int       lo = i1, hi = i1;
    for (int k = nl->start[i0]; k < nl->start[i1]; k++) {
      lo = PetscMin(lo, nl->nbr[k]);
      hi = PetscMax(hi, nl->nbr[k] + 1);
    }
    ahead            = PetscMax(ahead, hi);
    nl->blk_zero[b]  = ahead;
    nl->blk_final[b] = lo; /* the block's lowest partner, until the second loop */
  }
  for (int b = nl->nblk - 1; b >= 0; b--) {
    const int lowest = nl->blk_final[b];
    nl->blk_final[b] = PetscMin(PetscMin(nl->n, (b + 1) * SPAM_ROW_BLOCK), later);
    later            = PetscMin(later, lowest);
  }
}

/* A pending Keep (SpamNeighboursKeep) takes the reference positions now, before the first
 * change of xref or of the list since. */
static void FillKeep(SpamNeighbours *nl)
{
  if (!nl->keep) return;
  for (int i = 0; i < nl->n; i++)
    for (int d = 0; d < nl->dim; d++) nl->keep[(size_t)i * nl->dim + d] = nl->xref[d][i];
  nl->keep = NULL;
}

/* The local rows over the list's box (ghost-periodic directions open), then the ghosts
 * of the true box and their rows. */
static PetscErrorCode BuildList(SpamNeighbours *nl, const SpamBox *box)
{
  const SpamBox  *lbox = &nl->lbox;
  const SpamImage im   = nl->im;

  PetscFunctionBeginUser;
  FillKeep(nl);
  if (nl->ev_build) PetscCall(PetscLogEventBegin(nl->ev_build, 0, 0, 0, 0));
  BinParticles(nl, lbox);
  nl->start[0] = 0;
  if (nl->threads > 1) PetscCall(BuildRowsThreaded(nl, lbox, &im));
  else PetscCall(BuildRows(nl, lbox, &im));
  PetscCall(SpamNeighboursPadList(&nl->nbr, &nl->cap, nl->npairs));
  RowBlocks(nl);
  PetscCall(SpamNeighboursBuildGhosts(nl, box));
  PetscCall(SpamNeighboursBuildCanonical(nl)); /* -reproducible: the sorted full rows */
  nl->builds++;
  if (nl->ev_build) PetscCall(PetscLogEventEnd(nl->ev_build, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Whether some particle of [i0, i1) moved further than sqrt(lim) since the last build or
 * has a non-finite displacement, and (place) u = x - off: the positions in the box frame
 * of the last build. One loop without exits, so that it vectorises. dim, place and, in
 * the common layout (positions then velocities), the stride are literals at each call:
 * over run-time values (and inside an OpenMP region, whose body the compiler outlines
 * before it sees any literal) the loop was not vectorised, 36 instructions a particle in
 * 2D, 6 % of the gas's right-hand side (callgrind, gas h = 3, N = 65536); 7 now. */
static inline __attribute__((always_inline)) long DisplaceRows(SpamNeighbours *nl, const int dim, const double *x, const int stride, const int place, int i0, int i1, double lim)
{
  long over = 0;
  for (int i = i0; i < i1; i++) {
    double d2 = 0.0;
    for (int d = 0; d < dim; d++) {
      const double xi = x[(size_t)i * stride + d], dx = xi - nl->xref[d][i];
      d2 = d ? d2 + dx * dx : dx * dx; /* the sum 0 + dx^2 + ... has these bits */
      if (place) nl->u[d][i] = xi - nl->off[d][i];
    }
    over |= !(d2 <= lim);
  }
  return over;
}

static long DisplaceDim(SpamNeighbours *nl, const int dim, const double *x, int stride, PetscBool place, int i0, int i1, double lim)
{
  if (stride == 2 * dim) return place ? DisplaceRows(nl, dim, x, 2 * dim, 1, i0, i1, lim) : DisplaceRows(nl, dim, x, 2 * dim, 0, i0, i1, lim);
  return place ? DisplaceRows(nl, dim, x, stride, 1, i0, i1, lim) : DisplaceRows(nl, dim, x, stride, 0, i0, i1, lim);
}

static long DisplaceRange(SpamNeighbours *nl, int dim, const double *x, int stride, PetscBool place, int i0, int i1, double lim)
{
  if (dim == 1) return DisplaceDim(nl, 1, x, stride, place, i0, i1, lim);
  if (dim == 2) return DisplaceDim(nl, 2, x, stride, place, i0, i1, lim);
  return DisplaceDim(nl, 3, x, stride, place, i0, i1, lim);
}

/* Whether some particle moved further than sqrt(lim) since the last build (then the list
 * is rebuilt), and *nonfinite: some position is not finite. The reference positions are
 * finite (a build checks them), so a non-finite position has a non-finite displacement,
 * and the positions are looked at one by one only when some displacement is over lim. */
static int Displace(SpamNeighbours *nl, int dim, const double *x, int stride, PetscBool place, double lim, int *nonfinite)
{
  const int T    = nl->threads;
  long      over = 0;

  if (T <= 1) over = DisplaceRange(nl, dim, x, stride, place, 0, nl->n, lim);
  else {
#pragma omp parallel for num_threads(T) schedule(static) reduction(| : over)
    for (int t = 0; t < T; t++) over |= DisplaceRange(nl, dim, x, stride, place, (int)((long)nl->n * t / T), (int)((long)nl->n * (t + 1) / T), lim);
  }
  *nonfinite = 0;
  for (int i = 0; over && i < nl->n && !*nonfinite; i++)
    for (int d = 0; d < dim; d++) *nonfinite |= !(fabs(x[(size_t)i * stride + d]) <= DBL_MAX);
  return over != 0;
}

/* At a build: wraps every position into the box and keeps the shift off = x - u, so that
 * until the next build u = x - off needs no floor and no division. Between builds u may
 * leave [0, len) by up to skin/2; every use takes a minimum image of a difference, which
 * stays correct while the skin is below half an edge. Returns the first particle and
 * direction without a finite position in the box (bad[0] = -1: none). */
static void Wrap(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride, int bad[2])
{
  bad[0] = bad[1] = -1;
  for (int d = 0; d < box->dim; d++)
    for (int i = 0; i < nl->n; i++) {
      const double xi = x[(size_t)i * stride + d];
      nl->xref[d][i]  = xi;
      nl->off[d][i]   = xi - SpamBoxLocal(box, d, xi);
      nl->u[d][i]     = xi - nl->off[d][i];
      if (bad[0] < 0 && !isfinite(nl->u[d][i] + nl->off[d][i])) {
        bad[0] = i;
        bad[1] = d;
      }
    }
}

/* Wrap, then a failure on any rank fails every rank (no rank waits in the build's
 * collectives for one that left). x is finite here; a non-finite u or shift means a
 * non-finite box or an overflow of x - lo, which no cell can hold. */
static PetscErrorCode WrapAll(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride)
{
  const SpamHalo *h = &nl->ghosts.halo;
  int             bad[2];
  PetscMPIInt     first = -1;

  PetscFunctionBeginUser;
  FillKeep(nl);
  Wrap(nl, box, x, stride, bad);
  if (SpamHaloActive(h)) {
    PetscMPIInt mine = bad[0] >= 0 ? h->size - h->rank : 0, most;
    PetscCallMPI(MPI_Allreduce(&mine, &most, 1, MPI_INT, MPI_MAX, h->comm));
    first = most > 0 ? h->size - most : -1;
  }
  if (bad[0] >= 0) {
    const int i = bad[0], d = bad[1];
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FP, "particle %d at %g has no finite position in the box (corner %g, edge %g) along direction %d", i, x[(size_t)i * stride + d], box->lo[d], box->len[d], d);
  }
  PetscCheck(first < 0, PETSC_COMM_SELF, PETSC_ERR_FP, "a particle of rank %d has no finite position in the box", first);
  PetscFunctionReturn(0);
}

/* The rebuild decision and the rank of the first non-finite position, agreed by every
 * rank of the halo in one reduction: a rank that rebuilt alone, or stopped alone, would
 * leave the others waiting in the build's collectives. */
static PetscErrorCode Agree(SpamNeighbours *nl, int *rebuild, int nonfinite)
{
  const SpamHalo *h = &nl->ghosts.halo;

  PetscFunctionBeginUser;
  nl->bad_rank = nonfinite ? 0 : -1;
  if (!SpamHaloActive(h)) PetscFunctionReturn(0);
  {
    PetscMPIInt mine[2] = {*rebuild, nonfinite ? h->size - h->rank : 0}, all[2];
    PetscCallMPI(MPI_Allreduce(mine, all, 2, MPI_INT, MPI_MAX, h->comm));
    *rebuild     = all[0];
    nl->bad_rank = all[1] > 0 ? h->size - all[1] : -1;
  }
  PetscFunctionReturn(0);
}

/* The update; with lazy, u is left stale (*stale) when the list is kept and no ghost
 * slot's position has to be taken from it. */
static PetscErrorCode Update(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride, PetscBool force, PetscBool lazy, PetscInt *bad, PetscBool *stale)
{
  const int dim = box->dim;
  int       nonfinite, rebuild, over;

  PetscFunctionBeginUser;
  nl->updates++;
  *bad   = -1;
  *stale = (PetscBool)(lazy && !nl->ghosts.n && !SpamHaloActive(&nl->ghosts.halo) && nl->builds > 0);
  /* Two particles each moving skin/2 towards each other stay inside the list range. */
  over    = Displace(nl, dim, x, stride, (PetscBool)!*stale, 0.25 * nl->skin * nl->skin, &nonfinite);
  rebuild = force || nl->builds == 0 || (!nonfinite && over);
  PetscCall(Agree(nl, &rebuild, nonfinite));
  if (nl->bad_rank >= 0) {
    if (!nonfinite) *bad = SPAM_BAD_ON_OTHER_RANK;
    for (PetscInt i = 0; i < nl->n && *bad < 0; i++)
      for (int d = 0; d < dim; d++)
        if (!isfinite(x[(size_t)i * stride + d])) *bad = i;
    PetscFunctionReturn(0);
  }
  if (rebuild) {
    *stale = PETSC_FALSE; /* Wrap writes every u */
    PetscCall(WrapAll(nl, box, x, stride));
    PetscCall(BuildList(nl, box));
  } else PetscCall(SpamNeighboursMoveGhosts(nl));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursUpdate(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride, PetscBool force, PetscInt *bad)
{
  PetscBool stale;

  PetscFunctionBeginUser;
  PetscCall(Update(nl, box, x, stride, force, PETSC_FALSE, bad, &stale));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursUpdateStale(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride, PetscInt *bad, PetscBool *stale)
{
  PetscFunctionBeginUser;
  PetscCall(Update(nl, box, x, stride, PETSC_FALSE, PETSC_TRUE, bad, stale));
  PetscFunctionReturn(0);
}

/* The list as a build at reference positions xref made it: same shifts, same cells, same
 * pair order, so that the right-hand side of a restarted run is the same function of the
 * state as the uninterrupted run's (which built its list at those positions). */
PetscErrorCode SpamNeighboursRestore(SpamNeighbours *nl, const SpamBox *box, const double *xref)
{
  PetscFunctionBeginUser;
  PetscCall(WrapAll(nl, box, xref, box->dim));
  PetscCall(BuildList(nl, box));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursKeep(SpamNeighbours *nl, double *xref, long *builds)
{
  PetscFunctionBeginUser;
  nl->keep = xref; /* filled by FillKeep before xref or the list change */
  *builds  = nl->builds;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursRevert(SpamNeighbours *nl, const SpamBox *box, const double *xref, long builds)
{
  PetscFunctionBeginUser;
  nl->keep = NULL;
  if (nl->builds == builds) PetscFunctionReturn(0);
  PetscCall(SpamNeighboursRestore(nl, box, xref));
  PetscFunctionReturn(0);
}

/* First row whose pairs start at or after pair p (start is non-decreasing). */
static int RowAtPair(const SpamNeighbours *nl, size_t p)
{
  int lo = 0, hi = nl->n;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if ((size_t)nl->start[mid] < p) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

void SpamNeighboursSplitRows(const SpamNeighbours *nl, int T, int t, int rows[2])
{
  rows[0] = t == 0 ? 0 : RowAtPair(nl, nl->npairs * (size_t)t / (size_t)T);
  rows[1] = t == T - 1 ? nl->n : RowAtPair(nl, nl->npairs * (size_t)(t + 1) / (size_t)T);
}
