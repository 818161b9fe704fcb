/* Creating the TS of a run: the method from -ts_type (validated here, so an unknown name
 * is one line of bad input, not a PETSc traceback), the one RHS, the translation-invariant
 * tolerances, and the splits basicsymplectic needs. */
#include "ts_family.h"
#include <spam/errors.h>

const char *const SpamStepLimitNames[] = {"accuracy", "fixed", "output", "cfl", "force", "end"};

static const char *const AdaptTypes[] = {"none", "basic", "dsp"};

PetscErrorCode SpamIntegratorsRegister(void)
{
  PetscFunctionBeginUser;
  PetscCall(TSRegister(SPAM_TSARKODE, SpamTSCreate_ARKode));
  PetscCall(TSRegister(SPAM_TSARKODE_IMEX, SpamTSCreate_ARKodeImex));
  PetscCall(TSRegister(SPAM_TSCVODE, SpamTSCreate_CVode));
  PetscCall(TSRegister(SPAM_TSBLOCK_KDK, SpamTSCreate_Block));
  PetscCall(SpamSymplecticRegister());
  PetscFunctionReturn(0);
}

/* The value of option 'opt' checked against 'names'; 'def' when the option is absent. */
static PetscErrorCode ChosenName(const char *opt, const char *def, const char *const *names, int n, char *val, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(val, def, len));
  PetscCall(PetscOptionsGetString(NULL, NULL, opt, val, len, NULL));
  PetscCall(SpamCheckAllowed(opt, val, names, n));
  PetscFunctionReturn(0);
}

static PetscErrorCode TsRhs(TS ts, PetscReal t, Vec X, Vec F, void *ctx)
{
  SpamTsApp         *app = (SpamTsApp *)ctx;
  const PetscScalar *x;
  PetscScalar       *f;
  PetscInt           bad;

  PetscFunctionBeginUser;
  (void)ts;
  if (SpamTSRKKeepStageZero(app)) PetscFunctionReturn(0); /* F holds f(y_n): rk_rollback.c */
  PetscCall(VecGetArrayRead(X, &x));
  PetscCall(VecGetArrayWrite(F, &f));
  PetscCall(SpamRhs(app->sim, x, f, &bad));
  if (bad >= 0) {
    /* PETSc's explicit methods have no recoverable RHS failure: finish the step on a zero
     * derivative and let the loop report the particle. */
    if (app->bad < 0) {
      app->bad  = bad;
      app->tbad = t;
    }
    PetscCall(PetscArrayzero(f, (size_t)app->sim->p.n * app->sim->model.layout.nvar));
  }
  PetscCall(VecRestoreArrayWrite(F, &f));
  PetscCall(VecRestoreArrayRead(X, &x));
  SpamTSRKEvaluated(app);
  PetscFunctionReturn(0);
}

/* PETSc's weighted error norm uses tol_i = atol_i + rtol_i max(|y_i|, |yhat_i|). With
 * vector tolerances, positions get atol_i = rtol h + atol, rtol_i = 0 (translation
 * invariant, as for ARKODE) and velocities atol_i = rtol c0 + atol, rtol_i = rtol. */
static PetscErrorCode Tolerances(TS ts, const SpamTsApp *app)
{
  const SpamTSFamily *f;
  const SpamSim    *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  const double      rtol = app->o->rtol, atol = app->o->atol;
  Vec               va, vr;
  PetscScalar      *a, *r;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  /* A method with its own controller weighs errors by SpamErrorWeights on its own vectors:
   * two state-sized vectors here would be memory it never reads. */
  if (f->steps == SPAM_TS_STEPS_OWN) {
    PetscCall(TSSetTolerances(ts, atol, NULL, rtol, NULL));
    PetscFunctionReturn(0);
  }
  PetscCall(VecDuplicate(sim->p.X, &va));
  PetscCall(VecDuplicate(sim->p.X, &vr));
  PetscCall(VecSet(va, atol));
  PetscCall(VecSet(vr, rtol));
  if (!app->o->classic_weights) {
    PetscCall(VecGetArray(va, &a));
    PetscCall(VecGetArray(vr, &r));
    for (PetscInt i = 0; i < sim->p.n; i++)
      for (int d = 0; d < sim->model.dim; d++) {
        a[(size_t)i * l->nvar + l->x + d] = rtol * sim->model.kernel.h + atol;
        r[(size_t)i * l->nvar + l->x + d] = 0.0;
        a[(size_t)i * l->nvar + l->v + d] = rtol * app->w.vscale + atol;
      }
    PetscCall(VecRestoreArray(vr, &r));
    PetscCall(VecRestoreArray(va, &a));
  }
  PetscCall(TSSetTolerances(ts, atol, va, rtol, vr));
  PetscCall(VecDestroy(&va));
  PetscCall(VecDestroy(&vr));
  PetscFunctionReturn(0);
}

