/* Which of this rank's particles (and which of their images) go to which rank: the choice
 * of a halo build (halo.h), by occupied cells.
 *
 * The box is cut into a grid of cells at least rc wide. Every rank lists the cells its
 * particles occupy, each with the bounding box of its particles there, and sends each other
 * rank those that could hold a partner of that rank's particles: an image of the cell's box
 * within rc of the other rank's bounding box. A rank then sends particle i (as image code s)
 * to rank r when the image lies within rc of one of r's cell boxes, which it finds among
 * the cells next to the image's. So r receives what lies within rc of the boxes of its
 * particles' cells (a few per cent more than the partners), whatever shape its piece has.
 * Bounding boxes alone (one per rank, or one per run of the local order) take in whole
 * other ranks once a few fast particles stretch them (the 3D expansion on 2 ranks: 57398
 * ghosts for a rank of ~48700 with 32 part boxes, of which at most ~15000 had a pair). The cost of a build is O(n) lookups and O(cells * ranks) box
 * tests, not O(n * ranks).
 *
 * Along a periodic direction the grid is the box (every particle is wrapped into it at a
 * build); along the others it reaches to the farthest particle of any rank (an open face
 * lets particles fly out, and within a step one may stand a little beyond a wall). */
#include "halo_select.h"

/* The cells of one build: per direction, count nc and width w (w >= rc; coarser when the
 * grid would pass SPAM_HALO_MAX_CELLS, which bounds the two maps below). */
#define SPAM_HALO_MAX_CELLS (1 << 22)

typedef struct {
  int          dim, nc[3];
  double       o[3], w[3], len[3], rc; /* cell c along d: [o + c w, o + (c + 1) w)   */
  PetscBool    per[3];   /* periodic by the minimum image: cell indices wrap           */
  PetscBool    gper[3];  /* periodic by ghost images: the image codes -1, 1             */
  unsigned     walls;    /* bit f: face f has a mirror wall                              */
  double       depth[6]; /* how far beyond face f any particle stands                   */
} Grid;

/* The grid over the box, or along a direction that is not periodic over every rank's
 * particles (h->boxes) too. */
static void MakeGrid(const SpamHalo *h, const SpamBox *box, const PetscBool gper[3], double rc, Grid *g)
{
  long total = 1;

  g->dim   = box->dim;
  g->rc    = rc;
  g->walls = h->walls;
  for (int f = 0; f < 6; f++) g->depth[f] = h->depth[f];
  for (int d = 0; d < 3; d++) {
    double lo = 0.0, hi = d < box->dim ? box->len[d] : 1.0;
    g->len[d]  = hi;
    g->gper[d] = (PetscBool)(d < box->dim && box->periodic[d] && gper[d]);
    g->per[d]  = (PetscBool)(d < box->dim && box->periodic[d] && !gper[d]);
    if (d < box->dim && !box->periodic[d])
      for (int r = 0; r < h->size; r++) {
        lo = PetscMin(lo, h->boxes[6 * r + d]);
        hi = PetscMax(hi, h->boxes[6 * r + 3 + d]);
      }
    g->o[d]  = lo;
    g->w[d]  = hi - lo;
    g->nc[d] = d < box->dim ? PetscMax(1, (int)PetscMin(1e6, g->w[d] / rc)) : 1;
    total *= g->nc[d];
  }
  while (total > SPAM_HALO_MAX_CELLS) { /* halve the finest direction */
    int m = 0;
    for (int d = 1; d < 3; d++)
      if (g->nc[d] > g->nc[m]) m = d;
    total    = total / g->nc[m] * ((g->nc[m] + 1) / 2);
    g->nc[m] = (g->nc[m] + 1) / 2;
  }
  for (int d = 0; d < 3; d++) g->w[d] /= g->nc[d];
}

/* The cell index along d of a coordinate, clamped into the grid (an image beyond it is
 * within rc of the edge cells only, the cells being at least rc wide). */
static int CellAlong(const Grid *g, int d, double x)
{
  const double c = PetscFloorReal((x - g->o[d]) / g->w[d]);
  return c < 0 ? 0 : c >= g->nc[d] ? g->nc[d] - 1 : (int)c;
}

static long KeyOf(const Grid *g, const int c[3])
{
  return (long)c[0] + (long)g->nc[0] * ((long)c[1] + (long)g->nc[1] * c[2]);
}

static void CellOfKey(const Grid *g, long key, int c[3])
{
  c[0] = (int)(key % g->nc[0]);
  c[1] = (int)((key / g->nc[0]) % g->nc[1]);
  c[2] = (int)(key / ((long)g->nc[0] * g->nc[1]));
}

