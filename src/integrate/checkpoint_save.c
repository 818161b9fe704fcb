/* Writing a checkpoint: what the run needs to go on bit for bit (checkpoint.h). Entries
 * (h5dump -A shows them; /checkpoint/NAME):
 *   version, options, method            text: who wrote it and with what options
 *   exact                               1: taken with no clamp pending (see time_loop.c)
 *   time, step, nglobal, nvar, dim      the moment and the shape of the state
 *   state [n*nvar]                      the packed state, rows in the run's particle order
 *   id [n], mass [n]                    each row's input row and mass (checked on restart)
 *   xref [n*dim]                        the neighbour list's reference positions
 *   acc [n*dim]                         the last force evaluation (the force step bound)
 *   h [n]                               the adaptive range: the h_i the next solve starts
 *                                       from (the last step's)
 *   h_next                              the step the integrator proposes next
 *   velocity_scale                      the error weights' velocity scale (the start's c0)
 *   arkode_history [5], arkode_accepted ERKStep's controller: h_next, 2 errors, 2 steps
 *   loop [11]                           schedule, loop times and end (see PutLoop)
 *   kick_cached                         basicsymplectic: the kick's force is cached
 *   block_rates, block_rate [n*nvar]    block_kdk: the rates its next cycle starts from
 *                                       (per particle: on several ranks each rank's)
 *   progress [6], limit                 counters of the last step and what limited it
 *   rhs_stats [3], list_builds          the RHS's counters
 *   run_result                          the run's result so far (same build only)
 *   out_*                               the output series (output_resume.c)
 * On P > 1 ranks (checkpoint_file.h: one file, each rank's block in rank order) the
 * per-particle entries state, id, xref, mass, acc, block_rate and the rank's own rhs_stats are each
 * rank's, in its local order, and the shared entries add
 *   decomposition_cut [P+1]             the curve keys of the cut in force (bits as int64)
 *   decomposition_count [P]             what each rank got at that cut
 *   decomposition [5]                   has_cut, cut imbalance, imbalance, cuts, migrations
 *   migration_loop [6]                  builds at the last migration and halo check, the
 *                                       halo then, migrations run, particles moved, and
 *                                       whether the integrator was re-made since the step */
#include "loop_state.h"
#include "ts_family.h"
#include <spam/decompose.h>
#include <spam/version.h>
#include <sundials/sundials_config.h>

#include <spam_commit.h> /* SPAM_GIT_COMMIT, made at every build (cmake/commit_header.cmake) */

PetscErrorCode SpamCheckpointVersion(char *buf, size_t len)
{
  char        petsc[64];

  PetscFunctionBeginUser;
  (void)snprintf(petsc, sizeof petsc, "%d.%d.%d", PETSC_VERSION_MAJOR, PETSC_VERSION_MINOR, PETSC_VERSION_SUBMINOR);
  /* Test only: SPAM_TEST_VERSION stands in for the program's version, so that a test can
   * write a checkpoint of "another version" (an environment variable, not an option). */
  const char *test = getenv("SPAM_TEST_VERSION");
  (void)snprintf(buf, len, "spam-ark %s (commit %s), PETSc %s, SUNDIALS %s, checkpoint layout 1", test ? test : SPAM_VERSION, SPAM_GIT_COMMIT, petsc, SUNDIALS_VERSION);
  PetscFunctionReturn(0);
}

static PetscErrorCode PutIdentity(SpamSim *sim, const SpamRunResult *r, SpamCkFile *c)
{
  char  version[256], *all = NULL;

  PetscFunctionBeginUser;
  PetscCall(SpamCheckpointVersion(version, sizeof version));
  PetscCall(SpamCkPutText(c, "version", version, strlen(version)));
  PetscCall(PetscOptionsGetAll(NULL, &all));
  PetscCall(SpamCkPutText(c, "options", all ? all : "", all ? strlen(all) : 0));
  PetscCall(PetscFree(all));
  PetscCall(SpamCkPutText(c, "method", r->method, strlen(r->method)));
  PetscCall(SpamCkPutLong(c, "nglobal", (long)sim->p.nglobal));
  PetscCall(SpamCkPutLong(c, "nvar", sim->model.layout.nvar));
  PetscCall(SpamCkPutLong(c, "dim", sim->model.dim));
  PetscFunctionReturn(0);
}

/* Per-particle arrays in the run's particle order into pc (a restart builds the same
 * order from the same options, and checks it by id; on several ranks each rank's own),
 * the list's build count into c. */
