/* The one time loop. Every method is a TS (see integrator.h); the loop steps it with
 * TSStep towards t_end, writing the outputs due inside a step from the method's
 * interpolant (TSInterpolate), or, where there is none or -output_stop asks, towards the
 * next output time (output_mode.c), so it can monitor each step, write outputs at exact
 * times, apply the physical step bound, and stop cleanly when the state goes bad.
 * Failure is a result: the reason, time and step go to the monitor and summary.json; so is
 * an interruption (SIGINT, SIGTERM), seen between steps, after which the outputs of the
 * time reached are written and the loop ends. */
#include <spam/integrator.h>
#include <spam/errors.h>
#include <spam/interrupt.h>

typedef struct {
  double         out_interval, snap_interval, next_out, next_snap;
  SpamOutputMode mode;
  Vec            Xout; /* the interpolated state of an output time (interpolated mode) */
} Schedule;

/* Times within this relative distance are one time. Output times are products k*interval
 * and the time a method reaches is a sum of steps, so an output time and the end time
 * (240 * 2.0943951023931953 and 502.6548245743669 in options/rotor.opts), or a step's end
 * and its target, can differ by a few ulps; treated as distinct, they cost a step of
 * ~1e-13 that repeats the last row, snapshot and steps.csv line. 1e-13 is ~500 ulps, far
 * below any step a run takes (the step floor is 1e-12 t_end). */
#define SPAM_TIME_ROUNDOFF 1e-13

/* t has reached target, to round-off. */
static PetscBool Reached(double t, double target)
{
  return (PetscBool)(t >= target - SPAM_TIME_ROUNDOFF * fabs(target));
}

/* The first multiple of interval after t; the end time if that is past or at it. */
static double NextMultiple(double t, double interval, double t_end)
{
  if (interval <= 0) return t_end;
  double k = floor(t / interval + 1e-9) + 1.0;
  return Reached(k * interval, t_end) ? t_end : k * interval;
}

/* With a fixed step, outputs fall on step boundaries: an output time between two steps
 * would shorten a step and change the method being studied. */
static void ScheduleInit(const SpamRunOptions *o, double fixed_dt, Schedule *s)
{
  s->out_interval  = o->output_interval;
  s->snap_interval = o->snapshot_interval;
  if (fixed_dt > 0) {
    if (s->out_interval > 0) s->out_interval = fixed_dt * PetscMax(1.0, ceil(s->out_interval / fixed_dt - 1e-9));
    if (s->snap_interval > 0) s->snap_interval = fixed_dt * PetscMax(1.0, ceil(s->snap_interval / fixed_dt - 1e-9));
  }
  s->next_out  = NextMultiple(0.0, s->out_interval, o->t_end);
  s->next_snap = NextMultiple(0.0, s->snap_interval, o->t_end);
}

/* Diagnostics row (and snapshot when due) of state X at time p->t: sim->X, or an
 * interpolated state. The writers read the state only through y; the density summation
 * they start from checks the neighbour list against y's own positions. */
static PetscErrorCode OutputOf(Vec X, SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, PetscBool snapshot, SpamRunResult *r)
{
  const PetscScalar *y;
  SpamDiagnostics    d;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(X, &y));
  PetscCall(SpamDiagnosticsCompute(sim, &o->diag, p->t, y, &d));
  if (p->steps == 0 && p->t == 0.0) r->first = d;
  r->last = d;
  SpamRunUpdateDrifts(&d, r);
  PetscCall(SpamTimeseriesAppend(out, sim, p, &d, &r->first));
  if (snapshot) PetscCall(SpamSnapshotWrite(out, sim, y, p->t, NULL));
  PetscCall(VecRestoreArrayRead(X, &y));
  PetscCall(SpamMonitorProgress(sim, o, p, r));
  PetscFunctionReturn(0);
}

static PetscErrorCode Output(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, PetscBool snapshot, SpamRunResult *r)
{
  PetscFunctionBeginUser;
  PetscCall(OutputOf(sim->X, sim, o, out, p, snapshot, r));
  PetscFunctionReturn(0);
}