/* Distance from the interval [a, b] to [lo, hi] (0 where they meet). */
static double IntervalGap(double a, double b, double lo, double hi)
{
  return PetscMax(0.0, PetscMax(lo - b, a - hi));
}

/* Along d, the smallest gap of any image of the interval [a, b] (the codes this direction
 * makes: periodic shifts, the minimum image, mirrors in its walls) to [lo, hi]. */
static double ImageGap(const Grid *g, int d, double a, double b, double lo, double hi)
{
  const double L   = g->len[d];
  double       gap = IntervalGap(a, b, lo, hi);

  if (d >= g->dim) return 0.0;
  if (g->per[d] || g->gper[d]) gap = PetscMin(gap, PetscMin(IntervalGap(a - L, b - L, lo, hi), IntervalGap(a + L, b + L, lo, hi)));
  if ((g->walls >> (2 * d)) & 1) gap = PetscMin(gap, IntervalGap(-b, -a, lo, hi));
  if ((g->walls >> (2 * d + 1)) & 1) gap = PetscMin(gap, IntervalGap(2.0 * L - b, 2.0 * L - a, lo, hi));
  return gap;
}

/* Whether an image of the box cb (a cell's particles) could be within rc of the box lo, hi
 * (a rank's particles). */
static PetscBool CellNearBox(const Grid *g, const double *cb, const double *lo, const double *hi)
{
  double r2 = 0.0;

  for (int d = 0; d < g->dim; d++) {
    const double gap = ImageGap(g, d, cb[d], cb[3 + d], lo[d], hi[d]);
    r2 += gap * gap;
  }
  return (PetscBool)(r2 < g->rc * g->rc);
}

/* This rank's bounding box of box-local positions, all-gathered (empty: lo = +inf, hi =
 * -inf, at infinite distance from everything; unused directions [0, 0]). */
static PetscErrorCode GatherBoxes(SpamHalo *h, int dim, int n, double *const u[3])
{
  double mine[6];

  PetscFunctionBeginUser;
  for (int d = 0; d < 3; d++) {
    mine[d]     = d < dim ? INFINITY : 0.0;
    mine[3 + d] = d < dim ? -INFINITY : 0.0;
  }
  for (int d = 0; d < dim; d++)
    for (int i = 0; i < n; i++) {
      mine[d]     = PetscMin(mine[d], u[d][i]);
      mine[3 + d] = PetscMax(mine[3 + d], u[d][i]);
    }
  PetscCallMPI(MPI_Allgather(mine, 6, MPI_DOUBLE, h->boxes, 6, MPI_DOUBLE, h->comm));
  PetscFunctionReturn(0);
}

/* The two maps over the grid's cells (made at the first build, -1 and 0 between builds),
 * the pool of their rank lists, and the list of this rank's occupied cells. */
static PetscErrorCode Reserve(SpamHalo *h, const Grid *g, int n)
{
  const long total = (long)g->nc[0] * g->nc[1] * g->nc[2];

  PetscFunctionBeginUser;
  if (total > h->sel.ncells) {
    PetscCall(PetscFree2(h->sel.head, h->sel.near));
    PetscCall(PetscMalloc2(total, &h->sel.head, total, &h->sel.near));
    for (long k = 0; k < total; k++) h->sel.head[k] = -1, h->sel.near[k] = 0;
    h->sel.ncells = total;
  }
  if (!h->sel.scnt) PetscCall(PetscMalloc5(h->size, &h->sel.scnt, h->size, &h->sel.rcnt, h->size, &h->sel.soff, h->size + 1, &h->sel.rcoff, h->size, &h->sel.stamp));
  if (n + 1 > h->sel.occcap) {
    PetscCall(PetscFree2(h->sel.occ, h->sel.obox));
    h->sel.occcap = n + n / 2 + 16;
    PetscCall(PetscMalloc2(h->sel.occcap, &h->sel.occ, 6 * (size_t)h->sel.occcap, &h->sel.obox));
  }
  PetscFunctionReturn(0);
}

/* This rank's occupied cells, each once, and the bounding box of its particles in each:
 * occ[k] is a cell's key, obox[6 k ..] its lo[3], hi[3] (head, -1 between builds, maps a
 * key to k meanwhile). */