static PetscErrorCode PutParticles(SpamSim *sim, SpamCkFile *pc, SpamCkFile *c)
{
  const int          dim = sim->model.dim, n = (int)sim->p.n;
  const PetscScalar *y;
  double            *xref;
  int64_t           *id;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamCkPutReal(pc, "state", (size_t)n * sim->model.layout.nvar, y));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscMalloc2((size_t)n * dim + 1, &xref, (size_t)n + 1, &id));
  for (int i = 0; i < n; i++) {
    id[i] = SpamSimRowOf(sim, i);
    for (int d = 0; d < dim; d++) xref[(size_t)i * dim + d] = sim->pair.nl.xref[d][i];
  }
  PetscCall(SpamCkPutInt(pc, "id", (size_t)n, id));
  PetscCall(SpamCkPutReal(pc, "xref", (size_t)n * dim, xref));
  PetscCall(SpamCkPutReal(pc, "mass", (size_t)n, sim->pair.f.m));
  PetscCall(SpamCkPutReal(pc, "acc", (size_t)n * dim, sim->pair.f.acc));
  if (sim->pair.f.adaptive) PetscCall(SpamCkPutReal(pc, "h", (size_t)n, sim->pair.f.h));
  PetscCall(SpamCkPutLong(c, "list_builds", sim->pair.nl.builds));
  {
    const double stats[3] = {(double)sim->run.stats.rhs_evals, sim->run.stats.rhs_time, sim->run.stats.pair_visits};
    PetscCall(SpamCkPutReal(pc, "rhs_stats", 3, stats));
  }
  PetscCall(PetscFree2(xref, id));
  PetscFunctionReturn(0);
}

/* Several ranks: the cut the next migration decides by, and the loop's migration state,
 * so that a restart migrates when and as the uninterrupted run does. */
static PetscErrorCode PutRanks(const SpamSim *sim, const SpamLoop *L, SpamCkFile *c)
{
  const SpamDecomp *dec = sim->geo.dec;
  int64_t          *cut;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(dec->nranks + 1, &cut));
  memcpy(cut, dec->cut, sizeof *cut * (size_t)(dec->nranks + 1));
  PetscCall(SpamCkPutInt(c, "decomposition_cut", (size_t)dec->nranks + 1, cut));
  PetscCall(PetscFree(cut));
  PetscCall(SpamCkPutInt(c, "decomposition_count", (size_t)dec->nranks, dec->count));
  {
    const double v[5] = {dec->has_cut, dec->cut_imbalance, dec->imbalance, (double)dec->cuts, (double)dec->migrations};
    PetscCall(SpamCkPutReal(c, "decomposition", 5, v));
  }
  {
    const double v[6] = {(double)L->builds_migrated, (double)L->builds_checked, L->halo_migrated, (double)sim->run.migrations_run, (double)sim->run.migrated, L->followed};
    PetscCall(SpamCkPutReal(c, "migration_loop", 6, v));
  }
  PetscFunctionReturn(0);
}

/* The integrator: the step it proposes next, and what the method keeps of its own (ERKStep
 * its controller's history). */
static PetscErrorCode PutIntegrator(TS ts, const SpamTsApp *app, PetscBool followed, SpamCkFile *c, SpamCkFile *pc)
{
  const SpamTSFamily *f;
  PetscReal           dt;

  PetscFunctionBeginUser;
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->ck_put) PetscCall(f->ck_put(ts, app, c, &dt));
  if (f->ck_put_particles) PetscCall(f->ck_put_particles(ts, pc));
  PetscCall(SpamCkPutScalar(c, "h_next", dt));
  PetscCall(SpamCkPutScalar(c, "velocity_scale", app->w.vscale));
  {
    /* the kick's cached force is at the current positions: the next step reuses it */
    PetscBool          cached = app->cache_valid;
    const PetscScalar *y;
    const SpamSim     *sim = app->sim;
    if (cached) {
      PetscCall(VecGetArrayRead(sim->p.X, &y));
      for (PetscInt i = 0; i < sim->p.n && cached; i++)
        for (int d = 0; d < sim->model.dim; d++)
          if (memcmp(&y[(size_t)i * sim->model.layout.nvar + sim->model.layout.x + d], &app->xcache[(size_t)i * sim->model.dim + d], sizeof(double))) cached = PETSC_FALSE;
      PetscCall(VecRestoreArrayRead(sim->p.X, &y));
    }
    if (SpamSimDistributed(sim)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &cached, 1, MPIU_BOOL, MPI_LAND, sim->p.comm));
    PetscCall(SpamCkPutLong(c, "kick_cached", cached));
  }
  {
    PetscBool jump;
    PetscCall(SpamTSJumpPending(ts, followed, &jump));
    PetscCall(SpamCkPutLong(c, "step_restart_pending", jump));
  }
  PetscFunctionReturn(0);
}

