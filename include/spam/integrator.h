/* One integrator interface. Every method is a PETSc TS type, so one TSStep loop serves
 * them all: ARKODE ERKStep ("arkode"), ARKStep with the diffusion implicit ("arkode_imex")
 * and CVODE Adams ("cvode") are registered as TS types by spam-ark, and PETSc's explicit types (rk, ssp, euler, basicsymplectic) are used as
 * they are, with a kick-drift-kick Verlet registered for basicsymplectic (its kdk and dkd
 * schemes stepped by spam-ark's own step on the state vector). */
#ifndef SPAM_INTEGRATOR_H
#define SPAM_INTEGRATOR_H
#include <petscts.h>
#include <spam/run.h>
#include <spam/weights.h>
#include <arkode/arkode_erkstep.h>

#define SPAM_TSARKODE "arkode"
#define SPAM_TSCVODE  "cvode"
#define SPAM_TSARKODE_IMEX "arkode_imex"
#define SPAM_TSBLOCK_KDK "block_kdk"
/* The fraction of the stability function's step ARKODE takes (SpamSundialsStability). */
#define SPAM_ARK_CFL_FRACTION 0.5

/* END: a step shortened to land on t_end (the only stop of a run that interpolates its
 * outputs); OUTPUT: shortened to land on an output time (-output_stop, or a method or scene
 * that cannot interpolate: see output_mode.c). */
typedef enum { SPAM_LIMIT_ACCURACY, SPAM_LIMIT_FIXED, SPAM_LIMIT_OUTPUT, SPAM_LIMIT_CFL, SPAM_LIMIT_FORCE, SPAM_LIMIT_END } SpamStepLimit;
extern const char *const SpamStepLimitNames[];

/* The options of the arkode TS type (arkode_options.c), read by its setfromoptions. */
typedef struct {
  char      table[64], adapt[16];
  double    fixed_step;      /* 0: adaptive                                               */
  double    safety, max_growth, max_first_growth, max_efail_growth; /* 0: ARKODE's       */
  double    adapt_params[3]; /* controller gains k1, k2, k3 (n_adapt_params 0: ARKODE's) */
  PetscInt  n_adapt_params;
  PetscBool fixed_by_ts;     /* the fixed step is -ts_dt, asked by -ts_adapt_type none    */
  PetscBool sundials_stats;  /* print ERKStepPrintAllStats at the end of the run          */
} SpamArkodeSettings;

/* The application context of the TS. The weights come first: SUNDIALS hands one user-data
 * pointer to the RHS and to the error-weight function, which reads a SpamWeightsCtx. */
typedef struct {
  SpamWeightsCtx        w;
  SpamSim              *sim;
  const SpamRunOptions *o;
  PetscInt              bad;           /* particle with a non-finite position, or -1      */
  double                tbad;          /* the stage time at which it was seen             */
  PetscErrorCode        perr;          /* a PETSc error inside a SUNDIALS callback        */
  double                bound;         /* physical step bound last computed (inf: none)   */
  SpamStepLimit         bound_which;   /* which of cfl and force set it                   */
  long                  bound_calls;
  PetscBool             self_stepping; /* arkode and cvode pick steps and stop times      */
  char                  fail[256];     /* SUNDIALS flag name and message of a failure     */
  /* kick-drift-kick: the force at the end of a step is the force at the next start */
  double               *xcache, *acache;
  PetscBool             cache_valid;
  PetscObjectState      cache_state;   /* the state vector's when its positions were last
                                        * known to be xcache's (-1: not known)         */
  /* adaptive rk (rk_rollback.c): the step, time and rejections at the last stage 0 (a
   * retry repeats the first two), whether the next RHS call is stage 0 of a first attempt
   * (1) or of a retry (2), and whether the first attempt's f(y_n) is in the stage vector */
  PetscInt              retry_step, retry_reject;
  double                retry_t;
  int                   stage0;
  PetscBool             f0_kept;
  void                 *imex_pc;       /* arkode_imex's stage preconditioner (imex_precond.h), or NULL */
} SpamTsApp;

