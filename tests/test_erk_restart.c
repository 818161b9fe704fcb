/* Bit-identical continuation of ARKODE ERKStep and PETSc rk runs after a restart.
 * (a) spam-ark's controller (arkode_controller.c) takes the very steps of ARKODE's built-in
 *     one: every step size and the final state equal bit for bit, for pid, pi, i, expgus,
 *     impgus with their default gains and pid with user gains, on Dormand-Prince 5(4).
 * (b) ERKStep runs stopped after step K, rebuilt from what a checkpoint holds (t, y, the
 *     controller's SpamArkodeHistory) and continued, take the steps of the uninterrupted run
 *     and end on its state bit for bit, for Dormand-Prince 5(4), Verner 6(5) (c-fixed) and
 *     Bogacki-Shampine 3(2), restarting at an early step, a middle one, right after a step
 *     with a rejection and right before one (the first step after the restart is rejected).
 * (c) the same through spam-ark's TS on a small gas (SpamTSCreate, TSStep) with the call
 *     order a restart follows: arkode DP5 with SpamTSARKodeGet/SetHistory, stopping at
 *     every multiple of GAS_STOP as the time loop stops at output times (a checkpoint waits
 *     for a step SpamTSARKodeCheckpointable allows; control: restarts forced right after
 *     the other steps part), and rk 5dp + basic with the deterministic maxpy and the retry
 *     keeping stage 0's f(y_n).
 * The ODE of (a) and (b): 96 independent Kepler orbits (GM = 1) of eccentricity 0.5 to 0.9
 * and semi-major axis 1 to 1.5, on a PETSc Vec as spam-ark's state; their pericentre
 * passages give the controllers rejected steps to handle. */
#include <spam/integrator.h>
#include <spam/run.h>
#include <spam/errors.h>
#include <nvector/nvector_petsc.h>
#include "test_util.h"

#define NORB  96
#define NSTEP 400
#define MAXK  4 /* restart points around rejections (a fifth for arkode: a closed step) */

/* ---------------------------------------------------------------- the Kepler ODE */
static int KeplerRhs(realtype t, N_Vector y, N_Vector ydot, void *data)
{
  const PetscScalar *u;
  PetscScalar       *f;
  (void)t;
  (void)data;
  if (VecGetArrayRead(N_VGetVector_Petsc(y), &u) || VecGetArray(N_VGetVector_Petsc(ydot), &f)) return -1;
  for (int k = 0; k < NORB; k++) {
    const double *q = u + 4 * k, r2 = q[0] * q[0] + q[1] * q[1], r3 = r2 * sqrt(r2);
    f[4 * k]     = q[2];
    f[4 * k + 1] = q[3];
    f[4 * k + 2] = -q[0] / r3;
    f[4 * k + 3] = -q[1] / r3;
  }
  if (VecRestoreArray(N_VGetVector_Petsc(ydot), &f) || VecRestoreArrayRead(N_VGetVector_Petsc(y), &u)) return -1;
  return 0;
}

/* Each orbit starts at its apocentre, turned by its own angle. */
static PetscErrorCode KeplerStart(Vec Y)
{
  PetscScalar *u;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(Y, &u));
  for (int k = 0; k < NORB; k++) {
    const double e = 0.5 + 0.4 * k / (NORB - 1), a = 1.0 + 0.5 * ((k * 37) % NORB) / NORB, th = 2.0 * PETSC_PI * k / NORB;
    const double r = a * (1 + e), v = sqrt((1 - e) / (a * (1 + e)));
    u[4 * k]     = r * cos(th);
    u[4 * k + 1] = r * sin(th);
    u[4 * k + 2] = -v * sin(th);
    u[4 * k + 3] = v * cos(th);
  }
  PetscCall(VecRestoreArray(Y, &u));
  PetscFunctionReturn(0);
}

typedef struct {
  const char *table, *adapt;
  int         builtin;  /* ARKODE's own controller instead of ours */
  int         ngains;   /* 0: default gains                        */
  double      gains[3];
  int         plain;    /* PETSc's fused linear combination (control) */
} Method;

