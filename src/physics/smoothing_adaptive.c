/* The adaptive kernel range: each particle's h_i solves
 *   rho_i(h_i) h_i^D = eta^D m_i,   rho_i(h) = sum_j m_j w(r_ij, h)  (self term included),
 * so that its range holds about the same number of neighbours wherever the particles go
 * (Springel & Hernquist 2002; Price 2012, J. Comput. Phys. 231, 759, Sec. 2.4), and the
 * grad-h factor Omega_i = 1 + (h_i / (D rho_i)) d rho_i/d h_i of the momentum and energy
 * equations (rhs_gas_adaptive.c). rho_i depends on h_i alone, so each particle's root is
 * its own; the passes over the half list sum every particle's rho and d rho/dh at its
 * current h at once, and Newton's step (kept inside a bracket by bisection) moves those
 * not yet converged, from the last evaluation's h_i. The passes and the force pass walk
 * the near rows (fields.h): the list's local pairs within reach of the h_i (SPAM_H_REACH) plus
 * the list's skin, kept by a first pass over the whole list (its range is the bound
 * h_max h) and used by later evaluations while the particles stay within half the skin
 * and the h_i within their reach. An h_i held at a bound does not move
 * with the particles there, so its Omega is 1. A particle that does not converge stops
 * the run with its row.
 * On several ranks the other ranks' particles are ghost slots (halo.h, within the list
 * range h_max h + skin): rho_i depends on the partners' positions only, so each rank
 * solves its own particles, the ghosts held settled at the h_j their owners had at the
 * last evaluation (their side of a pair is not summed), and the solved h_j and rho_j are
 * gathered into the slots afterwards for the force pass. Under -reproducible the sums run
 * over the canonical rows (each particle's partners sorted by id): the same bits on any
 * number of ranks, as h_i's start is carried with the particle through migrations
 * (sim_migrate.c). Nothing here allocates (the slots grow at list builds only). */
#include <spam/sim.h>
#include <spam/physics.h>
#include <spam/errors.h>
#include "../pair/pair_walk_adaptive.h"

/* Bisection alone halves the bracket [h_min h, h_max h] to 1e-10 of h in under 40 steps. */
#define SPAM_H_MAX_ITER 100
/* The reach of a solve's later passes, a factor of each h_i at its start: the list holds
 * the pairs within h_max h + skin, about (h_max + skin/h)^D times those within h_i on
 * the initial lattice (4.4 in 2D at the defaults), and an evaluation moves h_i by far
 * less than this between two right-hand sides, so its later passes and the force pass
 * walk only the pairs within max(reach_i, reach_j). A Newton or bisection step beyond
 * the reach sends those walks back to the whole list, which gives the same sums (the
 * pairs left out are beyond both ranges, their terms exactly zero). */
#define SPAM_H_REACH 1.1

PetscBool SpamModelAdaptive(const SpamModel *m)
{
  return (PetscBool)(m->tensor && m->solid.smoothing != SPAM_SMOOTHING_FIXED);
}

double SpamModelListRange(const SpamModel *m)
{
  return SpamModelAdaptive(m) ? m->solid.h_max * m->kernel.h : m->kernel.h;
}

static inline double PowD(double s, int dim)
{
  return dim == 1 ? s : dim == 2 ? s * s : s * s * s;
}

/* The kernel's scales at the h_i of slots i0 .. i1-1: w(r, h) = wnorm (h0/h)^D F(r/h) and
 * w'(r, h)/r = gnorm (h0/h)^(D+2) G(r/h), for the kernel made at h0. */
static void Scales(SpamFields *f, const SpamKernel *k, int i0, int i1)
{
  for (int i = i0; i < i1; i++) {
    const double s = k->h / f->h[i], sd = PowD(s, k->dim);
    f->hinv[i]     = 1.0 / f->h[i];
    f->wn[i]       = k->wnorm * sd;
    f->gn[i]       = k->gnorm * sd * s * s;
  }
}

typedef struct {
  SpamFields *f;
  int         row;  /* the last row whose start in the near rows is set */
  size_t      cnt;  /* pairs kept in the near rows                     */
  double      skin; /* the list's skin: the near rows' margin          */
} DensityPass;

