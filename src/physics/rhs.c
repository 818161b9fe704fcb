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
  PetscCheck(sim->model.accel, sim->comm, PETSC_ERR_SUP, "model %s has no acceleration function", sim->model.name);
  PetscCall(PetscLogEventBegin(sim->ev.rhs, 0, 0, 0, 0));
  PetscCall(PetscTime(&t0));
  PetscCall(sim->model.accel(sim, x, stride, bad));
  PetscCall(PetscTime(&t1));
  PetscCall(PetscLogEventEnd(sim->ev.rhs, 0, 0, 0, 0));
  sim->stats.rhs_evals++;
  sim->stats.rhs_time += t1 - t0;
  PetscFunctionReturn(0);
}
