/* The balanced cut of the Hilbert curve through the global h-cell grid (decompose.h). */
#include <spam/decompose.h>

PetscErrorCode SpamDecompCreate(MPI_Comm comm, const SpamBox *box, double h, double recut_above, SpamDecomp *dec)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(dec, sizeof *dec));
  dec->comm = comm;
  dec->box  = *box;
  PetscCallMPI(MPI_Comm_size(dec->comm, &dec->nranks));
  PetscCallMPI(MPI_Comm_rank(dec->comm, &dec->rank));
  SpamCellGridInit(box, h, &dec->grid);
  dec->recut_above = recut_above > 1.0 ? recut_above : SPAM_RECUT_ABOVE_DEFAULT;
  PetscCall(PetscCalloc2(dec->nranks + 1, &dec->cut, dec->nranks, &dec->count));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDecompDestroy(SpamDecomp *dec)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(dec->cut, dec->count));
  PetscFunctionReturn(0);
}

uint64_t SpamDecompKey(const SpamDecomp *dec, const double *x)
{
  int c[3];
  SpamCellOf(&dec->grid, &dec->box, x, c);
  return SpamCellHilbertKey(&dec->grid, c);
}

PetscMPIInt SpamDecompOwner(const SpamDecomp *dec, uint64_t key)
{
  /* The last rank r with cut[r] <= key: empty ranks (cut[r] == cut[r+1]) own nothing. */
  PetscMPIInt lo = 0, hi = dec->nranks; /* cut[lo] <= key; the answer is below hi */
  while (hi - lo > 1) {
    const PetscMPIInt mid = lo + (hi - lo) / 2;
    if (dec->cut[mid] <= key) lo = mid;
    else hi = mid;
  }
  return lo;
}

double SpamDecompImbalance(PetscMPIInt nranks, const PetscInt64 *count)
{
  PetscInt64 max = 0, sum = 0;
  for (PetscMPIInt r = 0; r < nranks; r++) {
    max = PetscMax(max, count[r]);
    sum += count[r];
  }
  return sum ? (double)max * nranks / (double)sum : 1.0;
}

/* Number of keys below b in the ascending array (its lower bound). */
static PetscInt64 CountBelow(PetscInt n, const uint64_t *key, uint64_t b)
{
  PetscInt lo = 0, hi = n;
  while (lo < hi) {
    const PetscInt mid = lo + (hi - lo) / 2;
    if (key[mid] < b) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/* The bisection of all nranks - 1 inner boundaries at once. With C(b) the global number
 * of particles whose cell key is below b, boundary r seeks the target T = r N / P with
 * C(lo) < T <= C(hi), halving [lo, hi] by one allreduce of the P - 1 counts per step
 * (at most dim * bits steps: 15 for a 32^3 grid), so it needs O(P) memory on each rank
 * whatever the particle count, and no rank ever sees another's particles. */
typedef struct {
  uint64_t   *lo, *hi;
  PetscInt64 *clo, *chi, *target, *c;
} Bisection;

static PetscErrorCode Bisect(SpamDecomp *dec, PetscInt n, const uint64_t *key, PetscInt64 N, Bisection *b)
{
  const PetscMPIInt P   = dec->nranks;
  const uint64_t    end = (uint64_t)1 << (dec->grid.dim * dec->grid.bits);
  PetscBool         open;

  PetscFunctionBeginUser;
  for (PetscMPIInt r = 1; r < P; r++) {
    b->target[r] = N * r / P;
    b->lo[r]     = 0;
    b->hi[r]     = end;
    b->clo[r]    = 0;
    b->chi[r]    = N;
  }
  do {
    open = PETSC_FALSE;
    for (PetscMPIInt r = 1; r < P; r++) {
      const PetscBool active = (PetscBool)(b->target[r] > 0 && b->hi[r] - b->lo[r] > 1);
      b->c[r] = active ? CountBelow(n, key, b->lo[r] + (b->hi[r] - b->lo[r]) / 2) : 0;
      open    = (PetscBool)(open || active);
    }
    if (!open) break; /* the same on every rank: lo, hi and the targets are replicated */
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, b->c + 1, P - 1, MPIU_INT64, MPI_SUM, dec->comm));
    for (PetscMPIInt r = 1; r < P; r++) {
      if (!(b->target[r] > 0 && b->hi[r] - b->lo[r] > 1)) continue;
      const uint64_t mid = b->lo[r] + (b->hi[r] - b->lo[r]) / 2;
      if (b->c[r] >= b->target[r]) {
        b->hi[r]  = mid;
        b->chi[r] = b->c[r];
      } else {
        b->lo[r]  = mid;
        b->clo[r] = b->c[r];
      }
    }
  } while (open);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDecompCut(SpamDecomp *dec, PetscInt n, const uint64_t *sorted_keys)
{
  const PetscMPIInt P = dec->nranks;
  PetscInt64        N = n, *at;
  Bisection         b;

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &N, 1, MPIU_INT64, MPI_SUM, dec->comm));
  PetscCall(PetscMalloc7(P, &b.lo, P, &b.hi, P, &b.clo, P, &b.chi, P, &b.target, P, &b.c, P + 1, &at));
  PetscCall(Bisect(dec, n, sorted_keys, N, &b));
  dec->cut[0] = 0;
  dec->cut[P] = (uint64_t)1 << (dec->grid.dim * dec->grid.bits);
  at[0]       = 0;
  at[P]       = N;
  for (PetscMPIInt r = 1; r < P; r++) {
    /* Both ends are cell boundaries; the nearer to the target splits the straddling cell
     * best: |C - T| <= half that cell's particles. */
    const PetscBool low = (PetscBool)(b.target[r] == 0 || b.target[r] - b.clo[r] < b.chi[r] - b.target[r]);
    dec->cut[r]         = low ? b.lo[r] : b.hi[r];
    at[r]               = low ? b.clo[r] : b.chi[r];
  }
  for (PetscMPIInt r = 0; r < P; r++) dec->count[r] = at[r + 1] - at[r];
  dec->cut_imbalance = SpamDecompImbalance(P, dec->count);
  dec->has_cut       = PETSC_TRUE;
  dec->cuts++;
  PetscCall(PetscFree7(b.lo, b.hi, b.clo, b.chi, b.target, b.c, at));
  PetscFunctionReturn(0);
}
