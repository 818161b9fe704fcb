/* Sod's shock tube (Sod, J. Comput. Phys. 27, 1 (1978)): the ideal gas gamma = 1.4 at rest,
 * (rho, p) = (1, 1) for x < 0 and (0.125, 0.1) for x > 0, in 1D or as a 2D or 3D tube along
 * x, periodic across.
 *
 * Why a uniform lattice with unequal masses: the kernel range h is fixed, so the resolution
 * is the lattice spacing. Equal masses would need eight times the spacing on the right,
 * where a fixed h then holds an eighth of the neighbours (in 1D at h = 6 left spacings,
 * none at all): the low-density side would be unresolved. One spacing everywhere with the mass
 * m = rho * (cell volume) keeps both sides equally resolved, and the summation density
 * rho_i = sum_j m_j w_ij recovers rho on either side (smeared over h at the contact).
 *
 * Units: lattice spacing 1 (h counts spacings, as in every lattice scene). The exact
 * solution depends on x/t only, so the classical tube of unit length at t = 0.2 is this
 * one with -sod_n spacings per unit length at t = 0.2 n: the default end time. The tube
 * holds -sod_length such units (default 2: x in [-n, n)) and is periodic along x too, so
 * its ends carry the reversed jump; its waves (a fan moving right from -n, reaching -0.76 n,
 * and a shock moving left from +n, reaching 0.65 n at t = 0.2 n) stay outside |x| < n/2
 * (the classical tube [-0.5, 0.5]), so the region compared is that of the single Riemann
 * problem. At least 1.4 units: shorter, the two problems' shocks meet by t = 0.2. Mirror
 * walls at the ends (-wall_xlo, -wall_xhi) replace the reversed jump; their reflections
 * do not reach the compared region by t = 0.2 either. -mass m scales both
 * densities and both pressures: the same flow (same e, same velocities).
 *
 * The energies per unit mass e = p / ((gamma - 1) rho) are given per particle; -gas_e0
 * (one energy for every particle) has no meaning here and is refused. The artificial
 * viscosity's sound speed is the model's constant reference c = sqrt(gamma (gamma - 1) e0)
 * with e0 = 2.5, the left state's energy: c = 1.183 at gamma = 1.4. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;      /* lattice spacings per unit length of the classical tube            */
  double   length; /* tube length in those units (periodic)                             */
  PetscInt width;  /* lattice points across the tube in each transverse direction       */
} SpamSodParams;

static const SpamSceneOption Table[] = {
  {"sod_n", SPAM_SCENE_OPTION_INT, "Lattice spacings per unit length of the classical tube (the end time is 0.2 n; default 200, 100, 25 in 1D, 2D, 3D)", NULL},
  {"sod_length", SPAM_SCENE_OPTION_REAL, "Tube length in those units, periodic (the jump at 0, its reverse at the ends)", NULL},
  {"sod_width", SPAM_SCENE_OPTION_INT, "Lattice points across the tube in each transverse direction (2D, 3D; periodic)", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

/* The left and right states (Sod 1978), in units of the left density and pressure. */
#define SOD_RHO_LEFT  1.0
#define SOD_P_LEFT    1.0
#define SOD_RHO_RIGHT 0.125
#define SOD_P_RIGHT   0.1
#define SOD_GAMMA     1.4
#define SOD_T_END     0.2 /* in units where the tube has unit length per -sod_n spacings */
/* The shortest periodic tube whose two Riemann problems (the jump at 0 and its reverse at
 * the ends) stay apart until t = 0.2: their shocks (1.752 t) meet when L/2 = 2 x 0.3504. */
#define SOD_LENGTH_MIN 1.4

/* Lattice sites along the tube: length x n, rounded (1.1 x 30 is 33.000000000000004). */
static double TubeSites(const SpamSodParams *p)
{
  return round(p->length * (double)p->n);
}

static PetscErrorCode SodOptions(const SpamCommonParams *c, SpamSodParams *p)
{
  char      val[128];
  PetscBool e0_set, width_set, help;

  PetscFunctionBeginUser;
  p->n      = c->dim == 1 ? 200 : c->dim == 2 ? 100 : 25; /* runs of seconds: 400, 1600, 3200 particles */
  p->length = 2.0;
  p->width  = 8;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene sod (Sod 1978 shock tube)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "sod_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "sod_length", &p->length, NULL));
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "sod_width", &p->width, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 2) SPAM_BAD_INPUT("-sod_n", val, "must be at least 2 lattice spacings per unit length");
  PetscCall(SpamOptionText("-sod_length", p->length, val, sizeof val));
  if (!(p->length >= SOD_LENGTH_MIN && p->length <= 1e6)) SPAM_BAD_INPUT("-sod_length", val, "allowed: %g to 1e6 unit lengths (shorter, the shock of the reversed jump at the ends meets the tube's own by t = 0.2)", SOD_LENGTH_MIN);
  if (fabs(p->length * (double)p->n - TubeSites(p)) > 1e-9 * p->length * (double)p->n || fmod(TubeSites(p), 2.0) != 0.0) SPAM_BAD_INPUT("-sod_length", val, "-sod_length x -sod_n must be an even whole number of lattice spacings (the jump sits between two sites)");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->width));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-sod_width", &width_set));
  if (c->dim == 1 && width_set) SPAM_BAD_INPUT("-sod_width", val, "applies to the 2D and 3D tubes (this run: -dim 1)");
  if (c->dim > 1 && p->width < 1) SPAM_BAD_INPUT("-sod_width", val, "must be a positive number of lattice points");
  PetscCall(PetscSNPrintf(val, sizeof val, "%g x %" PetscInt_FMT "^%d", p->length * (double)p->n, p->width, c->dim - 1));
  PetscCall(SpamCheckParticleCount("-sod_length x -sod_n x -sod_width^(D-1)", val, p->length * (double)p->n * pow((double)p->width, c->dim - 1)));
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-gas_e0", &e0_set));
  PetscCall(SpamOptionText("-gas_e0", 0.0, val, sizeof val));
  if (e0_set && !help) SPAM_BAD_INPUT("-gas_e0", val, "-scene sod gives each particle the energy of its state, e = p / ((gamma - 1) rho)");
  PetscFunctionReturn(0);
}

