/* The simulation object: a DMSwarm holding one packed field, and the scratch of the RHS. */
#include <spam/sim.h>
#include <spam/physics.h>
#include <spam/decompose.h>
#include <spam/zero_pages.h>

/* Gids in rank order: this rank's particles follow those of the ranks before it. */
static PetscErrorCode NumberParticles(SpamSwarm *sw)
{
  PetscInt64 n = sw->n, first = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Exscan(&n, &first, 1, MPIU_INT64, MPI_SUM, sw->comm));
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(sw->comm, &rank));
    if (rank == 0) first = 0; /* MPI_Exscan leaves rank 0's result undefined */
  }
  for (PetscInt i = 0; i < sw->n; i++) sw->gid[i] = first + i;
  PetscFunctionReturn(0);
}

/* The fields a migration carries (masses, body labels, the list's reference positions:
 * sim_migrate.c) on several ranks only: one rank never migrates nor places particles
 * (SpamSimDistribute, and a restart continues on the rank count that wrote it), and DMSwarm
 * zeroes every field it sizes, so on one rank they would take 28 bytes a particle in 2D
 * that nothing reads. */
static PetscErrorCode RegisterCarried(DM swarm, int dim)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)swarm), &size));
  if (size == 1) PetscFunctionReturn(0);
  PetscCall(DMSwarmRegisterPetscDatatypeField(swarm, SPAM_MASS_FIELD, 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(swarm, SPAM_BODY_FIELD, 1, PETSC_INT));
  PetscCall(DMSwarmRegisterPetscDatatypeField(swarm, SPAM_XREF_FIELD, dim, PETSC_REAL));
  PetscFunctionReturn(0);
}

/* DMSwarm registers DMSwarm_pid and DMSwarm_rank itself and writes zeros into them when
 * it sizes them: spam-ark never reads pid, and sets rank only before a migration (a local
 * sort reads it: zeros there mean this rank, on one rank). The zeros stay, without their
 * 12 bytes a particle of resident memory (zero_pages.c) until something writes them. */
static PetscErrorCode ZeroUnusedFields(DM swarm, PetscInt n)
{
  PetscInt64 *pid;
  PetscInt   *rank;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(swarm, DMSwarmField_pid, NULL, NULL, (void **)&pid));
  SpamZeroPages(pid, (size_t)n * sizeof *pid);
  PetscCall(DMSwarmRestoreField(swarm, DMSwarmField_pid, NULL, NULL, (void **)&pid));
  PetscCall(DMSwarmGetField(swarm, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  SpamZeroPages(rank, (size_t)n * sizeof *rank);
  PetscCall(DMSwarmRestoreField(swarm, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimCreate(MPI_Comm comm, const SpamModel *model, const SpamBox *box, PetscInt n, double skin, SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sim, sizeof *sim));
  sim->p.comm  = comm;
  sim->model = *model;
  sim->geo.box   = *box;
  sim->p.n     = n;
  sim->pair.skin  = skin;
  sim->pair.threads = 1;
  sim->pair.ghost_mass_build = -1;
  PetscCall(DMCreate(comm, &sim->p.swarm));
  PetscCall(DMSetType(sim->p.swarm, DMSWARM));
  PetscCall(DMSetDimension(sim->p.swarm, model->dim));
  PetscCall(DMSwarmSetType(sim->p.swarm, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(sim->p.swarm));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sim->p.swarm, SPAM_STATE_FIELD, model->layout.nvar, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(sim->p.swarm, SPAM_GID_FIELD, 1, PETSC_INT64));
  PetscCall(RegisterCarried(sim->p.swarm, model->dim));
  /* h_i travels with its particle on any number of ranks: the solve starts from it. */
  if (SpamModelAdaptive(model)) PetscCall(DMSwarmRegisterPetscDatatypeField(sim->p.swarm, SPAM_H_FIELD, 1, PETSC_REAL));
  PetscCall(DMSwarmFinalizeFieldRegister(sim->p.swarm));
  PetscCall(DMSwarmSetLocalSizes(sim->p.swarm, n, 0));
  PetscCall(ZeroUnusedFields(sim->p.swarm, n));
  PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&sim->p.gid));
  PetscCall(NumberParticles(&sim->p));
  PetscCall(SpamFieldsCreate(model->dim, (int)n, (int)n, model->tensor, &sim->pair.f));
  SpamFieldsSetMasses(&sim->pair.f, NULL, model->mass);
  if (model->inverse_mass) PetscCall(SpamFieldsAddInverseMass(&sim->pair.f));
  if (SpamModelAdaptive(model)) PetscCall(SpamFieldsAddSmoothing(&sim->pair.f));
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
  PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    for (int d = 0; d < dim; d++) {
      s[i * bs + l->x + d] = x[i * dim + d];
      s[i * bs + l->v + d] = v[i * dim + d];
    }
  }
  PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  if (m) SpamFieldsSetMasses(&sim->pair.f, m, 0.0);
  PetscFunctionReturn(0);
}

