/* -reproducible, run on 1, 2 and 3 ranks.
 *
 * Right-hand side. A gas of N particles (a perturbed lattice: 2D Lucy with a density pass,
 * 3D Wendland C2 with unequal masses, 2D in an open box at gamma = 2) is built on rank 0,
 * distributed over the ranks by SpamSimMigrate (Hilbert cut) and given its halo; one
 * SpamRhs per mode. The reference is a one-rank sim (PETSC_COMM_SELF on rank 0) holding
 * the particles in REVERSED gid order, with -threads 2. Checks, values gathered by gid:
 *  - reproducible: density and acceleration of every particle bit-identical to the
 *    reference (another rank count, another local order, another thread count);
 *  - default (control): some values differ in the last bits (the sums follow the list
 *    order: the decomposition and the local order decide them);
 *  - reproducible against default on the reference: within a bound derived for a change
 *    of summation order (a few ulp of each row's sum of absolute terms), the roundings of
 *    the two codes' pair terms, and of the separation across a periodic face (u_i - u_j
 *    - L against u_i - (u_j + L)), carried through q = P/rho^2 into the force;
 *  - every canonical row sorted by strictly increasing (gid, image) key.
 * Norm. SpamNVReproducibleWrmsNorm_Petsc on one vector of 4099 components split evenly,
 * split unevenly and held whole on one rank: the same bits every way and on every rank
 * (SUNDIALS' own norm printed beside it), within 1e-12 of a long-double sum; a NaN or an
 * overflow on one rank only gives NaN or infinity on every rank (no hang); clones keep
 * the operation. */
#include <spam/decompose.h>
#include <spam/error_norm.h>
#include <spam/kernel.h>
#include <nvector/nvector_petsc.h>
#include <float.h>
#include <stdarg.h>
#include "test_util.h"

typedef struct {
  TestCount   count;
  MPI_Comm    comm;
  PetscMPIInt rank, size;
} Ctx;

/* A check whose outcome rank 0 decided (ok is broadcast): printed once. */
static PetscErrorCode Check(Ctx *t, int ok, const char *fmt, ...)
{
  va_list ap;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, t->comm));
  va_start(ap, fmt);
  TestCheckAgreed(t->comm, &t->count, ok, fmt, ap);
  va_end(ap);
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- the gas ------- */
typedef struct {
  const char *name, *kernel;
  int         dim, side;  /* a lattice of side^dim sites at spacing 1                    */
  double      L, h, gamma;
  PetscBool   periodic, unequal_mass;
} Case;

static double Uniform(PetscInt64 gid, int d, int what)
{
  uint64_t s = (uint64_t)gid * 7919u + (uint64_t)d * 104729u + (uint64_t)what * 1299709u;
  return TestUniform(&s);
}
static double PositionOf(const Case *c, PetscInt64 gid, int d)
{
  PetscInt64 site = gid;
  for (int k = 0; k < d; k++) site /= c->side;
  return (double)(site % c->side) + 0.5 + 0.6 * (Uniform(gid, d, 0) - 0.5);
}
static double VelocityOf(PetscInt64 gid, int d) { return 0.2 * (Uniform(gid, d, 1) - 0.5); }
static double MassOf(const Case *c, PetscInt64 gid) { return c->unequal_mass ? 1.0 + 0.25 * Uniform(gid, 0, 2) : 1.0; }

static PetscInt CountOf(const Case *c)
{
  PetscInt n = 1;
  for (int d = 0; d < c->dim; d++) n *= c->side;
  return n;
}

/* The gas on comm with all its particles on the first rank (in reversed gid order when
 * asked), in mode reproducible or default, with `threads` threads. */
