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
  const SpamImage     im = sim->nl.im;
  int                *parent, *label;
  PetscInt            bad;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, y + sim->model.layout.x, sim->model.layout.nvar, PETSC_TRUE, &bad));
  PetscCheck(bad < 0, sim->comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT, bad);
  PetscCall(PetscMalloc2(sim->n + 1, &parent, sim->n + 1, &label));
  for (PetscInt i = 0; i < sim->n; i++) parent[i] = (int)i, label[i] = -1;
  for (int i = 0; i < sim->nl.n; i++) {
    for (int p = sim->nl.start[i]; p < sim->nl.start[i + 1]; p++) {
      double dx[2];
      if (SpamPairDelta2(&sim->nl, &im, i, sim->nl.nbr[p], dx) < range * range) parent[Find(parent, i)] = Find(parent, sim->nl.nbr[p]);
    }
    for (int p = sim->nl.gstart[i]; p < sim->nl.gstart[i + 1]; p++) { /* a periodic image joins its source */
      const int j = sim->nl.gnbr[p], src = sim->nl.ghosts.src[j - sim->nl.n];
      double    dx[2];
      if (sim->nl.ghosts.kind[j - sim->nl.n] == SPAM_GHOST_PERIODIC && SpamPairDelta2(&sim->nl, &im, i, j, dx) < range * range) parent[Find(parent, i)] = Find(parent, src);
    }
  }
  ps->nbody = 0;
  for (PetscInt i = 0; i < sim->n; i++) {
    const int root = Find(parent, (int)i);
    if (label[root] < 0) label[root] = ps->nbody++;
    ps->body[i] = label[root];
  }
  PetscCall(PetscFree2(parent, label));
  PetscCall(PetscFree3(ps->bpos, ps->bneg, ps->bfac));
  PetscCall(PetscCalloc3(ps->nbody, &ps->bpos, ps->nbody, &ps->bneg, ps->nbody, &ps->bfac));
  PetscFunctionReturn(0);
}
