/* Free expansion (Hoover & Hoover 2001, Figs. 2-3): an n^D square lattice of unit
 * spacing fills one corner of a periodic box of edge 2n, so the gas expands into 2^D
 * times its volume: twofold in 1D, fourfold in 2D, eightfold in 3D. Small seeded random
 * offsets (or velocities) break the lattice symmetry. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt  n;          /* lattice points per direction                           */
  double    amplitude;  /* size of the random offsets or velocities               */
  PetscInt  seed;
  PetscBool velocities; /* perturb velocities instead of positions                */
} SpamExpansionParams;

static const SpamSceneOption Table[] = {
  {"expansion_n", SPAM_SCENE_OPTION_INT, "Lattice points per direction of the initial gas (N = n^D)", NULL},
  {"expansion_amplitude", SPAM_SCENE_OPTION_REAL, "Size of the uniform random offsets (lattice units) or velocities", NULL},
  {"expansion_seed", SPAM_SCENE_OPTION_INT, "Seed of the random perturbation", NULL},
  {"expansion_perturb_velocities", SPAM_SCENE_OPTION_BOOL, "Perturb velocities instead of positions", NULL},
  {"periodic", SPAM_SCENE_OPTION_BOOLS, NULL, ", which builds its own box"}, /* read with the common options (scene.c) */
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

static PetscErrorCode SpamExpansionOptions(const SpamCommonParams *c, SpamExpansionParams *p)
{
  char val[64];

  PetscFunctionBeginUser;
  p->n          = 32;
  p->amplitude  = 0.01;
  p->seed       = 1;
  p->velocities = PETSC_FALSE;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene expansion (Hoover & Hoover 2001)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "expansion_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "expansion_amplitude", &p->amplitude, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "expansion_seed", &p->seed, NULL));
  PetscCall(SpamSceneOptionBool(PetscOptionsObject, Table, "expansion_perturb_velocities", &p->velocities, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 1) SPAM_BAD_INPUT("-expansion_n", val, "must be a positive number of lattice points");
  PetscCall(SpamCheckParticleCount("-expansion_n", val, pow((double)p->n, c->dim))); /* n^D in double: no overflow */
  (void)snprintf(val, sizeof val, "%g", p->amplitude);
  if (!(p->amplitude >= 0.0 && p->amplitude < 0.5)) SPAM_BAD_INPUT("-expansion_amplitude", val, "allowed: 0 <= amplitude < 0.5 lattice spacings");
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamExpansionBuild(const SpamCommonParams *c, const SpamExpansionParams *p, SpamParticles *out)
{
  const int  dim = c->dim;
  PetscInt   n   = 1;
  uint64_t   rng = (uint64_t)p->seed;
  SpamEosIsentrope eos = {c->gamma, c->kappa};

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) n *= p->n;
  PetscCall(SpamParticlesAllocate(dim, n, out));
  out->mass    = c->mass;
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.lo[d]       = 0.0;
    out->box.len[d]      = 2.0 * (double)p->n;
    out->box.periodic[d] = c->periodic[d];
  }
  for (PetscInt i = 0; i < n; i++) {
    PetscInt rem = i;
    for (int d = 0; d < dim; d++) {
      const double site = (double)(rem % p->n) + 0.5;
      const double r    = p->amplitude * SpamSceneUniform(&rng);
      rem /= p->n;
      out->x[i * dim + d] = site + (p->velocities ? 0.0 : r);
      out->v[i * dim + d] = p->velocities ? r : 0.0;
    }
  }
  PetscCall(PetscStrncpy(out->info.name, "expansion", sizeof out->info.name));
  out->info.volume_ratio = pow(2.0, dim);
  /* Unit lattice: nominal density m; sound crosses the n-wide gas in n / c. */
  out->info.sound_traversal_time = (double)p->n / SpamEosSoundSpeed(&eos, c->mass);
  out->info.t_end_default        = 2.0 * out->info.sound_traversal_time;
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  SpamSolidDefaults(solid);
  solid->material        = SPAM_MATERIAL_ISENTROPE;
  solid->density         = SPAM_DENSITY_SUMMATION;
  solid->density_initial = SPAM_DENSITY_INITIAL_SUMMED;
  solid->rho0            = c->mass;
  solid->plain_default   = PETSC_TRUE; /* a gas expanding into vacuum has no background pressure */
  PetscCall(SpamExpansionOptions(c, p));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  (void)solid;
  PetscCall(SpamExpansionBuild(c, p, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneExpansion(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"expansion", 2 | 4 | 8, PETSC_FALSE, Table, sizeof(SpamExpansionParams), PETSC_FALSE, "2 x -expansion_n", Options, Build};
  PetscFunctionReturn(0);
}
