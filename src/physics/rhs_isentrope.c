/* Right-hand side of the isentropic gas (Hoover & Hoover 2001, Eqs. 8 and 13):
 *   dr_i/dt = v_i,
 *   dv_i/dt = -m sum_j [(P/rho^2)_i + (P/rho^2)_j] grad_i w_ij.
 * With gamma = 2 the bracket is constant and the density pass is skipped (Eq. 20). Every
 * pair is visited once and updates both particles with opposite signs, so the total
 * momentum is conserved to round-off. Nothing here allocates.
 *
 * The pair loops run over each particle's neighbours in chunks of SPAM_PAIR_CHUNK: a first
 * loop, which has no stores but to a small stack buffer, computes the pair terms and is
 * vectorised by the compiler (gathers of u[j] and q[j], a vector sqrt); a second, scalar
 * loop subtracts them from particle j and adds them to particle i in list order. The
 * accelerations are interleaved (a[j*dim + d]), so that each j's update touches one cache
 * line, not dim of them: in alternating runs this made the force pass 0.96-0.98 of its
 * time with SoA arrays.
 * Particle i's own sum is taken in list order in the second loop, so its rounding does
 * not depend on the vector width of the clone that runs (SPAM_CLONES below);
 * test_pair_reference bounds it against a plain loop.
 *
 * These loops are written for Lucy's kernel, equal masses and no ghost slots but other
 * ranks' particles: the benchmark's case and every default run, on any number of ranks.
 * Any other kernel, unequal masses or periodic and mirror ghosts go through the pair
 * driver instead (pass_pressure.c: the same pair terms, one loop), and -reproducible
 * through the canonical rows (pass_canonical.c: each particle's own sum in an order fixed
 * by the partners' ids). */
#include <spam/sim.h>
#include <omp.h>

#define SPAM_PAIR_CHUNK 64

/* The parameters named const int below are literals at every call, so that each
 * combination is its own loop without branches: dim, uniform P/rho^2 (gamma = 2: q[j] is
 * not read) and img (the row's pairs may cross a periodic face: minimum image). */
#define SPAM_INLINE static inline __attribute__((always_inline))

/* Separation u_i - u_j of pair (i, j) along d (zero for d >= dim). Written without a
 * loop over d: gcc 12 keeps a local dx[3] indexed in a loop as memory and then does not
 * vectorise the pair loop. */
SPAM_INLINE double Delta(const int dim, const int img, const SpamImage *im, const SpamNeighbours *nl, const double *ui, int j, int d)
{
  if (d >= dim) return 0.0;
  const double dx = ui[d] - nl->u[d][j];
  return img ? SpamImageDelta(im, d, dx) : dx;
}

/* m w_ij of np listed neighbours nb of a particle at ui, into wj. */
SPAM_INLINE void DensityChunk(const int dim, const int img, const SpamImage *im, const SpamNeighbours *nl, const SpamKernel *k, double wm, const double *ui, const int *nb, int np, double *wj)
{
  for (int c = 0; c < np; c++) {
    const double x = Delta(dim, img, im, nl, ui, nb[c], 0), y = Delta(dim, img, im, nl, ui, nb[c], 1), z = Delta(dim, img, im, nl, ui, nb[c], 2);
    const double s = sqrt(x * x + y * y + z * z) * k->hinv;
    double       t = 1.0 - s;
    t              = t > 0.0 ? t : 0.0;
    wj[c]          = wm * (1.0 + 3.0 * s) * t * t * t;
  }
}

/* Rows [i0, i1) of the density pass, added to rho. */
SPAM_INLINE void DensityRows(const int dim, const SpamNeighbours *nl, const SpamImage *im, const SpamKernel *k, double wm, double *rho, int i0, int i1)
{
  for (int i = i0; i < i1; i++) {
    double ri = 0.0, ui[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) ui[d] = nl->u[d][i];
    for (int p0 = nl->start[i]; p0 < nl->start[i + 1]; p0 += SPAM_PAIR_CHUNK) {
      const int *nb = nl->nbr + p0, np = PetscMin(SPAM_PAIR_CHUNK, nl->start[i + 1] - p0);
      double     wj[SPAM_PAIR_CHUNK];
      if (nl->image[i]) DensityChunk(dim, 1, im, nl, k, wm, ui, nb, np, wj);
      else DensityChunk(dim, 0, im, nl, k, wm, ui, nb, np, wj);
      for (int c = 0; c < np; c++) {
        ri += wj[c];
        rho[nb[c]] += wj[c];
      }
    }
    /* Other ranks' particles (remote ghosts): particle i's share only, the owner computes
     * its own (newton off across ranks; ghosts.h). */
    for (int p0 = nl->gstart[i]; p0 < nl->gstart[i + 1]; p0 += SPAM_PAIR_CHUNK) {
      const int *nb = nl->gnbr + p0, np = PetscMin(SPAM_PAIR_CHUNK, nl->gstart[i + 1] - p0);
      double     wj[SPAM_PAIR_CHUNK];
      if (nl->image[i]) DensityChunk(dim, 1, im, nl, k, wm, ui, nb, np, wj);
      else DensityChunk(dim, 0, im, nl, k, wm, ui, nb, np, wj);
      for (int c = 0; c < np; c++) ri += wj[c];
    }
    rho[i] += ri;
  }
}

