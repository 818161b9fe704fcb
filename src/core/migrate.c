/* Migration between steps (decompose.h): owners by the curve cut, DMSwarmMigrate of a
 * DMSWARM_BASIC swarm with our own destination in DMSwarm_rank (the PIC migration with a
 * DMDA cell DM loses and duplicates particles in PETSc 3.18), then the local sort, which
 * also drops what was sent, and X re-made.
 *
 * Every local phase ends in Agree: an error raised on some ranks only would leave the
 * others waiting in the next collective call for ever (an early multi-rank run hung so).
 * The swarm may only resize while no field is open, so X (which holds the state field)
 * and the gid field are closed around DMSwarmMigrate; what the particles' owner keeps
 * outside the swarm it puts into the swarm's carried fields, or sends otherwise, in its
 * depart (swarm.h). */
#include <spam/decompose.h>
#include <spam/errors.h>
#include <stdint.h>

/* Curve key of each particle's cell; *bad: the smallest gid with a non-finite position
 * (INT64_MAX if none), whose owner cannot be known. */
static PetscErrorCode CurveKeys(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, uint64_t *key, PetscInt64 *bad)
{
  const PetscScalar *y;

  PetscFunctionBeginUser;
  *bad = INT64_MAX;
  PetscCall(VecGetArrayRead(p->X, &y));
  for (PetscInt i = 0; i < p->n; i++) {
    const double *x = y + (size_t)i * m->nvar + m->x;
    for (int d = 0; d < m->dim; d++)
      if (!isfinite(x[d])) *bad = PetscMin(*bad, p->gid[i]);
    key[i] = SpamDecompKey(dec, x);
  }
  PetscCall(VecRestoreArrayRead(p->X, &y));
  PetscFunctionReturn(0);
}

static int CompareKeys(const void *a, const void *b)
{
  const uint64_t p = *(const uint64_t *)a, q = *(const uint64_t *)b;
  return (p > q) - (p < q);
}

/* A new cut from the particles' keys (collective; the sorted copy is local). */
static PetscErrorCode Recut(SpamDecomp *dec, PetscInt n, const uint64_t *key)
{
  uint64_t      *sorted = NULL;
  PetscErrorCode ierr   = PetscMalloc1(n + 1, &sorted);

  PetscFunctionBeginUser;
  if (!ierr) {
    PetscCall(PetscArraycpy(sorted, key, n));
    qsort(sorted, (size_t)n, sizeof *sorted, CompareKeys);
  }
  PetscCall(SpamAgreeOnFailure(dec->comm, ierr, "a re-cut"));
  PetscCall(SpamDecompCut(dec, n, sorted));
  PetscCall(PetscFree(sorted));
  PetscFunctionReturn(0);
}

/* dest[i] by the cut in force, and over all ranks: tally[r] the particles rank r will
 * hold, tally[P] the particles that change rank. */
