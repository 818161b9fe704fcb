/* ARKODE ARKStep as a PETSc TS type ("arkode_imex"): an additive Runge-Kutta method whose
 * implicit part is the diffusion (the pair Laplacians of viscosity and conduction, with the
 * viscous force's work: model.h's SPAM_RHS_DIFFUSION) and whose explicit part is the rest
 * (pressure, the flow scheme's laws, gravity, the motion of the particles). Diffusion
 * bounds an explicit step by h^2/nu and h^2/chi; here it bounds nothing, and the step is
 * set by the error and by the explicit part's stability.
 *
 * The stages' implicit systems are solved by Newton's method (SUNNonlinSol_Newton) with
 * GMRES (SUNLinSol_SPGMR) on ARKStep's difference-quotient Jacobian-vector product, each
 * Krylov iteration one evaluation of the diffusion part: unpreconditioned
 * (-arkode_imex_pc none: no matrix is formed), or preconditioned on the right by the
 * assembled diffusion Jacobian (-arkode_imex_pc diffusion, imex_precond.c), whose product
 * may also stand for the difference quotient after each stage's first linear solve
 * (-arkode_imex_jv assembled: a Krylov iteration then costs a sparse product instead of an
 * evaluation; Newton's residual, the true one, still decides convergence). The error
 * weights, the controllers and the stability function (-step_cfl, -step_force) are those
 * of the arkode type; the controller is ARKODE's own (a restart
 * does not carry its history). Like arkode, TSStep takes one ARKStep step towards
 * ts->max_time. */
#include <petsc/private/tsimpl.h>
#include "ts_family.h"
#include <spam/errors.h>
#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_petsc.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>
#include <sunlinsol/sunlinsol_spgmr.h>
#include "imex_precond.h"

/* The additive pairs of ARKODE 6.4 (Kennedy and Carpenter), by the name the option takes:
 * the implicit (ESDIRK) and explicit tables. */
static const char *const ImexTables[]   = {"ARK324L2SA", "ARK436L2SA", "ARK437L2SA", "ARK548L2SA", "ARK548L2SAb"};
static const char *const ImexImplicit[] = {"ARKODE_ARK324L2SA_DIRK_4_2_3", "ARKODE_ARK436L2SA_DIRK_6_3_4", "ARKODE_ARK437L2SA_DIRK_7_3_4", "ARKODE_ARK548L2SA_DIRK_8_4_5", "ARKODE_ARK548L2SAb_DIRK_8_4_5"};
static const char *const ImexExplicit[] = {"ARKODE_ARK324L2SA_ERK_4_2_3", "ARKODE_ARK436L2SA_ERK_6_3_4", "ARKODE_ARK437L2SA_ERK_7_3_4", "ARKODE_ARK548L2SA_ERK_8_4_5", "ARKODE_ARK548L2SAb_ERK_8_4_5"};
#define NIMEX 5
/* The stage preconditioner: none, or the diffusion part's assembled Jacobian. */
static const char *const ImexPCs[] = {"none", "diffusion"};
#define NIMEX_PC 2
/* GMRES's products J v: ARKStep's difference quotient (one evaluation of the diffusion part
 * each, the viscous work's term included), or the assembled J's (a sparse product). */
static const char *const ImexJvs[] = {"difference", "assembled"};
#define NIMEX_JV 2

/* The solver options (-arkode_imex_*). */
/* Vectors ARKStep clones besides its stages' right-hand sides (SUNDIALS 6.4.1: weights,
 * solution and predictor work, four temporaries, the Hermite interpolant's four), Newton's
 * and the linear-solver interface's work, and GMRES's beyond its Krylov basis. */
#define SPAM_ARK_IMEX_WORK_VECTORS 28

typedef struct {
  char     table[32];
  double   nonlin_coef; /* Newton's tolerance as a fraction of the error test's       */
  double   eps_lin;     /* GMRES's tolerance as a fraction of Newton's                */
  PetscInt max_nonlin;  /* Newton iterations of a stage before the step is retried    */
  PetscInt krylov_dim;  /* GMRES's Krylov dimension (no restarts)                     */
  char     pc[16];      /* the stage preconditioner (ImexPCs)                         */
  char     jv[16];      /* GMRES's products (ImexJvs)                                 */
  PetscInt predictor;   /* ARKStepSetPredictorMethod: the stages' first Newton iterate */
  PetscInt lsetup_freq; /* ARKStepSetLSetupFrequency: steps between set-ups (0: ARKODE's) */
  PetscBool deduce;     /* ARKStepSetDeduceImplicitRhs: the stage's f_I from its solve */
  PetscBool reuse;      /* keep the diffusion part's position fields (diffusion_cache.h) */
} SpamImexSolver;

