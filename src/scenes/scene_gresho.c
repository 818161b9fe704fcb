/* The Gresho-Chan vortex (Gresho & Chan 1990; the standard test of Liska & Wendroff 2003,
 * Springel 2010): a steady, inviscid rotation whose centrifugal force the pressure gradient
 * balances exactly, so the exact solution is the initial state for all time. With r
 * measured in units of L from the box centre:
 *   v_phi = 5 r (r < 0.2), 2 - 5 r (0.2 <= r < 0.4), 0 beyond;
 *   P     = p0 + 12.5 r^2, p0 + 4 + 12.5 r^2 - 20 r + 4 ln(5 r), p0 - 2 + 4 ln 2 (times m),
 * the standard problem for p0 = 5 and gamma = 5/3. The particles sit on a triangular
 * lattice of spacing a = (2/sqrt 3)^(1/2), so that rho = m: n per row, the even number of
 * rows nearest 2n/sqrt 3, in the periodic box L x (rows a sqrt(3)/2), L = n a. Not the
 * square lattice: a square lattice of the SPAM gas has a negative stiffness against its
 * diagonal shear (tests/run_taylor_green.py), so under this pressure it breaks up within a
 * sound crossing and fills the quiet gas beyond r = 0.4 with velocity noise (measured:
 * 20% of the peak at t = 1 on 32 x 32). Beyond r = 0.4 the state is uniform, so the box
 * need not be square. Lengths are in units of L and velocities as in the standard problem
 * (peak 1), so its time unit is L here. */
#include <spam/scene.h>
#include <spam/errors.h>

typedef struct {
  PetscInt n;          /* particles per row of the triangular lattice                */
  double   p0;         /* pressure at the vortex centre (standard: 5)                */
} SpamGreshoParams;

static const SpamSceneOption Table[] = {
  {"gresho_n", SPAM_SCENE_OPTION_INT, "Particles per row of the triangular lattice (the box edge L = n a, a = 1.0746; N about 1.15 n^2)", NULL},
  {"gresho_p0", SPAM_SCENE_OPTION_REAL, "Pressure at the vortex centre (times the density m): 5 is the standard problem, larger lowers the Mach number 1/sqrt(gamma (p0 + 1/2)) of the peak", NULL},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

/* The standard profile: azimuthal velocity and pressure at radius r (units of L). */
static void GreshoProfile(double r, double p0, double *vphi, double *pres)
{
  if (r < 0.2) {
    *vphi = 5.0 * r;
    *pres = p0 + 12.5 * r * r;
  } else if (r < 0.4) {
    *vphi = 2.0 - 5.0 * r;
    *pres = p0 + 4.0 + 12.5 * r * r - 20.0 * r + 4.0 * log(5.0 * r);
  } else {
    *vphi = 0.0;
    *pres = p0 - 2.0 + 4.0 * log(2.0);
  }
}

static PetscErrorCode SpamGreshoOptions(const SpamCommonParams *c, SpamGreshoParams *p)
{
  char val[64];

  PetscFunctionBeginUser;
  p->n  = 32;
  p->p0 = 5.0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene gresho (Gresho-Chan vortex)", "spam-ark");
  PetscCall(SpamSceneOptionInt(PetscOptionsObject, Table, "gresho_n", &p->n, NULL));
  PetscCall(SpamSceneOptionReal(PetscOptionsObject, Table, "gresho_p0", &p->p0, NULL));
  PetscOptionsEnd();
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, p->n));
  if (p->n < 1) SPAM_BAD_INPUT("-gresho_n", val, "must be a positive number of lattice points");
  PetscCall(SpamCheckParticleCount("-gresho_n", val, 1.2 * pow((double)p->n, 2.0)));
  PetscCall(SpamOptionText("-gresho_p0", p->p0, val, sizeof val));
  /* P is smallest at the centre; the bounds keep the energies, their squares and the
   * reference energy p0/(gamma - 1) normal numbers. */
  if (!(p->p0 >= 1e-100 && p->p0 <= 1e100)) SPAM_BAD_INPUT("-gresho_p0", val, "must be from 1e-100 to 1e100 (the pressure at the centre, its smallest value)");
  (void)c;
  PetscFunctionReturn(0);
}