/* SUNDIALS callbacks shared by the arkode and cvode types (user data: a SpamTsApp). */
int  SpamSundialsRhs(realtype t, N_Vector y, N_Vector ydot, void *data);
/* The explicit part and the diffusion part of an IMEX split (model.h's SpamRhsPart). */
int  SpamSundialsRhsExplicit(realtype t, N_Vector y, N_Vector ydot, void *data);
int  SpamSundialsRhsDiffusion(realtype t, N_Vector y, N_Vector ydot, void *data);
/* ARKODE's stability function: the physical step bound (SpamStepBound) of y. */
int  SpamSundialsStability(N_Vector y, realtype t, realtype *hstab, void *data);
void SpamSundialsErrHandler(int code, const char *module, const char *function, char *msg, void *data);
/* Writes "<call> returned <FLAG_NAME> (<last SUNDIALS message>)" into app->fail. */
void SpamSundialsFailure(SpamTsApp *app, const char *call, char *(*namefn)(long), int flag);

/* Reads and checks the arkode options inside a PetscOptionsBegin block (o: the run's end
 * time, step floor and -ts_dt; erk: with ERKStep's -arkode_table, else the step options
 * alone, which arkode_imex shares); ERKStep's controller number of an -arkode_adapt name. */
PetscErrorCode SpamArkodeOptionsRead(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o, PetscBool erk, SpamArkodeSettings *s);
int            SpamArkodeAdaptMethod(const char *name);
/* -ts_adapt_type for an arkode or arkode_imex TS (type_name): none (with -ts_dt) sets
 * s->fixed_step; others refused. */
PetscErrorCode SpamArkodeAdaptType(const SpamRunOptions *o, const char *type_name, SpamArkodeSettings *s);
/* The step settings of an arkode or arkode_imex TS; NULL for another type. */
PetscErrorCode SpamTSARKodeGetSettings(TS ts, const SpamArkodeSettings **s);
/* With -help: lists the options of the SUNDIALS type that is not ts's own (PETSc lists only
 * the chosen type's), so -help shows every option of spam-ark with its default. */
PetscErrorCode SpamTSSundialsHelp(TS ts, const SpamRunOptions *o);
PetscErrorCode SpamCVodeOptionsRead(PetscOptionItems *PetscOptionsObject, PetscInt *max_order, PetscBool *stats);

/* What a restarted arkode run needs to continue bit for bit: the next step size, the
 * controller's error and step history (ERKStep's ehist, hhist after the last accepted
 * step) and the steps accepted so far (the Gustafsson controllers' first-step form). */
typedef struct {
  double h_next, ehist[2], hhist[2];
  long   accepted;
} SpamArkodeHistory;
/* After an accepted step: what a restart needs to continue bit for bit. */
PetscErrorCode SpamTSARKodeGetHistory(TS ts, SpamArkodeHistory *h);
/* On a freshly set-up arkode TS whose time and solution are the checkpoint's (TSSetTime
 * and the state copied into the solution; before or after TSSetUp: ERKStep is
 * re-initialised from them here): the first step is h_next, the controller uses the saved
 * history until ARKODE's own catches up, and the first step's growth limit is the
 * ordinary one (not ARKODE's larger first-step growth). */
PetscErrorCode SpamTSARKodeSetHistory(TS ts, const SpamArkodeHistory *h);
/* Whether the state after the last step may be checkpointed: always for other types; for
 * arkode only if that step did not end on the stop time (its output is then ARKODE's
 * interpolant, not y_n) and no clamp to the stop time is pending for the next step
 * (ERKStep then takes h eta, not the reported step): t + h_next < tstop (1 - 1e-12). */
PetscErrorCode SpamTSARKodeCheckpointable(TS ts, PetscBool *ok);
/* After a migration (the particles moved between ranks): the arkode TS continues on the
 * new solution vector X of another local length, its step and error history kept
 * (ERKStepResize). */
PetscErrorCode SpamTSARKodeResize(TS ts, Vec X);
/* After a migration: the TS continues on app->sim->p.X (another local length). arkode keeps
 * its step and error history (SpamTSARKodeResize); rk, ssp and euler with fixed steps are
 * reset on the new vector with their time, step number and step size (TSReset +
 * TSSetSolution: PETSc 3.18 has no resize; rk evaluates its first stage again). The
 * others cannot follow (*followed false) and keep the first distribution: PETSc's
 * adaptors hold a vector of the old length, CVODE would restart at order 1 with a tiny
 * step, the Verlet type's split index sets and force cache are made for one length. */