typedef struct {
  SUNContext         sunctx;
  N_Vector           y;
  void              *mem;
  SUNNonlinearSolver nls;
  SUNLinearSolver    ls;
  SpamArkodeSettings set;    /* the step options it shares with arkode (arkode_options.c) */
  SpamImexSolver     solver; /* its own                                                 */
  SpamImexPC         pc;     /* -arkode_imex_pc diffusion                               */
} TS_SpamARKImex;

static PetscErrorCode SolverDefaults(SpamImexSolver *v)
{
  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(v->table, "ARK436L2SA", sizeof v->table));
  v->nonlin_coef = 0.1;  /* ARKODE's defaults */
  /* 0.2 (ARKODE's 0.05): on Couette at Re 0.32 the same errors with 10-20 % fewer GMRES
   * iterations (docs/integrators.md) */
  v->eps_lin     = 0.2;
  v->max_nonlin  = 3;
  v->krylov_dim  = 50; /* a step of ~70 explicit diffusion limits takes ~30 GMRES iterations (ARKODE: 5) */
  PetscCall(PetscStrncpy(v->pc, "diffusion", sizeof v->pc)); /* see SpamImexPCCreate and docs/integrators.md */
  /* difference: the assembled J is the one of ARKODE's last set-up, stale between set-ups
   * in the positions and, beside a moving wall, in the work's derivative (a small difference
   * of near velocities): Newton then converges linearly, and at -ts_rtol 1e-9 with fixed
   * steps on Couette its three iterations no longer suffice; where it converges it saves
   * 5-13 % of the implicit evaluations (Couette at Re 0.32, docs/integrators.md) */
  PetscCall(PetscStrncpy(v->jv, "difference", sizeof v->jv));
  /* 0, ARKODE's (the previous solution). 5, minimum correction (the stage's known part,
   * whose positions are the stage's own, so every later evaluation of the stage reuses its
   * position fields, diffusion_cache.h) takes fewer implicit evaluations on Couette, but at
   * large fixed steps Newton's test accepts its iterate early: on the heat mode at T/8 the
   * error is 1e-3 of the amplitude and ARK436L2SA's order falls to 2.4 (run_imex_order) */
  v->predictor   = 0;
  v->lsetup_freq = 0;
  /* PETSC_FALSE: the deduced f_I is not the pair sums', and the energy books drift by the
   * Newton tolerance's size (1e-2 on Couette at Re 0.32) */
  v->deduce      = PETSC_FALSE;
  v->reuse       = PETSC_TRUE; /* the same bits, fewer pair walks */
  PetscFunctionReturn(0);
}

