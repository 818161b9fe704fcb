/* The model's options, read for every scene that does not carry its own model: the
 * material, the Lame constants and every choice of the PRE study space (viscosities,
 * conduction, density, coordinates, angular momentum). The scene supplies the defaults. */
#include <spam/scene.h>
#include <spam/errors.h>
#include <float.h>

const char *const SpamDensityModeNames[]    = {"summation", "continuity", "chain-rule"};
const char *const SpamDensityInitialNames[] = {"ideal", "summed"};
const char *const SpamCoordsModeNames[]     = {"R0", "R1", "R2"};
const char *const SpamAngmomModeNames[]     = {"none", "gauss", "Ti", "Tij"};
const char *const SpamViscosityModeNames[]  = {"none", "monaghan", "vonneumann"};
const char *const SpamMaterialNames[]       = {"elastic", "gas", "isentrope"};
const char *const SpamGasSchemeNames[]      = {"plain", "flow"};
const char *const SpamBackgroundModeNames[] = {"none", "mean"};
const char *const SpamDiffusionFormNames[]  = {"gradient", "pair"};
const char *const SpamShiftWorkNames[]      = {"false", "stratified", "true"};

/* -shift_compression's value: stratified, or a boolean (alone: true). */
static PetscErrorCode ShiftWorkChoice(const char *val, SpamShiftWork *w)
{
  static const char *const on[] = {"", "true", "1", "yes", "on"}, *const off[] = {"false", "0", "no", "off"};
  char                     shown[100];

  PetscFunctionBeginUser;
  *w = SPAM_SHIFT_WORK_STRATIFIED;
  if (!strcmp(val, "stratified")) PetscFunctionReturn(0);
  for (size_t k = 0; k < sizeof on / sizeof *on; k++)
    if (!strcmp(val, on[k])) {
      *w = SPAM_SHIFT_WORK_ALL;
      PetscFunctionReturn(0);
    }
  for (size_t k = 0; k < sizeof off / sizeof *off; k++)
    if (!strcmp(val, off[k])) {
      *w = SPAM_SHIFT_WORK_OFF;
      PetscFunctionReturn(0);
    }
  SpamClip(val, shown, sizeof shown);
  SPAM_BAD_INPUT("-shift_compression", shown, "allowed: stratified, true (or alone), false");
}

/* Index of val in names, or a bad-input error listing them. */
static PetscErrorCode Choice(const char *opt, const char *val, const char *const *names, int n, int *k)
{
  char allowed[256] = "", shown[100];

  PetscFunctionBeginUser;
  for (*k = 0; *k < n; (*k)++)
    if (!strcmp(val, names[*k])) PetscFunctionReturn(0);
  for (int j = 0; j < n; j++) {
    PetscCall(PetscStrlcat(allowed, j ? ", " : "", sizeof allowed));
    PetscCall(PetscStrlcat(allowed, names[j], sizeof allowed));
  }
  SpamClip(val, shown, sizeof shown);
  SPAM_BAD_INPUT(opt, shown, "allowed: %s", allowed);
}

static PetscErrorCode Positive(const char *opt, double v, PetscBool zero_ok)
{
  char val[128];

  PetscFunctionBeginUser;
  PetscCall(SpamOptionText(opt, v, val, sizeof val));
  if (!isfinite(v) || v < 0.0 || (!zero_ok && v == 0.0)) SPAM_BAD_INPUT(opt, val, "must be a finite %s number", zero_ok ? "non-negative" : "positive");
  if (v != 0.0 && v < DBL_MIN) SPAM_BAD_INPUT(opt, val, "too small (subnormal): must be 0 or at least %g", DBL_MIN);
  PetscFunctionReturn(0);
}

/* The gas's scheme and its laws (gas_flow.c). A gas that has viscosity or conduction is a
 * fluid whose flow the plain equations get wrong where pressure dominates viscosity (the
 * pair force's error in the absolute pressure acts as a shear stiffness), so the flow
 * scheme is its default; an inviscid gas keeps the papers' plain equations, and so does a
 * scene that asks for them (solid.h: plain_default). The laws'
 * options are read only with the flow scheme, so that the plain scheme refuses them. */
