/* The local order after a migration: by the cell's place on the Hilbert curve of the cut
 * (cell_keys.c), then by gid. (Not the set-up sort's rows or Morton curve: a piece of the
 * local order along the Hilbert curve has no jumps, so the boxes of its parts, which
 * decide the halo (halo.c), hug the rank's particles.) A migration appends what arrives, so without this the order would depend on
 * the history of migrations; with it, it depends only on which particles a rank holds and
 * where they are, and particles near in space stay near in memory (what the set-up sort
 * is for). The same pass drops the particles that were sent away (their DMSwarm_rank is
 * another rank's): sorted to the end and cut off with one resize. PETSc's own removal
 * (DMSwarmMigrate with remove_sent_points) resizes every field once per removed particle:
 * with an allocator that copies on a shrinking realloc (AddressSanitizer's does) that
 * is quadratic, and the test's 10^5-particle distribution did not finish in 4 minutes. */
#include <spam/decompose.h>
#include <string.h>

typedef struct {
  int        gone; /* sent to another rank: dropped */
  uint64_t   cell;
  PetscInt64 gid;
  PetscInt   i;
} LocalKey;

static int CompareLocal(const void *a, const void *b)
{
  const LocalKey *p = a, *q = b;
  if (p->gone != q->gone) return p->gone - q->gone;
  if (p->cell != q->cell) return p->cell < q->cell ? -1 : 1;
  return (p->gid > q->gid) - (p->gid < q->gid);
}

static uint64_t OrderKeyOf(const SpamCellGrid *g, const SpamBox *box, const double *x)
{
  int c[3];
  SpamCellOf(g, box, x, c);
  return SpamCellHilbertKey(g, c);
}

PetscBool SpamSwarmSortedLocal(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, const double *y)
{
  uint64_t prev = 0;

  for (PetscInt i = 0; i < p->n; i++) {
    const uint64_t k = OrderKeyOf(&dec->grid, &dec->box, y + (size_t)i * m->nvar + m->x);
    if (i > 0 && (k < prev || (k == prev && p->gid[i] < p->gid[i - 1]))) return PETSC_FALSE;
    prev = k;
  }
  return PETSC_TRUE;
}

/* a[i] = old a[order[i].i] for i < keep, for the field's whole block of bytes; tmp holds
 * n blocks. */
static PetscErrorCode PermuteField(DM sw, const char *name, PetscInt n, PetscInt keep, const LocalKey *order, char *tmp)
{
  PetscInt      bs;
  PetscDataType type;
  size_t        size;
  char         *a;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(sw, name, &bs, &type, (void **)&a));
  PetscCall(PetscDataTypeGetSize(type, &size));
  size *= (size_t)bs;
  memcpy(tmp, a, (size_t)n * size);
  for (PetscInt i = 0; i < keep; i++) memcpy(a + (size_t)i * size, tmp + (size_t)order[i].i * size, size);
  PetscCall(DMSwarmRestoreField(sw, name, &bs, &type, (void **)&a));
  PetscFunctionReturn(0);
}

/* The place of gid in a checkpoint's local order (SpamSwarmSortLocalAs): the gids sorted,
 * with their places. */
typedef struct {
  PetscInt64 gid;
  PetscInt   at;
} Place;

typedef struct {
  PetscInt n;
  Place   *p; /* by gid */
} Places;

static int ComparePlaces(const void *a, const void *b)
{
  const PetscInt64 p = ((const Place *)a)->gid, q = ((const Place *)b)->gid;
  return (p > q) - (p < q);
}

/* A gid not among the places sorts after all that are (the caller counts them). */
static uint64_t PlaceOf(const Places *p, PetscInt64 gid)
{
  PetscInt lo = 0, hi = p->n;
  while (lo < hi) {
    const PetscInt mid = lo + (hi - lo) / 2;
    if (p->p[mid].gid < gid) lo = mid + 1;
    else hi = mid;
  }
  return lo < p->n && p->p[lo].gid == gid ? (uint64_t)p->p[lo].at : UINT64_MAX;
}