PetscErrorCode SpamTSFollowParticles(TS ts, SpamTsApp *app, PetscBool *followed);
/* Whether a TS of this type and adaptor (a TS) can follow a migration: arkode, and rk,
 * ssp, euler with fixed steps (-ts_adapt_type none). */
PetscBool SpamTSTypeCanFollow(const char *type, const char *adapt);
PetscBool SpamTSCanFollow(TS ts);

/* ERKStep's built-in controllers (pid, pi, i, expgus, impgus with their default or
 * -arkode_adapt_params gains, order p) as an ARKAdaptFn that carries its own history
 * across a restart (arkode_controller.c). The arkode type always uses it. */
typedef struct {
  int               method; /* SpamArkodeAdaptMethod                                */
  double            k[3];   /* gains                                                */
  double            growth; /* largest growth after a step (-arkode_max_growth)     */
  void             *mem;    /* the ERKStep it controls                              */
  SpamArkodeHistory saved;  /* stands in while ERKStep's own history is blank       */
  double            last_e[2], last_h[2]; /* (e1, e2), (h1, h2) of the last attempt */
} SpamArkodeController;
PetscErrorCode SpamArkodeControllerSetUp(SpamArkodeController *c, const SpamArkodeSettings *s, void *mem);
int            SpamArkodeControllerAdapt(N_Vector y, realtype t, realtype h1, realtype h2, realtype h3, realtype e1, realtype e2, realtype e3, int q, int p, realtype *hnew, void *data);
PetscErrorCode SpamArkodeControllerGet(const SpamArkodeController *c, SpamArkodeHistory *h);
PetscErrorCode SpamArkodeControllerResume(SpamArkodeController *c, const SpamArkodeHistory *h);
/* ARKODE's table by name, with the last stage time moved off 1 for tables whose last
 * stage is not the solution (see ts_arkode.c): what the arkode type hands ERKStep. */
PetscErrorCode SpamArkodeLoadTable(const char *name, ARKodeButcherTable *B);

/* Deterministic linear combinations (det_combination.c): sums that skip zero coefficients
 * and add the terms in index order, so that a combination does not depend on how many
 * vectors it has. On the N_Vector (its clones inherit it) for ERKStep; on the Vec's maxpy
 * (its duplicates inherit it) for PETSc's rk. */
PetscErrorCode SpamNVectorDeterministic(N_Vector y);
/* Arms (around one ERKStepEvolve, while only the integrator writes y) or disarms the memo
 * of the last combination written into y, which lets a combination that y already holds
 * be skipped: an FSAL table's solution, the same sum as its last stage (det_combination.c).
 * Composed on y's Vec at the first call. */
PetscErrorCode SpamNVectorCombinationArm(N_Vector y, PetscBool armed);
/* Clones of y (and of its clones) over arrays that are not written at creation
 * (nvector_unwritten.c): a vector the integrator never writes takes no resident memory. */
void SpamNVectorCloneUnwritten(N_Vector y);
PetscErrorCode SpamNVectorReserve(Vec y, PetscInt count);
PetscErrorCode SpamVecDeterministicMAXPY(Vec X);
/* The retry of a rejected rk step keeps the first attempt's stage 0 derivative f(y_n)
 * (rk_rollback.c): the uninterrupted run reuses it (FSAL), a restarted one would
 * evaluate it again at the rolled-back state. Installs a TSSetPreStage hook. */
PetscErrorCode SpamTSRKKeepFirstStage(TS ts, SpamTsApp *app);
/* In the RHS of a PETSc method: whether this call is stage 0 of a retried rk step whose
 * output vector still holds f(y_n) from the first attempt (then the call must leave it),
 * and the bookkeeping after a call that did evaluate. */
PetscBool SpamTSRKKeepStageZero(SpamTsApp *app);
void      SpamTSRKEvaluated(SpamTsApp *app);

