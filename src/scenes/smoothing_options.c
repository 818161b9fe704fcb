/* The kernel range's options: -smoothing_length fixed (one h, the papers' scenes),
 * adaptive (each particle's own h_i solved from rho_i h_i^D = eta^D m_i to -h_tol, with
 * -h_eta and the bounds -h_min, -h_max) or evolved (h_i in the state, integrated from that
 * relation's start), and the refusals of what those ranges do not cover yet. */
#include <spam/scene.h>
#include <spam/errors.h>

const char *const SpamSmoothingModeNames[] = {"fixed", "adaptive", "evolved"};

/* The bounds' defaults: the list range is h_max h, so its pairs grow as h_max^D; a gas
 * compressed fourfold in 2D (a strong shock's shell) needs h_i down to h/2. */
#define SPAM_H_MIN_DEFAULT 0.25
#define SPAM_H_MAX_DEFAULT 2.0
/* Beyond this the list holds (10 h)^D / h^D times the pairs of the fixed range. */
#define SPAM_H_MAX_MOST 10

PetscErrorCode SpamSmoothingOptions(PetscOptionItems *PetscOptionsObject, PetscBool help, const char *mat, SpamSolidParams *p, char *mode, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(mode, SpamSmoothingModeNames[p->smoothing], len));
  if (p->h_min == 0.0) p->h_min = SPAM_H_MIN_DEFAULT;
  if (p->h_max == 0.0) p->h_max = SPAM_H_MAX_DEFAULT;
  if (p->h_tol == 0.0) p->h_tol = SPAM_H_TOL_DEFAULT;
  if (help || !strcmp(mat, "gas")) PetscCall(PetscOptionsString("-smoothing_length", "Gas: kernel range fixed (one h), adaptive (h_i solved from rho_i h_i^D = eta^D m_i in each evaluation, with grad-h terms) or evolved (h_i in the state, dh_i/dt = -h_i/(D rho_i) drho_i/dt, started from that relation)", "README", mode, mode, len, NULL));
  if (help || (!strcmp(mat, "gas") && (!strcmp(mode, "adaptive") || !strcmp(mode, "evolved")))) {
    PetscCall(PetscOptionsReal("-h_eta", "Adaptive h: eta = h_i / (m_i/rho_i)^(1/D), the range in mean particle spacings (0: -h, the range on a lattice of unit spacing)", "README", p->h_eta, &p->h_eta, NULL));
    PetscCall(PetscOptionsReal("-h_min", "Adaptive h: lower bound of h_i as a factor of -h", "README", p->h_min, &p->h_min, NULL));
    PetscCall(PetscOptionsReal("-h_tol", "Adaptive h: |rho_i h_i^D / (eta^D m_i) - 1| at which the solve takes h_i as settled (evolved: the start's solve); a loose one leaves noise in the right-hand side", "README", p->h_tol, &p->h_tol, NULL));
    PetscCall(PetscOptionsReal("-h_max", "Adaptive h: upper bound of h_i as a factor of -h (the neighbour list's range)", "README", p->h_max, &p->h_max, NULL));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSmoothingValidate(const char *mode, SpamSolidParams *p)
{
  char val[128];
  int  k;

  PetscFunctionBeginUser;
  for (k = 0; k < 3 && strcmp(mode, SpamSmoothingModeNames[k]); k++) {}
  if (k == 3) {
    SpamClip(mode, val, sizeof val);
    SPAM_BAD_INPUT("-smoothing_length", val, "allowed: fixed, adaptive, evolved");
  }
  p->smoothing = (SpamSmoothingMode)k;
  PetscCall(SpamOptionText("-h_eta", p->h_eta, val, sizeof val));
  if (!(p->h_eta >= 0.0) || !isfinite(p->h_eta)) SPAM_BAD_INPUT("-h_eta", val, "must be 0 (-h) or a positive number of mean spacings");
  PetscCall(SpamOptionText("-h_min", p->h_min, val, sizeof val));
  if (!(p->h_min > 0.0 && p->h_min <= 1.0)) SPAM_BAD_INPUT("-h_min", val, "must be above 0 and at most 1 (a factor of -h)");
  PetscCall(SpamOptionText("-h_tol", p->h_tol, val, sizeof val));
  if (!(p->h_tol >= 1e-15 && p->h_tol <= 1e-2)) SPAM_BAD_INPUT("-h_tol", val, "must be from 1e-15 to 1e-2 (a relative residual of rho h^D = eta^D m)");
  PetscCall(SpamOptionText("-h_max", p->h_max, val, sizeof val));
  if (!(p->h_max >= 1.0 && p->h_max <= SPAM_H_MAX_MOST)) SPAM_BAD_INPUT("-h_max", val, "must be from 1 to %d (a factor of -h; the neighbour list's range is h_max h)", SPAM_H_MAX_MOST);
  PetscFunctionReturn(0);
}

/* The first choice the adaptive range does not take, or NULL. Its pair pass has the
 * pressure, Monaghan's viscosity and the energy equation's work; the tensor path's other
 * laws read gradients over one kernel range. */
static const char *UnsupportedLaw(const SpamSolidParams *s)
{
  if (s->density != SPAM_DENSITY_SUMMATION) return "-density continuity and chain-rule (the adaptive density is the summed one)";
  if (s->scheme == SPAM_GAS_FLOW) return "-gas_scheme flow";
  if (s->coords != SPAM_COORDS_R0) return "-coordinates R1 and R2";
  if (s->viscosity == SPAM_VISCOSITY_VON_NEUMANN) return "-viscosity vonneumann";
  if (s->shear_visc > 0.0 || s->bulk_visc > 0.0) return "-viscosity_shear and -viscosity_bulk";
  if (s->conductivity > 0.0) return "-conductivity";
  if (s->angmom != SPAM_ANGMOM_NONE) return "-angmom";
  if (s->closest_approach > 0.0) return "-closest_approach";
  return NULL;
}

/* Options whose estimates or files assume the one range h, refused when given. */
static PetscErrorCode CheckRunOptions(const SpamSolidParams *s)
{
  static const char *const fixed_only[][2] = {
    {"-grid_interval", "the grid fields interpolate with the one kernel range h"},
  };
  PetscBool has;
  char      val[128];

  PetscFunctionBeginUser;
  for (size_t k = 0; k < sizeof fixed_only / sizeof fixed_only[0]; k++) {
    PetscCall(PetscOptionsHasName(NULL, NULL, fixed_only[k][0], &has));
    if (!has) continue;
    PetscCall(PetscSNPrintf(val, sizeof val, "%s", fixed_only[k][0]));
    SPAM_BAD_INPUT("-smoothing_length", SpamSmoothingModeNames[s->smoothing], "does not take %s yet: %s", val, fixed_only[k][1]);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSmoothingCheck(const SpamCommonParams *c, const SpamParticles *p, const SpamSolidParams *s, PetscMPIInt size)
{
  const char  *law;
  const double range = s->h_max * c->h + c->skin;

  PetscFunctionBeginUser;
  if (p->model_set || s->material != SPAM_MATERIAL_GAS || s->smoothing == SPAM_SMOOTHING_FIXED) PetscFunctionReturn(0);
  if ((law = UnsupportedLaw(s))) SPAM_BAD_INPUT("-smoothing_length", SpamSmoothingModeNames[s->smoothing], "does not take %s yet: the adaptive pass has the pressure, Monaghan's viscosity and the energy equation only", law);
  (void)size; /* other ranks' particles are ghost slots within the list range h_max h + skin */
  /* -reproducible's canonical rows take periodic images as slots like any partner; the
   * half-list passes would need each image's share folded onto its source in every
   * iteration of the h solve. */
  if (c->periodic_ghosts && !c->reproducible) SPAM_BAD_INPUT("-smoothing_length", SpamSmoothingModeNames[s->smoothing], "does not take -periodic_images ghost yet (but does with -reproducible): the adaptive half-list passes take the periodic pairs by the minimum image");
  if (SpamWallsAny(&p->walls, p->dim)) SPAM_BAD_INPUT("-smoothing_length", SpamSmoothingModeNames[s->smoothing], "does not take mirror walls yet: their images are placed within the fixed range h");
  for (int d = 0; d < p->dim; d++)
    if (p->box.periodic[d] && p->box.len[d] < 2.0 * range) SPAM_BAD_INPUT("-smoothing_length", SpamSmoothingModeNames[s->smoothing], "needs every periodic edge at least twice the list range h_max h + skin = %g (edge %d is %g): the pairs take the minimum image", range, d, p->box.len[d]);
  PetscCall(CheckRunOptions(s));
  PetscFunctionReturn(0);
}