static PetscErrorCode MakeSim(MPI_Comm comm, const Case *c, PetscBool reproducible, PetscBool reversed, int threads, SpamSim *sim)
{
  SpamBox     box = {c->dim, {0, 0, 0}, {c->L, c->L, c->L}, {c->periodic, c->periodic, c->periodic}};
  SpamKernel  kern;
  SpamModel   model;
  PetscMPIInt rank;
  PetscInt    n, *row_of;
  double     *x, *v, *m;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  n = rank ? 0 : CountOf(c);
  PetscCall(SpamKernelCreate(c->kernel, c->dim, c->h, &kern));
  PetscCall(SpamModelIsentropeSetUp(c->dim, &kern, 1.0, c->gamma, 1.0 / c->gamma, &model));
  PetscCall(SpamSimCreate(comm, &model, &box, n, 0.1 * c->h, sim));
  sim->pair.threads      = threads;
  sim->pair.reproducible = reproducible;
  PetscCall(PetscMalloc4((size_t)n * c->dim + 1, &x, (size_t)n * c->dim + 1, &v, n + 1, &m, n + 1, &row_of));
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt64 g = reversed ? n - 1 - i : i;
    row_of[i]          = (PetscInt)g;
    for (int d = 0; d < c->dim; d++) {
      x[i * c->dim + d] = PositionOf(c, g, d);
      v[i * c->dim + d] = VelocityOf(g, d);
    }
    m[i] = MassOf(c, g);
  }
  if (reversed) PetscCall(SpamSwarmSetRows(&sim->p, row_of));
  PetscCall(SpamSimFill(sim, x, v, m));
  PetscCall(PetscFree4(x, v, m, row_of));
  PetscCall(SpamSimSetUp(sim));
  PetscFunctionReturn(0);
}

/* The list made anew with the other ranks' particles as remote ghosts (halo.h). The
 * program's set-up attaches its decomposition to the sim (sim->geo.dec), which sets the halo;
 * this test distributes with a decomposition of its own, so it sets the halo here. */
static PetscErrorCode UseHalo(SpamSim *sim)
{
  const PetscBool all[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE};
  const long      builds = sim->pair.nl.builds;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursDestroy(&sim->pair.nl));
  PetscCall(SpamNeighboursCreate((int)sim->p.n, &sim->geo.box, sim->model.kernel.h, sim->pair.skin, &sim->pair.nl));
  if (sim->pair.periodic_ghosts || sim->pair.reproducible) PetscCall(SpamNeighboursSetPeriodicGhosts(&sim->pair.nl, &sim->geo.box, all));
  if (sim->pair.reproducible) PetscCall(SpamNeighboursSetCanonical(&sim->pair.nl, sim->p.gid));
  PetscCall(SpamNeighboursSetComm(&sim->pair.nl, sim->p.comm));
  PetscCall(SpamNeighboursSetThreads(&sim->pair.nl, sim->pair.threads));
  PetscCall(SpamSimBuildList(sim));
  sim->pair.nl.builds = builds + 1; /* the count goes on: what is kept per build (ghost masses) is made again */
  PetscFunctionReturn(0);
}

/* One right-hand side; on the first rank of sim's communicator, res[g * (1 + dim) + k]
 * holds particle g's density (k = 0) and acceleration (k = 1 .. dim), gathered by gid. */
static PetscErrorCode Evaluate(SpamSim *sim, double *res)
{
  const SpamLayout *l = &sim->model.layout;
  const int         dim = sim->model.dim, w = 1 + dim + 1;
  PetscScalar      *y;
  double           *ydot, *mine, *all = NULL;
  PetscInt          bad;
  PetscMPIInt       rank, size, n = (PetscMPIInt)sim->p.n, *cnt = NULL, *off = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(sim->p.comm, &rank));
  PetscCallMPI(MPI_Comm_size(sim->p.comm, &size));
  PetscCall(PetscMalloc2((size_t)sim->p.n * l->nvar + 1, &ydot, (size_t)sim->p.n * w + 1, &mine));
  PetscCall(VecGetArray(sim->p.X, &y));
  PetscCall(SpamRhs(sim, y, ydot, &bad));
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "bad particle %" PetscInt_FMT, bad);
  for (PetscInt i = 0; i < sim->p.n; i++) {
    mine[i * w]     = (double)sim->p.gid[i];
    mine[i * w + 1] = sim->model.density_free ? 0.0 : sim->pair.f.rho[i]; /* gamma = 2: no density pass */
    for (int d = 0; d < dim; d++) mine[i * w + 2 + d] = ydot[(size_t)i * l->nvar + l->v + d];
  }
  if (rank == 0) PetscCall(PetscMalloc3(size, &cnt, size, &off, (size_t)sim->p.nglobal * w + 1, &all));
  n *= w;
  PetscCallMPI(MPI_Gather(&n, 1, MPI_INT, cnt, 1, MPI_INT, 0, sim->p.comm));
  if (rank == 0)
    for (int r = 0; r < size; r++) off[r] = r ? off[r - 1] + cnt[r - 1] : 0;
  PetscCallMPI(MPI_Gatherv(mine, n, MPI_DOUBLE, all, cnt, off, MPI_DOUBLE, 0, sim->p.comm));
  if (rank == 0) {
    for (PetscInt k = 0; k < sim->p.nglobal; k++) {
      const PetscInt64 g = (PetscInt64)all[k * w];
      for (int c = 0; c < 1 + dim; c++) res[g * (1 + dim) + c] = all[k * w + 1 + c];
    }
    PetscCall(PetscFree3(cnt, off, all));
  }
  PetscCall(PetscFree2(ydot, mine));
  PetscFunctionReturn(0);
}