/* Pair terms f_ij r_ij of np listed neighbours nb of particle i (at ui, q_i = qi) into
 * fd. f > 0 pushes i away from j for positive pressure. The loop only stores: particle i's
 * sum is taken in the scatter loop (ForceRows), because gcc 12 made this loop's vector
 * reduction an epilogue of eight serial adds per component, reloaded from the stack, for
 * rows of about 13 pairs: 18% of the force pass's samples (perf annotate, N = 16384). */
SPAM_INLINE void ForceChunk(const int dim, const int uniform, const int img, const SpamImage *im, const SpamNeighbours *nl, const SpamKernel *k, double coef, const double *q, double qi, const double *ui, const int *nb, int np, double fd[3][SPAM_PAIR_CHUNK])
{
  const double cq = coef * (qi + qi);
#pragma omp simd
  for (int c = 0; c < np; c++) {
    const double x = Delta(dim, img, im, nl, ui, nb[c], 0), y = Delta(dim, img, im, nl, ui, nb[c], 1), z = Delta(dim, img, im, nl, ui, nb[c], 2);
    double       t = 1.0 - sqrt(x * x + y * y + z * z) * k->hinv;
    t              = t > 0.0 ? t : 0.0;
    const double f = (uniform ? cq : coef * (qi + q[nb[c]])) * t * t;
    fd[0][c]       = f * x;
    if (dim > 1) fd[1][c] = f * y;
    if (dim > 2) fd[2][c] = f * z;
  }
}

/* Rows [i0, i1) of the force pass, added to acc. */
SPAM_INLINE void ForceRows(const int dim, const int uniform, const SpamNeighbours *nl, const SpamImage *im, const SpamKernel *k, double coef, const double *q, double *acc, int i0, int i1)
{
  for (int i = i0; i < i1; i++) {
    double ai[3] = {0, 0, 0}, ui[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) ui[d] = nl->u[d][i];
    for (int p0 = nl->start[i]; p0 < nl->start[i + 1]; p0 += SPAM_PAIR_CHUNK) {
      const int *nb = nl->nbr + p0, np = PetscMin(SPAM_PAIR_CHUNK, nl->start[i + 1] - p0);
      double     fd[3][SPAM_PAIR_CHUNK];
      if (nl->image[i]) ForceChunk(dim, uniform, 1, im, nl, k, coef, q, q[i], ui, nb, np, fd);
      else ForceChunk(dim, uniform, 0, im, nl, k, coef, q, q[i], ui, nb, np, fd);
      for (int c = 0; c < np; c++) {
        double *aj = acc + (size_t)nb[c] * dim;
        aj[0] -= fd[0][c];
        ai[0] += fd[0][c];
        if (dim > 1) {
          aj[1] -= fd[1][c];
          ai[1] += fd[1][c];
        }
        if (dim > 2) {
          aj[2] -= fd[2][c];
          ai[2] += fd[2][c];
        }
      }
    }
    for (int p0 = nl->gstart[i]; p0 < nl->gstart[i + 1]; p0 += SPAM_PAIR_CHUNK) { /* remote ghosts: i's share */
      const int *nb = nl->gnbr + p0, np = PetscMin(SPAM_PAIR_CHUNK, nl->gstart[i + 1] - p0);
      double     fd[3][SPAM_PAIR_CHUNK];
      if (nl->image[i]) ForceChunk(dim, uniform, 1, im, nl, k, coef, q, q[i], ui, nb, np, fd);
      else ForceChunk(dim, uniform, 0, im, nl, k, coef, q, q[i], ui, nb, np, fd);
      for (int c = 0; c < np; c++)
        for (int d = 0; d < dim; d++) ai[d] += fd[d][c];
    }
    for (int d = 0; d < dim; d++) acc[(size_t)i * dim + d] += ai[d];
  }
}

/* One block of rows of a pass: thread t of the pass's T sums rows [i0, i1) into its own
 * buffer, which it zeroes first (thread 0's is the output itself). One loop for each
 * dimension and, in the force pass, for uniform and per-particle P/rho^2. */
