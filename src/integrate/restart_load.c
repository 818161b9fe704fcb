/* -restart FILE: reading and checking a checkpoint before the run touches its directory,
 * then putting it back into the particles, the neighbour list, the integrator and the loop
 * (checkpoint_save.c says what each entry is). */
#define _DEFAULT_SOURCE /* realpath */
#include "loop_state.h"
#include "ts_family.h"
#include <spam/decompose.h>
#include <spam/errors.h>
#include <stdlib.h>
#include <libgen.h>
#include <errno.h>
#include <unistd.h>

/* Whether the method continues bit for bit, and why not. */
static PetscErrorCode Exactness(TS ts, const SpamCkFile *c, PetscBool *exact, char *why, size_t len)
{
  const SpamTSFamily *f;
  TSAdapt             adapt;
  long                ckexact, pending;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  PetscCall(SpamCkGetLong(c, "exact", &ckexact));
  PetscCall(SpamCkGetLong(c, "step_restart_pending", &pending));
  *exact = PETSC_TRUE;
  why[0] = 0;
  if (f->restart_inexact) (void)snprintf(why, len, "%s", f->restart_inexact);
  else if (f->steps == SPAM_TS_STEPS_ADAPTOR) {
    TSAdaptType at;
    PetscCall(TSGetAdapt(ts, &adapt));
    PetscCall(TSAdaptGetType(adapt, &at));
    if (strcmp(at, TSADAPTBASIC) && strcmp(at, TSADAPTNONE)) (void)snprintf(why, len, "PETSc's %s adaptor keeps its error history private: it restarts without it", at);
  }
  if (!why[0] && !ckexact) (void)snprintf(why, len, "the checkpoint was taken while a stop-time clamp was pending");
  if (!why[0] && pending) (void)snprintf(why, len, "the checkpoint was taken after a state jump, before the method restarted");
  if (why[0]) *exact = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* What this method takes back beyond the common entries (its row's ck_check). */
static PetscErrorCode CheckMethodEntries(TS ts, const SpamRestart *rs)
{
  const SpamTSFamily *f;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->ck_check) PetscCall(f->ck_check(&rs->file, rs->path));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckVersion(const SpamRestart *rs)
{
  char        now[256];
  const char *was;
  size_t      len;

  PetscFunctionBeginUser;
  PetscCall(SpamCheckpointVersion(now, sizeof now));
  PetscCall(SpamCkGetText(&rs->file, "version", &was, &len));
  if (strcmp(was, now)) SPAM_BAD_INPUT("-restart", rs->path, "was written by %s; this program is %s: a checkpoint continues only in the build that wrote it", was, now);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckOptions(const SpamRestart *rs)
{
  const char *was;
  size_t      len;
  char       *now = NULL, name[128], a[256], b[256];

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetText(&rs->file, "options", &was, &len));
  PetscCall(PetscOptionsGetAll(NULL, &now));
  PetscCall(SpamRestartOptionsDiffer(was, now ? now : "", name, sizeof name, a, b, sizeof a));
  PetscCall(PetscFree(now));
  if (name[0]) SPAM_BAD_INPUT("-restart", rs->path, "option -%s was %s in the checkpoint and is %s here: a restart continues the same run (only outputs, the end and checkpoints may change)", name, a, b);
  PetscFunctionReturn(0);
}

/* The checkpoint continues on the rank count that wrote it: each rank takes back its own
 * block in its own order (another count would need a new cut and other pair orders). */
static PetscErrorCode CheckRanks(const SpamSwarm *sw, SpamRestart *rs)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(sw->comm, &size));
  PetscCall(SpamCkFileRanks(&rs->file, &rs->ranks));
  if (rs->ranks != size) SPAM_BAD_INPUT("-restart", rs->path, "was written on %d rank%s and this run has %d: a checkpoint continues on the rank count that wrote it (mpiexec -n %d)", (int)rs->ranks, rs->ranks == 1 ? "" : "s", (int)size, (int)rs->ranks);
  PetscFunctionReturn(0);
}

/* The same particles in the same order with the same masses (on several ranks the order
 * is each rank's block's, put back by SpamSimPlace, and the masses are checked then). */