static PetscErrorCode Destinations(const SpamDecomp *dec, PetscInt n, const uint64_t *key, PetscInt *dest, PetscInt64 *tally)
{
  const PetscMPIInt P = dec->nranks;

  PetscFunctionBeginUser;
  for (PetscMPIInt r = 0; r <= P; r++) tally[r] = 0;
  for (PetscInt i = 0; i < n; i++) {
    dest[i] = SpamDecompOwner(dec, key[i]);
    tally[dest[i]]++;
    tally[P] += dest[i] != dec->rank;
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, tally, P + 1, MPIU_INT64, MPI_SUM, dec->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmClose(SpamSwarm *p, const PetscInt *dest)
{
  PetscInt *rank;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(p->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(PetscArraycpy(rank, dest, p->n));
  PetscCall(DMSwarmRestoreField(p->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(DMSwarmRestoreField(p->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&p->gid));
  p->gid = NULL;
  PetscCall(SpamSwarmCloseState(p));
  PetscFunctionReturn(0);
}

/* The arrived particles in order, the gid field re-opened and its index re-made. */
static PetscErrorCode Reorder(SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec)
{
  PetscBool permuted;

  PetscFunctionBeginUser;
  PetscCall(SpamSwarmSortLocal(p, m, dec, &permuted));
  PetscCall(DMSwarmGetField(p->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&p->gid));
  PetscCall(DMSwarmGetLocalSize(p->swarm, &p->n));
  PetscCall(SpamSwarmIndexRows(p));
  PetscFunctionReturn(0);
}

/* Whether every rank's particles are already in (cell, gid) order. */
static PetscErrorCode AllSorted(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, PetscBool *sorted)
{
  const PetscScalar *y;
  int                mine, all;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(p->X, &y));
  mine = SpamSwarmSortedLocal(p, m, dec, y);
  PetscCall(VecRestoreArrayRead(p->X, &y));
  PetscCallMPI(MPIU_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, p->comm));
  *sorted = (PetscBool)all;
  PetscFunctionReturn(0);
}

/* Sends the particles by dest, sorts and re-makes X, then the owner's arrival (collective). */
static PetscErrorCode Move(SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, const PetscInt *dest, PetscInt64 moved)
{
  PetscFunctionBeginUser;
  PetscCall(m->depart(m->ctx, dest)); /* by the old gids and order */
  PetscCall(SpamAgreeOnFailure(p->comm, SpamSwarmClose(p, dest), "closing the swarm for a migration"));
  /* Sent particles stay until the sort drops them all at once (local_order.c says why). */
  if (moved) PetscCall(DMSwarmMigrate(p->swarm, PETSC_FALSE));
  PetscCall(SpamAgreeOnFailure(p->comm, Reorder(p, m, dec), "the local sort after a migration"));
  PetscCall(SpamSwarmOpenState(p));
  PetscCall(m->arrive(m->ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmMigrate(SpamSwarm *p, const SpamMigration *m, SpamDecomp *dec, SpamMigrateInfo *info)
{
  const PetscMPIInt P  = dec->nranks;
  const PetscInt    n0 = p->n;
  uint64_t         *key  = NULL;
  PetscInt         *dest = NULL;
  PetscInt64       *tally = NULL, bad = INT64_MAX;
  PetscBool         sorted = PETSC_FALSE;
  PetscErrorCode    ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(info, sizeof *info));
  info->bad = -1;
  ierr = PetscMalloc3(n0 + 1, &key, n0 + 1, &dest, P + 1, &tally);
  if (!ierr) ierr = CurveKeys(p, m, dec, key, &bad);
  PetscCall(SpamAgreeOnFailure(p->comm, ierr, "the owners of a migration"));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT64, MPI_MIN, p->comm));
  if (bad != INT64_MAX) {
    info->bad = bad;
    PetscCall(PetscFree3(key, dest, tally));
    PetscFunctionReturn(0);
  }
  if (dec->has_cut) { /* what the cut in force would give */
    PetscCall(Destinations(dec, n0, key, dest, tally));
    info->imbalance_before = SpamDecompImbalance(P, tally);
    /* Not below what the last cut itself achieved: with few particles per rank the
     * granularity of the cells would otherwise ask for a cut at every call. */
    info->recut = (PetscBool)(info->imbalance_before > PetscMax(dec->recut_above, dec->cut_imbalance));
  } else { /* no cut yet: the particles as they are placed now */
    PetscInt64 n = n0;
    PetscCall(PetscArrayzero(tally, P));
    PetscCallMPI(MPI_Allgather(&n, 1, MPIU_INT64, tally, 1, MPIU_INT64, p->comm));
    info->imbalance_before = SpamDecompImbalance(P, tally);
    info->recut            = PETSC_TRUE;
  }
  if (info->recut) {
    PetscCall(Recut(dec, n0, key));
    PetscCall(Destinations(dec, n0, key, dest, tally));
  }
  info->moved     = tally[P];
  info->imbalance = SpamDecompImbalance(P, tally);
  for (PetscInt i = 0; i < n0; i++) info->sent += dest[i] != dec->rank;
  if (!info->moved) PetscCall(AllSorted(p, m, dec, &sorted));
  if (!sorted) {
    PetscCall(Move(p, m, dec, dest, info->moved));
    info->changed  = PETSC_TRUE;
    info->resized  = (PetscBool)(p->n != n0);
    info->received = p->n - (n0 - info->sent);
  }
  dec->imbalance = info->imbalance;
  dec->migrations++;
  PetscCall(PetscFree3(key, dest, tally));
  PetscFunctionReturn(0);
}
