/* The per-particle step of the block steps (ts_block_kdk.c) and the one neighbour walk it
 * needs: the signal speed of each particle (the CFL condition of a particle in a shock is
 * set by its neighbours' sound speeds and their approach, not its own alone) and the
 * deepest bin among its neighbours (the Saitoh-Makino limiter). */
#include "block_kdk.h"
#include "../pair/pair_walk.h"

typedef struct {
  const double *c, *vel;
  const int    *lev;
  double       *sig;
  int          *nbmax;
  const int    *src;  /* [ghosts] local source of each ghost slot (-1: remote)      */
  const unsigned char *kind; /* [ghosts] SpamGhostKind                             */
  int           n;
} WalkCtx;

/* The local particle a slot's share goes to: itself, the source of a periodic image (the
 * image stands for the same particle), or none (a mirror image: the wall's). */
static inline int Owner(const WalkCtx *c, int j)
{
  if (j < c->n) return j;
  return c->kind[j - c->n] == SPAM_GHOST_PERIODIC ? c->src[j - c->n] : -1;
}

static inline __attribute__((always_inline)) void SignalPair(const int dim, WalkCtx *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  const double *vi = c->vel + (size_t)i * dim, *vj = c->vel + (size_t)j * dim;
  double        vr = 0.0, s;
  const int     o  = Owner(c, j);
  (void)w;
  (void)g;
  for (int d = 0; d < dim; d++) vr += (vi[d] - vj[d]) * dx[d];
  s = c->c[i] + c->c[j] + (vr < 0.0 && r2 > 0.0 ? -3.0 * vr / sqrt(r2) : 0.0);
  if (s > c->sig[i]) c->sig[i] = s;
  if (c->lev[j] > c->nbmax[i]) c->nbmax[i] = c->lev[j];
  if (o >= 0) {
    if (s > c->sig[o]) c->sig[o] = s;
    if (c->lev[i] > c->nbmax[o]) c->nbmax[o] = c->lev[i];
  }
}
SPAM_PAIR_WALK(WalkSignal, WalkCtx, SignalPair)
SPAM_PAIR_WALK_MASKED(WalkSignalMarked, WalkCtx, SignalPair)

/* Under -reproducible: the canonical rows (every partner of a local particle, sorted by
 * key), each pair taken from the row's side and only the row's particle updated. The
 * separation u_i - u_j is then the same expression whichever rank holds j (a periodic
 * image's pair seen from its two ends may differ in the last bit, so the half list's
 * Newton update would not be), and sig and nbmax are maxima, whose bits do not depend on
 * the order: the walk gives the same bits on any rank count. With mask, only the pairs
 * with a marked member, as the masked half-list walk. */
static void WalkSignalCanonical(const SpamNeighbours *nl, const SpamKernel *k, const unsigned char *mask, WalkCtx *c)
{
  const int dim = nl->dim;

  for (int i = 0; i < nl->n; i++) {
    const int     mi = mask ? mask[i] : 1;
    const double *vi = c->vel + (size_t)i * dim;
    for (int p = nl->cstart[i]; p < nl->cstart[i + 1]; p++) {
      const int j = nl->cnbr[p];
      double    r2 = 0.0, vr = 0.0, dx[3] = {0.0, 0.0, 0.0};
      if (!mi && !mask[j]) continue;
      for (int d = 0; d < dim; d++) {
        dx[d] = nl->u[d][i] - nl->u[d][j];
        r2 += dx[d] * dx[d];
      }
      if (r2 >= k->h2) continue;
      for (int d = 0; d < dim; d++) vr += (vi[d] - c->vel[(size_t)j * dim + d]) * dx[d];
      const double s = c->c[i] + c->c[j] + (vr < 0.0 && r2 > 0.0 ? -3.0 * vr / sqrt(r2) : 0.0);
      if (s > c->sig[i]) c->sig[i] = s;
      if (c->lev[j] > c->nbmax[i]) c->nbmax[i] = c->lev[j];
    }
  }
}

PetscErrorCode SpamBlockWalkDestroy(SpamBlockWalk *w)
{
  PetscFunctionBeginUser;
  if (w->cap) PetscCall(PetscFree6(w->c, w->vel, w->sig, w->lev, w->nbmax, w->mark));
  if (w->cap) PetscCall(PetscFree4(w->row, w->seen, w->send, w->recv));
  w->cap = 0;
  PetscFunctionReturn(0);
}