/* Values (of n) that differ bitwise, and the largest difference relative to the largest
 * magnitude of their kind (density, acceleration). */
static long DiffBits(const double *a, const double *b, PetscInt N, int dim, double *rel_rho, double *rel_acc)
{
  long   differ = 0;
  double rmax = 0, amax = 0, dr = 0, da = 0;

  for (PetscInt g = 0; g < N; g++)
    for (int c = 0; c < 1 + dim; c++) {
      const double x = a[g * (1 + dim) + c], y = b[g * (1 + dim) + c];
      differ += memcmp(&x, &y, sizeof x) != 0;
      if (c == 0) rmax = PetscMax(rmax, fabs(y)), dr = PetscMax(dr, fabs(x - y));
      else amax = PetscMax(amax, fabs(y)), da = PetscMax(da, fabs(x - y));
    }
  *rel_rho = rmax > 0 ? dr / rmax : dr; /* gamma = 2: no densities (all 0) */
  *rel_acc = amax > 0 ? da / amax : da;
  return differ;
}

/* Every canonical row in strictly increasing key order (on every rank). */
static PetscErrorCode RowsSorted(Ctx *t, const Case *c, const SpamSim *sim)
{
  const SpamNeighbours *nl   = &sim->pair.nl;
  long                  bad  = 0, rows = 0;

  PetscFunctionBeginUser;
  for (int i = 0; i < nl->n; i++)
    for (int p = nl->cstart[i] + 1; p < nl->cstart[i + 1]; p++) bad += !(nl->key[nl->cnbr[p - 1]] < nl->key[nl->cnbr[p]]);
  rows = nl->n;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_LONG, MPI_SUM, t->comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &rows, 1, MPI_LONG, MPI_SUM, t->comm));
  PetscCall(Check(t, bad == 0 && rows == CountOf(c), "%s, %d ranks: %ld canonical rows, %ld entries out of key order", c->name, t->size, rows, bad));
  PetscFunctionReturn(0);
}

/* The bound on |reproducible - default| of every density and acceleration of the
 * one-rank reproducible sim s (after its RHS), from its canonical rows; u = 2^-53.
 *   Sum order: a recursive sum of k terms t is off by at most (k - 1) u sum |t| (to first
 *   order); two orders, the threaded default's buffer additions and the two codes' pair
 *   term roundings (a handful of operations each) stay within (2k + 12) u sum |t|.
 *   Separation: across a periodic face the default's minimum image forms (u_i - u_j) - L,
 *   the canonical row u_i - (u_j + L); each component differs by at most
 *   delta = 2 u (|u_i| + |u_j| + L) (two roundings of numbers below that size), and a term
 *   moves by its derivative times delta: m_j |w'| = m_j |g| r for the density,
 *   m_j (q_i + q_j) (2 |g| + |w''|) for a component of the force (d(g dx)/d dx).
 *   q = kappa rho^(gamma - 2): |dq| <= |gamma - 2| q |drho| / rho + 4 u q (pow's roundings).
 * brho[i] and bacc[i * dim + d] by local index; dq over the slots. */