/* One ERKStep as spam-ark's arkode type sets it up (table with the c-fix, deterministic
 * combinations, our controller). ctl must stay where it is while mem lives. */
typedef struct {
  void                *mem;
  SpamArkodeController ctl;
} Erk;

static PetscErrorCode ErkCreate(const Method *m, N_Vector y, double t, SUNContext sctx, Erk *e)
{
  ARKodeButcherTable B;
  SpamArkodeSettings s;

  PetscFunctionBeginUser;
  e->mem = ERKStepCreate(KeplerRhs, t, y, sctx);
  PetscCheck(e->mem, PETSC_COMM_SELF, PETSC_ERR_LIB, "ERKStepCreate failed");
  PetscCall(SpamArkodeLoadTable(m->table, &B));
  PetscCallARK(ERKStepSetTable(e->mem, B));
  ARKodeButcherTable_Free(B);
  PetscCallARK(ERKStepSStolerances(e->mem, 1e-7, 1e-9));
  PetscCallARK(ERKStepSetMaxNumSteps(e->mem, -1));
  PetscCall(PetscMemzero(&s, sizeof s));
  PetscCall(PetscStrncpy(s.adapt, m->adapt, sizeof s.adapt));
  s.n_adapt_params = m->ngains;
  for (int k = 0; k < 3; k++) s.adapt_params[k] = m->gains[k];
  if (m->builtin) PetscCallARK(ERKStepSetAdaptivityMethod(e->mem, SpamArkodeAdaptMethod(m->adapt), m->ngains == 0, 0, s.adapt_params));
  else PetscCall(SpamArkodeControllerSetUp(&e->ctl, &s, e->mem));
  PetscFunctionReturn(0);
}

typedef struct {
  double h[NSTEP], y[4 * NORB];
  long   netf[NSTEP]; /* rejections so far, after each step */
} Trace;

/* NSTEP steps; with restart > 0 the ERKStep is freed after step 'restart' and a new one
 * continues from t, y and the controller history alone. */
static PetscErrorCode ErkRun(const Method *m, int restart, SUNContext sctx, Trace *tr)
{
  Vec                Y;
  N_Vector           y;
  Erk                e;
  realtype           t = 0.0;
  long               netf0 = 0;
  const PetscScalar *u;

  PetscFunctionBeginUser;
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 4 * NORB, &Y));
  PetscCall(KeplerStart(Y));
  y = N_VMake_Petsc(Y, sctx);
  PetscCheck(y && N_VEnableFusedOps_Petsc(y, SUNTRUE) == 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "N_Vector set-up failed");
  if (!m->plain) PetscCall(SpamNVectorDeterministic(y));
  PetscCall(ErkCreate(m, y, 0.0, sctx, &e));
  for (int s = 0; s < NSTEP; s++) {
    long netf;
    PetscCallARK(ERKStepEvolve(e.mem, 1e9, y, &t, ARK_ONE_STEP));
    PetscCallARK(ERKStepGetLastStep(e.mem, &tr->h[s]));
    PetscCallARK(ERKStepGetNumErrTestFails(e.mem, &netf));
    tr->netf[s] = netf0 + netf;
    if (s + 1 == restart) { /* the checkpoint: t, y (in Y), the history */
      SpamArkodeHistory hist;
      PetscCall(SpamArkodeControllerGet(&e.ctl, &hist));
      netf0 = tr->netf[s];
      ERKStepFree(&e.mem);
      PetscCall(ErkCreate(m, y, t, sctx, &e));
      PetscCall(SpamArkodeControllerResume(&e.ctl, &hist));
    }
  }
  PetscCall(VecGetArrayRead(Y, &u));
  PetscCall(PetscArraycpy(tr->y, u, 4 * NORB));
  PetscCall(VecRestoreArrayRead(Y, &u));
  ERKStepFree(&e.mem);
  N_VDestroy(y);
  PetscCall(VecDestroy(&Y));
  PetscFunctionReturn(0);
}

