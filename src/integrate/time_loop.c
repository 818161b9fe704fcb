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
#include <spam/zero_pages.h>
#include <spam/interrupt.h>
#include <spam/physics.h> /* the Gauss maxima of the run figures */
#include "loop_state.h"
#include "ts_family.h"

typedef SpamSchedule Schedule;

/* A checkpoint asked for waits at most this many steps for one without a pending clamp
 * (with outputs denser than the steps there may be none); it is then written as inexact. */
#define SPAM_CKPT_MAX_DEFER 20

/* Times within this relative distance are one time. Output times are products k*interval
 * and the time a method reaches is a sum of steps, so an output time and the end time
 * (240 * 2.0943951023931953 and 502.6548245743669 in options/rotor.opts), or a step's end
 * and its target, can differ by a few ulps; treated as distinct, they cost a step of
 * ~1e-13 that repeats the last row, snapshot and steps.csv line. 1e-13 is ~500 ulps, far
 * below any step a run takes (the step floor is 1e-12 t_end). */
#define SPAM_TIME_ROUNDOFF 1e-13
/* Particles a block of CheckState's loops (a few KiB of state: in the first-level cache). */
#define SPAM_CHECK_BLOCK 128

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

/* Diagnostics row (and snapshot when due) of state X at time p->t: sim->p.X, or an
 * interpolated state. The writers read the state only through y; the density summation
 * they start from checks the neighbour list against y's own positions. */
/* Rank 0's rows of the text series, run through SpamRunAgreed: a failed write there ends
 * every rank. */
typedef struct {
  SpamOutput            *out;
  const SpamSim         *sim;
  const SpamProgress    *p;
  const SpamDiagnostics *d, *first;
} SeriesRow;

static PetscErrorCode AppendTimeseries(void *ctx)
{
  SeriesRow *w = ctx;
  return SpamTimeseriesAppend(w->out, w->sim, w->p, w->d, w->first);
}

static PetscErrorCode AppendSteps(void *ctx)
{
  SeriesRow *w = ctx;
  return SpamStepsAppend(w->out, w->p);
}

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
  {
    SeriesRow w = {out, sim, p, &d, &r->first};
    PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, AppendTimeseries, &w));
  }
  /* Every rank's: the snapshot's step attribute is written collectively (rank 0's row set
   * it there only, and the other ranks wrote 0 into P-rank snapshots). */
  out->step = p->steps;
  if (snapshot) PetscCall(SpamSnapshotWrite(out, sim, y, p->t, NULL)); /* collective */
  PetscCall(VecRestoreArrayRead(X, &y));
  if (!o->quiet) PetscCall(SpamMonitorProgress(sim, o, p, r));
  PetscFunctionReturn(0);
}

static PetscErrorCode Output(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, PetscBool snapshot, SpamRunResult *r)
{
  PetscFunctionBeginUser;
  PetscCall(OutputOf(sim->p.X, sim, o, out, p, snapshot, r));
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
    keep = sim->run.stats.rhs_evals;
    if (!s->Xout) PetscCall(VecDuplicate(sim->p.X, &s->Xout)); /* made at the first interpolated output only */
    PetscCall(TSInterpolate(ts, tout, s->Xout));
    r->interpolation_rhs_evals += sim->run.stats.rhs_evals - keep;
    sim->run.stats.rhs_evals = keep;
    q.t = tout;
    PetscCall(OutputOf(s->Xout, sim, o, out, &q, snap, r));
    r->interpolated_rows++;
    if (Reached(tout, s->next_out)) s->next_out = NextMultiple(tout, s->out_interval, o->t_end);
    if (Reached(tout, s->next_snap)) s->next_snap = NextMultiple(tout, s->snap_interval, o->t_end);
  }
  PetscFunctionReturn(0);
}

/* Whether the method keeps the state its last step started from (ts_family.h): then the
 * loop keeps no copy of its own, a state vector of memory less. */
static PetscErrorCode MethodKeepsLastGood(TS ts, PetscBool *yes)
{
  const SpamTSFamily *f;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  *yes = PETSC_FALSE;
  if (f->keeps_last_good) PetscCall(f->keeps_last_good(ts, yes));
  PetscFunctionReturn(0);
}

/* The last good state: the loop's copy, or the method's (accepted: after an accepted step,
 * else after a failed one); NULL if neither has it. */
