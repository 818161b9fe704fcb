/* Conserved and monitored quantities of a state, reduced over all ranks. */
#include <spam/diagnostics.h>
#include <spam/physics.h>

/* Internal energy and spurious torque from the model; angular momentum of each body. */
static PetscErrorCode ModelDiagnostics(SpamSim *sim, const double *y, SpamDiagnostics *d)
{
  SpamModelDiag md;
  double        lb[2] = {NAN, NAN};

  PetscFunctionBeginUser;
  d->torque         = NAN;
  d->lbody[0]       = d->lbody[1] = NAN;
  d->gauss_singular = 0.0;
  if (!sim->model.diag) PetscFunctionReturn(0);
  PetscCall(sim->model.diag(sim, y, &md));
  d->internal += md.internal;
  d->total    = d->kinetic + d->internal;
  d->torque   = md.torque;
  if (sim->ps && sim->model.dim == 2) {
    d->nbody          = sim->ps->nbody;
    d->gauss_singular = (double)sim->ps->gauss_singular;
    if (sim->ps->nbody <= 2) {
      PetscCall(SpamBodyAngularMomentum(sim, y, lb));
      d->lbody[0] = lb[0];
      if (sim->ps->nbody == 2) d->lbody[1] = lb[1];
    }
  }
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
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT " at t = %g", bad, t);
  for (PetscInt i = 0; i < sim->n; i++) {
    const double *p = y + (size_t)i * l->nvar;
    double        v2 = 0.0;
    for (int k = 0; k < dim; k++) {
      loc[1 + k] += m->mass * p[l->v + k];
      loc[4 + k] += m->mass * (p[l->x + k] - sim->box.lo[k]);
      v2 += p[l->v + k] * p[l->v + k];
    }
    loc[0] += m->mass;
    loc[7] += 0.5 * m->mass * v2;
    if (!m->diag) loc[8] += m->mass * SpamEosEnergy(&m->eos, sim->f.rho[i]);
  }
  PetscCallMPI(MPIU_Allreduce(loc, glob, 11, MPI_DOUBLE, MPI_SUM, sim->comm));
  d->mass = glob[0];
  for (int k = 0; k < dim; k++) {
    d->p[k] = glob[1 + k];
    xc[k]   = glob[4 + k] / d->mass;
    vc[k]   = glob[1 + k] / d->mass;
  }
  d->kinetic  = glob[7];
  d->internal = glob[8];
  d->total    = d->kinetic + d->internal;
  /* Angular momentum about the centre of mass, in the centre-of-mass frame. */
  for (PetscInt i = 0; i < sim->n && dim >= 2; i++) {
    const double *p = y + (size_t)i * l->nvar;
    double        r[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (int k = 0; k < dim; k++) {
      r[k] = p[l->x + k] - sim->box.lo[k] - xc[k];
      v[k] = p[l->v + k] - vc[k];
    }
    lloc[0] += m->mass * (r[1] * v[2] - r[2] * v[1]);
    lloc[1] += m->mass * (r[2] * v[0] - r[0] * v[2]);
    lloc[2] += m->mass * (r[0] * v[1] - r[1] * v[0]);
    lloc[3] += m->mass * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  PetscCallMPI(MPIU_Allreduce(lloc, lglob, 4, MPI_DOUBLE, MPI_SUM, sim->comm));
  for (int k = 0; k < 3; k++) d->l[k] = lglob[k];
  d->gyration = sqrt(lglob[3] / d->mass);
  PetscCall(ModelDiagnostics(sim, y, d));
  if (o->entropy && !m->diag) { /* the entropy estimates are those of the isentropic gas */
    PetscCall(SpamEntropySum(sim, y, &d->entropy_sum));
    if (o->grid_spacing > 0) PetscCall(SpamEntropyGrid(sim, y, o->grid_spacing, &d->entropy_grid));
  }
  PetscFunctionReturn(0);
}

/* Per body: sums of m, m r, m v, then Lz = sum m (r - r_b) x (v - v_b). */
PetscErrorCode SpamBodyAngularMomentum(SpamSim *sim, const double *y, double *lbody)
{
  const SpamLayout *l  = &sim->model.layout;
  const int         nb = sim->ps->nbody;
  const double      m  = sim->model.mass;
  double           *s, *lz;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2(5 * nb, &s, nb, &lz));
  for (PetscInt i = 0; i < sim->n; i++) {
    const double *p = y + (size_t)i * l->nvar;
    double       *b = s + 5 * sim->ps->body[i];
    b[0] += m;
    for (int d = 0; d < 2; d++) {
      b[1 + d] += m * p[l->x + d];
      b[3 + d] += m * p[l->v + d];
    }
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, s, 5 * nb, MPI_DOUBLE, MPI_SUM, sim->comm));
  for (PetscInt i = 0; i < sim->n; i++) {
    const double *p = y + (size_t)i * l->nvar, *b = s + 5 * sim->ps->body[i];
    const double  r[2] = {p[l->x] - b[1] / b[0], p[l->x + 1] - b[2] / b[0]}, v[2] = {p[l->v] - b[3] / b[0], p[l->v + 1] - b[4] / b[0]};
    lz[sim->ps->body[i]] += m * (r[0] * v[1] - r[1] * v[0]);
  }
  PetscCallMPI(MPIU_Allreduce(lz, lbody, nb, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscCall(PetscFree2(s, lz));
  PetscFunctionReturn(0);
}
