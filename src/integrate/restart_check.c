/* -restart: every value of a checkpoint checked before the run touches its directory. The
 * checksum says a file is as it was written, not that its writer was spam-ark: a file
 * edited and summed again must still hold what this run could have written. So each
 * value passes the check of the option or file it came from (the intervals through the
 * options' own validators, the particles as a particle file's rows, the output series as
 * the lists they become), and the loop's times and counters must be those of a run at
 * the checkpoint's time and step. A refusal is bad input naming the file and the entry. */
#include "loop_state.h"
#include <spam/errors.h>
#include <spam/decompose.h>
#include <stddef.h>

/* Whole numbers a double carries exactly (counters stored as reals). */
#define WHOLE_MAX 9007199254740992.0

#define BAD_ENTRY(rs, entry, fmt, ...) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry '%s' " fmt, (rs)->path, entry, ##__VA_ARGS__)

/* Each value of a real entry (n of them) finite, in [lo, hi], and whole if asked. */
static PetscErrorCode CheckReals(const SpamRestart *rs, const SpamCkFile *c, const char *name, size_t n, double lo, double hi, PetscBool whole)
{
  const double *v;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(c, name, n, &v));
  for (size_t k = 0; k < n; k++)
    if (!(v[k] >= lo && v[k] <= hi) || (whole && v[k] != floor(v[k]))) BAD_ENTRY(rs, name, "[%zu] = %.17g: must be a finite %s from %.17g to %.17g", k, v[k], whole ? "whole number" : "number", lo, hi);
  PetscFunctionReturn(0);
}

/* One value of a real or integer entry of length 1 in [lo, hi]; *v (may be NULL) gets it. */
static PetscErrorCode CheckLong(const SpamRestart *rs, const char *name, long lo, long hi, long *v)
{
  long x;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetLong(&rs->file, name, &x));
  if (x < lo || x > hi) BAD_ENTRY(rs, name, "= %ld: must be from %ld to %ld", x, lo, hi);
  if (v) *v = x;
  PetscFunctionReturn(0);
}

/* The next output time of a schedule at time t: with an interval, after t by at most one
 * interval (NextMultiple in time_loop.c), never past the end; without one, the end. */
static PetscBool ScheduleFits(double next, double interval, double t, double t_end)
{
  if (!(next <= t_end)) return PETSC_FALSE;
  if (interval == 0) return (PetscBool)(next == t_end);
  return (PetscBool)(next >= t - 1e-9 * interval && next <= t + interval * (1.0 + 1e-6));
}

/* loop [11]: intervals, next output times, loop times, wall clock, the writer's end. The
 * intervals pass the options' checks against the end time of the run that wrote them. */
static PetscErrorCode CheckLoop(const SpamRunOptions *o, const SpamRestart *rs)
{
  const double  *v;
  SpamRunOptions was = *o;
  char           from[PETSC_MAX_PATH_LEN + 32];

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(&rs->file, "loop", 11, &v));
  if (!(v[10] > rs->t && v[10] <= DBL_MAX)) BAD_ENTRY(rs, "loop", "[10] = %.17g: the end time of the run that wrote it must be finite and after its time %.17g", v[10], rs->t);
  (void)snprintf(from, sizeof from, "checkpoint %s: entry 'loop'", rs->path);
  was.output_interval   = v[0];
  was.snapshot_interval = v[1];
  was.t_end             = v[10];
  PetscCall(SpamRunOptionsCheckIntervals(&was, from));
  /* (The snapshot count of the interval is checked where it is taken, against this run's
   * -snapshot_max, which a restart may change: restart_load.c CheckTakenIntervals.) */
  if (memcmp(&v[4], &rs->t, sizeof rs->t)) BAD_ENTRY(rs, "loop", "[4] = %.17g: the loop's time must be the checkpoint's time %.17g", v[4], rs->t);
  for (int k = 2; k <= 3; k++)
    if (!ScheduleFits(v[k], v[k - 2], rs->t, v[10])) BAD_ENTRY(rs, "loop", "[%d] = %.17g: the next %s time must follow the time %.17g within one interval %.17g, or be the end %.17g", k, v[k], k == 2 ? "output" : "snapshot", rs->t, v[k - 2], v[10]);
  if (!(v[5] >= 0 && v[5] <= DBL_MAX)) BAD_ENTRY(rs, "loop", "[5] = %.17g: the last step must be finite and not negative", v[5]);
  /* the last row and snapshot: at or before the time (-1: no snapshot yet) */
  for (int k = 6; k <= 7; k++)
    if (!(v[k] <= rs->t && (v[k] >= 0 || v[k] == -1.0))) BAD_ENTRY(rs, "loop", "[%d] = %.17g: the time of the last %s must lie from 0 to the time %.17g", k, v[k], k == 6 ? "row" : "snapshot", rs->t);
  if (!(v[8] >= 0 && v[8] <= DBL_MAX)) BAD_ENTRY(rs, "loop", "[8] = %.17g: the wall-clock time must be finite and not negative", v[8]);
  PetscFunctionReturn(0);
}