/* The loop: schedule, times, wall clock and checkpoint clock. */
static PetscErrorCode PutLoop(const SpamRunOptions *o, const SpamLoop *L, const SpamRunResult *r, SpamCkFile *c)
{
  PetscLogDouble now;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&now));
  {
    const double v[11] = {L->s.out_interval, L->s.snap_interval, L->s.next_out, L->s.next_snap, L->t, L->dt_prev, L->t_row, L->t_snap, now - L->wall0, L->next_ckpt, o->t_end};
    PetscCall(SpamCkPutReal(c, "loop", 11, v));
  }
  {
    const double v[6] = {L->p.t, (double)L->p.steps, (double)L->p.rejected, (double)L->p.limited, L->p.dt, L->p.rhs_time};
    PetscCall(SpamCkPutReal(c, "progress", 6, v));
  }
  PetscCall(SpamCkPutText(c, "limit", L->p.limit ? L->p.limit : "", L->p.limit ? strlen(L->p.limit) : 0));
  PetscCall(SpamCkPutScalar(c, "time", L->t));
  PetscCall(SpamCkPutLong(c, "step", L->p.steps));
  /* The result so far (first diagnostics, drift maxima, counters) as the bytes of the
   * struct: only the build that wrote it reads it back (the version check). */
  PetscCall(SpamCkPutText(c, "run_result", (const char *)r, sizeof *r));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCheckpointWrite(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, const SpamRunResult *r, SpamLoop *L, PetscBool exact)
{
  SpamCkFile     c, mine;
  const PetscBool ranks = SpamSimDistributed(sim);
  char           path[PETSC_MAX_PATH_LEN];
  size_t         bytes = 0;
  PetscLogDouble t0, t1;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t0));
  PetscCall(SpamCkFileInit(&c));
  PetscCall(SpamCkFileInit(&mine));
  ierr = PutIdentity(sim, r, &c);
  if (!ierr) ierr = SpamCkPutLong(&c, "exact", exact);
  if (!ierr) ierr = PutParticles(sim, ranks ? &mine : &c, &c);
  if (!ierr && ranks) ierr = PutRanks(sim, L, &c);
  if (!ierr) ierr = PutIntegrator(ts, app, L->followed, &c, ranks ? &mine : &c);
  if (!ierr) ierr = PutLoop(o, L, r, &c);
  if (!ierr && out->owned) ierr = SpamOutputSave(out, &c); /* rank 0's files; rank 0 writes the shared entries */
  if (!ierr) ierr = SpamOutputPath(out, SPAM_CHECKPOINT_FILE, path, sizeof path);
  if (ranks) { /* a rank that failed to gather its part must not leave the others in the write */
    int bad = ierr != 0;
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, sim->p.comm));
    if (bad && !ierr) ierr = PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_FILE_WRITE, PETSC_ERROR_INITIAL, "cannot write the checkpoint: another rank failed to gather its part");
  }
  if (!ierr) ierr = ranks ? SpamCkFileWriteRanks(sim->p.comm, &c, &mine, path, &bytes) : SpamCkFileWrite(sim->p.comm, &c, path, &bytes);
  PetscCall(SpamCkFileDestroy(&mine));
  PetscCall(SpamCkFileDestroy(&c));
  PetscCall(ierr);
  PetscCall(PetscTime(&t1));
  L->ckpt_count++;
  L->ckpt_bytes   = (double)bytes;
  L->ckpt_seconds = t1 - t0;
  PetscCall(SpamManifestAdd(out, SPAM_CHECKPOINT_FILE, "checkpoint", L->t, PETSC_FALSE));
  PetscCall(SpamManifestWrite(out));
  {
    char line[PETSC_MAX_PATH_LEN + 256];
    (void)snprintf(line, sizeof line, "spam-ark: checkpoint at t = %.6g (step %ld%s): %s, %.3g MB in %.3f s\n", L->t, L->p.steps, exact ? "" : ", inexact: a stop-time clamp was pending", path, 1e-6 * (double)bytes, t1 - t0);
    PetscCall(PetscPrintf(sim->p.comm, "%s", line));
  }
  PetscFunctionReturn(0);
}
