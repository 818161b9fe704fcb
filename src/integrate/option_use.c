/* No option silently ignored. PETSc keeps every option given, used or not; at the end of
 * set-up each one given must be used by this run: an option of spam-ark that applies to
 * another method, scene or model is refused naming what it applies to, an unknown one
 * with the nearest known name. Relevance is decided from the run itself (the method, the
 * scene, the model's choices), not from whether a query happened, because PETSc's
 * TSSetFromOptions reads generic -ts_* options (-ts_rtol, -ts_adapt_*) for every method. */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include <spam/options.h>
#include <strings.h>
#include <errno.h>
#include <spam/errors.h>
#include "ts_family.h"
#include <spam/physics.h>
#include <spam/scene.h>

/* What an option of spam-ark applies to. G_SCENE: the scenes whose options tables hold it
 * (scene_list.h), found there rather than listed here. */
typedef enum {
  G_ALL, G_DT, G_ADAPTIVE, G_TOLERANCE, G_TS, G_TS_ADAPT, G_METHOD,
  G_SCENE, G_ISENTROPE, G_REPRODUCIBLE,
  G_MODEL, G_WALL, G_SOLID, G_SOLID_GAS, G_SOLID_GAMMA, G_SOLID_ELASTIC, G_SOLID_VISC, G_SOLID_R2, G_SOLID_TORQUE, G_SOLID_CONT, G_SOLID_FLOW, G_SOLID_ADAPTIVE, G_ENTROPY, G_RANKS
} Group;

typedef struct {
  const char *name;  /* without the leading '-' */
  PetscBool   value; /* takes a value (PETSC_FALSE: a boolean, alone means true) */
  Group       group;
} Known;

/* Every option spam-ark reads but the scenes' own (their tables, scene_list.h), and the
 * PETSc TS options it documents. */
static const Known KnownOptions[] = {
  {"dim", PETSC_TRUE, G_ALL}, {"h", PETSC_TRUE, G_ALL}, {"mass", PETSC_TRUE, G_ALL}, {"neighbour_skin", PETSC_TRUE, G_ALL},
  {"migrate_interval", PETSC_TRUE, G_RANKS}, {"threads", PETSC_TRUE, G_ALL}, {"scene", PETSC_TRUE, G_ALL}, {"scene_translate", PETSC_TRUE, G_ALL}, {"sort_particles", PETSC_FALSE, G_ALL},
  {"ts_type", PETSC_TRUE, G_ALL}, {"ts_max_time", PETSC_TRUE, G_ALL}, {"ts_max_steps", PETSC_TRUE, G_ALL}, {"ts_max_reject", PETSC_TRUE, G_ALL},
  {"unstable_dt_min", PETSC_TRUE, G_ALL}, {"unstable_energy_growth", PETSC_TRUE, G_ALL}, {"output_dir", PETSC_TRUE, G_ALL},
  {"output_interval", PETSC_TRUE, G_ALL}, {"snapshot_interval", PETSC_TRUE, G_ALL}, {"snapshot_hdf5", PETSC_FALSE, G_ALL},
  {"snapshot_csv", PETSC_FALSE, G_ALL}, {"monitor", PETSC_FALSE, G_ALL}, {"quiet", PETSC_FALSE, G_ALL}, {"diag_entropy", PETSC_FALSE, G_ALL},
  {"output_overwrite", PETSC_FALSE, G_ALL}, {"snapshot_max", PETSC_TRUE, G_ALL}, /* the run's own directory (output_options.c) */
  {"grid_interval", PETSC_TRUE, G_ALL}, /* fields on a grid at the snapshot times (grid.h) */
  {"initial_csv", PETSC_TRUE, G_ALL}, {"final_csv", PETSC_TRUE, G_ALL}, {"diag_grid_spacing", PETSC_TRUE, G_ENTROPY},
  {"ts_dt", PETSC_TRUE, G_DT}, {"ts_rtol", PETSC_TRUE, G_TOLERANCE}, {"ts_atol", PETSC_TRUE, G_TOLERANCE},
  {"arkode_classic_weights", PETSC_FALSE, G_TOLERANCE}, {"step_cfl", PETSC_TRUE, G_ADAPTIVE}, {"step_force", PETSC_TRUE, G_ADAPTIVE},
  {"ts_adapt_type", PETSC_TRUE, G_TS},
  {"eos_gamma", PETSC_TRUE, G_ISENTROPE}, {"eos_kappa", PETSC_TRUE, G_ISENTROPE},
  {"material", PETSC_TRUE, G_MODEL}, {"density", PETSC_TRUE, G_SOLID}, {"density_mean", PETSC_TRUE, G_SOLID}, {"coordinates", PETSC_TRUE, G_SOLID},
  {"angmom", PETSC_TRUE, G_SOLID}, {"viscosity", PETSC_TRUE, G_SOLID}, {"viscosity_shear", PETSC_TRUE, G_SOLID}, {"viscosity_bulk", PETSC_TRUE, G_SOLID},
  {"conductivity", PETSC_TRUE, G_SOLID}, {"closest_approach", PETSC_TRUE, G_SOLID}, {"gas_e0", PETSC_TRUE, G_SOLID_GAS},
  {"gas_gamma", PETSC_TRUE, G_SOLID_GAMMA}, {"solid_lambda", PETSC_TRUE, G_SOLID_ELASTIC}, {"solid_eta", PETSC_TRUE, G_SOLID_ELASTIC},
  {"viscosity_alpha", PETSC_TRUE, G_SOLID_VISC}, {"viscosity_beta", PETSC_TRUE, G_SOLID_VISC}, {"xsph_eps", PETSC_TRUE, G_SOLID_R2},
  {"angmom_scope", PETSC_TRUE, G_SOLID_TORQUE}, {"density_initial", PETSC_TRUE, G_SOLID_CONT},
  {"gas_scheme", PETSC_TRUE, G_SOLID_GAS}, {"background_pressure", PETSC_TRUE, G_SOLID_FLOW}, {"shift_coefficient", PETSC_TRUE, G_SOLID_FLOW}, {"diffusion_form", PETSC_TRUE, G_SOLID_FLOW}, {"conduction_linear", PETSC_FALSE, G_SOLID_FLOW}, {"shift_compression", PETSC_FALSE, G_SOLID_FLOW},
  /* The gas's kernel range: one h, or each particle's own (smoothing_options.c). */
  {"smoothing_length", PETSC_TRUE, G_SOLID_GAS}, {"h_eta", PETSC_TRUE, G_SOLID_ADAPTIVE}, {"h_min", PETSC_TRUE, G_SOLID_ADAPTIVE}, {"h_max", PETSC_TRUE, G_SOLID_ADAPTIVE}, {"h_tol", PETSC_TRUE, G_SOLID_ADAPTIVE},
  /* the pair layer: kernel, gravity, periodic images as ghosts (scene.c) */
  {"kernel", PETSC_TRUE, G_MODEL}, {"gravity", PETSC_TRUE, G_MODEL}, {"periodic_images", PETSC_TRUE, G_ALL},
  /* Mirror walls per box face (core/walls.c); relevance by face and condition (WallRelevant). */
  {"wall_xlo", PETSC_TRUE, G_WALL}, {"wall_xhi", PETSC_TRUE, G_WALL}, {"wall_ylo", PETSC_TRUE, G_WALL},
  {"wall_yhi", PETSC_TRUE, G_WALL}, {"wall_zlo", PETSC_TRUE, G_WALL}, {"wall_zhi", PETSC_TRUE, G_WALL},
  {"wall_xlo_velocity", PETSC_TRUE, G_WALL}, {"wall_xhi_velocity", PETSC_TRUE, G_WALL}, {"wall_ylo_velocity", PETSC_TRUE, G_WALL},
  {"wall_yhi_velocity", PETSC_TRUE, G_WALL}, {"wall_zlo_velocity", PETSC_TRUE, G_WALL}, {"wall_zhi_velocity", PETSC_TRUE, G_WALL},
  {"wall_xlo_temperature", PETSC_TRUE, G_WALL}, {"wall_xhi_temperature", PETSC_TRUE, G_WALL}, {"wall_ylo_temperature", PETSC_TRUE, G_WALL},
  {"wall_yhi_temperature", PETSC_TRUE, G_WALL}, {"wall_zlo_temperature", PETSC_TRUE, G_WALL}, {"wall_zhi_temperature", PETSC_TRUE, G_WALL},
  /* The norm of the weighted error (error_norm.c); a fixed step has none. */
  {"error_norm", PETSC_TRUE, G_TOLERANCE},
  /* Outputs from the interpolant unless -output_stop (time_loop.c,
   * output_mode.c); ARKODE's / CVODE's statistics table (ts_arkode.c, ts_cvode.c). */
  {"output_stop", PETSC_FALSE, G_ALL},
  /* Checkpoints and restart (checkpoint_*.c, restart_*.c). */
  {"checkpoint_interval", PETSC_TRUE, G_ALL}, {"checkpoint_wall", PETSC_TRUE, G_ALL}, {"restart", PETSC_TRUE, G_ALL},
  /* Canonical pair sums and a partition-independent norm (scene.c reads
   * it and refuses the other models, pass_canonical.c, error_norm.c). */
  {"reproducible", PETSC_FALSE, G_REPRODUCIBLE},
};
#define NKNOWN ((int)(sizeof KnownOptions / sizeof KnownOptions[0]))