/* The first step (from 0) whose size differs, or -1; and whether the states are equal. */
static int FirstDiff(const double *a, const double *b, int n)
{
  for (int i = 0; i < n; i++)
    if (memcmp(&a[i], &b[i], sizeof(double))) return i;
  return -1;
}

/* Restart points: early, middle, right after a step with a rejection, right before one. */
static int RestartPoints(const long *netf, int n, int *K, const char **what)
{
  int nk = 0, after = -1, before = -1;

  K[nk] = 3, what[nk++] = "early";
  K[nk] = n / 2, what[nk++] = "middle";
  for (int s = 8; s < n - 20; s++) {
    if (after < 0 && netf[s] > netf[s - 1]) after = s + 1;                       /* step s+1 (1-based) had one */
    if (before < 0 && netf[s] > netf[s - 1] && netf[s - 1] == netf[s - 2]) before = s; /* step s+1 will have one */
  }
  if (after > 0) K[nk] = after, what[nk++] = "after a rejected step";
  if (before > 0) K[nk] = before, what[nk++] = "first step after it rejected";
  return nk;
}

static PetscErrorCode PartA(TestCount *c, SUNContext sctx)
{
  static const Method ms[] = {
    {"ARKODE_DORMAND_PRINCE_7_4_5", "pid", 0, 0, {0}, 0},    {"ARKODE_DORMAND_PRINCE_7_4_5", "pi", 0, 0, {0}, 0},     {"ARKODE_DORMAND_PRINCE_7_4_5", "i", 0, 0, {0}, 0},
    {"ARKODE_DORMAND_PRINCE_7_4_5", "expgus", 0, 0, {0}, 0}, {"ARKODE_DORMAND_PRINCE_7_4_5", "impgus", 0, 0, {0}, 0}, {"ARKODE_DORMAND_PRINCE_7_4_5", "pid", 0, 3, {0.7, 0.3, 0.05}, 0},
  };
  Trace *ours, *theirs;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ours));
  PetscCall(PetscNew(&theirs));
  for (size_t k = 0; k < sizeof ms / sizeof ms[0]; k++) {
    Method b = ms[k];
    b.builtin = 1;
    PetscCall(ErkRun(&ms[k], 0, sctx, ours));
    PetscCall(ErkRun(&b, 0, sctx, theirs));
    const int dh = FirstDiff(ours->h, theirs->h, NSTEP), dy = FirstDiff(ours->y, theirs->y, 4 * NORB);
    TestCheck(c, dh < 0 && dy < 0 && ours->netf[NSTEP - 1] == theirs->netf[NSTEP - 1], "(a) DP5 %s%s: our controller == ARKODE's over %d steps (%ld rejections): first differing step %d, state entry %d", ms[k].adapt, ms[k].ngains ? " gains 0.7,0.3,0.05" : "", NSTEP, theirs->netf[NSTEP - 1], dh, dy);
    TestReading(PETSC_COMM_SELF, "kepler_rejections", (double)theirs->netf[NSTEP - 1]);
  }
  PetscCall(PetscFree(ours));
  PetscCall(PetscFree(theirs));
  PetscFunctionReturn(0);
}