static PetscErrorCode CheckParticles(SpamSim *sim, SpamRestart *rs)
{
  long           ng, nvar, dim;
  const int64_t *id;
  const double  *m;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetLong(&rs->file, "nglobal", &ng));
  PetscCall(SpamCkGetLong(&rs->file, "nvar", &nvar));
  PetscCall(SpamCkGetLong(&rs->file, "dim", &dim));
  if (ng != (long)sim->p.nglobal || nvar != sim->model.layout.nvar || dim != sim->model.dim) SPAM_BAD_INPUT("-restart", rs->path, "holds %ld particles of %ld variables in %ldD; these options make %ld of %d in %dD", ng, nvar, dim, (long)sim->p.nglobal, sim->model.layout.nvar, sim->model.dim);
  if (rs->ranks > 1) {
    PetscCall(SpamCkFileReadRank(sim->p.comm, &rs->file, &rs->mine));
    PetscFunctionReturn(0);
  }
  PetscCall(SpamCkGetInt(&rs->file, "id", (size_t)sim->p.n, &id));
  PetscCall(SpamCkGetReal(&rs->file, "mass", (size_t)sim->p.n, &m));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    if (id[i] != SpamSimRowOf(sim, i)) SPAM_BAD_INPUT("-restart", rs->path, "row %ld holds particle %lld; the scene made here puts particle %ld there (the scene or its input file changed)", (long)i, (long long)id[i], (long)SpamSimRowOf(sim, i));
    if (memcmp(&m[i], &sim->pair.f.m[i], sizeof m[i])) SPAM_BAD_INPUT("-restart", rs->path, "particle %ld has mass %.17g in the checkpoint and %.17g here (the scene or its input file changed)", (long)SpamSimRowOf(sim, i), m[i], sim->pair.f.m[i]);
  }
  PetscFunctionReturn(0);
}

/* A restart continues the series of the directory its checkpoint is in. */
static PetscErrorCode CheckDirectory(const SpamRunOptions *o, const SpamRestart *rs)
{
  char  copy[PETSC_MAX_PATH_LEN], a[PATH_MAX], b[PATH_MAX];
  char *dir;

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(copy, rs->path, sizeof copy));
  dir = dirname(copy);
  if (!realpath(dir, a) || !realpath(o->output_dir, b) || strcmp(a, b)) SPAM_BAD_INPUT("-restart", rs->path, "lies in %s but -output_dir is %s: a restart continues the series of the checkpoint's own directory (give -output_dir %s)", dir, o->output_dir, dir);
  PetscFunctionReturn(0);
}

/* The output and snapshot intervals not given are the checkpoint's (their defaults follow
 * the end time, which a restart may move); a run that stops at outputs keeps them. */
static PetscErrorCode TakeIntervals(SpamRunOptions *o, SpamRestart *rs)
{
  const double  *loop;
  const char    *blob;
  size_t         len;
  SpamRunResult  r;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(&rs->file, "loop", 11, &loop));
  PetscCall(SpamCkGetText(&rs->file, "run_result", &blob, &len));
  if (len != sizeof r) SPAM_BAD_INPUT("-restart", rs->path, "its run record has %zu bytes, this build's %zu", len, sizeof r);
  memcpy(&r, blob, sizeof r);
  if (!o->output_interval_set) o->output_interval = loop[0];
  if (!o->snapshot_interval_set) o->snapshot_interval = loop[1];
  if (!strcmp(r.output_mode, "stopped") && (o->output_interval != loop[0] || o->snapshot_interval != loop[1])) SPAM_BAD_INPUT("-restart", rs->path, "this run stops its steps at the output times (%s), so a changed -output_interval or -snapshot_interval would change its steps", r.output_mode_reason[0] ? r.output_mode_reason : "-output_stop");
  if (!(o->t_end > rs->t)) SPAM_BAD_INPUT("-restart", rs->path, "is at t = %.17g, not before -ts_max_time %.17g: nothing to continue", rs->t, o->t_end);
  PetscFunctionReturn(0);
}

/* The intervals the restart goes on with against its end time, as the options' are: one
 * taken from the checkpoint is named by its entry. */
