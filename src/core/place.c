/* A restart on the ranks of its checkpoint puts every particle back on the rank, and at the
 * place in its local order, that the checkpoint holds it at (decompose.h): the pair sums
 * follow the local order, so only the same blocks in the same order continue the run bit
 * for bit. The run's own start distributed the scene by a fresh cut; the checkpoint's
 * blocks come from the migrations since. Who gets gid g is found without any rank holding
 * a table of all gids: the checkpoint's blocks tell a PetscSF over the gids (rows in
 * blocks of consecutive gids, as particle_rows.c lays them out) which rank each gid goes
 * to, and a second one tells each particle's present holder. */
#include <spam/decompose.h>
#include <spam/errors.h>
#include <petscsf.h>

/* An SF from n leaves (gids) to the rows of the gids' block layout. */
static PetscErrorCode GidGraph(const SpamSwarm *p, PetscLayout layout, PetscInt n, const PetscInt64 *gids, PetscSF *sf)
{
  PetscInt *at;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &at));
  for (PetscInt i = 0; i < n; i++) at[i] = (PetscInt)gids[i];
  PetscCall(PetscSFCreate(p->comm, sf));
  PetscCall(PetscSFSetGraphLayout(*sf, layout, n, NULL, PETSC_COPY_VALUES, at));
  PetscCall(PetscSFSetUp(*sf));
  PetscCall(PetscFree(at));
  PetscFunctionReturn(0);
}

/* dest[i]: the rank whose block holds the gid of local particle i (-1: none). */
static PetscErrorCode Owners(const SpamSwarm *p, PetscInt n, const PetscInt64 *gids, PetscInt *dest)
{
  PetscLayout layout;
  PetscSF     sf;
  PetscInt   *owner, *me, lo, hi;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(p->comm, &rank));
  PetscCall(PetscLayoutCreate(p->comm, &layout));
  PetscCall(PetscLayoutSetSize(layout, p->nglobal));
  PetscCall(PetscLayoutSetUp(layout));
  PetscCall(PetscLayoutGetRange(layout, &lo, &hi));
  PetscCall(PetscMalloc2(hi - lo + 1, &owner, n + 1, &me));
  for (PetscInt r = 0; r < hi - lo; r++) owner[r] = -1;
  for (PetscInt i = 0; i < n; i++) me[i] = rank;
  PetscCall(GidGraph(p, layout, n, gids, &sf));
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, me, owner, MPI_REPLACE));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, me, owner, MPI_REPLACE));
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(GidGraph(p, layout, p->n, p->gid, &sf));
  PetscCall(PetscSFBcastBegin(sf, MPIU_INT, owner, dest, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_INT, owner, dest, MPI_REPLACE));
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(PetscFree2(owner, me));
  PetscCall(PetscLayoutDestroy(&layout));
  PetscFunctionReturn(0);
}

/* The block's gids lie in the scene and the blocks hold nglobal particles in all. */
static PetscErrorCode CheckBlock(const SpamSwarm *p, PetscInt n, const PetscInt64 *gids)
{
  PetscInt64 bad = -1, total = n;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n && bad < 0; i++)
    if (gids[i] < 0 || gids[i] >= p->nglobal) bad = gids[i] < 0 ? 0 : gids[i];
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT64, MPI_MAX, p->comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &total, 1, MPIU_INT64, MPI_SUM, p->comm));
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks hold a particle id outside 0..%" PetscInt64_FMT, (PetscInt64)p->nglobal - 1);
  PetscCheck(total == p->nglobal, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks hold %" PetscInt64_FMT " particles, the scene %" PetscInt64_FMT, total, (PetscInt64)p->nglobal);
  PetscFunctionReturn(0);
}

/* Whether the particles sit as the blocks say (same rank, same place), over all ranks. */
static PetscErrorCode InPlace(const SpamSwarm *p, PetscInt n, const PetscInt64 *gids, const PetscInt *dest, PetscBool *in_place, PetscInt64 *missing)
{
  PetscMPIInt rank;
  int         ok;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(p->comm, &rank));
  ok       = p->n == n;
  *missing = -1;
  for (PetscInt i = 0; i < p->n; i++) {
    if (dest[i] < 0) *missing = PetscMax(*missing, p->gid[i]);
    if (dest[i] != rank || (ok && p->gid[i] != gids[i])) ok = 0;
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_LAND, p->comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, missing, 1, MPIU_INT64, MPI_MAX, p->comm));
  *in_place = (PetscBool)ok;
  PetscFunctionReturn(0);
}

/* The arrived particles in the block's order, the gid field re-opened and indexed. */
static PetscErrorCode Reorder(SpamSwarm *p, const SpamMigration *m, PetscInt n, const PetscInt64 *gids)
{
  PetscBool permuted;

  PetscFunctionBeginUser;
  PetscCall(SpamSwarmSortLocalAs(p, m, n, gids, &permuted));
  PetscCall(DMSwarmGetField(p->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&p->gid));
  PetscCall(DMSwarmGetLocalSize(p->swarm, &p->n));
  PetscCall(SpamSwarmIndexRows(p));
  PetscFunctionReturn(0);
}

/* Sends the particles by dest, in the block's order, X re-made, the owner's arrival. */
static PetscErrorCode Move(SpamSwarm *p, const SpamMigration *m, PetscInt n, const PetscInt64 *gids, const PetscInt *dest)
{
  PetscFunctionBeginUser;
  PetscCall(m->depart(m->ctx, dest)); /* as a migration carries them */
  PetscCall(SpamAgreeOnFailure(p->comm, SpamSwarmClose(p, dest), "closing the swarm to place the particles"));
  PetscCall(DMSwarmMigrate(p->swarm, PETSC_FALSE));
  PetscCall(SpamAgreeOnFailure(p->comm, Reorder(p, m, n, gids), "the local order of a checkpoint"));
  PetscCall(SpamSwarmOpenState(p));
  PetscCall(m->arrive(m->ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSwarmPlace(SpamSwarm *p, const SpamMigration *m, PetscInt n, const PetscInt64 *gids, PetscBool *changed)
{
  PetscInt  *dest = NULL;
  PetscInt64 missing = -1;
  PetscBool  in_place = PETSC_FALSE;
  int        wrong;

  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  PetscCall(CheckBlock(p, n, gids));
  PetscCall(PetscMalloc1(p->n + 1, &dest));
  PetscCall(Owners(p, n, gids, dest));
  PetscCall(InPlace(p, n, gids, dest, &in_place, &missing));
  if (missing >= 0 || in_place) PetscCall(PetscFree(dest));
  PetscCheck(missing < 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks lack particle %" PetscInt64_FMT, missing);
  if (in_place) PetscFunctionReturn(0);
  *changed = PETSC_TRUE;
  PetscCall(Move(p, m, n, gids, dest));
  PetscCall(PetscFree(dest));
  wrong = p->n != n;
  for (PetscInt i = 0; i < p->n && !wrong; i++) wrong = p->gid[i] != gids[i];
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &wrong, 1, MPI_INT, MPI_MAX, p->comm));
  PetscCheck(!wrong, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks name a particle twice");
  PetscFunctionReturn(0);
}
