/* Whether a run writes its outputs from the method's dense output or stops at them.
 * Stopping at every output time cuts the step the controller chose, so the cadence of the
 * outputs, not the method, sets the step count of a loose tolerance (measured: 20 of 30
 * steps of F8 at rtol 1e-4). An interpolant removes that, where the method has one and
 * the state evolves smoothly between two step ends. */
#include "ts_family.h"

const char *const SpamOutputModeNames[] = {"interpolated", "stopped", "steps"};

PetscErrorCode SpamTSOutputMode(TS ts, const SpamTsApp *app, double fixed_dt, SpamOutputMode *mode, char *why, size_t len)
{
  const SpamSim *sim = app->sim;
  const SpamTSFamily *f;
  PetscBool           interp = PETSC_FALSE;

  PetscFunctionBeginUser;
  why[0] = 0;
  *mode  = SPAM_OUTPUT_STOPPED;
  PetscCall(SpamTSFamilyOf(ts, &f));
  if (f->interpolates) PetscCall(f->interpolates(ts, &interp));
  if (fixed_dt > 0) {
    /* The output intervals are whole steps (time_loop.c): the step ends are the output
     * times, nothing to interpolate and no step cut but the last, to t_end. */
    *mode = SPAM_OUTPUT_STEPS;
    (void)snprintf(why, len, "fixed step %.6g: the output intervals are rounded to whole steps, which land on the output times", fixed_dt);
  } else if (app->o->output_stop) (void)snprintf(why, len, "-output_stop true");
  else if (sim->model.post_step || sim->pair.nl.ghosts.mirror) {
    /* A wall reflection or closest-approach jump happens after a step: the interpolant of
     * that step holds the particle beyond the wall (or the pair too close) at the times in
     * between, a state the run never had. Stopping keeps every output a state it had. */
    (void)snprintf(why, len, "the state jumps after steps (%s): an interpolant across a jump is not a state of the run", sim->pair.nl.ghosts.mirror ? "mirror-wall reflections" : "closest-approach reflections");
  } else if (!interp) {
    const char *sub = "";
    if (f->sub_type) PetscCall(f->sub_type(ts, &sub));
    (void)snprintf(why, len, "%s %s has no interpolant in PETSc 3.18", f->type, sub);
  }
  else *mode = SPAM_OUTPUT_INTERPOLATED;
  PetscFunctionReturn(0);
}
