/* Block individual time steps ("block_kdk"): kick-drift-kick with each particle's step in
 * a power-of-two bin dt_k = D / 2^k of the top step D, as GADGET, SWIFT and Phantom step
 * their particles. One TSStep is one synchronised cycle of length D (at most the distance
 * to the next output time, and -ts_dt if given), so every output is a synchronised state.
 *
 * Within the cycle time is counted in ticks of D / 2^L (L = -block_max_level). At each
 * tick where some particle's step ends: every particle drifts (x += v dt, v its
 * half-kicked velocity), the right-hand side is evaluated on the predicted state (the
 * fields other than x of a particle mid-step advanced along its last rate, as GADGET
 * predicts them), the particles whose step ends get their second half kick and start a
 * new step in the bin their criterion asks (CFL on h_i with the signal speed, and
 * sqrt(h_i/|a_i|)), and the Saitoh-Makino limiter keeps each bin at most two levels longer
 * than its neighbours': a particle too slow beside a neighbour just made fast is woken,
 * its step ended now with its kicks corrected to the time it actually ran.
 *
 * Every field but the position is kicked with its rate (velocity, energy, and the
 * density, stress and books where the model carries them); positions drift with the
 * velocity alone. Where the model has a pass restricted to the active particles
 * (model.h's rhs_active: the gas with one h) each tick computes the forces of the
 * particles whose step ends there and no others (-block_restricted, the default; false:
 * the whole right-hand side at each tick, the same result up to round-off); the neighbour
 * walks of the step criterion and the limiter visit only the pairs with a particle whose
 * bin may change. A woken particle's new rate comes from a second restricted evaluation
 * on the same predicted state. -ts_view reports the fraction of particles active per
 * evaluation and how many evaluations were restricted.
 *
 * On several ranks every particle-by-particle step is the one rank's (a particle's drift,
 * prediction and kicks read its own data only); what crosses ranks is the right-hand side
 * (through the halo, as for any method), the walk's inputs of other ranks' particles
 * (block_bins.c) and each decision of the cycle, reduced over the ranks (AnyRank,
 * RankReduce); the restricted pass takes the other ranks' particles through the halo
 * (rhs_tensor.c). Migrations come between cycles (FollowBlock carries
 * f with the particles, by id). A checkpoint keeps f, the rates the next cycle starts
 * from: a restart continues bit for bit. */
#include <petsc/private/tsimpl.h>
#include "ts_family.h"
#include "block_kdk.h"
#include <spam/errors.h>
#include <stdint.h>

typedef struct {
  SpamBlockSettings set;
  PetscBool         restricted_set; /* -block_restricted given (refused where no pass exists) */
  SpamBlockWalk     walk;
  PetscInt          n, nv;   /* particles and fields the arrays were made for         */
  PetscInt64       *gid;     /* [n] their global ids, in the arrays' order              */
  double           *f, *g, *yp; /* [n nv]: rates at each particle's step start, the last
                                * evaluation's, the predicted state                      */
  int              *lev;     /* [n] bin of the current step                            */
  PetscInt64       *start;   /* [n] tick where the current step began                  */
  PetscInt64       *len;     /* [n] its length in ticks: 2^(L - lev), or shorter when a
                              * wake was put off to the next tick of the bin it needs   */
  unsigned char    *ends;    /* [n] the step ends (or is woken) at this tick            */
  PetscInt         *act;     /* [n] the particles whose step ends at this tick, ascending
                              * (nends of them), then those woken there (up to nact): the
                              * loops after the evaluation visit these, not all n        */
  PetscInt          nends, nact;
  unsigned char    *chg, *nxt; /* [n] bin made deeper: this ring's mask, the next ring's  */
  unsigned char    *woke;    /* [n] woken at this tick, its new rate still to take       */
  unsigned char    *near;    /* [2 n] scratch of the restricted pass                     */
  PetscBool         have_f;  /* f holds the rates of the synchronised state             */
  /* -block_criterion error: the step each particle's controller asks for next (infinity:
   * none yet, the CFL criterion alone), the cut ones of particles whose step was rejected
   * in this cycle, the cycle's start (state, rates, asked steps, kernel ranges) to redo it
   * from, and scratch weights */
  SpamBlockErrorCtx ectl;
  double           *want, *cut, *cap, *y0, *f0, *want0, *h0, *wscr;
  long              rejected, over; /* cycles rejected; particle steps above the tolerance */
  /* statistics: cycles, evaluations, particle steps, woken particles, sum over the
   * evaluations of the fraction of particles whose step ended there, deepest bin */
  long              cycles, evals, psteps, woken, restricted, wake_evals, delayed, ests;
  double            err_max; /* largest particle estimate */
  double            active_sum;
  int               deepest;
} TS_SpamBlock;

/* Several ranks take every decision of the cycle together: a flag set on any rank (or held
 * on all), the smallest or largest value. On one rank nothing is exchanged. */
static PetscErrorCode AnyRank(const SpamSim *sim, MPI_Op op, PetscBool *flag)
{
  PetscFunctionBeginUser;
  if (SpamSimDistributed(sim)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, flag, 1, MPIU_BOOL, op, sim->p.comm));
  PetscFunctionReturn(0);
}

static PetscErrorCode RankReduce(const SpamSim *sim, MPI_Datatype type, MPI_Op op, void *v)
{
  PetscFunctionBeginUser;
  if (SpamSimDistributed(sim)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, v, 1, type, op, sim->p.comm));
  PetscFunctionReturn(0);
}

/* One evaluation into out; *ok false (and the failure booked) when a particle went bad. */
static PetscErrorCode Evaluate(SpamTsApp *app, double t, const double *y, double *out, PetscBool *ok)
{
  PetscInt bad;

  PetscFunctionBeginUser;
  PetscCall(SpamRhs(app->sim, y, out, &bad));
  *ok = (PetscBool)(bad < 0);
  PetscCall(AnyRank(app->sim, MPI_LAND, ok));
  if (bad >= 0 && app->bad < 0) {
    app->bad  = bad;
    app->tbad = t;
  }
  PetscFunctionReturn(0);
}

/* The list's positions moved to those of y (collective); *ok false if one is not finite. */
static PetscErrorCode PlaceList(SpamTsApp *app, double t, const double *y, PetscBool *ok)
{
  SpamSim          *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  PetscInt          bad;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, l->nvar, PETSC_FALSE, &bad));
  *ok = (PetscBool)(bad < 0); /* agreed by every rank (neighbours.h) */
  if (bad >= 0 && app->bad < 0) {
    app->bad  = bad;
    app->tbad = t;
  }
  PetscFunctionReturn(0);
}

/* The rates of the particles marked in mask (NULL: all) into out: the restricted pass where
 * the settings ask for it and the state allows it, else the whole right-hand side. */
static PetscErrorCode EvaluateMarked(SpamTsApp *app, TS_SpamBlock *b, double t, const double *y, double *out, const unsigned char *mask, PetscBool *ok)
{
  PetscBool done = PETSC_FALSE;
  PetscInt  bad  = -1;

  PetscFunctionBeginUser;
  if (mask && b->set.restricted) PetscCall(SpamRhsActive(app->sim, y, out, mask, b->near, &done, &bad));
  if (bad >= 0) {
    *ok = PETSC_FALSE;
    if (app->bad < 0) {
      app->bad  = bad;
      app->tbad = t;
    }
    PetscFunctionReturn(0);
  }
  if (done) {
    *ok = PETSC_TRUE;
    b->restricted++;
    PetscFunctionReturn(0);
  }
  PetscCall(Evaluate(app, t, y, out, ok));
  PetscFunctionReturn(0);
}

