/* Right-hand side of the isentropic gas (Hoover & Hoover 2001, Eqs. 8 and 13):
 *   dr_i/dt = v_i,
 *   dv_i/dt = -m sum_j [(P/rho^2)_i + (P/rho^2)_j] grad_i w_ij.
 * With gamma = 2 the bracket is constant and the density pass is skipped (Eq. 20). One
 * list update per evaluation, then the passes of one context (pair_pass.h): the chunked
 * half-list rows (pass_chunked.c), or under -reproducible the canonical rows
 * (pass_canonical.c). Nothing here allocates. */
#include <spam/sim.h>
#include <spam/gas_images.h>
#include <spam/physics.h>
#include "../pair/pair_pass.h"

/* The context of sim's current list (after SpamNeighboursUpdate and the slots' reserve). */
static SpamPairPass SpamPairPassOf(SpamSim *sim)
{
  const SpamGhosts *gh = &sim->pair.nl.ghosts;
  SpamPairPass      p  = {0};
  p.nl                 = &sim->pair.nl;
  p.k                  = &sim->model.kernel;
  p.f                  = &sim->pair.f;
  p.gh                 = gh;
  p.n                  = (int)sim->p.n;
  p.slots              = SpamNeighboursSlots(&sim->pair.nl);
  p.dim                = sim->model.dim;
  p.ghost_newton       = gh->nlocal > 0 || gh->mirror;
  p.canonical          = SpamNeighboursCanonical(&sim->pair.nl);
  /* the thread buffers hold the local particles only: ghost reactions are one thread's
   * (the canonical rows take none: a row is one thread's whatever the ghosts) */
  p.threads            = p.ghost_newton && !p.canonical ? 1 : sim->pair.threads;
  p.tacc               = sim->pair.tacc;
  p.trho               = sim->pair.trho;
  p.uniform_mass       = sim->pair.f.uniform_mass;
  p.mass               = sim->p.n ? sim->pair.f.m[0] : sim->model.mass;
  p.uniform_q          = sim->model.density_free;
  return p;
}

/* Room for the ghost slots of the current list in the fields (grows only when a list
 * build found more ghosts than ever before), and their masses after a build. */
static PetscErrorCode ReserveSlots(SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(SpamFieldsReserve(&sim->pair.f, SpamNeighboursSlots(&sim->pair.nl)));
  PetscCall(SpamSimGhostMasses(sim));
  PetscFunctionReturn(0);
}

