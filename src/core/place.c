/* A restart on the ranks of its checkpoint puts every particle back on the rank, and at the
 * place in its local order, that the checkpoint holds it at (decompose.h): the pair sums
 * follow the local order, so only the same blocks in the same order continue the run bit
 * for bit. The run's own start distributed the scene by a fresh cut; the checkpoint's
 * blocks come from the migrations since. Who gets gid g is found without any rank holding
 * a table of all gids: the checkpoint's blocks tell a PetscSF over the gids (rows in
 * blocks of consecutive gids, as particle_rows.c lays them out) which rank each gid goes
 * to, and a second one tells each particle's present holder. */
#include <spam/decompose.h>
#include <spam/physics.h>
#include <spam/errors.h>

/* An SF from n leaves (gids) to the rows of the gids' block layout. */
static PetscErrorCode GidGraph(const SpamSim *sim, PetscLayout layout, PetscInt n, const PetscInt64 *gids, PetscSF *sf)
{
  PetscInt *at;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &at));
  for (PetscInt i = 0; i < n; i++) at[i] = (PetscInt)gids[i];
  PetscCall(PetscSFCreate(sim->comm, sf));
  PetscCall(PetscSFSetGraphLayout(*sf, layout, n, NULL, PETSC_COPY_VALUES, at));
  PetscCall(PetscSFSetUp(*sf));
  PetscCall(PetscFree(at));
  PetscFunctionReturn(0);
}

/* dest[i]: the rank whose block holds the gid of local particle i (-1: none). */
static PetscErrorCode Owners(const SpamSim *sim, PetscInt n, const PetscInt64 *gids, PetscInt *dest)
{
  PetscLayout layout;
  PetscSF     sf;
  PetscInt   *owner, *me, lo, hi;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(sim->comm, &rank));
  PetscCall(PetscLayoutCreate(sim->comm, &layout));
  PetscCall(PetscLayoutSetSize(layout, sim->nglobal));
  PetscCall(PetscLayoutSetUp(layout));
  PetscCall(PetscLayoutGetRange(layout, &lo, &hi));
  PetscCall(PetscMalloc2(hi - lo + 1, &owner, n + 1, &me));
  for (PetscInt r = 0; r < hi - lo; r++) owner[r] = -1;
  for (PetscInt i = 0; i < n; i++) me[i] = rank;
  PetscCall(GidGraph(sim, layout, n, gids, &sf));
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, me, owner, MPI_REPLACE));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, me, owner, MPI_REPLACE));
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(GidGraph(sim, layout, sim->n, sim->gid, &sf));
  PetscCall(PetscSFBcastBegin(sf, MPIU_INT, owner, dest, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_INT, owner, dest, MPI_REPLACE));
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(PetscFree2(owner, me));
  PetscCall(PetscLayoutDestroy(&layout));
  PetscFunctionReturn(0);
}

/* The block's gids lie in the scene and the blocks hold nglobal particles in all. */
static PetscErrorCode CheckBlock(const SpamSim *sim, PetscInt n, const PetscInt64 *gids)
{
  PetscInt64 bad = -1, total = n;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n && bad < 0; i++)
    if (gids[i] < 0 || gids[i] >= sim->nglobal) bad = gids[i] < 0 ? 0 : gids[i];
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT64, MPI_MAX, sim->comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &total, 1, MPIU_INT64, MPI_SUM, sim->comm));
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks hold a particle id outside 0..%" PetscInt64_FMT, (PetscInt64)sim->nglobal - 1);
  PetscCheck(total == sim->nglobal, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks hold %" PetscInt64_FMT " particles, the scene %" PetscInt64_FMT, total, (PetscInt64)sim->nglobal);
  PetscFunctionReturn(0);
}

/* Whether the particles sit as the blocks say (same rank, same place), over all ranks. */
static PetscErrorCode InPlace(const SpamSim *sim, PetscInt n, const PetscInt64 *gids, const PetscInt *dest, PetscBool *in_place, PetscInt64 *missing)
{
  PetscMPIInt rank;
  int         ok;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(sim->comm, &rank));
  ok       = sim->n == n;
  *missing = -1;
  for (PetscInt i = 0; i < sim->n; i++) {
    if (dest[i] < 0) *missing = PetscMax(*missing, sim->gid[i]);
    if (dest[i] != rank || (ok && sim->gid[i] != gids[i])) ok = 0;
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_LAND, sim->comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, missing, 1, MPIU_INT64, MPI_MAX, sim->comm));
  *in_place = (PetscBool)ok;
  PetscFunctionReturn(0);
}

/* The arrived particles in the block's order, the gid field re-opened and indexed. */
static PetscErrorCode Reorder(SpamSim *sim, PetscInt n, const PetscInt64 *gids)
{
  PetscBool permuted;

  PetscFunctionBeginUser;
  PetscCall(SpamSwarmSortLocalAs(sim, n, gids, &permuted));
  PetscCall(DMSwarmGetField(sim->swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&sim->gid));
  PetscCall(DMSwarmGetLocalSize(sim->swarm, &sim->n));
  PetscCall(SpamSimIndexRows(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimPlace(SpamSim *sim, PetscInt n, const PetscInt64 *gids, PetscBool *changed)
{
  PetscInt  *dest = NULL;
  PetscInt64 missing = -1;
  PetscBool  in_place = PETSC_FALSE;
  int        wrong;

  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  PetscCall(CheckBlock(sim, n, gids));
  PetscCall(PetscMalloc1(sim->n + 1, &dest));
  PetscCall(Owners(sim, n, gids, dest));
  PetscCall(InPlace(sim, n, gids, dest, &in_place, &missing));
  if (missing >= 0) PetscCall(PetscFree(dest));
  PetscCheck(missing < 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks lack particle %" PetscInt64_FMT, missing);
  if (in_place) {
    PetscCall(PetscFree(dest));
    PetscFunctionReturn(0);
  }
  *changed = PETSC_TRUE;
  if (sim->model.carry_depart) PetscCall(sim->model.carry_depart(sim, dest)); /* as a migration carries them */
  PetscCall(SpamAgreeOnFailure(sim->comm, SpamSimDetach(sim, dest), "closing the swarm to place the particles"));
  PetscCall(PetscFree(dest));
  PetscCall(DMSwarmMigrate(sim->swarm, PETSC_FALSE));
  PetscCall(SpamAgreeOnFailure(sim->comm, Reorder(sim, n, gids), "the local order of a checkpoint"));
  if (sim->model.carry_arrive) PetscCall(sim->model.carry_arrive(sim));
  PetscCall(DMSwarmCreateGlobalVectorFromField(sim->swarm, SPAM_STATE_FIELD, &sim->X));
  PetscCall(SpamAgreeOnFailure(sim->comm, SpamSimResize(sim), "re-making the scratch for the checkpoint's particles"));
  wrong = sim->n != n;
  for (PetscInt i = 0; i < sim->n && !wrong; i++) wrong = sim->gid[i] != gids[i];
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &wrong, 1, MPI_INT, MPI_MAX, sim->comm));
  PetscCheck(!wrong, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the checkpoint's blocks name a particle twice");
  PetscFunctionReturn(0);
}