/* Validates -ts_type and the sub-type option of the chosen type before PETSc sees them. */
static PetscErrorCode ChooseType(TS ts, const SpamTSFamily **f)
{
  const char *names[SPAM_TS_FAMILIES_MAX];
  const int   n = SpamTSFamilyNames(names, SPAM_TS_FAMILIES_MAX);
  char        type[64], sub[64];

  PetscFunctionBeginUser;
  PetscCall(ChosenName("-ts_type", SPAM_TSARKODE, names, n, type, sizeof type));
  PetscCall(TSSetType(ts, type));
  PetscCall(SpamTSFamilyOf(ts, f));
  if ((*f)->sub_option) PetscCall(ChosenName((*f)->sub_option, (*f)->sub_default, (*f)->subs, (*f)->nsubs, sub, sizeof sub));
  /* Checked for every method: PETSc reads it for all (arkode takes none with -ts_dt as its
   * fixed step and cvode refuses it, in their setfromoptions). */
  PetscCall(ChosenName("-ts_adapt_type", (*f)->adapt_default, AdaptTypes, 3, sub, sizeof sub));
  PetscFunctionReturn(0);
}

/* The sound speed that scales the velocity weights, the default steps and the CFL bound. */
static PetscErrorCode InitialSoundSpeed(SpamSim *sim, double *c0)
{
  const PetscScalar *y;

  PetscFunctionBeginUser;
  *c0 = 1.0;
  if (sim->model.max_sound_speed) {
    PetscCall(VecGetArrayRead(sim->p.X, &y));
    PetscCall(sim->model.max_sound_speed(sim, y, c0));
    PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  }
  if (!(*c0 > 0)) *c0 = 1.0;
  PetscFunctionReturn(0);
}

/* Every run starts at t = 0: the output schedule, the end time and a snapshot's time are
 * measured from there (a snapshot read back starts at 0 again). PETSc's -ts_init_time
 * would move the TS alone, so any other value is refused. */