static PetscErrorCode LastGood(TS ts, const SpamLoop *L, PetscBool accepted, Vec *good)
{
  const SpamTSFamily *f;

  PetscFunctionBeginUser;
  *good = L->Xgood;
  if (*good) PetscFunctionReturn(0);
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->last_good) PetscCall(f->last_good(ts, accepted, good));
  PetscFunctionReturn(0);
}

static PetscErrorCode Unstable(SpamSim *sim, SpamOutput *out, Vec Xgood, double tgood, SpamRunResult *r, const char *why)
{
  const PetscScalar *g;
  PetscInt           bad = -1;

  PetscFunctionBeginUser;
  r->status = SPAM_STATUS_UNSTABLE;
  PetscCall(PetscStrncpy(r->reason, why, sizeof r->reason));
  /* Keep the last good state as a snapshot tagged last_good. */
  if (Xgood) {
    PetscCall(VecGetArrayRead(Xgood, &g));
    PetscCall(SpamDensitySummation(sim, g, &bad));
    if (bad < 0) PetscCall(SpamSnapshotWrite(out, sim, g, tgood, "last_good"));
    PetscCall(VecRestoreArrayRead(Xgood, &g));
  } else PetscCall(PetscPrintf(sim->p.comm, "spam-ark: the method kept no last good state: no last_good snapshot\n"));
  PetscCall(PetscPrintf(sim->p.comm, "spam-ark: unstable: %s\n", r->reason));
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
    PetscCall(VecGetArrayRead(sim->p.X, &y));
    PetscCall(sim->model.max_sound_speed(sim, y, &c));
    PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  }
  floor_ke        = 0.5 * r->first.mass * (1e-3 * c) * (1e-3 * c);
  r->energy_scale = PetscMax(fabs(r->first.total), r->first.kinetic);
  if (isfinite(floor_ke)) r->energy_scale = PetscMax(r->energy_scale, floor_ke);
  PetscFunctionReturn(0);
}

/* The run ends short of t_end (a signal, the step limit): the row and snapshot of the time
 * reached, unless this very state was just written. */
static PetscErrorCode FinalOutputs(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, PetscBool row_done, PetscBool snap_done, SpamRunResult *r)
{
  const PetscBool snap = (PetscBool)(o->snapshot_interval > 0 && !snap_done);

  PetscFunctionBeginUser;
  if (!row_done) PetscCall(Output(sim, o, out, p, snap, r));
  else if (snap) {
    const PetscScalar *y;
    PetscCall(VecGetArrayRead(sim->p.X, &y));
    PetscCall(SpamSnapshotWrite(out, sim, y, p->t, NULL));
    PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  }
  PetscFunctionReturn(0);
}

/* Signal sig (SIGINT or SIGTERM, as agreed by every rank) came: the step in progress has
 * been completed and accepted; write the outputs of the time reached and end. */
static PetscErrorCode Interrupted(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, const SpamProgress *p, int sig, PetscBool row_done, PetscBool snap_done, SpamRunResult *r)
{
  PetscFunctionBeginUser;
  r->status = SPAM_STATUS_INTERRUPTED;
  r->signal = sig;
  (void)snprintf(r->reason, sizeof r->reason, "interrupted by %s at t = %.6g (step %ld)", r->signal == SIGINT ? "SIGINT" : "SIGTERM", p->t, p->steps);
  PetscCall(FinalOutputs(sim, o, out, p, row_done, snap_done, r));
  PetscFunctionReturn(0);
}

/* Whether any of the n doubles is an infinity or a NaN: all its exponent bits set, so
 * that adding 2^52 to them carries into the sign bit. Adds, ands and ors of 64-bit
 * integers, which vectorise on the baseline x86-64 (SSE2 has no 64-bit compare). */