/* PETSc's own run-time options, read by PetscInitialize or PetscFinalize rather than during
 * set-up (so possibly not yet marked used), pass unchecked: logging and profiling (-log_*,
 * -info), memory checks (-malloc*, -memory_view, -objects_dump, -checkstack), error and
 * debugger handling (-on_error_*, -fp_trap, -no_signal_handler, -*debugger*), the options
 * machinery itself (-options_*, -help, -skip_petscrc), MPI and viewers. */
static const char *const PetscRuntime[] = {"log", "info", "malloc", "memory_view", "objects_dump", "checkstack", "on_error_", "fp_trap", "no_signal_handler", "debugger",
                                           "start_in_debugger", "stop_for_debugger", "attach_debugger", "options_", "help", "skip_petscrc", "mpi", "viewer_", "error_output_", "history", "nox", "display", "saws", "check_pointer_intensity", "get_total_flops"};

/* The row of option name in the first scene's table that holds it, or NULL. */
static const SpamSceneOption *SceneOption(const char *name)
{
  for (int i = 0; i < SpamSceneCount(); i++) {
    SpamSceneOps           ops;
    const SpamSceneOption *o;
    if (SpamSceneGet(i, &ops)) return NULL; /* the list's own functions only fill in constants */
    o = SpamSceneOptionFind(ops.options_table, name);
    if (o) return o;
  }
  return NULL;
}

/* The row of option name in the first TS type's table that holds it (ts_family.h), or NULL. */
static const SpamTSOption *MethodOption(const char *name)
{
  const SpamTSFamily *f;
  const SpamTSOption *o;

  for (int k = 0; (f = SpamTSFamilyAt(k)); k++)
    if ((o = SpamTSFamilyOption(f, name))) return o;
  return NULL;
}

/* Option name as known: from the table above, a TS type's (group G_METHOD) or a scene's
 * (group G_SCENE). */
