/* Migrations during a multi-rank run. Between two accepted steps, after -migrate_interval
 * list builds (or sooner when the halo has grown: MigrationDue), every particle goes to the
 * owner of its cell (SpamSimMigrate: a re-cut when
 * the imbalance has grown past its threshold), and whatever holds one value per particle
 * follows: the TS solution and ERKStep's vectors (SpamTSARKodeResize keeps the step and
 * error history), the loop's last good state and interpolation scratch, the list's kept
 * reference positions. Without migrations the run stays correct (a rank's halo is taken
 * from the bounding box of its particles wherever they are), only slower as the boxes grow.
 * ERKStep, rk, ssp, euler and block_kdk (between its cycles, carrying its rates by id)
 * follow (SpamTSFollowParticles); cvode and basicsymplectic keep the first distribution. */
#include <spam/integrator.h>
#include <spam/decompose.h>
#include "loop_state.h"

PetscErrorCode SpamLoopRemakeVectors(SpamSim *sim, SpamLoop *L)
{
  PetscFunctionBeginUser;
  if (L->Xgood) { /* else the method keeps the last good state (time_loop.c) */
    PetscCall(VecDestroy(&L->Xgood));
    PetscCall(VecDuplicate(sim->p.X, &L->Xgood));
    PetscCall(VecCopy(sim->p.X, L->Xgood));
  }
  if (L->s.Xout) {
    PetscCall(VecDestroy(&L->s.Xout));
    PetscCall(VecDuplicate(sim->p.X, &L->s.Xout));
  }
  PetscCall(PetscFree(L->xref_keep));
  PetscCall(PetscMalloc1((size_t)sim->p.n * (sim->model.dim + 1) + 1, &L->xref_keep));
  PetscFunctionReturn(0);
}

/* The largest halo of any rank: other ranks' particles it holds as ghosts (collective). */
static PetscErrorCode HaloMax(const SpamSim *sim, double *halo)
{
  const double mine = sim->pair.nl.ghosts.n - sim->pair.nl.ghosts.nlocal;

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(&mine, halo, 1, MPI_DOUBLE, MPI_MAX, sim->p.comm));
  *halo = PetscMax(*halo, 1.0); /* a halo of none grows by no factor */
  PetscFunctionReturn(0);
}

/* Whether a migration is due: -migrate_interval builds since the last, or sooner, at a
 * build, when the largest halo has grown by SPAM_MIGRATE_HALO_GROWTH since it (the parts of
 * a rank's particles spread as they move, and its halo with them: the 3D expansion's grew
 * 4.4-fold in 20 builds). The build count is the same on every rank, so is the decision. */
static PetscErrorCode MigrationDue(const SpamSim *sim, const SpamRunOptions *o, SpamLoop *L, PetscBool *due)
{
  const long since = sim->pair.nl.builds - L->builds_migrated;
  double     halo;

  PetscFunctionBeginUser;
  *due = (PetscBool)(since >= o->migrate_interval);
  if (*due || since == 0 || sim->pair.nl.builds == L->builds_checked) PetscFunctionReturn(0);
  L->builds_checked = sim->pair.nl.builds;
  PetscCall(HaloMax(sim, &halo));
  *due = (PetscBool)(halo > SPAM_MIGRATE_HALO_GROWTH * L->halo_migrated);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLoopMigrate(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamLoop *L)
{
  SpamMigrateInfo info;
  PetscBool       followed, due;

  PetscFunctionBeginUser;
  if (!SpamSimDistributed(sim) || o->migrate_interval <= 0 || !SpamTSCanFollow(ts)) PetscFunctionReturn(0);
  if (L->halo_migrated <= 0) PetscCall(HaloMax(sim, &L->halo_migrated)); /* the first distribution's */
  PetscCall(MigrationDue(sim, o, L, &due));
  if (!due) PetscFunctionReturn(0);
  PetscCall(SpamSimMigrate(sim, sim->geo.dec, &info));
  /* A non-finite position was caught by the step's own checks before this point; a
   * migration that found one changed nothing, and the next step reports it. */
  L->builds_migrated = sim->pair.nl.builds;
  PetscCall(HaloMax(sim, &L->halo_migrated));
  if (!info.changed) PetscFunctionReturn(0);
  sim->run.migrations_run++;
  sim->run.migrated += info.moved;
  PetscCall(SpamTSFollowParticles(ts, app, &followed));
  L->followed = followed;
  PetscCall(SpamLoopRemakeVectors(sim, L));
  PetscFunctionReturn(0);
}