/* The sort keys of the n local particles, straight from the swarm's fields: the order
 * key of the cell, or (places given) the particle's place; *keep counts those whose
 * DMSwarm_rank is this rank. */
static PetscErrorCode MakeKeys(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, const Places *places, PetscInt n, LocalKey *key, PetscInt *keep)
{
  PetscReal  *s;
  PetscInt64 *gid;
  PetscInt   *rank;
  PetscMPIInt me;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(p->comm, &me));
  PetscCall(DMSwarmGetField(p->swarm, SPAM_STATE_FIELD, NULL, NULL, (void **)&s));
  PetscCall(DMSwarmGetField(p->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&gid));
  PetscCall(DMSwarmGetField(p->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  *keep = 0;
  for (PetscInt i = 0; i < n; i++) {
    const uint64_t k = places ? PlaceOf(places, gid[i]) : OrderKeyOf(&dec->grid, &dec->box, s + (size_t)i * m->nvar + m->x);
    key[i]           = (LocalKey){rank[i] != me, k, gid[i], i};
    *keep += rank[i] == me;
  }
  PetscCall(DMSwarmRestoreField(p->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(DMSwarmRestoreField(p->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&gid));
  PetscCall(DMSwarmRestoreField(p->swarm, SPAM_STATE_FIELD, NULL, NULL, (void **)&s));
  PetscFunctionReturn(0);
}

/* Every field that belongs to a particle: the state, the gid and the owner's carried
 * fields; PETSc's DMSwarm_pid (unused) and DMSwarm_rank (set before each migration) need
 * no order. tmp holds n blocks of the largest, the state's (nvar reals). */
static PetscErrorCode PermuteAll(const SpamSwarm *p, const SpamMigration *m, PetscInt n, PetscInt keep, const LocalKey *key)
{
  char *tmp;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1((size_t)n * m->nvar * sizeof(PetscReal) + 1, &tmp));
  PetscCall(PermuteField(p->swarm, SPAM_STATE_FIELD, n, keep, key, tmp));
  PetscCall(PermuteField(p->swarm, SPAM_GID_FIELD, n, keep, key, tmp));
  for (int f = 0; f < m->ncarried; f++) PetscCall(PermuteField(p->swarm, m->carried[f], n, keep, key, tmp));
  PetscCall(PetscFree(tmp));
  PetscFunctionReturn(0);
}

static PetscErrorCode SortBy(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, const Places *places, PetscBool *permuted)
{
  PetscInt  n, keep;
  LocalKey *key;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(p->swarm, &n));
  PetscCall(PetscMalloc1(n + 1, &key));
  PetscCall(MakeKeys(p, m, dec, places, n, key, &keep));
  qsort(key, (size_t)n, sizeof *key, CompareLocal);
  *permuted = (PetscBool)(keep < n);
  for (PetscInt i = 0; i < keep && !*permuted; i++) *permuted = (PetscBool)(key[i].i != i);
  if (*permuted) PetscCall(PermuteAll(p, m, n, keep, key));
  PetscCall(PetscFree(key));
  if (keep < n) PetscCall(DMSwarmSetLocalSizes(p->swarm, keep, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmSortLocal(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, PetscBool *permuted)
{
  PetscFunctionBeginUser;
  PetscCall(SortBy(p, m, dec, NULL, permuted));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmSortLocalAs(const SpamSwarm *p, const SpamMigration *m, PetscInt n, const PetscInt64 *gids, PetscBool *permuted)
{
  Places at = {n, NULL};

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &at.p));
  for (PetscInt i = 0; i < n; i++) at.p[i] = (Place){gids[i], i};
  qsort(at.p, (size_t)n, sizeof *at.p, ComparePlaces);
  PetscCall(SortBy(p, m, NULL, &at, permuted));
  PetscCall(PetscFree(at.p));
  PetscFunctionReturn(0);
}
