/* The Sedov-Taylor point blast (Sedov 1959; Taylor 1950) in 2D (cylindrical) or 3D
 * (spherical): the ideal gas gamma = 5/3 at rest on an n^D square lattice of unit spacing
 * (density m) filling a periodic box, the energy E0 deposited in the particles within h
 * of the box centre, weighted by the kernel: e_i = e0 + E0 w(r_i) / sum_j m_j w(r_j), so
 * the deposit is E0 exactly and spread over the smallest region the method resolves.
 * -sedov_deposit_radius spreads it over a wider (or narrower) range instead: at the
 * adaptive range a deposit into a few particles leaves them hot and isolated at the centre.
 *
 * The self-similar solution needs a cold ambient gas: e0 (-gas_e0, default 1e-3, pressure
 * 6.7e-4) is below 1e-3 of the post-shock pressure while the shock stays inside the box at
 * the default energy 1e4. The default end time is when the shock radius R(t) = xi0
 * (E0 t^2 / rho)^(1/(D+2)) reaches 0.35 n (xi0 taken as 1.1, between the 2D 1.13 and 3D
 * 1.15 of gamma = 5/3: only the end time depends on it), so the shock is well inside the
 * periodic box and never meets its images.
 *
 * The artificial viscosity's sound speed is the model's constant reference, that of the
 * ambient gas (c = 0.033): at the shock its quadratic term beta mu^2 does the work. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;      /* lattice points per direction of the periodic box                  */
  double   energy; /* blast energy E0                                                   */
  double   radius; /* the deposit's kernel range (0: -h, the model's range)              */
} SpamSedovParams;

static const SpamSceneOption Table[] = {
  {"sedov_n", SPAM_SCENE_OPTION_INT, "Lattice points per direction of the periodic box (default 48 in 2D, 20 in 3D)", NULL},
  {"sedov_energy", SPAM_SCENE_OPTION_REAL, "Blast energy E0, deposited kernel-weighted within h of the centre", NULL},
  {"sedov_deposit_radius", SPAM_SCENE_OPTION_REAL, "Range of the kernel that weights the deposit of E0, in lattice spacings (0: -h)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

#define SEDOV_GAMMA     (5.0 / 3.0)
#define SEDOV_E_AMBIENT 1e-3
#define SEDOV_XI0_EST   1.1  /* for the default end time only                          */
#define SEDOV_R_END     0.35 /* shock radius at the default end time, in box edges     */

static PetscErrorCode SedovOptions(const SpamCommonParams *c, SpamSedovParams *p)
{
  char val[128];

  PetscFunctionBeginUser;
  p->n      = c->dim == 3 ? 20 : 48; /* about 9 s in 2D, a minute in 3D (one thread) */
  p->energy = 1e4;
  p->radius = 0.0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene sedov (point blast)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "sedov_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "sedov_energy", &p->energy, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "sedov_deposit_radius", &p->radius, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 4) SPAM_BAD_INPUT("-sedov_n", val, "must be at least 4 lattice points per direction");
  PetscCall(SpamCheckParticleCount("-sedov_n", val, pow((double)p->n, c->dim)));
  PetscCall(SpamOptionText("-sedov_energy", p->energy, val, sizeof val));
  if (!(p->energy >= 1e-100 && p->energy <= 1e100)) SPAM_BAD_INPUT("-sedov_energy", val, "allowed: 1e-100 to 1e100");
  PetscCall(SpamOptionText("-sedov_deposit_radius", p->radius, val, sizeof val));
  /* Above the half diagonal of a lattice cell (the nearest particles' distance from the
   * centre, a cell corner) so that some particle takes the energy; below a quarter of the box. */
  if (!(p->radius == 0.0 || (p->radius > 0.5 * sqrt((double)c->dim) && p->radius < 0.25 * (double)p->n))) SPAM_BAD_INPUT("-sedov_deposit_radius", val, "must be 0 (-h) or above sqrt(dim)/2 (the nearest particles) and below n/4 (-sedov_n %" PetscInt_FMT ")", p->n);
  PetscFunctionReturn(0);
}

/* Kernel-weighted deposit of E0 about the centre: into e (which holds e0 already). The
 * weight is the model's kernel at its range -h, or at -sedov_deposit_radius when given. */
static PetscErrorCode Deposit(const SpamCommonParams *c, double energy, double radius, const double *centre, SpamParticles *out)
{
  const int  dim = out->dim;
  double     norm = 0.0, *w;
  SpamKernel k    = c->kernel;

  PetscFunctionBeginUser;
  if (radius > 0.0) PetscCall(SpamKernelCreate(c->kernel.name, dim, radius, &k));
  PetscCall(PetscCalloc1(out->n + 1, &w));
  for (PetscInt i = 0; i < out->n; i++) {
    double r2 = 0.0;
    for (int d = 0; d < dim; d++) r2 += (out->x[(size_t)i * dim + d] - centre[d]) * (out->x[(size_t)i * dim + d] - centre[d]);
    w[i] = SpamKernelW(&k, r2);
    norm += c->mass * w[i];
  }
  for (PetscInt i = 0; i < out->n; i++) out->e[i] += energy * w[i] / norm;
  PetscCall(PetscFree(w));
  PetscFunctionReturn(0);
}

static PetscErrorCode SedovBuild(const SpamCommonParams *c, const SpamSedovParams *p, const SpamSolidParams *s, SpamParticles *out)
{
  const int dim = c->dim;
  PetscInt  n   = 1;
  double    centre[3] = {0, 0, 0}, r_end, t_end;
  char      val[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (!(c->h < 0.25 * (double)p->n)) SPAM_BAD_INPUT("-sedov_n", val, "the box must be wider than 4 h (-h %g): the blast would fill it", c->h);
  for (int d = 0; d < dim; d++) n *= p->n;
  PetscCall(SpamParticlesAllocate(dim, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  out->columns = SPAM_COLUMN_X | SPAM_COLUMN_V | SPAM_COLUMN_E;
  out->mass    = c->mass;
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.lo[d]       = 0.0;
    out->box.len[d]      = (double)p->n;
    out->box.periodic[d] = PETSC_TRUE;
    centre[d]            = 0.5 * (double)p->n;
  }
  for (PetscInt i = 0; i < n; i++) {
    PetscInt rem = i;
    for (int d = 0; d < dim; d++) {
      out->x[(size_t)i * dim + d] = (double)(rem % p->n) + 0.5;
      rem /= p->n;
    }
    out->e[i]   = s->gas_e0;
    out->rho[i] = c->mass;
  }
  PetscCall(Deposit(c, p->energy, p->radius, centre, out));
  r_end = SEDOV_R_END * (double)p->n;
  t_end = sqrt(pow(r_end / SEDOV_XI0_EST, dim + 2) * c->mass / p->energy);
  PetscCall(PetscStrncpy(out->info.name, "sedov", sizeof out->info.name));
  out->info.sound_traversal_time = t_end; /* the ambient gas is cold: the blast's own time */
  out->info.t_end_default        = t_end;
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SedovOptions(c, p));
  SpamSolidGasDefaults(c->mass, solid); /* unit lattice */
  solid->gamma           = SEDOV_GAMMA;
  solid->gas_e0          = SEDOV_E_AMBIENT;
  solid->viscosity       = SPAM_VISCOSITY_MONAGHAN;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  PetscCall(SedovBuild(c, p, solid, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneSedov(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"sedov", 4 | 8, PETSC_FALSE, Table, sizeof(SpamSedovParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