/* time, step and progress [6] (time, steps, rejected, limited, last step, RHS seconds). */
static PetscErrorCode CheckProgress(const SpamRestart *rs)
{
  const double *p;

  PetscFunctionBeginUser;
  if (!(rs->t >= 0 && rs->t <= DBL_MAX)) BAD_ENTRY(rs, "time", "= %.17g: must be a finite time, not negative", rs->t);
  if (rs->step < 0 || rs->step > PETSC_MAX_INT) BAD_ENTRY(rs, "step", "= %ld: must be a step count from 0 to %ld", rs->step, (long)PETSC_MAX_INT);
  PetscCall(CheckReals(rs, &rs->file, "progress", 6, 0.0, DBL_MAX, PETSC_FALSE));
  PetscCall(SpamCkGetReal(&rs->file, "progress", 6, &p));
  if (p[0] > rs->t) BAD_ENTRY(rs, "progress", "[0] = %.17g: the last step's time is past the checkpoint's time %.17g", p[0], rs->t);
  if (p[1] != (double)rs->step) BAD_ENTRY(rs, "progress", "[1] = %.17g: the step count must be the checkpoint's step %ld", p[1], rs->step);
  for (int k = 2; k <= 3; k++)
    if (p[k] != floor(p[k]) || p[k] > WHOLE_MAX) BAD_ENTRY(rs, "progress", "[%d] = %.17g: a count must be a whole number", k, p[k]);
  PetscFunctionReturn(0);
}

/* What the integrator and the list take back: flags 0 or 1, counters, the proposed step,
 * the error weights' velocity scale (positive, as SpamTSSetVelocityScale requires). */
static PetscErrorCode CheckIntegrator(const SpamRestart *rs)
{
  double vscale;

  PetscFunctionBeginUser;
  PetscCall(CheckLong(rs, "exact", 0, 1, NULL));
  PetscCall(CheckLong(rs, "step_restart_pending", 0, 1, NULL));
  PetscCall(CheckLong(rs, "kick_cached", 0, 1, NULL));
  PetscCall(CheckLong(rs, "list_builds", 0, LONG_MAX, NULL));
  PetscCall(CheckReals(rs, &rs->file, "h_next", 1, 0.0, DBL_MAX, PETSC_FALSE));
  PetscCall(SpamCkGetScalar(&rs->file, "velocity_scale", &vscale));
  if (!(vscale > 0 && vscale <= DBL_MAX)) BAD_ENTRY(rs, "velocity_scale", "= %.17g: must be a positive finite speed", vscale);
  if (SpamCkHas(&rs->file, "arkode_history")) {
    PetscCall(CheckReals(rs, &rs->file, "arkode_history", 5, 0.0, DBL_MAX, PETSC_FALSE));
    PetscCall(CheckLong(rs, "arkode_accepted", 0, LONG_MAX, NULL));
  }
  PetscCall(SpamCkGetText(&rs->file, "limit", &(const char *){NULL}, NULL));
  PetscFunctionReturn(0);
}

