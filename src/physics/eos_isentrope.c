/* The isentropic ideal-gas model: state [x, v], pressure P = kappa rho^gamma. */
#include <spam/sim.h>

PetscBool SpamEosDensityFree(const SpamEosIsentrope *q)
{
  return (PetscBool)(q->gamma == 2.0);
}

PetscErrorCode SpamModelIsentropeSetUp(int dim, double h, double mass, double gamma, double kappa, SpamModel *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof *m));
  m->dim       = dim;
  m->mass      = mass;
  m->eos.gamma = gamma;
  m->eos.kappa = kappa;
  PetscCall(SpamKernelLucyInit(dim, h, &m->kernel));
  PetscCall(SpamLayoutPositionsVelocities(dim, &m->layout));
  m->density_free = SpamEosDensityFree(&m->eos);
  m->rhs          = SpamRhsIsentrope;
  m->accel        = SpamAccelIsentrope;
  PetscCall(PetscStrncpy(m->name, "isentrope", sizeof m->name));
  PetscFunctionReturn(0);
}