/* Registers "arkode", "cvode" and the Verlet schemes "kdk" and "dkd"; call once. */
PetscErrorCode SpamIntegratorsRegister(void);
PetscErrorCode SpamTSCreate_ARKode(TS ts);
PetscErrorCode SpamTSCreate_CVode(TS ts);
PetscErrorCode SpamTSCreate_ARKodeImex(TS ts);
PetscErrorCode SpamTSCreate_Block(TS ts);
/* The step settings of an arkode_imex TS; NULL for another type. */
PetscErrorCode SpamTSARKodeImexGetSettings(TS ts, const SpamArkodeSettings **s);
PetscErrorCode SpamSymplecticRegister(void);

/* Creates the TS on sim->p.X from the options (validated: an unknown type or scheme is bad
 * input) with the RHS, tolerances and, for basicsymplectic, the position/momentum split. */
PetscErrorCode SpamTSCreate(SpamSim *sim, const SpamRunOptions *o, SpamTsApp *app, TS *ts);
PetscErrorCode SpamTSAppDestroy(SpamTsApp *app);
/* A restart: the velocity scale of the run's start (app->w.vscale, which SpamTSCreate takes
 * from the sound speed of the state it finds), for the error weights and tolerances. */
PetscErrorCode SpamTSSetVelocityScale(TS ts, SpamTsApp *app, double c0);
/* Splits for basicsymplectic; refuses (bad input) a model whose state is more than r, v. */
PetscErrorCode SpamSymplecticSetUp(TS ts, SpamTsApp *app);
/* Makes VecGetSubVector on X (and on vectors duplicated from it later) reuse one
 * sub-vector and scatter per index set instead of creating them on every call. */
PetscErrorCode SpamVecCacheSubVectors(Vec X);
/* "rk 5dp", "arkode ARKODE_DORMAND_PRINCE_7_4_5", ...; the adaptor; the fixed step or 0. */
PetscErrorCode SpamTSDescribe(TS ts, char *method, size_t mlen, char *adapt, size_t alen, double *fixed_dt);

/* How the outputs of run r are taken: "interpolated" (the method's dense output between
 * steps, TSInterpolate; the only stop is t_end), "stopped" (steps are cut to land on each
 * output time) or "steps" (fixed steps, whose ends the output times are rounded to); why[]
 * says why a run does not interpolate. */
typedef enum { SPAM_OUTPUT_INTERPOLATED, SPAM_OUTPUT_STOPPED, SPAM_OUTPUT_STEPS } SpamOutputMode;
extern const char *const SpamOutputModeNames[];
PetscErrorCode SpamTSOutputMode(TS ts, const SpamTsApp *app, double fixed_dt, SpamOutputMode *mode, char *why, size_t len);

/* ARKODE's or CVODE's table of statistics (its PrintAllStats, SUN_OUTPUTFORMAT_TABLE) on
 * file: always with force (-ts_view), else only under -sundials_stats; nothing for the
 * other types. */
PetscErrorCode SpamTSSundialsStats(TS ts, FILE *file, PetscBool force);
/* -ts_adapt_monitor for arkode, cvode and basicsymplectic, whose steps never consult
 * PETSc's adaptor: a line per accepted step (the step from t0); nothing for the others. */
PetscErrorCode SpamTSAdaptMonitorSelf(TS ts, long step, double t0, double dt, long rejected);

/* A restart of the cvode TS (after TSSetUp): its first step. */
PetscErrorCode SpamTSCVodeSetInitStep(TS ts, double h);

/* A checkpoint being continued (checkpoint.h). */
typedef struct SpamRestart SpamRestart;

/* Integrates to t_end with the TS made by SpamTSCreate (any method), writing outputs as
 * it goes, from t = 0 or from the checkpoint rs (NULL: a new run); an unstable run ends
 * with r->status = UNSTABLE, not an error. */
PetscErrorCode SpamRun(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, SpamRestart *rs, SpamRunResult *r);

/* Physical step bound of state y: min(cfl h / c_max, force sqrt(h / |a|max)), each term
 * only when its coefficient is positive; +inf when both are off. |a| is taken from the
 * last force evaluation (sim->acc). */
PetscErrorCode SpamStepBound(SpamSim *sim, const SpamRunOptions *o, const double *y, double *dt, SpamStepLimit *which);
#endif
