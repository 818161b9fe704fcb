/* The Verlet step of the schemes spam-ark registers with PETSc's basicsymplectic ("kdk",
 * "dkd"), taken on the interleaved state [x v] itself. PETSc's own step works on position
 * and velocity sub-vectors, gathered from the state and scattered back at every step, with
 * an update vector and copies between them and the split functions: at N = 16384 about 990
 * instructions a particle per force evaluation against 600 for a whole Runge-Kutta stage.
 * Here a stage is one pass over the particles beside the force evaluation.
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
#include <stdint.h>

PetscErrorCode SpamKickCacheCreate(SpamTsApp *app)
{
  const size_t len = (size_t)app->sim->p.n * app->sim->model.dim;

  PetscFunctionBeginUser;
  if (!app->xcache) PetscCall(PetscMalloc2(len + 1, &app->xcache, len + 1, &app->acache));
  app->cache_valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Whether x (stride between particles) and the compact xc hold the same bits: one pass
 * without an early exit, which the compiler vectorises (the usual answer is yes). */
static PetscBool SameBits(PetscInt n, int dim, const double *x, int stride, const double *xc)
{
  uint64_t diff = 0;

  for (PetscInt i = 0; i < n; i++)
    for (int d = 0; d < dim; d++) {
      uint64_t a, b;
      memcpy(&a, &x[(size_t)i * stride + d], sizeof a);
      memcpy(&b, &xc[(size_t)i * dim + d], sizeof b);
      diff |= a ^ b;
    }
  return (PetscBool)(diff == 0);
}

PetscErrorCode SpamKickCached(SpamTsApp *app, const double *x, int stride, PetscBool *cached)
{
  const SpamSim *sim = app->sim;

  PetscFunctionBeginUser;
  *cached = (PetscBool)(app->cache_valid && SameBits(sim->p.n, sim->model.dim, x, stride, app->xcache));
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
  int           nv, ox, ov; /* entries a particle, offsets of its position and velocity */
  const double *a;          /* the force kicked with                                    */
  double       *acache, *xcache;
  double        hc, hd;     /* c_k dt, d_k dt                                           */
  PetscBool     kick, drift, keep;
} StagePass;

/* One stage on every particle of y: v = v + hc a, then x = x + hd v where drift. With
 * keep (a fresh evaluation in a) the cache takes a and the positions it was evaluated at
 * in the same pass. Inlined with a constant dim by Pass, so the inner loop unrolls. */
static inline void PassDim(const StagePass *s, double *restrict y, const int dim)
{
  const double *restrict a = s->a;
  double *restrict       ac = s->acache, *restrict xc = s->xcache;
  const double           hc = s->hc, hd = s->hd;
  const int              nv = s->nv, ox = s->ox, ov = s->ov;
  const PetscBool        kick = s->kick, drift = s->drift, keep = s->keep;

  for (PetscInt i = 0; i < s->n; i++) {
    double *restrict p = y + (size_t)i * nv;
    for (int d = 0; d < dim; d++) {
      const double ai = a[(size_t)i * dim + d];
      if (keep) {
        ac[(size_t)i * dim + d] = ai;
        xc[(size_t)i * dim + d] = p[ox + d];
      }
      if (kick) p[ov + d] = p[ov + d] + hc * ai;
      if (drift) p[ox + d] = p[ox + d] + hd * p[ov + d];
    }
  }
}

static void Pass(const StagePass *s, double *y, int dim)
{
  switch (dim) {
  case 1:
    PassDim(s, y, 1);
    break;
  case 2:
    PassDim(s, y, 2);
    break;
  default:
    PassDim(s, y, 3);
    break;
  }
}

/* Stage k of scheme sc at the TS's time and step, on the state y. */
static PetscErrorCode Stage(TS ts, SpamTsApp *app, const SpamSympScheme *sc, int k, double *y)
{
  SpamSim          *sim = app->sim;
  const SpamLayout *l   = &sim->model.layout;
  StagePass         s   = {sim->p.n, l->nvar, l->x, l->v, app->acache, app->acache, app->xcache, sc->c[k] * ts->time_step, sc->d[k] * ts->time_step, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};

  PetscFunctionBeginUser;
  if (sc->c[k] != 0.0) {
    PetscBool cached, ok;
    PetscCall(SpamKickCached(app, y + l->x, l->nvar, &cached));
    if (!cached) {
      PetscCall(SpamKickEvaluate(app, ts->ptime, y + l->x, l->nvar, &ok));
      if (ok) {
        s.a              = sim->pair.f.acc;
        s.keep           = PETSC_TRUE;
        app->cache_valid = PETSC_TRUE;
      }
    }
    s.kick = (PetscBool)(s.hc != 0.0); /* VecAXPY does nothing for a zero factor */
  }
  s.drift = (PetscBool)(sc->d[k] != 0.0 && s.hd != 0.0);
  if (!(s.kick || s.drift || s.keep)) PetscFunctionReturn(0);
  Pass(&s, y, sim->model.dim);
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
    PetscScalar *y;
    PetscBool    ok;
    PetscCall(TSPreStage(ts, ts->ptime));
    PetscCall(VecGetArray(X, &y));
    PetscCall(Stage(ts, app, sc, k, y));
    PetscCall(VecRestoreArray(X, &y));
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
