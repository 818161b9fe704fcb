/* The isentropic ideal-gas model: state [x, v], pressure P = kappa rho^gamma. */
#include <spam/sim.h>

PetscBool SpamEosDensityFree(const SpamEosIsentrope *q)
{
  return (PetscBool)(q->gamma == 2.0);
}

/* Internal energy sum m e(rho) at the summed density; the forces are central. */
static PetscErrorCode DiagIsentrope(SpamSim *sim, const double *y, SpamModelDiag *d)
{
  double loc = 0.0;

  PetscFunctionBeginUser;
  (void)y;
  for (PetscInt i = 0; i < sim->p.n; i++) loc += sim->pair.f.m[i] * SpamEosEnergy(&sim->model.eos, sim->pair.f.rho[i]);
  PetscCallMPI(MPIU_Allreduce(&loc, &d->internal, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  d->torque = NAN; /* not computed: the pair forces are central */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamModelIsentropeSetUp(int dim, const SpamKernel *kernel, double mass, double gamma, double kappa, SpamModel *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof *m));
  m->dim       = dim;
  m->mass      = mass;
  m->eos.gamma = gamma;
  m->eos.kappa = kappa;
  m->kernel    = *kernel;
  PetscCall(SpamLayoutPositionsVelocities(dim, &m->layout));
  m->density_free = SpamEosDensityFree(&m->eos);
  m->rhs          = SpamRhsIsentrope;
  m->accel        = SpamAccelIsentrope;
  m->max_sound_speed = SpamMaxSoundSpeedIsentrope;
  m->diag            = DiagIsentrope;
  PetscCall(PetscStrncpy(m->name, "isentrope", sizeof m->name));
  PetscFunctionReturn(0);
}

/* c = sqrt(gamma P / rho) at the summed density; the density pass runs here only, since
 * the force of the gamma = 2 gas does not need it. */
PetscErrorCode SpamMaxSoundSpeedIsentrope(SpamSim *sim, const double *y, double *cmax)
{
  double   rmax = 0.0;
  PetscInt bad;

  PetscFunctionBeginUser;
  PetscCall(SpamDensitySummation(sim, y, &bad));
  for (PetscInt i = 0; i < sim->p.n && bad < 0; i++) rmax = PetscMax(rmax, sim->pair.f.rho[i]);
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &rmax, 1, MPI_DOUBLE, MPI_MAX, sim->p.comm));
  /* gamma > 1: the sound speed grows with density. */
  *cmax = SpamEosSoundSpeed(&sim->model.eos, rmax);
  PetscFunctionReturn(0);
}