/* Kicks the fields other than the position of particle i by dt along rate (the fields
 * before the position and after it: two loops without a test per field). */
static inline void Kick(const SpamLayout *l, int dim, double *p, const double *rate, double dt)
{
  for (int k = 0; k < l->x; k++) p[k] += dt * rate[k];
  for (int k = l->x + dim; k < l->nvar; k++) p[k] += dt * rate[k];
}

/* The shallowest bin whose step D / 2^k is at most dt; -1 beyond bin L. */
static int LevelFor(double dt, double D, int L)
{
  int k = 0;
  if (!(dt > 0.0)) return -1;
  while (k <= L && D / (double)((PetscInt64)1 << k) > dt) k++;
  return k > L ? -1 : k;
}

/* The step particle i's error controller asks for, at most the cap a rejection of this
 * cycle set (infinity under the CFL criterion). */
static inline double Controlled(const TS_SpamBlock *b, PetscInt i)
{
  return b->want ? PetscMin(b->want[i], b->cap[i]) : PETSC_INFINITY;
}

/* The deepest bin whose grid tick s lies on (s a multiple of 2^(L-k)): a step may only
 * start on its own bin's grid, so that it ends on the coarser bins' ends. */
static int AlignedLevel(PetscInt64 s, int L)
{
  int k = L;
  while (k > 0 && !(s & ((PetscInt64)1 << (L - k)))) k--;
  return k;
}

static PetscErrorCode Fail(TS ts, SpamTsApp *app, const char *msg)
{
  PetscFunctionBeginUser;
  (void)snprintf(app->fail, sizeof app->fail, "%s", msg);
  ts->reason = TS_DIVERGED_STEP_REJECTED;
  PetscFunctionReturn(0);
}

/* Some particle wanted a step below the deepest bin (row >= 0: this rank's, the lowest
 * such): every rank fails with the message of the lowest such row of all. *ok false
 * then, on every rank. */
static PetscErrorCode TooDeep(TS ts, SpamTsApp *app, PetscInt64 row, double want, double D, int L, PetscBool *ok)
{
  PetscInt64 first = row < 0 ? INT64_MAX : row;
  double     w;

  PetscFunctionBeginUser;
  PetscCall(RankReduce(app->sim, MPIU_INT64, MPI_MIN, &first));
  *ok = (PetscBool)(first == INT64_MAX);
  if (*ok) PetscFunctionReturn(0);
  w = row == first ? want : PETSC_INFINITY;
  PetscCall(RankReduce(app->sim, MPI_DOUBLE, MPI_MIN, &w));
  {
    char msg[200];
    (void)snprintf(msg, sizeof msg, "particle %" PetscInt64_FMT " wants a step %.3e below the deepest bin %.3e (-block_max_level %d)", first, w, D / (double)((PetscInt64)1 << L), L);
    PetscCall(Fail(ts, app, msg));
  }
  PetscFunctionReturn(0);
}

/* The bins of a synchronised start: each particle's wanted bin, then the limiter applied
 * until no bin changes (a deep bin spreads to its neighbours two levels at a time). */
static PetscErrorCode FirstBins(TS ts, SpamTsApp *app, TS_SpamBlock *b, const double *y, double D, int L, PetscBool *ok)
{
  SpamSim  *sim = app->sim;
  PetscBool changed = PETSC_TRUE;
  PetscInt64 row = -1;
  double     wrow = 0.0;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE; /* b->walk holds the signal speeds of y (TSStep walked it for TopStep) */
  for (PetscInt i = 0; i < b->n && row < 0; i++) {
    const double want = SpamBlockWanted(sim, &b->set, &b->walk, i, b->f + (size_t)i * b->nv, Controlled(b, i));
    b->lev[i]         = LevelFor(want, D, L);
    if (b->lev[i] < 0) {
      row  = SpamSimRowOf(sim, i);
      wrow = want;
    }
  }
  PetscCall(TooDeep(ts, app, row, wrow, D, L, ok));
  if (!*ok) PetscFunctionReturn(0);
  for (int pass = 0; L > 0 && changed && pass <= L; pass++) { /* one bin: nothing to limit */
    changed = PETSC_FALSE;
    PetscCall(SpamBlockNeighbours(sim, y, b->lev, NULL, &b->walk));
    for (PetscInt i = 0; i < b->n; i++)
      if (b->lev[i] < b->walk.nbmax[i] - SPAM_BLOCK_LIMITER) {
        b->lev[i] = b->walk.nbmax[i] - SPAM_BLOCK_LIMITER;
        changed   = PETSC_TRUE;
      }
    PetscCall(AnyRank(sim, MPI_LOR, &changed));
  }
  PetscFunctionReturn(0);
}

/* Every particle drifted by dt to tick s (x += dt v, v its half-kicked velocity), and the
 * state the right-hand side sees there (b->yp): the position as drifted, the other fields
 * advanced from the step's middle (where the first half kick left them) along the step's
 * rate (Kick's arithmetic on a copy), so that a particle whose step ends at s gets the
 * whole old kick; the particles whose step ends at s listed in b->act (b->nends of them)
 * and marked in b->ends. One loop over the particles, the arrays and offsets held in
 * locals: a byte store may alias anything, and with the fields read through b the
 * compiler would load them again for every particle. */
static void DriftPredict(TS_SpamBlock *b, const SpamLayout *l, int dim, double *y, PetscInt64 s, double dt, double tau)
{
  const PetscInt    n = b->n, nv = b->nv;
  const int         lx = l->x, lv = l->v, nvar = l->nvar;
  const double     *f = b->f;
  double           *yp = b->yp;
  const PetscInt64 *start = b->start, *len = b->len;
  unsigned char    *ends = b->ends;
  PetscInt         *act = b->act, na = 0;

  for (PetscInt i = 0; i < n; i++) {
    double       *p = y + (size_t)i * nv, *q = yp + (size_t)i * nv;
    const double *r = f + (size_t)i * nv;
    const double  dl = (double)len[i] * tau, since = (double)(s - start[i]) * tau, c = since - 0.5 * dl;
    for (int d = 0; d < dim; d++) p[lx + d] += dt * p[lv + d];
    for (int k = 0; k < lx; k++) q[k] = p[k] + c * r[k];
    for (int k = lx; k < lx + dim; k++) q[k] = p[k];
    for (int k = lx + dim; k < nvar; k++) q[k] = p[k] + c * r[k];
    ends[i] = (unsigned char)(start[i] + len[i] == s);
    if (ends[i]) act[na++] = i;
  }
  b->nends = b->nact = na;
}

/* The limiter against the bins just made deeper at tick s (b->chg), one ring of
 * neighbours: a particle more than two bins coarser than a neighbour takes a deeper bin.
 * One starting a step at s just does; one mid-step is woken, its step ended at s with its
 * kicks corrected to the time it ran (the first half kick of the step planned undone, half
 * the step run kicked with the old rate and, in WokenKicks once its rate is known, half
 * with the new one), and starts anew. Only the pairs with a particle just made deeper are
 * walked: the limiter held before, so only they can break it. b->chg becomes this ring's
 * deepened particles; *moved: some bin changed. */