static void RowBound(const SpamSim *s, int i, const double *dq, double *brho, double *bacc)
{
  const SpamNeighbours *nl = &s->pair.nl;
  const SpamKernel     *k  = &s->model.kernel;
  const SpamFields     *f  = &s->pair.f;
  const int             dim = s->model.dim;
  const double          u = 0.5 * DBL_EPSILON;
  double                sabs = f->m[i] * k->wnorm, sep = 0.0, sacc[3] = {0, 0, 0}, sq[3] = {0, 0, 0}, sdx = 0.0;
  int                   kk = 0;

  for (int p = nl->cstart[i]; p < nl->cstart[i + 1]; p++) {
    const int j = nl->cnbr[p];
    double    dx[3] = {0, 0, 0}, r2 = 0.0, delta = 0.0;
    for (int d = 0; d < dim; d++) {
      dx[d] = nl->u[d][i] - nl->u[d][j];
      r2 += dx[d] * dx[d];
      delta = PetscMax(delta, 2.0 * u * (fabs(nl->u[d][i]) + fabs(nl->u[d][j]) + s->geo.box.len[d]));
    }
    if (r2 >= k->h2) continue;
    const double r = sqrt(r2), sc = r * k->hinv, qq = f->q[i] + f->q[j];
    const double w = SpamKernelShapeScaledF(k->kind, dim, k->wnorm, sc), g = SpamKernelShapeScaledG(k->kind, dim, k->gnorm, sc), w2 = SpamKernelShapeScaledH(k->kind, dim, k->gnorm, sc);
    kk++;
    sabs += f->m[j] * fabs(w);
    sep += f->m[j] * fabs(g) * r * delta * sqrt((double)dim);
    for (int d = 0; d < dim && dq; d++) {
      sacc[d] += fabs(f->m[j] * qq * g * dx[d]);
      sq[d] += f->m[j] * fabs(g * dx[d]) * (dq[i] + dq[j]);
    }
    sdx += f->m[j] * qq * (2.0 * fabs(g) + fabs(w2)) * delta;
  }
  if (!dq) *brho = (2.0 * kk + 12.0) * u * sabs + sep;
  else
    for (int d = 0; d < dim; d++) bacc[d] = (2.0 * kk + 12.0) * u * sacc[d] + sq[d] + sdx;
}