static PetscBool Find(const char *name, Known *k)
{
  const SpamSceneOption *o;
  const SpamTSOption    *m;

  for (int j = 0; j < NKNOWN; j++)
    if (!strcasecmp(name, KnownOptions[j].name)) { /* PETSc ignores case */
      *k = KnownOptions[j];
      return PETSC_TRUE;
    }
  if ((m = MethodOption(name))) {
    *k = (Known){m->name, m->value, G_METHOD};
    return PETSC_TRUE;
  }
  o = SceneOption(name);
  if (!o) return PETSC_FALSE;
  *k = (Known){o->name, (PetscBool)(o->type != SPAM_SCENE_OPTION_BOOL), G_SCENE};
  return PETSC_TRUE;
}

static PetscBool IsPetscRuntime(const char *name)
{
  for (size_t k = 0; k < sizeof PetscRuntime / sizeof PetscRuntime[0]; k++)
    if (!strncmp(name, PetscRuntime[k], strlen(PetscRuntime[k]))) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* The options given, from PetscOptionsGetAll ("-name [value] ..."), which, unlike every
 * query, leaves the used marks alone. names[i] has no '-'; values[i] is NULL for none. */
typedef struct {
  char  *all;
  int    n;
  char **names, **values;
} Given;

static PetscErrorCode GivenGet(Given *g)
{
  int ntok = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(g, sizeof *g));
  PetscCall(PetscOptionsGetAll(NULL, &g->all));
  for (const char *p = g->all; *p; p++) ntok += *p == ' ';
  PetscCall(PetscCalloc2(ntok + 2, &g->names, ntok + 2, &g->values));
  for (char *save = NULL, *tok = strtok_r(g->all, " ", &save); tok; tok = strtok_r(NULL, " ", &save)) {
    PetscBool key; /* PETSc's own rule: -name, not a negative number such as -5,-5 or -inf */
    PetscCall(PetscOptionsValidKey(tok, &key));
    if (key) g->names[g->n++] = tok + 1;
    else if (g->n && !g->values[g->n - 1]) g->values[g->n - 1] = tok;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode GivenFree(Given *g)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(g->names, g->values));
  PetscCall(PetscFree(g->all));
  PetscFunctionReturn(0);
}

/* The options read as PetscInt. PETSc 3.18 converts their text with strtoll and casts to
 * its 32-bit PetscInt without a range check, so 2147483648 arrives as -2147483648 and a
 * longer number as whatever its low bits say: check the text itself first. These and the
 * scenes' of type SPAM_SCENE_OPTION_INT. */
static const char *const IntegerOptions[] = {"dim", "threads", "ts_max_steps", "ts_max_reject", "ts_ssp_nstages", "cvode_max_order", "arkode_imex_max_nonlin_iters", "arkode_imex_krylov_dim", "arkode_imex_predictor", "arkode_imex_lsetup_freq", "snapshot_max", "block_max_level"};

/* The name of integer option name as the program spells it, or NULL: not an integer. */
static const char *IntegerOption(const char *name)
{
  const SpamSceneOption *o = SceneOption(name);

  for (size_t k = 0; k < sizeof IntegerOptions / sizeof IntegerOptions[0]; k++)
    if (!strcasecmp(name, IntegerOptions[k])) return IntegerOptions[k];
  return o && o->type == SPAM_SCENE_OPTION_INT ? o->name : NULL;
}

static PetscErrorCode CheckIntegerRange(const char *name, const char *value)
{
  const char *known = IntegerOption(name);
  char       *end;
  long long   v;

  PetscFunctionBeginUser;
  if (!known) PetscFunctionReturn(0);
  errno = 0;
  v     = strtoll(value, &end, 10);
  if (end == value || *end) PetscFunctionReturn(0); /* not an integer literal: PETSc's parser says so */
  if (errno == ERANGE || v < PETSC_MIN_INT || v > PETSC_MAX_INT) {
    char shown[100], opt[64];
    SpamClip(value, shown, sizeof shown);
    (void)snprintf(opt, sizeof opt, "-%s", known);
    SPAM_BAD_INPUT(opt, shown, "an integer from %d to %d (PetscInt is 32-bit here)", PETSC_MIN_INT, PETSC_MAX_INT);
  }
  PetscFunctionReturn(0);
}

/* The options read as lists (PetscOptions*Array): PETSc's parser skips an empty element,
 * so "-box_lo 1,,2" would read as 1,2 in silence. Ours, PETSc's TS adaptor lists, and the
 * scenes' of type SPAM_SCENE_OPTION_REALS or BOOLS. */
static const char *const ListOptions[] = {"scene_translate", "gravity", "arkode_adapt_params", "ts_adapt_clip", "ts_adapt_dsp_pid", "ts_adapt_dsp_kbeta", "ts_adapt_dsp_alpha"};

static PetscBool IsListOption(const char *name)
{
  const size_t           n = strlen(name);
  const SpamSceneOption *o = SceneOption(name);

  if (!strncasecmp(name, "wall_", 5) && n > 9 && !strcasecmp(name + n - 9, "_velocity")) return PETSC_TRUE;
  for (size_t k = 0; k < sizeof ListOptions / sizeof ListOptions[0]; k++)
    if (!strcasecmp(name, ListOptions[k])) return PETSC_TRUE;
  return (PetscBool)(o && (o->type == SPAM_SCENE_OPTION_REALS || o->type == SPAM_SCENE_OPTION_BOOLS));
}

/* A list option's value with an empty element (a leading, trailing or doubled comma) is
 * refused, naming the element. */
