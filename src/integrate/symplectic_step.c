/* The Verlet step of the schemes spam-ark registers with PETSc's basicsymplectic ("kdk",
 * "dkd"), taken on the interleaved state [x v] itself. PETSc's own step works on position
 * and velocity sub-vectors, gathered from the state and scattered back at every step, with
 * an update vector and copies between them and the split functions. Here a stage is one
 * pass over the particles beside the force evaluation (callgrind, N = 16384, 40 kdk steps:
 * 987 instructions a particle per force evaluation with PETSc's step, 662 with this one).
 *
 * The arithmetic is PETSc 3.18's TSStep_BasicSymplectic, so the two give the same bits:
 * stage k first kicks, v = v + (c_k dt) a(x) when c_k is not zero (the force evaluated
 * unless the cache holds it), then drifts, x = x + (d_k dt) v when d_k is not zero, and
 * advances the time by d_k dt. Each update is a product then a sum, as the reference BLAS
 * daxpy behind VecAXPY computes it (this file is compiled without contraction into fused
 * multiply-adds). Both updates read and write one particle's own entries, so a stage's
 * kick and drift run in one pass. The stage hooks (pre- and post-stage, the adaptor's
 * stage check, the domain check) are called as PETSc calls them. */
#include <petsc/private/tsimpl.h>
#include "symplectic.h"
#include <spam/errors.h>
#include <string.h>

PetscErrorCode SpamKickCacheCreate(SpamTsApp *app)
{
  const size_t len = (size_t)app->sim->p.n * app->sim->model.dim;

  PetscFunctionBeginUser;
  if (!app->xcache) PetscCall(PetscMalloc2(len + 1, &app->xcache, len + 1, &app->acache));
  app->cache_valid = PETSC_FALSE;
  app->cache_state = -1;
  PetscFunctionReturn(0);
}

/* Whether x (stride between particles) and the compact xc hold the same bits, stopping at
 * the first difference (after a drift, the first particle that moved). */
static PetscBool SameBits(PetscInt n, int dim, const double *x, int stride, const double *xc)
{
  for (PetscInt i = 0; i < n; i++)
    if (memcmp(&x[(size_t)i * stride], &xc[(size_t)i * dim], (size_t)dim * sizeof *x)) return PETSC_FALSE;
  return PETSC_TRUE;
}

PetscErrorCode SpamKickCached(SpamTsApp *app, const double *x, int stride, PetscBool same, PetscBool *cached)
{
  const SpamSim *sim = app->sim;

  PetscFunctionBeginUser;
  *cached = (PetscBool)(app->cache_valid && (same || SameBits(sim->p.n, sim->model.dim, x, stride, app->xcache)));
  if (SpamSimDistributed(sim)) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, cached, 1, MPIU_BOOL, MPI_LAND, sim->p.comm));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKickEvaluate(SpamTsApp *app, double t, const double *x, int stride, PetscBool *ok)
{
  SpamSim *sim = app->sim;
  PetscInt bad;

  PetscFunctionBeginUser;
  PetscCall(SpamAccel(sim, x, stride, &bad));
  *ok = (PetscBool)(bad < 0);
  if (*ok) PetscFunctionReturn(0);
  if (app->bad < 0) {
    app->bad  = bad;
    app->tbad = t;
  }
  PetscCall(PetscArrayzero(app->acache, (size_t)sim->p.n * sim->model.dim));
  app->cache_valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamKickKeep(SpamTsApp *app, const double *x, int stride)
{
  const SpamSim *sim = app->sim;
  const int      dim = sim->model.dim;

  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(app->acache, sim->pair.f.acc, (size_t)sim->p.n * dim)); /* same layout, a[i*dim + d] */
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < dim; d++) app->xcache[(size_t)i * dim + d] = x[(size_t)i * stride + d];
  app->cache_valid = PETSC_TRUE;
  PetscFunctionReturn(0);
}

typedef struct {
  PetscInt      n;
  const double *a;      /* the force kicked with                */
  double       *acache, *xcache;
  double        hc, hd; /* c_k dt, d_k dt                       */
  PetscBool     kick, drift, keep;
} StagePass;

/* One stage on every particle of the state y, [x v] (layout.c: positions first, then
 * velocities, dim each): v = v + hc a where kick, then x = x + hd v where drift; where keep
 * (a fresh evaluation in a), the cache takes a and the positions it was evaluated at in
 * the same pass. dim and the flags are constants in each copy Pass inlines: every copy is
 * a straight loop. */
