/* Running a simulation: the run options' parsing, the monitor and the exit code (the record
 * itself, options and result, is run_record.h). */
#ifndef SPAM_RUN_H
#define SPAM_RUN_H
#include <spam/run_record.h>
#include <spam/output_run.h>
#include <spam/error_norm.h>

/* Default of -migrate_interval. A migration after 2 ranks' particles moved up to h/2 took
 * about 7 RHS evaluations of the same particles (decompose.h), and the expansion builds its
 * list about every 3 evaluations: every 20 builds costs about 7 / 60, a tenth of the run,
 * while the fastest particles have moved at most 10 skins (each build follows a move of
 * skin/2), a few cells, so the halo of a rank's bounding box grows by little. */
#define SPAM_MIGRATE_INTERVAL_DEFAULT 20
/* A migration comes sooner, at a list build, once the largest halo has grown by this
 * factor since the last one (loop_migrate.c). */
#define SPAM_MIGRATE_HALO_GROWTH 1.5

/* Reads and validates every run option; sim gives scene defaults (end time). */
PetscErrorCode SpamRunOptionsParse(const SpamSim *sim, SpamRunOptions *o);
/* The output and snapshot intervals of o checked as the options are (finite, not negative,
 * at most a million rows up to o->t_end); from: NULL for the options, or the checkpoint
 * entry the intervals were read from ("checkpoint PATH: entry 'loop'"), which a refusal
 * then names. */
PetscErrorCode SpamRunOptionsCheckIntervals(const SpamRunOptions *o, const char *from);
/* Per-step monitor line and the progress line with ETA. */
PetscErrorCode SpamMonitorStep(MPI_Comm comm, const SpamProgress *p);
PetscErrorCode SpamMonitorProgress(const SpamSim *sim, const SpamRunOptions *o, const SpamProgress *p, const SpamRunResult *r);
/* Drifts of the conserved quantities between two diagnostics. */
void SpamRunUpdateDrifts(const SpamDiagnostics *d, SpamRunResult *r);
/* The exit code of a run that ended with result r (see errors.h; 128 + signal when
 * interrupted, as a shell reports a process a signal ended). */
int SpamRunExitCode(const SpamRunResult *r);
#endif
