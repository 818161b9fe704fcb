/* Checks of the options as a whole: the command line before PETSc reads it, values given
 * without a value, and options given but not used by this run. */
#ifndef SPAM_OPTIONS_H
#define SPAM_OPTIONS_H
#include <spam/sim.h>
#include <spam/run.h>
#include <petscts.h>

/* Before PetscInitialize: rewrites --help and --version to -help and -version, answers
 * -version ("spam-ark VERSION"), and checks every -options_file argument (and the
 * -options_file lines inside those files) the way PETSc would read it, so that a missing,
 * unreadable or malformed file is one line of bad input, not PETSc's abort. Returns -1 to
 * go on, else the exit code (0 after -version, 2 after printing the bad input). */
int SpamArgvCheck(int argc, char **argv);

/* Refuses a non-boolean option of spam-ark given with no value or an empty one (PETSc
 * would ignore it). Reads the database without marking anything used. */
PetscErrorCode SpamOptionsCheckValues(void);

/* At the end of set-up: refuses every option given that this run does not use, naming why
 * (the method, scene or model it applies to), and every unknown option with the nearest
 * known name. PETSc's own run-time options (SpamOptionsPetscRuntime) pass. */
PetscErrorCode SpamOptionsCheckUse(const SpamSim *sim, const SpamRunOptions *o, TS ts);
#endif