/* A text field of the record must end within its bytes. */
static PetscBool Terminated(const char *s, size_t len)
{
  return (PetscBool)(memchr(s, 0, len) != NULL);
}

/* run_result: the record of a run going on (status ok, no signal), its texts terminated,
 * its counters not negative. */
static PetscErrorCode CheckResult(const SpamRestart *rs)
{
  const char   *blob;
  size_t        len;
  SpamRunResult r;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetText(&rs->file, "run_result", &blob, &len));
  if (len != sizeof r) BAD_ENTRY(rs, "run_result", "has %zu bytes, this build's record %zu", len, sizeof r);
  memcpy(&r, blob, sizeof r);
  if (r.status != SPAM_STATUS_OK || r.signal != 0) BAD_ENTRY(rs, "run_result", "holds status %d and signal %d: a checkpoint is of a run going on (status 0, no signal)", (int)r.status, r.signal);
  if (!Terminated(r.reason, sizeof r.reason) || !Terminated(r.method, sizeof r.method) || !Terminated(r.adapt, sizeof r.adapt) || !Terminated(r.output_mode, sizeof r.output_mode) || !Terminated(r.output_mode_reason, sizeof r.output_mode_reason) || !Terminated(r.restart_from, sizeof r.restart_from) || !Terminated(r.restart_why, sizeof r.restart_why))
    BAD_ENTRY(rs, "run_result", "holds a text without its end");
  if (r.steps < 0 || r.attempts < 0 || r.rejected < 0 || r.rhs_evals < 0 || r.limited < 0 || r.jumps < 0 || r.jump_steps < 0 || r.interpolated_rows < 0 || r.interpolation_rhs_evals < 0 || r.checkpoints < 0 || r.restart_step < 0 || r.restart_rhs_evals < 0)
    BAD_ENTRY(rs, "run_result", "holds a negative count");
  PetscFunctionReturn(0);
}

/* Positions (stride apart from x0) as a particle file's rows are checked (SpamBoxOutside):
 * finite, and inside the box across every face that has a mirror wall (the run reflects
 * back whatever crossed one after each step; periodic and open faces let particles out,
 * so a position beyond them is a state a run reaches). */
static PetscErrorCode CheckPositions(const SpamSim *sim, const SpamRestart *rs, const char *name, const double *x0, size_t n, int stride)
{
  PetscBool walls[6] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  char      why[160];

  PetscFunctionBeginUser;
  for (int f = 0; f < 2 * sim->model.dim; f++) walls[f] = SpamWallOn(&sim->geo.walls, f);
  for (size_t i = 0; i < n; i++) {
    const double *x = x0 + i * (size_t)stride;
    for (int d = 0; d < sim->model.dim; d++)
      if (!isfinite(x[d])) BAD_ENTRY(rs, name, "holds a particle (row %zu) whose position %d is %g, not finite", i, d, x[d]);
    if (SpamBoxOutside(sim->model.dim, sim->geo.box.lo, sim->geo.box.len, walls, x, why, sizeof why) >= 0) BAD_ENTRY(rs, name, "holds a particle (row %zu) beyond a mirror wall: %s", i, why);
  }
  PetscFunctionReturn(0);
}

/* This rank's particles (pc: the file's on one rank, the rank's own block on several):
 * the state finite with positive densities and its positions as a file's, the list's
 * reference positions likewise, the last forces finite, the RHS counters. */