SPAM_INLINE void DensityBlock(const SpamSim *sim, double *rho, int i0, int i1, int t)
{
  const SpamModel *m  = &sim->model;
  const SpamImage  im = sim->nl.im;
  const double     wm = m->mass * m->kernel.wnorm; /* m w(0) */
  for (PetscInt i = 0; i < sim->n; i++) rho[i] = t == 0 ? wm : 0.0;
  switch (m->dim) {
  case 1: DensityRows(1, &sim->nl, &im, &m->kernel, wm, rho, i0, i1); break;
  case 2: DensityRows(2, &sim->nl, &im, &m->kernel, wm, rho, i0, i1); break;
  default: DensityRows(3, &sim->nl, &im, &m->kernel, wm, rho, i0, i1); break;
  }
}

SPAM_INLINE void ForceBlock(const SpamSim *sim, double *acc, int i0, int i1)
{
  const SpamModel *m    = &sim->model;
  const SpamImage  im   = sim->nl.im;
  const double     coef = -m->mass * m->kernel.gnorm; /* -m (w'/r) / (1-s)^2 > 0 */
  const int        u    = m->density_free;
  for (size_t k = 0; k < (size_t)sim->n * m->dim; k++) acc[k] = 0.0;
#define SPAM_FORCE_ROWS(D, U) ForceRows(D, U, &sim->nl, &im, &m->kernel, coef, sim->f.q, acc, i0, i1)
  switch (m->dim) {
  case 1: u ? SPAM_FORCE_ROWS(1, 1) : SPAM_FORCE_ROWS(1, 0); break;
  case 2: u ? SPAM_FORCE_ROWS(2, 1) : SPAM_FORCE_ROWS(2, 0); break;
  default: u ? SPAM_FORCE_ROWS(3, 1) : SPAM_FORCE_ROWS(3, 0); break;
  }
#undef SPAM_FORCE_ROWS
}

/* The two passes below are compiled twice, for the x86-64 baseline (SSE2) and for AVX2,
 * and the loader picks the clone the processor runs (an ifunc): the binary stays
 * portable, and on the benchmark machine the AVX2 force pass took 0.87 of the SSE2
 * one's time. AVX-512 was no faster (rows hold ~13 pairs, so 8-wide loops are mostly
 * remainder) and FMA is not enabled: contracted products would round differently on
 * different machines.
 *
 * With -threads T > 1 the rows are split into T blocks of about equal pair counts, and
 * each thread sums its block into its own buffer (thread 0 into the output, the others
 * into sim->tacc or sim->trho); the buffers are then added in thread order. No two
 * threads write one address, and every sum is taken in an order fixed by the list and
 * T alone, so the results are the same run to run (and differ from T = 1 only by the
 * order of the additions). */
#define SPAM_CLONES __attribute__((target_clones("avx2", "default")))

/* Adds the T - 1 scratch buffers of len values to out, in thread order (inside a parallel
 * region: the values are shared out among the threads). */
static inline void AddThreadBuffers(double *out, const double *scratch, size_t len, int T)
{
#pragma omp for schedule(static)
  for (size_t k = 0; k < len; k++)
    for (int s = 1; s < T; s++) out[k] += scratch[(size_t)(s - 1) * len + k];
}

/* Whether the chunked loops apply (see the top of this file): no ghost slots but other
 * ranks' particles, whose pairs the loops walk for the local particle only. Not with
 * walls: another rank's particle may come as a mirror image, whose slot must take the
 * pair's reaction for the walls' books, and the books must be made at every pass. */
static PetscBool FastPath(const SpamSim *sim)
{
  return (PetscBool)(sim->model.kernel.kind == SPAM_KERNEL_LUCY && sim->f.uniform_mass && sim->nl.ghosts.nlocal == 0 && !sim->nl.ghosts.mirror);
}

/* Room for the ghost slots of the current list in the fields (grows only when a list
 * build found more ghosts than ever before), and their masses after a build. */
static PetscErrorCode ReserveSlots(SpamSim *sim)
{
  PetscFunctionBeginUser;
  PetscCall(SpamFieldsReserve(&sim->f, SpamNeighboursSlots(&sim->nl)));
  PetscCall(SpamSimGhostMasses(sim));
  PetscFunctionReturn(0);
}

