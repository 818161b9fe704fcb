/* The optional physical step bound: a sound wave must not cross more than a fraction of
 * the kernel range in one step (CFL), nor may the fastest-accelerating particle move that
 * far from rest (force criterion). The sound speed, not |v|, enters: a uniform velocity
 * adds nothing to the dynamics (Galilean invariance), so it must not shrink the step. */
#include <spam/integrator.h>

/* cfl times the time a sound wave takes to cross the kernel range: cfl h / c_max with one
 * range; with the adaptive range cfl times the least h_i / c_i over the particles, c_i the
 * gas's own sound speed sqrt(gamma (gamma - 1) e_i) or the model's, whichever is larger,
 * and h_i that of the last right-hand side. 0: no sound speed. */
static PetscErrorCode CflStep(SpamSim *sim, double cfl, const double *y, double *t)
{
  const SpamLayout *l = &sim->model.layout;
  double            c;

  PetscFunctionBeginUser;
  *t = 0.0;
  PetscCall(sim->model.max_sound_speed(sim, y, &c));
  if (!sim->pair.f.adaptive) {
    if (c > 0) *t = cfl * sim->model.kernel.h / c;
    PetscFunctionReturn(0);
  }
  {
    const double g = sim->model.solid.gamma;
    double       least = PETSC_INFINITY;
    for (PetscInt i = 0; i < sim->p.n; i++) {
      const double e = y[(size_t)i * l->nvar + l->e], ci = PetscMax(c, e > 0.0 ? sqrt(g * (g - 1.0) * e) : 0.0);
      if (ci > 0.0) least = PetscMin(least, sim->pair.f.h[i] / ci);
    }
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &least, 1, MPI_DOUBLE, MPI_MIN, sim->p.comm));
    if (least < PETSC_INFINITY) *t = cfl * least;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamStepBound(SpamSim *sim, const SpamRunOptions *o, const double *y, double *dt, SpamStepLimit *which)
{
  const double h = sim->model.kernel.h;

  PetscFunctionBeginUser;
  *dt    = PETSC_INFINITY;
  *which = SPAM_LIMIT_ACCURACY;
  if (o->cfl > 0 && sim->model.max_sound_speed) {
    double t;
    PetscCall(CflStep(sim, o->cfl, y, &t));
    if (t > 0) {
      *dt    = t;
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