static PetscErrorCode CheckTakenIntervals(const SpamSim *sim, const SpamRunOptions *o, const SpamOutputOptions *oo, const SpamRestart *rs)
{
  char from[PETSC_MAX_PATH_LEN + 32];

  PetscFunctionBeginUser;
  (void)snprintf(from, sizeof from, "checkpoint %s: entry 'loop'", rs->path);
  PetscCall(SpamRunOptionsCheckIntervals(o, o->output_interval_set && o->snapshot_interval_set ? NULL : from));
  PetscCall(SpamOutputOptionsCheckSnapshots(sim, o, oo, o->snapshot_interval_set ? NULL : from));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRestartLoad(SpamSim *sim, SpamRunOptions *o, const SpamOutputOptions *oo, TS ts, SpamRestart *rs)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(rs, sizeof *rs));
  PetscCall(PetscStrncpy(rs->path, o->restart, sizeof rs->path));
  PetscCall(SpamCkFileInit(&rs->file));
  PetscCall(SpamCkFileInit(&rs->mine));
  if (access(rs->path, R_OK)) SPAM_BAD_INPUT("-restart", rs->path, "cannot be read: %s", strerror(errno));
  PetscCall(SpamCkFileRead(sim->p.comm, rs->path, &rs->file));
  PetscCall(CheckVersion(rs));
  PetscCall(CheckRanks(&sim->p, rs));
  PetscCall(CheckOptions(rs));
  PetscCall(CheckParticles(sim, rs));
  PetscCall(SpamCkGetScalar(&rs->file, "time", &rs->t));
  PetscCall(SpamCkGetLong(&rs->file, "step", &rs->step));
  PetscCall(CheckDirectory(o, rs));
  PetscCall(SpamRestartCheck(sim, o, oo, rs));
  PetscCall(CheckMethodEntries(ts, rs));
  PetscCall(TakeIntervals(o, rs));
  PetscCall(CheckTakenIntervals(sim, o, oo, rs));
  PetscCall(Exactness(ts, &rs->file, &rs->exact, rs->why, sizeof rs->why));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRestartDestroy(SpamRestart *rs)
{
  PetscFunctionBeginUser;
  PetscCall(SpamCkFileDestroy(&rs->file));
  PetscCall(SpamCkFileDestroy(&rs->mine));
  PetscFunctionReturn(0);
}

/* Several ranks: the integrator and the loop on the vectors of the placed particles.
 * ERKStep is made anew below (ApplyIntegrator): it only needs the new solution (a resize
 * of an ERKStep that never stepped fails inside ARKODE). A method that cannot follow
 * particles never migrated them, so its checkpoint's blocks are the start's distribution
 * and nothing was moved. */
static PetscErrorCode FollowPlaced(TS ts, SpamTsApp *app, SpamLoop *L)
{
  const SpamTSFamily *f;
  PetscBool           followed = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->follow_placed) {
    PetscCall(f->follow_placed(ts, app->sim->p.X));
    followed = PETSC_TRUE;
  } else PetscCall(SpamTSFollowParticles(ts, app, &followed));
  PetscCheck(followed, app->sim->p.comm, PETSC_ERR_PLIB, "the checkpoint's particles moved, but this method keeps the start's distribution");
  PetscCall(SpamLoopRemakeVectors(app->sim, L));
  PetscFunctionReturn(0);
}

/* Several ranks: the cut in force and the migration state at the checkpoint. */
static PetscErrorCode ApplyRanks(SpamSim *sim, const SpamCkFile *c, SpamLoop *L)
{
  SpamDecomp    *dec = sim->geo.dec;
  const int64_t *cut, *count;
  const double  *d, *m;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetInt(c, "decomposition_cut", (size_t)dec->nranks + 1, &cut));
  PetscCall(SpamCkGetInt(c, "decomposition_count", (size_t)dec->nranks, &count));
  PetscCall(SpamCkGetReal(c, "decomposition", 5, &d));
  PetscCall(SpamCkGetReal(c, "migration_loop", 6, &m));
  memcpy(dec->cut, cut, sizeof *cut * (size_t)(dec->nranks + 1));
  for (PetscMPIInt r = 0; r < dec->nranks; r++) dec->count[r] = count[r];
  dec->has_cut       = (PetscBool)(d[0] != 0);
  dec->cut_imbalance = d[1];
  dec->imbalance     = d[2];
  dec->cuts          = (long)d[3];
  dec->migrations    = (long)d[4];
  L->builds_migrated = (long)m[0];
  L->builds_checked  = (long)m[1];
  L->halo_migrated   = m[2];
  sim->run.migrations_run = (long)m[3];
  sim->run.migrated      = (PetscInt64)m[4];
  L->followed        = (PetscBool)(m[5] != 0);
  PetscFunctionReturn(0);
}

