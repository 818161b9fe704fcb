/* The walls' diagnostics: the books summed over particles, the rates at an output time,
 * and their timeseries columns. */
#include <spam/diagnostics.h>

static const char *const Axis[3] = {"x", "y", "z"};

/* The walls' rates are the sums of every rank's mirror images' shares. */
static PetscErrorCode SumOverRanks(MPI_Comm comm, SpamWallRates *r)
{
  double      v[SPAM_FACES * 5];
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size == 1) PetscFunctionReturn(0);
  for (int f = 0; f < SPAM_FACES; f++) {
    for (int d = 0; d < 3; d++) v[5 * f + d] = r->force[f][d];
    v[5 * f + 3] = r->work[f];
    v[5 * f + 4] = r->heat[f];
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, v, SPAM_FACES * 5, MPI_DOUBLE, MPI_SUM, comm));
  for (int f = 0; f < SPAM_FACES; f++) {
    for (int d = 0; d < 3; d++) r->force[f][d] = v[5 * f + d];
    r->work[f] = v[5 * f + 3];
    r->heat[f] = v[5 * f + 4];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamWallDiagnostics(SpamSim *sim, const double *y, SpamDiagnostics *d)
{
  const SpamLayout *l = &sim->model.layout;
  const int         nb = 2 + l->dim;
  double            loc[5] = {0, 0, 0, 0, 0}, glob[5], *scratch;
  PetscInt          bad;
  SpamRhsStats      keep = sim->run.stats;

  PetscFunctionBeginUser;
  if (!sim->pair.nl.ghosts.mirror) PetscFunctionReturn(0);
  for (PetscInt i = 0; l->wb >= 0 && i < sim->p.n; i++)
    for (int c = 0; c < nb; c++) loc[c] += y[(size_t)i * l->nvar + l->wb + c];
  PetscCallMPI(MPIU_Allreduce(loc, glob, 5, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  d->wall_work = glob[0];
  d->wall_heat = glob[1];
  for (int k = 0; k < l->dim; k++) d->wall_impulse[k] = glob[2 + k];
  /* The rates at this state: one RHS evaluation, not counted in the run's statistics. */
  PetscCall(PetscMalloc1((size_t)sim->p.n * l->nvar + 1, &scratch));
  PetscCall(sim->model.rhs(sim, y, scratch, &bad));
  PetscCall(PetscFree(scratch));
  sim->run.stats = keep;
  d->wall    = sim->out.wall_rates;
  PetscCall(SumOverRanks(sim->p.comm, &d->wall));
  PetscFunctionReturn(0);
}

void SpamWallColumns(const SpamSim *sim, char *buf, size_t len)
{
  const int dim = sim->model.dim;
  size_t    u   = 0;

  buf[0] = 0;
  if (!SpamWallsAny(&sim->geo.walls, dim)) return;
  u += (size_t)snprintf(buf + u, len - u, ",wall_work,wall_heat");
  for (int k = 0; k < dim && u < len; k++) u += (size_t)snprintf(buf + u, len - u, ",wall_impulse_%s", Axis[k]);
  for (int f = 0; f < 2 * dim && u < len; f++) {
    if (!SpamWallOn(&sim->geo.walls, f)) continue;
    for (int k = 0; k < dim && u < len; k++) u += (size_t)snprintf(buf + u, len - u, ",wall_%s_f%s", SpamFaceNames[f], Axis[k]);
    if (u < len) u += (size_t)snprintf(buf + u, len - u, ",wall_%s_work_rate,wall_%s_heat_rate", SpamFaceNames[f], SpamFaceNames[f]);
  }
}

void SpamWallValues(const SpamSim *sim, const SpamDiagnostics *d, char *buf, size_t len)
{
  const int dim = sim->model.dim;
  size_t    u   = 0;

  buf[0] = 0;
  if (!SpamWallsAny(&sim->geo.walls, dim)) return;
  u += (size_t)snprintf(buf + u, len - u, ",%.12e,%.12e", d->wall_work, d->wall_heat);
  for (int k = 0; k < dim && u < len; k++) u += (size_t)snprintf(buf + u, len - u, ",%.12e", d->wall_impulse[k]);
  for (int f = 0; f < 2 * dim && u < len; f++) {
    if (!SpamWallOn(&sim->geo.walls, f)) continue;
    for (int k = 0; k < dim && u < len; k++) u += (size_t)snprintf(buf + u, len - u, ",%.12e", d->wall.force[f][k]);
    if (u < len) u += (size_t)snprintf(buf + u, len - u, ",%.12e,%.12e", d->wall.energy ? d->wall.work[f] : NAN, d->wall.energy ? d->wall.heat[f] : NAN);
  }
}