static PetscErrorCode CheckInitTime(TS ts)
{
  PetscReal t;
  char      val[128];

  PetscFunctionBeginUser;
  PetscCall(TSGetTime(ts, &t));
  PetscCall(SpamOptionText("-ts_init_time", t, val, sizeof val));
  if (t != 0.0) SPAM_BAD_INPUT("-ts_init_time", val, "every run starts at t = 0 (0 is the only value; -ts_max_time is the duration)");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSCreate(SpamSim *sim, const SpamRunOptions *o, SpamTsApp *app, TS *ts)
{
  const SpamTSFamily *f;
  TSAdapt             adapt;
  PetscBool           help;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(app, sizeof *app));
  app->sim    = sim;
  app->o      = o;
  app->bad    = -1;
  app->bound  = PETSC_INFINITY;
  app->w.sim  = sim;
  app->w.rtol = o->rtol;
  app->w.atol = o->atol;
  PetscCall(InitialSoundSpeed(sim, &app->w.vscale));
  PetscCall(TSCreate(sim->p.comm, ts));
  PetscCall(TSSetProblemType(*ts, TS_NONLINEAR));
  PetscCall(TSSetApplicationContext(*ts, app));
  PetscCall(ChooseType(*ts, &f));
  PetscCall(TSSetRHSFunction(*ts, NULL, TsRhs, app));
  if (f->created) PetscCall(f->created(*ts, app));
  if (f->on_vector) PetscCall(f->on_vector(sim->p.X));
  PetscCall(TSSetSolution(*ts, sim->p.X));
  PetscCall(TSSetTime(*ts, 0.0));
  PetscCall(TSSetMaxTime(*ts, o->t_end));
  PetscCall(TSSetMaxSteps(*ts, PETSC_MAX_INT - 1));
  PetscCall(TSSetExactFinalTime(*ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetErrorIfStepFails(*ts, PETSC_FALSE)); /* failure is a result */
  PetscCall(TSGetAdapt(*ts, &adapt));
  {
    PetscErrorCode ierr;
    PetscCall(SpamPushPetscOptionsErrorHandler("ts_*"));
    ierr = TSSetFromOptions(*ts);
    PetscCall(PetscPopErrorHandler());
    PetscCall(ierr); /* reported once already */
  }
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  if (help) PetscCall(SpamTSSundialsHelp(*ts, o));
  PetscCall(CheckInitTime(*ts));
  {
    /* -ts_view is PETSc's, acted on at the end of the run (time_loop.c) as TSSolve does:
     * queried here so that the check of unused options knows the run takes it. */
    PetscBool view;
    PetscCall(PetscOptionsHasName(NULL, NULL, "-ts_view", &view));
  }
  /* Our options win over PETSc's for the quantities both read. */
  PetscCall(TSSetMaxTime(*ts, o->t_end));
  PetscCall(TSSetTimeStep(*ts, o->dt_first > 0 ? o->dt_first : 0.05 * sim->model.kernel.h / app->w.vscale));
  PetscCall(Tolerances(*ts, app));
  PetscCall(SpamErrorNormSetTS(*ts, o->error_norm)); /* -error_norm as PETSc's adaptor norm */
  PetscCall(TSSetUp(*ts));
  if (f->set_up) PetscCall(f->set_up(*ts, app));
  PetscFunctionReturn(0);
}

/* The velocity scale c0 is the sound speed of the state SpamTSCreate finds in sim->p.X: a
 * run restarted from a checkpoint must get back the one of its start, or its error
 * weights (and so its steps) differ from the uninterrupted run's. */
PetscErrorCode SpamTSSetVelocityScale(TS ts, SpamTsApp *app, double c0)
{
  PetscFunctionBeginUser;
  PetscCheck(c0 > 0 && isfinite(c0), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "velocity scale %g is not a positive number", c0);
  app->w.vscale = c0;                /* arkode, cvode: read by SpamErrorWeights      */
  PetscCall(Tolerances(ts, app));    /* PETSc's methods: the vector tolerances      */
  PetscFunctionReturn(0);
}

/* PETSc's adaptors keep a work vector of the solution's length that TSReset does not
 * drop (TSAdaptChoose_Basic then copies the new X into the old one): only PETSc's methods
 * without an adaptor can be reset onto another length. */
PetscBool SpamTSTypeCanFollow(const char *type, const char *adapt)
{
  const SpamTSFamily *f = SpamTSFamilyNamed(type);

  if (!f) return PETSC_FALSE;
  return (PetscBool)(f->follow == SPAM_TS_FOLLOW_RESIZE || f->follow == SPAM_TS_FOLLOW_CARRY || (f->follow == SPAM_TS_FOLLOW_RESET_FIXED && !strcmp(adapt, TSADAPTNONE)));
}

PetscBool SpamTSCanFollow(TS ts)
{
  TSType      type;
  TSAdapt     a;
  TSAdaptType atype;

  if (TSGetType(ts, &type) || !type || TSGetAdapt(ts, &a) || TSAdaptGetType(a, &atype)) return PETSC_FALSE;
  return SpamTSTypeCanFollow(type, atype ? atype : TSADAPTNONE);
}

PetscErrorCode SpamTSFollowParticles(TS ts, SpamTsApp *app, PetscBool *followed)
{
  const SpamTSFamily *f;
  PetscReal           t, dt;
  PetscInt            step;

  PetscFunctionBeginUser;
  *followed = PETSC_FALSE;
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->follow == SPAM_TS_FOLLOW_RESIZE) {
    PetscCall(SpamTSARKodeResize(ts, app->sim->p.X));
    *followed = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  if (f->follow == SPAM_TS_FOLLOW_CARRY) {
    PetscCall(f->follow_carry(ts, app));
    *followed = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  if (!SpamTSCanFollow(ts)) PetscFunctionReturn(0);
  /* PETSc 3.18 has no TS resize: TSReset drops the work vectors and tolerances, which are
   * made again for the new X; time, step number and step size stay with the TS. */
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(TSGetStepNumber(ts, &step));
  PetscCall(TSReset(ts));
  if (f->on_vector) PetscCall(f->on_vector(app->sim->p.X));
  PetscCall(TSSetSolution(ts, app->sim->p.X));
  PetscCall(Tolerances(ts, app));
  PetscCall(TSSetUp(ts));
  PetscCall(TSSetTime(ts, t));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetStepNumber(ts, step));
  PetscCall(TSRestartStep(ts)); /* rk's first stage is evaluated, not taken from the new, empty last stage */
  *followed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSAppDestroy(SpamTsApp *app)
{
  PetscFunctionBeginUser;
  if (app->xcache) PetscCall(PetscFree2(app->xcache, app->acache));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSDescribe(TS ts, char *method, size_t mlen, char *adapt, size_t alen, double *fixed_dt)
{
  const SpamTSFamily *f;
  const char         *sub = "";
  TSAdapt             a;
  TSAdaptType         atype;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  *fixed_dt = 0.0;
  if (f->describe) PetscCall(f->describe(ts, &sub, adapt, alen, fixed_dt));
  else {
    if (f->sub_type) PetscCall(f->sub_type(ts, &sub));
    PetscCall(TSGetAdapt(ts, &a));
    PetscCall(TSAdaptGetType(a, &atype));
    PetscCall(PetscStrncpy(adapt, atype, alen));
    if (!strcmp(atype, TSADAPTNONE)) PetscCall(TSGetTimeStep(ts, fixed_dt));
  }
  (void)snprintf(method, mlen, "%s%s%s", f->type, sub[0] ? " " : "", sub);
  PetscFunctionReturn(0);
}
