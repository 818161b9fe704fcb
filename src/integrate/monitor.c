/* Monitor lines and the drift bookkeeping of conserved quantities. */
#include <spam/run.h>

PetscErrorCode SpamMonitorStep(MPI_Comm comm, const SpamProgress *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "step %6ld  t %-12.6g dt %-11.4e set by %-8s rejected %-5ld rhs %-7ld bound-limited %ld\n", p->steps, p->t, p->dt, p->limit ? p->limit : "-", p->rejected, p->rhs_evals, p->limited));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamMonitorProgress(const SpamSim *sim, const SpamRunOptions *o, const SpamProgress *p, const SpamRunResult *r)
{
  const double frac = o->t_end > 0 ? p->t / o->t_end : 1.0;
  const double eta  = frac > 0 ? p->wall * (1.0 - frac) / frac : 0.0;
  const double norm = (double)sim->p.nglobal * log(sim->out.scene.volume_ratio > 0 ? sim->out.scene.volume_ratio : 1.0);

  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(sim->p.comm, "t %-10.5g %5.1f%%  steps %-6ld rejected %-4ld rhs %-7ld dt %-10.3e dE/E %-9.2e", p->t, 100.0 * frac, p->steps, p->rejected, p->rhs_evals, p->dt, r->energy_drift_max));
  if (norm > 0) PetscCall(PetscPrintf(sim->p.comm, " dS/NklnV %6.3f", (r->last.entropy_sum - r->first.entropy_sum) / norm));
  PetscCall(PetscPrintf(sim->p.comm, "  rhs %3.0f%% of wall %.1fs eta %.1fs\n", p->wall > 0 ? 100.0 * p->rhs_time / p->wall : 0.0, p->wall, eta));
  PetscFunctionReturn(0);
}

/* Drift scales: energy against |E0|, or against the run's energy scale (time_loop.c) when
 * E0 is zero to round-off (a body at rest and unstrained, whose |E - E0| / 1e-300 printed
 * as 1e+269); momentum against sqrt(2 M E0), the momentum the system would have if all its
 * energy were motion in one direction; angular momentum against that momentum times the
 * initial radius of gyration. */
void SpamRunUpdateDrifts(const SpamDiagnostics *d, SpamRunResult *r)
{
  const SpamDiagnostics *d0 = &r->first;
  const double           e_ref = fabs(d0->total) > 1e-12 * r->energy_scale ? fabs(d0->total) : PetscMax(r->energy_scale, 1e-300);
  double                 dp = 0.0, dl = 0.0;

  r->momentum_scale = sqrt(2.0 * d0->mass * PetscMax(fabs(d0->total), 1e-300));
  r->angmom_scale   = r->momentum_scale * PetscMax(d0->gyration, 1e-300);
  for (int k = 0; k < 3; k++) {
    const double gain = d->momentum_in[k] - d0->momentum_in[k];
    dp += (d->p[k] - d0->p[k] - gain) * (d->p[k] - d0->p[k] - gain);
    dl += (d->l[k] - d0->l[k]) * (d->l[k] - d0->l[k]);
  }
  r->energy_drift_max   = PetscMax(r->energy_drift_max, fabs(d->total - d0->total - (d->energy_in - d0->energy_in)) / e_ref);
  /* Not measured (walls without books): NaN stays NaN (PetscMax would drop it). */
  r->momentum_drift_max = isfinite(dp) ? PetscMax(r->momentum_drift_max, sqrt(dp) / r->momentum_scale) : NAN;
  r->angmom_drift_max   = PetscMax(r->angmom_drift_max, sqrt(dl) / r->angmom_scale);
}