static PetscErrorCode DeriveBound(const SpamSim *s, double *brho, double *bacc)
{
  const SpamNeighbours *nl = &s->pair.nl;
  const int             n = nl->n, dim = s->model.dim;
  const double          u = 0.5 * DBL_EPSILON, gam = s->model.eos.gamma;
  double               *dq;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(SpamNeighboursSlots(nl) + 1, &dq));
  for (int i = 0; i < n; i++) {
    RowBound(s, i, NULL, &brho[i], NULL);
    /* gamma = 2: q = kappa for every particle, no density pass (rho holds nothing) */
    dq[i] = s->model.density_free ? 0.0 : fabs(gam - 2.0) * s->pair.f.q[i] * brho[i] / s->pair.f.rho[i] * 1.01 + 4.0 * u * s->pair.f.q[i];
  }
  for (int q = 0; q < nl->ghosts.n; q++) dq[n + q] = dq[nl->ghosts.src[q]]; /* one rank: every ghost is an image */
  for (int i = 0; i < n; i++) RowBound(s, i, dq, NULL, bacc + (size_t)i * dim);
  PetscCall(PetscFree(dq));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckCase(Ctx *t, const Case *c)
{
  const PetscInt N = CountOf(c);
  const int      w = 1 + c->dim;
  double        *ref_rep = NULL, *ref_def = NULL, *dist_rep, *dist_def;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2((size_t)N * w, &dist_rep, (size_t)N * w, &dist_def));
  /* Distributed, both modes. */
  for (int mode = 0; mode < 2; mode++) {
    SpamSim         sim;
    SpamDecomp      dec;
    SpamMigrateInfo info;
    PetscCall(MakeSim(t->comm, c, (PetscBool)(mode == 0), PETSC_FALSE, 1, &sim));
    PetscCall(SpamDecompCreate(sim.p.comm, &sim.geo.box, sim.model.kernel.h, 0.0, &dec));
    PetscCall(SpamSimMigrate(&sim, &dec, &info));
    PetscCall(UseHalo(&sim));
    PetscCall(Evaluate(&sim, mode == 0 ? dist_rep : dist_def));
    if (mode == 0) PetscCall(RowsSorted(t, c, &sim));
    PetscCall(SpamDecompDestroy(&dec));
    PetscCall(SpamSimDestroy(&sim));
  }
  /* The one-rank references, reversed order, two threads; and the bound. */
  double worst = 0.0;
  long   over  = 0;
  if (t->rank == 0) {
    SpamSim rep, def;
    double *brho, *bacc;
    PetscCall(PetscMalloc2((size_t)N * w, &ref_rep, (size_t)N * w, &ref_def));
    PetscCall(MakeSim(PETSC_COMM_SELF, c, PETSC_TRUE, PETSC_TRUE, 2, &rep));
    PetscCall(MakeSim(PETSC_COMM_SELF, c, PETSC_FALSE, PETSC_TRUE, 2, &def));
    PetscCall(Evaluate(&rep, ref_rep));
    PetscCall(Evaluate(&def, ref_def));
    PetscCall(PetscMalloc2(N, &brho, (size_t)N * c->dim, &bacc));
    PetscCall(DeriveBound(&rep, brho, bacc));
    for (PetscInt i = 0; i < N; i++) { /* the bound by local index, the values by gid */
      const PetscInt64 g = rep.p.gid[i];
      for (int k = 0; k < w; k++) {
        const double diff = fabs(ref_rep[g * w + k] - ref_def[g * w + k]), b = k == 0 ? brho[i] : bacc[(size_t)i * c->dim + k - 1];
        over += !(diff <= b);
        worst = PetscMax(worst, diff / b);
      }
    }
    PetscCall(PetscFree2(brho, bacc));
    PetscCall(SpamSimDestroy(&rep));
    PetscCall(SpamSimDestroy(&def));
  }
  PetscCall(Check(t, over == 0, "%s: reproducible vs default RHS on one rank: largest |difference| / derived bound %.3g (%ld of %ld values over)", c->name, worst, over, (long)(N * w)));
  {
    long   drep = 0, ddef = 0;
    double rr = 0, ra = 0, dr = 0, da = 0;
    if (t->rank == 0) {
      drep = DiffBits(dist_rep, ref_rep, N, c->dim, &rr, &ra);
      ddef = DiffBits(dist_def, ref_def, N, c->dim, &dr, &da);
    }
    PetscCall(Check(t, drep == 0, "%s: reproducible RHS on %d ranks (1 thread) vs one rank, reversed order, 2 threads: %ld of %ld values differ bitwise", c->name, t->size, drep, (long)(N * w)));
    PetscCall(Check(t, ddef > 0, "%s: control, default RHS the same way: %ld of %ld values differ bitwise (largest: density %.2e, acceleration %.2e of the largest)", c->name, ddef, (long)(N * w), dr, da));
  }
  if (t->rank == 0) PetscCall(PetscFree2(ref_rep, ref_def));
  PetscCall(PetscFree2(dist_rep, dist_def));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- the norm ------ */
#define NORM_N 4099

static double NormX(PetscInt i) { uint64_t s = 1000003u * (uint64_t)i + 17; return (2.0 * TestUniform(&s) - 1.0) * pow(10.0, 6.0 * TestUniform(&s) - 3.0); }
static double NormW(PetscInt i) { uint64_t s = 999983u * (uint64_t)i + 5; return pow(10.0, 4.0 * TestUniform(&s) - 2.0); }

/* x and w of NORM_N components over comm with nlocal here (entry i of the whole vector is
 * NormX(i), NormW(i)); bad >= 0 replaces x at that global index with `value`. */
