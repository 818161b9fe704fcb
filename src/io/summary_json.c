/* summary.json: one JSON object with the run's settings, statistics and conservation. */
#include <spam/output_run.h>
#include <spam/physics.h>
#include <sys/resource.h>
#include <spam/version.h>

static const char *StatusName(SpamStatus s)
{
  switch (s) {
  case SPAM_STATUS_OK: return "ok";
  case SPAM_STATUS_MAX_STEPS: return "max_steps";
  case SPAM_STATUS_UNSTABLE: return "unstable";
  case SPAM_STATUS_INTERRUPTED: return "interrupted";
  default: return "failed";
  }
}

/* The summary being written, and the keys written as null (listed at the end). */
typedef struct {
  SpamFile f;
  char     nulls[2048];
} Summary;

static void NoteNull(Summary *s, const char *key)
{
  size_t n = strlen(s->nulls);
  (void)snprintf(s->nulls + n, sizeof s->nulls - n, "%s\"%s\"", n ? ", " : "", key);
}

/* Every number goes through here: JSON has no NaN or infinity, so those are null. */
static void Value(Summary *s, const char *key, double v)
{
  if (isfinite(v)) SpamFilePrintf(&s->f, "%.10g", v);
  else {
    SpamFilePrintf(&s->f, "null");
    NoteNull(s, key);
  }
}

static void Num(Summary *s, const char *key, double v)
{
  SpamFilePrintf(&s->f, "  \"%s\": ", key);
  Value(s, key, v);
  SpamFilePrintf(&s->f, ",\n");
}

static void Vec3(Summary *s, const char *key, const double *v)
{
  PetscBool noted = PETSC_FALSE;

  SpamFilePrintf(&s->f, "  \"%s\": [", key);
  for (int k = 0; k < 3; k++) {
    if (!isfinite(v[k]) && !noted) {
      NoteNull(s, key);
      noted = PETSC_TRUE;
    }
    if (isfinite(v[k])) SpamFilePrintf(&s->f, "%s%.10g", k ? ", " : "", v[k]);
    else SpamFilePrintf(&s->f, "%snull", k ? ", " : "");
  }
  SpamFilePrintf(&s->f, "],\n");
}

static void Int(Summary *s, const char *key, long v)
{
  SpamFilePrintf(&s->f, "  \"%s\": %ld,\n", key, v);
}

static void Str(Summary *s, const char *key, const char *v)
{
  SpamFilePrintf(&s->f, "  \"%s\": ", key);
  SpamFileJsonString(&s->f, v);
  SpamFilePrintf(&s->f, ",\n");
}

/* The model and the settings that define it: a study script reads them to label runs. */
/* The model's settings, as the model states them. */
static void ModelFields(Summary *f, const SpamModel *m)
{
  SpamSetting set[SPAM_MAX_SETTINGS];
  const int   n = SpamModelSettings(m, set);

  for (int k = 0; k < n; k++) {
    if (set[k].str) Str(f, set[k].key, set[k].str);
    else Num(f, set[k].key, set[k].num);
  }
}

/* Where the run stopped and why; the time reached and, after a signal, which one. */
static void Outcome(Summary *f, const SpamRunOptions *o, const SpamRunResult *r)
{
  Str(f, "status", StatusName(r->status));
  Str(f, "reason", r->reason);
  Num(f, "t_end", o->t_end);
  Num(f, "t_final", r->t);
  if (r->status == SPAM_STATUS_INTERRUPTED) Int(f, "signal", r->signal);
}

/* The rule of one list update and one placement of the ghost positions (on several
 * ranks the halo's exchange of positions) per evaluation, over this process's evaluations. */
static void RhsPasses(Summary *f, const SpamRhsStats *s)
{
  const double n = s->counted ? (double)s->counted : NAN;

  Int(f, "rhs_evals_process", s->counted);
  Int(f, "rhs_evals_diffusion", s->rhs_evals_diffusion); /* of those, the diffusion part's alone (arkode_imex) */
  Num(f, "list_updates_per_rhs", (double)s->list_updates / n);
  Num(f, "ghost_placements_per_rhs", (double)s->ghost_placements / n);
}

