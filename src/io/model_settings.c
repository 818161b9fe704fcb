/* The model's settings as one JSON object, stored with every snapshot (root attribute
 * "model"), so that a snapshot says which physics made it. One function reads SpamModel:
 * when the model changes, this is the one place to follow it. */
#include <spam/output.h>

/* Appends to buf at *used, never past len (snprintf's count is clipped). */
static void Put(char *buf, size_t len, size_t *used, const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(4, 5);
static void Put(char *buf, size_t len, size_t *used, const char *fmt, ...)
{
  va_list ap;
  int     k;

  if (*used >= len) return;
  va_start(ap, fmt);
  k = vsnprintf(buf + *used, len - *used, fmt, ap);
  va_end(ap);
  if (k > 0) *used = PetscMin(len, *used + (size_t)k);
}

/* The tensor path's choices (gas and elastic solid). Names come from the option tables. */
static void PutSolid(const SpamSolidParams *s, char *buf, size_t len, size_t *used)
{
  Put(buf, len, used, ", \"material\": \"%s\", \"density\": \"%s\", \"density_initial\": \"%s\", \"coordinates\": \"%s\", \"xsph_eps\": %.17g", SpamMaterialNames[s->material], SpamDensityModeNames[s->density], SpamDensityInitialNames[s->density_initial], SpamCoordsModeNames[s->coords], s->xsph_eps);
  Put(buf, len, used, ", \"rho_geometric\": %s, \"angmom\": \"%s\", \"angmom_per_body\": %s", s->rho_geometric ? "true" : "false", SpamAngmomModeNames[s->angmom], s->per_body ? "true" : "false");
  Put(buf, len, used, ", \"viscosity\": \"%s\", \"visc_alpha\": %.17g, \"visc_beta\": %.17g, \"shear_viscosity\": %.17g, \"bulk_viscosity\": %.17g, \"conductivity\": %.17g, \"closest_approach\": %.17g", SpamViscosityModeNames[s->viscosity], s->visc_alpha, s->visc_beta, s->shear_visc, s->bulk_visc, s->conductivity, s->closest_approach);
  if (s->material == SPAM_MATERIAL_GAS) Put(buf, len, used, ", \"gas_gamma\": %.17g, \"gas_e0\": %.17g", s->gamma, s->gas_e0);
  else Put(buf, len, used, ", \"lambda\": %.17g, \"eta\": %.17g, \"rho0\": %.17g", s->lambda, s->eta, s->rho0);
}

PetscErrorCode SpamModelSettingsJson(const SpamModel *m, char *buf, size_t len)
{
  size_t used = 0;

  PetscFunctionBeginUser;
  Put(buf, len, &used, "{\"name\": \"%s\", \"dim\": %d, \"mass\": %.17g, \"kernel\": \"lucy\", \"h\": %.17g", m->name, m->dim, m->mass, m->kernel.h);
  if (!strcmp(m->name, "isentrope")) Put(buf, len, &used, ", \"eos_gamma\": %.17g, \"eos_kappa\": %.17g", m->eos.gamma, m->eos.kappa);
  if (!strcmp(m->name, "springs")) Put(buf, len, &used, ", \"spring_k\": %.17g, \"spring_r0\": %.17g, \"bond_range\": %.17g", m->springs.k, m->springs.r0, m->springs.range);
  if (!strcmp(m->name, "gas") || !strcmp(m->name, "elastic")) PutSolid(&m->solid, buf, len, &used);
  Put(buf, len, &used, "}");
  PetscCheck(used < len, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the model settings need more than %zu bytes", len);
  PetscFunctionReturn(0);
}
