/* Conserved and monitored quantities of a state, reduced over all ranks. */
#include <spam/diagnostics.h>
#include <spam/entropy.h>
#include <stdint.h>

/* Internal energy, spurious torque and bodies, as the model computes them. */
static PetscErrorCode ModelDiagnostics(SpamSim *sim, const double *y, SpamDiagnostics *d)
{
  SpamModelDiag md = {0.0, NAN, 0.0, 0, {NAN, NAN}, 0.0};

  PetscFunctionBeginUser;
  PetscCall(sim->model.diag(sim, y, &md));
  d->internal       = md.internal;
  PetscCall(SpamGravityEnergy(sim, y, &md.potential));
  d->potential      = md.potential;
  d->total          = d->kinetic + d->internal + d->potential;
  d->torque         = md.torque;
  d->nbody          = md.nbody;
  d->lbody[0]       = md.lbody[0];
  d->lbody[1]       = md.lbody[1];
  d->gauss_singular = md.gauss_singular;
  PetscFunctionReturn(0);
}

/* sum m b of the flow scheme's book b (0 where the layout has none). */
static PetscErrorCode SchemeEnergy(SpamSim *sim, const double *y, double *e)
{
  const SpamLayout *l   = &sim->model.layout;
  double            loc = 0.0;

  PetscFunctionBeginUser;
  *e = 0.0;
  if (l->fb < 0) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->p.n; i++) loc += sim->pair.f.m[i] * y[(size_t)i * l->nvar + l->fb];
  PetscCallMPI(MPIU_Allreduce(&loc, e, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}

/* Sums over particles of m, m v, m x and the energies; angular momentum needs the centre
 * of mass first, so it is a second pass. Positions are taken relative to the box corner
 * (unwrapped), which keeps every figure independent of where the box sits. */
PetscErrorCode SpamDiagnosticsCompute(SpamSim *sim, const SpamDiagnosticsOptions *o, double t, const double *y, SpamDiagnostics *d)
{
  const SpamModel  *m = &sim->model;
  const SpamLayout *l = &m->layout;
  const int         dim = m->dim;
  double            loc[11] = {0}, glob[11], xc[3] = {0, 0, 0}, vc[3] = {0, 0, 0}, lloc[4] = {0, 0, 0, 0}, lglob[4];
  PetscInt          bad;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(d, sizeof *d));
  d->t = t;
  PetscCall(SpamDensitySummation(sim, y, &bad));
  {
    /* the input row of the first bad particle over all ranks (a rank whose own are all
     * finite learns it here): every rank stops, with one message */
    PetscInt64 row = bad >= 0 && bad < sim->p.n ? (PetscInt64)SpamSimRowOf(sim, bad) : INT64_MAX;
    PetscInt   any = bad >= 0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &row, 1, MPIU_INT64, MPI_MIN, sim->p.comm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPIU_INT, MPI_MAX, sim->p.comm));
    PetscCheck(!any, sim->p.comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt64_FMT " at t = %g", row, t);
  }
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, mi = sim->pair.f.m[i];
    double        v2 = 0.0;
    for (int k = 0; k < dim; k++) {
      loc[1 + k] += mi * p[l->v + k];
      loc[4 + k] += mi * (p[l->x + k] - sim->geo.box.lo[k]);
      v2 += p[l->v + k] * p[l->v + k];
    }
    loc[0] += mi;
    loc[7] += 0.5 * mi * v2;
  }
  PetscCallMPI(MPIU_Allreduce(loc, glob, 11, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  d->mass = glob[0];
  for (int k = 0; k < dim; k++) {
    d->p[k] = glob[1 + k];
    xc[k]   = glob[4 + k] / d->mass;
    vc[k]   = glob[1 + k] / d->mass;
  }
  d->kinetic  = glob[7];
  d->total    = d->kinetic;
  /* Angular momentum about the centre of mass, in the centre-of-mass frame. */
  for (PetscInt i = 0; i < sim->p.n && dim >= 2; i++) {
    const double *p = y + (size_t)i * l->nvar;
    double        r[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (int k = 0; k < dim; k++) {
      r[k] = p[l->x + k] - sim->geo.box.lo[k] - xc[k];
      v[k] = p[l->v + k] - vc[k];
    }
    const double  mi = sim->pair.f.m[i];
    lloc[0] += mi * (r[1] * v[2] - r[2] * v[1]);
    lloc[1] += mi * (r[2] * v[0] - r[0] * v[2]);
    lloc[2] += mi * (r[0] * v[1] - r[1] * v[0]);
    lloc[3] += mi * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  PetscCallMPI(MPIU_Allreduce(lloc, lglob, 4, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  for (int k = 0; k < 3; k++) d->l[k] = lglob[k];
  d->gyration = sqrt(lglob[3] / d->mass);
  PetscCall(ModelDiagnostics(sim, y, d));
  if (o->entropy && !m->tensor && strcmp(m->name, "springs")) { /* the entropy estimates are those of the isentropic gas */
    PetscCall(SpamEntropySum(sim, y, &d->entropy_sum));
    if (o->grid_spacing > 0) PetscCall(SpamEntropyGrid(sim, y, o->grid_spacing, &d->entropy_grid));
  } else if (o->entropy_gas) { /* the gas's sum estimate with its own e_i (run_options.c) */
    PetscCall(SpamEntropySum(sim, y, &d->entropy_sum));
    d->entropy_grid = NAN;
  }
  PetscCall(SpamWallDiagnostics(sim, y, d));
  PetscCall(SchemeEnergy(sim, y, &d->scheme_energy));
  d->energy_in = d->wall_work + d->wall_heat + d->scheme_energy;
  /* Walls without books (the isentrope's: its state is [x v]) exchange momentum unmeasured:
   * its drift is then not defined (null in summary.json). */
  for (int k = 0; k < dim; k++) d->momentum_in[k] = sim->pair.nl.ghosts.mirror && l->wb < 0 ? NAN : d->wall_impulse[k] + d->mass * m->gravity[k] * t;
  PetscFunctionReturn(0);
}