static PetscErrorCode SolverOptionsRead(PetscOptionItems *PetscOptionsObject, SpamImexSolver *v)
{
  char val[64];

  PetscFunctionBeginUser;
  PetscCall(SolverDefaults(v));
  PetscOptionsHeadBegin(PetscOptionsObject, "ARKODE ARKStep IMEX options (-ts_type arkode_imex)");
  PetscCall(PetscOptionsString("-arkode_imex_table", "Additive Runge-Kutta pair: ARK324L2SA, ARK436L2SA, ARK437L2SA, ARK548L2SA, ARK548L2SAb", "README", v->table, v->table, sizeof v->table, NULL));
  PetscCall(PetscOptionsReal("-arkode_imex_nonlin_coef", "Newton tolerance of a stage, as a fraction of the error test's", "README", v->nonlin_coef, &v->nonlin_coef, NULL));
  PetscCall(PetscOptionsReal("-arkode_imex_eps_lin", "GMRES tolerance, as a fraction of Newton's", "README", v->eps_lin, &v->eps_lin, NULL));
  PetscCall(PetscOptionsInt("-arkode_imex_max_nonlin_iters", "Newton iterations of a stage before the step is retried smaller", "README", v->max_nonlin, &v->max_nonlin, NULL));
  PetscCall(PetscOptionsInt("-arkode_imex_krylov_dim", "GMRES Krylov dimension (no restarts)", "README", v->krylov_dim, &v->krylov_dim, NULL));
  PetscCall(PetscOptionsString("-arkode_imex_pc", "GMRES preconditioner: none, or diffusion (the assembled diffusion Jacobian, solved by the KSP of prefix -imex_pc_)", "README", v->pc, v->pc, sizeof v->pc, NULL));
  PetscCall(PetscOptionsString("-arkode_imex_jv", "GMRES's products J v: difference (ARKStep's difference quotient, one evaluation each) or, with -arkode_imex_pc diffusion, assembled (the assembled Jacobian's sparse product, from each stage's second linear solve on)", "README", v->jv, v->jv, sizeof v->jv, NULL));
  PetscCall(PetscOptionsInt("-arkode_imex_predictor", "The stages' first Newton iterate (ARKStepSetPredictorMethod): 0 trivial, 1 maximum order, 2 variable order, 3 cutoff, 5 minimum correction", "README", v->predictor, &v->predictor, NULL));
  PetscCall(PetscOptionsInt("-arkode_imex_lsetup_freq", "Steps between the linear solver's set-ups (ARKStepSetLSetupFrequency; 0: ARKODE's 20)", "README", v->lsetup_freq, &v->lsetup_freq, NULL));
  PetscCall(PetscOptionsBool("-arkode_imex_deduce", "Take a stage's implicit right-hand side from its Newton solve instead of one more evaluation (ARKStepSetDeduceImplicitRhs)", "README", v->deduce, &v->deduce, NULL));
  PetscCall(PetscOptionsBool("-arkode_imex_reuse_fields", "Reuse the diffusion part's densities and moments between its evaluations at bitwise the same positions (the same results)", "README", v->reuse, &v->reuse, NULL));
  PetscOptionsHeadEnd();
  PetscCall(SpamCheckAllowed("-arkode_imex_jv", v->jv, ImexJvs, NIMEX_JV));
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, v->predictor));
  if (v->predictor < 0 || v->predictor > 5 || v->predictor == 4) SPAM_BAD_INPUT("-arkode_imex_predictor", val, "must be 0, 1, 2, 3 or 5");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, v->lsetup_freq));
  if (v->lsetup_freq < 0 || v->lsetup_freq > 1000) SPAM_BAD_INPUT("-arkode_imex_lsetup_freq", val, "must be 0 to 1000");
  if (strcmp(v->pc, "diffusion") && !strcmp(v->jv, "assembled")) SPAM_BAD_INPUT("-arkode_imex_jv", v->jv, "needs the assembled Jacobian of -arkode_imex_pc diffusion (this run: -arkode_imex_pc %s)", v->pc);
  PetscCall(SpamCheckAllowed("-arkode_imex_table", v->table, ImexTables, NIMEX));
  PetscCall(SpamCheckAllowed("-arkode_imex_pc", v->pc, ImexPCs, NIMEX_PC));
  PetscCall(SpamOptionText("-arkode_imex_nonlin_coef", v->nonlin_coef, val, sizeof val));
  if (!(v->nonlin_coef > 0.0) || !isfinite(v->nonlin_coef)) SPAM_BAD_INPUT("-arkode_imex_nonlin_coef", val, "must be a positive number");
  PetscCall(SpamOptionText("-arkode_imex_eps_lin", v->eps_lin, val, sizeof val));
  if (!(v->eps_lin > 0.0) || !isfinite(v->eps_lin)) SPAM_BAD_INPUT("-arkode_imex_eps_lin", val, "must be a positive number");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, v->max_nonlin));
  if (v->max_nonlin < 1 || v->max_nonlin > 100) SPAM_BAD_INPUT("-arkode_imex_max_nonlin_iters", val, "must be 1 to 100");
  PetscCall(PetscSNPrintf(val, sizeof val, "%" PetscInt_FMT, v->krylov_dim));
  if (v->krylov_dim < 1 || v->krylov_dim > 500) SPAM_BAD_INPUT("-arkode_imex_krylov_dim", val, "must be 1 to 500");
  PetscFunctionReturn(0);
}

/* The pair's two tables. ARKStep in SUNDIALS 6.4.1 reuses the last stage's derivatives as
 * the next step's first when that stage sits at c = 1, as ERKStep does (ts_arkode.c); the
 * explicit tables' last rows are not their b, so the stage is not the solution. The
 * right-hand side does not depend on t: the stage time moves to 1 - 1e-6 in both tables
 * (ARKStep wants their c equal), which changes nothing but the reuse. */