static PetscErrorCode MakeVectors(MPI_Comm comm, PetscInt nlocal, SUNContext sunctx, PetscInt bad, double value, Vec *X, Vec *W, N_Vector *x, N_Vector *w)
{
  PetscInt     lo, hi;
  PetscScalar *xa, *wa;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, nlocal, NORM_N, X));
  PetscCall(VecDuplicate(*X, W));
  PetscCall(VecGetOwnershipRange(*X, &lo, &hi));
  PetscCall(VecGetArrayWrite(*X, &xa));
  PetscCall(VecGetArrayWrite(*W, &wa));
  for (PetscInt i = lo; i < hi; i++) {
    xa[i - lo] = i == bad ? value : NormX(i);
    wa[i - lo] = NormW(i);
  }
  PetscCall(VecRestoreArrayWrite(*X, &xa));
  PetscCall(VecRestoreArrayWrite(*W, &wa));
  *x = N_VMake_Petsc(*X, sunctx);
  *w = N_VMake_Petsc(*W, sunctx);
  PetscCheck(*x && *w, comm, PETSC_ERR_LIB, "N_VMake_Petsc failed");
  PetscCheck(N_VEnableFusedOps_Petsc(*x, SUNTRUE) == 0, comm, PETSC_ERR_LIB, "N_VEnableFusedOps_Petsc failed");
  PetscCall(SpamErrorNormAttach(*x, SPAM_ERROR_NORM_RMS, PETSC_TRUE));
  PetscFunctionReturn(0);
}

static PetscErrorCode FreeVectors(Vec *X, Vec *W, N_Vector *x, N_Vector *w)
{
  PetscFunctionBeginUser;
  N_VDestroy(*x);
  N_VDestroy(*w);
  PetscCall(VecDestroy(X));
  PetscCall(VecDestroy(W));
  PetscFunctionReturn(0);
}

/* The reproducible and SUNDIALS' norms of the vector split with nlocal here. */
static PetscErrorCode Norms(MPI_Comm comm, PetscInt nlocal, SUNContext sunctx, PetscInt bad, double value, double nrm[2])
{
  Vec      X, W;
  N_Vector x, w;

  PetscFunctionBeginUser;
  PetscCall(MakeVectors(comm, nlocal, sunctx, bad, value, &X, &W, &x, &w));
  nrm[0] = N_VWrmsNorm(x, w);
  nrm[1] = N_VWrmsNorm_Petsc(x, w);
  PetscCall(FreeVectors(&X, &W, &x, &w));
  PetscFunctionReturn(0);
}

