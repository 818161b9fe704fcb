/* Right-hand side of the linear elastic solid (PRE Secs. I-II, VI-VIII), composed of the
 * tensor-path modules in the order of ARCHITECTURE.md:
 *   neighbours -> density (summed, or the state's continuity value)
 *   pass 1: velocity gradient, coordinate rate (R0/R1/R2)
 *   constitutive law: Hooke stress rate with rotation terms (or the ideal gas
 *     P = (gamma - 1) rho e), Newtonian and artificial viscosity, Q = sigma/rho^2
 *   torque scaling factors (T_i, T_ij) -> pass 2: dv/dt, de/dt, drho/dt
 *   Fourier conduction (temperature gradient, heat flux), Gauss's constraint.
 * The state is [x y vx vy e (rho) (sxx sxy syy)]. Nothing here allocates. */
#include <spam/physics.h>

/* Density of every particle into sim->rho; *bad is the first non-positive or non-finite. */
static PetscErrorCode Density(SpamSim *sim, const double *y, PetscInt *bad)
{
  const SpamLayout *l = &sim->model.layout;

  PetscFunctionBeginUser;
  if (sim->model.solid.density == SPAM_DENSITY_SUMMATION) {
    PetscCall(SpamDensitySummation(sim, y, bad));
    PetscFunctionReturn(0);
  }
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, y + l->x, l->nvar, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->n; i++) {
    sim->rho[i] = y[(size_t)i * l->nvar + l->rho];
    if (!(sim->rho[i] > 0.0) || !isfinite(sim->rho[i])) {
      *bad = i;
      break;
    }
  }
  PetscFunctionReturn(0);
}

/* Q_i = sigma_i / rho_i^2: the state's stress (elastic), or -P/rho^2 I with
 * P = (gamma - 1) rho e (ideal gas). */
static void StressOverRho2(const SpamSim *sim, const double *y, double *qs)
{
  const SpamLayout *l = &sim->model.layout;
  for (PetscInt i = 0; i < sim->n; i++) {
    if (sim->model.solid.material == SPAM_MATERIAL_GAS) {
      const double p = (sim->model.solid.gamma - 1.0) * y[(size_t)i * l->nvar + l->e] / sim->rho[i];
      qs[3 * i] = qs[3 * i + 2] = -p;
      qs[3 * i + 1]             = 0.0;
      continue;
    }
    const double *s = y + (size_t)i * l->nvar + l->s, r2 = sim->rho[i] * sim->rho[i];
    for (int k = 0; k < 3; k++) qs[3 * i + k] = s[k] / r2;
  }
}

/* The velocity the continuity equation uses: v, or dr/dt for the chain-rule form. */
static void ContinuityVelocity(const SpamSim *sim, const double *y, double *u)
{
  const SpamLayout *l = &sim->model.layout;
  for (PetscInt i = 0; i < sim->n; i++)
    for (int d = 0; d < 2; d++) u[2 * i + d] = sim->model.solid.density == SPAM_DENSITY_CHAIN_RULE ? sim->ps->xdot[2 * i + d] : y[(size_t)i * l->nvar + l->v + d];
}

static void Assemble(const SpamSim *sim, double *ydot)
{
  const SpamLayout         *l  = &sim->model.layout;
  const SpamPhysicsScratch *ps = sim->ps;
  for (PetscInt i = 0; i < sim->n; i++) {
    double *r = ydot + (size_t)i * l->nvar;
    for (int d = 0; d < 2; d++) {
      r[l->x + d] = ps->xdot[2 * i + d];
      r[l->v + d] = sim->acc[2 * i + d];
    }
    r[l->e] = ps->edot[i];
    if (l->rho >= 0) r[l->rho] = ps->rhodot[i];
  }
}

