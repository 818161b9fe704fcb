/* The simulation object: a DMSwarm holding one packed field, and the scratch of the RHS. */
#include <spam/sim.h>

PetscErrorCode SpamSimCreate(MPI_Comm comm, const SpamModel *model, const SpamBox *box, PetscInt n, double skin, SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sim, sizeof *sim));
  sim->comm  = comm;
  sim->model = *model;
  sim->box   = *box;
  sim->n     = n;
  sim->skin  = skin;
  sim->threads = 1;
  PetscCall(DMCreate(comm, &sim->swarm));
  PetscCall(DMSetType(sim->swarm, DMSWARM));
  PetscCall(DMSetDimension(sim->swarm, model->dim));
  PetscCall(DMSwarmSetType(sim->swarm, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(sim->swarm));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sim->swarm, SPAM_STATE_FIELD, model->layout.nvar, PETSC_REAL));
  PetscCall(DMSwarmFinalizeFieldRegister(sim->swarm));
  PetscCall(DMSwarmSetLocalSizes(sim->swarm, n, 0));
  PetscCall(SpamFieldsCreate(model->dim, (int)n, (int)n, model->tensor, &sim->f));
  SpamFieldsSetMasses(&sim->f, NULL, model->mass);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimFill(SpamSim *sim, const double *x, const double *v, const double *m)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  PetscReal        *s;
  PetscInt          bs;
  PetscDataType     type;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(sim->swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  for (PetscInt i = 0; i < sim->n; i++) {
    for (int d = 0; d < dim; d++) {
      s[i * bs + l->x + d] = x[i * dim + d];
      s[i * bs + l->v + d] = v[i * dim + d];
    }
  }
  PetscCall(DMSwarmRestoreField(sim->swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  if (m) SpamFieldsSetMasses(&sim->f, m, 0.0);
  PetscFunctionReturn(0);
}

static PetscErrorCode RegisterEvents(SpamSim *sim)
{
  PetscClassId id;

  PetscFunctionBeginUser;
  PetscCall(PetscClassIdRegister("spam-ark", &id));
  PetscCall(PetscLogEventRegister("SpamRHS", id, &sim->ev.rhs));
  PetscCall(PetscLogEventRegister("SpamNbrBuild", id, &sim->nl.ev_build));
  PetscCall(PetscLogEventRegister("SpamDensity", id, &sim->ev.density));
  PetscCall(PetscLogEventRegister("SpamForce", id, &sim->ev.force));
  PetscFunctionReturn(0);
}

/* The first neighbour list is built with the particles, not in the first right-hand
 * side: its allocation (the list's reserve grows to fit) stays out of the RHS, and the
 * RHS timings, like LAMMPS's loop time, leave the set-up out. */
static PetscErrorCode FirstBuild(SpamSim *sim)
{
  const SpamLayout  *l = &sim->model.layout;
  const PetscScalar *y;
  PetscInt           bad;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(sim->X, &y));
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, y + l->x, l->nvar, PETSC_TRUE, &bad));
  PetscCall(VecRestoreArrayRead(sim->X, &y));
  PetscCheck(bad < 0, sim->comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT " at set-up", SpamSimRowOf(sim, bad));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimSetUp(SpamSim *sim)
{
  const PetscInt n = sim->n;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetSize(sim->swarm, &sim->nglobal));
  PetscCall(DMSwarmCreateGlobalVectorFromField(sim->swarm, SPAM_STATE_FIELD, &sim->X));
  if (sim->threads > 1) PetscCall(PetscMalloc2((size_t)(sim->threads - 1) * sim->model.dim * sim->f.cap + 1, &sim->tacc, (size_t)(sim->threads - 1) * sim->f.cap + 1, &sim->trho));
  /* gamma = 2: P/rho^2 = kappa for every particle, set once. */
  for (PetscInt i = 0; i < sim->f.cap; i++) sim->f.q[i] = sim->model.eos.kappa;
  PetscCall(SpamNeighboursCreate((int)n, &sim->box, sim->model.kernel.h, sim->skin, &sim->nl));
  if (sim->periodic_ghosts) {
    const PetscBool all[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE};
    PetscCall(SpamNeighboursSetPeriodicGhosts(&sim->nl, &sim->box, all));
  }
  if (SpamWallsAny(&sim->walls, sim->model.dim)) PetscCall(SpamNeighboursSetWalls(&sim->nl, &sim->walls));
  PetscCall(SpamNeighboursSetThreads(&sim->nl, sim->threads));
  PetscCall(RegisterEvents(sim));
  PetscCall(FirstBuild(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimDestroy(SpamSim *sim)
{
  PetscFunctionBeginUser;
  if (sim->X) PetscCall(DMSwarmDestroyGlobalVectorFromField(sim->swarm, SPAM_STATE_FIELD, &sim->X));
  PetscCall(SpamFieldsDestroy(&sim->f));
  if (sim->nl.start) {
    PetscCall(PetscFree2(sim->tacc, sim->trho));
    PetscCall(SpamNeighboursDestroy(&sim->nl));
  }
  PetscCall(PetscFree2(sim->row_of, sim->at_row));
  PetscCall(DMDestroy(&sim->swarm));
  PetscFunctionReturn(0);
}
