/* A run from its first file to its exit code. */
#include <spam/session.h>
#include <spam/checkpoint.h>
#include <spam/interrupt.h>
#include <spam/errors.h>

int SpamRunExitCode(const SpamRunResult *r)
{
  switch (r->status) {
  case SPAM_STATUS_OK:
  case SPAM_STATUS_MAX_STEPS: return SPAM_EXIT_OK;
  case SPAM_STATUS_UNSTABLE: return SPAM_EXIT_UNSTABLE;
  case SPAM_STATUS_INTERRUPTED: return 128 + r->signal; /* 130 SIGINT, 143 SIGTERM */
  default: return SPAM_EXIT_ERROR;
  }
}

static const char *ManifestStatus(SpamStatus s)
{
  static const char *names[] = {"ok", "max_steps", "unstable", "interrupted", "failed"};
  return names[s];
}

typedef struct {
  const char *path, *kind;
  SpamOutput *out;
} Listed;

/* Rank 0 lists the file in the manifest (through SpamRunAgreed). */
static PetscErrorCode ListParticles(void *ctx)
{
  Listed *w = ctx;

  PetscFunctionBeginUser;
  PetscCall(SpamManifestAdd(w->out, w->path, w->kind, NAN, PETSC_TRUE));
  PetscCall(SpamManifestWrite(w->out));
  PetscFunctionReturn(0);
}

/* Collective: the CSV is gathered to rank 0, which writes it and lists it. */
static PetscErrorCode WriteParticles(const char *path, SpamSim *sim, SpamOutput *out, const char *kind)
{
  const PetscScalar *y;
  Listed             w = {path, kind, out};

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamParticlesCsvWrite(path, sim, y));
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, ListParticles, &w));
  PetscFunctionReturn(0);
}

static PetscErrorCode Report(const SpamSwarm *sw, const SpamRunOptions *o, const SpamRunResult *r)
{
  PetscFunctionBeginUser;
  if (r->status == SPAM_STATUS_INTERRUPTED) {
    char line[512]; /* snprintf: PETSc's printf writes 3 as "3." */
    (void)snprintf(line, sizeof line, "spam-ark: %s; outputs complete at t = %g of %g after %ld steps", r->reason, r->t, o->t_end, r->steps);
    PetscCall(PetscPrintf(sw->comm, "%s; results in %s\n", line, o->output_dir));
  } else {
    /* Every evaluation the run made: ARKODE's and CVODE's dense output evaluates the RHS at
     * each output time, and SUNDIALS' own statistics (-sundials_stats) count those too. */
    const long extra = r->interpolation_rhs_evals + r->restart_rhs_evals;
    char       cost[160] = "";
    if (extra) (void)snprintf(cost, sizeof cost, " (+%ld by the interpolant%s: %ld in all)", extra, r->restart_rhs_evals ? " and the restart" : "", r->rhs_evals + extra);
    PetscCall(PetscPrintf(sw->comm, "spam-ark: %s after %ld steps (%ld rejected), %ld RHS evaluations%s, %.2f s; energy drift %.3e; results in %s\n", r->status == SPAM_STATUS_UNSTABLE ? "unstable" : "done", r->steps, r->rejected, r->rhs_evals, cost, r->wall, r->energy_drift_max, o->output_dir));
  }
  PetscFunctionReturn(0);
}

/* Rank 0 owns the output directory: its lock, manifest, text series and summary. The
 * other ranks take part in every collective of the run with an output that has no open
 * file (appends to it do nothing). */
static PetscBool DirectoryOwner(const SpamSwarm *sw)
{
  PetscMPIInt rank = 0;
  (void)MPI_Comm_rank(sw->comm, &rank);
  return (PetscBool)(rank == 0);
}