/* Room for the list's slots: grows only when a build added ghosts. */
static PetscErrorCode Reserve(SpamBlockWalk *w, int slots, int dim)
{
  PetscFunctionBeginUser;
  if (slots <= w->cap) PetscFunctionReturn(0);
  PetscCall(SpamBlockWalkDestroy(w));
  w->cap = slots + slots / 4 + 16;
  PetscCall(PetscMalloc6(w->cap, &w->c, (size_t)w->cap * dim, &w->vel, w->cap, &w->sig, w->cap, &w->lev, w->cap, &w->nbmax, w->cap, &w->mark));
  PetscCall(PetscMalloc4(w->cap, &w->row, w->cap, &w->seen, (size_t)w->cap * (SPAM_BLOCK_SENT + dim), &w->send, (size_t)w->cap * (SPAM_BLOCK_SENT + dim), &w->recv));
  PetscFunctionReturn(0);
}

/* The sound speed of particle block p: the ideal gas's own sqrt(gamma (gamma - 1) e), at
 * least the model's (for the gas, the ambient one; for the others, their only one). */
static double SoundSpeed(const SpamSim *sim, double cmodel, const double *p)
{
  const SpamModel *m = &sim->model;

  if (m->tensor && m->solid.material == SPAM_MATERIAL_GAS && m->layout.e >= 0) {
    const double e = p[m->layout.e], g = m->solid.gamma;
    return PetscMax(cmodel, e > 0.0 ? sqrt(g * (g - 1.0) * e) : 0.0);
  }
  return cmodel;
}

/* The walk's per-slot inputs of local particle i from its block p. */
static inline void Load(const SpamSim *sim, double cmod, const double *p, const int *lev, int i, SpamBlockWalk *w)
{
  const int dim = sim->model.dim, v = sim->model.layout.v;

  w->c[i]     = SoundSpeed(sim, cmod, p);
  w->sig[i]   = w->c[i];
  w->lev[i]   = lev ? lev[i] : 0;
  w->nbmax[i] = w->lev[i];
  for (int d = 0; d < dim; d++) w->vel[(size_t)i * dim + d] = p[v + d];
}

/* The remote ghost slots' inputs from their owners through the halo (collective): sound
 * speed, bin, mark and velocity of each, mirrored as a local image's where the slot is
 * another rank's mirror image. */
static PetscErrorCode Remote(const SpamGhosts *gh, int dim, int n, const unsigned char *mask, SpamBlockWalk *w)
{
  const int nc = SPAM_BLOCK_SENT + dim;

  PetscFunctionBeginUser;
  for (int i = 0; i < n; i++) {
    double *q = w->send + (size_t)i * nc;
    q[0]      = w->c[i];
    q[1]      = w->lev[i];
    q[2]      = mask ? mask[i] : 0;
    for (int d = 0; d < dim; d++) q[SPAM_BLOCK_SENT + d] = w->vel[(size_t)i * dim + d];
  }
  PetscCall(SpamHaloForward(&gh->halo, nc, w->send, w->recv));
  for (int k = gh->nlocal; k < gh->n; k++) {
    const double *q = w->recv + (size_t)(k - gh->nlocal) * nc;
    const int     s = n + k;
    w->c[s]         = q[0];
    w->sig[s]       = 0.0;
    w->lev[s]       = (int)q[1];
    w->mark[s]      = (unsigned char)q[2];
    for (int d = 0; d < dim; d++) w->vel[(size_t)s * dim + d] = ((gh->flip[k] >> d) & 1) ? -q[SPAM_BLOCK_SENT + d] : q[SPAM_BLOCK_SENT + d];
  }
  PetscFunctionReturn(0);
}

/* The rows a masked walk must read besides those the transposed list names: the rows with
 * a marked remote ghost slot among their ghost partners (the transposed list knows only
 * the local sources' marks). */
static void RemoteRows(const SpamNeighbours *nl, SpamBlockWalk *w)
{
  const int first = nl->n + nl->ghosts.nlocal;

  for (int i = 0; i < nl->n; i++) {
    if (w->row[i]) continue;
    for (int p = nl->gstart[i]; p < nl->gstart[i + 1]; p++) {
      const int j = nl->gnbr[p];
      if (j >= first && w->mark[j]) {
        w->row[i] = 1;
        break;
      }
    }
  }
}