static PetscErrorCode Wake(SpamSim *sim, TS_SpamBlock *b, double *y, PetscInt64 s, int L, PetscInt64 ticks, double tau, PetscBool *moved)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim, aligned = AlignedLevel(s, L);

  PetscFunctionBeginUser;
  *moved = PETSC_FALSE;
  PetscCall(SpamBlockNeighbours(sim, b->yp, b->lev, b->chg, &b->walk));
  for (PetscInt i = 0; i < b->n; i++) {
    b->nxt[i] = 0;
    if (!b->walk.seen[i] || b->lev[i] >= b->walk.nbmax[i] - SPAM_BLOCK_LIMITER || b->lev[i] >= L) continue; /* unseen: beside no deepened bin */
    *moved    = PETSC_TRUE;
    b->nxt[i] = 1;
    if (!b->ends[i] && b->set.wake_delay && aligned > b->walk.nbmax[i] - SPAM_BLOCK_LIMITER) {
      /* s is off the grid of the bin it needs: its step is cut to end at that grid's next
       * tick instead (no deeper than the limiter asks), the first half kick made half the
       * shortened step */
      const int        need = PetscMin(L, b->walk.nbmax[i] - SPAM_BLOCK_LIMITER);
      const PetscInt64 g = ticks >> need, e = (s / g + 1) * g;
      Kick(l, dim, y + (size_t)i * b->nv, b->f + (size_t)i * b->nv, 0.5 * (double)(e - b->start[i] - b->len[i]) * tau);
      b->len[i] = e - b->start[i];
      b->lev[i] = need;
      b->delayed++;
      continue;
    }
    if (!b->ends[i]) {
      const double old = (double)b->len[i] * tau, ran = (double)(s - b->start[i]) * tau;
      Kick(l, dim, y + (size_t)i * b->nv, b->f + (size_t)i * b->nv, 0.5 * (ran - old));
      b->ends[i] = 1;
      b->woke[i] = 1;
      b->act[b->nact++] = i;
      b->woken++;
      b->psteps++;
    }
    b->lev[i] = PetscMin(L, PetscMax(aligned, b->walk.nbmax[i] - SPAM_BLOCK_LIMITER));
  }
  PetscCall(PetscArraycpy(b->chg, b->nxt, b->n));
  PetscCall(AnyRank(sim, MPI_LOR, moved));
  PetscFunctionReturn(0);
}

/* The woken particles' second half kicks, half the time they ran along their rate at s
 * (evaluated for them alone on the predicted state when the pass is restricted). */
static PetscErrorCode WokenKicks(SpamTsApp *app, TS_SpamBlock *b, double *y, PetscInt64 s, double t0, double tau, PetscBool *ok)
{
  const SpamLayout *l   = &app->sim->model.layout;
  const int         dim = app->sim->model.dim;
  PetscBool         any = (PetscBool)(b->nact > b->nends); /* the woken follow the ends in b->act */

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  PetscCall(AnyRank(app->sim, MPI_LOR, &any)); /* the restricted evaluation is collective */
  if (!any) PetscFunctionReturn(0);
  if (b->set.restricted) { /* the full pass left every rate in g already */
    PetscCall(EvaluateMarked(app, b, t0 + (double)s * tau, b->yp, b->g, b->woke, ok));
    b->wake_evals++;
    if (!*ok) PetscFunctionReturn(0);
  }
  for (PetscInt a = b->nends; a < b->nact; a++) {
    const PetscInt i = b->act[a];
    Kick(l, dim, y + (size_t)i * b->nv, b->g + (size_t)i * b->nv, 0.5 * (double)(s - b->start[i]) * tau);
    b->woke[i] = 0;
  }
  PetscFunctionReturn(0);
}

/* After the evaluation at tick s: the particles whose step ends take their new bin (the
 * wanted one, no coarser than s's grid allows, the limiter's against the neighbours'
 * bins); then the particles these leave too slow are woken (only a bin made deeper can
 * leave one so), and theirs in turn.
 * Each particle starting a step gets its first half kick. */
static PetscErrorCode Rebin(TS ts, SpamTsApp *app, TS_SpamBlock *b, double *y, PetscInt64 s, double t0, double D, int L, PetscInt64 ticks, double tau, PetscBool *ok)
{
  SpamSim          *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim, aligned = AlignedLevel(s, L);
  PetscBool         deeper = PETSC_FALSE;
  PetscInt64        row    = -1;
  double            wrow   = 0.0;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  PetscCall(SpamBlockNeighbours(sim, b->yp, b->lev, b->ends, &b->walk));
  PetscCall(PetscArrayzero(b->chg, b->n));
  for (PetscInt a = 0; a < b->nends && row < 0; a++) {
    const PetscInt i    = b->act[a];
    const double   want = SpamBlockWanted(sim, &b->set, &b->walk, i, b->g + (size_t)i * b->nv, Controlled(b, i));
    int            k    = LevelFor(want, D, L);
    if (k < 0) {
      row  = SpamSimRowOf(sim, i);
      wrow = want;
      break;
    }
    k = PetscMin(L, PetscMax(k, PetscMax(aligned, b->walk.nbmax[i] - SPAM_BLOCK_LIMITER)));
    b->chg[i] = (unsigned char)(k > b->lev[i]);
    deeper |= k > b->lev[i];
    b->lev[i] = k;
  }
  PetscCall(TooDeep(ts, app, row, wrow, D, L, ok));
  if (!*ok) PetscFunctionReturn(0);
  PetscCall(AnyRank(sim, MPI_LOR, &deeper));
  /* a woken particle's bin is deeper too: the limiter spreads ring by ring until it holds */
  for (int ring = 0; deeper && ring <= L; ring++) PetscCall(Wake(sim, b, y, s, L, ticks, tau, &deeper));
  PetscCall(WokenKicks(app, b, y, s, t0, tau, ok));
  if (!*ok) PetscFunctionReturn(0);
  for (PetscInt a = 0; a < b->nact; a++) { /* the ends and the woken */
    const PetscInt i = b->act[a];
    PetscCall(PetscArraycpy(b->f + (size_t)i * b->nv, b->g + (size_t)i * b->nv, b->nv));
    b->len[i] = ticks >> b->lev[i];
    Kick(l, dim, y + (size_t)i * b->nv, b->f + (size_t)i * b->nv, 0.5 * (double)b->len[i] * tau);
    b->start[i] = s;
    b->deepest  = PetscMax(b->deepest, b->lev[i]);
  }
  PetscFunctionReturn(0);
}

/* The top step: the longest any particle wants, at most the distance to the stop time,
 * -ts_dt, and 2^L times the shortest any particle wants (so that it fits the deepest
 * bin: with -block_max_level 0 the method is global kick-drift-kick on the shortest). */
