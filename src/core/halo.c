/* The halo of a rank through PetscSF: the graph of a build from the chosen items
 * (halo_select.c), and the forward and reverse exchanges. */
#include "halo_select.h"

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
  h->unit[0] = MPI_DATATYPE_NULL;
  h->unit[1] = MPI_DOUBLE;
  for (int c = 2; c <= SPAM_HALO_MAX_COMP; c++) {
    PetscCallMPI(MPI_Type_contiguous(c, MPI_DOUBLE, &h->unit[c]));
    PetscCallMPI(MPI_Type_commit(&h->unit[c]));
  }
  PetscCallMPI(MPI_Type_contiguous(7, MPI_DOUBLE, &h->unit_cell));
  PetscCallMPI(MPI_Type_commit(&h->unit_cell));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamHaloDestroy(SpamHalo *h)
{
  PetscFunctionBeginUser;
  if (!h->active) PetscFunctionReturn(0);
  PetscCall(PetscSFDestroy(&h->sf));
  for (int c = 2; c <= SPAM_HALO_MAX_COMP; c++) PetscCallMPI(MPI_Type_free(&h->unit[c]));
  PetscCallMPI(MPI_Type_free(&h->unit_cell));
  PetscCall(PetscFree5(h->boxes, h->scount, h->rcount, h->roff, h->soff));
  PetscCall(SpamHaloCellsDestroy(&h->sel));
  PetscCall(PetscFree(h->item_src));
  PetscCall(PetscFree(h->item_rank));
  PetscCall(PetscFree(h->item_shift));
  PetscCall(PetscFree(h->sendbuf));
  PetscCall(PetscFree4(h->ghost_owner, h->ghost_index, h->ghost_shift, h->recvbuf));
  h->active = PETSC_FALSE;
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
  PetscCall(SpamHaloChooseItems(h, box, gper, n, u, rc));
  PetscCall(ExchangeCounts(h));
  PetscCall(GrowGhosts(h, h->nghost + 1));
  PetscCall(SpamHaloGrowItems(h, h->nitems + 1));
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