/* -gas_e0 would be dropped without a word: the profile sets every particle's energy. */
static PetscErrorCode RefuseGasE0(void)
{
  PetscBool set;
  char      val[128];

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, "-gas_e0", &set));
  if (!set) PetscFunctionReturn(0);
  PetscCall(SpamOptionText("-gas_e0", 0.0, val, sizeof val));
  SPAM_BAD_INPUT("-gas_e0", val, "-scene gresho sets e = P(r)/((gamma - 1) rho) from its pressure profile: set the pressure level with -gresho_p0");
}

/* Rows of the lattice: the even number nearest 2n/sqrt 3 (a periodic triangular lattice
 * needs an even count), so that the box is nearly square. */
static PetscInt GreshoRows(PetscInt n)
{
  return PetscMax(2, 2 * (PetscInt)floor(n / sqrt(3.0) + 0.5));
}

static PetscErrorCode SpamGreshoBuild(const SpamCommonParams *c, const SpamGreshoParams *p, const SpamSolidParams *s, SpamParticles *out)
{
  const PetscInt ny = GreshoRows(p->n), n = p->n * ny;
  const double   a = sqrt(2.0 / sqrt(3.0)), L = (double)p->n * a, Ly = (double)ny * a * 0.5 * sqrt(3.0);
  char           line[320];

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, n, out));
  PetscCall(SpamParticlesAllocateFields(out));
  out->mass    = c->mass;
  out->columns = SPAM_COLUMN_X | SPAM_COLUMN_V | SPAM_COLUMN_E; /* the energy is the profile's, not -gas_e0 */
  SpamLatticeTriangular(p->n, ny, a, out->x);
  for (PetscInt i = 0; i < n; i++) {
    const double dx = out->x[2 * i] - 0.5 * L, dy = out->x[2 * i + 1] - 0.5 * Ly, r = sqrt(dx * dx + dy * dy);
    double       vphi, pres;
    GreshoProfile(r / L, p->p0, &vphi, &pres);
    out->v[2 * i]     = r > 0.0 ? -vphi * dy / r : 0.0;
    out->v[2 * i + 1] = r > 0.0 ? vphi * dx / r : 0.0;
    out->e[i]         = pres / (s->gamma - 1.0); /* P = m P_std and rho = m: e does not depend on m */
    out->rho[i]       = c->mass;
  }
  out->box = (SpamBox){2, {0, 0, 0}, {L, Ly, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  PetscCall(PetscStrncpy(out->info.name, "gresho", sizeof out->info.name));
  out->info.sound_traversal_time = L / sqrt(s->gamma * p->p0);
  out->info.t_end_default        = L; /* t = 1 of the standard problem */
  (void)snprintf(line, sizeof line, "gresho: %" PetscInt_FMT " x %" PetscInt_FMT " particles, box %.10g x %.10g, centre (%.10g, %.10g), unit L = %.10g; peak v_phi 1 at r = 0.2 L (Mach %.4g); time unit L\n", p->n, ny, L, Ly, 0.5 * L, 0.5 * Ly, L, 1.0 / sqrt(s->gamma * (p->p0 + 0.5)));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s", line));
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  PetscCall(SpamGreshoOptions(c, p));
  SpamSolidGasDefaults(c->mass, solid);
  solid->gamma           = 5.0 / 3.0;
  /* The reference sound speed (error weights, CFL bound) is the centre's: the slowest. */
  solid->gas_e0 = ((const SpamGreshoParams *)p)->p0 / (solid->gamma - 1.0);
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  PetscCall(SpamSceneRequireGas("gresho", solid));
  PetscCall(RefuseGasE0());
  PetscCall(SpamGreshoBuild(c, p, solid, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneGresho(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"gresho", 4, PETSC_FALSE, Table, sizeof(SpamGreshoParams), PETSC_FALSE, NULL, Options, Build};
  PetscFunctionReturn(0);
}
