/* A run from its first file to its exit code: the output directory, the time loop under
 * SIGINT/SIGTERM handling, the final files, and a failure turned into status "failed". */
#ifndef SPAM_SESSION_H
#define SPAM_SESSION_H
#include <spam/integrator.h>

/* Call once every input is validated (nothing is written before). On success *exit_code
 * says how the run ended (0, 3, 130, 143); an error (a failed write, say) is returned
 * after the open temporaries are removed, summary.json says "status": "failed" with the
 * reason (when it can still be written) and the directory is released. rs: the checkpoint
 * the run continues (checkpoint.h), or NULL. */
PetscErrorCode SpamRunSession(SpamSim *sim, const SpamRunOptions *o, const SpamOutputOptions *oo, TS ts, SpamTsApp *app, SpamRestart *rs, int *exit_code);
#endif