static void Counts(Summary *f, const SpamSim *sim, const SpamRunResult *r)
{
  Int(f, "steps", r->steps);
  Int(f, "rejected_steps", r->rejected);
  Int(f, "step_attempts", r->attempts);
  Int(f, "rhs_evals", r->rhs_evals);
  Int(f, "bound_limited_steps", r->limited);
  Int(f, "post_step_jumps", r->jumps);
  Int(f, "steps_with_jumps", r->jump_steps);
  /* How the output times were reached (time_loop.c, output_mode.c). */
  Str(f, "output_mode", r->output_mode);
  Str(f, "output_mode_reason", r->output_mode_reason);
  Int(f, "interpolated_rows", r->interpolated_rows);
  Int(f, "interpolation_rhs_evals", r->interpolation_rhs_evals);
  /* The run's whole cost in evaluations: the method's, the interpolant's and a restart's. */
  Int(f, "rhs_evals_total", r->rhs_evals + r->interpolation_rhs_evals + r->restart_rhs_evals);
  /* Gauss's constraint: the largest acceleration it added (0 without it). */
  Num(f, "gauss_accel_max", sim->ps ? sim->ps->gauss_accel_max : 0.0);
  Num(f, "gauss_momentum_residual_max", sim->ps ? sim->ps->gauss_momentum_residual : 0.0);
  Int(f, "neighbour_builds", sim->pair.nl.builds);
  Int(f, "neighbour_list_grows", sim->pair.nl.grows);
  if (sim->model.tensor && sim->model.solid.smoothing == SPAM_SMOOTHING_EVOLVED) { /* Omega <= 0 took 1 (smoothing_adaptive.c) */
    Int(f, "omega_floored", sim->run.stats.omega_floored);
    Int(f, "omega_floored_max_per_rhs", sim->run.stats.omega_floored_max);
  }
  RhsPasses(f, &sim->run.stats);
}

/* The checkpoints this run wrote, and the one it continued (null when new). */
static void Checkpoints(Summary *f, const SpamRunResult *r)
{
  Int(f, "checkpoints_written", r->checkpoints);
  Num(f, "checkpoint_bytes", r->checkpoint_bytes);
  Num(f, "checkpoint_write_s", r->checkpoint_write);
  if (!r->restart_from[0]) {
    SpamFilePrintf(&f->f, "  \"restart_from\": null,\n");
    return;
  }
  Str(f, "restart_from", r->restart_from);
  Num(f, "restart_t", r->restart_t);
  Int(f, "restart_step", r->restart_step);
  Str(f, "restart", r->restart_exact ? "bitwise" : "approximate");
  Str(f, "restart_why_approximate", r->restart_exact ? "" : r->restart_why);
  Int(f, "restart_rhs_evals", r->restart_rhs_evals);
}

static void Performance(Summary *f, const SpamRunCounts *run, const SpamRunResult *r)
{
  struct rusage ru;

  getrusage(RUSAGE_SELF, &ru);
  Num(f, "wall_time_s", r->wall);
  Num(f, "rhs_time_s", run->stats.rhs_time);
  Num(f, "rhs_time_share", r->wall > 0 ? run->stats.rhs_time / r->wall : 0.0);
  Num(f, "pair_interactions_per_s", run->stats.rhs_time > 0 ? run->stats.pair_visits / run->stats.rhs_time : 0.0);
  Num(f, "ns_per_pair", run->stats.pair_visits > 0 ? 1e9 * run->stats.rhs_time / run->stats.pair_visits : 0.0);
  Int(f, "peak_rss_bytes", (long)ru.ru_maxrss * 1024L);
}

/* Drifts relative to the initial energy (and the momentum scales built on it) mean
 * nothing when that energy is zero, a body at rest and unstrained: null then, and the
 * drift over the energy scale (time_loop.c) says what happened instead. */
