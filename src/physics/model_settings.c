/* The model's settings as (key, value) pairs for the outputs. */
#include <spam/model.h>

static void Num(SpamSetting *s, int *n, const char *key, double v)
{
  if (*n < SPAM_MAX_SETTINGS) s[(*n)++] = (SpamSetting){key, NULL, v};
}

static void Str(SpamSetting *s, int *n, const char *key, const char *v)
{
  if (*n < SPAM_MAX_SETTINGS) s[(*n)++] = (SpamSetting){key, v, 0.0};
}

/* The tensor path's choices (gas or elastic). */
static void TensorSettings(const SpamSolidParams *p, SpamSetting *s, int *n)
{
  if (p->material == SPAM_MATERIAL_GAS) {
    Num(s, n, "gas_gamma", p->gamma);
    Str(s, n, "gas_scheme", SpamGasSchemeNames[p->scheme]);
    if (p->scheme == SPAM_GAS_FLOW) {
      Str(s, n, "background_pressure", SpamBackgroundModeNames[p->background]);
      Num(s, n, "shift_coefficient", p->shift_coef);
      Str(s, n, "diffusion_form", SpamDiffusionFormNames[p->diffusion]);
      Str(s, n, "conduction_linear", p->heat_linear ? "true" : "false");
      Str(s, n, "shift_compression", SpamShiftWorkNames[p->shift_work]);
    }
  } else {
    Num(s, n, "solid_lambda", p->lambda);
    Num(s, n, "solid_eta", p->eta);
  }
  Str(s, n, "density", SpamDensityModeNames[p->density]);
  Str(s, n, "density_initial", SpamDensityInitialNames[p->density_initial]);
  Str(s, n, "density_mean", p->rho_geometric ? "geometric" : "arithmetic");
  Str(s, n, "coordinates", SpamCoordsModeNames[p->coords]);
  Num(s, n, "xsph_eps", p->xsph_eps);
  Str(s, n, "angmom", SpamAngmomModeNames[p->angmom]);
  Str(s, n, "angmom_scope", p->per_body ? "body" : "global");
  Str(s, n, "viscosity", SpamViscosityModeNames[p->viscosity]);
  Num(s, n, "viscosity_alpha", p->visc_alpha);
  Num(s, n, "viscosity_beta", p->visc_beta);
  Num(s, n, "viscosity_shear", p->shear_visc);
  Num(s, n, "viscosity_bulk", p->bulk_visc);
  Num(s, n, "conductivity", p->conductivity);
  Num(s, n, "closest_approach", p->closest_approach);
  if (p->smoothing != SPAM_SMOOTHING_FIXED) { /* a fixed range's outputs keep their keys */
    Str(s, n, "smoothing_length", SpamSmoothingModeNames[p->smoothing]);
    Num(s, n, "h_eta", p->h_eta);
    Num(s, n, "h_min", p->h_min);
    Num(s, n, "h_max", p->h_max);
    if (p->h_tol != SPAM_H_TOL_DEFAULT) Num(s, n, "h_tol", p->h_tol); /* the default's outputs keep their keys */
  }
}

int SpamModelSettings(const SpamModel *m, SpamSetting *s)
{
  static const char *const axes[3] = {"gravity_x", "gravity_y", "gravity_z"};
  int                      n       = 0;

  Str(s, &n, "model", m->name);
  if (!strcmp(m->name, "springs")) {
    Num(s, &n, "spring_k", m->springs.k);
    Num(s, &n, "spring_r0", m->springs.r0);
    return n;
  }
  Str(s, &n, "kernel", m->kernel.name ? m->kernel.name : "lucy");
  for (int d = 0; d < m->dim; d++) Num(s, &n, axes[d], m->gravity[d]);
  if (m->tensor) TensorSettings(&m->solid, s, &n);
  else {
    Num(s, &n, "eos_gamma", m->eos.gamma);
    Num(s, &n, "eos_kappa", m->eos.kappa);
  }
  return n;
}