/* d w(r, h)/d h = -(D w + r w'(r)) / h, with r w'(r) = r^2 g. */
static inline __attribute__((always_inline)) double DwDh(const int dim, double w, double g, double r2, double hinv)
{
  return -(dim * w + r2 * g) * hinv;
}

/* A settled particle keeps the sums of the pass that settled it (its h_i has not moved
 * since, so a new pass would give the same bits): only the open particles' sides are
 * added, and a pair of two settled particles is skipped. */
static inline __attribute__((always_inline)) void DensityPair(const int dim, DensityPass *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  SpamFields *f = c->f;
  (void)dx;
  if (!f->settled[i]) {
    f->rho[i] += f->m[j] * wi;
    f->drho[i] += f->m[j] * DwDh(dim, wi, gi, r2, f->hinv[i]);
  }
  if (!f->settled[j]) {
    f->rho[j] += f->m[i] * wj;
    f->drho[j] += f->m[i] * DwDh(dim, wj, gj, r2, f->hinv[j]);
  }
}
#define SPAM_BOTH_SETTLED(c, i, j) ((c)->f->settled[i] != 0.0 && (c)->f->settled[j] != 0.0)

/* The keeping pass keeps the pairs within the larger reach plus the skin, row after row
 * (rows come in order; a row with none gets its start when a later row or the end is
 * reached). */
static inline __attribute__((always_inline)) void KeepNear(DensityPass *c, int i, int j, double r2)
{
  SpamFields  *f  = c->f;
  const double hc = (f->hcap[i] > f->hcap[j] ? f->hcap[i] : f->hcap[j]) + c->skin;
  if (r2 >= hc * hc) return;
  while (c->row < i) f->near_start[++c->row] = (int)c->cnt;
  f->near_nbr[c->cnt++] = j;
}
SPAM_PAIR_WALK_ADAPTIVE(WalkDensityFirst, DensityPass, DensityPair, SPAM_BOTH_SETTLED, KeepNear)
SPAM_PAIR_WALK_ADAPTIVE(WalkDensity, DensityPass, DensityPair, SPAM_BOTH_SETTLED, SPAM_NEAR_NONE)

/* The canonical rows' pair: particle i's side only, in its row's order. */
static inline __attribute__((always_inline)) void DensityRowPair(const int dim, DensityPass *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  SpamFields *f = c->f;
  (void)dx;
  (void)wj;
  (void)gj;
  f->rho[i] += f->m[j] * wi;
  f->drho[i] += f->m[j] * DwDh(dim, wi, gi, r2, f->hinv[i]);
}
#define SPAM_ROW_SETTLED(c, i) ((c)->f->settled[i] != 0.0)
SPAM_PAIR_ROWS_ADAPTIVE(WalkDensityCanon, DensityPass, DensityRowPair, SPAM_ROW_SETTLED)

void SpamSmoothingPairs(const SpamSim *sim, SpamNeighbours *near)
{
  const SpamFields *f = &sim->pair.f;

  *near = sim->pair.nl;
  if (f->near_wide) return;
  near->start  = f->near_start;
  near->nbr    = f->near_nbr;
  near->npairs = (size_t)f->near_start[near->n];
}

/* Room for every pair of the list in the near rows: grows with the list only. */
static PetscErrorCode ReserveNear(SpamFields *f, const SpamNeighbours *nl)
{
  PetscFunctionBeginUser;
  if (f->near_cap >= nl->npairs) PetscFunctionReturn(0);
  f->near_cap = PetscMax(nl->cap, nl->npairs);
  PetscCall(PetscRealloc(f->near_cap * sizeof(int), &f->near_nbr));
  PetscFunctionReturn(0);
}

/* rho_i and d rho_i/d h_i of every open local particle at its current h_i; a keeping
 * pass walks the whole list and keeps the near rows, the others walk those. */
