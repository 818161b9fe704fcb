/* The one right-hand side every integrator calls: the model's own function, timed and
 * counted so that each method reports the same statistics. */
#include <spam/sim.h>

PetscErrorCode SpamRhs(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->ev.rhs, 0, 0, 0, 0));
  PetscCall(PetscTime(&t0));
  PetscCall(sim->model.rhs(sim, y, ydot, bad));
  PetscCall(PetscTime(&t1));
  PetscCall(PetscLogEventEnd(sim->ev.rhs, 0, 0, 0, 0));
  sim->stats.rhs_evals++;
  sim->stats.rhs_time += t1 - t0;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamAccel(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PetscCheck(sim->model.accel, sim->p.comm, PETSC_ERR_SUP, "model %s has no acceleration function", sim->model.name);
  PetscCall(PetscLogEventBegin(sim->ev.rhs, 0, 0, 0, 0));
  PetscCall(PetscTime(&t0));
  PetscCall(sim->model.accel(sim, x, stride, bad));
  PetscCall(PetscTime(&t1));
  PetscCall(PetscLogEventEnd(sim->ev.rhs, 0, 0, 0, 0));
  sim->stats.rhs_evals++;
  sim->stats.rhs_time += t1 - t0;
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
    for (int d = 0; d < sim->model.dim; d++) loc -= sim->f.m[i] * sim->model.gravity[d] * (y[(size_t)i * l->nvar + l->x + d] - sim->box.lo[d]);
  PetscCallMPI(MPIU_Allreduce(&loc, pot, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}