static PetscErrorCode LoadTables(const char *name, ARKodeButcherTable *Bi, ARKodeButcherTable *Be)
{
  int       k = 0, s;
  PetscBool last_is_solution = PETSC_TRUE;

  PetscFunctionBeginUser;
  while (k < NIMEX && strcmp(name, ImexTables[k])) k++;
  PetscCheck(k < NIMEX, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "unknown additive table %s", name);
  *Bi = ARKodeButcherTable_LoadDIRKByName(ImexImplicit[k]);
  *Be = ARKodeButcherTable_LoadERKByName(ImexExplicit[k]);
  PetscCheck(*Bi && *Be, PETSC_COMM_SELF, PETSC_ERR_LIB, "ARKodeButcherTable_Load*ByName(%s) failed", name);
  s = (*Be)->stages;
  for (int j = 0; j < s; j++)
    if ((*Be)->A[s - 1][j] != (*Be)->b[j] || (*Bi)->A[s - 1][j] != (*Bi)->b[j]) last_is_solution = PETSC_FALSE;
  if (!last_is_solution && PetscAbsReal((*Be)->c[s - 1] - 1.0) < 1e-8) (*Be)->c[s - 1] = (*Bi)->c[s - 1] = 1.0 - 1e-6;
  PetscFunctionReturn(0);
}

/* The step options: a fixed step, or ARKODE's controller with the arkode type's settings. */
static PetscErrorCode ConfigureSteps(void *mem, const SpamArkodeSettings *o)
{
  realtype gains[3];

  PetscFunctionBeginUser;
  if (o->fixed_step > 0) {
    PetscCallARK(ARKStepSetFixedStep(mem, o->fixed_step));
    PetscFunctionReturn(0);
  }
  for (int k = 0; k < 3; k++) gains[k] = o->adapt_params[k];
  /* idefault 1: the controller's own gains; pq 0: the embedding's order, as for arkode */
  PetscCallARK(ARKStepSetAdaptivityMethod(mem, SpamArkodeAdaptMethod(o->adapt), o->n_adapt_params == 0, 0, gains));
  if (o->safety > 0) PetscCallARK(ARKStepSetSafetyFactor(mem, o->safety));
  if (o->max_growth > 0) PetscCallARK(ARKStepSetMaxGrowth(mem, o->max_growth));
  if (o->max_first_growth > 0) PetscCallARK(ARKStepSetMaxFirstGrowth(mem, o->max_first_growth));
  if (o->max_efail_growth > 0) PetscCallARK(ARKStepSetMaxEFailGrowth(mem, o->max_efail_growth));
  PetscFunctionReturn(0);
}

static PetscBool Preconditioned(const TS_SpamARKImex *ark)
{
  return (PetscBool)!strcmp(ark->solver.pc, "diffusion");
}

/* Newton's method with matrix-free GMRES (ARKStep's difference-quotient J v: no
 * ARKStepSetJacTimes), preconditioned on the right or not at all. */