static void OccupiedCells(SpamHalo *h, const Grid *g, int n, double *const u[3])
{
  h->sel.nocc = 0;
  for (int i = 0; i < n; i++) {
    int     c[3] = {0, 0, 0};
    long    key;
    double *b;
    for (int d = 0; d < g->dim; d++) c[d] = CellAlong(g, d, u[d][i]);
    key = KeyOf(g, c);
    if (h->sel.head[key] < 0) {
      h->sel.head[key] = h->sel.nocc;
      h->sel.occ[h->sel.nocc] = key;
      b = h->sel.obox + 6 * (size_t)h->sel.nocc++;
      for (int d = 0; d < 3; d++) b[d] = b[3 + d] = d < g->dim ? u[d][i] : 0.0;
      continue;
    }
    b = h->sel.obox + 6 * (size_t)h->sel.head[key];
    for (int d = 0; d < g->dim; d++) {
      b[d]     = PetscMin(b[d], u[d][i]);
      b[3 + d] = PetscMax(b[3 + d], u[d][i]);
    }
  }
  for (int k = 0; k < h->sel.nocc; k++) h->sel.head[h->sel.occ[k]] = -1;
}

/* Room for `need` cells of CELL_VALUES doubles in *a. */
#define CELL_VALUES 7
static PetscErrorCode GrowCells(double **a, int *cap, int need)
{
  PetscFunctionBeginUser;
  if (need <= *cap) PetscFunctionReturn(0);
  *cap = need + need / 2 + 64;
  PetscCall(PetscRealloc((size_t)*cap * CELL_VALUES * sizeof(double), a));
  PetscFunctionReturn(0);
}

/* Sends every other rank the occupied cells near its box and receives theirs: sel.rcells
 * holds, from sel.rcoff[r], the cells rank r sent, each as its key (a double: exact, the
 * grid has at most SPAM_HALO_MAX_CELLS cells) and the box of its particles. */
static PetscErrorCode ExchangeCells(SpamHalo *h, const Grid *g)
{
  int nsend = 0, nrecv = 0;

  PetscFunctionBeginUser;
  for (int r = 0; r < h->size; r++) {
    h->sel.scnt[r] = 0;
    h->sel.soff[r] = nsend;
    if (r == h->rank) continue;
    PetscCall(GrowCells(&h->sel.scells, &h->sel.skcap, nsend + h->sel.nocc));
    for (int k = 0; k < h->sel.nocc; k++) {
      const double *cb = h->sel.obox + 6 * (size_t)k;
      double       *q  = h->sel.scells + CELL_VALUES * (size_t)(nsend + h->sel.scnt[r]);
      if (!CellNearBox(g, cb, h->boxes + 6 * (size_t)r, h->boxes + 6 * (size_t)r + 3)) continue;
      q[0] = (double)h->sel.occ[k];
      for (int c = 0; c < 6; c++) q[1 + c] = cb[c];
      h->sel.scnt[r]++;
    }
    nsend += h->sel.scnt[r];
  }
  PetscCallMPI(MPI_Alltoall(h->sel.scnt, 1, MPI_INT, h->sel.rcnt, 1, MPI_INT, h->comm));
  for (int r = 0; r < h->size; r++) {
    h->sel.rcoff[r] = nrecv;
    nrecv += h->sel.rcnt[r];
  }
  h->sel.rcoff[h->size] = nrecv;
  PetscCall(GrowCells(&h->sel.rcells, &h->sel.rkcap, nrecv + 1));
  PetscCall(GrowCells(&h->sel.scells, &h->sel.skcap, nsend + 1));
  PetscCallMPI(MPI_Alltoallv(h->sel.scells, h->sel.scnt, h->sel.soff, h->unit_cell, h->sel.rcells, h->sel.rcnt, h->sel.rcoff, h->unit_cell, h->comm));
  PetscFunctionReturn(0);
}

/* The cells within one cell of c (the neighbourhood a point within rc of c can lie in,
 * the cells being at least rc wide), wrapped along the minimum-image directions and cut at
 * the grid's edges elsewhere, into keys. Returns the count. */
static int Neighbourhood(const Grid *g, const int c[3], long keys[27])
{
  int  idx[3][3], k[3], m = 0;
  long stride[3] = {1, g->nc[0], (long)g->nc[0] * g->nc[1]};

  for (int d = 0; d < 3; d++) { /* the indices along d, each once (a few per key: no modulo per cell) */
    k[d] = 0;
    if (d >= g->dim) idx[d][k[d]++] = 0;
    else if (g->per[d] && g->nc[d] < 3)
      for (int q = 0; q < g->nc[d]; q++) idx[d][k[d]++] = q;
    else
      for (int q = c[d] - 1; q <= c[d] + 1; q++) {
        if (g->per[d]) idx[d][k[d]++] = q < 0 ? q + g->nc[d] : q >= g->nc[d] ? q - g->nc[d] : q;
        else if (q >= 0 && q < g->nc[d]) idx[d][k[d]++] = q;
      }
  }
  for (int z = 0; z < k[2]; z++)
    for (int y = 0; y < k[1]; y++)
      for (int x = 0; x < k[0]; x++) keys[m++] = idx[0][x] + stride[1] * idx[1][y] + stride[2] * idx[2][z];
  return m;
}