/* Summation density of the context's list into f->rho (local slots). */
static PetscErrorCode Density(SpamRunCounts *run, const SpamPairPass *p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(run->ev.density, 0, 0, 0, 0));
  if (p->canonical) PetscCall(SpamCanonicalDensity(p));
  else PetscCall(SpamChunkedDensity(p));
  PetscCall(PetscLogEventEnd(run->ev.density, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* The right-hand side's rows (y, ydot) written as the force pass completes them. */
typedef struct {
  const SpamSim *sim;
  const double  *y;
  double        *ydot;
  PetscBool      stale; /* the list's positions are placed by the pass (SpamNeighboursUpdateStale) */
} RhsOut;

/* dr/dt = v and dv/dt = acc of particles [i0, i1) in the layout [x v] (nvar = 2 dim),
 * dim a literal: copies the compiler makes whole-vector moves of. Through the layout's
 * offsets and a loop over a run-time dim it took 45 instructions a particle in 2D, 7 % of
 * the gas's right-hand side (callgrind, gas h = 3, N = 65536). */
static inline __attribute__((always_inline)) void CopyRows(const int dim, const double *restrict y, double *restrict ydot, const double *restrict acc, size_t i0, size_t i1)
{
  for (size_t i = i0; i < i1; i++)
    for (int d = 0; d < dim; d++) {
      ydot[i * 2 * dim + d]       = y[i * 2 * dim + dim + d];
      ydot[i * 2 * dim + dim + d] = acc[i * dim + d];
    }
}

/* Whether the rows are [x v] without gravity (CopyRows writes them). */
static PetscBool PlainRows(const SpamModel *m)
{
  const SpamLayout *l = &m->layout;
  return (PetscBool)(!m->gravity_on && l->x == 0 && l->v == m->dim && l->nvar == 2 * m->dim && m->dim >= 1 && m->dim <= 3);
}

static void WriteRowsPlain(int dim, const double *y, double *ydot, const double *acc, size_t i0, size_t i1)
{
  if (dim == 1) CopyRows(1, y, ydot, acc, i0, i1);
  else if (dim == 2) CopyRows(2, y, ydot, acc, i0, i1);
  else CopyRows(3, y, ydot, acc, i0, i1);
}

/* dr/dt = v and dv/dt = acc (plus gravity, added to acc as the unblocked path does) of
 * particles [i0, i1). */
static void WriteRows(void *ctx, int i0, int i1)
{
  const RhsOut     *o = ctx;
  const SpamModel  *m = &o->sim->model;
  const SpamLayout *l = &m->layout;
  const int         dim = m->dim, nv = l->nvar;
  double           *acc = o->sim->pair.f.acc;

  if (PlainRows(m)) {
    WriteRowsPlain(dim, o->y, o->ydot, acc, (size_t)i0, (size_t)i1);
    return;
  }
  for (int i = i0; i < i1; i++)
    for (int d = 0; d < dim; d++) {
      if (m->gravity_on) acc[(size_t)i * dim + d] += m->gravity[d];
      o->ydot[(size_t)i * nv + l->x + d] = o->y[(size_t)i * nv + l->v + d];
      o->ydot[(size_t)i * nv + l->v + d] = acc[(size_t)i * dim + d];
    }
}

/* Accelerations from f->q = P/rho^2 into f->acc; the walls' books of the mirror slots.
 * With out (a right-hand side) and a pass that fits the row blocks, the rows of ydot are
 * written by the pass as their accelerations complete (*written set), while they are in
 * the cache. */
static PetscErrorCode Force(SpamSim *sim, const SpamPairPass *p, RhsOut *out, PetscBool *written)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->run.ev.force, 0, 0, 0, 0));
  *written = (PetscBool)(out && SpamChunkedForceFits(p));
  if (out && out->stale && !*written) SpamNeighboursPlace(p->nl, out->y + sim->model.layout.x, sim->model.layout.nvar, 0, p->n);
  if (p->canonical) PetscCall(SpamCanonicalForce(p));
  else if (*written) PetscCall(SpamChunkedForceBlocks(p, out->stale ? out->y + sim->model.layout.x : NULL, sim->model.layout.nvar, WriteRows, out));
  else PetscCall(SpamChunkedForce(p));
  /* The isentrope's walls: their forces only (its energy has no equation to book work in). */
  if (p->gh->mirror) PetscCall(SpamWallBooks(p->gh, p->f, &sim->model.layout, p->n, PETSC_FALSE, &sim->out.wall_rates, NULL));
  PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDensityOfList(SpamSim *sim)
{
  const SpamPairPass p = SpamPairPassOf(sim);

  PetscFunctionBeginUser;
  if (sim->pair.f.adaptive) { /* each particle's own range: the h solve sums the density */
    PetscCall(SpamSmoothingSolve(sim));
    PetscFunctionReturn(0);
  }
  if (SpamGasImagesOfPlace(sim)) SpamGasImagesMasses(sim); /* the ghosts' temperatures are current */
  PetscCall(Density(&sim->run, &p));
  /* The callers (the tensor path, diagnostics) read the ghosts' densities too. */
  PetscCall(SpamGhostsGather(p.gh, p.dim, p.n, 1, SPAM_GHOST_SCALAR, p.f->rho));
  if (SpamGasImagesOfPlace(sim)) SpamGasImagesDensities(sim);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDensitySummation(SpamSim *sim, const double *y, PetscInt *bad)
{
  const SpamLayout *l = &sim->model.layout;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, l->nvar, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  PetscCall(ReserveSlots(sim));
  if (l->h >= 0) { /* the evolved range: the density at the state's h_i */
    PetscCall(SpamSmoothingAt(sim, y));
    PetscFunctionReturn(0);
  }
  if (SpamGasImagesOfPlace(sim)) PetscCall(SpamGasImagesTemperatures(sim, y));
  PetscCall(SpamDensityOfList(sim));
  PetscFunctionReturn(0);
}

/* The accelerations, and with out the right-hand side itself (*written) when the pass
 * writes it. */
static PetscErrorCode Accel(SpamSim *sim, const double *x, int stride, RhsOut *out, PetscBool *written, PetscInt *bad)
{
  const SpamModel *m = &sim->model;
  SpamPairPass     p;

  PetscFunctionBeginUser;
  *written = PETSC_FALSE;
  /* A right-hand side without a density pass reads the list's positions in the force
   * pass only, which can place them itself. */
  if (out && m->density_free && sim->pair.threads == 1 && !SpamNeighboursCanonical(&sim->pair.nl)) PetscCall(SpamNeighboursUpdateStale(&sim->pair.nl, &sim->geo.box, x, stride, bad, &out->stale));
  else PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, x, stride, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  PetscCall(ReserveSlots(sim));
  p = SpamPairPassOf(sim);
  if (!m->density_free) { /* gamma = 2: P/rho^2 is the same constant everywhere, ghosts included (ReserveSlots) */
    PetscCall(Density(&sim->run, &p));
    for (PetscInt i = 0; i < sim->p.n; i++) sim->pair.f.q[i] = SpamEosPOverRho2(&m->eos, sim->pair.f.rho[i]);
    PetscCall(SpamGhostsGather(p.gh, m->dim, p.n, 1, SPAM_GHOST_SCALAR, sim->pair.f.q));
  }
  PetscCall(Force(sim, &p, out, written));
  if (m->gravity_on && !*written)
    for (PetscInt i = 0; i < sim->p.n; i++)
      for (int d = 0; d < m->dim; d++) sim->pair.f.acc[(size_t)i * m->dim + d] += m->gravity[d];
  /* Canonical rows list every pair twice, once in each particle's row. */
  sim->run.stats.pair_visits += p.canonical ? (double)sim->pair.nl.ncpairs : (double)(sim->pair.nl.npairs + sim->pair.nl.ngpairs);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamAccelIsentrope(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  PetscBool written;

  PetscFunctionBeginUser;
  PetscCall(Accel(sim, x, stride, NULL, &written, bad));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsIsentrope(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim, nv = l->nvar;
  RhsOut            out = {sim, y, ydot, PETSC_FALSE};
  PetscBool         written;

  PetscFunctionBeginUser;
  PetscCall(Accel(sim, y + l->x, nv, &out, &written, bad));
  if (*bad >= 0 || written) PetscFunctionReturn(0);
  if (sim->pair.threads == 1 && PlainRows(&sim->model)) {
    WriteRowsPlain(dim, y, ydot, sim->pair.f.acc, 0, (size_t)sim->p.n);
    PetscFunctionReturn(0);
  }
#pragma omp parallel for if (sim->pair.threads > 1) num_threads(sim->pair.threads) schedule(static)
  for (PetscInt i = 0; i < sim->p.n; i++) {
    for (int d = 0; d < dim; d++) {
      ydot[(size_t)i * nv + l->x + d] = y[(size_t)i * nv + l->v + d];
      ydot[(size_t)i * nv + l->v + d] = sim->pair.f.acc[(size_t)i * dim + d];
    }
  }
  PetscFunctionReturn(0);
}