static PetscErrorCode GasSchemeOptions(PetscOptionItems *PetscOptionsObject, PetscBool help, const char *mat, SpamSolidParams *p, char *scheme, size_t ls, char *bg, size_t lb, char *form, size_t lf)
{
  const PetscBool fluid = (PetscBool)(!strcmp(mat, "gas") && !p->plain_default && (p->shear_visc > 0.0 || p->bulk_visc > 0.0 || p->conductivity > 0.0));

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(scheme, fluid ? "flow" : "plain", ls));
  PetscCall(PetscStrncpy(bg, "mean", lb));
  PetscCall(PetscStrncpy(form, "pair", lf));
  if (p->shift_coef == 0.0) p->shift_coef = SPAM_SHIFT_COEF_DEFAULT;
  if (help || !strcmp(mat, "gas")) PetscCall(PetscOptionsString("-gas_scheme", "Gas pair scheme: plain (the papers' equations) or flow (background pressure out of the momentum equation, transport shifting); default flow for a gas with viscosity or conduction, else plain (and in the expansion and convection scenes)", "README", scheme, scheme, ls, NULL));
  if (help || !strcmp(scheme, "flow")) {
    PetscCall(PetscOptionsString("-background_pressure", "Flow scheme: pressure taken out of the momentum equation: mean (the particles' mean pressure, fitted along gravity where there is gravity) or none", "README", bg, bg, lb, NULL));
    PetscCall(PetscOptionsReal("-shift_coefficient", "Flow scheme: transport shifting coefficient C (shift velocity C c h times the particle-volume gradient; 0: off)", "README", p->shift_coef, &p->shift_coef, NULL));
    PetscCall(PetscOptionsString("-diffusion_form", "Flow scheme: viscosity and conduction as pair Laplacians in one pass (pair: damps particle-scale noise) or through the particles' gradients (gradient: the papers' two passes)", "README", form, form, lf, NULL));
    char sw[32] = "stratified";
    PetscCall(PetscOptionsString("-shift_compression", "Flow scheme, summed density: the background pressure's compression work follows the particles (v + dv), as the summed density does, not the fluid (v) alone: B / rho^2 times the summed density's rate from the shift, less its volume mean, is added to de/dt and booked. stratified: where B varies along gravity (a layer across walls) and no no-slip wall moves; true (or alone): every such run, walls moving refused; false: off", "README", sw, sw, sizeof sw, NULL));
    PetscCall(ShiftWorkChoice(sw, &p->shift_work));
    /* On by default where the pair form conducts (the convection cell's conduction state
     * read through moved particles fed the roll below onset: docs/gas-flow.md); the
     * default is what the option's checks below accept, so it never refuses a run. */
    p->heat_linear = (PetscBool)(!strcmp(form, "pair") && p->conductivity > 0.0 && (strcmp(bg, "none") || p->shift_coef > 0.0));
    PetscCall(PetscOptionsBool("-conduction_linear", "Flow scheme, pair form: conduction exact for a linear temperature on any arrangement (each side subtracts its corrected gradient's part; not conserved pair by pair: the book carries it); default true with -diffusion_form pair and -conductivity > 0, false turns it off", "README", p->heat_linear, &p->heat_linear, NULL));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSolidOptions(SpamSolidParams *p)
{
  char      dens[32], init[32], mean[32] = "arithmetic", coords[32], angm[32], scope[32] = "global", visc[32], mat[32], scheme[32], bg[32], form[32], smooth[32];
  int       k;
  PetscBool help;

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(dens, SpamDensityModeNames[p->density], sizeof dens));
  PetscCall(PetscStrncpy(init, SpamDensityInitialNames[p->density_initial], sizeof init));
  PetscCall(PetscStrncpy(coords, SpamCoordsModeNames[p->coords], sizeof coords));
  PetscCall(PetscStrncpy(angm, SpamAngmomModeNames[p->angmom], sizeof angm));
  PetscCall(PetscStrncpy(visc, SpamViscosityModeNames[p->viscosity], sizeof visc));
  PetscCall(PetscStrncpy(mat, SpamMaterialNames[p->material], sizeof mat));
  /* The options of one choice are read only when it is made (all of them with -help), so
   * that the end of set-up refuses, say, -xsph_eps without -coordinates R2. */
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Elastic solid (Hoover, Hoover & Merritt 2004)", "spam-ark");
  PetscCall(PetscOptionsString("-material", "Model: isentrope (P = kappa rho^gamma, state [x v]; default of expansion and file), gas (P = (gamma-1) rho e with the energy equation) or elastic (Hooke, stress in the state; default of the lattice scenes)", "README", mat, mat, sizeof mat, NULL));
  if (help || !strcmp(mat, "gas")) PetscCall(PetscOptionsReal("-gas_e0", "Gas: initial energy per unit mass of every particle", "README", p->gas_e0, &p->gas_e0, NULL));
  PetscCall(PetscOptionsReal("-viscosity_shear", "Newtonian shear viscosity eta_s (0: off)", "README", p->shear_visc, &p->shear_visc, NULL));
  PetscCall(PetscOptionsReal("-viscosity_bulk", "Newtonian bulk viscosity eta_b (0: off)", "README", p->bulk_visc, &p->bulk_visc, NULL));
  PetscCall(PetscOptionsReal("-conductivity", "Fourier heat conductivity kappa, Q = -kappa grad T (0: off)", "README", p->conductivity, &p->conductivity, NULL));
  if (help || !strcmp(mat, "gas") || p->conductivity != 0.0) PetscCall(PetscOptionsReal("-gas_gamma", "Gas: gamma of P = (gamma - 1) rho e (2 in 2D); also sets T = (gamma - 1) e (-material gas or -conductivity)", "README", p->gamma, &p->gamma, NULL));
  PetscCall(GasSchemeOptions(PetscOptionsObject, help, mat, p, scheme, sizeof scheme, bg, sizeof bg, form, sizeof form));
  PetscCall(SpamSmoothingOptions(PetscOptionsObject, help, mat, p, smooth, sizeof smooth));
  if (help || !strcmp(mat, "elastic")) {
    PetscCall(PetscOptionsReal("-solid_lambda", "Lame constant lambda (default sqrt(3)/4: springs k = 1; -material elastic)", "README", p->lambda, &p->lambda, NULL));
    PetscCall(PetscOptionsReal("-solid_eta", "Lame constant eta, the shear modulus (default sqrt(3)/4; -material elastic)", "README", p->eta, &p->eta, NULL));
  }
  PetscCall(PetscOptionsString("-density", "Density: summation, continuity or chain-rule (continuity with dr/dt)", "README", dens, dens, sizeof dens, NULL));
  if (help || strcmp(dens, "summation")) PetscCall(PetscOptionsString("-density_initial", "Initial continuity density: ideal (sqrt(4/3) on the unit lattice) or summed", "README", init, init, sizeof init, NULL));
  PetscCall(PetscOptionsString("-density_mean", "Pair density rho_ij of gradients and R2: arithmetic or geometric", "README", mean, mean, sizeof mean, NULL));
  PetscCall(PetscOptionsString("-coordinates", "Coordinate update: R0 (v), R1 (<v>) or R2 (Monaghan's XSPH)", "README", coords, coords, sizeof coords, NULL));
  if (help || !strcmp(coords, "R2")) PetscCall(PetscOptionsReal("-xsph_eps", "Epsilon of R2 (PRE: 1; Monaghan: 0.5)", "README", p->xsph_eps, &p->xsph_eps, NULL));
  PetscCall(PetscOptionsString("-angmom", "Angular momentum: none, gauss (Gauss's principle), Ti or Tij (torque scaling)", "README", angm, angm, sizeof angm, NULL));
  if (help || !strcmp(angm, "Ti") || !strcmp(angm, "Tij")) PetscCall(PetscOptionsString("-angmom_scope", "Torque scaling (Ti, Tij) over: global or body (each connected body)", "README", scope, scope, sizeof scope, NULL));
  PetscCall(PetscOptionsString("-viscosity", "Artificial viscosity: none, monaghan (pair Pi_ij) or vonneumann (particle q_i)", "README", visc, visc, sizeof visc, NULL));
  if (help || strcmp(visc, "none")) {
    PetscCall(PetscOptionsReal("-viscosity_alpha", "Linear coefficient alpha (alpha c h)", "README", p->visc_alpha, &p->visc_alpha, NULL));
    PetscCall(PetscOptionsReal("-viscosity_beta", "Quadratic coefficient beta (beta h^2)", "README", p->visc_beta, &p->visc_beta, NULL));
  }
  PetscCall(PetscOptionsReal("-closest_approach", "Reflect the radial relative velocity of approaching pairs nearer than this, after each step (0: off; PRE Sec. IV)", "README", p->closest_approach, &p->closest_approach, NULL));
  PetscOptionsEnd();
  PetscCall(Choice("-material", mat, SpamMaterialNames, 3, &k));
  p->material = (SpamMaterial)k;
  PetscCall(Positive("-gas_e0", p->gas_e0, PETSC_TRUE));
  PetscCall(Positive("-viscosity_shear", p->shear_visc, PETSC_TRUE));
  PetscCall(Positive("-viscosity_bulk", p->bulk_visc, PETSC_TRUE));
  PetscCall(Positive("-conductivity", p->conductivity, PETSC_TRUE));
  {
    char val[128];
    PetscCall(SpamOptionText("-gas_gamma", p->gamma, val, sizeof val));
    if (!(p->gamma > 1.0) || !isfinite(p->gamma)) SPAM_BAD_INPUT("-gas_gamma", val, "must be greater than 1");
  }
  PetscCall(Positive("-viscosity_alpha", p->visc_alpha, PETSC_TRUE));
  PetscCall(Positive("-viscosity_beta", p->visc_beta, PETSC_TRUE));
  PetscCall(Positive("-closest_approach", p->closest_approach, PETSC_TRUE));
  PetscCall(Choice("-gas_scheme", scheme, SpamGasSchemeNames, 2, &k));
  p->scheme = (SpamGasScheme)k;
  PetscCall(Choice("-background_pressure", bg, SpamBackgroundModeNames, 2, &k));
  p->background = (SpamBackgroundMode)k;
  PetscCall(Positive("-shift_coefficient", p->shift_coef, PETSC_TRUE));
  if (p->shift_coef > 10.0) {
    char val[128];
    PetscCall(SpamOptionText("-shift_coefficient", p->shift_coef, val, sizeof val));
    SPAM_BAD_INPUT("-shift_coefficient", val, "allowed: 0 <= C <= 10 (the shift is a diffusion of coefficient C c h: beyond that it outruns sound)");
  }
  PetscCall(Choice("-diffusion_form", form, SpamDiffusionFormNames, 2, &k));
  p->diffusion = (SpamDiffusionForm)k;
  PetscCall(SpamSmoothingValidate(smooth, p));
  if (p->heat_linear && p->scheme == SPAM_GAS_FLOW && p->material == SPAM_MATERIAL_GAS) {
    if (p->diffusion != SPAM_DIFFUSION_PAIR || !(p->conductivity > 0.0)) SPAM_BAD_INPUT("-conduction_linear", "true", "corrects the pair form's conduction: it needs -diffusion_form pair and -conductivity > 0");
    if (p->smoothing != SPAM_SMOOTHING_FIXED) SPAM_BAD_INPUT("-conduction_linear", "true", "is written for one smoothing length (the adaptive path has no pair form)");
    if (p->background == SPAM_BACKGROUND_NONE && !(p->shift_coef > 0.0)) SPAM_BAD_INPUT("-conduction_linear", "true", "is booked with the flow scheme's laws: it needs -background_pressure mean or -shift_coefficient > 0");
  }
  if (p->scheme == SPAM_GAS_PLAIN || p->material != SPAM_MATERIAL_GAS) { /* the flow scheme's laws are off in the plain scheme */
    p->background = SPAM_BACKGROUND_NONE;
    p->shift_coef = 0.0;
    p->diffusion  = SPAM_DIFFUSION_GRADIENT;
    p->heat_linear = PETSC_FALSE;
    p->shift_work  = SPAM_SHIFT_WORK_OFF;
  }
  PetscCall(Choice("-viscosity", visc, SpamViscosityModeNames, 3, &k));
  p->viscosity = (SpamViscosityMode)k;
  PetscCall(Positive("-solid_lambda", p->lambda, PETSC_TRUE));
  PetscCall(Positive("-solid_eta", p->eta, PETSC_FALSE));
  PetscCall(Positive("-xsph_eps", p->xsph_eps, PETSC_TRUE));
  PetscCall(Choice("-density", dens, SpamDensityModeNames, 3, &k));
  p->density = (SpamDensityMode)k;
  if (p->shift_work == SPAM_SHIFT_WORK_ALL && p->scheme == SPAM_GAS_FLOW && p->material == SPAM_MATERIAL_GAS) { /* the default applies only where it can */
    if (p->background == SPAM_BACKGROUND_NONE || !(p->shift_coef > 0.0)) SPAM_BAD_INPUT("-shift_compression", "true", "is the background pressure's work on the shift's compression: it needs -background_pressure mean and -shift_coefficient > 0");
    if (p->density != SPAM_DENSITY_SUMMATION) SPAM_BAD_INPUT("-shift_compression", "true", "follows the summed density: it needs -density summation (a continuity density does not see the shift)");
    if (p->smoothing == SPAM_SMOOTHING_ADAPTIVE) SPAM_BAD_INPUT("-shift_compression", "true", "is written for one smoothing length (the adaptive path's walks do not carry it)");
  }
  PetscCall(Choice("-density_initial", init, SpamDensityInitialNames, 2, &k));
  p->density_initial = (SpamDensityInitial)k;
  {
    static const char *const means[] = {"arithmetic", "geometric"};
    PetscCall(Choice("-density_mean", mean, means, 2, &k));
    p->rho_geometric = (PetscBool)(k == 1);
  }
  PetscCall(Choice("-coordinates", coords, SpamCoordsModeNames, 3, &k));
  p->coords = (SpamCoordsMode)k;
  PetscCall(Choice("-angmom", angm, SpamAngmomModeNames, 4, &k));
  p->angmom = (SpamAngmomMode)k;
  {
    static const char *const scopes[] = {"global", "body"};
    PetscCall(Choice("-angmom_scope", scope, scopes, 2, &k));
    p->per_body = (PetscBool)(k == 1);
  }
  PetscFunctionReturn(0);
}