/* The received cells into the maps: each cell's list of ranks (head, pool), and `near` set
 * on every cell within one cell of one (where a point may be within rc of it). undo:
 * clears them again. */
static PetscErrorCode MapCells(SpamHalo *h, const Grid *g, PetscBool undo)
{
  const int nrecv = h->sel.rcoff[h->size];

  PetscFunctionBeginUser;
  if (!undo && nrecv > h->sel.poolcap) {
    PetscCall(PetscFree2(h->sel.pool_rank, h->sel.pool_next));
    h->sel.poolcap = nrecv + nrecv / 2 + 64;
    PetscCall(PetscMalloc2(h->sel.poolcap, &h->sel.pool_rank, h->sel.poolcap, &h->sel.pool_next));
  }
  for (int r = 0; r < h->size; r++)
    for (int k = h->sel.rcoff[r]; k < h->sel.rcoff[r + 1]; k++) {
      const long key = (long)h->sel.rcells[CELL_VALUES * (size_t)k];
      long       nb[27];
      int        c[3], m;
      if (undo) h->sel.head[key] = -1;
      else {
        h->sel.pool_rank[k] = r;
        h->sel.pool_next[k] = h->sel.head[key];
        h->sel.head[key]    = k;
      }
      CellOfKey(g, key, c);
      m = Neighbourhood(g, c, nb);
      for (int q = 0; q < m; q++) h->sel.near[nb[q]] = (unsigned char)!undo;
    }
  PetscFunctionReturn(0);
}

/* The image codes along d of a particle at u that could reach another rank's cells: itself,
 * a periodic image within rc of the box (ghost-image directions), a mirror in a wall it is
 * within rc of (rc + the wall's depth: a particle beyond the wall pairs with images from
 * deeper in the box). In ascending code order; returns the count. */
static int CodesAlong(const Grid *g, int d, double u, int code[3])
{
  int k = 0;

  if (d >= g->dim) {
    code[0] = 0;
    return 1;
  }
  if (g->gper[d] && u > g->len[d] - g->rc) code[k++] = -1;
  code[k++] = 0;
  if (g->gper[d] && u < g->rc) code[k++] = 1;
  if (((g->walls >> (2 * d)) & 1) && u < g->rc + g->depth[2 * d]) code[k++] = SPAM_HALO_MIRROR_LO;
  if (((g->walls >> (2 * d + 1)) & 1) && u > g->len[d] - g->rc - g->depth[2 * d + 1]) code[k++] = SPAM_HALO_MIRROR_HI;
  return k;
}

/* Squared distance from x to the box cb (of another rank's particles in one cell; its
 * nearest periodic copy along the minimum-image directions). */
static double BoxDistance2(const Grid *g, const double x[3], const double *cb)
{
  double r2 = 0.0;

  for (int d = 0; d < g->dim; d++) {
    double gap = IntervalGap(x[d], x[d], cb[d], cb[3 + d]);
    if (g->per[d]) gap = PetscMin(gap, PetscMin(IntervalGap(x[d], x[d], cb[d] - g->len[d], cb[3 + d] - g->len[d]), IntervalGap(x[d], x[d], cb[d] + g->len[d], cb[3 + d] + g->len[d])));
    r2 += gap * gap;
  }
  return r2;
}

/* Adds the items of the image x (codes sh) of particle i: one per rank with a cell box
 * within rc of x. stamp[r] == tag: r already has it. */