static PetscErrorCode Sums(SpamSim *sim, int keep)
{
  SpamFields       *f   = &sim->pair.f;
  const SpamKernel *k   = &sim->model.kernel;
  const int         n   = (int)sim->p.n, dim = k->dim;
  DensityPass       c   = {f, 0, 0, sim->pair.nl.skin};
  SpamNeighbours    near;

  PetscFunctionBeginUser;
  Scales(f, k, 0, n);
  for (int i = 0; i < n; i++) {
    if (f->settled[i]) continue;
    f->rho[i]  = f->m[i] * f->wn[i]; /* F(0) = 1: w(0, h_i) */
    f->drho[i] = -dim * f->rho[i] * f->hinv[i];
  }
  if (SpamNeighboursCanonical(&sim->pair.nl)) {
    PetscCall(WalkDensityCanon(&sim->pair.nl, k, f, &c));
    PetscFunctionReturn(0);
  }
  if (keep) {
    f->near_start[0] = 0;
    PetscCall(WalkDensityFirst(&sim->pair.nl, k, f, &c));
    while (c.row < n) f->near_start[++c.row] = (int)c.cnt;
    PetscFunctionReturn(0);
  }
  SpamSmoothingPairs(sim, &near);
  PetscCall(WalkDensity(&near, k, f, &c));
  PetscFunctionReturn(0);
}

/* The solve's bounds and target. */
typedef struct {
  int    dim;
  double eta, lo, hi; /* eta and the bounds of h_i as lengths                           */
  double tol;         /* |rho h^D / (eta^D m) - 1| of a settled h_i (-h_tol, 1e-10: Newton's
                       * last step then moved h_i by about 1e-11 of itself, the next would
                       * by the square of that, so the right-hand side is smooth to that level) */
} Solve;

/* One step of particle i's solve at the sums of its current h_i: 1 when h_i stays (the
 * relation holds to -h_tol, or h_i is held at the bound that the relation lies
 * beyond), with Omega_i set; else 0 with the next h_i. */
static int Step(const Solve *s, SpamFields *f, int i)
{
  const double h = f->h[i], tgt = f->m[i] * PowD(s->eta * f->hinv[i], s->dim), res = f->rho[i] - tgt;
  const double fp = f->drho[i] + s->dim * tgt * f->hinv[i]; /* d(rho - tgt)/dh */
  double       hn;

  if (fabs(res) <= s->tol * tgt) {
    f->omega[i] = 1.0 + h * f->drho[i] / (s->dim * f->rho[i]);
    return 1;
  }
  if ((res < 0.0 && h >= s->hi) || (res > 0.0 && h <= s->lo)) {
    f->omega[i] = 1.0;
    return 1;
  }
  if (res < 0.0) f->hlo[i] = h;
  else f->hhi[i] = h;
  hn = h - res / fp;
  /* A bracket end still at its bound has not been evaluated: Newton may try the bound. */
  if (fp > 0.0 && hn >= f->hhi[i] && f->hhi[i] == s->hi) hn = s->hi;
  else if (fp > 0.0 && hn <= f->hlo[i] && f->hlo[i] == s->lo) hn = s->lo;
  else if (!(fp > 0.0) || !(hn > f->hlo[i] && hn < f->hhi[i])) hn = 0.5 * (f->hlo[i] + f->hhi[i]);
  f->h[i] = hn;
  return 0;
}

/* Whether the near rows serve this solve: kept on this list, every particle within half
 * the skin of where they were kept (a pair's distance then changed by less than the
 * skin), every starting h_i within its reach. */
static int NearServe(const SpamFields *f, const SpamNeighbours *nl)
{
  const double lim = 0.25 * nl->skin * nl->skin;

  if (!f->near_valid || f->near_builds != nl->builds) return 0;
  for (int i = 0; i < nl->n; i++) {
    double r2 = 0.0;
    for (int d = 0; d < nl->dim; d++) {
      const double dx = nl->u[d][i] - f->xnear[(size_t)i * nl->dim + d];
      r2 += dx * dx;
    }
    if (r2 >= lim || f->h[i] > f->hcap[i]) return 0;
  }
  return 1;
}

/* The near rows are kept at the current positions with reaches from the current h_i. */
static void NearKeptHere(SpamFields *f, const SpamNeighbours *nl, double hi)
{
  for (int i = 0; i < nl->n; i++) {
    f->hcap[i] = PetscMin(SPAM_H_REACH * f->h[i], hi);
    for (int d = 0; d < nl->dim; d++) f->xnear[(size_t)i * nl->dim + d] = nl->u[d][i];
  }
  f->near_builds = nl->builds;
  f->near_valid  = 1;
}

