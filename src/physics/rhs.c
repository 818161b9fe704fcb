/* The one right-hand side every integrator calls: the model's own function, timed and
 * counted so that each method reports the same statistics. */
#include <spam/sim.h>

/* Where an evaluation starts: the clock and the list's counters. */
typedef struct {
  PetscLogDouble t;
  long           updates, placements;
} Mark;

static PetscErrorCode Start(SpamSim *sim, Mark *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->run.ev.rhs, 0, 0, 0, 0));
  m->updates    = sim->pair.nl.updates;
  m->placements = sim->pair.nl.placements;
  PetscCall(PetscTime(&m->t));
  PetscFunctionReturn(0);
}

/* One evaluation counted with its time, list updates and ghost placements. */
static PetscErrorCode Finish(SpamSim *sim, const Mark *m)
{
  SpamRhsStats  *s = &sim->run.stats;
  PetscLogDouble t1;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t1));
  PetscCall(PetscLogEventEnd(sim->run.ev.rhs, 0, 0, 0, 0));
  s->rhs_evals++;
  s->rhs_time += t1 - m->t;
  s->counted++;
  s->list_updates += sim->pair.nl.updates - m->updates;
  s->ghost_placements += sim->pair.nl.placements - m->placements;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhs(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  Mark m = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(Start(sim, &m));
  PetscCall(sim->model.rhs(sim, y, ydot, bad));
  PetscCall(Finish(sim, &m));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsOfPart(SpamSim *sim, const double *y, double *ydot, SpamRhsPart part, PetscInt *bad)
{
  Mark m = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCheck(sim->model.rhs_part, sim->p.comm, PETSC_ERR_SUP, "model %s has no right-hand side by parts", sim->model.name);
  PetscCall(Start(sim, &m));
  PetscCall(sim->model.rhs_part(sim, y, ydot, part, bad));
  PetscCall(Finish(sim, &m));
  if (part == SPAM_RHS_DIFFUSION) sim->run.stats.rhs_evals_diffusion++;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsActive(SpamSim *sim, const double *y, double *ydot, const unsigned char *active, unsigned char *near, PetscBool *done, PetscInt *bad)
{
  Mark m = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCheck(sim->model.rhs_active, sim->p.comm, PETSC_ERR_SUP, "model %s has no right-hand side restricted to active particles", sim->model.name);
  PetscCall(Start(sim, &m));
  PetscCall(sim->model.rhs_active(sim, y, ydot, active, near, done, bad));
  if (*done || *bad >= 0) PetscCall(Finish(sim, &m));
  else PetscCall(PetscLogEventEnd(sim->run.ev.rhs, 0, 0, 0, 0)); /* not evaluated: the caller's full evaluation counts */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamAccel(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  Mark m = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCheck(sim->model.accel, sim->p.comm, PETSC_ERR_SUP, "model %s has no acceleration function", sim->model.name);
  PetscCall(Start(sim, &m));
  PetscCall(sim->model.accel(sim, x, stride, bad));
  PetscCall(Finish(sim, &m));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamGravityEnergy(SpamSim *sim, const double *y, double *pot)
{
  const SpamLayout *l   = &sim->model.layout;
  double            loc = 0.0;

  PetscFunctionBeginUser;
  *pot = 0.0;
  if (!sim->model.gravity_on) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < sim->model.dim; d++) loc -= sim->pair.f.m[i] * sim->model.gravity[d] * (y[(size_t)i * l->nvar + l->x + d] - sim->geo.box.lo[d]);
  PetscCallMPI(MPIU_Allreduce(&loc, pot, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}