static PetscBool ZeroEnergy(const SpamRunResult *r)
{
  return (PetscBool)(!(fabs(r->first.total) > 1e-12 * r->energy_scale));
}

/* Why the total angular momentum is not a conserved quantity of this run, or NULL. In a
 * periodic box the pairs across a boundary exert torque about the centre and a particle that
 * wraps jumps in L (the gresho scene loses a few percent of L_z so); a wall's images push
 * the particles without books of the torque (momentum has books, diagnostics_walls.c). A
 * drift of L would then measure the box, not the method. */
static const char *AngmomNotConserved(const SpamSim *sim)
{
  for (int d = 0; d < sim->model.dim; d++)
    if (sim->geo.box.periodic[d]) return "not conserved: periodic box";
  for (int s = 0; s < 2 * sim->model.dim; s++)
    if (SpamWallOn(&sim->geo.walls, s)) return "not conserved: walls";
  return NULL;
}

static void Drifts(Summary *f, const SpamRunResult *r, const char *angmom_not_conserved)
{
  const SpamDiagnostics *a = &r->first, *b = &r->last;
  const double           zero = ZeroEnergy(r) ? NAN : 1.0; /* NaN: written as null */

  Num(f, "energy_rel_drift_final", zero * fabs(b->total - a->total) / PetscMax(fabs(a->total), 1e-300));
  Num(f, "energy_rel_drift_max", zero * r->energy_drift_max);
  Num(f, "energy_scale", r->energy_scale);
  Num(f, "energy_drift_over_scale_final", r->energy_scale > 0 ? fabs(b->total - a->total) / r->energy_scale : NAN);
  Vec3(f, "momentum_initial", a->p);
  Vec3(f, "momentum_final", b->p);
  Num(f, "momentum_scale", zero * r->momentum_scale);
  Num(f, "momentum_rel_drift_max", zero * r->momentum_drift_max);
  Vec3(f, "angular_momentum_initial", a->l);
  Vec3(f, "angular_momentum_final", b->l);
  Num(f, "angular_momentum_scale", zero * r->angmom_scale);
  /* Null where L is not conserved, with the reason; the same measure as a change. */
  Num(f, "angular_momentum_rel_drift_max", angmom_not_conserved ? NAN : zero * r->angmom_drift_max);
  Num(f, "angular_momentum_rel_change_max", zero * r->angmom_drift_max);
  SpamFilePrintf(&f->f, "  \"angular_momentum_conserved\": %s,\n", angmom_not_conserved ? "false" : "true");
  if (angmom_not_conserved) Str(f, "angular_momentum_not_conserved", angmom_not_conserved);
}

static void Conservation(Summary *f, const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r)
{
  const SpamDiagnostics *a = &r->first, *b = &r->last;
  const double           norm = (double)sim->p.nglobal * log(sim->out.scene.volume_ratio > 0 ? sim->out.scene.volume_ratio : 1.0);

  Num(f, "volume_ratio", sim->out.scene.volume_ratio);
  Num(f, "sound_traversal_time", sim->out.scene.sound_traversal_time);
  Num(f, "energy_initial", a->total);
  Num(f, "energy_final", b->total);
  Num(f, "kinetic_final", b->kinetic);
  Num(f, "internal_final", b->internal);
  Drifts(f, r, AngmomNotConserved(sim));
  Num(f, "entropy_sum_initial", a->entropy_sum);
  Num(f, "entropy_sum_final", b->entropy_sum);
  Num(f, "entropy_grid_initial", a->entropy_grid);
  Num(f, "entropy_grid_final", b->entropy_grid);
  Num(f, "dS_sum_ratio_final", norm > 0 ? (b->entropy_sum - a->entropy_sum) / norm : NAN);
  Num(f, "dS_grid_ratio_final", norm > 0 && o->diag.grid_spacing > 0 ? (b->entropy_grid - a->entropy_grid) / norm : NAN);
}

