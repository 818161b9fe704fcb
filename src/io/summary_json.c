/* summary.json: one JSON object with the run's settings, statistics and conservation. */
#include <spam/run.h>
#include <spam/physics.h>
#include <sys/resource.h>
#include <spam/version.h>

static const char *StatusName(SpamStatus s)
{
  switch (s) {
  case SPAM_STATUS_OK: return "ok";
  case SPAM_STATUS_MAX_STEPS: return "max_steps";
  default: return "unstable";
  }
}

/* JSON has no NaN or infinity: write null. */
static void Num(FILE *f, const char *key, double v)
{
  if (isfinite(v)) fprintf(f, "  \"%s\": %.10g,\n", key, v);
  else fprintf(f, "  \"%s\": null,\n", key);
}

static void Vec3(FILE *f, const char *key, const double *v)
{
  fprintf(f, "  \"%s\": [%.10g, %.10g, %.10g],\n", key, v[0], v[1], v[2]);
}

static void Str(FILE *f, const char *key, const char *v)
{
  fprintf(f, "  \"%s\": \"", key);
  for (const char *c = v; *c; c++) {
    if (*c == '"' || *c == '\\') fputc('\\', f);
    if ((unsigned char)*c >= 0x20) fputc(*c, f);
  }
  fprintf(f, "\",\n");
}

/* The model and the settings that define it: a study script reads them to label runs. */
static void ModelFields(FILE *f, const SpamModel *m)
{
  const SpamSolidParams *s = &m->solid;

  Str(f, "model", m->name);
  if (!strcmp(m->name, "isentrope")) {
    Num(f, "eos_gamma", m->eos.gamma);
    Num(f, "eos_kappa", m->eos.kappa);
  } else if (!strcmp(m->name, "springs")) {
    Num(f, "spring_k", m->springs.k);
    Num(f, "spring_r0", m->springs.r0);
  } else {
    if (s->material == SPAM_MATERIAL_GAS) Num(f, "gas_gamma", s->gamma);
    else {
      Num(f, "solid_lambda", s->lambda);
      Num(f, "solid_eta", s->eta);
    }
    Str(f, "density", SpamDensityModeNames[s->density]);
    Str(f, "density_initial", SpamDensityInitialNames[s->density_initial]);
    Str(f, "density_mean", s->rho_geometric ? "geometric" : "arithmetic");
    Str(f, "coordinates", SpamCoordsModeNames[s->coords]);
    Num(f, "xsph_eps", s->xsph_eps);
    Str(f, "angmom", SpamAngmomModeNames[s->angmom]);
    Str(f, "angmom_scope", s->per_body ? "body" : "global");
    Str(f, "viscosity", SpamViscosityModeNames[s->viscosity]);
    Num(f, "viscosity_alpha", s->visc_alpha);
    Num(f, "viscosity_beta", s->visc_beta);
    Num(f, "viscosity_shear", s->shear_visc);
    Num(f, "viscosity_bulk", s->bulk_visc);
    Num(f, "conductivity", s->conductivity);
    Num(f, "closest_approach", s->closest_approach);
  }
}