/* The particles a masked walk reads (SpamNeighboursMarkedNear's answer) from the rows it
 * reads (row, SpamNeighboursMarkedRows's): those, and the partners the marked particles'
 * own rows list. One transposed pass for both instead of two. */
static void NearOfRows(const SpamNeighbours *nl, const unsigned char *mask, const unsigned char *row, unsigned char *near)
{
  for (int i = 0; i < nl->n; i++) near[i] = row[i];
  for (int p = 0; p < nl->n; p++) {
    if (!mask[p]) continue;
    for (int c = nl->start[p]; c < nl->start[p + 1]; c++) near[nl->nbr[c]] = 1;
  }
}

PetscErrorCode SpamBlockNeighbours(SpamSim *sim, const double *y, const int *lev, const unsigned char *mask, SpamBlockWalk *w)
{
  const SpamLayout *l      = &sim->model.layout;
  const SpamGhosts *gh     = &sim->pair.nl.ghosts;
  const int         dim    = sim->model.dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);
  const PetscBool   remote = SpamHaloActive(&gh->halo);
  double            cmod   = 0.0;
  PetscBool         rows   = PETSC_FALSE; /* w->row holds the rows of the masked walk */
  WalkCtx           c;

  PetscFunctionBeginUser;
  PetscCall(Reserve(w, slots, dim));
  if (sim->model.max_sound_speed) PetscCall(sim->model.max_sound_speed(sim, y, &cmod));
  /* without ghosts a masked walk reads only the marked particles and their listed partners */
  if (mask && slots == n && !remote) {
    PetscCall(SpamNeighboursMarkedRows(&sim->pair.nl, mask, w->row));
    NearOfRows(&sim->pair.nl, mask, w->row, w->seen);
    rows = PETSC_TRUE;
  } else
    for (int i = 0; i < n; i++) w->seen[i] = 1;
  for (int i = 0; i < n; i++)
    if (w->seen[i]) Load(sim, cmod, y + (size_t)i * l->nvar, lev, i, w);
  for (int k = 0; k < gh->nlocal; k++) { /* this rank's periodic and mirror images */
    const int s   = gh->src[k];
    w->c[n + k]   = w->c[s];
    w->sig[n + k] = 0.0;
    w->lev[n + k] = w->lev[s];
    if (mask) w->mark[n + k] = mask[s]; /* an image of a marked particle is marked */
    for (int d = 0; d < dim; d++) w->vel[(size_t)(n + k) * dim + d] = ((gh->flip[k] >> d) & 1) ? -w->vel[(size_t)s * dim + d] : w->vel[(size_t)s * dim + d];
  }
  if (remote) PetscCall(Remote(gh, dim, n, mask, w));
  c = (WalkCtx){w->c, w->vel, w->lev, w->sig, w->nbmax, gh->src, gh->kind, n};
  if (mask)
    for (int i = 0; i < n; i++) w->mark[i] = mask[i];
  if (SpamNeighboursCanonical(&sim->pair.nl)) WalkSignalCanonical(&sim->pair.nl, &sim->model.kernel, mask ? w->mark : NULL, &c);
  else if (mask) {
    if (!rows) PetscCall(SpamNeighboursMarkedRows(&sim->pair.nl, mask, w->row));
    if (remote) RemoteRows(&sim->pair.nl, w);
    PetscCall(WalkSignalMarked(&sim->pair.nl, &sim->model.kernel, w->mark, w->row, &c));
  } else PetscCall(WalkSignal(&sim->pair.nl, &sim->model.kernel, &c));
  PetscFunctionReturn(0);
}

double SpamBlockWanted(const SpamSim *sim, const SpamBlockSettings *s, const SpamBlockWalk *w, PetscInt i, const double *rate, double controlled)
{
  const SpamLayout *l  = &sim->model.layout;
  const double      h  = sim->pair.f.adaptive ? sim->pair.f.h[i] : sim->model.kernel.h;
  double            dt = PETSC_INFINITY, a2 = 0.0;

  if (w->sig[i] > 0.0) dt = s->cfl * h / w->sig[i];
  if (s->criterion == SPAM_BLOCK_CRITERION_ERROR) return PetscMin(dt, controlled);
  for (int d = 0; d < sim->model.dim; d++) a2 += rate[l->v + d] * rate[l->v + d];
  if (a2 > 0.0) dt = PetscMin(dt, s->force * sqrt(h / sqrt(a2)));
  return dt;
}
