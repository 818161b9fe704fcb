/* Checkpoints and restart. A checkpoint (OUTPUT_DIR/checkpoint.h5, checkpoint_file.h) holds
 * everything a run needs to go on as if it had never stopped: the particles' state and
 * per-particle fields by id, the neighbour list's reference positions (the right-hand side
 * is a pure function of the state only for the same list), the integrator's next step and
 * controller history, the loop's counters, schedule and result so far, the output series
 * written so far, the whole options string and the program's version.
 *
 * Written every -checkpoint_interval of simulated time, every -checkpoint_wall seconds and
 * when SIGINT or SIGTERM ends the run; always at a step boundary where no stop-time clamp
 * is pending (ERKStep cannot resume a clamped step bit for bit), which may defer a request
 * by a step. On P ranks the one file holds every rank's particles in its local order, the
 * cut and the migration state; a restart takes them back on P ranks (another rank count is
 * refused) and goes on as if uninterrupted. `-restart FILE` continues it: bitwise for arkode (every table, fixed or
 * adaptive), PETSc rk with the basic adaptor (or fixed steps), euler, ssp with fixed steps
 * and basicsymplectic; approximately (the state is exact, the method's history is not) for
 * cvode and PETSc's dsp adaptor. The restarted run appends to the series in the same
 * directory: files written after the checkpoint are removed, the series continue from it. */
#ifndef SPAM_CHECKPOINT_H
#define SPAM_CHECKPOINT_H
#include <spam/integrator.h>
#include <spam/output_resume.h>

/* What a run reads from a checkpoint before it touches its output directory. */
struct SpamRestart {
  SpamCkFile file;
  SpamCkFile mine;       /* several ranks: this rank's particles (the file's otherwise)    */
  PetscMPIInt ranks;     /* the ranks that wrote it (this run's: others are refused)      */
  char       path[PETSC_MAX_PATH_LEN];
  PetscBool  exact;      /* the method continues bit for bit (see above)                */
  char       why[160];   /* why not, when not                                           */
  double     t;
  long       step;
};

/* The run's version line as checkpoints record it and restarts compare it. */
PetscErrorCode SpamCheckpointVersion(char *buf, size_t len);
/* Reads and checks o->restart for this run (sim set up from the same options, ts made):
 * a file that is not a checkpoint, is truncated or corrupt, comes from another version or
 * was written with another physics option, particle count, id or mass is refused (exit 2,
 * one line naming what differs). Output-only options may differ; the output and snapshot
 * intervals not given here are the checkpoint's. Every value is checked (SpamRestartCheck). */
PetscErrorCode SpamRestartLoad(SpamSim *sim, SpamRunOptions *o, const SpamOutputOptions *oo, TS ts, SpamRestart *rs);
/* Every value of the checkpoint rs read (time, step, loop, integrator, result, this rank's
 * particles, the output series) checked as the option or file it came from, before the
 * directory is touched (restart_check.c); oo: the output options (-snapshot_max). */
PetscErrorCode SpamRestartCheck(const SpamSim *sim, const SpamRunOptions *o, const SpamOutputOptions *oo, const SpamRestart *rs);
PetscErrorCode SpamRestartDestroy(SpamRestart *rs);
/* Options whose change keeps the physics (outputs, the end, checkpoints): they may differ
 * between a checkpoint and its restart. name without the leading '-'. */
PetscBool SpamRestartOptionFree(const char *name);
/* The first option (name and both values) that differs between the options strings of a
 * checkpoint and this run, ignoring the free ones; name[0] = 0 when none does. */
PetscErrorCode SpamRestartOptionsDiffer(const char *saved, const char *now, char *name, size_t nlen, char *was, char *is, size_t vlen);
#endif