static PetscErrorCode CheckListElements(const char *name, const char *value)
{
  int k = 1;

  PetscFunctionBeginUser;
  if (!IsListOption(name)) PetscFunctionReturn(0);
  for (const char *p = value;; p++, k++) {
    const char *end = strchr(p, ',');
    if (end == p || (!end && !*p)) {
      char shown[100], opt[64];
      SpamClip(value, shown, sizeof shown);
      (void)snprintf(opt, sizeof opt, "-%s", name);
      SPAM_BAD_INPUT(opt, shown, "element %d is empty: a list is values separated by single commas", k);
    }
    if (!end) break;
    p = end;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOptionsCheckValues(void)
{
  Given g;

  PetscFunctionBeginUser;
  PetscCall(GivenGet(&g));
  for (int i = 0; i < g.n; i++) {
    Known           k = {NULL, PETSC_FALSE, G_ALL};
    const PetscBool known = Find(g.names[i], &k);
    if (g.values[i]) {
      PetscErrorCode ierr = CheckIntegerRange(g.names[i], g.values[i]);
      if (!ierr) ierr = CheckListElements(g.names[i], g.values[i]);
      if (ierr) {
        PetscCall(GivenFree(&g));
        return ierr; /* reported already, as one line */
      }
    }
    if (!known || !k.value || g.values[i]) continue;
    PetscCall(GivenFree(&g));
    if (!strcmp(k.name, "h")) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-h: missing value: -h is the kernel range, a number (e.g. -h 3); for the list of options use -help");
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-%s: missing or empty value: give it after a space (-%s VALUE); spam-ark -help shows its default", k.name, k.name);
  }
  PetscCall(GivenFree(&g));
  PetscFunctionReturn(0);
}

/* The run, as far as relevance goes. */
typedef struct {
  const SpamSim         *sim;
  const char            *scene, *model;
  const SpamSolidParams *solid; /* NULL unless the model is the tensor-path solid */
  const SpamRunOptions  *o;
  char                   type[32], adapt[32], method[160];
  const SpamTSFamily    *f;               /* the row of the method's TS type        */
  TS                     ts;
  PetscBool              error_controlled; /* a step rule's steps under error control */
  PetscBool              own;             /* the type chooses its own steps         */
  PetscBool              adaptive;
  double                 arkode_fixed;    /* arkode's fixed step, or 0             */
  PetscBool              arkode_fixed_ts; /* ... given as -ts_adapt_type none -ts_dt */
  const char            *pc_prefix;       /* arkode_imex's preconditioner KSP, or NULL */
} Run;

static PetscErrorCode RunDescribe(const SpamSim *sim, const SpamRunOptions *o, TS ts, Run *r)
{
  TSAdapt                   adapt;
  TSAdaptType               atype;
  const char               *sub = NULL;
  const SpamArkodeSettings *s;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  r->sim   = sim;
  r->scene = sim->out.scene.name;
  r->model = sim->model.name;
  r->o     = o;
  if (!strcmp(r->model, "elastic") || !strcmp(r->model, "gas")) r->solid = &sim->model.solid;
  PetscCall(SpamTSFamilyOf(ts, &r->f));
  r->ts               = ts;
  r->error_controlled = (PetscBool)(r->f->error_controlled && r->f->error_controlled(ts));
  PetscCall(PetscStrncpy(r->type, r->f->type, sizeof r->type));
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(TSAdaptGetType(adapt, &atype));
  PetscCall(PetscStrncpy(r->adapt, atype, sizeof r->adapt));
  r->own = (PetscBool)(r->f->steps == SPAM_TS_STEPS_OWN);
  PetscCall(SpamTSARKodeGetSettings(ts, &s)); /* NULL but for the arkode type */
  if (s) {
    r->arkode_fixed    = s->fixed_step;
    r->arkode_fixed_ts = s->fixed_by_ts;
  }
  PetscCall(SpamTSARKodeImexPCPrefix(ts, &r->pc_prefix));
  r->adaptive = r->own ? (PetscBool)!(r->arkode_fixed > 0) : (PetscBool)strcmp(atype, TSADAPTNONE);
  if (r->f->sub_type) PetscCall(r->f->sub_type(ts, &sub));
  if (sub) (void)snprintf(r->method, sizeof r->method, "-ts_type %s %s %s", r->type, r->f->sub_option, sub);
  else (void)snprintf(r->method, sizeof r->method, "-ts_type %s", r->type);
  if (r->arkode_fixed > 0) (void)snprintf(r->method + strlen(r->method), sizeof r->method - strlen(r->method), r->arkode_fixed_ts ? " -ts_adapt_type none -ts_dt %.17g" : " -arkode_fixed_step %.17g", r->arkode_fixed);
  PetscFunctionReturn(0);
}

/* Names in the order given, written "a", "a and b" or "a, b and c" (the refusals' lists). */
typedef struct {
  char        said[256];
  const char *last;
  int         count;
} NameList;

static void NameListAdd(NameList *l, const char *name)
{
  if (l->last) (void)snprintf(l->said + strlen(l->said), sizeof l->said - strlen(l->said), "%s%s", l->count > 1 ? ", " : "", l->last);
  l->last = name;
  l->count++;
}

static void NameListText(const NameList *l, char *out, size_t len)
{
  (void)snprintf(out, len, "%s%s%s", l->said, l->count > 1 ? " and " : "", l->last ? l->last : "");
}

/* An option a TS type's implementation reads: relevant when this run's type reads it (and,
 * for the adaptive-only ones, its steps are adaptive); if not, why[] names the types that
 * read it, in the table's order. */
static PetscBool RelevantToMethod(const char *name, const Run *r, char *why, size_t len)
{
  const SpamTSOption *mine = SpamTSFamilyOption(r->f, name);
  const SpamTSFamily *f;
  NameList            types = {"", NULL, 0};
  char                said[256];

  if (mine && (!mine->adaptive || r->adaptive)) return PETSC_TRUE;
  if (mine) {
    (void)snprintf(why, len, "applies to -ts_type %s with adaptive steps (this run: %s)", r->type, r->method);
    return PETSC_FALSE;
  }
  for (int k = 0; (f = SpamTSFamilyAt(k)); k++) {
    if (SpamTSFamilyOption(f, name)) NameListAdd(&types, f->type);
  }
  NameListText(&types, said, sizeof said);
  (void)snprintf(why, len, "applies to -ts_type %s (this run: %s)", said, r->method);
  return PETSC_FALSE;
}

/* The groups of the method and the outputs: whether g applies to run r (*known: g is one
 * of them); if not, why[] says what it applies to. */
static PetscBool RelevantMethod(Group g, const Run *r, char *why, size_t len, PetscBool *known)
{
  *known = PETSC_TRUE;
  switch (g) {
  case G_ALL: return PETSC_TRUE;
  case G_RANKS:
    /* Migrations come after list builds; the springs model builds none after set-up (its
     * bonds are fixed), so its particles stay where the first distribution put them. */
    if (SpamSimDistributed(r->sim) && SpamBondsAny(r->sim)) {
      (void)snprintf(why, len, "applies to models that rebuild their neighbour list (this run: the springs model, whose bonds are fixed at set-up, builds none and never migrates)");
      return PETSC_FALSE;
    }
    if (SpamSimDistributed(r->sim) && SpamTSTypeCanFollow(r->type, r->adapt)) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to runs on several ranks with -ts_type arkode, or rk, ssp, euler with fixed steps (this run: %s)", SpamSimDistributed(r->sim) ? r->method : "one rank");
    return PETSC_FALSE;
  case G_ENTROPY:
    if (r->o->diag.entropy) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to the entropy estimates (this run: -diag_entropy false)");
    return PETSC_FALSE;
  case G_DT:
    if (!(r->arkode_fixed > 0 && !r->arkode_fixed_ts)) return PETSC_TRUE;
    (void)snprintf(why, len, "the step of this run is -arkode_fixed_step %.17g", r->arkode_fixed);
    return PETSC_FALSE;
  case G_TOLERANCE: /* the weighted norm: the error test's, and an implicit method's solver's */
    if (r->f->step_rule && !r->error_controlled) {
      (void)snprintf(why, len, "applies to steps under error control (this run: %s %s)", r->method, r->f->step_rule);
      return PETSC_FALSE;
    }
    if (r->adaptive || r->f->solves) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to adaptive steps and to -ts_type arkode_imex's solver (this run: %s%s takes fixed steps)", r->method, r->own ? "" : strcmp(r->adapt, TSADAPTNONE) ? "" : " -ts_adapt_type none");
    return PETSC_FALSE;
  case G_ADAPTIVE:
    if (r->f->step_rule) {
      (void)snprintf(why, len, "applies to the bound of a global step (this run: %s %s)", r->method, r->f->step_rule);
      return PETSC_FALSE;
    }
    if (r->adaptive) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to adaptive steps (this run: %s%s takes fixed steps)", r->method, r->own ? "" : strcmp(r->adapt, TSADAPTNONE) ? "" : " -ts_adapt_type none");
    return PETSC_FALSE;
  case G_TS:
    /* arkode takes -ts_adapt_type none (with -ts_dt) as its fixed step (arkode_options.c) */
    if (!r->own || r->arkode_fixed_ts) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to PETSc's methods rk, ssp, euler and basicsymplectic (this run: %s, which controls its own steps: see -%s)", r->method, SpamTSFamilyOption(r->f, "arkode_adapt") ? "arkode_adapt" : r->f->step_rule ? "block_cfl" : "ts_rtol");
    return PETSC_FALSE;
  case G_TS_ADAPT:
    if (!r->own && strcmp(r->adapt, TSADAPTNONE)) return PETSC_TRUE;
    if (r->own) (void)snprintf(why, len, "PETSc's step adaptor applies to rk, ssp, euler and basicsymplectic (this run: %s, which controls its own steps)", r->method);
    else (void)snprintf(why, len, "applies to an active step adaptor (this run: %s -ts_adapt_type none)", r->method);
    return PETSC_FALSE;
  default: break;
  }
  *known = PETSC_FALSE;
  return PETSC_TRUE;
}

/* The groups of the models (the isentrope, the smooth-particle models), as RelevantMethod. */
static PetscBool RelevantModel(Group g, const Run *r, char *why, size_t len, PetscBool *known)
{
  *known = PETSC_TRUE;
  if (g == G_ISENTROPE) {
    if (!strcmp(r->model, "isentrope")) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -material isentrope (this run: -scene %s, model %s)", r->scene, r->model);
    return PETSC_FALSE;
  }
  if (g == G_REPRODUCIBLE) {
    const SpamSolidParams *s = r->solid;
    if (!strcmp(r->model, "isentrope") || (s && s->material == SPAM_MATERIAL_GAS && s->smoothing != SPAM_SMOOTHING_FIXED)) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -material isentrope and to the gas at -smoothing_length adaptive (this run: -scene %s, model %s)", r->scene, r->model);
    return PETSC_FALSE;
  }
  if (g == G_MODEL) {
    if (strcmp(r->model, "springs")) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to the smooth-particle models (this run: -scene %s carries its own model, springs)", r->scene);
    return PETSC_FALSE;
  }
  *known = PETSC_FALSE;
  return PETSC_TRUE;
}

/* A scene's option: relevant to the scenes whose tables hold it; if not this run's, why[]
 * names them in the list's order ("a, b and c") and the note of the first one's row. */
static PetscBool RelevantToScene(const char *name, const Run *r, char *why, size_t len)
{
  NameList    scenes = {"", NULL, 0};
  char        said[256];
  const char *note = NULL;

  for (int i = 0; i < SpamSceneCount(); i++) {
    SpamSceneOps           ops;
    const SpamSceneOption *o;
    if (SpamSceneGet(i, &ops)) break; /* the list's own functions only fill in constants */
    if (!(o = SpamSceneOptionFind(ops.options_table, name))) continue;
    if (!strcmp(r->scene, ops.name)) return PETSC_TRUE;
    if (!note) note = o->note;
    NameListAdd(&scenes, ops.name);
  }
  NameListText(&scenes, said, sizeof said);
  (void)snprintf(why, len, "applies to -scene %s (this run: -scene %s%s)", said, r->scene, note ? note : "");
  return PETSC_FALSE;
}

/* The groups of the tensor-path solid (planewave, rotor, rotor-pair, tensile). */
static PetscBool RelevantSolid(Group g, const Run *r, char *why, size_t len)
{
  const SpamSolidParams *s = r->solid;

  if (!s) {
    (void)snprintf(why, len, "applies to -material gas and elastic (this run: -scene %s, model %s)", r->scene, r->model);
    return PETSC_FALSE;
  }
  switch (g) {
  case G_SOLID: return PETSC_TRUE;
  case G_SOLID_GAS:
    if (s->material == SPAM_MATERIAL_GAS) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -material gas (this run: -material %s)", SpamMaterialNames[s->material]);
    return PETSC_FALSE;
  case G_SOLID_GAMMA:
    if (s->material == SPAM_MATERIAL_GAS || s->conductivity > 0) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -material gas and to the temperature of -conductivity (this run: -material %s, -conductivity 0)", SpamMaterialNames[s->material]);
    return PETSC_FALSE;
  case G_SOLID_ELASTIC:
    if (s->material == SPAM_MATERIAL_ELASTIC) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -material elastic (this run: -material %s)", SpamMaterialNames[s->material]);
    return PETSC_FALSE;
  case G_SOLID_VISC:
    if (s->viscosity != SPAM_VISCOSITY_NONE) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -viscosity monaghan and vonneumann (this run: -viscosity none)");
    return PETSC_FALSE;
  case G_SOLID_R2:
    if (s->coords == SPAM_COORDS_R2) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -coordinates R2 (this run: -coordinates %s)", SpamCoordsModeNames[s->coords]);
    return PETSC_FALSE;
  case G_SOLID_TORQUE:
    if (s->angmom == SPAM_ANGMOM_TI || s->angmom == SPAM_ANGMOM_TIJ) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -angmom Ti and Tij (this run: -angmom %s)", SpamAngmomModeNames[s->angmom]);
    return PETSC_FALSE;
  case G_SOLID_FLOW:
    if (s->material == SPAM_MATERIAL_GAS && s->scheme == SPAM_GAS_FLOW) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to the gas's -gas_scheme flow (this run: -material %s%s)", SpamMaterialNames[s->material], s->material == SPAM_MATERIAL_GAS ? ", -gas_scheme plain" : "");
    return PETSC_FALSE;
  case G_SOLID_ADAPTIVE:
    if (s->material == SPAM_MATERIAL_GAS && s->smoothing != SPAM_SMOOTHING_FIXED) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to the gas's -smoothing_length adaptive and evolved (this run: -material %s%s)", SpamMaterialNames[s->material], s->material == SPAM_MATERIAL_GAS ? ", -smoothing_length fixed" : "");
    return PETSC_FALSE;
  case G_SOLID_CONT:
    if (s->density != SPAM_DENSITY_SUMMATION) return PETSC_TRUE;
    (void)snprintf(why, len, "applies to -density continuity and chain-rule (this run: -density summation)");
    return PETSC_FALSE;
  default: return PETSC_TRUE;
  }
}

/* Whether group g applies to run r; if not, why[] says what it applies to. */
static PetscBool Relevant(Group g, const Run *r, char *why, size_t len)
{
  PetscBool known, yes = RelevantMethod(g, r, why, len, &known);

  if (known) return yes;
  yes = RelevantModel(g, r, why, len, &known);
  if (known) return yes;
  return RelevantSolid(g, r, why, len);
}

/* Levenshtein distance of two short names (longer names are cut at 63 bytes). */
static int Distance(const char *a, const char *b)
{
  int       row[64];
  const int la = (int)PetscMin(strlen(a), 63), lb = (int)PetscMin(strlen(b), 63);

  for (int j = 0; j <= lb; j++) row[j] = j;
  for (int i = 1; i <= la; i++) {
    int diag = row[0];
    row[0]   = i;
    for (int j = 1; j <= lb; j++) {
      const int up = row[j], best = PetscMin(PetscMin(row[j] + 1, row[j - 1] + 1), diag + (a[i - 1] != b[j - 1]));
      diag   = up;
      row[j] = best;
    }
  }
  return row[lb];
}

/* The known name nearest to name, if near enough to be a misspelling of it. */
/* Keeps candidate in *best when it is nearer to name than *dbest. */
static void Nearer(const char *name, const char *candidate, const char **best, int *dbest)
{
  const int d = Distance(name, candidate);

  if (d < *dbest) {
    *dbest = d;
    *best  = candidate;
  }
}

static const char *Nearest(const char *name)
{
  const char         *best = NULL;
  int                 dbest = 1 << 30;
  const SpamTSFamily *f;

  for (int k = 0; k < NKNOWN; k++) Nearer(name, KnownOptions[k].name, &best, &dbest);
  for (int k = 0; (f = SpamTSFamilyAt(k)); k++)
    for (const SpamTSOption *o = f->options; o && o->name; o++) Nearer(name, o->name, &best, &dbest);
  for (int i = 0; i < SpamSceneCount(); i++) {
    SpamSceneOps ops;
    if (SpamSceneGet(i, &ops)) break; /* the list's own functions only fill in constants */
    for (const SpamSceneOption *o = ops.options_table; o && o->name; o++) Nearer(name, o->name, &best, &dbest);
  }
  /* Near: at most 2 edits (a quarter of a long name), and fewer than half the name. */
  return dbest <= PetscMax(2, (int)strlen(name) / 4) && dbest < (int)strlen(name) / 2 + 1 ? best : NULL;
}

static PetscErrorCode RefuseUnknown(const char *name, const char *value)
{
  char        shown[100], hint[200] = "", base[128];
  const char *eq = strchr(name, '='), *near;

  PetscFunctionBeginUser;
  SpamClip(name, shown, sizeof shown);
  if (eq) {
    (void)snprintf(base, sizeof base, "%.*s", (int)PetscMin(eq - name, 100), name);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-%s: unknown option: PETSc options take their value after a space, not '=': write -%s %s", shown, base, eq + 1);
  }
  near = Nearest(name);
  if (near) (void)snprintf(hint, sizeof hint, " (did you mean -%s?)", near);
  else (void)snprintf(hint, sizeof hint, " (spam-ark -help lists every option)");
  if (value) {
    char v[100];
    SpamClip(value, v, sizeof v);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "unknown option -%s = '%s'%s", shown, v, hint);
  }
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "unknown option -%s%s", shown, hint);
}