/* Several ranks: each rank's block back in its order, the masses checked as on one rank. */
static PetscErrorCode PlaceParticles(SpamSim *sim, TS ts, SpamTsApp *app, const SpamRestart *rs, SpamLoop *L)
{
  size_t         n;
  const int64_t *id;
  const double  *m;
  PetscBool      changed;
  PetscInt64     bad = -1;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetLength(&rs->mine, "id", &n));
  PetscCall(SpamCkGetInt(&rs->mine, "id", n, &id));
  PetscCall(SpamSimPlace(sim, (PetscInt)n, id, &changed));
  if (changed) PetscCall(FollowPlaced(ts, app, L));
  PetscCall(SpamCkGetReal(&rs->mine, "mass", n, &m));
  for (PetscInt i = 0; i < sim->p.n && bad < 0; i++)
    if (memcmp(&m[i], &sim->pair.f.m[i], sizeof m[i])) bad = SpamSimRowOf(sim, i);
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT64, MPI_MAX, sim->p.comm));
  if (bad >= 0) SPAM_BAD_INPUT("-restart", rs->path, "particle %lld has another mass in the checkpoint than here (the scene or its input file changed)", (long long)bad);
  PetscCall(ApplyRanks(sim, &rs->file, L));
  PetscFunctionReturn(0);
}

/* Particles, their list at the checkpoint's reference positions, the last forces. */
static PetscErrorCode ApplyParticles(SpamSim *sim, const SpamRestart *rs)
{
  const SpamCkFile *pc  = rs->ranks > 1 ? &rs->mine : &rs->file; /* the particles' entries */
  const int         dim = sim->model.dim;
  const size_t      n   = (size_t)sim->p.n;
  const double     *state, *xref, *acc, *stats;
  PetscScalar      *y;
  long              builds;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(pc, "state", n * sim->model.layout.nvar, &state));
  PetscCall(SpamCkGetReal(pc, "xref", n * dim, &xref));
  PetscCall(SpamCkGetReal(pc, "acc", n * dim, &acc));
  PetscCall(SpamCkGetReal(pc, "rhs_stats", 3, &stats));
  PetscCall(SpamCkGetLong(&rs->file, "list_builds", &builds));
  PetscCall(VecGetArrayWrite(sim->p.X, &y));
  PetscCall(PetscArraycpy(y, state, n * sim->model.layout.nvar));
  PetscCall(VecRestoreArrayWrite(sim->p.X, &y));
  PetscCall(SpamNeighboursRestore(&sim->pair.nl, &sim->geo.box, xref));
  sim->pair.nl.builds        = builds;
  sim->pair.ghost_mass_build = -1; /* the slots were laid out anew: their masses with them */
  PetscCall(SpamFieldsReserve(&sim->pair.f, SpamNeighboursSlots(&sim->pair.nl)));
  PetscCall(PetscArraycpy(sim->pair.f.acc, acc, n * dim));
  if (sim->pair.f.adaptive) { /* the solve's start: from it the first one repeats the last bits */
    const double *h;
    PetscCall(SpamCkGetReal(pc, "h", n, &h));
    PetscCall(PetscArraycpy(sim->pair.f.h, h, n));
  }
  sim->run.stats.rhs_evals   = (long)stats[0];
  sim->run.stats.rhs_time    = stats[1];
  sim->run.stats.pair_visits = stats[2];
  PetscFunctionReturn(0);
}

/* Whether the uninterrupted run would reuse the derivative at the restart state (FSAL
 * stage, ERKStep's kept F[0], the kick's cached force): the restarted method evaluates it
 * once more, which is booked apart so that rhs_evals stays the uninterrupted run's. */
static PetscErrorCode ReusedDerivative(TS ts, const SpamCkFile *c, PetscBool *reused)
{
  const SpamTSFamily *f;

  PetscFunctionBeginUser;
  PetscCall(SpamTSFamilyOf(ts, &f));
  *reused = PETSC_FALSE;
  if (SpamCkHas(c, "migration_loop")) { /* a migration re-made the method's vectors: f is due anew */
    const double *m;
    PetscCall(SpamCkGetReal(c, "migration_loop", 6, &m));
    if (m[5] != 0) PetscFunctionReturn(0);
  }
  if (f->ck_reuses_f) PetscCall(f->ck_reuses_f(ts, c, reused));
  PetscFunctionReturn(0);
}

/* The integrator at the checkpoint's time and step, taking the step it proposed next
 * (ERKStep: with its controller's history; CVODE: as its first step). */
