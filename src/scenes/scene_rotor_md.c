/* The rotating hexagon as molecular dynamics (PRE Fig. 4a): springs phi = k/2 (1 - r)^2
 * between initial nearest neighbours of the unit triangular lattice (k = 1 gives the
 * Lame constants lambda = eta = sqrt(3/16) of the SPAM solid), the same rigid rotation
 * as the rotor scene. Central forces: E and L are conserved to integrator accuracy. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;
  double   speed, k, range;
} SpamRotorMdParams;

static const SpamSceneOption Table[] = {
  {"rotor_n", SPAM_SCENE_OPTION_INT, "Shells of the hexagon (N = 1 + 3n + 3n^2; 8 gives 217)", NULL},
  {"rotor_speed", SPAM_SCENE_OPTION_REAL, "Speed of the vertices of the rigidly rotating hexagon", NULL},
  {"spring_k", SPAM_SCENE_OPTION_REAL, "Spring constant k of phi = k/2 (1 - r)^2", NULL},
  {"spring_range", SPAM_SCENE_OPTION_REAL, "Pairs closer than this at t = 0 are bonded (nearest neighbours: 1.1)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamRotorMdOptions(const SpamCommonParams *c, SpamRotorMdParams *p)
{
  char val[64];

  PetscFunctionBeginUser;
  (void)c;
  p->n     = 8;
  p->speed = 0.1;
  p->k     = 1.0;
  p->range = 1.1;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene rotor-md (Hoover, Hoover & Merritt 2004, Fig. 4a)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "rotor_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "rotor_speed", &p->speed, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "spring_k", &p->k, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "spring_range", &p->range, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 1 || p->n > 1000) SPAM_BAD_INPUT("-rotor_n", val, "allowed: 1 to 1000 shells");
  PetscCall(SpamCheckParticleCount("-rotor_n", val, 1.0 + 3.0 * (double)p->n * (double)(p->n + 1)));
  (void)snprintf(val, sizeof val, "%g", p->speed);
  /* The default run lasts one revolution, 2 pi n / speed: 1e-300 made it 6e300 long (and
   * 4.9e-324 infinite); 1e300 stopped as unstable at once. Both ends ran at 1e-6 and 10. */
  if (!(p->speed >= 1e-6 && p->speed <= 10.0)) SPAM_BAD_INPUT("-rotor_speed", val, "must be a positive speed from 1e-6 to 10 (the vertex speed; the longitudinal sound speed of the default solid is about 1.06)");
  (void)snprintf(val, sizeof val, "%g", p->k);
  if (!isfinite(p->k) || p->k <= 0.0) SPAM_BAD_INPUT("-spring_k", val, "must be positive");
  (void)snprintf(val, sizeof val, "%g", p->range);
  if (!isfinite(p->range) || p->range <= 0.0 || p->range >= c->h) SPAM_BAD_INPUT("-spring_range", val, "allowed: 0 < range < h");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamRotorMdBuild(const SpamCommonParams *c, const SpamRotorMdParams *p, SpamParticles *out)
{
  const PetscInt n     = 1 + 3 * p->n + 3 * p->n * p->n;
  const double   omega = p->speed / (double)p->n;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, n, out));
  out->mass = c->mass;
  (void)SpamLatticeHexagon(p->n, 1.0, out->x);
  for (PetscInt i = 0; i < n; i++) {
    out->v[2 * i]     = -omega * out->x[2 * i + 1];
    out->v[2 * i + 1] = omega * out->x[2 * i];
  }
  SpamParticlesOpenBox(out, c->h + 0.25 * (double)p->n + 1.0);
  PetscCall(PetscStrncpy(out->info.name, "rotor-md", sizeof out->info.name));
  out->info.sound_traversal_time = 2.0 * (double)p->n / sqrt(9.0 / 8.0);
  out->info.t_end_default        = 2.0 * PETSC_PI / omega;
  out->model_set                 = PETSC_TRUE;
  PetscCall(SpamModelSpringsSetUp(2, c->h, c->mass, p->k, 1.0, p->range, &out->model));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  SpamSolidDefaults(solid);
  PetscCall(SpamRotorMdOptions(c, p));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  (void)solid;
  PetscCall(SpamRotorMdBuild(c, p, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneRotorMd(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"rotor-md", 4, PETSC_TRUE, Table, sizeof(SpamRotorMdParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