static PetscErrorCode TopStep(const TS ts, const SpamTsApp *app, const TS_SpamBlock *b, double *top)
{
  double D = ts->max_time - ts->ptime, longest = 0.0, shortest = PETSC_INFINITY;

  PetscFunctionBeginUser;
  if (app->o->dt_first > 0) D = PetscMin(D, app->o->dt_first);
  for (PetscInt i = 0; i < b->n; i++) {
    const double want = SpamBlockWanted(app->sim, &b->set, &b->walk, i, b->f + (size_t)i * b->nv, Controlled(b, i));
    longest  = PetscMax(longest, want);
    shortest = PetscMin(shortest, want);
  }
  PetscCall(RankReduce(app->sim, MPI_DOUBLE, MPI_MAX, &longest));
  PetscCall(RankReduce(app->sim, MPI_DOUBLE, MPI_MIN, &shortest));
  if (longest > 0.0) D = PetscMin(D, longest);
  if (shortest > 0.0) D = PetscMin(D, shortest * (double)((PetscInt64)1 << b->set.max_level));
  *top = D;
  PetscFunctionReturn(0);
}

/* Under -block_criterion error, after the second half kicks at a tick: each particle
 * whose step ended gets its error estimate and the step its controller asks next. A step
 * above the tolerance is accepted, its successor cut by the controller; a step above
 * -block_reject F times the tolerance (default 4: more than twice too long, the estimate
 * being of order dt^2) rejects the whole cycle (no particle's step can be redone alone: its
 * neighbours moved on its forces): *rejected (on any rank), its particle's cut step kept in
 * b->cut for the redo. Without it an event within a long step (a shock's arrival at a
 * particle at rest) enters the result unchecked. A woken particle, whose step the limiter
 * cut short, keeps the step it asked before. */
static PetscErrorCode Estimate(const SpamSim *sim, TS_SpamBlock *b, const double *y, double tau, PetscBool *rejected)
{
  PetscBool bad = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < b->nends; a++) {
    const PetscInt i  = b->act[a];
    const size_t   o  = (size_t)i * b->nv;
    const double   dt = (double)b->len[i] * tau;
    double         e;
    e          = SpamBlockError(sim, &b->ectl, y + o, b->f + o, b->g + o, dt, b->wscr);
    b->want[i] = SpamBlockErrorStep(dt, e);
    b->ests++;
    b->err_max = PetscMax(b->err_max, e);
    b->over += e > 1.0;
    if (b->set.reject > 0.0 && !(e <= b->set.reject)) {
      b->cut[i] = PetscMin(b->cut[i], b->want[i]);
      bad       = PETSC_TRUE;
    }
  }
  PetscCall(AnyRank(sim, MPI_LOR, &bad));
  *rejected = bad;
  PetscFunctionReturn(0);
}

/* One tick: drift everyone to tick s, evaluate on the predicted state, second half kick of
 * the particles whose step ends there. The evaluation is the restricted pass (where the
 * settings ask for it) even when every particle's step ends (the cycle's last tick): it
 * skips the full pass's gradient walk, of which the gas it covers reads nothing. */
static PetscErrorCode Tick(SpamTsApp *app, TS_SpamBlock *b, double *y, PetscInt64 from, PetscInt64 s, double t0, double tau, PetscBool *ok, PetscBool *rejected)
{
  SpamSim          *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  const double      dt  = (double)(s - from) * tau;
  PetscInt64        nact, all;

  PetscFunctionBeginUser;
  DriftPredict(b, l, dim, y, s, dt, tau);
  nact = b->nact;
  all      = nact;
  PetscCall(RankReduce(sim, MPIU_INT64, MPI_SUM, &all));
  PetscCall(EvaluateMarked(app, b, t0 + (double)s * tau, b->yp, b->g, b->ends, ok));
  b->evals++;
  if (!*ok) PetscFunctionReturn(0);
  for (PetscInt a = 0; a < b->nends; a++) {
    const PetscInt i = b->act[a];
    Kick(l, dim, y + (size_t)i * b->nv, b->g + (size_t)i * b->nv, 0.5 * (double)b->len[i] * tau);
  }
  if (b->want) PetscCall(Estimate(sim, b, y, tau, rejected));
  b->psteps += nact;
  b->active_sum += (double)all / (double)PetscMax(sim->p.nglobal, 1);
  PetscFunctionReturn(0);
}

/* One cycle from the synchronised state y with rates b->f: its top step D, the bins, the
 * ticks. *rejected (-block_criterion error with -block_reject): some particle's estimate
 * exceeded -block_reject at a tick, and the cycle stopped there (y and b->f half done). */
static PetscErrorCode Cycle(TS ts, SpamTsApp *app, TS_SpamBlock *b, double *y, double *D, PetscBool *ok, PetscBool *rejected)
{
  const int        L     = (int)b->set.max_level;
  const PetscInt64 ticks = (PetscInt64)1 << L;
  const double     t0    = ts->ptime;
  double           tau   = 0.0;
  PetscInt64       s     = 0;

  PetscFunctionBeginUser;
  *rejected = PETSC_FALSE;
  PetscCall(SpamBlockNeighbours(app->sim, y, NULL, NULL, &b->walk)); /* the signal speeds TopStep reads */
  PetscCall(TopStep(ts, app, b, D));
  tau = *D / (double)ticks;
  PetscCall(FirstBins(ts, app, b, y, *D, L, ok)); /* the bins of this cycle's top step */
  if (*ok) {
    for (PetscInt i = 0; i < b->n; i++) {
      b->len[i] = ticks >> b->lev[i];
      Kick(&app->sim->model.layout, app->sim->model.dim, y + (size_t)i * b->nv, b->f + (size_t)i * b->nv, 0.5 * (double)b->len[i] * tau);
      b->start[i] = 0;
      b->deepest  = PetscMax(b->deepest, b->lev[i]);
    }
  }
  while (*ok && !*rejected && s < ticks) {
    PetscInt64 next = ticks;
    for (PetscInt i = 0; i < b->n; i++) next = PetscMin(next, b->start[i] + b->len[i]);
    PetscCall(RankReduce(app->sim, MPIU_INT64, MPI_MIN, &next));
    PetscCall(Tick(app, b, y, s, next, t0, tau, ok, rejected));
    s = next;
    if (*ok && !*rejected && s < ticks) PetscCall(Rebin(ts, app, b, y, s, t0, *D, L, ticks, tau, ok));
  }
  PetscFunctionReturn(0);
}

/* Under -block_criterion error, the particles with no step asked yet (the run's start):
 * as ARKODE's first step, trials. Each such particle takes the kick-drift-kick step's
 * predicted end over the length dt it is allowed (the CFL bound, then the last trial's
 * answer): the position drifted with the half-kicked velocity, the other fields advanced
 * along their rates; the rates are evaluated there, and the difference of the two kicks
 * over dt, weighed as any step's estimate, gives the step asked: dt safety err^(-1/2) (at
 * most SPAM_BLOCK_GROWTH dt). (A drift with the velocity alone would see nothing move in
 * a gas at rest.) Repeated while some particle's answer is below half its trial's length,
 * at most FIRST_TRIALS times: one evaluation each, at the run's start only. The other
 * particles stay where they are in the trials. b->yp, b->g and b->cut are scratch; the
 * kernel ranges the trials' evaluations leave (the adaptive range) are put back. */
