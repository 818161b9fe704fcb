/* The harmonic chain: a periodic 1D line of n equal masses m at unit spacing, each joined
 * to its two neighbours by a linear spring phi = k/2 (1 - r)^2 (the spring model of
 * rotor-md, bonding range 1.1). In 1D the spring force k (1 - |dx|) sign(dx) is exactly
 * linear in the displacements while neighbours keep their order, so the chain is a
 * linear test problem with a closed-form spectrum w(q) = 2 sqrt(k/m) |sin(q/2)|. For
 * even n the zone-boundary mode u_i = A (-1)^i is a normal mode with the largest
 * frequency w_max = 2 sqrt(k/m); the scene starts in it (at rest), so the step limits of
 * explicit methods are those of w_max: 2 sqrt(2) / w_max for classical RK4, 2 / w_max
 * for Verlet. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;          /* particles of the ring (even)                               */
  double   k, amplitude;
} SpamChainParams;

static const SpamSceneOption Table[] = {
  {"chain_n", SPAM_SCENE_OPTION_INT, "Particles of the periodic chain (even: the zone-boundary mode exists)", NULL},
  {"spring_k", SPAM_SCENE_OPTION_REAL, "Spring constant k of phi = k/2 (1 - r)^2", NULL},
  {"chain_amplitude", SPAM_SCENE_OPTION_REAL, "Amplitude A of the zone-boundary displacement u_i = A (-1)^i", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamChainOptions(const SpamCommonParams *c, SpamChainParams *p)
{
  char val[64];

  PetscFunctionBeginUser;
  p->n         = 64;
  p->k         = 1.0;
  p->amplitude = 0.01;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene chain (periodic harmonic chain, -dim 1)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "chain_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "spring_k", &p->k, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "chain_amplitude", &p->amplitude, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  /* The box (n unit spacings) must hold two kernel ranges and the skin. */
  if (p->n % 2 || (double)p->n < 2.0 * c->h + c->skin) SPAM_BAD_INPUT("-chain_n", val, "must be even and at least 2 h + skin");
  PetscCall(SpamCheckParticleCount("-chain_n", val, (double)p->n));
  (void)snprintf(val, sizeof val, "%g", p->k);
  if (!isfinite(p->k) || p->k <= 0.0) SPAM_BAD_INPUT("-spring_k", val, "must be positive");
  (void)snprintf(val, sizeof val, "%g", p->amplitude);
  if (!(fabs(p->amplitude) < 0.25)) SPAM_BAD_INPUT("-chain_amplitude", val, "allowed: |A| < 0.25 spacings (neighbours keep their order)");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamChainBuild(const SpamCommonParams *c, const SpamChainParams *p, SpamParticles *out)
{
  const double wmax = 2.0 * sqrt(p->k / c->mass);

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(1, p->n, out));
  out->mass = c->mass;
  for (PetscInt i = 0; i < p->n; i++) out->x[i] = (double)i + 0.5 + (i % 2 ? -p->amplitude : p->amplitude);
  out->box = (SpamBox){1, {0, 0, 0}, {(double)p->n, 0, 0}, {PETSC_TRUE, PETSC_FALSE, PETSC_FALSE}};
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "chain: N = %" PetscInt_FMT ", w_max = 2 sqrt(k/m) = %.10g; step limits 2 sqrt(2)/w_max = %.10g (RK4), 2/w_max = %.10g (Verlet)\n",
                        p->n, wmax, 2.0 * sqrt(2.0) / wmax, 2.0 / wmax));
  PetscCall(PetscStrncpy(out->info.name, "chain", sizeof out->info.name));
  /* Long waves travel at a sqrt(k/m): one traversal of the ring is n sqrt(m/k). */
  out->info.sound_traversal_time = (double)p->n / sqrt(p->k / c->mass);
  out->info.t_end_default        = 100.0 * 2.0 * PETSC_PI / wmax;
  out->model_set                 = PETSC_TRUE;
  PetscCall(SpamModelSpringsSetUp(1, c->h, c->mass, p->k, 1.0, 1.1, &out->model));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  SpamSolidDefaults(solid);
  PetscCall(SpamChainOptions(c, p));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  (void)solid;
  PetscCall(SpamChainBuild(c, p, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneChain(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"chain", 2, PETSC_TRUE, Table, sizeof(SpamChainParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
