/* Migrations during a multi-rank run. Between two accepted steps, after -migrate_interval
 * list builds, every particle goes to the owner of its cell (SpamSimMigrate: a re-cut when
 * the imbalance has grown past its threshold), and whatever holds one value per particle
 * follows: the TS solution and ERKStep's vectors (SpamTSARKodeResize keeps the step and
 * error history), the loop's last good state and interpolation scratch, the list's kept
 * reference positions. Without migrations the run stays correct (a rank's halo is taken
 * from the bounding box of its particles wherever they are), only slower as the boxes grow.
 * ERKStep, rk, ssp and euler follow (SpamTSFollowParticles); cvode and basicsymplectic
 * keep the first distribution. */
#include <spam/integrator.h>
#include <spam/decompose.h>
#include "loop_state.h"

static PetscErrorCode RemakeLoopVectors(SpamSim *sim, SpamLoop *L)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&L->Xgood));
  PetscCall(VecDuplicate(sim->X, &L->Xgood));
  PetscCall(VecCopy(sim->X, L->Xgood));
  if (L->s.Xout) {
    PetscCall(VecDestroy(&L->s.Xout));
    PetscCall(VecDuplicate(sim->X, &L->s.Xout));
  }
  PetscCall(PetscFree(L->xref_keep));
  PetscCall(PetscMalloc1((size_t)sim->n * sim->model.dim + 1, &L->xref_keep));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLoopMigrate(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamLoop *L)
{
  SpamMigrateInfo info;
  PetscBool       followed;

  PetscFunctionBeginUser;
  if (!SpamSimDistributed(sim) || o->migrate_interval <= 0 || !SpamTSCanFollow(ts)) PetscFunctionReturn(0);
  if (sim->nl.builds - L->builds_migrated < o->migrate_interval) PetscFunctionReturn(0);
  PetscCall(SpamSimMigrate(sim, sim->dec, &info));
  /* A non-finite position was caught by the step's own checks before this point; a
   * migration that found one changed nothing, and the next step reports it. */
  L->builds_migrated = sim->nl.builds;
  if (!info.changed) PetscFunctionReturn(0);
  sim->migrations_run++;
  sim->migrated += info.moved;
  PetscCall(SpamTSFollowParticles(ts, app, &followed));
  PetscCall(RemakeLoopVectors(sim, L));
  PetscFunctionReturn(0);
}
