/* Connected bodies: particles closer than a range share a body. Union-find with path
 * halving over the neighbour list; labels are renumbered 0..nbody-1 in order of the
 * first particle of each body, so they are deterministic. */
#include <spam/physics.h>

static int Find(int *parent, int i)
{
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i         = parent[i];
  }
  return i;
}

PetscErrorCode SpamBodiesLabel(SpamSim *sim, const double *y, double range)
{
  SpamPhysicsScratch *ps = sim->ps;
  const SpamImage     im = sim->pair.nl.im;
  int                *parent, *label;
  PetscInt            bad;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + sim->model.layout.x, sim->model.layout.nvar, PETSC_TRUE, &bad));
  PetscCheck(bad < 0, sim->p.comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT, bad);
  PetscCall(PetscMalloc2(sim->p.n + 1, &parent, sim->p.n + 1, &label));
  for (PetscInt i = 0; i < sim->p.n; i++) parent[i] = (int)i, label[i] = -1;
  for (int i = 0; i < sim->pair.nl.n; i++) {
    for (int p = sim->pair.nl.start[i]; p < sim->pair.nl.start[i + 1]; p++) {
      double dx[2];
      if (SpamPairDelta2(&sim->pair.nl, &im, i, sim->pair.nl.nbr[p], dx) < range * range) parent[Find(parent, i)] = Find(parent, sim->pair.nl.nbr[p]);
    }
    for (int p = sim->pair.nl.gstart[i]; p < sim->pair.nl.gstart[i + 1]; p++) { /* a periodic image joins its source */
      const int j = sim->pair.nl.gnbr[p], src = sim->pair.nl.ghosts.src[j - sim->pair.nl.n];
      double    dx[2];
      if (sim->pair.nl.ghosts.kind[j - sim->pair.nl.n] == SPAM_GHOST_PERIODIC && SpamPairDelta2(&sim->pair.nl, &im, i, j, dx) < range * range) parent[Find(parent, i)] = Find(parent, src);
    }
  }
  ps->nbody = 0;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const int root = Find(parent, (int)i);
    if (label[root] < 0) label[root] = ps->nbody++;
    ps->body[i] = label[root];
  }
  PetscCall(PetscFree2(parent, label));
  PetscCall(PetscFree3(ps->bpos, ps->bneg, ps->bfac));
  PetscCall(PetscCalloc3(ps->nbody, &ps->bpos, ps->nbody, &ps->bneg, ps->nbody, &ps->bfac));
  PetscFunctionReturn(0);
}

/* Per body: sums of m, m r, m v, then Lz = sum m (r - r_b) x (v - v_b). */
PetscErrorCode SpamBodyAngularMomentum(SpamSim *sim, const double *y, double *lbody)
{
  const SpamLayout *l  = &sim->model.layout;
  const int         nb = sim->ps->nbody;
  double           *s, *lz;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2(5 * nb, &s, nb, &lz));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, m = sim->pair.f.m[i];
    double       *b = s + 5 * sim->ps->body[i];
    b[0] += m;
    for (int d = 0; d < 2; d++) {
      b[1 + d] += m * p[l->x + d];
      b[3 + d] += m * p[l->v + d];
    }
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, s, 5 * nb, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, *b = s + 5 * sim->ps->body[i], m = sim->pair.f.m[i];
    const double  r[2] = {p[l->x] - b[1] / b[0], p[l->x + 1] - b[2] / b[0]}, v[2] = {p[l->v] - b[3] / b[0], p[l->v + 1] - b[4] / b[0]};
    lz[sim->ps->body[i]] += m * (r[0] * v[1] - r[1] * v[0]);
  }
  PetscCallMPI(MPIU_Allreduce(lz, lbody, nb, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscCall(PetscFree2(s, lz));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamBodiesDiag(SpamSim *sim, const double *y, SpamModelDiag *d)
{
  PetscFunctionBeginUser;
  d->lbody[0] = d->lbody[1] = NAN;
  if (!sim->ps || sim->model.dim != 2) PetscFunctionReturn(0);
  d->nbody          = sim->ps->nbody;
  d->gauss_singular = (double)sim->ps->gauss_singular;
  if (sim->ps->nbody <= 2) {
    double lb[2] = {NAN, NAN};
    PetscCall(SpamBodyAngularMomentum(sim, y, lb));
    d->lbody[0] = lb[0];
    if (sim->ps->nbody == 2) d->lbody[1] = lb[1];
  }
  PetscFunctionReturn(0);
}
