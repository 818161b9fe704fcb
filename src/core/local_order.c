/* The local order after a migration: by the cell of the set-up sort (cell_keys.c), then
 * by gid. Removal in DMSwarmMigrate moves the last particle into each hole and appends
 * what arrives, so without this the order would depend on the history of migrations;
 * with it, it depends only on which particles a rank holds and where they are, and
 * particles near in space stay near in memory (what the set-up sort is for). */
#include <spam/decompose.h>
#include <string.h>

typedef struct {
  uint64_t   cell;
  PetscInt64 gid;
  PetscInt   i;
} LocalKey;

static int CompareLocal(const void *a, const void *b)
{
  const LocalKey *p = a, *q = b;
  if (p->cell != q->cell) return p->cell < q->cell ? -1 : 1;
  return (p->gid > q->gid) - (p->gid < q->gid);
}

static uint64_t OrderKeyOf(const SpamCellGrid *g, const SpamBox *box, const double *x)
{
  int c[3];
  SpamCellOf(g, box, x, c);
  return SpamCellOrderKey(g, c);
}

PetscBool SpamSimIsSortedLocal(const SpamSim *sim, const SpamCellGrid *grid, const double *y)
{
  const SpamLayout *l    = &sim->model.layout;
  uint64_t          prev = 0;

  for (PetscInt i = 0; i < sim->n; i++) {
    const uint64_t k = OrderKeyOf(grid, &sim->box, y + (size_t)i * l->nvar + l->x);
    if (i > 0 && (k < prev || (k == prev && sim->gid[i] < sim->gid[i - 1]))) return PETSC_FALSE;
    prev = k;
  }
  return PETSC_TRUE;
}

/* Every field that belongs to a particle; PETSc's DMSwarm_pid (unused) and DMSwarm_rank
 * (set before each migration) need no order. */
static const char *const particle_fields[] = {SPAM_STATE_FIELD, SPAM_GID_FIELD, SPAM_MASS_FIELD, SPAM_BODY_FIELD};

/* a[i] = old a[order[i].i], for the field's whole block of bytes; tmp holds n blocks. */
static PetscErrorCode PermuteField(DM sw, const char *name, PetscInt n, const LocalKey *order, char *tmp)
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
  for (PetscInt i = 0; i < n; i++) memcpy(a + (size_t)i * size, tmp + (size_t)order[i].i * size, size);
  PetscCall(DMSwarmRestoreField(sw, name, &bs, &type, (void **)&a));
  PetscFunctionReturn(0);
}

/* The sort keys of the n local particles, straight from the swarm's fields. */
static PetscErrorCode MakeKeys(SpamSim *sim, const SpamCellGrid *grid, PetscInt n, LocalKey *key)
{
  const SpamLayout *l = &sim->model.layout;
  PetscReal        *s;
  PetscInt64       *gid;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(sim->swarm, SPAM_STATE_FIELD, NULL, NULL, (void **)&s));
  PetscCall(DMSwarmGetField(sim->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&gid));
  for (PetscInt i = 0; i < n; i++) key[i] = (LocalKey){OrderKeyOf(grid, &sim->box, s + (size_t)i * l->nvar + l->x), gid[i], i};
  PetscCall(DMSwarmRestoreField(sim->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&gid));
  PetscCall(DMSwarmRestoreField(sim->swarm, SPAM_STATE_FIELD, NULL, NULL, (void **)&s));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmSortLocal(SpamSim *sim, const SpamCellGrid *grid, PetscBool *permuted)
{
  PetscInt  n;
  LocalKey *key;
  char     *tmp;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(sim->swarm, &n));
  PetscCall(PetscMalloc1(n + 1, &key));
  PetscCall(MakeKeys(sim, grid, n, key));
  qsort(key, (size_t)n, sizeof *key, CompareLocal);
  *permuted = PETSC_FALSE;
  for (PetscInt i = 0; i < n && !*permuted; i++) *permuted = (PetscBool)(key[i].i != i);
  if (*permuted) {
    /* the state's block (nvar reals) is the largest of the fields */
    PetscCall(PetscMalloc1((size_t)n * sim->model.layout.nvar * sizeof(PetscReal) + 1, &tmp));
    for (size_t f = 0; f < sizeof particle_fields / sizeof *particle_fields; f++) PetscCall(PermuteField(sim->swarm, particle_fields[f], n, key, tmp));
    PetscCall(PetscFree(tmp));
  }
  PetscCall(PetscFree(key));
  PetscFunctionReturn(0);
}