static inline __attribute__((always_inline)) void PassDim(const StagePass *s, double *restrict y, const int dim, const int kick, const int drift, const int keep)
{
  const double *restrict a  = s->a;
  double *restrict       ac = s->acache, *restrict xc = s->xcache;
  const double           hc = s->hc, hd = s->hd;

  for (PetscInt i = 0; i < s->n; i++) {
    double *restrict p = y + (size_t)i * 2 * dim;
    for (int d = 0; d < dim; d++) {
      const double ai = a[(size_t)i * dim + d];
      if (keep) {
        ac[(size_t)i * dim + d] = ai;
        xc[(size_t)i * dim + d] = p[d];
      }
      if (kick) p[dim + d] = p[dim + d] + hc * ai;
      if (drift) p[d] = p[d] + hd * p[dim + d];
    }
  }
}

#define SPAM_PASS_FLAGS(DIM)                      \
  switch (flags) {                                \
  case 1: PassDim(s, y, DIM, 1, 0, 0); break;     \
  case 2: PassDim(s, y, DIM, 0, 1, 0); break;     \
  case 3: PassDim(s, y, DIM, 1, 1, 0); break;     \
  case 4: PassDim(s, y, DIM, 0, 0, 1); break;     \
  case 5: PassDim(s, y, DIM, 1, 0, 1); break;     \
  case 6: PassDim(s, y, DIM, 0, 1, 1); break;     \
  case 7: PassDim(s, y, DIM, 1, 1, 1); break;     \
  default: break;                                 \
  }

static void Pass(const StagePass *s, double *y, int dim)
{
  const int flags = (s->kick ? 1 : 0) | (s->drift ? 2 : 0) | (s->keep ? 4 : 0);

  switch (dim) {
  case 1:
    SPAM_PASS_FLAGS(1)
    break;
  case 2:
    SPAM_PASS_FLAGS(2)
    break;
  default:
    SPAM_PASS_FLAGS(3)
    break;
  }
}

/* Stage k of scheme sc at the TS's time and step. The positions are known to be the
 * cache's, without comparing them, while the state vector is as the pass that kept the
 * cache (or found it valid) left it without drifting: the usual first kick of a kdk step. */
static PetscErrorCode Stage(TS ts, SpamTsApp *app, const SpamSympScheme *sc, int k)
{
  SpamSim         *sim = app->sim;
  const int        dim = sim->model.dim;
  Vec              X   = ts->vec_sol;
  StagePass        s   = {sim->p.n, app->acache, app->acache, app->xcache, sc->c[k] * ts->time_step, sc->d[k] * ts->time_step, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  PetscBool        cached = PETSC_FALSE;
  PetscObjectState state;
  PetscScalar     *y;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectStateGet((PetscObject)X, &state));
  PetscCall(VecGetArray(X, &y));
  if (sc->c[k] != 0.0) {
    PetscCall(SpamKickCached(app, y, 2 * dim, (PetscBool)(state == app->cache_state), &cached));
    if (!cached) {
      PetscBool ok;
      PetscCall(SpamKickEvaluate(app, ts->ptime, y, 2 * dim, &ok));
      if (ok) {
        s.a              = sim->pair.f.acc;
        s.keep           = PETSC_TRUE;
        app->cache_valid = PETSC_TRUE;
      }
    }
    s.kick = (PetscBool)(s.hc != 0.0); /* VecAXPY does nothing for a zero factor */
  }
  s.drift = (PetscBool)(s.hd != 0.0);
  Pass(&s, y, dim);
  PetscCall(VecRestoreArray(X, &y));
  PetscCall(PetscObjectStateGet((PetscObject)X, &state));
  app->cache_state = app->cache_valid && !s.drift && (s.keep || cached) ? state : -1;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSymplecticStep(TS ts)
{
  SpamTsApp            *app;
  const char           *name;
  const SpamSympScheme *sc;
  Vec                   X = ts->vec_sol;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &app));
  PetscCall(TSBasicSymplecticGetType(ts, &name));
  sc = SpamSympSchemeNamed(name);
  PetscCheck(sc, PetscObjectComm((PetscObject)ts), PETSC_ERR_PLIB, "basicsymplectic scheme %s is PETSc's: its own step takes it", name);
  for (int k = 0; k < 2; k++) {
    PetscBool ok;
    PetscCall(TSPreStage(ts, ts->ptime));
    PetscCall(Stage(ts, app, sc, k));
    if (sc->d[k] != 0.0) ts->ptime = ts->ptime + sc->d[k] * ts->time_step;
    PetscCall(TSPostStage(ts, ts->ptime, 0, &X));
    PetscCall(TSAdaptCheckStage(ts->adapt, ts, ts->ptime, X, &ok));
    if (ok) PetscCall(TSFunctionDomainError(ts, ts->ptime + ts->time_step, X, &ok));
    if (!ok) {
      ts->reason = TS_DIVERGED_STEP_REJECTED;
      PetscFunctionReturn(0);
    }
  }
  PetscFunctionReturn(0);
}
