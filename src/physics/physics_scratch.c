/* Scratch of the tensor path and the spring model, allocated once at set-up and freed
 * with the swarm (a PetscContainer composed on it), so SpamSimDestroy needs no change. */
#include <spam/physics.h>

static PetscErrorCode ScratchDestroy(void *ctx)
{
  SpamPhysicsScratch *ps = (SpamPhysicsScratch *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(ps->body));
  PetscCall(PetscFree3(ps->bpos, ps->bneg, ps->bfac));
  PetscCall(PetscFree(ps->bond_start));
  PetscCall(PetscFree(ps->bond_nbr));
  PetscCall(SpamBondHaloDestroy(&ps->bond_halo));
  PetscCall(PetscFree(ps));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamPhysicsScratchCreate(SpamSim *sim)
{
  const PetscInt      n = sim->p.n + 1;
  SpamPhysicsScratch *ps;
  PetscContainer      c;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ps));
  ps->n = sim->p.n;
  PetscCall(PetscCalloc1(n, &ps->body));
  ps->nbody = 1;
  PetscCall(PetscCalloc3(1, &ps->bpos, 1, &ps->bneg, 1, &ps->bfac));
  PetscCall(PetscContainerCreate(sim->p.comm, &c));
  PetscCall(PetscContainerSetPointer(c, ps));
  PetscCall(PetscContainerSetUserDestroy(c, ScratchDestroy));
  PetscCall(PetscObjectCompose((PetscObject)sim->p.swarm, "spam_physics_scratch", (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  sim->ps = ps;
  PetscFunctionReturn(0);
}