/* The outputs due strictly inside the step just taken (before its end time p->t, which
 * the loop writes from the state itself), from the method's interpolant. The integrator's
 * state and history are not touched: the interpolant goes to a scratch vector. */
static PetscErrorCode InterpolatedOutputs(TS ts, SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, Schedule *s, SpamRunResult *r)
{
  SpamProgress q = *p;
  long         keep;

  PetscFunctionBeginUser;
  for (;;) {
    const double    tout = PetscMin(s->next_out, s->next_snap);
    PetscBool       snap;
    if (Reached(tout, p->t)) break; /* at the step's end, to round-off: its own state */
    snap = (PetscBool)(o->snapshot_interval > 0 && Reached(tout, s->next_snap));
    /* ERKStep's Hermite interpolant of degree 4 or 5 evaluates the right-hand side (it
     * does not keep those evaluations between calls): output work, booked apart so that
     * rhs_evals stays the method's work whatever the output cadence. */
    keep = sim->stats.rhs_evals;
    PetscCall(TSInterpolate(ts, tout, s->Xout));
    r->interpolation_rhs_evals += sim->stats.rhs_evals - keep;
    sim->stats.rhs_evals = keep;
    q.t = tout;
    PetscCall(OutputOf(s->Xout, sim, o, out, &q, snap, r));
    r->interpolated_rows++;
    if (Reached(tout, s->next_out)) s->next_out = NextMultiple(tout, s->out_interval, o->t_end);
    if (Reached(tout, s->next_snap)) s->next_snap = NextMultiple(tout, s->snap_interval, o->t_end);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Unstable(SpamSim *sim, SpamOutput *out, Vec Xgood, double tgood, SpamRunResult *r, const char *why)
{
  const PetscScalar *g;
  PetscInt           bad;

  PetscFunctionBeginUser;
  r->status = SPAM_STATUS_UNSTABLE;
  PetscCall(PetscStrncpy(r->reason, why, sizeof r->reason));
  /* Keep the last good state as a snapshot tagged last_good. */
  PetscCall(VecGetArrayRead(Xgood, &g));
  PetscCall(SpamDensitySummation(sim, g, &bad));
  if (bad < 0) PetscCall(SpamSnapshotWrite(out, sim, g, tgood, "last_good"));
  PetscCall(VecRestoreArrayRead(Xgood, &g));
  PetscCall(PetscPrintf(sim->comm, "spam-ark: unstable: %s\n", r->reason));
  PetscFunctionReturn(0);
}

/* The unit of the blow-up bound: E_ref = max(|E0|, KE0, M (c0/1000)^2 / 2), the initial
 * total or kinetic energy or, should both be (nearly) zero, the kinetic energy of the
 * whole mass M moving at a thousandth of the largest initial sound speed c0 (models with a
 * sound speed). |E0| alone fails for a body at rest with no strain: it is zero, and
 * round-off kinetic energy (1e-48) then exceeds any multiple of a 1e-300 floor. The third
 * term is far below the energy of any real motion of the material (a strain of 1e-3 holds
 * about as much), so it never hides a blow-up of a run that has energy to start with. */
static PetscErrorCode EnergyScale(SpamSim *sim, SpamRunResult *r)
{
  double c = 0.0, floor_ke;

  PetscFunctionBeginUser;
  if (sim->model.max_sound_speed) {
    const PetscScalar *y;
    PetscCall(VecGetArrayRead(sim->X, &y));
    PetscCall(sim->model.max_sound_speed(sim, y, &c));
    PetscCall(VecRestoreArrayRead(sim->X, &y));
  }
  floor_ke        = 0.5 * r->first.mass * (1e-3 * c) * (1e-3 * c);
  r->energy_scale = PetscMax(fabs(r->first.total), r->first.kinetic);
  if (isfinite(floor_ke)) r->energy_scale = PetscMax(r->energy_scale, floor_ke);
  PetscFunctionReturn(0);
}

/* SIGINT or SIGTERM came: the step in progress has been completed and accepted; write the
 * row and snapshot of the time reached (unless this very state was just written) and end. */
static PetscErrorCode Interrupted(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, PetscBool row_done, PetscBool snap_done, SpamRunResult *r)
{
  const PetscBool snap = (PetscBool)(o->snapshot_interval > 0 && !snap_done);

  PetscFunctionBeginUser;
  r->status = SPAM_STATUS_INTERRUPTED;
  r->signal = SpamInterruptSignal();
  (void)snprintf(r->reason, sizeof r->reason, "interrupted by %s at t = %.6g (step %ld)", r->signal == SIGINT ? "SIGINT" : "SIGTERM", p->t, p->steps);
  if (!row_done) PetscCall(Output(sim, o, out, p, snap, r));
  else if (snap) {
    const PetscScalar *y;
    PetscCall(VecGetArrayRead(sim->X, &y));
    PetscCall(SpamSnapshotWrite(out, sim, y, p->t, NULL));
    PetscCall(VecRestoreArrayRead(sim->X, &y));
  }
  PetscFunctionReturn(0);
}

/* Why the state after a step is unacceptable, or an empty string: a non-finite entry, a
 * non-positive carried density, or kinetic energy grown past the bound. */
static PetscErrorCode CheckState(const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r, double t, long step, char *why, size_t len)
{
  const SpamLayout  *l  = &sim->model.layout;
  const int          nv = l->nvar;
  const PetscScalar *y;
  double             ke = 0.0;
  PetscInt           bad = -1, neg = -1;

  PetscFunctionBeginUser;
  why[0] = 0;
  PetscCall(VecGetArrayRead(sim->X, &y));
  for (PetscInt i = 0; i < sim->n; i++) {
    const PetscScalar *s = y + (size_t)i * nv;
    for (int k = 0; k < nv; k++)
      if (!isfinite(s[k]) && bad < 0) bad = i;
    if (l->rho >= 0 && !(s[l->rho] > 0) && neg < 0) neg = i;
    for (int d = 0; d < sim->model.dim; d++) ke += 0.5 * sim->model.mass * s[l->v + d] * s[l->v + d];
  }
  PetscCall(VecRestoreArrayRead(sim->X, &y));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &ke, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  {
    const double e0 = PetscMax(r->energy_scale, 1e-300);
    if (bad >= 0) (void)snprintf(why, len, "non-finite state of particle %" PetscInt_FMT " at t = %.6g (step %ld)", SpamSimRowOf(sim, bad), t, step);
    else if (neg >= 0) (void)snprintf(why, len, "density of particle %" PetscInt_FMT " is not positive at t = %.6g (step %ld)", SpamSimRowOf(sim, neg), t, step);
    else if (o->energy_growth > 0 && ke > o->energy_growth * e0) (void)snprintf(why, len, "kinetic energy %.6g exceeds %g times the energy scale %.6g at t = %.6g (step %ld)", ke, o->energy_growth, e0, t, step);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Progress(TS ts, const SpamSim *sim, PetscLogDouble wall0, double dt, SpamProgress *p)
{
  PetscInt       steps, rejected;
  PetscReal      t;
  PetscLogDouble now;

  PetscFunctionBeginUser;
  PetscCall(TSGetStepNumber(ts, &steps));
  PetscCall(TSGetStepRejections(ts, &rejected));
  PetscCall(TSGetTime(ts, &t));
  PetscCall(PetscTime(&now));
  p->t         = t;
  p->steps     = steps;
  p->rejected  = rejected;
  p->rhs_evals = sim->stats.rhs_evals;
  p->rhs_time  = sim->stats.rhs_time;
  p->dt        = dt;
  p->wall      = now - wall0;
  PetscFunctionReturn(0);
}

/* The step size for TS methods that take the step the TS holds: the fixed step, or the
 * controller's proposal capped by the physical bound, and in both cases cut to end on
 * tstop (the next output time, or t_end when the outputs are interpolated; a cut step is
 * booked as 'cut'). Returns what set it. */
static PetscErrorCode ChooseStep(TS ts, SpamTsApp *app, double fixed_dt, double tstop, SpamStepLimit cut, SpamStepLimit *limit)
{
  SpamSim           *sim = app->sim;
  PetscReal          t, dt;
  TSAdapt            adapt;
  const PetscScalar *y;

  PetscFunctionBeginUser;
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetTimeStep(ts, &dt));
  *limit = fixed_dt > 0 ? SPAM_LIMIT_FIXED : SPAM_LIMIT_ACCURACY;
  if (fixed_dt > 0) dt = fixed_dt;
  else if (app->o->cfl > 0 || app->o->force > 0) {
    PetscCall(VecGetArrayRead(sim->X, &y));
    PetscCall(SpamStepBound(sim, app->o, y, &app->bound, &app->bound_which));
    PetscCall(VecRestoreArrayRead(sim->X, &y));
    PetscCall(TSGetAdapt(ts, &adapt));
    PetscCall(TSAdaptSetStepLimits(adapt, PETSC_DEFAULT, app->bound));
    if (dt > app->bound) {
      dt     = app->bound;
      *limit = app->bound_which;
    }
  }
  if (t + dt > tstop - 1e-9 * dt) {
    if (tstop - t < dt * (1.0 - 1e-9)) *limit = cut;
    dt = tstop - t;
  }
  PetscCall(TSSetTimeStep(ts, dt));
  PetscFunctionReturn(0);
}

/* The physical bound for methods that choose their own steps: ARKODE calls it itself
 * (stability function); CVODE gets it as its largest step. */
static PetscErrorCode SelfSteppingBound(TS ts, SpamTsApp *app)
{
  TSType             type;
  const PetscScalar *y;

  PetscFunctionBeginUser;
  PetscCall(TSGetType(ts, &type));
  if (strcmp(type, SPAM_TSCVODE) || !(app->o->cfl > 0 || app->o->force > 0)) PetscFunctionReturn(0);
  PetscCall(VecGetArrayRead(app->sim->X, &y));
  PetscCall(SpamStepBound(app->sim, app->o, y, &app->bound, &app->bound_which));
  PetscCall(VecRestoreArrayRead(app->sim->X, &y));
  PetscFunctionReturn(0);
}

/* The jumps between steps: particles that crossed a mirror wall reflected back, and the
 * model's own (closest-approach reflection). A changed state restarts the method: an
 * FSAL stage or Adams history computed before the jump is no longer valid. */
static PetscErrorCode PostStep(TS ts, SpamSim *sim, SpamRunResult *r)
{
  PetscScalar *y;
  PetscInt     changed = 0, crossed = 0;

  PetscFunctionBeginUser;
  if (!sim->model.post_step && !sim->nl.ghosts.mirror) PetscFunctionReturn(0);
  PetscCall(VecGetArray(sim->X, &y));
  if (sim->nl.ghosts.mirror) PetscCall(SpamWallReflect(sim, y, &crossed));
  if (sim->model.post_step) PetscCall(sim->model.post_step(sim, y, &changed));
  PetscCall(VecRestoreArray(sim->X, &y));
  changed += crossed;
  if (changed > 0) {
    r->jumps += changed;
    r->jump_steps++;
    PetscCall(TSRestartStep(ts));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode FailureReason(TS ts, const SpamTsApp *app, long step, double t, char *why, size_t len)
{
  TSConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(TSGetConvergedReason(ts, &reason));
  why[0] = 0;
  if (app->bad >= 0) (void)snprintf(why, len, "non-finite position of particle %" PetscInt_FMT " at stage time t = %.6g, step %ld", SpamSimRowOf(app->sim, app->bad), app->tbad, step);
  else if (reason < 0) (void)snprintf(why, len, "%.200s at t = %.6g, step %ld", app->fail[0] ? app->fail : TSConvergedReasons[reason], t, step);
  PetscFunctionReturn(0);
}

/* The loop proper; Xgood holds the last accepted state. */
static PetscErrorCode Loop(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, SpamRunResult *r, Vec Xgood, Vec Xout)
{
  PetscLogDouble wall0;
  SpamProgress   p = {0};
  Schedule       s;
  double         t = 0.0, dt_prev = 0.0; /* no previous step: the first cannot shrink */
  double         t_row = 0.0, t_snap;    /* times of the last row and snapshot written */
  const double   dt_min = o->dt_min > 0 ? o->dt_min : 1e-12 * PetscMax(o->t_end, 1e-300);

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  PetscCall(PetscTime(&wall0));
  PetscCall(SpamTSDescribe(ts, r->method, sizeof r->method, r->adapt, sizeof r->adapt, &r->fixed_dt));
  {
    char line[512]; /* snprintf: PETSc's printf writes 3 as "3." */
    (void)snprintf(line, sizeof line, "spam-ark: scene %s, %ld particles in %dD, h %g, %s, step %s, rtol %g atol %g, to t = %g\n", sim->scene.name, (long)sim->nglobal, sim->model.dim, sim->model.kernel.h, r->method, r->fixed_dt > 0 ? "fixed" : r->adapt, o->rtol, o->atol, o->t_end);
    PetscCall(PetscPrintf(sim->comm, "%s", line));
  }
  ScheduleInit(o, r->fixed_dt, &s);
  s.Xout = Xout;
  PetscCall(SpamTSOutputMode(ts, app, r->fixed_dt, &s.mode, r->output_mode_reason, sizeof r->output_mode_reason));
  PetscCall(PetscStrncpy(r->output_mode, SpamOutputModeNames[s.mode], sizeof r->output_mode));
  PetscCall(VecCopy(sim->X, Xgood));
  p.limit = SpamStepLimitNames[SPAM_LIMIT_ACCURACY];
  PetscCall(Output(sim, o, out, &p, o->snapshot_interval > 0, r));
  t_snap = o->snapshot_interval > 0 ? 0.0 : -1.0;
  PetscCall(EnergyScale(sim, r));
  PetscCall(TSMonitor(ts, 0, 0.0, sim->X));
  while (t < o->t_end && p.steps < o->max_steps) {
    /* Interpolating, the only stop is t_end; a step cut there is an "end" step. */
    const PetscBool     dense = (PetscBool)(s.mode == SPAM_OUTPUT_INTERPOLATED);
    const double        tstop = dense ? o->t_end : PetscMin(s.next_out, s.next_snap);
    const SpamStepLimit cut   = dense ? SPAM_LIMIT_END : SPAM_LIMIT_OUTPUT;
    SpamStepLimit       limit = r->fixed_dt > 0 ? SPAM_LIMIT_FIXED : SPAM_LIMIT_ACCURACY;
    char          why[256];
    PetscReal     tnew;

    if (SpamInterruptSignal()) {
      PetscCall(Interrupted(sim, o, out, &p, (PetscBool)(t_row == t), (PetscBool)(t_snap == t), r));
      break;
    }
    PetscCall(TSSetMaxTime(ts, tstop));
    if (!app->self_stepping) PetscCall(ChooseStep(ts, app, r->fixed_dt, tstop, cut, &limit));
    else PetscCall(SelfSteppingBound(ts, app));
    PetscCall(TSStep(ts));
    PetscCall(FailureReason(ts, app, p.steps + 1, t, why, sizeof why));
    if (why[0]) {
      PetscCall(Unstable(sim, out, Xgood, t, r, why));
      break;
    }
    PetscCall(TSGetTime(ts, &tnew));
    if (tnew != tstop && Reached(tnew, tstop) && tnew <= tstop * (1.0 + SPAM_TIME_ROUNDOFF)) {
      /* A step that lands within round-off of its stop time has reached it: the TS holds
       * tstop itself, so the next step starts from the output time, not an ulp before. */
      tnew = tstop;
      PetscCall(TSSetTime(ts, tnew));
    }
    PetscCall(Progress(ts, sim, wall0, tnew - t, &p));
    if (app->self_stepping && isfinite(app->bound) && p.dt >= app->bound * (1.0 - 1e-9)) limit = app->bound_which;
    if (app->self_stepping && tnew >= tstop && limit == SPAM_LIMIT_ACCURACY && r->fixed_dt <= 0) limit = cut;
    if (limit == SPAM_LIMIT_CFL || limit == SPAM_LIMIT_FORCE) r->limited++;
    p.limited = r->limited;
    p.limit   = SpamStepLimitNames[limit];
    t         = tnew;
    PetscCall(CheckState(sim, o, r, t, p.steps, why, sizeof why));
    /* A collapse, not the cautious first steps of a start from rest: only a shrinking step
     * below the floor fails. */
    if (!why[0] && r->fixed_dt <= 0 && limit != cut && p.dt < dt_min && p.dt < dt_prev) (void)snprintf(why, sizeof why, "step size %.3e fell below the floor %.3e at t = %.6g (step %ld)", p.dt, dt_min, t, p.steps);
    if (why[0]) {
      PetscCall(Unstable(sim, out, Xgood, r->t, r, why));
      break;
    }
    PetscCall(PostStep(ts, sim, r));
    PetscCall(VecCopy(sim->X, Xgood));
    if (limit != cut) dt_prev = p.dt;
    r->t = t;
    PetscCall(SpamStepsAppend(out, &p));
    if (o->monitor) PetscCall(SpamMonitorStep(sim, &p));
    /* TSSolve would call the -ts_monitor monitors; this loop steps the TS itself. */
    PetscCall(TSMonitor(ts, (PetscInt)p.steps, t, sim->X));
    PetscCall(SpamTSAdaptMonitorSelf(ts, p.steps - 1, t - p.dt, p.dt, p.rejected));
    if (dense) PetscCall(InterpolatedOutputs(ts, sim, o, out, &p, &s, r));
    if (Reached(t, PetscMin(s.next_out, s.next_snap)) || t >= o->t_end || p.steps >= o->max_steps) {
      const PetscBool snap = (PetscBool)(o->snapshot_interval > 0 && (Reached(t, s.next_snap) || t >= o->t_end || p.steps >= o->max_steps));
      PetscCall(Output(sim, o, out, &p, snap, r));
      t_row = t;
      if (snap) t_snap = t;
      if (Reached(t, s.next_out)) s.next_out = NextMultiple(t, s.out_interval, o->t_end);
      if (Reached(t, s.next_snap)) s.next_snap = NextMultiple(t, s.snap_interval, o->t_end);
    }
  }
  if (r->status == SPAM_STATUS_OK && t < o->t_end) r->status = SPAM_STATUS_MAX_STEPS;
  r->steps     = p.steps;
  r->rejected  = p.rejected;
  r->attempts  = p.steps + p.rejected;
  r->rhs_evals = sim->stats.rhs_evals;
  {
    PetscLogDouble now;
    PetscCall(PetscTime(&now));
    r->wall = now - wall0;
  }
  PetscFunctionReturn(0);
}

/* Xgood and Xout are freed on every path: a failed write ends the run with an error, not a leak. */
PetscErrorCode SpamRun(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, SpamRunResult *r)
{
  Vec            Xgood, Xout;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(sim->X, &Xgood));
  PetscCall(VecDuplicate(sim->X, &Xout));
  ierr = Loop(sim, o, ts, app, out, r, Xgood, Xout);
  PetscCall(VecDestroy(&Xout));
  PetscCall(VecDestroy(&Xgood));
  PetscCall(ierr);
  /* What TSSolve does at its end: -ts_view (with SUNDIALS' table for arkode and cvode);
   * and -sundials_stats. */
  PetscCall(TSViewFromOptions(ts, NULL, "-ts_view"));
  PetscCall(SpamTSSundialsStats(ts, PETSC_STDOUT, PETSC_FALSE));
  PetscFunctionReturn(0);
}