/* Whether every rank holds the same bits of v. */
static PetscErrorCode SameOnAllRanks(MPI_Comm comm, double v, int *same)
{
  double lo, hi;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&v, &lo, 1, MPI_DOUBLE, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(&v, &hi, 1, MPI_DOUBLE, MPI_MAX, comm));
  *same = (isnan(v) && isnan(lo) && isnan(hi)) || (!memcmp(&lo, &v, sizeof v) && !memcmp(&hi, &v, sizeof v));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckNorm(Ctx *t)
{
  SUNContext  sunctx;
  double      even[2], uneven[2], whole[2];
  long double exact = 0.0L;
  PetscInt    share, sum_before = 0;
  int         same[3];

  PetscFunctionBeginUser;
  PetscCheck(SUNContext_Create((void *)&t->comm, &sunctx) == 0, t->comm, PETSC_ERR_LIB, "SUNContext_Create failed");
  /* Uneven: rank r holds a share proportional to (r + 1)^2. */
  {
    const PetscInt total = (PetscInt)(t->size * (t->size + 1) * (2 * t->size + 1) / 6);
    for (int r = 0; r < t->rank; r++) sum_before += (PetscInt)(r + 1) * (r + 1);
    share = (NORM_N * (sum_before + (PetscInt)(t->rank + 1) * (t->rank + 1))) / total - (NORM_N * sum_before) / total;
  }
  PetscCall(Norms(t->comm, PETSC_DECIDE, sunctx, -1, 0.0, even));
  PetscCall(Norms(t->comm, share, sunctx, -1, 0.0, uneven));
  PetscCall(Norms(PETSC_COMM_SELF, NORM_N, sunctx, -1, 0.0, whole));
  for (PetscInt i = 0; i < NORM_N; i++) exact += (long double)(NormX(i) * NormW(i)) * (long double)(NormX(i) * NormW(i));
  exact = sqrtl(exact / NORM_N);
  PetscCall(SameOnAllRanks(t->comm, even[0], &same[0]));
  PetscCall(SameOnAllRanks(t->comm, uneven[0], &same[1]));
  PetscCall(SameOnAllRanks(t->comm, whole[0], &same[2]));
  PetscCall(Check(t, same[0] && same[1] && same[2] && !memcmp(&even[0], &whole[0], sizeof(double)) && !memcmp(&uneven[0], &whole[0], sizeof(double)),
                  "norm of %d components on %d ranks: reproducible %.17g split evenly, %.17g unevenly (rank 0 holds %ld), %.17g whole on one rank: the same bits on every rank (SUNDIALS' own: %.17g, %.17g, %.17g)",
                  NORM_N, t->size, even[0], uneven[0], (long)share, whole[0], even[1], uneven[1], whole[1]));
  if (t->size > 1) {
    const int differ = memcmp(&even[1], &whole[1], sizeof(double)) || memcmp(&uneven[1], &whole[1], sizeof(double));
    PetscCall(Check(t, differ, "control: SUNDIALS' own norm takes other bits for another split (%.17g, %.17g, %.17g)", even[1], uneven[1], whole[1]));
  }
  PetscCall(Check(t, fabs(whole[0] - (double)exact) <= 1e-12 * (double)exact, "reproducible norm %.17g within 1e-12 of the long-double sum %.17Lg (relative %.2e)", whole[0], exact, fabs(whole[0] - (double)exact) / (double)exact));
  /* A NaN and an overflow on the last rank only. */
  {
    double nan_n[2], inf_n[2];
    int    s0, s1;
    PetscCall(Norms(t->comm, PETSC_DECIDE, sunctx, NORM_N - 1, NAN, nan_n));
    PetscCall(Norms(t->comm, PETSC_DECIDE, sunctx, NORM_N - 1, 1e300, inf_n));
    PetscCall(SameOnAllRanks(t->comm, nan_n[0], &s0));
    PetscCall(SameOnAllRanks(t->comm, inf_n[0], &s1));
    PetscCall(Check(t, s0 && s1 && isnan(nan_n[0]) && isinf(inf_n[0]), "a NaN component on the last rank: norm %g on every rank; a component whose square overflows: %g on every rank", nan_n[0], inf_n[0]));
  }
  /* The operation survives SUNDIALS' cloning (the integrators' work vectors). */
  {
    Vec      X, W;
    N_Vector x, w, xc;
    PetscCall(MakeVectors(t->comm, PETSC_DECIDE, sunctx, -1, 0.0, &X, &W, &x, &w));
    xc = N_VClone(x);
    PetscCall(Check(t, xc->ops->nvwrmsnorm == SpamNVReproducibleWrmsNorm_Petsc && xc->ops->nvwrmsnormvectorarray == NULL, "a clone keeps the reproducible norm (and no fused array norm that would bypass it)"));
    N_VDestroy(xc);
    PetscCall(FreeVectors(&X, &W, &x, &w));
  }
  PetscCheck(SUNContext_Free(&sunctx) == 0, t->comm, PETSC_ERR_LIB, "SUNContext_Free failed");
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  Ctx        t = {{0, 0}, MPI_COMM_NULL, 0, 1};
  const Case cases[] = {
    {"2D Lucy, periodic 20^2, gamma 1.7", "lucy", 2, 20, 20.0, 3.0, 1.7, PETSC_TRUE, PETSC_FALSE},
    {"3D Wendland C2, periodic 9^3, unequal masses", "wendland_c2", 3, 9, 9.0, 2.2, 5.0 / 3.0, PETSC_TRUE, PETSC_TRUE},
    {"2D Lucy, open box, gamma 2 (no density pass)", "lucy", 2, 16, 18.0, 3.0, 2.0, PETSC_FALSE, PETSC_FALSE},
  };

  PetscCall(TestInitialize(&argc, &argv));
  t.comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_rank(t.comm, &t.rank));
  PetscCallMPI(MPI_Comm_size(t.comm, &t.size));
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) PetscCall(CheckCase(&t, &cases[k]));
  PetscCall(CheckNorm(&t));
  if (t.rank == 0) (void)TestFinish(&t.count);
  PetscCall(TestFinalize());
  return t.count.failed ? 1 : 0;
}
