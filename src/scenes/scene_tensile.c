/* Tensile instability (PRE Sec. IV, Fig. 1): the periodic triangular crystal at rest under
 * uniform hydrostatic tension sigma_xx = sigma_yy = sigma0, one particle (the one nearest
 * the centre) given the velocity kick along x. Standard SPAM turns the tension into an
 * attraction between neighbours: the kinetic energy grows exponentially at a rate that
 * rises with sigma0; velocity averaging (R2) suppresses it. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt nx, ny;
  double   stress, kick;
  SpamSolidParams solid;
} SpamTensileParams;

static const SpamSceneOption Table[] = {
  {"tensile_nx", SPAM_SCENE_OPTION_INT, "Particles per lattice row", NULL},
  {"tensile_ny", SPAM_SCENE_OPTION_INT, "Lattice rows (even)", NULL},
  {"tensile_stress", SPAM_SCENE_OPTION_REAL, "Hydrostatic tension sigma0 (positive: tension)", NULL},
  {"tensile_kick", SPAM_SCENE_OPTION_REAL, "Initial x velocity of the centre particle", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamTensileOptions(const SpamCommonParams *c, SpamTensileParams *p)
{
  char val[64];

  PetscFunctionBeginUser;
  p->nx     = 24;
  p->ny     = 24;
  p->stress = 0.01;
  p->kick   = 1e-10;
  SpamSolidDefaults(&p->solid);
  p->solid.rho0 = c->mass * sqrt(4.0 / 3.0);
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene tensile (Hoover, Hoover & Merritt 2004, Fig. 1)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "tensile_nx", &p->nx, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "tensile_ny", &p->ny, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "tensile_stress", &p->stress, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "tensile_kick", &p->kick, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->ny));
  if (p->ny < 2 || p->ny % 2) SPAM_BAD_INPUT("-tensile_ny", val, "must be an even number of rows >= 2 (periodic triangular lattice)");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->nx));
  if (p->nx < 1) SPAM_BAD_INPUT("-tensile_nx", val, "must be positive");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT " x %" PetscInt_FMT, p->nx, p->ny));
  PetscCall(SpamCheckParticleCount("-tensile_nx x -tensile_ny", val, (double)p->nx * (double)p->ny));
  (void)snprintf(val, sizeof val, "%g", p->stress);
  if (!isfinite(p->stress)) SPAM_BAD_INPUT("-tensile_stress", val, "must be a finite number");
  (void)snprintf(val, sizeof val, "%g", p->kick);
  if (!isfinite(p->kick)) SPAM_BAD_INPUT("-tensile_kick", val, "must be a finite number");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamTensileBuild(const SpamCommonParams *c, const SpamTensileParams *p, SpamParticles *out)
{
  const PetscInt n = p->nx * p->ny, centre = (p->ny / 2) * p->nx + p->nx / 2;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  out->mass = c->mass;
  SpamLatticeTriangular(p->nx, p->ny, 1.0, out->x);
  for (PetscInt i = 0; i < n; i++) {
    out->rho[i]           = p->solid.rho0;
    out->sigma[3 * i]     = p->stress;
    out->sigma[3 * i + 2] = p->stress;
  }
  out->v[2 * centre] = p->kick;
  out->box           = (SpamBox){2, {0, 0, 0}, {(double)p->nx, 0.5 * sqrt(3.0) * (double)p->ny, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  PetscCall(PetscStrncpy(out->info.name, "tensile", sizeof out->info.name));
  out->info.sound_traversal_time = (double)p->nx / sqrt((p->solid.lambda + 2.0 * p->solid.eta) / p->solid.rho0);
  out->info.t_end_default        = 150.0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SpamTensileOptions(c, p));
  *solid = ((const SpamTensileParams *)p)->solid;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  SpamTensileParams q = *(const SpamTensileParams *)p;

  PetscFunctionBeginUser;
  q.solid = *solid;
  PetscCall(SpamTensileBuild(c, &q, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneTensile(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"tensile", 4, PETSC_FALSE, Table, sizeof(SpamTensileParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