/* A note when h is below the range that resolves the fan: the flow is planar, so the fan
 * stretches the spacing along x by 2.3 (to density 0.43) in every dimension; a particle
 * there then keeps fewer than three neighbours along x within h, and the fan breaks into
 * steps. Measured (docs/scenes/sod.md): 1D h = 3, 4, 5 miss the fan ends by 10, 3, 1.2 h
 * (rho*L +10%, +0.2%, +4%), h >= 6 within 0.5 h; 2D h = 3 and 3D h = 3 give rho*L 12% and
 * 13% high, 2D h = 4 within 2.3%. */
static PetscErrorCode NoteRange(const SpamCommonParams *c)
{
  static const double h_min[4] = {0.0, 6.0, 4.0, 4.0};
  char                line[256];

  PetscFunctionBeginUser;
  if (c->h >= h_min[c->dim]) PetscFunctionReturn(0);
  (void)snprintf(line, sizeof line, "sod: note: -h %g lattice spacings is below %g (%dD): the rarefaction fan is under-resolved and breaks into steps (options/sod.opts)\n", c->h, h_min[c->dim], c->dim); /* PETSc's %g writes 3 as "3." */
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  PetscFunctionReturn(0);
}

/* Lattice site k of the tube (x along it; transverse sites at 0.5, 1.5, ...). */
static void Site(int dim, PetscInt k, PetscInt nx, PetscInt width, double x0, double *x)
{
  x[0] = x0 + (double)(k % nx) + 0.5;
  k /= nx;
  for (int d = 1; d < dim; d++) {
    x[d] = (double)(k % width) + 0.5;
    k /= width;
  }
}

static PetscErrorCode SodBuild(const SpamCommonParams *c, const SpamSodParams *p, const SpamSolidParams *s, SpamParticles *out)
{
  const int      dim = c->dim;
  const PetscInt nx  = (PetscInt)TubeSites(p), w = dim > 1 ? p->width : 1;
  const double   x0  = -0.5 * (double)nx;
  PetscInt       n   = nx;

  PetscFunctionBeginUser;
  for (int d = 1; d < dim; d++) n *= w;
  PetscCall(SpamParticlesAllocate(dim, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  PetscCall(PetscCalloc1(n + 1, &out->m));
  out->columns = SPAM_COLUMN_X | SPAM_COLUMN_V | SPAM_COLUMN_M | SPAM_COLUMN_E;
  out->mass    = c->mass;
  for (PetscInt i = 0; i < n; i++) {
    PetscBool left;
    Site(dim, i, nx, w, x0, out->x + (size_t)i * dim);
    left       = (PetscBool)(out->x[(size_t)i * dim] < 0.0);
    out->m[i]  = c->mass * (left ? SOD_RHO_LEFT : SOD_RHO_RIGHT); /* unit cell volume */
    out->e[i]  = (left ? SOD_P_LEFT / SOD_RHO_LEFT : SOD_P_RIGHT / SOD_RHO_RIGHT) / (s->gamma - 1.0);
    out->rho[i] = out->m[i];
  }
  out->box.dim = dim;
  for (int d = 0; d < dim; d++) {
    out->box.lo[d]       = d ? 0.0 : x0;
    out->box.len[d]      = d ? (double)w : (double)nx;
    out->box.periodic[d] = PETSC_TRUE;
  }
  PetscCall(NoteRange(c));
  PetscCall(PetscStrncpy(out->info.name, "sod", sizeof out->info.name));
  out->info.sound_traversal_time = (double)p->n / s->sound_speed; /* a unit length at the reference speed */
  out->info.t_end_default        = SOD_T_END * (double)p->n;
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SodOptions(c, p));
  SpamSolidGasDefaults(c->mass * SOD_RHO_LEFT, solid);
  solid->gamma           = SOD_GAMMA;
  solid->gas_e0          = SOD_P_LEFT / (SOD_RHO_LEFT * (SOD_GAMMA - 1.0)); /* reference sound speed only */
  solid->viscosity       = SPAM_VISCOSITY_MONAGHAN;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  SpamSolidParams s = *solid;

  PetscFunctionBeginUser;
  s.sound_speed = sqrt(s.gamma * (s.gamma - 1.0) * s.gas_e0); /* as the model will set it */
  PetscCall(SodBuild(c, p, &s, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneSod(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"sod", 2 | 4 | 8, PETSC_FALSE, Table, sizeof(SpamSodParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