static PetscErrorCode ConfigureSolver(TS_SpamARKImex *ark, MPI_Comm comm)
{
  const PetscBool pre = Preconditioned(ark);

  PetscFunctionBeginUser;
  ark->nls = SUNNonlinSol_Newton(ark->y, ark->sunctx);
  PetscCheck(ark->nls, comm, PETSC_ERR_LIB, "SUNNonlinSol_Newton failed");
  PetscCallARK(ARKStepSetNonlinearSolver(ark->mem, ark->nls));
  ark->ls = SUNLinSol_SPGMR(ark->y, pre ? SUN_PREC_RIGHT : SUN_PREC_NONE, (int)ark->solver.krylov_dim, ark->sunctx);
  PetscCheck(ark->ls, comm, PETSC_ERR_LIB, "SUNLinSol_SPGMR failed");
  PetscCallARKLS(ARKStepSetLinearSolver(ark->mem, ark->ls, NULL));
  if (pre) PetscCallARKLS(ARKStepSetPreconditioner(ark->mem, SpamImexPCSetup, SpamImexPCSolve));
  if (pre && !strcmp(ark->solver.jv, "assembled")) PetscCallARKLS(ARKStepSetJacTimes(ark->mem, SpamImexPCJacTimesSetup, SpamImexPCJacTimes));
  PetscCallARKLS(ARKStepSetEpsLin(ark->mem, ark->solver.eps_lin));
  PetscCallARK(ARKStepSetNonlinConvCoef(ark->mem, ark->solver.nonlin_coef));
  PetscCallARK(ARKStepSetMaxNonlinIters(ark->mem, (int)ark->solver.max_nonlin));
  PetscCallARK(ARKStepSetPredictorMethod(ark->mem, (int)ark->solver.predictor));
  if (ark->solver.lsetup_freq > 0) PetscCallARK(ARKStepSetLSetupFrequency(ark->mem, (int)ark->solver.lsetup_freq));
  PetscCallARK(ARKStepSetDeduceImplicitRhs(ark->mem, ark->solver.deduce ? SUNTRUE : SUNFALSE));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetUp_SpamARKImex(TS ts)
{
  TS_SpamARKImex    *ark = (TS_SpamARKImex *)ts->data;
  MPI_Comm           comm = PetscObjectComm((PetscObject)ts);
  SpamTsApp         *app;
  ARKodeButcherTable Bi, Be;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCheck(app, comm, PETSC_ERR_ORDER, "the arkode_imex TS needs a SpamTsApp application context");
  if (!app->sim->model.rhs_part) SPAM_BAD_INPUT("-ts_type", SPAM_TSARKODE_IMEX, "treats diffusion implicitly: it needs -material gas with -gas_scheme flow, -diffusion_form pair, one smoothing length and -viscosity_shear or -conductivity > 0 (this run: model %s)", app->sim->model.name);
  app->sim->pair.dcache.enabled = ark->solver.reuse;
  PetscCallARK(SUNContext_Create((void *)&app->sim->p.comm, &ark->sunctx));
  ark->y = N_VMake_Petsc(ts->vec_sol, ark->sunctx);
  PetscCheck(ark->y, comm, PETSC_ERR_LIB, "N_VMake_Petsc failed");
  PetscCheck(N_VEnableFusedOps_Petsc(ark->y, SUNTRUE) == 0, comm, PETSC_ERR_LIB, "N_VEnableFusedOps_Petsc failed");
  PetscCall(SpamErrorNormAttach(ark->y, app->o->error_norm, app->sim->pair.reproducible)); /* -error_norm: cloned with y */
  PetscCall(LoadTables(ark->solver.table, &Bi, &Be));
  /* The memory for every vector ARKStep, Newton and GMRES will clone, asked for once, so
   * that a run short of memory ends with its one-line error (SpamNVectorReserve). */
  PetscCall(SpamNVectorReserve(ts->vec_sol, 2 * (PetscInt)Be->stages + ark->solver.krylov_dim + SPAM_ARK_IMEX_WORK_VECTORS));
  ark->mem = ARKStepCreate(SpamSundialsRhsExplicit, SpamSundialsRhsDiffusion, ts->ptime, ark->y, ark->sunctx);
  if (!ark->mem) {
    ARKodeButcherTable_Free(Bi);
    ARKodeButcherTable_Free(Be);
  }
  PetscCheck(ark->mem, comm, PETSC_ERR_LIB, "ARKStepCreate failed");
  PetscCallARK(ARKStepSetUserData(ark->mem, app));
  app->imex_pc = Preconditioned(ark) ? &ark->pc : NULL;
  ark->pc.ark        = !strcmp(ark->solver.jv, "assembled") ? ark->mem : NULL;
  ark->pc.jv_started = PETSC_FALSE;
  PetscCallARK(ARKStepSetErrHandlerFn(ark->mem, SpamSundialsErrHandler, app));
  {
    const int flag = ARKStepSetTables(ark->mem, Bi->q, Bi->p, Bi, Be); /* ARKStep keeps copies */
    ARKodeButcherTable_Free(Bi);
    ARKodeButcherTable_Free(Be);
    PetscCall(SpamCheckArkode(flag, "ARKStepSetTables"));
  }
  if (app->o->classic_weights) PetscCallARK(ARKStepSStolerances(ark->mem, app->o->rtol, app->o->atol));
  else PetscCallARK(ARKStepWFtolerances(ark->mem, SpamErrorWeights));
  PetscCall(ConfigureSolver(ark, comm));
  PetscCallARK(ARKStepSetMaxNumSteps(ark->mem, -1)); /* the loop counts steps itself */
  if (ts->max_reject > 0) {
    PetscCallARK(ARKStepSetMaxErrTestFails(ark->mem, (int)ts->max_reject));
    PetscCallARK(ARKStepSetMaxConvFails(ark->mem, (int)ts->max_reject));
  }
  PetscCall(ConfigureSteps(ark->mem, &ark->set));
  if (ark->set.fixed_step <= 0 && app->o->dt_first > 0) PetscCallARK(ARKStepSetInitStep(ark->mem, app->o->dt_first));
  if (ark->set.fixed_step <= 0 && (app->o->cfl > 0 || app->o->force > 0)) {
    PetscCallARK(ARKStepSetStabilityFn(ark->mem, SpamSundialsStability, app));
    PetscCallARK(ARKStepSetCFLFraction(ark->mem, SPAM_ARK_CFL_FRACTION));
  }
  app->self_stepping = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSStep_SpamARKImex(TS ts)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;
  SpamTsApp      *app;
  realtype        tret, h;
  long            netf, ncfn;
  int             flag;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  /* The state jumped between steps (TSRestartStep): drop the stored stage and history. */
  if (ts->steprestart && ts->steps > 0) PetscCallARK(ARKStepReset(ark->mem, ts->ptime, ark->y));
  ts->steprestart = PETSC_FALSE;
  PetscCallARK(ARKStepSetStopTime(ark->mem, ts->max_time)); /* set again after each stop */
  flag = ARKStepEvolve(ark->mem, ts->max_time, ark->y, &tret, ARK_ONE_STEP);
  PetscCall(app->perr);
  if (flag < 0) {
    SpamSundialsFailure(app, "ARKStepEvolve", ARKStepGetReturnFlagName, flag);
    ts->reason = TS_DIVERGED_STEP_REJECTED;
    PetscFunctionReturn(0);
  }
  PetscCallARK(ARKStepGetLastStep(ark->mem, &h));
  PetscCallARK(ARKStepGetNumErrTestFails(ark->mem, &netf));
  PetscCallARK(ARKStepGetNumStepSolveFails(ark->mem, &ncfn));
  ts->ptime     = tret;
  ts->time_step = h;
  ts->reject    = (PetscInt)(netf + ncfn);
  PetscFunctionReturn(0);
}

/* Dense output (TSInterpolate): ARKStep's Hermite interpolant of the last step. */
static PetscErrorCode TSInterpolate_SpamARKImex(TS ts, PetscReal t, Vec X)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;
  N_Vector        x   = N_VMake_Petsc(X, ark->sunctx);
  SpamTsApp      *app;
  int             flag;

  PetscFunctionBeginUser;
  PetscCheck(x, PetscObjectComm((PetscObject)ts), PETSC_ERR_LIB, "N_VMake_Petsc failed");
  PetscCall(TSGetApplicationContext(ts, &app));
  flag = ARKStepGetDky(ark->mem, t, 0, x);
  N_VDestroy(x);
  PetscCall(app->perr);
  PetscCall(SpamCheckArkode(flag, "ARKStepGetDky"));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSReset_SpamARKImex(TS ts)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;

  PetscFunctionBeginUser;
  if (ark->mem) ARKStepFree(&ark->mem);
  if (ark->ls) PetscCallARKLS(SUNLinSolFree(ark->ls));
  ark->ls = NULL;
  if (ark->nls) PetscCallARK(SUNNonlinSolFree(ark->nls));
  ark->nls = NULL;
  if (ark->y) N_VDestroy(ark->y);
  ark->y = NULL;
  /* the KSP and its options stay (made by setfromoptions); the matrices go */
  PetscCall(MatDestroy(&ark->pc.P));
  PetscCall(VecDestroy(&ark->pc.r));
  PetscCall(VecDestroy(&ark->pc.z));
  PetscCall(SpamDiffusionJacDestroy(&ark->pc.jac));
  if (ark->sunctx) PetscCallARK(SUNContext_Free(&ark->sunctx));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSDestroy_SpamARKImex(TS ts)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;

  PetscFunctionBeginUser;
  PetscCall(TSReset_SpamARKImex(ts));
  PetscCall(SpamImexPCDestroy(&ark->pc));
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "SpamTSSundialsStats_C", NULL));
  PetscCall(PetscFree(ts->data));
  PetscFunctionReturn(0);
}

