/* The gid index of the local particles (swarm.h). */
#include <spam/swarm.h>
#include <stdint.h>

typedef struct {
  PetscInt64 gid;
  PetscInt   i;
} GidIndex;

static int CompareGids(const void *a, const void *b)
{
  const GidIndex *p = a, *q = b;
  return (p->gid > q->gid) - (p->gid < q->gid);
}

PetscErrorCode SpamSwarmSetRows(SpamSwarm *p, const PetscInt *row_of)
{
  PetscInt64 first = INT64_MAX; /* this rank's gids are first .. first + n - 1 */

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < p->n; i++) first = PetscMin(first, p->gid[i]);
  for (PetscInt i = 0; i < p->n; i++) p->gid[i] = first + row_of[i];
  PetscCall(SpamSwarmIndexRows(p));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmIndexRows(SpamSwarm *p)
{
  PetscBool sorted = PETSC_TRUE;
  GidIndex *key;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(p->at_row));
  for (PetscInt i = 1; i < p->n && sorted; i++) sorted = (PetscBool)(p->gid[i] > p->gid[i - 1]);
  if (sorted) PetscFunctionReturn(0); /* at_row would be the identity */
  PetscCall(PetscMalloc1(p->n, &key));
  PetscCall(PetscMalloc1(p->n, &p->at_row));
  for (PetscInt i = 0; i < p->n; i++) key[i] = (GidIndex){p->gid[i], i};
  qsort(key, (size_t)p->n, sizeof *key, CompareGids);
  for (PetscInt r = 0; r < p->n; r++) p->at_row[r] = key[r].i;
  PetscCall(PetscFree(key));
  PetscFunctionReturn(0);
}
