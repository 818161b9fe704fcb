/* What the output layer does with a run's record: checks the output options against the
 * run's times, and writes summary.json. */
#ifndef SPAM_OUTPUT_RUN_H
#define SPAM_OUTPUT_RUN_H
#include <spam/run_record.h>

/* Reads -output_overwrite, -snapshot_max and -grid_interval; refuses a snapshot interval
 * that would write more than -snapshot_max snapshots and a grid spacing that is negative,
 * not finite, gives too many points over sim's box or has no snapshot times to be written
 * at. Call before the set-up ends (see main.c). */
PetscErrorCode SpamOutputOptionsParse(const SpamSim *sim, const SpamRunOptions *ro, SpamOutputOptions *o);
/* The snapshot count of ro's interval up to ro->t_end against -snapshot_max, and the grid
 * fields against the snapshot times, as SpamOutputOptionsParse checks them; from as for
 * SpamRunOptionsCheckIntervals. */
PetscErrorCode SpamOutputOptionsCheckSnapshots(const SpamSim *sim, const SpamRunOptions *ro, const SpamOutputOptions *o, const char *from);

/* summary.json: the run's outcome, counts, conservation and performance (rank 0 writes it). */
PetscErrorCode SpamSummaryWrite(SpamOutput *out, const SpamSim *sim, const SpamRunOptions *o, const SpamRunResult *r);
#endif