PetscErrorCode SpamRhsSolid(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  SpamPhysicsScratch    *ps   = sim->ps;
  const SpamSolidParams *sp   = &sim->model.solid;
  const SpamAngmomMode   angm = sp->angmom;
  double               total;

  PetscFunctionBeginUser;
  PetscCall(Density(sim, y, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  SpamVelocityGradient(sim, y, sim->rho, ps->gradv);
  SpamCoordinateRate(sim, y, sim->rho, ps->xdot);
  ContinuityVelocity(sim, y, ps->u);
  StressOverRho2(sim, y, ps->qs);
  if (sp->shear_visc > 0.0 || sp->bulk_visc > 0.0) SpamNewtonianViscosity(sim, ps->gradv, ps->qs);
  if (sp->viscosity == SPAM_VISCOSITY_VON_NEUMANN) SpamViscosityVonNeumann(sim, ps->gradv, ps->qs);
  if (sp->material == SPAM_MATERIAL_ELASTIC) SpamElasticStressRate(sim, y, ps->gradv, ydot);
  if (angm == SPAM_ANGMOM_TI || angm == SPAM_ANGMOM_TIJ) PetscCall(SpamTorqueScalingFactors(sim, ps->qs, &total));
  SpamForceTensor(sim, y, ps->qs);
  if (sp->conductivity > 0.0) {
    SpamTemperatureGradient(sim, y, sim->rho, ps->heat);
    SpamFourierConduction(sim, ps->heat);
  }
  if (angm == SPAM_ANGMOM_GAUSS) PetscCall(SpamGaussConstraint(sim, y));
  Assemble(sim, ydot);
  sim->stats.pair_visits += 4.0 * (double)sim->nl.npairs;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDiagSolid(SpamSim *sim, const double *y, SpamModelDiag *d)
{
  const SpamLayout *l   = &sim->model.layout;
  double            loc = 0.0, tq;
  PetscInt          bad;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->n; i++) loc += sim->model.mass * y[(size_t)i * l->nvar + l->e];
  PetscCallMPI(MPIU_Allreduce(&loc, &d->internal, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscCall(Density(sim, y, &bad));
  d->torque = NAN;
  if (bad >= 0) PetscFunctionReturn(0);
  StressOverRho2(sim, y, sim->ps->qs);
  if (sim->model.solid.shear_visc > 0.0 || sim->model.solid.bulk_visc > 0.0) { /* the viscous stress has torques too */
    SpamVelocityGradient(sim, y, sim->rho, sim->ps->gradv);
    SpamNewtonianViscosity(sim, sim->ps->gradv, sim->ps->qs);
  }
  tq = SpamTorqueSum(sim, sim->ps->qs);
  PetscCallMPI(MPIU_Allreduce(&tq, &d->torque, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscFunctionReturn(0);
}

/* Scratch, bodies (connected within the kernel range) and, on request, the summed value
 * as the initial continuity density. */
PetscErrorCode SpamSetUpSolid(SpamSim *sim)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;
  PetscInt          bad;

  PetscFunctionBeginUser;
  PetscCall(SpamPhysicsScratchCreate(sim));
  PetscCall(VecGetArray(sim->X, &y));
  PetscCall(SpamBodiesLabel(sim, y, sim->model.kernel.h));
  if (sim->model.solid.material == SPAM_MATERIAL_GAS) /* the scenes set elastic energies */
    for (PetscInt i = 0; i < sim->n; i++) y[(size_t)i * l->nvar + l->e] = sim->model.solid.gas_e0;
  if (l->rho >= 0 && sim->model.solid.density_initial == SPAM_DENSITY_INITIAL_SUMMED) {
    PetscCall(SpamDensitySummation(sim, y, &bad));
    for (PetscInt i = 0; i < sim->n; i++) y[(size_t)i * l->nvar + l->rho] = sim->rho[i];
  }
  PetscCall(VecRestoreArray(sim->X, &y));
  PetscFunctionReturn(0);
}

/* The longitudinal (or gas) sound speed at the stress-free density: a linear material's
 * signal speed does not depend on its state. */
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

PetscErrorCode SpamModelSolidSetUp(int dim, double h, double mass, const SpamSolidParams *p, SpamModel *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof *m));
  m->dim   = dim;
  m->mass  = mass;
  m->solid = *p;
  if (p->material == SPAM_MATERIAL_GAS) {
    const double pres = (p->gamma - 1.0) * p->rho0 * p->gas_e0;
    m->solid.sound_speed = sqrt(p->gamma * pres / p->rho0);
    PetscCall(SpamLayoutSolid(dim, (PetscBool)(p->density != SPAM_DENSITY_SUMMATION), PETSC_FALSE, p->rho0, pres > 0.0 ? pres : 1.0, &m->layout));
  } else {
    m->solid.sound_speed = sqrt((p->lambda + 2.0 * p->eta) / p->rho0);
    PetscCall(SpamLayoutSolid(dim, (PetscBool)(p->density != SPAM_DENSITY_SUMMATION), PETSC_TRUE, p->rho0, p->lambda + 2.0 * p->eta, &m->layout));
  }
  PetscCall(SpamKernelLucyInit(dim, h, &m->kernel));
  m->rhs   = SpamRhsSolid;
  m->max_sound_speed = SolidSoundSpeed;
  m->diag  = SpamDiagSolid;
  m->setup = SpamSetUpSolid;
  if (p->closest_approach > 0) m->post_step = SolidClosestApproach;
  PetscCall(PetscStrncpy(m->name, p->material == SPAM_MATERIAL_GAS ? "gas" : "elastic", sizeof m->name));
  PetscFunctionReturn(0);
}
