/* One row of diagnostics per output time, and one row per accepted step. */
#include <spam/output.h>

PetscErrorCode SpamTimeseriesAppend(SpamOutput *o, const SpamSim *sim, const SpamProgress *pr, const SpamDiagnostics *d, const SpamDiagnostics *d0)
{
  const double norm = (double)sim->p.nglobal * log(sim->out.scene.volume_ratio > 0 ? sim->out.scene.volume_ratio : 1.0);
  double       rs = NAN, rg = NAN;
  char         walls[2048];

  PetscFunctionBeginUser;
  o->step = pr->steps;
  SpamWallValues(sim, d, walls, sizeof walls);
  if (norm > 0) {
    rs = (d->entropy_sum - d0->entropy_sum) / norm;
    rg = (d->entropy_grid - d0->entropy_grid) / norm;
  }
  SpamFilePrintf(&o->timeseries, "%.10g,%ld,%ld,%ld,%.6e,%.10g,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%.12e,%.12e,%.12e,%.10e,%.10e,%.8f,%.8f,%ld,%.4f,%.4f,%.12e,%d,%.15e,%.15e,%.0f,%.12e,%.12e%s\n", d->t, pr->steps, pr->rejected, pr->rhs_evals, pr->dt, d->mass, d->p[0], d->p[1], d->p[2], d->l[0], d->l[1], d->l[2], d->kinetic, d->internal, d->total, d->entropy_sum, d->entropy_grid, rs, rg, pr->limited, pr->rhs_time, pr->wall, d->torque, d->nbody, d->lbody[0], d->lbody[1], d->gauss_singular, d->potential, d->scheme_energy, walls);
  /* Flushed every row: a reader (or a killed run) sees whole rows only. */
  PetscCall(SpamFileCheck(&o->timeseries));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamStepsAppend(SpamOutput *o, const SpamProgress *pr)
{
  PetscFunctionBeginUser;
  SpamFilePrintf(&o->steps, "%ld,%.17g,%.17g,%ld,%ld,%s\n", pr->steps, pr->t, pr->dt, pr->rejected, pr->rhs_evals, pr->limit ? pr->limit : "");
  /* Not flushed each step (one row per step would cost a system call each); a write
   * error is sticky and shows here or at the latest when the file is committed. */
  if (o->steps.err) PetscCall(SpamFileCheck(&o->steps));
  PetscFunctionReturn(0);
}