/* Summation density of the current list into sim->f.rho. */
SPAM_CLONES static PetscErrorCode Density(SpamSim *sim)
{
  const int T = sim->threads;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->ev.density, 0, 0, 0, 0));
  if (SpamNeighboursCanonical(&sim->nl)) PetscCall(SpamCanonicalDensity(sim)); /* -reproducible */
  else if (!FastPath(sim)) PetscCall(SpamPressureDensityWalk(sim));
  else if (T == 1) DensityBlock(sim, sim->f.rho, 0, sim->nl.n, 0);
  else {
#pragma omp parallel num_threads(T)
    {
      const int t = omp_get_thread_num();
      int       rows[2];
      SpamNeighboursSplitRows(&sim->nl, T, t, rows);
      DensityBlock(sim, t == 0 ? sim->f.rho : sim->trho + (size_t)(t - 1) * sim->n, rows[0], rows[1], t);
#pragma omp barrier
      AddThreadBuffers(sim->f.rho, sim->trho, (size_t)sim->n, T);
    }
  }
  PetscCall(PetscLogEventEnd(sim->ev.density, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Accelerations from sim->f.q = P/rho^2 into sim->f.acc. */
SPAM_CLONES static PetscErrorCode Force(SpamSim *sim)
{
  const int    T   = sim->threads;
  const size_t len = (size_t)sim->n * sim->model.dim;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->ev.force, 0, 0, 0, 0));
  if (SpamNeighboursCanonical(&sim->nl)) PetscCall(SpamCanonicalForce(sim)); /* -reproducible */
  else if (!FastPath(sim)) PetscCall(SpamPressureForceWalk(sim));
  else if (T == 1) ForceBlock(sim, sim->f.acc, 0, sim->nl.n);
  else {
#pragma omp parallel num_threads(T)
    {
      const int t = omp_get_thread_num();
      int       rows[2];
      SpamNeighboursSplitRows(&sim->nl, T, t, rows);
      ForceBlock(sim, t == 0 ? sim->f.acc : sim->tacc + (size_t)(t - 1) * len, rows[0], rows[1]);
#pragma omp barrier
      AddThreadBuffers(sim->f.acc, sim->tacc, len, T);
    }
  }
  PetscCall(PetscLogEventEnd(sim->ev.force, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDensitySummation(SpamSim *sim, const double *y, PetscInt *bad)
{
  const SpamLayout *l = &sim->model.layout;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, y + l->x, l->nvar, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  PetscCall(ReserveSlots(sim));
  PetscCall(Density(sim));
  /* The callers (the tensor path, diagnostics) read the ghosts' densities too; the pair
   * driver has gathered them, the chunked loops (other ranks' particles only) and the
   * canonical passes have not. The gather is a collective on several ranks, and whether a
   * rank's own loops are the chunked ones depends on its own local ghosts: each rank makes
   * exactly one gather here or in the pair driver, even a rank without ghosts. */
  if (SpamNeighboursCanonical(&sim->nl) || (FastPath(sim) && (sim->nl.ghosts.n || SpamSimDistributed(sim))))
    PetscCall(SpamGhostsGather(&sim->nl.ghosts, sim->model.dim, (int)sim->n, 1, SPAM_GHOST_SCALAR, sim->f.rho));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamAccelIsentrope(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  const SpamModel *m = &sim->model;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, x, stride, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  PetscCall(ReserveSlots(sim));
  if (!m->density_free) { /* gamma = 2: P/rho^2 is the same constant everywhere, ghosts included (ReserveSlots) */
    PetscCall(Density(sim));
    for (PetscInt i = 0; i < sim->n; i++) sim->f.q[i] = SpamEosPOverRho2(&m->eos, sim->f.rho[i]);
    PetscCall(SpamGhostsGather(&sim->nl.ghosts, m->dim, (int)sim->n, 1, SPAM_GHOST_SCALAR, sim->f.q));
  }
  PetscCall(Force(sim));
  if (m->gravity_on)
    for (PetscInt i = 0; i < sim->n; i++)
      for (int d = 0; d < m->dim; d++) sim->f.acc[(size_t)i * m->dim + d] += m->gravity[d];
  /* Canonical rows list every pair twice, once in each particle's row. */
  sim->stats.pair_visits += SpamNeighboursCanonical(&sim->nl) ? (double)sim->nl.ncpairs : (double)(sim->nl.npairs + sim->nl.ngpairs);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsIsentrope(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim, nv = l->nvar;

  PetscFunctionBeginUser;
  PetscCall(SpamAccelIsentrope(sim, y + l->x, nv, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
#pragma omp parallel for if (sim->threads > 1) num_threads(sim->threads) schedule(static)
  for (PetscInt i = 0; i < sim->n; i++) {
    for (int d = 0; d < dim; d++) {
      ydot[(size_t)i * nv + l->x + d] = y[(size_t)i * nv + l->v + d];
      ydot[(size_t)i * nv + l->v + d] = sim->f.acc[(size_t)i * dim + d];
    }
  }
  PetscFunctionReturn(0);
}
