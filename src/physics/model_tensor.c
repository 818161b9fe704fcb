/* The tensor-path model (elastic solid or gas with the energy equation): its layout, hooks
 * and set-up. */
#include <spam/physics.h>
#include <spam/stress.h>

PetscErrorCode SpamDiagSolid(SpamSim *sim, const double *y, SpamModelDiag *d)
{
  const SpamLayout *l   = &sim->model.layout;
  double            loc = 0.0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->p.n; i++) loc += sim->pair.f.m[i] * y[(size_t)i * l->nvar + l->e];
  PetscCallMPI(MPIU_Allreduce(&loc, &d->internal, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscCall(SpamTensorTorqueSum(sim, y, &d->torque));
  PetscCall(SpamBodiesDiag(sim, y, d));
  PetscFunctionReturn(0);
}

/* Scratch, bodies (connected within the kernel range), the gas's initial energy where the
 * input gave none, and on request the summed value as the initial continuity density. */
PetscErrorCode SpamSetUpSolid(SpamSim *sim)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;
  PetscInt          bad;

  PetscFunctionBeginUser;
  PetscCall(SpamPhysicsScratchCreate(sim));
  PetscCall(VecGetArray(sim->p.X, &y));
  PetscCall(SpamBodiesLabel(sim, y, sim->model.kernel.h));
  if (sim->model.solid.material == SPAM_MATERIAL_GAS && !sim->model.energy_given)
    for (PetscInt i = 0; i < sim->p.n; i++) y[(size_t)i * l->nvar + l->e] = sim->model.solid.gas_e0;
  for (PetscInt i = 0; l->fb >= 0 && i < sim->p.n; i++) y[(size_t)i * l->nvar + l->fb] = 0.0;
  for (PetscInt i = 0; l->wb >= 0 && i < sim->p.n; i++) /* the walls' books start empty */
    for (int c = 0; c < 2 + l->dim; c++) y[(size_t)i * l->nvar + l->wb + c] = 0.0;
  if (l->rho >= 0 && sim->model.solid.density_initial == SPAM_DENSITY_INITIAL_SUMMED) {
    PetscCall(SpamDensitySummation(sim, y, &bad));
    for (PetscInt i = 0; i < sim->p.n; i++) y[(size_t)i * l->nvar + l->rho] = sim->pair.f.rho[i];
  }
  if (l->h >= 0) PetscCall(SpamSmoothingStart(sim, y)); /* h_i solved once, then integrated */
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* The longitudinal (or gas) sound speed at the reference density: a linear material's
 * signal speed does not depend on its state; the gas's is taken at its initial state. */
static PetscErrorCode SolidSoundSpeed(SpamSim *sim, const double *y, double *cmax)
{
  PetscFunctionBeginUser;
  (void)y;
  *cmax = sim->model.solid.sound_speed;
  PetscFunctionReturn(0);
}

/* Closest-approach reflection after each accepted step (PRE Sec. IV). */
static PetscErrorCode SolidClosestApproach(SpamSim *sim, double *y, PetscInt *changed)
{
  PetscFunctionBeginUser;
  PetscCall(SpamClosestApproachReflect(sim, y, sim->model.solid.closest_approach, changed));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamModelSolidSetUp(int dim, const SpamKernel *kernel, double mass, const SpamSolidParams *p, SpamModel *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof *m));
  m->dim    = dim;
  m->mass   = mass;
  m->solid  = *p;
  m->kernel = *kernel;
  m->tensor = PETSC_TRUE;
  /* The shift is a diffusion of the particles' number density, sum_j grad w_ij. At a
   * wavenumber where the kernel's Fourier transform is negative it runs backwards and
   * pairs the particles: Lucy's does in 2D and 3D (Dehnen and Aly 2012), and with it the
   * rows of a gas at rest pair up (0.15 of a spacing in 300 time units) or keep moving.
   * A kernel whose transform is positive serves the shift itself; for any other the
   * shift takes Wendland C2's gradient (positive in D <= 3) of the same range. */
  if (kernel->fourier_positive) m->shift_kernel = *kernel;
  else PetscCall(SpamKernelCreate("wendland_c2", dim, kernel->h, &m->shift_kernel));
  if (p->material == SPAM_MATERIAL_GAS) {
    const double pres    = (p->gamma - 1.0) * p->rho0 * p->gas_e0;
    m->solid.sound_speed = sqrt(p->gamma * pres / p->rho0);
    PetscCall(SpamLayoutSolid(dim, (PetscBool)(p->density != SPAM_DENSITY_SUMMATION), PETSC_FALSE, p->rho0, pres > 0.0 ? pres : 1.0, &m->layout));
  } else {
    m->solid.sound_speed = sqrt((p->lambda + 2.0 * p->eta) / p->rho0);
    PetscCall(SpamLayoutSolid(dim, (PetscBool)(p->density != SPAM_DENSITY_SUMMATION), PETSC_TRUE, p->rho0, p->lambda + 2.0 * p->eta, &m->layout));
  }
  m->rhs             = p->material == SPAM_MATERIAL_GAS && p->smoothing != SPAM_SMOOTHING_FIXED ? SpamRhsGasAdaptive : SpamRhsSolid;
  if (p->material == SPAM_MATERIAL_GAS && p->smoothing == SPAM_SMOOTHING_EVOLVED) PetscCall(SpamLayoutAddSmoothing(&m->layout, kernel->h));
  if (SpamRhsSolidActiveCovers(p)) m->rhs_active = SpamRhsSolidActive;
  /* Diffusion to treat apart: the pair Laplacians of the flow scheme, with one range. */
  if (p->material == SPAM_MATERIAL_GAS && p->scheme == SPAM_GAS_FLOW && p->diffusion == SPAM_DIFFUSION_PAIR && p->smoothing == SPAM_SMOOTHING_FIXED && (p->shear_visc > 0.0 || p->conductivity > 0.0)) {
    m->rhs_part      = SpamRhsSolidPart;
    m->diffusion_jac = SpamDiffusionJacAssemble;
  }
  if (p->smoothing != SPAM_SMOOTHING_FIXED && !(p->h_eta > 0.0)) m->solid.h_eta = kernel->h; /* -h spacings of a unit lattice */
  m->max_sound_speed = SolidSoundSpeed;
  m->diag            = SpamDiagSolid;
  m->setup           = SpamSetUpSolid;
  if (p->closest_approach > 0) m->post_step = SolidClosestApproach;
  PetscCall(PetscStrncpy(m->name, p->material == SPAM_MATERIAL_GAS ? "gas" : "elastic", sizeof m->name));
  PetscFunctionReturn(0);
}