/* -sundials_stats (or force): ARKStepPrintAllStats, SUNDIALS' own table (explicit and
 * implicit evaluations, Newton and GMRES iterations, their failures). */
static PetscErrorCode SundialsStats_SpamARKImex(TS ts, FILE *file, PetscBool force)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;

  PetscFunctionBeginUser;
  if (!ark->mem || !(force || ark->set.sundials_stats)) PetscFunctionReturn(0);
  PetscCallARK(ARKStepPrintAllStats(ark->mem, file, SUN_OUTPUTFORMAT_TABLE));
  if (Preconditioned(ark)) PetscCall(SpamImexPCPrintStats(&ark->pc, file));
  {
    SpamTsApp                *app;
    const SpamDiffusionCache *c;
    PetscCall(TSGetApplicationContext(ts, &app));
    c = &app->sim->pair.dcache;
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "Diffusion fields reused   = %ld of %ld implicit evaluations\n", c->hits, c->hits + c->misses));
  }
  PetscFunctionReturn(0);
}

/* -ts_view: the pair, the solver and the controller, then ARKStep's statistics. */
static PetscErrorCode TSView_SpamARKImex(TS ts, PetscViewer viewer)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;
  PetscBool       ascii;
  FILE           *fd;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) PetscFunctionReturn(0);
  PetscCall(PetscViewerASCIIPrintf(viewer, "  ARKODE ARKStep IMEX, pair %s (diffusion implicit), Newton-GMRES (Krylov dimension %" PetscInt_FMT ", preconditioner %s, J v %s), ", ark->solver.table, ark->solver.krylov_dim, ark->solver.pc, ark->solver.jv));
  if (ark->set.fixed_step > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "fixed step %g\n", ark->set.fixed_step));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "controller %s\n", ark->set.adapt));
  if (!ark->mem) PetscFunctionReturn(0);
  PetscCall(PetscViewerFlush(viewer));
  PetscCall(PetscViewerASCIIGetPointer(viewer, &fd));
  PetscCall(SundialsStats_SpamARKImex(ts, fd, PETSC_TRUE));
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetFromOptions_SpamARKImex(TS ts, PetscOptionItems *PetscOptionsObject)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;
  SpamTsApp      *app;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCheck(app, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the arkode_imex TS needs a SpamTsApp application context before TSSetFromOptions");
  PetscCall(SpamArkodeOptionsRead(PetscOptionsObject, app->o, PETSC_FALSE, &ark->set));
  PetscCall(SpamArkodeAdaptType(app->o, SPAM_TSARKODE_IMEX, &ark->set));
  PetscCall(SolverOptionsRead(PetscOptionsObject, &ark->solver));
  if (Preconditioned(ark)) PetscCall(SpamImexPCCreate(&ark->pc));
  else {
    PetscCall(SpamImexPCDestroy(&ark->pc));
    if (PetscOptionsObject->printhelp) PetscCall(SpamImexPCHelp());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSARKodeImexPCPrefix(TS ts, const char **prefix)
{
  PetscBool imex;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSARKODE_IMEX, &imex));
  *prefix = imex && Preconditioned((TS_SpamARKImex *)ts->data) ? SPAM_IMEX_PC_PREFIX : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSARKodeImexGetSettings(TS ts, const SpamArkodeSettings **s)
{
  PetscBool imex;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)ts, SPAM_TSARKODE_IMEX, &imex));
  *s = imex ? &((TS_SpamARKImex *)ts->data)->set : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSCreate_ARKodeImex(TS ts)
{
  TS_SpamARKImex *ark = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ark));
  PetscCall(PetscStrncpy(ark->set.adapt, "pid", sizeof ark->set.adapt));
  PetscCall(SolverDefaults(&ark->solver));
  ts->data                = (void *)ark;
  ts->ops->setfromoptions = TSSetFromOptions_SpamARKImex;
  ts->ops->setup          = TSSetUp_SpamARKImex;
  ts->ops->step           = TSStep_SpamARKImex;
  ts->ops->reset          = TSReset_SpamARKImex;
  ts->ops->destroy        = TSDestroy_SpamARKImex;
  ts->ops->view           = TSView_SpamARKImex;
  ts->ops->interpolate    = TSInterpolate_SpamARKImex;
  ts->default_adapt_type  = TSADAPTNONE; /* ARKStep adapts by itself */
  ts->usessnes            = PETSC_FALSE; /* SUNDIALS' Newton, not PETSc's SNES */
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "SpamTSSundialsStats_C", SundialsStats_SpamARKImex));
  PetscFunctionReturn(0);
}