/* Everything that writes, in order; any error returns at once to SpamRunSession. */
static PetscErrorCode Session(SpamSim *sim, const SpamRunOptions *o, TS ts, SpamTsApp *app, SpamOutput *out, SpamRestart *rs, SpamRunResult *r)
{
  const PetscBool owner = DirectoryOwner(&sim->p);

  PetscFunctionBeginUser;
  if (o->initial_csv[0] && !rs) PetscCall(WriteParticles(o->initial_csv, sim, out, "initial_particles"));
  PetscCall(SpamRun(sim, o, ts, app, out, rs, r));
  if (o->final_csv[0] && r->status != SPAM_STATUS_UNSTABLE) PetscCall(WriteParticles(o->final_csv, sim, out, "final_particles"));
  if (!owner) {
    SpamOutputRelease(out);
    PetscFunctionReturn(0);
  }
  PetscCall(SpamSummaryWrite(out, sim, o, r));
  PetscCall(SpamOutputClose(out, ManifestStatus(r->status)));
  PetscFunctionReturn(0);
}

/* The directory opened (or resumed) by rank 0, and its result known to every rank: a
 * refusal (in use, not writable) ends every rank with rank 0's error code, printed once. */
static PetscErrorCode OpenOutputs(SpamSim *sim, const SpamRunOptions *o, const SpamOutputOptions *more, SpamRestart *rs, SpamOutput *out)
{
  PetscErrorCode ierr = 0;

  if (DirectoryOwner(&sim->p)) {
    if (rs) ierr = SpamOutputResume(o->output_dir, o->hdf5, o->csv, more, &rs->file, out);
    else ierr = SpamOutputOpen(o->output_dir, o->hdf5, o->csv, more, out);
  } else {
    (void)PetscMemzero(out, sizeof *out);
    out->lock_fd = -1;
    out->hdf5    = o->hdf5;
    out->csv     = o->csv;
    out->opt     = *more;
    (void)PetscStrncpy(out->dir, o->output_dir, sizeof out->dir);
    if (rs) ierr = SpamOutputResumeLists(&rs->file, out); /* the same list of files as rank 0 */
  }
  if (MPI_Bcast(&ierr, 1, MPI_INT, 0, sim->p.comm) != MPI_SUCCESS) return PETSC_ERR_MPI;
  return ierr;
}

/* The failure has been reported (one line); what is left is to leave the directory
 * honest: summary.json with "status": "failed" and the reason if the disk still takes it
 * (a second failure is ignored, silently), no temporaries, the lock released. */
static void Failed(SpamSim *sim, const SpamRunOptions *o, SpamOutput *out, SpamRunResult *r, PetscErrorCode ierr)
{
  char *msg = NULL;

  if (out->owned && !PetscPushErrorHandler(PetscIgnoreErrorHandler, NULL)) {
    (void)PetscErrorMessage(ierr, NULL, &msg);
    r->status = SPAM_STATUS_FAILED;
    if (ierr == PETSC_ERR_MEM && !(msg && !strncmp(msg, "out of memory", 13))) (void)snprintf(r->reason, sizeof r->reason, "out of memory (%s)", msg && msg[0] ? msg : "an allocation failed");
    else (void)snprintf(r->reason, sizeof r->reason, "%s", msg && msg[0] ? msg : "a library or system failure");
    SpamFileDiscard(&out->timeseries); /* partial files go, and free some room */
    SpamFileDiscard(&out->steps);
    (void)SpamSummaryWrite(out, sim, o, r);
    (void)PetscPopErrorHandler();
  }
  SpamOutputAbandon(out);
}

PetscErrorCode SpamRunSession(SpamSim *sim, const SpamRunOptions *o, const SpamOutputOptions *oo, TS ts, SpamTsApp *app, SpamRestart *rs, int *exit_code)
{
  SpamOutput        out;
  SpamOutputOptions more = *oo;
  SpamRunResult     r;
  SpamInterrupt *sig = NULL;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&r, sizeof r));
  /* From the first file to the last, a signal asks for a clean end instead of killing
   * (one during the opening is seen before the first step: outputs at t = 0). */
  PetscCall(SpamInterruptInstall(&sig));
  SpamWallColumns(sim, more.timeseries_more, sizeof more.timeseries_more);
  ierr = OpenOutputs(sim, o, &more, rs, &out);
  if (!ierr) ierr = Session(sim, o, ts, app, &out, rs, &r);
  if (ierr) Failed(sim, o, &out, &r, ierr);
  PetscCall(SpamInterruptRestore(&sig));
  PetscCall(ierr);
  PetscCall(Report(&sim->p, o, &r));
  *exit_code = SpamRunExitCode(&r);
  PetscFunctionReturn(0);
}