#define FIRST_TRIALS 4
static PetscErrorCode FirstWants(SpamTsApp *app, TS_SpamBlock *b, double t0, const double *y, PetscBool *ok)
{
  SpamSim          *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  PetscBool         any = PETSC_FALSE, again = PETSC_TRUE;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  for (PetscInt i = 0; i < b->n && !any; i++) any = (PetscBool)(b->want[i] >= PETSC_INFINITY);
  PetscCall(AnyRank(sim, MPI_LOR, &any));
  if (!any) PetscFunctionReturn(0);
  PetscCall(SpamBlockNeighbours(sim, y, NULL, NULL, &b->walk));
  if (sim->pair.f.adaptive) PetscCall(PetscArraycpy(b->h0, sim->pair.f.h, b->n));
  for (PetscInt i = 0; i < b->n; i++) {
    const double dt = b->want[i] >= PETSC_INFINITY ? SpamBlockWanted(sim, &b->set, &b->walk, i, b->f + (size_t)i * b->nv, PETSC_INFINITY) : 0.0;
    b->cut[i]       = dt < PETSC_INFINITY ? dt : 0.0; /* the trial's length (0: none) */
  }
  for (int trial = 0; trial < FIRST_TRIALS && again; trial++) {
    again = PETSC_FALSE;
    for (PetscInt i = 0; i < b->n; i++) {
      const size_t  o = (size_t)i * b->nv;
      const double *p = y + o, *r = b->f + o, dt = b->cut[i];
      double       *q = b->yp + o;
      for (int k = 0; k < b->nv; k++) q[k] = p[k] + dt * r[k];
      for (int d = 0; d < dim; d++) q[l->x + d] = p[l->x + d] + dt * (p[l->v + d] + 0.5 * dt * r[l->v + d]);
    }
    PetscCall(Evaluate(app, t0, b->yp, b->g, ok));
    if (!*ok) break;
    for (PetscInt i = 0; i < b->n; i++) {
      const size_t o  = (size_t)i * b->nv;
      const double dt = b->cut[i];
      double       e, w;
      if (!(dt > 0.0)) continue;
      e         = SpamBlockError(sim, &b->ectl, y + o, b->f + o, b->g + o, dt, b->wscr);
      w         = e > 0.0 ? dt * PetscMin(SPAM_BLOCK_GROWTH, SPAM_BLOCK_SAFETY / sqrt(e)) : SPAM_BLOCK_GROWTH * dt;
      b->want[i] = w;
      if (w < 0.5 * dt) {
        b->cut[i] = w;
        again     = PETSC_TRUE;
      }
    }
    PetscCall(AnyRank(sim, MPI_LOR, &again));
  }
  for (PetscInt i = 0; i < b->n; i++) b->cut[i] = PETSC_INFINITY;
  if (sim->pair.f.adaptive) PetscCall(PetscArraycpy(sim->pair.f.h, b->h0, b->n));
  PetscFunctionReturn(0);
}

/* Under -block_criterion error, before a cycle: its start kept (state, rates, the steps
 * asked, the kernel ranges), so that a rejected cycle can be redone from there. */
static PetscErrorCode KeepStart(const SpamSim *sim, TS_SpamBlock *b, const double *y)
{
  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(b->y0, y, (size_t)b->n * b->nv));
  PetscCall(PetscArraycpy(b->f0, b->f, (size_t)b->n * b->nv));
  PetscCall(PetscArraycpy(b->want0, b->want, b->n));
  if (sim->pair.f.adaptive) PetscCall(PetscArraycpy(b->h0, sim->pair.f.h, b->n));
  for (PetscInt i = 0; i < b->n; i++) b->cut[i] = b->cap[i] = PETSC_INFINITY;
  PetscFunctionReturn(0);
}

/* A rejected cycle: back to its start, each rejected particle's steps capped for the rest
 * of the cycle's tries at the step its controller gave after the rejected one (a cap, not
 * only its first step: before the event that made its error jump its controller would
 * lengthen its steps again), the others as at the start. */