static PetscErrorCode PartB(TestCount *c, SUNContext sctx)
{
  static const Method ms[] = {
    {"ARKODE_DORMAND_PRINCE_7_4_5", "pid", 0, 0, {0}, 0}, {"ARKODE_VERNER_8_5_6", "pid", 0, 0, {0}, 0}, {"ARKODE_BOGACKI_SHAMPINE_4_2_3", "pid", 0, 0, {0}, 0}, {"ARKODE_DORMAND_PRINCE_7_4_5", "impgus", 0, 0, {0}, 0},
  };
  Trace *ref, *run;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ref));
  PetscCall(PetscNew(&run));
  for (size_t k = 0; k < sizeof ms / sizeof ms[0]; k++) {
    int         K[MAXK], good = 0, nk;
    const char *what[MAXK];
    PetscCall(ErkRun(&ms[k], 0, sctx, ref));
    nk = RestartPoints(ref->netf, NSTEP, K, what);
    for (int i = 0; i < nk; i++) {
      PetscCall(ErkRun(&ms[k], K[i], sctx, run));
      const int dh = FirstDiff(run->h, ref->h, NSTEP), dy = FirstDiff(run->y, ref->y, 4 * NORB);
      good += dh < 0 && dy < 0;
      TestCheck(c, dh < 0 && dy < 0 && run->netf[NSTEP - 1] == ref->netf[NSTEP - 1], "(b) %s %s: restart after step %d (%s) continues bitwise: first differing step %d, state entry %d", ms[k].table, ms[k].adapt, K[i], what[i], dh, dy);
    }
    TestCheck(c, nk == MAXK, "(b) %s: the run has a step with a rejection to restart around (%ld rejections in %d steps)", ms[k].table, ref->netf[NSTEP - 1], NSTEP);
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "RESTART arkode %s %s: %d/%d points bitwise\n", ms[k].table, ms[k].adapt, good, nk));
  }
  { /* Control: with N_Vector_Petsc's own fused combination (VecMAXPY groups vectors in
     * fours) Dormand-Prince's FSAL stage is not y_n+1 bit for bit and restarts part. */
    const Method m = {"ARKODE_DORMAND_PRINCE_7_4_5", "pid", 0, 0, {0}, 1};
    int          K[MAXK], nk, good = 0;
    const char  *what[MAXK];
    PetscCall(ErkRun(&m, 0, sctx, ref));
    nk = RestartPoints(ref->netf, NSTEP, K, what);
    for (int i = 0; i < nk; i++) {
      PetscCall(ErkRun(&m, K[i], sctx, run));
      good += FirstDiff(run->h, ref->h, NSTEP) < 0 && FirstDiff(run->y, ref->y, 4 * NORB) < 0;
    }
    TestCheck(c, good < nk, "(b) control: DP5 with PETSc's fused linear combination restarts bitwise at %d/%d points only (the comparison sees the difference)", good, nk);
  }
  PetscCall(PetscFree(ref));
  PetscCall(PetscFree(run));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------ spam-ark's TS on a small gas */
#define GAS_SIDE  8
#define GAS_N     (GAS_SIDE * GAS_SIDE)
#define GAS_STEPS 200
#define GAS_V     2.0  /* velocity spread: enough for a few rejected arkode steps */
#define GAS_STOP  0.25 /* arkode's stop times (steps are about 0.07)               */

