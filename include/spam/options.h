/* Checks of the options as a whole: the command line before PETSc reads it, values given
 * without a value, and options given but not used by this run. */
#ifndef SPAM_OPTIONS_H
#define SPAM_OPTIONS_H
#include <spam/sim.h>
#include <spam/run.h>
#include <petscts.h>

#include <spam/argv.h>

/* Refuses a non-boolean option of spam-ark given with no value or an empty one (PETSc
 * would ignore it). Reads the database without marking anything used. */
PetscErrorCode SpamOptionsCheckValues(void);

/* At the end of set-up: refuses every option given that this run does not use, naming why
 * (the method, scene or model it applies to), and every unknown option with the nearest
 * known name. PETSc's own run-time options (SpamOptionsPetscRuntime) pass. */
PetscErrorCode SpamOptionsCheckUse(const SpamSim *sim, const SpamRunOptions *o, TS ts);
#endif