static PetscErrorCode BackToStart(SpamSim *sim, TS_SpamBlock *b, double *y)
{
  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(y, b->y0, (size_t)b->n * b->nv));
  PetscCall(PetscArraycpy(b->f, b->f0, (size_t)b->n * b->nv));
  if (sim->pair.f.adaptive) PetscCall(PetscArraycpy(sim->pair.f.h, b->h0, b->n));
  for (PetscInt i = 0; i < b->n; i++) {
    b->cap[i]  = PetscMin(b->cap[i], b->cut[i]);
    b->want[i] = b->want0[i];
    b->cut[i]  = PETSC_INFINITY;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TSStep_SpamBlock(TS ts)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;
  SpamTsApp    *app;
  const double  t0 = ts->ptime;
  double       *y, D = 0.0; /* set by the cycle below; initialised for gcc's flow analysis under the sanitizers */
  PetscBool     ok = PETSC_TRUE, rejected = PETSC_FALSE;
  PetscInt      tries = 0;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCall(VecGetArray(ts->vec_sol, &y));
  /* the rates of a synchronised state: kept from the last tick (or a checkpoint), or anew
   * after a jump; when kept, the list is moved to y, where the last tick left it (a no-op
   * then) unless an output's list build was reverted or a restart rebuilt it at the
   * checkpoint's reference positions since */
  if (!b->have_f || ts->steprestart) PetscCall(Evaluate(app, t0, y, b->f, &ok));
  else PetscCall(PlaceList(app, t0, y, &ok));
  ts->steprestart = PETSC_FALSE;
  b->have_f       = ok;
  if (ok && b->want) {
    b->ectl = (SpamBlockErrorCtx){app->w.rtol, app->w.atol, app->w.vscale, app->o->error_norm}; /* the weights' scale is a restart's too */
    PetscCall(FirstWants(app, b, t0, y, &ok));
    if (ok) PetscCall(PlaceList(app, t0, y, &ok)); /* the trial's evaluation moved the list */
  }
  if (ok && b->want) {
    PetscCall(KeepStart(app->sim, b, y));
  }
  if (ok) PetscCall(Cycle(ts, app, b, y, &D, &ok, &rejected));
  while (ok && rejected) { /* -block_reject: redone with the rejected steps cut */
    b->rejected++;
    if (++tries >= PetscMax(ts->max_reject, 1)) {
      char msg[200];
      (void)snprintf(msg, sizeof msg, "a block cycle from t = %.6e was rejected %" PetscInt_FMT " times (some particle's error estimate above -block_reject %g times the tolerance each time; -ts_max_reject)", t0, tries, b->set.reject);
      PetscCall(Fail(ts, app, msg));
      ok = PETSC_FALSE;
      break;
    }
    PetscCall(BackToStart(app->sim, b, y));
    PetscCall(PlaceList(app, t0, y, &ok));
    if (ok) PetscCall(Cycle(ts, app, b, y, &D, &ok, &rejected));
  }
  PetscCall(VecRestoreArray(ts->vec_sol, &y));
  if (!ok) {
    b->have_f = PETSC_FALSE;
    if (!app->fail[0] && ts->reason >= 0) ts->reason = TS_DIVERGED_STEP_REJECTED;
    PetscFunctionReturn(0);
  }
  PetscCall(PetscArraycpy(b->f, b->g, (size_t)b->n * b->nv)); /* every step ended at the top tick */
  b->cycles++;
  ts->ptime     = t0 + D;
  ts->time_step = D;
  ts->reject    = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSSetUp_SpamBlock(TS ts)
{
  TS_SpamBlock     *b = (TS_SpamBlock *)ts->data;
  SpamTsApp        *app;
  SpamSim          *sim;
  const SpamLayout *l;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCheck(app, PetscObjectComm((PetscObject)ts), PETSC_ERR_ORDER, "the block_kdk TS needs a SpamTsApp application context");
  sim = app->sim;
  l   = &sim->model.layout;
  if (l->x < 0 || l->v < 0) SPAM_BAD_INPUT("-ts_type", SPAM_TSBLOCK_KDK, "kick-drift-kick needs positions and velocities in the state; model %s has none", sim->model.name);
  if (sim->model.post_step) SPAM_BAD_INPUT("-ts_type", SPAM_TSBLOCK_KDK, "model %s changes the state after each step (closest-approach reflection), which a block cycle cannot follow particle by particle: use -ts_type arkode", sim->model.name);
  b->n  = sim->p.n;
  b->nv = l->nvar;
  PetscCall(PetscMalloc3((size_t)b->n * b->nv + 1, &b->f, (size_t)b->n * b->nv + 1, &b->g, (size_t)b->n * b->nv + 1, &b->yp));
  PetscCall(PetscMalloc4(b->n + 1, &b->lev, b->n + 1, &b->start, b->n + 1, &b->len, b->n + 1, &b->ends));
  PetscCall(PetscCalloc4(b->n + 1, &b->chg, b->n + 1, &b->nxt, b->n + 1, &b->woke, 2 * b->n + 1, &b->near));
  PetscCall(PetscMalloc2(b->n + 1, &b->gid, b->n + 1, &b->act));
  PetscCall(PetscArraycpy(b->gid, sim->p.gid, b->n));
  if (b->set.criterion == SPAM_BLOCK_CRITERION_ERROR) {
    PetscCall(PetscMalloc4(b->n + 1, &b->want, b->n + 1, &b->cut, b->n + 1, &b->want0, b->n + 1, &b->cap));
    PetscCall(PetscMalloc4((size_t)b->n * b->nv + 1, &b->y0, (size_t)b->n * b->nv + 1, &b->f0, b->n + 1, &b->h0, b->nv + 1, &b->wscr));
    for (PetscInt i = 0; i < b->n; i++) b->want[i] = b->cap[i] = PETSC_INFINITY; /* no estimate yet: the CFL criterion alone */
  }
  if (b->set.restricted && !sim->model.rhs_active) {
    if (b->restricted_set) SPAM_BAD_INPUT("-block_restricted", "true", "model %s has no pass restricted to the active particles (the gas with one h, no conduction or viscous stress, R0 coordinates, no torque scaling has one): leave it false", sim->model.name);
    b->set.restricted = PETSC_FALSE; /* the default asks for it only where it exists */
  }
  b->have_f          = PETSC_FALSE;
  app->self_stepping = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSReset_SpamBlock(TS ts)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;

  PetscFunctionBeginUser;
  if (b->f) PetscCall(PetscFree3(b->f, b->g, b->yp));
  if (b->lev) PetscCall(PetscFree4(b->lev, b->start, b->len, b->ends));
  if (b->chg) PetscCall(PetscFree4(b->chg, b->nxt, b->woke, b->near));
  if (b->gid) PetscCall(PetscFree2(b->gid, b->act));
  if (b->want) PetscCall(PetscFree4(b->want, b->cut, b->want0, b->cap));
  if (b->y0) PetscCall(PetscFree4(b->y0, b->f0, b->h0, b->wscr));
  PetscCall(SpamBlockWalkDestroy(&b->walk));
  b->have_f = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode TSDestroy_SpamBlock(TS ts)
{
  PetscFunctionBeginUser;
  PetscCall(TSReset_SpamBlock(ts));
  PetscCall(PetscFree(ts->data));
  PetscFunctionReturn(0);
}

/* -ts_view: the settings and what the cycles did, with the fraction of particles active
 * per evaluation (the share of the work a pass over the active particles would do). */
static PetscErrorCode TSView_SpamBlock(TS ts, PetscViewer viewer)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;
  SpamTsApp    *app;
  PetscBool     ascii;
  PetscInt64    counts[3] = {b->psteps, b->woken, b->delayed}, nall = b->n; /* over the ranks */
  int           deepest   = b->deepest;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) PetscFunctionReturn(0);
  PetscCall(TSGetApplicationContext(ts, &app));
  if (app && app->sim && SpamSimDistributed(app->sim)) {
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, counts, 3, MPIU_INT64, MPI_SUM, app->sim->p.comm));
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &deepest, 1, MPI_INT, MPI_MAX, app->sim->p.comm));
    nall = app->sim->p.nglobal;
  }
  if (b->set.criterion == SPAM_BLOCK_CRITERION_ERROR) {
    long   c[3] = {b->rejected, b->ests, b->over};
    double e    = b->err_max;
    if (app && app->sim && SpamSimDistributed(app->sim)) {
      PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, c, 3, MPI_LONG, MPI_SUM, app->sim->p.comm));
      PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &e, 1, MPI_DOUBLE, MPI_MAX, app->sim->p.comm));
    }
    PetscCall(PetscViewerASCIIPrintf(viewer, "  block steps, kick-drift-kick, bins by error control: -ts_rtol %g -ts_atol %g (-error_norm %s per particle), bounded by -block_cfl %g; -block_max_level %" PetscInt_FMT ", limiter %d levels\n", b->ectl.rtol, b->ectl.atol, b->ectl.norm == SPAM_ERROR_NORM_MAX ? "max" : "rms", b->set.cfl, b->set.max_level, SPAM_BLOCK_LIMITER));
    PetscCall(PetscViewerASCIIPrintf(viewer, "  block error control: particle estimates %ld, above the tolerance %ld, largest %.3g, rejected cycles %ld (-block_reject %g)\n", c[1], c[2], e, c[0], b->set.reject));
  } else PetscCall(PetscViewerASCIIPrintf(viewer, "  block steps, kick-drift-kick: -block_cfl %g -block_force %g -block_max_level %" PetscInt_FMT ", limiter %d levels\n", b->set.cfl, b->set.force, b->set.max_level, SPAM_BLOCK_LIMITER));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  block cycles %ld, evaluations in them %ld, particle steps %" PetscInt64_FMT " (woken %" PetscInt64_FMT "), deepest bin %d\n", b->cycles, b->evals, counts[0], counts[1], deepest));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  block restricted pass %s: restricted evaluations %ld (of them for woken particles %ld)\n", b->set.restricted ? "on" : "off", b->restricted, b->wake_evals));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  block wakes put off to the needed bin's next tick (-block_wake_delay %s): %" PetscInt64_FMT "\n", b->set.wake_delay ? "true" : "false", counts[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  block mean active fraction %.6f (particle steps / (evaluations x particles) %.6f)\n", b->evals ? b->active_sum / (double)b->evals : 0.0, b->evals && nall ? (double)counts[0] / ((double)b->evals * (double)nall) : 0.0));
  PetscFunctionReturn(0);
}

static const char *const CriterionNames[] = {"cfl", "error"};