static PetscErrorCode GasSim(SpamSim *sim)
{
  SpamBox  b = {2, {0, 0, 0}, {GAS_SIDE, GAS_SIDE, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  double   x[2 * GAS_N], v[2 * GAS_N];
  uint64_t seed = 11;

  PetscFunctionBeginUser;
  for (int i = 0; i < GAS_N; i++) {
    x[2 * i]     = (i % GAS_SIDE) + 0.5 + 0.2 * (TestUniform(&seed) - 0.5);
    x[2 * i + 1] = (i / GAS_SIDE) + 0.5 + 0.2 * (TestUniform(&seed) - 0.5);
    v[2 * i]     = GAS_V * (TestUniform(&seed) - 0.5);
    v[2 * i + 1] = GAS_V * (TestUniform(&seed) - 0.5);
  }
  PetscCall(TestMakeSim(&b, 2.5, 2.0, GAS_N, x, v, sim));
  PetscFunctionReturn(0);
}

typedef struct {
  double t[GAS_STEPS];
  long   reject[GAS_STEPS];
  Vec    X;        /* final state                                                   */
  int    K;        /* the step after which it restarted                              */
  int    deferred; /* steps after the asked one that were not checkpointable (arkode) */
  int    closed;   /* steps after which no checkpoint could be taken                   */
  char   open[GAS_STEPS]; /* whether a checkpoint could be taken after the step        */
} GasTrace;

/* A restart as the time loop will do it: a new TS from SpamTSCreate, then the
 * checkpoint's time, step number and (arkode) history or (rk) next step. */
static PetscErrorCode GasRestart(SpamSim *sim, const SpamRunOptions *o, SpamTsApp *app, TS *ts, PetscBool arkode, int K)
{
  PetscReal         t, dt;
  SpamArkodeHistory h;
  const double      c0 = app->w.vscale; /* the start's sound speed */

  PetscFunctionBeginUser;
  PetscCall(TSGetTime(*ts, &t));
  PetscCall(TSGetTimeStep(*ts, &dt));
  if (arkode) PetscCall(SpamTSARKodeGetHistory(*ts, &h));
  PetscCall(TSDestroy(ts));
  PetscCall(SpamTSAppDestroy(app));
  /* sim->p.X holds the checkpoint's state (and, here, the neighbour list its run built) */
  PetscCall(SpamTSCreate(sim, o, app, ts));
  PetscCall(SpamTSSetVelocityScale(*ts, app, c0));
  PetscCall(TSSetTime(*ts, t));
  PetscCall(TSSetStepNumber(*ts, K));
  if (arkode) PetscCall(SpamTSARKodeSetHistory(*ts, &h));
  else PetscCall(TSSetTimeStep(*ts, dt));
  PetscFunctionReturn(0);
}

/* GAS_STEPS steps; arkode stops at every multiple of GAS_STOP as the time loop stops at
 * output times. With restart > 0 a restart after the first checkpointable step from
 * 'restart' on (force: at 'restart' itself). */
static PetscErrorCode GasRun(PetscBool arkode, int restart, PetscBool force, GasTrace *tr)
{
  SpamSim        sim;
  SpamRunOptions o;
  SpamTsApp      app;
  TS             ts;
  long           rej0 = 0;

  PetscFunctionBeginUser;
  tr->K        = 0;
  tr->deferred = 0;
  tr->closed   = 0;
  PetscCall(GasSim(&sim));
  PetscCall(SpamRunOptionsParse(&sim, &o));
  PetscCall(SpamTSCreate(&sim, &o, &app, &ts));
  for (int s = 0; s < GAS_STEPS; s++) {
    PetscInt          rej;
    PetscReal         t;
    TSConvergedReason reason;
    PetscCall(TSGetTime(ts, &t));
    if (arkode) PetscCall(TSSetMaxTime(ts, GAS_STOP * (PetscFloorReal(t / GAS_STOP + 1e-9) + 1)));
    PetscCall(TSStep(ts));
    PetscCall(TSGetConvergedReason(ts, &reason));
    PetscCheck(reason >= 0, PETSC_COMM_SELF, PETSC_ERR_NOT_CONVERGED, "gas step %d failed: %s", s, TSConvergedReasons[reason]);
    PetscCall(TSGetTime(ts, &tr->t[s]));
    PetscCall(TSGetStepRejections(ts, &rej));
    tr->reject[s] = rej0 + rej;
    {
      PetscBool ok;
      PetscCall(SpamTSARKodeCheckpointable(ts, &ok));
      tr->closed += !ok;
      tr->open[s] = (char)ok;
      if (!(restart > 0 && !tr->K && s + 1 >= restart)) continue;
      if (ok || force) {
        rej0  = tr->reject[s];
        tr->K = s + 1;
        PetscCall(GasRestart(&sim, &o, &app, &ts, arkode, s + 1));
      } else tr->deferred++;
    }
  }
  PetscCall(VecDuplicate(sim.p.X, &tr->X));
  PetscCall(VecCopy(sim.p.X, tr->X));
  PetscCall(TSDestroy(&ts));
  PetscCall(SpamTSAppDestroy(&app));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetGasOptions(PetscBool arkode)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsClearValue(NULL, "-ts_rk_type"));
  PetscCall(PetscOptionsClearValue(NULL, "-ts_adapt_type"));
  PetscCall(PetscOptionsSetValue(NULL, "-ts_max_time", "1000"));
  PetscCall(PetscOptionsSetValue(NULL, "-ts_rtol", "1e-9"));
  PetscCall(PetscOptionsSetValue(NULL, "-ts_type", arkode ? "arkode" : "rk"));
  if (!arkode) {
    PetscCall(PetscOptionsSetValue(NULL, "-ts_rk_type", "5dp"));
    PetscCall(PetscOptionsSetValue(NULL, "-ts_adapt_type", "basic"));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode PartC(TestCount *c, PetscBool arkode)
{
  const char *name = arkode ? "arkode DP5 pid" : "rk 5dp basic";
  GasTrace   *ref, *run;
  int         K[MAXK + 1], nk, good = 0;
  const char *what[MAXK + 1];

  PetscFunctionBeginUser;
  PetscCall(SetGasOptions(arkode));
  PetscCall(PetscNew(&ref));
  PetscCall(PetscNew(&run));
  PetscCall(GasRun(arkode, 0, PETSC_FALSE, ref));
  nk = RestartPoints(ref->reject, GAS_STEPS, K, what);
  if (arkode) {
    TestCheck(c, ref->closed > 0, "(c) %s: %d of %d steps ended on a stop time or left a clamp to one pending (no checkpoint then)", name, ref->closed, GAS_STEPS);
    for (int s = GAS_STEPS / 4; s < GAS_STEPS / 2 && nk < MAXK + 1; s++)
      if (!ref->open[s]) K[nk] = s + 1, what[nk++] = "asked where none may be taken";
  }
  for (int i = 0; i < nk; i++) {
    PetscBool same;
    PetscCall(GasRun(arkode, K[i], PETSC_FALSE, run));
    PetscCall(VecEqual(run->X, ref->X, &same));
    const int dt = FirstDiff(run->t, ref->t, GAS_STEPS);
    good += dt < 0 && same;
    TestCheck(c, dt < 0 && same && run->reject[GAS_STEPS - 1] == ref->reject[GAS_STEPS - 1], "(c) %s, gas of %d: restart after step %d (%s; asked %d, %d deferred) continues bitwise: first step ending at a different time %d, final states %s", name, GAS_N, run->K, what[i], K[i], run->deferred, dt, same ? "equal" : "differ");
    PetscCall(VecDestroy(&run->X));
  }
  TestCheck(c, nk >= MAXK, "(c) %s: the run has a step with a rejection to restart around (%ld rejections in %d steps)", name, ref->reject[GAS_STEPS - 1], GAS_STEPS);
  if (arkode) { /* what the deferral avoids: restarts at the closed steps themselves */
    int nb = 0, nt = 0;
    for (int q = 1; q < GAS_STEPS - 1; q++) {
      PetscBool same;
      if (ref->open[q]) continue;
      PetscCall(GasRun(arkode, q + 1, PETSC_TRUE, run));
      PetscCall(VecEqual(run->X, ref->X, &same));
      nt++;
      nb += same && FirstDiff(run->t, ref->t, GAS_STEPS) < 0;
      PetscCall(VecDestroy(&run->X));
    }
    TestCheck(c, nb < nt, "(c) control: %s forced to restart right after each closed step: %d/%d bitwise (the rest part: checkpoints wait for an open step)", name, nb, nt);
  }

  PetscCall(PetscPrintf(PETSC_COMM_SELF, "RESTART %s (TS, gas): %d/%d points bitwise\n", name, good, nk));
  PetscCall(VecDestroy(&ref->X));
  PetscCall(PetscFree(ref));
  PetscCall(PetscFree(run));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount  c = {0, 0};
  SUNContext sctx;

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(SpamIntegratorsRegister());
  PetscCall(SUNContext_Create(NULL, &sctx));
  PetscCall(PartA(&c, sctx));
  PetscCall(PartB(&c, sctx));
  PetscCall(PartC(&c, PETSC_TRUE));
  PetscCall(PartC(&c, PETSC_FALSE));
  PetscCall(SUNContext_Free(&sctx));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