PetscErrorCode SpamSummaryWrite(const SpamOutput *out, const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r)
{
  const SpamDiagnostics *a = &r->first, *b = &r->last;
  const double           norm = (double)sim->nglobal * log(sim->scene.volume_ratio > 0 ? sim->scene.volume_ratio : 1.0);
  char                   path[PETSC_MAX_PATH_LEN];
  struct rusage          ru;
  FILE                  *f;

  PetscFunctionBeginUser;
  getrusage(RUSAGE_SELF, &ru);
  PetscCall(SpamOutputPath(out, "summary.json", path, sizeof path));
  PetscCall(SpamFileBegin(path, &f));
  fprintf(f, "{\n");
  Str(f, "status", StatusName(r->status));
  Str(f, "reason", r->reason);
  Str(f, "scene", sim->scene.name);
  fprintf(f, "  \"dim\": %d,\n  \"n_particles\": %" PetscInt_FMT ",\n", sim->model.dim, sim->nglobal);
  Num(f, "h", sim->model.kernel.h);
  Num(f, "mass", sim->model.mass);
  ModelFields(f, &sim->model);
  Vec3(f, "box_lo", sim->box.lo);
  Vec3(f, "box_len", sim->box.len);
  Str(f, "method", r->method);
  Str(f, "adapt", r->adapt);
  Num(f, "fixed_step", r->fixed_dt);
  Num(f, "step_cfl", o->cfl);
  Num(f, "step_force", o->force);
  Num(f, "rtol", o->rtol);
  Num(f, "atol", o->atol);
  Num(f, "t_end", o->t_end);
  Num(f, "t_final", r->t);
  fprintf(f, "  \"steps\": %ld,\n  \"rejected_steps\": %ld,\n  \"step_attempts\": %ld,\n  \"rhs_evals\": %ld,\n  \"bound_limited_steps\": %ld,\n", r->steps, r->rejected, r->attempts, r->rhs_evals, r->limited);
  fprintf(f, "  \"post_step_jumps\": %ld,\n  \"steps_with_jumps\": %ld,\n", r->jumps, r->jump_steps);
  /* Gauss's constraint: the largest acceleration it added (0 without it). */
  fprintf(f, "  \"gauss_accel_max\": %.10g,\n", sim->ps ? sim->ps->gauss_accel_max : 0.0);
  fprintf(f, "  \"neighbour_builds\": %ld,\n  \"neighbour_list_grows\": %ld,\n", sim->nl.builds, sim->nl.grows);
  Num(f, "wall_time_s", r->wall);
  Num(f, "rhs_time_s", sim->stats.rhs_time);
  Num(f, "rhs_time_share", r->wall > 0 ? sim->stats.rhs_time / r->wall : 0.0);
  Num(f, "pair_interactions_per_s", sim->stats.rhs_time > 0 ? sim->stats.pair_visits / sim->stats.rhs_time : 0.0);
  Num(f, "ns_per_pair", sim->stats.pair_visits > 0 ? 1e9 * sim->stats.rhs_time / sim->stats.pair_visits : 0.0);
  fprintf(f, "  \"peak_rss_bytes\": %ld,\n", (long)ru.ru_maxrss * 1024L);
  Num(f, "volume_ratio", sim->scene.volume_ratio);
  Num(f, "sound_traversal_time", sim->scene.sound_traversal_time);
  Num(f, "energy_initial", a->total);
  Num(f, "energy_final", b->total);
  Num(f, "energy_rel_drift_final", fabs(b->total - a->total) / PetscMax(fabs(a->total), 1e-300));
  Num(f, "energy_rel_drift_max", r->energy_drift_max);
  Num(f, "kinetic_final", b->kinetic);
  Num(f, "internal_final", b->internal);
  Vec3(f, "momentum_initial", a->p);
  Vec3(f, "momentum_final", b->p);
  Num(f, "momentum_scale", r->momentum_scale);
  Num(f, "momentum_rel_drift_max", r->momentum_drift_max);
  Vec3(f, "angular_momentum_initial", a->l);
  Vec3(f, "angular_momentum_final", b->l);
  Num(f, "angular_momentum_scale", r->angmom_scale);
  Num(f, "angular_momentum_rel_drift_max", r->angmom_drift_max);
  Num(f, "entropy_sum_initial", a->entropy_sum);
  Num(f, "entropy_sum_final", b->entropy_sum);
  Num(f, "entropy_grid_initial", a->entropy_grid);
  Num(f, "entropy_grid_final", b->entropy_grid);
  Num(f, "dS_sum_ratio_final", norm > 0 ? (b->entropy_sum - a->entropy_sum) / norm : NAN);
  Num(f, "dS_grid_ratio_final", norm > 0 && o->diag.grid_spacing > 0 ? (b->entropy_grid - a->entropy_grid) / norm : NAN);
  Str(f, "output_dir", out->dir);
  fprintf(f, "  \"spam_ark_version\": \"%s\"\n}\n", SPAM_VERSION);
  PetscCall(SpamFileCommit(path, f));
  PetscFunctionReturn(0);
}