/* Why numbers are null, in words, for the reader who meets one. */
static void NullNote(Summary *f, const SpamRunResult *r)
{
  char note[768];

  SpamFilePrintf(&f->f, "  \"null_fields\": [%s],\n", f->nulls);
  if (!f->nulls[0]) return;
  (void)snprintf(note, sizeof note, "JSON has no NaN or infinity: null means not defined for this run (no entropy estimate or volume change, a quantity this model lacks%s%s) or not finite (the state blew up)",
                 ZeroEnergy(r) ? "; drifts relative to an initial energy of zero, see energy_drift_over_scale_final" : "",
                 strstr(f->nulls, "\"angular_momentum_rel_drift_max\"") ? "; the drift of a quantity this run does not conserve, see angular_momentum_not_conserved" : "");
  Str(f, "nulls", note);
}

/* The mirror walls, one key per face with a wall: wall_F (noslip or freeslip),
 * wall_F_velocity, wall_F_temperature (a number, or "adiabatic"). */
static void Walls(Summary *f, const SpamSim *sim)
{
  char key[48];

  for (int s = 0; s < 2 * sim->model.dim; s++) {
    if (!SpamWallOn(&sim->geo.walls, s)) continue;
    (void)snprintf(key, sizeof key, "wall_%s", SpamFaceNames[s]);
    Str(f, key, SpamWallSlipNames[sim->geo.walls.slip[s]]);
    (void)snprintf(key, sizeof key, "wall_%s_velocity", SpamFaceNames[s]);
    Vec3(f, key, sim->geo.walls.velocity[s]);
    (void)snprintf(key, sizeof key, "wall_%s_temperature", SpamFaceNames[s]);
    if (sim->geo.walls.isothermal[s]) Num(f, key, sim->geo.walls.temperature[s]);
    else Str(f, key, "adiabatic");
  }
}

/* The ranks and what moved between them. */
static void Ranks(Summary *f, const SpamRunResult *r)
{
  Int(f, "ranks", r->ranks);
  Int(f, "migrations", r->migrations);
  Num(f, "particles_migrated", r->migrated);
  Num(f, "rank_imbalance_final", r->imbalance);
  Num(f, "halo_ghosts_max_final", r->halo_max);
}

/* summary.json is listed in the manifest; the caller rewrites the manifest. */
PetscErrorCode SpamSummaryWrite(SpamOutput *out, const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r)
{
  char    path[PETSC_MAX_PATH_LEN];
  Summary f;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(out, "summary.json", path, sizeof path));
  PetscCall(PetscMemzero(&f, sizeof f));
  PetscCall(SpamFileBegin(path, &f.f));
  SpamFilePrintf(&f.f, "{\n");
  Outcome(&f, o, r);
  Str(&f, "scene", sim->out.scene.name);
  Int(&f, "dim", sim->model.dim);
  Int(&f, "n_particles", (long)sim->p.nglobal);
  Num(&f, "h", sim->model.kernel.h);
  Num(&f, "mass", sim->model.mass);
  ModelFields(&f, &sim->model);
  Vec3(&f, "box_lo", sim->geo.box.lo);
  Vec3(&f, "box_len", sim->geo.box.len);
  Walls(&f, sim);
  Str(&f, "method", r->method);
  Str(&f, "adapt", r->adapt);
  Num(&f, "fixed_step", r->fixed_dt);
  Num(&f, "step_cfl", o->cfl);
  Num(&f, "step_force", o->force);
  Num(&f, "rtol", o->rtol);
  Num(&f, "atol", o->atol);
  Counts(&f, sim, r);
  Ranks(&f, r);
  Checkpoints(&f, r);
  Performance(&f, &sim->run, r);
  Conservation(&f, sim, o, r);
  Str(&f, "output_dir", out->dir);
  NullNote(&f, r);
  SpamFilePrintf(&f.f, "  \"spam_ark_version\": \"%s\"\n}\n", SPAM_VERSION);
  PetscCall(SpamFileCommit(&f.f));
  PetscCall(SpamManifestAdd(out, "summary.json", "summary", NAN, PETSC_FALSE));
  PetscFunctionReturn(0);
}