void SpamSmoothingNearReset(SpamFields *f)
{
  f->near_valid = 0;
}

/* The h_j of the ghost slots from their owners, with their kernel scales (collective). */
static PetscErrorCode ShareRanges(SpamSim *sim)
{
  SpamFields *f = &sim->pair.f;
  const int   n = (int)sim->p.n;

  PetscFunctionBeginUser;
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, sim->model.dim, n, 1, SPAM_GHOST_SCALAR, f->h));
  Scales(f, &sim->model.kernel, n, SpamNeighboursSlots(&sim->pair.nl));
  PetscFunctionReturn(0);
}

/* A particle that did not converge, or whose Omega is not positive, as this rank's error. */
static PetscErrorCode Converged(SpamSim *sim, const Solve *s, int open, int last)
{
  const SpamFields *f = &sim->pair.f;

  PetscFunctionBeginUser;
  PetscCheck(!open, PETSC_COMM_SELF, PETSC_ERR_CONV_FAILED, "adaptive h: particle %" PetscInt_FMT " (input row) and %d others did not converge in %d iterations of rho h^D = eta^D m (h = %g, rho = %g, bounds %g to %g)", SpamSimRowOf(sim, last), open - 1,
             SPAM_H_MAX_ITER, f->h[last], f->rho[last], s->lo, s->hi);
  for (PetscInt i = 0; i < sim->p.n; i++)
    PetscCheck(f->omega[i] > 0.0 && isfinite(f->omega[i]), PETSC_COMM_SELF, PETSC_ERR_CONV_FAILED, "adaptive h: particle %" PetscInt_FMT " (input row) has the grad-h factor Omega = %g (h = %g, rho = %g): not positive, so its kernel range does not grow as its density falls", SpamSimRowOf(sim, i),
               f->omega[i], f->h[i], f->rho[i]);
  PetscFunctionReturn(0);
}

/* The bounds and target of a pass. */
static Solve SolveOf(const SpamSim *sim)
{
  const SpamSolidParams *p  = &sim->model.solid;
  const double           h0 = sim->model.kernel.h;
  const Solve            s  = {sim->model.dim, p->h_eta, p->h_min * h0, p->h_max * h0, p->h_tol > 0.0 ? p->h_tol : SPAM_H_TOL_DEFAULT};
  return s;
}

/* The start of a solve or pass: every local h_i within the bounds (h0 where it has none
 * yet), open, its bracket the bounds; the ghosts at their owners' h_j, held settled; the
 * near rows kept anew when the last ones do not serve. Returns whether they are kept in
 * the first pass. */
static PetscErrorCode Open(SpamSim *sim, const Solve *s, int *keep)
{
  SpamFields  *f  = &sim->pair.f;
  const double h0 = sim->model.kernel.h;
  const int    n  = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);

  PetscFunctionBeginUser;
  PetscCall(SpamFieldsReserve(f, slots));
  for (int i = 0; i < n; i++) { /* from the last evaluation's h_i (-h at the first) */
    f->h[i]       = f->h[i] > 0.0 ? PetscMin(PetscMax(f->h[i], s->lo), s->hi) : PetscMin(PetscMax(h0, s->lo), s->hi);
    f->hlo[i]     = s->lo;
    f->hhi[i]     = s->hi;
    f->settled[i] = 0.0;
  }
  PetscCall(ShareRanges(sim)); /* the ghosts at their owners' starts, held settled */
  for (int i = n; i < slots; i++) f->settled[i] = 1.0;
  *keep = !SpamNeighboursCanonical(&sim->pair.nl) && !NearServe(f, &sim->pair.nl);
  if (*keep) {
    PetscCall(ReserveNear(f, &sim->pair.nl));
    NearKeptHere(f, &sim->pair.nl, s->hi);
  }
  f->near_wide = 0;
  PetscFunctionReturn(0);
}

/* The end of a solve or pass (collective): every rank learns of a failure; the slots take
 * the h_j and rho_j of their owners for the force pass. */