/* The arkode_imex row of the table of methods (ts_family.h). */
static PetscErrorCode DescribeARKImex(TS ts, const char **sub, char *adapt, size_t alen, double *fixed_dt)
{
  const TS_SpamARKImex *ark = (const TS_SpamARKImex *)ts->data;

  PetscFunctionBeginUser;
  *sub      = ark->solver.table;
  *fixed_dt = ark->set.fixed_step;
  PetscCall(PetscStrncpy(adapt, ark->set.fixed_step > 0 ? "none" : ark->set.adapt, alen));
  PetscFunctionReturn(0);
}

/* -help when another type is chosen: the solver's options (the step options it shares
 * are the arkode type's, listed with it). */
static PetscErrorCode HelpARKImex(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o)
{
  SpamImexSolver v;

  PetscFunctionBeginUser;
  (void)o;
  PetscCall(SolverOptionsRead(PetscOptionsObject, &v));
  if (PetscOptionsObject->printhelp) PetscCall(SpamImexPCHelp()); /* the KSP's options */
  PetscFunctionReturn(0);
}

/* ARKStep takes its initial time when it is made: a set-up TS is made again at the
 * checkpoint's. */
static PetscErrorCode CkBeforeSetUpARKImex(TS ts)
{
  PetscFunctionBeginUser;
  if (ts->setupcalled) {
    PetscCall(TSReset_SpamARKImex(ts));
    ts->setupcalled = PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CkApplyARKImex(TS ts, const SpamCkFile *c, double h_next, PetscBool pending)
{
  TS_SpamARKImex *ark = (TS_SpamARKImex *)ts->data;

  PetscFunctionBeginUser;
  (void)c;
  (void)pending;
  PetscCheck(ark->mem, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the arkode_imex TS is not set up");
  if (h_next > 0 && ark->set.fixed_step <= 0) PetscCallARK(ARKStepSetInitStep(ark->mem, h_next));
  PetscFunctionReturn(0);
}

static const SpamTSOption OptionsARKImex[] = {
  {"arkode_imex_table", PETSC_TRUE, PETSC_FALSE},      {"arkode_imex_nonlin_coef", PETSC_TRUE, PETSC_FALSE}, {"arkode_imex_eps_lin", PETSC_TRUE, PETSC_FALSE},
  {"arkode_imex_max_nonlin_iters", PETSC_TRUE, PETSC_FALSE}, {"arkode_imex_krylov_dim", PETSC_TRUE, PETSC_FALSE}, {"arkode_imex_pc", PETSC_TRUE, PETSC_FALSE}, {"arkode_imex_jv", PETSC_TRUE, PETSC_FALSE},
  {"arkode_imex_predictor", PETSC_TRUE, PETSC_FALSE}, {"arkode_imex_lsetup_freq", PETSC_TRUE, PETSC_FALSE}, {"arkode_imex_deduce", PETSC_TRUE, PETSC_FALSE},
  {"arkode_imex_reuse_fields", PETSC_TRUE, PETSC_FALSE},
  {"arkode_fixed_step", PETSC_TRUE, PETSC_FALSE},      {"arkode_adapt", PETSC_TRUE, PETSC_TRUE},             {"arkode_adapt_params", PETSC_TRUE, PETSC_TRUE},
  {"arkode_safety", PETSC_TRUE, PETSC_TRUE},           {"arkode_max_growth", PETSC_TRUE, PETSC_TRUE},        {"arkode_max_first_growth", PETSC_TRUE, PETSC_TRUE},
  {"arkode_max_efail_growth", PETSC_TRUE, PETSC_TRUE}, {"sundials_stats", PETSC_FALSE, PETSC_FALSE},         {NULL, PETSC_FALSE, PETSC_FALSE}};

const SpamTSFamily SpamTSFamilyARKodeImex = {
  .options         = OptionsARKImex,
  .type            = SPAM_TSARKODE_IMEX,
  .adapt_default   = TSADAPTNONE,
  .steps           = SPAM_TS_STEPS_OWN,
  .follow          = SPAM_TS_FOLLOW_NONE,
  .solves          = PETSC_TRUE,
  .restart_inexact = "ARKStep's controller history cannot be set: it restarts with the step the run was about to take",
  .interpolates    = SpamTSInterpolatesAlways,
  .describe        = DescribeARKImex,
  .help_other      = HelpARKImex,
  .ck_before_setup = CkBeforeSetUpARKImex,
  .ck_apply        = CkApplyARKImex,
};
