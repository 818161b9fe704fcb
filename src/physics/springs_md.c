/* Molecular dynamics with harmonic springs phi(r) = k/2 (r0 - r)^2 between the pairs that
 * are closer than a bonding range at set-up (PRE Fig. 4a: k = 1, r0 = 1, nearest
 * neighbours of the triangular lattice). Central forces conserve the angular momentum
 * exactly; the state is [x, v], so the symplectic splits can use the acceleration. */
#include <spam/physics.h>
#include "../pair/pair_spring.h"

/* Bonds: a CSR half list (each pair once, in the neighbour list's row) of the pairs closer
 * than range at the positions y. */
static PetscErrorCode BuildBonds(SpamSim *sim, const double *y)
{
  SpamPhysicsScratch *ps = sim->ps;
  const SpamImage     im = SpamBoxImage(&sim->geo.box);
  const double        r2max = sim->model.springs.range * sim->model.springs.range;
  PetscInt            bad;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + sim->model.layout.x, sim->model.layout.nvar, PETSC_TRUE, &bad));
  PetscCheck(bad < 0, sim->p.comm, PETSC_ERR_FP, "non-finite position of particle %" PetscInt_FMT, bad);
  PetscCall(PetscMalloc1(sim->p.n + 1, &ps->bond_start));
  PetscCall(PetscMalloc1(sim->pair.nl.npairs + 1, &ps->bond_nbr));
  ps->nbonds        = 0;
  ps->bond_start[0] = 0;
  for (int i = 0; i < sim->pair.nl.n; i++) {
    for (int p = sim->pair.nl.start[i]; p < sim->pair.nl.start[i + 1]; p++) {
      double dx[2];
      if (SpamPairDelta2(&sim->pair.nl, &im, i, sim->pair.nl.nbr[p], dx) < r2max) ps->bond_nbr[ps->nbonds++] = sim->pair.nl.nbr[p];
    }
    ps->bond_start[i + 1] = ps->nbonds;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUpSprings(SpamSim *sim)
{
  PetscScalar *y;

  PetscFunctionBeginUser;
  PetscCall(SpamPhysicsScratchCreate(sim));
  PetscCall(VecGetArray(sim->p.X, &y));
  PetscCall(SpamBodiesLabel(sim, y, sim->model.springs.range));
  PetscCall(BuildBonds(sim, y));
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* Separation of the points xi and xj, minimum image; returns r. */
static double BondDelta(const SpamSim *sim, const SpamImage *im, const double *xi, const double *xj, double dx[3])
{
  double r2 = 0.0;
  for (int d = 0; d < sim->model.dim; d++) {
    dx[d] = SpamImageDelta(im, d, SpamBoxLocal(&sim->geo.box, d, xi[d]) - SpamBoxLocal(&sim->geo.box, d, xj[d]));
    r2 += dx[d] * dx[d];
  }
  return sqrt(r2);
}

/* Position of bond partner j: a local particle of x (stride), or a remote slot, whose
 * position SpamBondsGather brought. */
static const double *PartnerAt(const SpamSim *sim, const double *x, int stride, int j)
{
  return j < sim->p.n ? x + (size_t)j * stride : sim->ps->bond_halo.xremote + (size_t)(j - sim->p.n) * sim->model.dim;
}

static PetscErrorCode AccelSprings(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  const SpamPhysicsScratch *ps = sim->ps;
  const SpamSpringParams   *sp = &sim->model.springs;
  const SpamImage           im = SpamBoxImage(&sim->geo.box);
  const int                 dim = sim->model.dim;

  PetscFunctionBeginUser;
  *bad = -1;
  PetscCall(SpamBondsGather(sim, x, stride)); /* before any return: it is collective */
  for (PetscInt k = 0; k < sim->p.n * dim; k++) sim->pair.f.acc[k] = 0.0;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    for (int b = ps->bond_start[i]; b < ps->bond_start[i + 1]; b++) {
      const int    j = ps->bond_nbr[b];
      double       dx[3];
      const double r = BondDelta(sim, &im, x + (size_t)i * stride, PartnerAt(sim, x, stride, j), dx);
      if (!isfinite(r) || r == 0.0) {
        *bad = i;
        PetscFunctionReturn(0);
      }
      /* A remote partner's rank keeps this bond too and adds the opposite force to its
       * own particle (newton off across ranks, as the gas's remote pairs). */
      if (j < sim->p.n) SpamPairSpring(dim, &sim->pair.f, sp->k, sp->r0, (int)i, j, dx, r);
      else SpamPairSpringOne(dim, &sim->pair.f, sp->k, sp->r0, (int)i, dx, r);
    }
  }
  sim->run.stats.pair_visits += (double)ps->nbonds;
  PetscFunctionReturn(0);
}

static PetscErrorCode RhsSprings(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l = &sim->model.layout;

  PetscFunctionBeginUser;
  PetscCall(AccelSprings(sim, y + l->x, l->nvar, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < sim->model.dim; d++) {
      ydot[(size_t)i * l->nvar + l->x + d] = y[(size_t)i * l->nvar + l->v + d];
      ydot[(size_t)i * l->nvar + l->v + d] = sim->pair.f.acc[(size_t)i * sim->model.dim + d];
    }
  PetscFunctionReturn(0);
}

/* Potential energy sum k/2 (r0 - r)^2; the forces are central, so no spurious torque.
 * A bond with a remote partner is kept by both ranks: half of it on each. */
static PetscErrorCode DiagSprings(SpamSim *sim, const double *y, SpamModelDiag *d)
{
  const SpamPhysicsScratch *ps = sim->ps;
  const SpamImage           im = SpamBoxImage(&sim->geo.box);
  const SpamLayout         *l  = &sim->model.layout;
  double                    pe = 0.0;

  PetscFunctionBeginUser;
  PetscCall(SpamBondsGather(sim, y + l->x, l->nvar));
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int b = ps->bond_start[i]; b < ps->bond_start[i + 1]; b++) {
      const int    j = ps->bond_nbr[b];
      double       dx[3];
      const double r = BondDelta(sim, &im, y + (size_t)i * l->nvar + l->x, PartnerAt(sim, y + l->x, l->nvar, j), dx);
      const double share = j < sim->p.n ? 0.5 : 0.25;
      pe += share * sim->model.springs.k * (sim->model.springs.r0 - r) * (sim->model.springs.r0 - r);
    }
  PetscCallMPI(MPIU_Allreduce(&pe, &d->internal, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  d->torque = 0.0;
  PetscCall(SpamBodiesDiag(sim, y, d));
  PetscFunctionReturn(0);
}

/* The long-wave speed of a chain of springs, r0 sqrt(k/m): the signal-speed scale of the
 * spring lattice (its lattice sums change it by a factor of order one). */
static PetscErrorCode SpringsSoundSpeed(SpamSim *sim, const double *y, double *cmax)
{
  const SpamSpringParams *s = &sim->model.springs;

  PetscFunctionBeginUser;
  (void)y;
  *cmax = s->r0 * sqrt(s->k / sim->model.mass);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamModelSpringsSetUp(int dim, double h, double mass, double kspring, double r0, double bond_range, SpamModel *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof *m));
  m->dim     = dim;
  m->mass    = mass;
  m->springs = (SpamSpringParams){kspring, r0, bond_range};
  PetscCall(SpamKernelLucyInit(dim, h, &m->kernel)); /* the neighbour search range at set-up */
  PetscCall(SpamLayoutPositionsVelocities(dim, &m->layout));
  m->rhs   = RhsSprings;
  m->inverse_mass = PETSC_TRUE; /* pair_spring.h */
  m->accel = AccelSprings;
  m->max_sound_speed = SpringsSoundSpeed;
  m->diag  = DiagSprings;
  m->setup = SetUpSprings;
  m->carry_depart = SpamBondsDepart;
  m->carry_arrive = SpamBondsArrive;
  PetscCall(PetscStrncpy(m->name, "springs", sizeof m->name));
  PetscFunctionReturn(0);
}