static PetscErrorCode Close(SpamSim *sim, const Solve *s, int open, int last)
{
  SpamFields *f = &sim->pair.f;

  PetscFunctionBeginUser;
  PetscCall(SpamAgreeOnFailure(sim->p.comm, Converged(sim, s, open, last), "the adaptive h solve"));
  PetscCall(ShareRanges(sim));
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, sim->model.dim, (int)sim->p.n, 1, SPAM_GHOST_SCALAR, f->rho));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSmoothingSolve(SpamSim *sim)
{
  const Solve  s = SolveOf(sim);
  SpamFields  *f = &sim->pair.f;
  const int    n = (int)sim->p.n;
  int          open = n, last = -1, keep;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->run.ev.density, 0, 0, 0, 0));
  PetscCall(Open(sim, &s, &keep));
  for (int it = 0; it < SPAM_H_MAX_ITER && open; it++) {
    PetscCall(Sums(sim, keep && it == 0));
    open = 0;
    for (int i = 0; i < n; i++) {
      if (f->settled[i]) continue;
      if (Step(&s, f, i)) f->settled[i] = 1.0;
      else {
        open++;
        last = i;
        if (f->h[i] > f->hcap[i]) f->near_wide = 1, f->near_valid = 0;
      }
    }
  }
  PetscCall(PetscLogEventEnd(sim->run.ev.density, 0, 0, 0, 0));
  PetscCall(Close(sim, &s, open, last));
  PetscFunctionReturn(0);
}

/* The evolved range: h_i is the state's (-smoothing_length evolved), so one pass sums
 * rho_i and d rho_i/d h_i there and Omega_i follows; an h_i the integration carried past
 * a bound is held at it. Omega_i keeps its formula at a bound (the solve's 1 there would
 * switch on and off as an integrated h_i touches the bound: a 1D Sod tube at -h_max 2
 * took 25 times the right-hand sides), but for a particle whose Omega is not positive:
 * its range holds too few partners for rho h^D to grow with h (a particle leaving the
 * gas, whose density is its self term), where the solve would hold h_i at the upper
 * bound; it takes 1, and is counted. No iteration: the right-hand side is a smooth
 * function of the state, h_i included, but where Omega_i changes sign or h_i meets a
 * bound. */
PetscErrorCode SpamSmoothingAt(SpamSim *sim, const double *y)
{
  const Solve       s = SolveOf(sim);
  const SpamLayout *l = &sim->model.layout;
  SpamFields       *f = &sim->pair.f;
  const int         n = (int)sim->p.n;
  int               keep;
  long              floored = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->run.ev.density, 0, 0, 0, 0));
  PetscCall(SpamFieldsReserve(f, SpamNeighboursSlots(&sim->pair.nl)));
  for (int i = 0; i < n; i++) f->h[i] = y[(size_t)i * l->nvar + l->h];
  PetscCall(Open(sim, &s, &keep));
  PetscCall(Sums(sim, keep));
  for (int i = 0; i < n; i++) {
    const double om = 1.0 + f->h[i] * f->drho[i] / (s.dim * f->rho[i]);
    f->omega[i]     = om > 0.0 ? om : 1.0;
    floored += !(om > 0.0);
  }
  /* Counted, not silent: summary.json's omega_floored and a note at the end (time_loop.c). */
  sim->run.stats.omega_floored += floored;
  if (floored > sim->run.stats.omega_floored_max) sim->run.stats.omega_floored_max = floored;
  PetscCall(PetscLogEventEnd(sim->run.ev.density, 0, 0, 0, 0));
  PetscCall(Close(sim, &s, 0, -1));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSmoothingStart(SpamSim *sim, double *y)
{
  const SpamLayout *l = &sim->model.layout;
  PetscInt          bad;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, l->nvar, PETSC_FALSE, &bad));
  PetscCheck(bad < 0, sim->p.comm, PETSC_ERR_FP, "evolved h: the initial position of particle %" PetscInt_FMT " (input row) is not finite", SpamSimRowOf(sim, bad));
  PetscCall(SpamFieldsReserve(&sim->pair.f, SpamNeighboursSlots(&sim->pair.nl)));
  PetscCall(SpamSimGhostMasses(sim));
  PetscCall(SpamSmoothingSolve(sim));
  for (PetscInt i = 0; i < sim->p.n; i++) y[(size_t)i * l->nvar + l->h] = sim->pair.f.h[i];
  PetscFunctionReturn(0);
}