/* Whether name is among the options PETSc left unused. */
static PetscBool Unused(const char *name, PetscInt n, char **left)
{
  for (PetscInt i = 0; i < n; i++)
    if (!strcasecmp(name, left[i])) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* Whether -name was given on the command line (else it came from an options file, the
 * PETSC_OPTIONS variable or a .petscrc). */
static PetscErrorCode OnCommandLine(const char *name, PetscBool *yes)
{
  int    argc;
  char **args;

  PetscFunctionBeginUser;
  *yes = PETSC_FALSE;
  PetscCall(PetscGetArgs(&argc, &args));
  for (int i = 1; i < argc; i++)
    if (args[i][0] == '-' && (!strcasecmp(args[i] + 1, name) || (args[i][1] == '-' && !strcasecmp(args[i] + 2, name)))) *yes = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* An option this run does not use: refused when the user typed it; a note when it came
 * from an options file, whose presets (say -ts_rtol in planewave.opts) are meant for the
 * file's own method or choices and may be overridden on the command line. */
static PetscErrorCode NotUsed(const char *name, const char *value, const char *why)
{
  char      v[100], raw[600], text[700];
  PetscBool typed;

  PetscFunctionBeginUser;
  SpamClip(value ? value : "true", v, sizeof v);
  PetscCall(OnCommandLine(name, &typed));
  if (typed) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-%s = '%s': not used: %s", name, v, why);
  (void)snprintf(raw, sizeof raw, "-%s = '%s' (from an options file): not used: %s", name, v, why);
  SpamEscape(raw, text, sizeof text);
  PetscCall(PetscFPrintf(PETSC_COMM_WORLD, stderr, "spam-ark: note: %s\n", text));
  PetscFunctionReturn(0);
}

/* A wall option -wall_F[_velocity|_temperature]: the face must exist in the run; its
 * velocity applies to a no-slip wall of a model with viscous stresses (the tensor path),
 * its temperature to a wall of a model that conducts heat. */
static PetscBool WallRelevant(const char *name, const Run *r, char *why, size_t len)
{
  const SpamSim *sim = r->sim;
  const int      dim = sim->model.dim;
  const char    *suffix = name + 8; /* after "wall_" and the face */
  int            f = 0;

  while (f < SPAM_FACES && strncasecmp(name + 5, SpamFaceNames[f], 3)) f++;
  if (!strcmp(r->model, "springs")) {
    (void)snprintf(why, len, "applies to the smooth-particle models (this run: -scene %s carries its own model, springs)", r->scene);
    return PETSC_FALSE;
  }
  if (f / 2 >= dim) {
    (void)snprintf(why, len, "the %s face exists in %d dimensions (this run: -dim %d)", SpamFaceNames[f], f / 2 + 1, dim);
    return PETSC_FALSE;
  }
  if (!*suffix) return PETSC_TRUE;
  if (!strcasecmp(suffix, "_velocity") && (sim->geo.walls.slip[f] != SPAM_WALL_NOSLIP || !r->solid)) {
    (void)snprintf(why, len, "applies to a no-slip wall on the %s face of -material gas or elastic (this run: %s wall %s, model %s)", SpamFaceNames[f], SpamFaceNames[f], SpamWallSlipNames[sim->geo.walls.slip[f]], r->model);
    return PETSC_FALSE;
  }
  if (!strcasecmp(suffix, "_temperature") && (!SpamWallOn(&sim->geo.walls, f) || !r->solid || !(r->solid->conductivity > 0))) {
    (void)snprintf(why, len, "applies to a wall on the %s face of a model that conducts heat, -conductivity > 0 (this run: %s wall %s, model %s%s)", SpamFaceNames[f], SpamFaceNames[f], SpamWallSlipNames[sim->geo.walls.slip[f]], r->model, r->solid ? ", -conductivity 0" : "");
    return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

/* Whether known option k applies to run r; if not, why[] says what it applies to. */
static PetscBool KnownRelevant(const Known *k, const Run *r, char *why, size_t len)
{
  if (r->f->option_off && r->f->option_off(r->ts, k->name, why, len)) return PETSC_FALSE;
  if (k->group == G_WALL) return WallRelevant(k->name, r, why, len);
  if (k->group == G_SCENE) return RelevantToScene(k->name, r, why, len);
  if (k->group == G_METHOD) return RelevantToMethod(k->name, r, why, len);
  return Relevant(k->group, r, why, len);
}

static PetscErrorCode CheckOne(const char *name, const char *value, const Run *r, PetscInt nleft, char **left)
{
  Known k = {NULL, PETSC_FALSE, G_ALL};
  char  why[320];

  PetscFunctionBeginUser;
  if (Find(name, &k)) {
    if (!KnownRelevant(&k, r, why, sizeof why)) PetscCall(NotUsed(name, value, why));
    else if (Unused(name, nleft, left)) PetscCall(NotUsed(name, value, "not read by this scene, model or method"));
    PetscFunctionReturn(0);
  }
  if (IsPetscRuntime(name)) PetscFunctionReturn(0);
  /* The stage preconditioner's KSP and PC (-imex_pc_ksp_type, -imex_pc_pc_type, ...): read
   * by its KSPSetFromOptions; one PETSc left unread is not an option of that KSP or PC. */
  if (!strncasecmp(name, SPAM_IMEX_PC_PREFIX_TEXT, strlen(SPAM_IMEX_PC_PREFIX_TEXT))) {
    if (!r->pc_prefix) {
      (void)snprintf(why, sizeof why, "applies to the stage preconditioner of -ts_type arkode_imex -arkode_imex_pc diffusion (this run: %s%s)", r->method, strcmp(r->type, SPAM_TSARKODE_IMEX) ? "" : " -arkode_imex_pc none");
      PetscCall(NotUsed(name, value, why));
    } else if (Unused(name, nleft, left)) PetscCall(RefuseUnknown(name, value));
    PetscFunctionReturn(0);
  }
  /* TSSetFromOptions makes a SNES and reads its options (and its KSP's and PC's) for every
   * type, so PETSc marks them used; no method of spam-ark uses PETSc's solvers (the
   * implicit one, arkode_imex, solves with SUNDIALS' Newton and GMRES). */
  if (!strncmp(name, "snes_", 5) || !strncmp(name, "ksp_", 4) || !strncmp(name, "pc_", 3)) PetscCall(NotUsed(name, value, "applies to PETSc's implicit solvers (SNES, KSP, PC), which no -ts_type of spam-ark uses directly (arkode_imex solves with SUNDIALS' Newton-GMRES: see -arkode_imex_*; its stage preconditioner's KSP takes the prefix -imex_pc_)"));
  /* PETSc's step adaptor reads -ts_adapt_* for every method, used or not.
   * -ts_adapt_monitor reports the steps of every type (PETSc's adaptor, or the loop for
   * arkode, cvode and basicsymplectic: sundials_report.c). */
  if (!strcasecmp(name, "ts_adapt_monitor")) PetscFunctionReturn(0);
  if (!strncmp(name, "ts_adapt_", 9) && !Relevant(G_TS_ADAPT, r, why, sizeof why)) PetscCall(NotUsed(name, value, why));
  else if (Unused(name, nleft, left)) PetscCall(RefuseUnknown(name, value));
  PetscFunctionReturn(0);
}

/* -reproducible with a PETSc method under an active adaptor on more than one rank: PETSc
 * 3.18's weighted rms norm (TSErrorWeightedNorm2) sums each rank's part and then the
 * parts, with no hook to replace it, so the step sizes would depend on the split. The max
 * norm is a max, exact in any split. */
static PetscErrorCode CheckReproducibleMethod(const Run *r)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  if (!r->sim->pair.reproducible || !r->adaptive || r->o->error_norm == SPAM_ERROR_NORM_MAX) PetscFunctionReturn(0);
  if (r->own) PetscFunctionReturn(0); /* their vectors carry the partition-independent norm */
  PetscCallMPI(MPI_Comm_size(r->sim->p.comm, &size));
  if (size > 1) SPAM_BAD_INPUT("-reproducible", "true", "PETSc's step adaptor (this run: %s) sums its rms error norm rank by rank: on more than one rank use -ts_type arkode or cvode, or -error_norm max", r->method);
  PetscFunctionReturn(0);
}

/* -shift_compression true beside a moving no-slip wall: B's work on the shift's compression
 * heats the sheared rows under the wall steadily (the lid-driven cavity's internal energy
 * grows without bound, tests/run_cavity_heating.py), so the combination is refused; the
 * default (stratified) leaves such runs out (gas_flow.c: SpamGasFlowShiftWorks). */
static PetscErrorCode CheckShiftCompressionWalls(const Run *r)
{
  const SpamWalls *w = &r->sim->geo.walls;

  PetscFunctionBeginUser;
  if (!r->solid || r->solid->shift_work != SPAM_SHIFT_WORK_ALL) PetscFunctionReturn(0); /* the default leaves such runs out */
  for (int f = 0; f < SPAM_FACES; f++)
    if (w->slip[f] == SPAM_WALL_NOSLIP && (w->velocity[f][0] != 0.0 || w->velocity[f][1] != 0.0 || w->velocity[f][2] != 0.0))
      SPAM_BAD_INPUT("-shift_compression", "true", "heats the gas under a moving no-slip wall without bound (this run: the %s wall moves): use it with walls at rest", SpamFaceNames[f]);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOptionsCheckUse(const SpamSim *sim, const SpamRunOptions *o, TS ts)
{
  Given          g;
  Run            r;
  PetscInt       nleft;
  PetscErrorCode ierr = 0;
  char   **left, **lvalues;

  PetscFunctionBeginUser;
  PetscCall(RunDescribe(sim, o, ts, &r));
  PetscCall(PetscOptionsLeftGet(NULL, &nleft, &left, &lvalues));
  PetscCall(GivenGet(&g));
  for (int i = 0; i < g.n && !ierr; i++) ierr = CheckOne(g.names[i], g.values[i], &r, nleft, left);
  PetscCall(GivenFree(&g));
  PetscCall(PetscOptionsLeftRestore(NULL, &nleft, &left, &lvalues));
  PetscCall(ierr); /* the refusal, reported once already, after the clean-up */
  PetscCall(CheckReproducibleMethod(&r));
  PetscCall(CheckShiftCompressionWalls(&r));
  PetscFunctionReturn(0);
}
