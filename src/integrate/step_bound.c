/* The optional physical step bound: a sound wave must not cross more than a fraction of
 * the kernel range in one step (CFL), nor may the fastest-accelerating particle move that
 * far from rest (force criterion). The sound speed, not |v|, enters: a uniform velocity
 * adds nothing to the dynamics (Galilean invariance), so it must not shrink the step. */
#include <spam/integrator.h>

PetscErrorCode SpamStepBound(SpamSim *sim, const SpamRunOptions *o, const double *y, double *dt, SpamStepLimit *which)
{
  const double h = sim->model.kernel.h;

  PetscFunctionBeginUser;
  *dt    = PETSC_INFINITY;
  *which = SPAM_LIMIT_ACCURACY;
  if (o->cfl > 0 && sim->model.max_sound_speed) {
    double c;
    PetscCall(sim->model.max_sound_speed(sim, y, &c));
    if (c > 0) {
      *dt    = o->cfl * h / c;
      *which = SPAM_LIMIT_CFL;
    }
  }
  if (o->force > 0) {
    double a2 = 0.0;
    for (PetscInt i = 0; i < sim->p.n; i++) {
      double s = 0.0;
      const double *a = sim->pair.f.acc + (size_t)i * sim->model.dim;
      for (int d = 0; d < sim->model.dim; d++) s += a[d] * a[d];
      a2 = PetscMax(a2, s);
    }
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &a2, 1, MPI_DOUBLE, MPI_MAX, sim->p.comm));
    if (a2 > 0) {
      const double dtf = o->force * sqrt(h / sqrt(a2));
      if (dtf < *dt) {
        *dt    = dtf;
        *which = SPAM_LIMIT_FORCE;
      }
    }
  }
  PetscFunctionReturn(0);
}