static PetscErrorCode ApplyIntegrator(TS ts, SpamTsApp *app, const SpamRestart *rs)
{
  const SpamTSFamily *f;
  double              h_next, vscale;
  long                pending;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetScalar(&rs->file, "h_next", &h_next));
  PetscCall(SpamCkGetLong(&rs->file, "step_restart_pending", &pending));
  PetscCall(SpamCkGetScalar(&rs->file, "velocity_scale", &vscale));
  PetscCall(SpamTSSetVelocityScale(ts, app, vscale)); /* the error weights of the run's start */
  PetscCall(SpamTSFamilyOf(ts, &f));
  PetscCall(TSSetTime(ts, rs->t));
  PetscCall(TSSetStepNumber(ts, (PetscInt)rs->step));
  if (h_next > 0) PetscCall(TSSetTimeStep(ts, h_next));
  if (f->ck_before_setup) PetscCall(f->ck_before_setup(ts));
  PetscCall(TSSetUp(ts));
  if (f->ck_apply) PetscCall(f->ck_apply(ts, &rs->file, h_next, (PetscBool)(pending != 0)));
  if (f->ck_apply_particles) PetscCall(f->ck_apply_particles(ts, rs->ranks > 1 ? &rs->mine : &rs->file));
  app->cache_valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode ApplyLoop(const SpamCkFile *c, SpamLoop *L)
{
  const double *loop, *p;
  const char   *limit;
  size_t        len;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(c, "loop", 11, &loop));
  PetscCall(SpamCkGetReal(c, "progress", 6, &p));
  PetscCall(SpamCkGetText(c, "limit", &limit, &len));
  L->s.out_interval  = loop[0];
  L->s.snap_interval = loop[1];
  L->s.next_out      = loop[2];
  L->s.next_snap     = loop[3];
  L->t               = loop[4];
  L->dt_prev         = loop[5];
  L->t_row           = loop[6];
  L->t_snap          = loop[7];
  L->wall0          -= loop[8];
  L->p.t             = p[0];
  L->p.steps         = (long)p[1];
  L->p.rejected      = (long)p[2];
  L->p.limited       = (long)p[3];
  L->p.dt            = p[4];
  L->p.rhs_time      = p[5];
  L->rejected_base   = L->p.rejected;
  L->p.limit         = SpamStepLimitNames[SPAM_LIMIT_ACCURACY];
  for (int k = 0; k <= SPAM_LIMIT_END; k++)
    if (!strcmp(limit, SpamStepLimitNames[k])) L->p.limit = SpamStepLimitNames[k];
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRestartApply(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamRestart *rs, SpamRunResult *r, SpamLoop *L)
{
  const char   *blob;
  size_t        len;
  PetscBool     reused;
  SpamRunResult now = *r; /* what this run has set: method, output mode */

  PetscFunctionBeginUser;
  if (rs->ranks > 1) PetscCall(PlaceParticles(sim, ts, app, rs, L));
  PetscCall(ApplyParticles(sim, rs));
  PetscCall(ApplyIntegrator(ts, app, rs));
  PetscCall(ApplyLoop(&rs->file, L));
  PetscCall(SpamCkGetText(&rs->file, "run_result", &blob, &len));
  memcpy(r, blob, sizeof *r);
  PetscCall(PetscStrncpy(r->method, now.method, sizeof r->method));
  PetscCall(PetscStrncpy(r->adapt, now.adapt, sizeof r->adapt));
  PetscCall(PetscStrncpy(r->output_mode, now.output_mode, sizeof r->output_mode));
  PetscCall(PetscStrncpy(r->output_mode_reason, now.output_mode_reason, sizeof r->output_mode_reason));
  r->fixed_dt = now.fixed_dt;
  PetscCall(ReusedDerivative(ts, &rs->file, &reused));
  PetscCall(PetscStrncpy(r->restart_from, rs->path, sizeof r->restart_from));
  r->restart_t         = rs->t;
  r->restart_step      = rs->step;
  r->restart_exact     = rs->exact;
  r->restart_rhs_evals = reused ? 1 : 0;
  PetscCall(PetscStrncpy(r->restart_why, rs->why, sizeof r->restart_why));
  sim->run.stats.rhs_evals -= r->restart_rhs_evals;
  (void)o;
  {
    char line[PETSC_MAX_PATH_LEN + 512];
    (void)snprintf(line, sizeof line, "spam-ark: restart from %s at t = %.10g (step %ld): %s%s\n", rs->path, rs->t, rs->step, rs->exact ? "the method continues bit for bit" : "approximate: ", rs->exact ? "" : rs->why);
    PetscCall(PetscPrintf(sim->p.comm, "%s", line));
  }
  PetscFunctionReturn(0);
}