static PetscErrorCode OptionsRead(PetscOptionItems *PetscOptionsObject, SpamBlockSettings *s, PetscBool *restricted_set)
{
  char val[64], crit[16];

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(crit, CriterionNames[s->criterion], sizeof crit));
  PetscCall(PetscOptionsString("-block_criterion", "Block steps: each particle's bin from cfl (-block_cfl, -block_force) or error (its kick-drift-kick step against the embedded first-order one, held to -ts_rtol, -ts_atol in -error_norm's norm, bounded by -block_cfl)", "README", crit, crit, sizeof crit, NULL));
  PetscCall(SpamCheckAllowed("-block_criterion", crit, CriterionNames, 2));
  s->criterion = strcmp(crit, "error") ? SPAM_BLOCK_CRITERION_CFL : SPAM_BLOCK_CRITERION_ERROR;
  PetscCall(PetscOptionsReal("-block_reject", "Block steps, -block_criterion error: a particle's estimate above this many times the tolerance rejects the whole cycle, redone with that particle's steps capped (0: never; a step above the tolerance but not this is accepted and the next one cut)", "README", s->reject, &s->reject, NULL));
  PetscCall(SpamOptionText("-block_reject", s->reject, val, sizeof val));
  if (!(s->reject == 0.0 || s->reject >= 1.0)) SPAM_BAD_INPUT("-block_reject", val, "must be 0 (never) or at least 1");
  PetscCall(PetscOptionsReal("-block_cfl", "Block steps: each particle's step at most C h_i / v_sig,i (signal speed over its neighbours)", "README", s->cfl, &s->cfl, NULL));
  PetscCall(PetscOptionsReal("-block_force", "Block steps: each particle's step at most C' sqrt(h_i / |a_i|)", "README", s->force, &s->force, NULL));
  PetscCall(PetscOptionsBool("-block_restricted", "Block steps: each tick computes the forces of the active particles only (where the model has that pass: the gas with one h, no walls or periodic ghost images), else the whole right-hand side", "README", s->restricted, &s->restricted, restricted_set));
  PetscCall(PetscOptionsBool("-block_wake_delay", "Block steps: a particle the limiter wakes off its needed bin's grid ends its step at that grid's next tick (false: at once, in a bin as deep as the tick's alignment asks)", "README", s->wake_delay, &s->wake_delay, NULL));
  PetscCall(PetscOptionsInt("-block_max_level", "Block steps: the deepest bin, steps down to D / 2^L of the top step D", "README", s->max_level, &s->max_level, NULL));
  PetscCall(SpamOptionText("-block_cfl", s->cfl, val, sizeof val));
  if (!(s->cfl > 0 && s->cfl <= 1)) SPAM_BAD_INPUT("-block_cfl", val, "must be in (0, 1]");
  PetscCall(SpamOptionText("-block_force", s->force, val, sizeof val));
  if (!(s->force > 0 && s->force <= 1)) SPAM_BAD_INPUT("-block_force", val, "must be in (0, 1]");
  (void)snprintf(val, sizeof val, "%" PetscInt_FMT, s->max_level);
  if (s->max_level < 0 || s->max_level > 40) SPAM_BAD_INPUT("-block_max_level", val, "must be from 0 (one global step) to 40");
  PetscFunctionReturn(0);
}

static void Defaults(SpamBlockSettings *s)
{
  s->criterion = SPAM_BLOCK_CRITERION_CFL;
  s->reject    = 4.0; /* a step more than twice too long for an estimate of order dt^2 */
  s->cfl       = 0.25;
  s->force     = 0.25;
  s->max_level  = 16;
  s->restricted = PETSC_TRUE;
  s->wake_delay = PETSC_FALSE;
}

static PetscErrorCode TSSetFromOptions_SpamBlock(TS ts, PetscOptionItems *PetscOptionsObject)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;

  PetscFunctionBeginUser;
  PetscOptionsHeadBegin(PetscOptionsObject, "Block individual steps (kick-drift-kick)");
  PetscCall(OptionsRead(PetscOptionsObject, &b->set, &b->restricted_set));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTSCreate_Block(TS ts)
{
  TS_SpamBlock *b = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&b));
  Defaults(&b->set);
  ts->data                = (void *)b;
  ts->ops->setfromoptions = TSSetFromOptions_SpamBlock;
  ts->ops->setup          = TSSetUp_SpamBlock;
  ts->ops->step           = TSStep_SpamBlock;
  ts->ops->reset          = TSReset_SpamBlock;
  ts->ops->destroy        = TSDestroy_SpamBlock;
  ts->ops->view           = TSView_SpamBlock;
  ts->default_adapt_type  = TSADAPTNONE; /* the bins set the steps */
  ts->usessnes            = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* -help when another type is chosen: the block options with their defaults. */
static PetscErrorCode HelpBlock(PetscOptionItems *PetscOptionsObject, const SpamRunOptions *o)
{
  SpamBlockSettings s;

  PetscFunctionBeginUser;
  (void)o;
  Defaults(&s);
  PetscCall(OptionsRead(PetscOptionsObject, &s, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode DescribeBlock(TS ts, const char **sub, char *adapt, size_t alen, double *fixed_dt)
{
  PetscFunctionBeginUser;
  (void)ts;
  *sub      = "";
  *fixed_dt = 0.0;
  PetscCall(PetscStrncpy(adapt, "bins", alen));
  PetscFunctionReturn(0);
}

/* Per-particle values (nc doubles each, in the particles' order before a migration: ids
 * b->gid, b->n of them) into out, in the order of the particles after it (sim->p.gid): a
 * PetscSF matching the ids (collective). */
static PetscErrorCode CarryRates(const SpamSim *sim, const TS_SpamBlock *b, PetscInt nc, const double *in, double *out)
{
  PetscLayout  layout;
  PetscSF      sf;
  PetscInt    *roots, *leaves, nleaves;
  MPI_Datatype unit;
  int          mine, all;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(b->n + 1, &roots, sim->p.n + 1, &leaves));
  for (PetscInt i = 0; i < b->n; i++) roots[i] = (PetscInt)b->gid[i];
  for (PetscInt i = 0; i < sim->p.n; i++) leaves[i] = (PetscInt)sim->p.gid[i];
  PetscCall(PetscLayoutCreate(sim->p.comm, &layout));
  PetscCall(PetscLayoutSetSize(layout, sim->p.nglobal));
  PetscCall(PetscLayoutSetUp(layout));
  PetscCall(PetscSFCreateByMatchingIndices(layout, b->n, roots, NULL, 0, sim->p.n, leaves, NULL, 0, NULL, &sf));
  PetscCall(PetscLayoutDestroy(&layout));
  PetscCall(PetscFree2(roots, leaves));
  PetscCall(PetscSFGetGraph(sf, NULL, &nleaves, NULL, NULL));
  mine = nleaves == sim->p.n;
  PetscCallMPI(MPIU_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, sim->p.comm));
  PetscCheck(all, sim->p.comm, PETSC_ERR_PLIB, "a migrated particle's block rates were held by no rank");
  PetscCallMPI(MPI_Type_contiguous((PetscMPIInt)nc, MPI_DOUBLE, &unit));
  PetscCallMPI(MPI_Type_commit(&unit));
  PetscCall(PetscSFBcastBegin(sf, unit, in, out, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, unit, in, out, MPI_REPLACE));
  PetscCallMPI(MPI_Type_free(&unit));
  PetscCall(PetscSFDestroy(&sf));
  PetscFunctionReturn(0);
}

/* A migration between two cycles (every particle synchronised): the TS is made again on
 * the new vector, and the rates the next cycle starts from travel with their particles, so
 * that the run goes on as if nothing had moved (under -reproducible, bit for bit as on one
 * rank). Without rates (before the first cycle, or after a failed one) nothing travels. */
static PetscErrorCode FollowBlock(TS ts, SpamTsApp *app)
{
  TS_SpamBlock *b    = (TS_SpamBlock *)ts->data;
  SpamSim      *sim  = app->sim;
  PetscBool     have = b->have_f && b->f && b->gid;
  double       *f    = NULL, *want = NULL;
  PetscReal     t, dt;
  PetscInt      step;

  PetscFunctionBeginUser;
  PetscCall(AnyRank(sim, MPI_LAND, &have));
  if (have) {
    PetscCall(PetscMalloc1((size_t)sim->p.n * b->nv + 1, &f));
    PetscCall(CarryRates(sim, b, b->nv, b->f, f));
  }
  if (b->want) { /* the steps the controllers ask travel too (infinity: none yet) */
    PetscCall(PetscMalloc1(sim->p.n + 1, &want));
    PetscCall(CarryRates(sim, b, 1, b->want, want));
  }
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetTimeStep(ts, &dt));
  PetscCall(TSGetStepNumber(ts, &step));
  PetscCall(TSReset(ts));
  PetscCall(TSSetSolution(ts, sim->p.X));
  PetscCall(TSSetUp(ts));
  PetscCall(TSSetTime(ts, t));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetStepNumber(ts, step));
  if (have) {
    PetscCall(PetscArraycpy(b->f, f, (size_t)b->n * b->nv));
    b->have_f = PETSC_TRUE;
  }
  if (want) PetscCall(PetscArraycpy(b->want, want, b->n));
  PetscCall(PetscFree(f));
  PetscCall(PetscFree(want));
  ts->steprestart = PETSC_FALSE; /* nothing jumped: the next cycle starts from the carried rates */
  PetscFunctionReturn(0);
}

