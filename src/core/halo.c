/* The halo of a rank through PetscSF: which (particle, image) items go to which rank, the
 * graph from them, and the forward exchange of positions and fields. */
#include <spam/halo.h>

PetscErrorCode SpamHaloSetComm(SpamHalo *h, MPI_Comm comm)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCheck(!h->active && !h->sf, PETSC_COMM_SELF, PETSC_ERR_ORDER, "set the halo's communicator once, before the first build");
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size == 1) PetscFunctionReturn(0);
  h->active = PETSC_TRUE;
  h->comm   = comm;
  h->size   = size;
  PetscCallMPI(MPI_Comm_rank(comm, &h->rank));
  PetscCall(PetscMalloc5(6 * (size_t)size, &h->boxes, size, &h->scount, size, &h->rcount, size, &h->roff, size, &h->soff));
  PetscCall(PetscMalloc1(6 * (size_t)size * SPAM_HALO_PARTS, &h->parts));
  h->unit[0] = MPI_DATATYPE_NULL;
  h->unit[1] = MPI_DOUBLE;
  for (int c = 2; c <= SPAM_HALO_MAX_COMP; c++) {
    PetscCallMPI(MPI_Type_contiguous(c, MPI_DOUBLE, &h->unit[c]));
    PetscCallMPI(MPI_Type_commit(&h->unit[c]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloDestroy(SpamHalo *h)
{
  PetscFunctionBeginUser;
  if (!h->active) PetscFunctionReturn(0);
  PetscCall(PetscSFDestroy(&h->sf));
  for (int c = 2; c <= SPAM_HALO_MAX_COMP; c++) PetscCallMPI(MPI_Type_free(&h->unit[c]));
  PetscCall(PetscFree5(h->boxes, h->scount, h->rcount, h->roff, h->soff));
  PetscCall(PetscFree(h->parts));
  PetscCall(PetscFree(h->item_src));
  PetscCall(PetscFree(h->item_shift));
  PetscCall(PetscFree(h->sendbuf));
  PetscCall(PetscFree4(h->ghost_owner, h->ghost_index, h->ghost_shift, h->recvbuf));
  h->active = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Room for `need` items, the ones chosen so far kept (at builds only; grows by half). */
static PetscErrorCode GrowItems(SpamHalo *h, int need)
{
  PetscFunctionBeginUser;
  if (need <= h->icap) PetscFunctionReturn(0);
  h->icap = need + need / 2 + 64;
  PetscCall(PetscRealloc((size_t)h->icap * sizeof(int), &h->item_src));
  PetscCall(PetscRealloc((size_t)h->icap * sizeof(*h->item_shift), &h->item_shift));
  PetscCall(PetscRealloc((size_t)h->icap * SPAM_HALO_MAX_COMP * sizeof(double), &h->sendbuf));
  PetscFunctionReturn(0);
}

/* Room for `need` remote ghost slots (their contents are set after the growth). */
static PetscErrorCode GrowGhosts(SpamHalo *h, int need)
{
  PetscFunctionBeginUser;
  if (need <= h->gcap) PetscFunctionReturn(0);
  PetscCall(PetscFree4(h->ghost_owner, h->ghost_index, h->ghost_shift, h->recvbuf));
  h->gcap = need + need / 2 + 64;
  PetscCall(PetscMalloc4(h->gcap, &h->ghost_owner, h->gcap, &h->ghost_index, h->gcap, &h->ghost_shift, (size_t)h->gcap * SPAM_HALO_MAX_COMP, &h->recvbuf));
  PetscFunctionReturn(0);
}

/* The bounding box of particles [i0, i1) into lo[0..2], hi[0..2]: empty (lo = +inf,
 * hi = -inf, so that every distance to it is infinite) when there are none; unused
 * directions are [0, 0]. */
static void BoxOf(int dim, int i0, int i1, double *const u[3], double *lo, double *hi)
{
  for (int d = 0; d < 3; d++) {
    lo[d] = d < dim ? INFINITY : 0.0;
    hi[d] = d < dim ? -INFINITY : 0.0;
  }
  for (int d = 0; d < dim; d++)
    for (int i = i0; i < i1; i++) {
      lo[d] = PetscMin(lo[d], u[d][i]);
      hi[d] = PetscMax(hi[d], u[d][i]);
    }
}

/* This rank's bounding box of box-local positions, and those of its SPAM_HALO_PARTS parts,
 * all-gathered. One box is loose: a piece of a Hilbert curve cut on a grid whose edge is
 * no power of two is no box, and its bounding box can take in most of another rank's
 * particles (bench/README.md: on 2 ranks each rank received the whole other rank). The
 * parts follow the local order, which a migration sorts by cell, so their boxes hug the
 * piece; the one box stays the first, cheap test. */
static PetscErrorCode GatherBoxes(SpamHalo *h, int dim, int n, double *const u[3])
{
  double mine[6], parts[6 * SPAM_HALO_PARTS];

  PetscFunctionBeginUser;
  BoxOf(dim, 0, n, u, mine, mine + 3);
  for (int k = 0; k < SPAM_HALO_PARTS; k++) {
    const int i0 = (int)((long)n * k / SPAM_HALO_PARTS), i1 = (int)((long)n * (k + 1) / SPAM_HALO_PARTS);
    BoxOf(dim, i0, i1, u, parts + 6 * k, parts + 6 * k + 3);
  }
  PetscCallMPI(MPI_Allgather(mine, 6, MPI_DOUBLE, h->boxes, 6, MPI_DOUBLE, h->comm));
  PetscCallMPI(MPI_Allgather(parts, 6 * SPAM_HALO_PARTS, MPI_DOUBLE, h->parts, 6 * SPAM_HALO_PARTS, MPI_DOUBLE, h->comm));
  PetscFunctionReturn(0);
}

/* Distance from x to the interval [lo, hi] (0 inside). */
static double Gap(double x, double lo, double hi)
{
  return PetscMax(0.0, PetscMax(lo - x, x - hi));
}

/* Number of image codes of a direction: the shifts -1, 0, 1 and the two mirrors; gap
 * arrays are indexed by code + 1. */
#define NCODES 5

/* Along direction d, the gap of each image code s (gap[s + 1]) of a point at u to rank r's
 * interval; infinite for an image the direction does not make. A periodic direction kept
 * by the minimum image makes only s = 0, at the periodic distance; a face with a wall
 * makes its mirror image. */
static void Gaps(const SpamBox *box, const PetscBool gper[3], unsigned walls, const double *lo, const double *hi, int d, double u, double gap[NCODES])
{
  for (int e = 0; e < NCODES; e++) gap[e] = INFINITY;
  if (d >= box->dim) {
    gap[1] = 0.0;
    return;
  }
  gap[1] = Gap(u, lo[d], hi[d]);
  if ((walls >> (2 * d)) & 1) gap[SPAM_HALO_MIRROR_LO + 1] = Gap(SpamHaloImage(SPAM_HALO_MIRROR_LO, u, box->len[d]), lo[d], hi[d]);
  if ((walls >> (2 * d + 1)) & 1) gap[SPAM_HALO_MIRROR_HI + 1] = Gap(SpamHaloImage(SPAM_HALO_MIRROR_HI, u, box->len[d]), lo[d], hi[d]);
  if (!box->periodic[d]) return;
  {
    const double L = box->len[d], dn = Gap(u - L, lo[d], hi[d]), up = Gap(u + L, lo[d], hi[d]);
    if (gper[d]) {
      gap[0] = dn;
      gap[2] = up;
    } else gap[1] = PetscMin(gap[1], PetscMin(dn, up));
  }
}

/* Squared distance of the image codes sh of a point at x to the box [lo, hi]. */
static double ImageDistance(const SpamHalo *h, const SpamBox *box, const PetscBool gper[3], const double *lo, const double *hi, const double x[3], const int sh[3])
{
  double r2 = 0.0;

  for (int d = 0; d < box->dim; d++) {
    double g[NCODES];
    Gaps(box, gper, h->walls, lo, hi, d, x[d], g);
    r2 += g[sh[d] + 1] * g[sh[d] + 1];
  }
  return r2;
}

/* The codes along each direction whose gap is below rc (at most three: a direction is
 * periodic or walled), in ascending order, into e[d][0 .. ne[d]-1] (as code + 1). */
static void NearCodes(const double gap[3][NCODES], double rc2, int e[3][NCODES], int ne[3])
{
  for (int d = 0; d < 3; d++) {
    ne[d] = 0;
    for (int k = 0; k < NCODES; k++)
      if (gap[d][k] * gap[d][k] < rc2) e[d][ne[d]++] = k;
  }
}

/* Appends particle i's items for rank r: every image whose distance to r's box is below
 * rc and to one of r's parts too, in (z, y, x) code order. The parts are tested only for
 * the images that pass the box (almost always one, or none). */
static void AppendItems(SpamHalo *h, const SpamBox *box, const PetscBool gper[3], int r, int i, double *const u[3], double rc2)
{
  const double  x[3] = {u[0][i], box->dim > 1 ? u[1][i] : 0.0, box->dim > 2 ? u[2][i] : 0.0};
  const double *lo = h->boxes + 6 * (size_t)r, *hi = lo + 3;
  double        gap[3][NCODES];
  int           e[3][NCODES], ne[3];

  for (int d = 0; d < 3; d++) Gaps(box, gper, h->walls, lo, hi, d, x[d], gap[d]);
  NearCodes(gap, rc2, e, ne);
  for (int c = 0; c < ne[2]; c++)
    for (int b = 0; b < ne[1]; b++)
      for (int a = 0; a < ne[0]; a++) {
        const int sh[3] = {e[0][a] - 1, e[1][b] - 1, e[2][c] - 1};
        PetscBool near  = PETSC_FALSE;
        if (!(gap[0][e[0][a]] * gap[0][e[0][a]] + gap[1][e[1][b]] * gap[1][e[1][b]] + gap[2][e[2][c]] * gap[2][e[2][c]] < rc2)) continue;
        for (int k = 0; k < SPAM_HALO_PARTS && !near; k++) {
          const double *plo = h->parts + 6 * ((size_t)r * SPAM_HALO_PARTS + k);
          near = (PetscBool)(ImageDistance(h, box, gper, plo, plo + 3, x, sh) < rc2);
        }
        if (!near) continue;
        h->item_src[h->nitems]      = i;
        h->item_shift[h->nitems][0] = (signed char)sh[0];
        h->item_shift[h->nitems][1] = (signed char)sh[1];
        h->item_shift[h->nitems][2] = (signed char)sh[2];
        h->nitems++;
        h->scount[r]++;
      }
}

/* Counts and offsets: rcount[s] items arrive from rank s, laid out from roff[s]; this
 * rank's block starts at soff[r] on rank r. */
static PetscErrorCode ExchangeCounts(SpamHalo *h)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Alltoall(h->scount, 1, MPI_INT, h->rcount, 1, MPI_INT, h->comm));
  h->nghost = 0;
  for (int s = 0; s < h->size; s++) {
    /* A receiver over the int range fails alone: the graph could not index its slots. */
    PetscCheck(h->rcount[s] <= PETSC_MPI_INT_MAX - h->nghost, PETSC_COMM_SELF, PETSC_ERR_MEM, "more than %d remote ghosts", PETSC_MPI_INT_MAX);
    h->roff[s] = h->nghost;
    h->nghost += h->rcount[s];
  }
  PetscCallMPI(MPI_Alltoall(h->roff, 1, MPI_INT, h->soff, 1, MPI_INT, h->comm));
  PetscFunctionReturn(0);
}

/* The graph: leaf k (item k) feeds root soff[r] + (its place in the block for r) on r. */
static PetscErrorCode MakeGraph(SpamHalo *h)
{
  PetscSFNode *iremote;
  int          k = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(h->nitems + 1, &iremote));
  for (int r = 0; r < h->size; r++)
    for (int q = 0; q < h->scount[r]; q++, k++) {
      iremote[k].rank  = r;
      iremote[k].index = h->soff[r] + q;
    }
  PetscCall(PetscSFDestroy(&h->sf));
  PetscCall(PetscSFCreate(h->comm, &h->sf));
  PetscCall(PetscSFSetGraph(h->sf, h->nghost, h->nitems, NULL, PETSC_COPY_VALUES, iremote, PETSC_OWN_POINTER));
  PetscCall(PetscSFSetUp(h->sf));
  PetscFunctionReturn(0);
}

/* What each remote slot is: its owner from the block it lies in, the owner's index and
 * the shift sent along the graph (as doubles: exact for indices below 2^53). */
static PetscErrorCode DescribeGhosts(SpamHalo *h)
{
  PetscFunctionBeginUser;
  for (int k = 0; k < h->nitems; k++) {
    h->sendbuf[4 * (size_t)k] = h->item_src[k];
    for (int d = 0; d < 3; d++) h->sendbuf[4 * (size_t)k + 1 + d] = h->item_shift[k][d];
  }
  PetscCall(PetscSFReduceBegin(h->sf, h->unit[4], h->sendbuf, h->recvbuf, MPI_REPLACE));
  PetscCall(PetscSFReduceEnd(h->sf, h->unit[4], h->sendbuf, h->recvbuf, MPI_REPLACE));
  for (int s = 0; s < h->size; s++)
    for (int k = h->roff[s]; k < h->roff[s] + h->rcount[s]; k++) {
      h->ghost_owner[k] = s;
      h->ghost_index[k] = (int)h->recvbuf[4 * (size_t)k];
      for (int d = 0; d < 3; d++) h->ghost_shift[k][d] = (signed char)h->recvbuf[4 * (size_t)k + 1 + d];
    }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloSelect(SpamHalo *h, const SpamBox *box, const PetscBool gper[3], int n, double *const u[3], double rc)
{
  PetscFunctionBeginUser;
  if (!h->active) PetscFunctionReturn(0);
  for (int d = 0; d < 3; d++) h->len[d] = d < box->dim ? box->len[d] : 0.0;
  PetscCall(GatherBoxes(h, box->dim, n, u));
  h->nitems = 0;
  for (int r = 0; r < h->size; r++) {
    h->scount[r] = 0;
    if (r == h->rank) continue; /* own images: the local ghosts */
    for (int i = 0; i < n; i++) {
      PetscCall(GrowItems(h, h->nitems + 27));
      AppendItems(h, box, gper, r, i, u, rc * rc);
    }
  }
  PetscCall(ExchangeCounts(h));
  PetscCall(GrowGhosts(h, h->nghost + 1));
  PetscCall(GrowItems(h, h->nitems + 1));
  PetscCall(MakeGraph(h));
  PetscCall(DescribeGhosts(h));
  h->builds++;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloForwardPositions(const SpamHalo *h, int dim, double *const u[3], double *const dst[3])
{
  PetscFunctionBeginUser;
  if (!h->active || !h->sf) PetscFunctionReturn(0);
  for (int k = 0; k < h->nitems; k++)
    for (int d = 0; d < dim; d++) h->sendbuf[(size_t)k * dim + d] = SpamHaloImage(h->item_shift[k][d], u[d][h->item_src[k]], h->len[d]);
  PetscCall(PetscSFReduceBegin(h->sf, h->unit[dim], h->sendbuf, h->recvbuf, MPI_REPLACE));
  PetscCall(PetscSFReduceEnd(h->sf, h->unit[dim], h->sendbuf, h->recvbuf, MPI_REPLACE));
  for (int d = 0; d < dim; d++)
    for (int k = 0; k < h->nghost; k++) dst[d][k] = h->recvbuf[(size_t)k * dim + d];
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloForward(const SpamHalo *h, int ncomp, const double *field, double *dst)
{
  PetscFunctionBeginUser;
  if (!h->active || !h->sf) PetscFunctionReturn(0);
  PetscCheck(ncomp >= 1 && ncomp <= SPAM_HALO_MAX_COMP, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "a halo exchange carries 1 to %d values per particle, not %d", SPAM_HALO_MAX_COMP, ncomp);
  for (int k = 0; k < h->nitems; k++)
    for (int c = 0; c < ncomp; c++) h->sendbuf[(size_t)k * ncomp + c] = field[(size_t)h->item_src[k] * ncomp + c];
  PetscCall(PetscSFReduceBegin(h->sf, h->unit[ncomp], h->sendbuf, dst, MPI_REPLACE));
  PetscCall(PetscSFReduceEnd(h->sf, h->unit[ncomp], h->sendbuf, dst, MPI_REPLACE));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloReverseAdd(const SpamHalo *h, int ncomp, const double *slots, double *base, size_t stride)
{
  PetscFunctionBeginUser;
  if (!h->active || !h->sf) PetscFunctionReturn(0);
  PetscCheck(ncomp >= 1 && ncomp <= SPAM_HALO_MAX_COMP, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "a halo exchange carries 1 to %d values per particle, not %d", SPAM_HALO_MAX_COMP, ncomp);
  PetscCall(PetscSFBcastBegin(h->sf, h->unit[ncomp], slots, h->sendbuf, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(h->sf, h->unit[ncomp], slots, h->sendbuf, MPI_REPLACE));
  for (int k = 0; k < h->nitems; k++)
    for (int c = 0; c < ncomp; c++) base[(size_t)h->item_src[k] * stride + c] += h->sendbuf[(size_t)k * ncomp + c];
  PetscFunctionReturn(0);
}