static PetscBool NonFinite(const PetscScalar *y, size_t n)
{
  const uint64_t exp = (uint64_t)0x7ff << 52, one = (uint64_t)1 << 52;
  uint64_t       any = 0;

  for (size_t k = 0; k < n; k++) {
    uint64_t b;
    memcpy(&b, y + k, sizeof b);
    any |= (b & exp) + one;
  }
  return (PetscBool)((any >> 63) != 0);
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
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  /* By blocks of particles, each read once from memory: the scan for non-finite entries
   * (NonFinite: integer operations that vectorise; the particle is looked for only in a
   * block that has one), the densities, and the kinetic energy summed in particle order as
   * before, in a local sum (ke's address is taken below, and the compiler stored it at
   * every term). As one loop with a test a value it took 68 instructions a particle a step
   * (callgrind, velocity Verlet, N = 65536: 7 % of the run). */
  for (PetscInt i0 = 0; i0 < sim->p.n; i0 += SPAM_CHECK_BLOCK) {
    const PetscInt i1  = PetscMin(sim->p.n, i0 + SPAM_CHECK_BLOCK);
    const double   m2  = 0.5 * sim->model.mass;
    const int      dim = sim->model.dim, v = l->v;
    double         sum = ke;
    if (bad < 0 && NonFinite(y + (size_t)i0 * nv, (size_t)(i1 - i0) * (size_t)nv))
      for (PetscInt i = i0; i < i1 && bad < 0; i++)
        for (int k = 0; k < nv; k++)
          if (!isfinite(y[(size_t)i * nv + k])) bad = i;
    for (PetscInt i = i0; l->rho >= 0 && i < i1 && neg < 0; i++)
      if (!(y[(size_t)i * nv + l->rho] > 0)) neg = i;
    if (dim == 2) /* the common case with a literal dim: no inner loop */
      for (PetscInt i = i0; i < i1; i++) {
        const PetscScalar *s = y + (size_t)i * nv + v;
        sum += m2 * s[0] * s[0];
        sum += m2 * s[1] * s[1];
      }
    else
      for (PetscInt i = i0; i < i1; i++)
        for (int d = 0; d < dim; d++) sum += m2 * y[(size_t)i * nv + v + d] * y[(size_t)i * nv + v + d];
    ke = sum;
  }
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &ke, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  {
    const double e0 = PetscMax(r->energy_scale, 1e-300);
    if (bad >= 0) (void)snprintf(why, len, "non-finite state of particle %" PetscInt_FMT " at t = %.6g (step %ld)", SpamSimRowOf(sim, bad), t, step);
    else if (neg >= 0) (void)snprintf(why, len, "density of particle %" PetscInt_FMT " is not positive at t = %.6g (step %ld)", SpamSimRowOf(sim, neg), t, step);
    else if (o->energy_growth > 0 && ke > o->energy_growth * e0) (void)snprintf(why, len, "kinetic energy %.6g exceeds %g times the energy scale %.6g at t = %.6g (step %ld)", ke, o->energy_growth, e0, t, step);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Progress(TS ts, const SpamRunCounts *run, PetscLogDouble wall0, double dt, SpamProgress *p)
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
  p->rhs_evals = run->stats.rhs_evals;
  p->rhs_time  = run->stats.rhs_time;
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
    PetscCall(VecGetArrayRead(sim->p.X, &y));
    PetscCall(SpamStepBound(sim, app->o, y, &app->bound, &app->bound_which));
    PetscCall(VecRestoreArrayRead(sim->p.X, &y));
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
  const SpamTSFamily *f;
  const PetscScalar  *y;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (!f->bound_as_max_step || !(app->o->cfl > 0 || app->o->force > 0)) PetscFunctionReturn(0);
  PetscCall(VecGetArrayRead(app->sim->p.X, &y));
  PetscCall(SpamStepBound(app->sim, app->o, y, &app->bound, &app->bound_which));
  PetscCall(VecRestoreArrayRead(app->sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* The jumps between steps: particles that crossed a mirror wall reflected back, and the
 * model's own (closest-approach reflection). A changed state restarts the method: an
 * FSAL stage or Adams history computed before the jump is no longer valid. */
/* What the outputs of a step change and the trajectory must not see: the list (a build by
 * their density sums or the interpolant's right-hand sides) and, at the adaptive range,
 * the h_i each solve starts from (the last solve's). Kept before them, put back after. */
static PetscErrorCode KeepList(SpamSim *sim, SpamLoop *L)
{
  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursKeep(&sim->pair.nl, L->xref_keep, &L->builds_keep));
  if (sim->pair.f.adaptive) PetscCall(PetscArraycpy(L->xref_keep + (size_t)sim->p.n * sim->model.dim, sim->pair.f.h, sim->p.n));
  PetscFunctionReturn(0);
}

static PetscErrorCode RevertList(SpamSim *sim, SpamLoop *L)
{
  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursRevert(&sim->pair.nl, &sim->geo.box, L->xref_keep, L->builds_keep));
  if (sim->pair.f.adaptive) {
    PetscCall(PetscArraycpy(sim->pair.f.h, L->xref_keep + (size_t)sim->p.n * sim->model.dim, sim->p.n));
    SpamSmoothingNearReset(&sim->pair.f);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode PostStep(TS ts, SpamSim *sim, SpamRunResult *r)
{
  PetscScalar *y;
  PetscInt     changed = 0, crossed = 0;

  PetscFunctionBeginUser;
  if (!sim->model.post_step && !sim->pair.nl.ghosts.mirror) PetscFunctionReturn(0);
  PetscCall(VecGetArray(sim->p.X, &y));
  if (sim->pair.nl.ghosts.mirror) PetscCall(SpamWallReflect(sim, y, &crossed));
  if (sim->model.post_step) PetscCall(sim->model.post_step(sim, y, &changed));
  PetscCall(VecRestoreArray(sim->p.X, &y));
  changed += crossed;
  /* Every rank restarts its method together (TSRestartStep is collective), and the counts are the run's. */
  if (SpamSimDistributed(sim)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &changed, 1, MPIU_INT, MPI_SUM, sim->p.comm));
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

/* Whether a stop-time clamp is pending for the next step: ERKStep then takes a step it
 * cannot resume bit for bit from a checkpoint (after a clamp the next step is h*(h'/h),
 * not h'), and a state jump (TSRestartStep) waits to drop the history. Other methods have
 * their step cut by this loop, from a proposal the checkpoint keeps. */
static PetscErrorCode ClampPending(TS ts, PetscBool followed, PetscBool *pending)
{
  PetscBool ok, jump;

  PetscFunctionBeginUser;
  PetscCall(SpamTSARKodeCheckpointable(ts, &ok));
  PetscCall(SpamTSJumpPending(ts, followed, &jump));
  *pending = (PetscBool)(!ok || jump);
  PetscFunctionReturn(0);
}

/* A checkpoint is asked for by the simulated-time interval or the wall clock. */
static PetscErrorCode CheckpointAsked(const SpamSim *sim, const SpamRunOptions *o, SpamLoop *L)
{
  PetscLogDouble now;

  PetscFunctionBeginUser;
  if (o->checkpoint_interval > 0 && Reached(L->t, L->next_ckpt)) {
    L->ckpt_due  = PETSC_TRUE;
    L->next_ckpt = (floor(L->t / o->checkpoint_interval + 1e-9) + 1.0) * o->checkpoint_interval;
  }
  if (o->checkpoint_wall > 0) {
    PetscCall(PetscTime(&now));
    if (now - L->last_ckpt_wall >= o->checkpoint_wall) L->ckpt_due = PETSC_TRUE;
    /* Each rank has its own clock: one rank's due checkpoint is every rank's, or the
     * others would never join its collective write. */
    if (SpamSimDistributed(sim)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &L->ckpt_due, 1, MPIU_BOOL, MPI_LOR, sim->p.comm));
  }
  PetscFunctionReturn(0);
}

/* The signal that came (SIGINT or SIGTERM; 0: none), agreed by every rank: a signal reaches
 * the ranks at different moments, and a rank that stopped alone would leave the others
 * waiting in the next collective. The number itself is reduced, not a flag, so that every
 * rank reports the signal a single rank received (SIGINT to rank 1 is SIGINT on rank 0);
 * if different ranks received different ones, the largest (SIGTERM) wins. One small
 * reduction per step on more than one rank; a failed one stops the run as SIGTERM would. */
static int SignalAgreed(const SpamSim *sim)
{
  int mine = SpamInterruptSignal(), agreed = mine;

  if (SpamSimDistributed(sim) && MPI_Allreduce(&mine, &agreed, 1, MPI_INT, MPI_MAX, sim->p.comm) != MPI_SUCCESS) return SIGTERM;
  return agreed;
}

/* The stop of the next step: t_end when interpolating, else the next output time. */
static double NextStop(const SpamRunOptions *o, const Schedule *s)
{
  return s->mode == SPAM_OUTPUT_INTERPOLATED ? o->t_end : PetscMin(s->next_out, s->next_snap);
}

/* Writes the checkpoint asked for (or forced: an interruption) unless a clamp is pending,
 * in which case it waits for the next step, up to SPAM_CKPT_MAX_DEFER steps. *written
 * says whether it was written. */
static PetscErrorCode CheckpointServe(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, const SpamRunResult *r, SpamLoop *L, PetscBool *written)
{
  PetscBool pending = PETSC_FALSE;

  PetscFunctionBeginUser;
  *written = PETSC_FALSE;
  if (!L->ckpt_due || L->t >= o->t_end) PetscFunctionReturn(0);
  PetscCall(ClampPending(ts, L->followed, &pending));
  if (pending && L->ckpt_deferred < SPAM_CKPT_MAX_DEFER) {
    L->ckpt_deferred++;
    PetscFunctionReturn(0);
  }
  PetscCall(SpamCheckpointWrite(sim, o, ts, app, out, r, L, (PetscBool)!pending));
  L->ckpt_due      = PETSC_FALSE;
  L->ckpt_deferred = 0;
  PetscCall(PetscTime(&L->last_ckpt_wall));
  *written = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* A new run: the schedule from t = 0 and the row (and snapshot) of the initial state. */
static PetscErrorCode Start(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamOutput *out, SpamRunResult *r, SpamLoop *L)
{
  PetscFunctionBeginUser;
  ScheduleInit(o, r->fixed_dt, &L->s);
  L->p.limit = SpamStepLimitNames[SPAM_LIMIT_ACCURACY];
  PetscCall(Output(sim, o, out, &L->p, o->snapshot_interval > 0, r));
  L->t_snap = o->snapshot_interval > 0 ? 0.0 : -1.0;
  PetscCall(EnergyScale(sim, r));
  PetscCall(TSMonitor(ts, 0, 0.0, sim->p.X));
  PetscFunctionReturn(0);
}

/* A restart keeps the checkpoint's output schedule unless this run changed an interval
 * or the end (both allowed: they change outputs only); the checkpoint clock starts anew. */
static PetscErrorCode Reschedule(SpamSim *sim, const SpamRunOptions *o, double fixed_dt, const SpamRestart *rs, SpamLoop *L)
{
  Schedule      s;
  const double *loop;

  PetscFunctionBeginUser;
  (void)sim;
  PetscCall(SpamCkGetReal(&rs->file, "loop", 11, &loop));
  ScheduleInit(o, fixed_dt, &s);
  if (s.out_interval != L->s.out_interval || (o->t_end != loop[10] && L->s.next_out >= loop[10])) {
    L->s.out_interval = s.out_interval;
    L->s.next_out     = NextMultiple(L->t, s.out_interval, o->t_end);
  }
  if (s.snap_interval != L->s.snap_interval || (o->t_end != loop[10] && L->s.next_snap >= loop[10])) {
    L->s.snap_interval = s.snap_interval;
    L->s.next_snap     = NextMultiple(L->t, s.snap_interval, o->t_end);
  }
  L->next_ckpt = o->checkpoint_interval > 0 ? (floor(L->t / o->checkpoint_interval + 1e-9) + 1.0) * o->checkpoint_interval : INFINITY;
  PetscFunctionReturn(0);
}

/* Once the loop is over, the figures each rank kept of its own become the run's, which
 * rank 0 writes to summary.json: the slowest rank's RHS time, every rank's pairs, the
 * largest list growth count and Gauss maxima. */
static PetscErrorCode RunFigures(SpamSim *sim)
{
  double mx[4] = {sim->run.stats.rhs_time, (double)sim->pair.nl.grows, sim->ps ? sim->ps->gauss_accel_max : 0.0, sim->ps ? sim->ps->gauss_momentum_residual : 0.0}, visits = sim->run.stats.pair_visits;

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, mx, 4, MPI_DOUBLE, MPI_MAX, sim->p.comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &visits, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  sim->run.stats.rhs_time    = mx[0];
  sim->pair.nl.grows          = (long)mx[1];
  sim->run.stats.pair_visits = visits;
  if (sim->ps) {
    sim->ps->gauss_accel_max         = mx[2];
    sim->ps->gauss_momentum_residual = mx[3];
  }
  PetscFunctionReturn(0);
}

/* The evolved range's particle evaluations whose grad-h factor was not positive and took 1
 * (smoothing_adaptive.c): summed over the ranks (the most in one evaluation: the largest
 * rank's, a bound of the run's) for summary.json, and a note, so it is never silent. */
static PetscErrorCode OmegaFloored(SpamSim *sim)
{
  SpamRhsStats *s = &sim->run.stats;
  long          v[2] = {s->omega_floored, s->omega_floored_max};

  PetscFunctionBeginUser;
  if (!sim->model.tensor || sim->model.solid.smoothing != SPAM_SMOOTHING_EVOLVED) PetscFunctionReturn(0);
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &v[0], 1, MPI_LONG, MPI_SUM, sim->p.comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &v[1], 1, MPI_LONG, MPI_MAX, sim->p.comm));
  s->omega_floored     = v[0];
  s->omega_floored_max = v[1];
  if (v[0] > 0) PetscCall(PetscFPrintf(sim->p.comm, stderr, "spam-ark: note: evolved h: %ld particle evaluations (at most %ld in one right-hand side) had a grad-h factor Omega <= 0 (a range holding too few partners) and took Omega = 1 (summary.json: omega_floored)\n", v[0], v[1]));
  PetscFunctionReturn(0);
}

/* The decomposition's part of the result (summary.json). */
static PetscErrorCode RanksResult(SpamSim *sim, SpamRunResult *r)
{
  PetscMPIInt size;
  double      halo = sim->pair.nl.ghosts.n - sim->pair.nl.ghosts.nlocal, n = (double)sim->p.n, nmax;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(sim->p.comm, &size));
  r->ranks      = size;
  r->migrations = sim->run.migrations_run;
  r->migrated   = (double)sim->run.migrated;
  PetscCallMPI(MPIU_Allreduce(&halo, &r->halo_max, 1, MPI_DOUBLE, MPI_MAX, sim->p.comm));
  PetscCallMPI(MPIU_Allreduce(&n, &nmax, 1, MPI_DOUBLE, MPI_MAX, sim->p.comm));
  r->imbalance = nmax * size / PetscMax((double)sim->p.nglobal, 1.0);
  if (size > 1) PetscCall(RunFigures(sim));
  PetscCall(OmegaFloored(sim));
  PetscFunctionReturn(0);
}

/* The loop proper; Xgood (or the method: LastGood) holds the last accepted state. rs: the checkpoint a restart
 * continues (NULL: a new run). */
static PetscErrorCode Loop(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, SpamRunResult *r, SpamRestart *rs, SpamLoop *L)
{
  SpamProgress  *pp = &L->p;
  Schedule      *sp = &L->s;
  const double   dt_min = o->dt_min > 0 ? o->dt_min : 1e-12 * PetscMax(o->t_end, 1e-300);

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  {
    double *keep = L->xref_keep; /* allocated by SpamRun, as are the vectors */
    Vec     good = L->Xgood, xout = L->s.Xout;
    PetscCall(PetscMemzero(L, sizeof *L));
    L->xref_keep = keep;
    L->Xgood     = good;
    L->s.Xout    = xout;
    L->builds_migrated = sim->pair.nl.builds;
  }
  PetscCall(PetscTime(&L->wall0));
  L->last_ckpt_wall = L->wall0;
  L->next_ckpt      = o->checkpoint_interval > 0 ? o->checkpoint_interval : INFINITY;
  PetscCall(SpamTSDescribe(ts, r->method, sizeof r->method, r->adapt, sizeof r->adapt, &r->fixed_dt));
  {
    char line[512]; /* snprintf: PETSc's printf writes 3 as "3." */
    (void)snprintf(line, sizeof line, "spam-ark: scene %s, %ld particles in %dD, h %g, %s, step %s, rtol %g atol %g, to t = %g\n", sim->out.scene.name, (long)sim->p.nglobal, sim->model.dim, sim->model.kernel.h, r->method, r->fixed_dt > 0 ? "fixed" : r->adapt, o->rtol, o->atol, o->t_end);
    if (!o->quiet) PetscCall(PetscPrintf(sim->p.comm, "%s", line));
  }
  PetscCall(SpamTSOutputMode(ts, app, r->fixed_dt, &sp->mode, r->output_mode_reason, sizeof r->output_mode_reason));
  PetscCall(PetscStrncpy(r->output_mode, SpamOutputModeNames[sp->mode], sizeof r->output_mode));
  if (rs) {
    PetscCall(SpamRestartApply(sim, o, ts, app, rs, r, L));
    PetscCall(Reschedule(sim, o, r->fixed_dt, rs, L));
  } else PetscCall(Start(sim, o, ts, out, r, L));
  if (L->Xgood) PetscCall(VecCopy(sim->p.X, L->Xgood));
  while (L->t < o->t_end && pp->steps < o->max_steps) {
    /* Interpolating, the only stop is t_end; a step cut there is an "end" step. */
    const PetscBool     dense = (PetscBool)(sp->mode == SPAM_OUTPUT_INTERPOLATED);
    const double        tstop = NextStop(o, sp);
    const SpamStepLimit cut   = dense ? SPAM_LIMIT_END : SPAM_LIMIT_OUTPUT;
    SpamStepLimit       limit = r->fixed_dt > 0 ? SPAM_LIMIT_FIXED : SPAM_LIMIT_ACCURACY;
    char                why[256];
    PetscReal           tnew;
    double              t   = L->t;
    const int           sig = SignalAgreed(sim);

    if (sig) {
      /* The checkpoint first, so that it holds the series as a straight run writes them,
       * without the extra row and snapshot of the interruption. */
      PetscBool written;
      L->ckpt_due = PETSC_TRUE;
      PetscCall(CheckpointServe(sim, o, ts, app, out, r, L, &written));
      if (written || L->t >= o->t_end || L->ckpt_deferred == 0) {
        PetscCall(Interrupted(sim, o, out, pp, sig, (PetscBool)(L->t_row == t), (PetscBool)(L->t_snap == t), r));
        break;
      }
    }
    PetscCall(TSSetMaxTime(ts, tstop));
    if (!app->self_stepping) PetscCall(ChooseStep(ts, app, r->fixed_dt, tstop, cut, &limit));
    else PetscCall(SelfSteppingBound(ts, app));
    PetscCall(TSStep(ts));
    L->followed = PETSC_FALSE; /* the step evaluated f on the vectors a migration re-made */
    PetscCall(FailureReason(ts, app, pp->steps + 1, t, why, sizeof why));
    if (why[0]) {
      Vec good;
      PetscCall(LastGood(ts, L, PETSC_FALSE, &good));
      PetscCall(Unstable(sim, out, good, t, r, why));
      break;
    }
    PetscCall(TSGetTime(ts, &tnew));
    if (tnew != tstop && Reached(tnew, tstop) && tnew <= tstop * (1.0 + SPAM_TIME_ROUNDOFF)) {
      /* A step that lands within round-off of its stop time has reached it: the TS holds
       * tstop itself, so the next step starts from the output time, not an ulp before. */
      tnew = tstop;
      PetscCall(TSSetTime(ts, tnew));
    }
    PetscCall(Progress(ts, &sim->run, L->wall0, tnew - t, pp));
    pp->rejected += L->rejected_base;
    if (app->self_stepping && isfinite(app->bound) && pp->dt >= app->bound * (1.0 - 1e-9)) limit = app->bound_which;
    if (app->self_stepping && tnew >= tstop && limit == SPAM_LIMIT_ACCURACY && r->fixed_dt <= 0) limit = cut;
    if (limit == SPAM_LIMIT_CFL || limit == SPAM_LIMIT_FORCE) r->limited++;
    pp->limited = r->limited;
    pp->limit   = SpamStepLimitNames[limit];
    t           = tnew;
    L->t        = t;
    PetscCall(CheckState(sim, o, r, t, pp->steps, why, sizeof why));
    /* A collapse, not the cautious first steps of a start from rest: only a shrinking step
     * below the floor fails. */
    if (!why[0] && r->fixed_dt <= 0 && limit != cut && pp->dt < dt_min && pp->dt < L->dt_prev) (void)snprintf(why, sizeof why, "step size %.3e fell below the floor %.3e at t = %.6g (step %ld)", pp->dt, dt_min, t, pp->steps);
    if (why[0]) {
      Vec good;
      PetscCall(LastGood(ts, L, PETSC_TRUE, &good));
      PetscCall(Unstable(sim, out, good, r->t, r, why));
      break;
    }
    PetscCall(PostStep(ts, sim, r));
    if (L->Xgood) PetscCall(VecCopy(sim->p.X, L->Xgood));
    if (limit != cut) L->dt_prev = pp->dt;
    r->t = t;
    {
      SeriesRow w = {out, sim, pp, NULL, NULL};
      PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, AppendSteps, &w));
    }
    if (o->monitor) PetscCall(SpamMonitorStep(sim->p.comm, pp));
    /* TSSolve would call the -ts_monitor monitors; this loop steps the TS itself. */
    PetscCall(TSMonitor(ts, (PetscInt)pp->steps, t, sim->p.X));
    PetscCall(SpamTSAdaptMonitorSelf(ts, pp->steps - 1, t - pp->dt, pp->dt, pp->rejected));
    /* Outputs do not steer the run: a list build their density sums or the interpolant's
     * right-hand sides make is undone, so the method's next right-hand sides (and a
     * restart from a checkpoint taken now) see the list the step left. */
    const PetscBool outputs = (PetscBool)(PetscMin(sp->next_out, sp->next_snap) <= t * (1.0 + SPAM_TIME_ROUNDOFF) || t >= o->t_end);
    if (outputs) PetscCall(KeepList(sim, L)); /* only a step with outputs copies */
    if (dense) PetscCall(InterpolatedOutputs(ts, sim, o, out, pp, sp, r));
    if (Reached(t, PetscMin(sp->next_out, sp->next_snap)) || t >= o->t_end) {
      const PetscBool snap = (PetscBool)(o->snapshot_interval > 0 && (Reached(t, sp->next_snap) || t >= o->t_end));
      PetscCall(Output(sim, o, out, pp, snap, r));
      L->t_row = t;
      if (snap) L->t_snap = t;
      if (Reached(t, sp->next_out)) sp->next_out = NextMultiple(t, sp->out_interval, o->t_end);
      if (Reached(t, sp->next_snap)) sp->next_snap = NextMultiple(t, sp->snap_interval, o->t_end);
    }
    if (outputs) PetscCall(RevertList(sim, L));
    /* After the step's outputs, which read ERKStep's interpolant of the step (a resize drops
     * it); before a checkpoint, which then holds the particles where the next step finds
     * them, so that a restart on the same ranks needs no migration of its own. */
    PetscCall(SpamLoopMigrate(sim, o, ts, app, L));
    {
      /* Stopped short of the end by -ts_max_steps with checkpoints on: one now (no deferral:
       * the run ends here), before the row and snapshot of the time reached, which are this
       * run's own ending, not part of the series a continued run writes. */
      const PetscBool short_stop = (PetscBool)(pp->steps >= o->max_steps && t < o->t_end);
      PetscBool       written;
      PetscCall(CheckpointAsked(sim, o, L));
      if (short_stop && (o->checkpoint_interval > 0 || o->checkpoint_wall > 0)) {
        L->ckpt_due      = PETSC_TRUE;
        L->ckpt_deferred = SPAM_CKPT_MAX_DEFER;
      }
      PetscCall(CheckpointServe(sim, o, ts, app, out, r, L, &written));
      if (short_stop) PetscCall(FinalOutputs(sim, o, out, pp, (PetscBool)(L->t_row == t), (PetscBool)(L->t_snap == t), r));
    }
  }
  if (r->status == SPAM_STATUS_OK && L->t < o->t_end) r->status = SPAM_STATUS_MAX_STEPS;
  r->steps     = pp->steps;
  r->rejected  = pp->rejected;
  r->attempts  = pp->steps + pp->rejected;
  r->rhs_evals = sim->run.stats.rhs_evals;
  PetscCall(RanksResult(sim, r));
  r->checkpoints      = L->ckpt_count;
  r->checkpoint_bytes = L->ckpt_bytes;
  r->checkpoint_write = L->ckpt_seconds;
  {
    PetscLogDouble now;
    PetscCall(PetscTime(&now));
    r->wall = now - L->wall0;
  }
  PetscFunctionReturn(0);
}