/* Checkpoints: the rates each particle's first half kick of the next cycle takes (b->f, the
 * last tick's, evaluated on the predicted state: a restart could not make them again from
 * the synchronised state), so that a restart continues bit for bit. A marker among the
 * shared entries says they are there (checked before the run touches its directory). */
static PetscErrorCode CkPutBlock(TS ts, const SpamTsApp *app, SpamCkFile *c, PetscReal *dt)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;

  PetscFunctionBeginUser;
  (void)app;
  (void)dt;
  PetscCall(SpamCkPutLong(c, "block_rates", b->have_f));
  PetscFunctionReturn(0);
}

static PetscErrorCode CkPutParticlesBlock(TS ts, SpamCkFile *pc)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;

  PetscFunctionBeginUser;
  PetscCall(SpamCkPutReal(pc, "block_rate", b->have_f ? (size_t)b->n * b->nv : 0, b->f));
  if (b->want) PetscCall(SpamCkPutReal(pc, "block_want", (size_t)b->n, b->want)); /* the steps the controllers ask */
  PetscFunctionReturn(0);
}

static PetscErrorCode CkCheckBlock(const SpamCkFile *c, const char *path)
{
  PetscFunctionBeginUser;
  if (!SpamCkHas(c, "block_rates")) SPAM_BAD_INPUT("-restart", path, "has no entry 'block_rates' (the rates the next block cycle starts from), which a run of -ts_type block_kdk writes");
  PetscFunctionReturn(0);
}

static PetscErrorCode CkApplyBlock(TS ts, const SpamCkFile *c, double h_next, PetscBool pending)
{
  PetscFunctionBeginUser;
  (void)c;
  (void)h_next;
  ts->steprestart = pending ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* After set-up (which sized the arrays for this rank's particles, in the checkpoint's
 * order): the rates back, or none (the cycle evaluates them) if the writer had none. */
static PetscErrorCode CkApplyParticlesBlock(TS ts, const SpamCkFile *pc)
{
  TS_SpamBlock *b = (TS_SpamBlock *)ts->data;
  const double *f;
  size_t        len;

  PetscFunctionBeginUser;
  if (b->want && SpamCkHas(pc, "block_want")) { /* else (a run of -block_criterion cfl): none asked yet */
    PetscCall(SpamCkGetReal(pc, "block_want", (size_t)b->n, &f));
    PetscCall(PetscArraycpy(b->want, f, b->n));
  }
  PetscCall(SpamCkGetLength(pc, "block_rate", &len));
  b->have_f = PETSC_FALSE;
  if (len == 0) PetscFunctionReturn(0);
  PetscCall(SpamCkGetReal(pc, "block_rate", (size_t)b->n * b->nv, &f));
  PetscCall(PetscArraycpy(b->f, f, (size_t)b->n * b->nv));
  b->have_f = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* -block_criterion error: the tolerances and the norm apply, the force criterion not. */
static PetscBool ErrorControlled(TS ts)
{
  const TS_SpamBlock *b = (const TS_SpamBlock *)ts->data;
  return (PetscBool)(b && b->set.criterion == SPAM_BLOCK_CRITERION_ERROR);
}

static PetscBool OptionOff(TS ts, const char *name, char *why, size_t len)
{
  if (!ErrorControlled(ts)) {
    if (strcmp(name, "block_reject")) return PETSC_FALSE;
    (void)snprintf(why, len, "applies to -block_criterion error (this run: -block_criterion cfl)");
    return PETSC_TRUE;
  }
  if (!strcmp(name, "block_force")) {
    (void)snprintf(why, len, "applies to -block_criterion cfl (this run: -block_criterion error, whose error estimate replaces the force criterion)");
    return PETSC_TRUE;
  }
  if (!strcmp(name, "arkode_classic_weights")) {
    (void)snprintf(why, len, "applies to -ts_type arkode, arkode_imex and cvode (this run: -ts_type block_kdk -block_criterion error weighs each particle's error with spam-ark's weights)");
    return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

static const SpamTSOption OptionsBlock[] = {{"block_cfl", PETSC_TRUE, PETSC_FALSE}, {"block_force", PETSC_TRUE, PETSC_FALSE}, {"block_max_level", PETSC_TRUE, PETSC_FALSE}, {"block_restricted", PETSC_TRUE, PETSC_FALSE}, {"block_wake_delay", PETSC_TRUE, PETSC_FALSE}, {"block_criterion", PETSC_TRUE, PETSC_FALSE}, {"block_reject", PETSC_TRUE, PETSC_FALSE}, {NULL, PETSC_FALSE, PETSC_FALSE}};

const SpamTSFamily SpamTSFamilyBlock = {
  .options         = OptionsBlock,
  .type            = SPAM_TSBLOCK_KDK,
  .adapt_default   = TSADAPTNONE,
  .steps           = SPAM_TS_STEPS_OWN,
  .follow          = SPAM_TS_FOLLOW_CARRY,
  .follow_carry    = FollowBlock,
  .step_rule       = "sets each particle's step by -block_cfl and -block_force (or by -block_criterion error)",
  .ck_put             = CkPutBlock,
  .ck_check           = CkCheckBlock,
  .ck_apply           = CkApplyBlock,
  .ck_put_particles   = CkPutParticlesBlock,
  .ck_apply_particles = CkApplyParticlesBlock,
  .describe        = DescribeBlock,
  .error_controlled   = ErrorControlled,
  .option_off         = OptionOff,
  .help_other      = HelpBlock,
};