static PetscErrorCode ImageItems(SpamHalo *h, const Grid *g, int i, const int sh[3], const double x[3], long tag)
{
  int  c[3] = {0, 0, 0}, m;
  long nb[27];

  PetscFunctionBeginUser;
  for (int d = 0; d < g->dim; d++) c[d] = CellAlong(g, d, x[d]);
  if (!h->sel.near[KeyOf(g, c)]) PetscFunctionReturn(0);
  m = Neighbourhood(g, c, nb);
  for (int q = 0; q < m; q++)
    for (int k = h->sel.head[nb[q]]; k >= 0; k = h->sel.pool_next[k]) {
      const int r = h->sel.pool_rank[k];
      if (h->sel.stamp[r] == tag || !(BoxDistance2(g, x, h->sel.rcells + CELL_VALUES * (size_t)k + 1) < g->rc * g->rc)) continue;
      h->sel.stamp[r] = tag;
      PetscCall(SpamHaloGrowItems(h, h->nitems + 1));
      h->item_src[h->nitems] = i;
      h->item_rank[h->nitems] = r;
      for (int d = 0; d < 3; d++) h->item_shift[h->nitems][d] = (signed char)sh[d];
      h->nitems++;
      h->scount[r]++;
    }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloGrowItems(SpamHalo *h, int need)
{
  PetscFunctionBeginUser;
  if (need <= h->icap) PetscFunctionReturn(0);
  h->icap = need + need / 2 + 64;
  PetscCall(PetscRealloc((size_t)h->icap * sizeof(int), &h->item_src));
  PetscCall(PetscRealloc((size_t)h->icap * sizeof(int), &h->item_rank));
  PetscCall(PetscRealloc((size_t)h->icap * sizeof(*h->item_shift), &h->item_shift));
  PetscCall(PetscRealloc((size_t)h->icap * SPAM_HALO_MAX_COMP * sizeof(double), &h->sendbuf));
  PetscFunctionReturn(0);
}

/* Orders the items by rank, keeping their order within a rank (a counting sort through the
 * send buffer, which is free at a build). */
static void SortItems(SpamHalo *h)
{
  int         *src = (int *)h->sendbuf, *at = h->sel.soff;
  signed char *sh  = (signed char *)(src + h->nitems);

  for (int r = 0, off = 0; r < h->size; r++) {
    at[r] = off;
    off += h->scount[r];
  }
  for (int k = 0; k < h->nitems; k++) {
    const int q = at[h->item_rank[k]]++;
    src[q]      = h->item_src[k];
    for (int d = 0; d < 3; d++) sh[3 * q + d] = h->item_shift[k][d];
  }
  for (int k = 0; k < h->nitems; k++) {
    h->item_src[k] = src[k];
    for (int d = 0; d < 3; d++) h->item_shift[k][d] = sh[3 * k + d];
  }
}

PetscErrorCode SpamHaloCellsDestroy(SpamHaloCells *c)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(c->head, c->near));
  PetscCall(PetscFree2(c->pool_rank, c->pool_next));
  PetscCall(PetscFree2(c->occ, c->obox));
  PetscCall(PetscFree(c->scells));
  PetscCall(PetscFree(c->rcells));
  PetscCall(PetscFree5(c->scnt, c->rcnt, c->soff, c->rcoff, c->stamp));
  PetscCall(PetscMemzero(c, sizeof *c));
  PetscFunctionReturn(0);
}

/* The items in (particle, code, rank) order, then ordered by rank (a stable counting sort:
 * within a rank, by particle and code). */
static PetscErrorCode ParticleItems(SpamHalo *h, const Grid *g, int n, double *const u[3])
{
  long tag = 0;

  PetscFunctionBeginUser;
  for (int r = 0; r < h->size; r++) h->scount[r] = 0, h->sel.stamp[r] = -1;
  h->nitems = 0;
  for (int i = 0; i < n; i++) {
    const double x0[3] = {u[0][i], g->dim > 1 ? u[1][i] : 0.0, g->dim > 2 ? u[2][i] : 0.0};
    int          code[3][3], nco[3];
    for (int d = 0; d < 3; d++) nco[d] = CodesAlong(g, d, x0[d], code[d]);
    for (int cz = 0; cz < nco[2]; cz++)
      for (int cy = 0; cy < nco[1]; cy++)
        for (int cx = 0; cx < nco[0]; cx++) {
          const int sh[3] = {code[0][cx], code[1][cy], code[2][cz]};
          double    x[3];
          for (int d = 0; d < 3; d++) x[d] = d < g->dim ? SpamHaloImage(sh[d], x0[d], g->len[d]) : 0.0;
          PetscCall(ImageItems(h, g, i, sh, x, tag++));
        }
  }
  SortItems(h);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloChooseItems(SpamHalo *h, const SpamBox *box, const PetscBool gper[3], int n, double *const u[3], double rc)
{
  Grid g;

  PetscFunctionBeginUser;
  PetscCall(GatherBoxes(h, box->dim, n, u));
  MakeGrid(h, box, gper, rc, &g);
  PetscCall(Reserve(h, &g, n));
  OccupiedCells(h, &g, n, u);
  PetscCall(ExchangeCells(h, &g));
  PetscCall(MapCells(h, &g, PETSC_FALSE));
  PetscCall(ParticleItems(h, &g, n, u));
  PetscCall(MapCells(h, &g, PETSC_TRUE));
  PetscFunctionReturn(0);
}