static PetscErrorCode CheckParticleValues(const SpamSim *sim, const SpamRestart *rs, const SpamCkFile *pc)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  size_t            n;
  const double     *state, *xref;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetLength(pc, "id", &n));
  PetscCall(SpamCkGetReal(pc, "state", n * (size_t)l->nvar, &state));
  PetscCall(SpamCkGetReal(pc, "xref", n * (size_t)dim, &xref));
  PetscCall(CheckReals(rs, pc, "state", n * (size_t)l->nvar, -DBL_MAX, DBL_MAX, PETSC_FALSE));
  PetscCall(CheckPositions(sim, rs, "state", state + l->x, n, l->nvar));
  if (l->rho >= 0)
    for (size_t i = 0; i < n; i++)
      if (!(state[i * (size_t)l->nvar + l->rho] > 0)) BAD_ENTRY(rs, "state", "holds a particle (row %zu) whose density %.17g is not positive", i, state[i * (size_t)l->nvar + l->rho]);
  PetscCall(CheckPositions(sim, rs, "xref", xref, n, dim));
  PetscCall(CheckReals(rs, pc, "acc", n * (size_t)dim, -DBL_MAX, DBL_MAX, PETSC_FALSE));
  PetscCall(CheckReals(rs, pc, "rhs_stats", 3, 0.0, DBL_MAX, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* The migration state (ApplyRanks, ReusedDerivative) and, on several ranks, the cut. */
static PetscErrorCode CheckRanksEntries(const SpamSwarm *sw, const SpamRestart *rs)
{
  const int64_t *cut, *count;
  const double  *d, *m;
  const int      P = (int)rs->ranks;

  PetscFunctionBeginUser;
  /* read on one rank too when there (the restart's derivative booking) */
  if (rs->ranks < 2 && !SpamCkHas(&rs->file, "migration_loop")) PetscFunctionReturn(0);
  PetscCall(CheckReals(rs, &rs->file, "migration_loop", 6, 0.0, WHOLE_MAX, PETSC_FALSE));
  PetscCall(SpamCkGetReal(&rs->file, "migration_loop", 6, &m));
  if (m[0] != floor(m[0]) || m[1] != floor(m[1]) || m[3] != floor(m[3]) || m[4] != floor(m[4]) || (m[5] != 0 && m[5] != 1)) BAD_ENTRY(rs, "migration_loop", "holds a count that is not whole or a flag other than 0 or 1");
  if (rs->ranks < 2) PetscFunctionReturn(0);
  PetscCall(SpamCkGetInt(&rs->file, "decomposition_cut", (size_t)P + 1, &cut));
  PetscCall(SpamCkGetInt(&rs->file, "decomposition_count", (size_t)P, &count));
  for (int r = 0; r < P; r++)
    if (count[r] < 0 || count[r] > (int64_t)sw->nglobal) BAD_ENTRY(rs, "decomposition_count", "[%d] = %lld: must be from 0 to the particle count %lld", r, (long long)count[r], (long long)sw->nglobal);
  PetscCall(CheckReals(rs, &rs->file, "decomposition", 5, 0.0, DBL_MAX, PETSC_FALSE));
  PetscCall(SpamCkGetReal(&rs->file, "decomposition", 5, &d));
  if ((d[0] != 0 && d[0] != 1) || d[3] != floor(d[3]) || d[4] != floor(d[4]) || d[3] > WHOLE_MAX || d[4] > WHOLE_MAX) BAD_ENTRY(rs, "decomposition", "holds a flag other than 0 or 1 or a count that is not whole");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRestartCheck(const SpamSim *sim, const SpamRunOptions *o, const SpamOutputOptions *oo, const SpamRestart *rs)
{
  PetscErrorCode local;
  int            failed, any;

  PetscFunctionBeginUser;
  PetscCall(CheckProgress(rs));
  PetscCall(CheckLoop(o, rs));
  PetscCall(CheckIntegrator(rs));
  PetscCall(CheckResult(rs));
  PetscCall(CheckRanksEntries(&sim->p, rs));
  /* The shared entries are the same on every rank, and so is their verdict; the
   * particles are each rank's own: every rank learns whether any refused them (the one
   * that did has printed why), so that none goes on alone. */
  local  = CheckParticleValues(sim, rs, rs->ranks > 1 ? &rs->mine : &rs->file);
  failed = local ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, sim->p.comm));
  PetscCall(local);
  PetscCheck(!any, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: another rank's particles are refused", rs->path);
  PetscCall(SpamOutputResumeCheck(&rs->file, o->hdf5, oo, rs->t));
  PetscFunctionReturn(0);
}
