/* Triangular lattices: the periodic crystal of the plane-wave and tensile scenes and the
 * hexagonal rotor. */
#include <spam/scene.h>
#include <spam/errors.h>

void SpamLatticeTriangular(PetscInt nx, PetscInt ny, double a, double *x)
{
  const double ry = 0.5 * sqrt(3.0) * a;
  for (PetscInt j = 0; j < ny; j++)
    for (PetscInt i = 0; i < nx; i++) {
      x[2 * (j * nx + i)]     = a * ((double)i + 0.25 + 0.5 * (double)(j % 2));
      x[2 * (j * nx + i) + 1] = ry * ((double)j + 0.5);
    }
}

/* Axial coordinates (q, r) with |q|, |r|, |q + r| <= n: x = q + r/2, y = r sqrt(3)/2. */
PetscInt SpamLatticeHexagon(PetscInt n, double a, double *x)
{
  PetscInt k = 0;
  for (PetscInt r = -n; r <= n; r++)
    for (PetscInt q = -n; q <= n; q++) {
      if (PetscAbsInt(q + r) > n) continue;
      x[2 * k]     = a * ((double)q + 0.5 * (double)r);
      x[2 * k + 1] = a * 0.5 * sqrt(3.0) * (double)r;
      k++;
    }
  return k;
}

void SpamSolidDefaults(SpamSolidParams *p)
{
  PetscMemzero(p, sizeof *p);
  p->lambda          = 0.25 * sqrt(3.0);
  p->eta             = 0.25 * sqrt(3.0);
  p->rho0            = sqrt(4.0 / 3.0);
  p->density         = SPAM_DENSITY_CONTINUITY;
  p->density_initial = SPAM_DENSITY_INITIAL_IDEAL;
  p->coords          = SPAM_COORDS_R0;
  p->xsph_eps        = 1.0;
  p->angmom          = SPAM_ANGMOM_NONE;
  p->viscosity       = SPAM_VISCOSITY_NONE;
  p->material        = SPAM_MATERIAL_ELASTIC;
  p->gamma           = 2.0;
  p->gas_e0          = 1.0;
  p->visc_alpha      = 1.0;
  p->visc_beta       = 2.0;
}

void SpamSolidGasDefaults(double rho0, SpamSolidParams *p)
{
  SpamSolidDefaults(p);
  p->material        = SPAM_MATERIAL_GAS;
  p->density         = SPAM_DENSITY_SUMMATION;
  p->density_initial = SPAM_DENSITY_INITIAL_SUMMED;
  p->rho0            = rho0;
}

PetscErrorCode SpamSceneRequireGas(const char *scene, const SpamSolidParams *p)
{
  PetscFunctionBeginUser;
  if (p->material != SPAM_MATERIAL_GAS) SPAM_BAD_INPUT("-material", SpamMaterialNames[p->material], "-scene %s is a gas with its energy equation: use -material gas", scene);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamParticlesAllocateFields(SpamParticles *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscCalloc3(p->n + 1, &p->e, p->n + 1, &p->rho, (size_t)SpamStressComponents(p->dim) * p->n + 1, &p->sigma));
  PetscFunctionReturn(0);
}

void SpamParticlesOpenBox(SpamParticles *p, double margin)
{
  p->box.dim = p->dim;
  for (int d = 0; d < p->dim; d++) {
    double lo = PETSC_MAX_REAL, hi = -PETSC_MAX_REAL;
    for (PetscInt i = 0; i < p->n; i++) {
      lo = PetscMin(lo, p->x[i * p->dim + d]);
      hi = PetscMax(hi, p->x[i * p->dim + d]);
    }
    p->box.lo[d]       = lo - margin;
    p->box.len[d]      = hi - lo + 2.0 * margin;
    p->box.periodic[d] = PETSC_FALSE;
  }
}

PetscErrorCode SpamSimFillFields(SpamSim *sim, const SpamParticles *p)
{
  const SpamLayout *l  = &sim->model.layout;
  const int         ns = SpamStressComponents(p->dim);
  PetscReal        *s;
  PetscInt          bs;
  PetscDataType     type;

  PetscFunctionBeginUser;
  if (!p->e) PetscFunctionReturn(0);
  PetscCall(DMSwarmGetField(sim->p.swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    if (l->e >= 0) s[i * bs + l->e] = p->e[i];
    if (l->rho >= 0) s[i * bs + l->rho] = p->rho[i];
    for (int k = 0; l->s >= 0 && k < ns; k++) s[i * bs + l->s + k] = p->sigma[ns * i + k];
  }
  PetscCall(DMSwarmRestoreField(sim->p.swarm, SPAM_STATE_FIELD, &bs, &type, (void **)&s));
  PetscFunctionReturn(0);
}
