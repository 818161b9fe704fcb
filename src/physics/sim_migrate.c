/* The simulation's particles moved between ranks by the core (decompose.h): what the sim
 * keeps outside the swarm rides in the swarm's carried fields (masses, the list's
 * reference positions, body labels) or travels by the model's carry hooks (spring bonds,
 * springs_bonds.c); the scratch is re-made for the particles that arrived. */
#include <spam/sim.h>
#include <spam/physics.h>
#include <spam/errors.h>

static const char *const carried[] = {SPAM_MASS_FIELD, SPAM_BODY_FIELD, SPAM_XREF_FIELD};

/* Whether the swarm has the carried fields: on several ranks only (sim.c). */
static PetscBool HasCarried(const SpamSim *sim)
{
  PetscMPIInt size = 1;
  (void)MPI_Comm_size(sim->p.comm, &size);
  return (PetscBool)(size > 1);
}

/* One rank: the carried data into sim->stash by gid (every gid is below n there: the
 * particles are numbered by input row). */
static PetscErrorCode StowLocal(SpamSim *sim)
{
  const PetscInt n = sim->p.n;
  const int      dim = sim->model.dim;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(n + 1, &sim->stash.m, (size_t)n * dim + 1, &sim->stash.xref, n + 1, &sim->stash.body));
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt64 g = sim->p.gid[i];
    PetscCheck(g >= 0 && g < n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle %" PetscInt_FMT " has gid %" PetscInt64_FMT " outside 0..%" PetscInt_FMT " on one rank", i, g, n - 1);
    sim->stash.m[g]    = sim->pair.f.m[i];
    sim->stash.body[g] = sim->ps ? sim->ps->body[i] : 0;
    for (int d = 0; d < dim; d++) sim->stash.xref[(size_t)g * dim + d] = sim->pair.nl.builds ? sim->pair.nl.xref[d][i] : 0.0;
  }
  PetscFunctionReturn(0);
}

/* The masses, reference positions and body labels into the swarm's carried fields (local). */
static PetscErrorCode Stow(SpamSim *sim)
{
  PetscReal *m, *xref;
  PetscInt  *body;

  PetscFunctionBeginUser;
  if (!HasCarried(sim)) {
    PetscCall(StowLocal(sim));
    PetscFunctionReturn(0);
  }
  PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_MASS_FIELD, NULL, NULL, (void **)&m));
  PetscCall(PetscArraycpy(m, sim->pair.f.m, sim->p.n));
  PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_MASS_FIELD, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_XREF_FIELD, NULL, NULL, (void **)&xref));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < sim->model.dim; d++) xref[(size_t)i * sim->model.dim + d] = sim->pair.nl.builds ? sim->pair.nl.xref[d][i] : 0.0;
  PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_XREF_FIELD, NULL, NULL, (void **)&xref));
  if (sim->ps) {
    PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_BODY_FIELD, NULL, NULL, (void **)&body));
    for (PetscInt i = 0; i < sim->p.n; i++) body[i] = sim->ps->body[i];
    PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_BODY_FIELD, NULL, NULL, (void **)&body));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Depart(void *ctx, const PetscInt *dest)
{
  SpamSim *sim = ctx;

  PetscFunctionBeginUser;
  if (sim->model.carry_depart) PetscCall(sim->model.carry_depart(sim, dest));
  PetscCall(SpamAgreeOnFailure(sim->p.comm, Stow(sim), "carrying the particles' data in the swarm"));
  PetscFunctionReturn(0);
}

static PetscErrorCode Arrive(void *ctx)
{
  SpamSim *sim = ctx;

  PetscFunctionBeginUser;
  PetscCall(SpamAgreeOnFailure(sim->p.comm, SpamSimResize(sim), "re-making the scratch after a migration"));
  if (sim->model.carry_arrive) PetscCall(sim->model.carry_arrive(sim));
  PetscFunctionReturn(0);
}

static SpamMigration MigrationOf(SpamSim *sim)
{
  const SpamLayout *l = &sim->model.layout;
  return (SpamMigration){sim->model.dim, l->nvar, l->x, carried, HasCarried(sim) ? (int)(sizeof carried / sizeof *carried) : 0, sim, Depart, Arrive};
}

/* The list of the migrated particles, built at the reference positions they carried (the
 * positions of the last build, as if no migration had happened: same shifts, same rebuild
 * times); at the current positions when no list was built yet (collective). */
static PetscErrorCode RebuildList(SpamSim *sim)
{
  PetscReal *xref;

  PetscFunctionBeginUser;
  if (!sim->pair.nl.builds) {
    PetscCall(SpamSimBuildList(sim));
    PetscFunctionReturn(0);
  }
  if (!HasCarried(sim)) {
    const int dim = sim->model.dim;
    PetscCall(PetscMalloc1((size_t)sim->p.n * dim + 1, &xref));
    for (PetscInt i = 0; i < sim->p.n; i++)
      for (int d = 0; d < dim; d++) xref[(size_t)i * dim + d] = sim->stash.xref[(size_t)sim->p.gid[i] * dim + d];
    PetscCall(SpamNeighboursRestore(&sim->pair.nl, &sim->geo.box, xref));
    PetscCall(PetscFree(xref));
    PetscFunctionReturn(0);
  }
  PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_XREF_FIELD, NULL, NULL, (void **)&xref));
  PetscCall(SpamNeighboursRestore(&sim->pair.nl, &sim->geo.box, xref));
  PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_XREF_FIELD, NULL, NULL, (void **)&xref));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimMigrate(SpamSim *sim, SpamDecomp *dec, SpamMigrateInfo *info)
{
  const SpamMigration m = MigrationOf(sim);

  PetscFunctionBeginUser;
  PetscCall(SpamSwarmMigrate(&sim->p, &m, dec, info));
  if (info->changed) PetscCall(RebuildList(sim));
  PetscCall(PetscFree3(sim->stash.m, sim->stash.xref, sim->stash.body));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSimPlace(SpamSim *sim, PetscInt n, const PetscInt64 *gids, PetscBool *changed)
{
  const SpamMigration m = MigrationOf(sim);

  PetscFunctionBeginUser;
  PetscCall(SpamSwarmPlace(&sim->p, &m, n, gids, changed));
  PetscCall(PetscFree3(sim->stash.m, sim->stash.xref, sim->stash.body));
  PetscFunctionReturn(0);
}