static PetscErrorCode RegisterEvents(SpamSim *sim)
{
  PetscClassId id;

  PetscFunctionBeginUser;
  PetscCall(PetscClassIdRegister("spam-ark", &id));
  PetscCall(PetscLogEventRegister("SpamRHS", id, &sim->run.ev.rhs));
  PetscCall(PetscLogEventRegister("SpamNbrBuild", id, &sim->pair.nl.ev_build));
  PetscCall(PetscLogEventRegister("SpamDensity", id, &sim->run.ev.density));
  PetscCall(PetscLogEventRegister("SpamForce", id, &sim->run.ev.force));
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
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, l->nvar, PETSC_TRUE, &bad));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCheck(bad < 0, sim->p.comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT " at set-up", SpamSimRowOf(sim, bad));
  PetscFunctionReturn(0);
}

/* The per-particle scratch of n = sim->p.n local particles once the fields are made:
 * thread buffers, P/rho^2, and the neighbour list with the sim's ghosts and threads. */
static PetscErrorCode CreateScratch(SpamSim *sim)
{
  PetscFunctionBeginUser;
  if (sim->pair.threads > 1) PetscCall(PetscMalloc2((size_t)(sim->pair.threads - 1) * sim->model.dim * sim->pair.f.cap + 1, &sim->pair.tacc, (size_t)(sim->pair.threads - 1) * sim->pair.f.cap + 1, &sim->pair.trho));
  /* gamma = 2: P/rho^2 = kappa for every particle, set once. */
  for (PetscInt i = 0; i < sim->pair.f.cap; i++) sim->pair.f.q[i] = sim->model.eos.kappa;
  PetscCall(SpamNeighboursCreate((int)sim->p.n, &sim->geo.box, SpamModelListRange(&sim->model), sim->pair.skin, &sim->pair.nl));
  if (sim->geo.dec) PetscCall(SpamNeighboursSetComm(&sim->pair.nl, sim->p.comm)); /* other ranks' particles as ghosts */
  if (sim->pair.periodic_ghosts || sim->pair.reproducible) { /* -reproducible: images as ghost slots */
    const PetscBool all[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE};
    PetscCall(SpamNeighboursSetPeriodicGhosts(&sim->pair.nl, &sim->geo.box, all));
  }
  if (SpamWallsAny(&sim->geo.walls, sim->model.dim)) PetscCall(SpamNeighboursSetWalls(&sim->pair.nl, &sim->geo.walls));
  if (sim->pair.reproducible) PetscCall(SpamNeighboursSetCanonical(&sim->pair.nl, sim->p.gid));
  PetscCall(SpamNeighboursSetThreads(&sim->pair.nl, sim->pair.threads));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimSetUp(SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetSize(sim->p.swarm, &sim->p.nglobal));
  PetscCall(SpamSwarmOpenState(&sim->p));
  PetscCall(CreateScratch(sim));
  PetscCall(RegisterEvents(sim));
  PetscCall(FirstBuild(sim));
  PetscFunctionReturn(0);
}

/* On several ranks the pair loops of equal masses also take other ranks' particles at the
 * model's mass: equal masses must hold over every rank, not only this one's. */
static PetscErrorCode UniformMassEverywhere(SpamSim *sim)
{
  const PetscBool have = (PetscBool)(sim->p.n > 0);
  double          v[3] = {have && !sim->pair.f.uniform_mass ? 1.0 : 0.0, have ? -sim->pair.f.m[0] : -INFINITY, have ? sim->pair.f.m[0] : -INFINITY}, g[3];

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(v, g, 3, MPI_DOUBLE, MPI_MAX, sim->p.comm)); /* [any non-uniform, -min m0, max m0] */
  sim->pair.f.uniform_mass = (int)(g[0] == 0.0 && -g[1] == g[2]);
  PetscFunctionReturn(0);
}

/* The carried masses and body labels (the swarm's fields, or on one rank the stash) into the
 * re-made fields and labels. */