/* Xgood (unless the method keeps the last good state) and Xout (made by the first
 * interpolated output) are freed on every path: a failed
 * write ends the run with an error, not a leak. They live in the loop state, which a migration re-makes (loop_migrate.c). */
PetscErrorCode SpamRun(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, SpamRestart *rs, SpamRunResult *r)
{
  SpamLoop      *L;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  SpamReleaseFreedMemory();
  PetscCall(PetscNew(&L));
  PetscCall(PetscMalloc1((size_t)sim->p.n * (sim->model.dim + 1) + 1, &L->xref_keep));
  {
    PetscBool kept;
    PetscCall(MethodKeepsLastGood(ts, &kept));
    if (!kept) PetscCall(VecDuplicate(sim->p.X, &L->Xgood));
  }
  ierr = Loop(sim, o, ts, app, out, r, rs, L);
  PetscCall(VecDestroy(&L->s.Xout));
  PetscCall(VecDestroy(&L->Xgood));
  PetscCall(PetscFree(L->xref_keep));
  PetscCall(PetscFree(L));
  PetscCall(ierr);
  /* What TSSolve does at its end: -ts_view (with SUNDIALS' table for arkode and cvode);
   * and -sundials_stats. */
  PetscCall(TSViewFromOptions(ts, NULL, "-ts_view"));
  PetscCall(SpamTSSundialsStats(ts, PETSC_STDOUT, PETSC_FALSE));
  PetscFunctionReturn(0);
}
