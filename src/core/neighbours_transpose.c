/* The transposed half list: for each particle the rows that hold its pairs, so that a
 * walk over the pairs of a few marked particles (the active ones of block steps) finds
 * the rows it must read without reading every row of the list. Made on demand, once per
 * list build; the list itself is untouched. */
#include <spam/neighbours.h>

/* The ghost slot j's local source (-1: none, a remote particle's). */
static inline int SourceOf(const SpamNeighbours *nl, int j)
{
  return j < nl->n ? j : nl->ghosts.src[j - nl->n];
}

PetscErrorCode SpamNeighboursTranspose(SpamNeighbours *nl)
{
  const int n = nl->n;
  size_t    total;

  PetscFunctionBeginUser;
  if (nl->tbuilt == nl->builds && nl->tstart) PetscFunctionReturn(0);
  if (!nl->tstart) PetscCall(PetscMalloc1((size_t)n + 2, &nl->tstart));
  for (int p = 0; p <= n + 1; p++) nl->tstart[p] = 0;
  /* counts shifted by two, so that the fill below leaves tstart[p] at row p's start */
  for (int i = 0; i < n; i++) {
    for (int c = nl->start[i]; c < nl->start[i + 1]; c++) nl->tstart[nl->nbr[c] + 2]++;
    for (int c = nl->gstart[i]; c < nl->gstart[i + 1]; c++) {
      const int s = SourceOf(nl, nl->gnbr[c]);
      if (s >= 0) nl->tstart[s + 2]++;
    }
  }
  for (int p = 2; p <= n + 1; p++) nl->tstart[p] += nl->tstart[p - 1];
  total = (size_t)nl->tstart[n + 1];
  if (total + 1 > nl->tcap) {
    PetscCall(PetscFree(nl->trows));
    nl->tcap = total + total / 4 + 16;
    PetscCall(PetscMalloc1(nl->tcap, &nl->trows));
  }
  /* rows in ascending order, so each particle's rows come out ascending */
  for (int i = 0; i < n; i++) {
    for (int c = nl->start[i]; c < nl->start[i + 1]; c++) nl->trows[nl->tstart[nl->nbr[c] + 1]++] = i;
    for (int c = nl->gstart[i]; c < nl->gstart[i + 1]; c++) {
      const int s = SourceOf(nl, nl->gnbr[c]);
      if (s >= 0) nl->trows[nl->tstart[s + 1]++] = i;
    }
  }
  nl->tbuilt = nl->builds;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamNeighboursMarkedRows(SpamNeighbours *nl, const unsigned char *mask, unsigned char *row)
{
  const int n = nl->n;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursTranspose(nl));
  for (int i = 0; i < n; i++) row[i] = mask[i];
  for (int p = 0; p < n; p++) {
    if (!mask[p]) continue;
    for (int c = nl->tstart[p]; c < nl->tstart[p + 1]; c++) row[nl->trows[c]] = 1;
  }
  PetscFunctionReturn(0);
}

/* The marked rows, and the particles the marked ones' own rows list. */
PetscErrorCode SpamNeighboursMarkedNear(SpamNeighbours *nl, const unsigned char *mask, unsigned char *near)
{
  const int n = nl->n;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursMarkedRows(nl, mask, near));
  for (int p = 0; p < n; p++) {
    if (!mask[p]) continue;
    for (int c = nl->start[p]; c < nl->start[p + 1]; c++) near[nl->nbr[c]] = 1;
  }
  PetscFunctionReturn(0);
}
