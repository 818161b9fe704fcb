/* The start of a multi-rank run. Rank 0 holds every particle of the scene and sets it up
 * as a one-rank run does (set-up sort, first list, bodies, summed initial densities), so
 * that the initial state is the one-rank state bit for bit; one migration then sends each
 * particle to the owner of its cell. Building on rank 0 keeps every scene's set-up serial
 * code unchanged, at the price of rank 0 holding the whole scene once (the 10^8
 * particles would need scenes built in pieces: not done). */
#include <spam/sim.h>
#include <spam/physics.h>
#include <spam/decompose.h>

/* Rank 0 labelled the bodies; the others learn how many there are (the torque and
 * angular-momentum sums are reduced per body over every rank). */
static PetscErrorCode ShareBodies(SpamSim *sim)
{
  SpamPhysicsScratch *ps = sim->ps;
  int                 nb;

  PetscFunctionBeginUser;
  if (!ps) PetscFunctionReturn(0);
  nb = ps->nbody;
  PetscCallMPI(MPI_Bcast(&nb, 1, MPI_INT, 0, sim->p.comm));
  if (nb == ps->nbody) PetscFunctionReturn(0);
  PetscCall(PetscFree3(ps->bpos, ps->bneg, ps->bfac));
  PetscCall(PetscCalloc3(nb, &ps->bpos, nb, &ps->bneg, nb, &ps->bfac));
  ps->nbody = nb;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimDistribute(SpamSim *sim)
{
  PetscMPIInt     size;
  SpamMigrateInfo info;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(sim->p.comm, &size));
  if (size == 1) PetscFunctionReturn(0);
  PetscCall(ShareBodies(sim));
  PetscCall(PetscNew(&sim->geo.dec));
  PetscCall(SpamDecompCreate(sim->p.comm, &sim->geo.box, sim->model.kernel.h, 0.0, sim->geo.dec));
  PetscCall(SpamSimMigrate(sim, sim->geo.dec, &info));
  PetscCheck(info.bad < 0, sim->p.comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt64_FMT " at set-up", info.bad);
  if (!info.changed) { /* already in place: the list still needs the halo */
    PetscCall(SpamSimResize(sim));
    PetscCall(SpamSimBuildList(sim));
  }
  PetscFunctionReturn(0);
}