static PetscErrorCode TakeCarried(SpamSim *sim)
{
  PetscReal *m;
  PetscInt  *body;

  PetscFunctionBeginUser;
  if (sim->stash.m) { /* one rank: by gid from the stash (sim_migrate.c) */
    PetscCall(PetscMalloc2(sim->p.n + 1, &m, sim->p.n + 1, &body));
    for (PetscInt i = 0; i < sim->p.n; i++) {
      m[i]    = sim->stash.m[sim->p.gid[i]];
      body[i] = sim->stash.body[sim->p.gid[i]];
    }
  } else PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_MASS_FIELD, NULL, NULL, (void **)&m));
  SpamFieldsSetMasses(&sim->pair.f, m, 0.0);
  if (!sim->stash.m) PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_MASS_FIELD, NULL, NULL, (void **)&m));
  if (sim->pair.f.adaptive) { /* the solve's start, so that it does not depend on the ranks */
    PetscReal *h;
    PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_H_FIELD, NULL, NULL, (void **)&h));
    PetscCall(PetscArraycpy(sim->pair.f.h, h, sim->p.n));
    PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_H_FIELD, NULL, NULL, (void **)&h));
  }
  if (sim->geo.dec) PetscCall(UniformMassEverywhere(sim));
  if (sim->ps) {
    PetscCall(PetscFree(sim->ps->body));
    PetscCall(PetscMalloc1(sim->p.n + 1, &sim->ps->body));
    sim->ps->n = sim->p.n;
    if (!sim->stash.m) PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_BODY_FIELD, NULL, NULL, (void **)&body));
    for (PetscInt i = 0; i < sim->p.n; i++) sim->ps->body[i] = (int)body[i];
    if (!sim->stash.m) PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_BODY_FIELD, NULL, NULL, (void **)&body));
  }
  if (sim->stash.m) PetscCall(PetscFree2(m, body));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimResize(SpamSim *sim)
{
  const long          builds = sim->pair.nl.builds, grows = sim->pair.nl.grows;
  const PetscLogEvent ev     = sim->pair.nl.ev_build;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(sim->p.swarm, &sim->p.n));
  /* The fields keep their arrays while they have room: every value but the masses (taken
   * here) is made again by the next right-hand side. */
  sim->pair.f.n = (int)sim->p.n;
  PetscCall(SpamFieldsReserve(&sim->pair.f, (int)sim->p.n));
  PetscCall(TakeCarried(sim));
  /* The list has no resize: made anew, as are the thread buffers sized by the fields. */
  PetscCall(PetscFree2(sim->pair.tacc, sim->pair.trho));
  PetscCall(SpamNeighboursDestroy(&sim->pair.nl));
  PetscCall(CreateScratch(sim));
  sim->pair.nl.builds   = builds;
  sim->pair.ghost_mass_build = -1;
  sim->pair.nl.grows    = grows;
  sim->pair.nl.ev_build = ev;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimGhostMasses(SpamSim *sim)
{
  const SpamGhosts *g = &sim->pair.nl.ghosts;
  const int         dim = sim->model.dim, n = (int)sim->p.n;

  PetscFunctionBeginUser;
  if (sim->pair.ghost_mass_build == sim->pair.nl.builds) PetscFunctionReturn(0);
  PetscCall(SpamFieldsReserve(&sim->pair.f, SpamNeighboursSlots(&sim->pair.nl)));
  PetscCall(SpamGhostsGather(g, dim, n, 1, SPAM_GHOST_SCALAR, sim->pair.f.m));
  if (sim->pair.f.minv) PetscCall(SpamGhostsGather(g, dim, n, 1, SPAM_GHOST_SCALAR, sim->pair.f.minv));
  if (!sim->model.tensor && sim->model.density_free) PetscCall(SpamGhostsGather(g, dim, n, 1, SPAM_GHOST_SCALAR, sim->pair.f.q));
  sim->pair.ghost_mass_build = sim->pair.nl.builds;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimBuildList(SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(FirstBuild(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimDestroy(SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(SpamSwarmCloseState(&sim->p));
  PetscCall(SpamFieldsDestroy(&sim->pair.f));
  PetscCall(SpamDiffusionCacheDestroy(&sim->pair.dcache));
  if (sim->pair.nl.start) {
    PetscCall(PetscFree2(sim->pair.tacc, sim->pair.trho));
    PetscCall(SpamNeighboursDestroy(&sim->pair.nl));
  }
  PetscCall(PetscFree(sim->p.at_row));
  if (sim->geo.dec) PetscCall(SpamDecompDestroy(sim->geo.dec));
  PetscCall(PetscFree(sim->geo.dec));
  PetscCall(PetscFree3(sim->stash.m, sim->stash.xref, sim->stash.body));
  if (sim->p.gid) PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_GID_FIELD, NULL, NULL, (void **)&sim->p.gid));
  PetscCall(DMDestroy(&sim->p.swarm));
  PetscFunctionReturn(0);
}
