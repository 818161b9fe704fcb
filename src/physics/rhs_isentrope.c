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
 * loop subtracts them from particle j in list order. The accelerations are interleaved
 * (a[j*dim + d]), so that each j's update touches one cache line, not dim of them: in
 * alternating runs this made the force pass 0.96-0.98 of its time with SoA arrays.
 * Particle i's own sum is a vector reduction in the first loop, so its rounding depends
 * on the vector width of the clone that runs (SPAM_CLONES below): deterministic for a
 * given binary and processor; test_pair_reference bounds it against a plain loop. */
#include <spam/sim.h>

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

SPAM_INLINE void DensityPass(const int dim, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, double *rho)
{
  const SpamImage im = SpamBoxImage(box);
  const double    wm = mass * k->wnorm; /* m w(0) */
  for (int i = 0; i < nl->n; i++) rho[i] = wm;
  for (int i = 0; i < nl->n; i++) {
    double ri = 0.0, ui[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) ui[d] = nl->u[d][i];
    for (int p0 = nl->start[i]; p0 < nl->start[i + 1]; p0 += SPAM_PAIR_CHUNK) {
      const int *nb = nl->nbr + p0, np = PetscMin(SPAM_PAIR_CHUNK, nl->start[i + 1] - p0);
      double     wj[SPAM_PAIR_CHUNK];
      if (nl->image[i]) DensityChunk(dim, 1, &im, nl, k, wm, ui, nb, np, wj);
      else DensityChunk(dim, 0, &im, nl, k, wm, ui, nb, np, wj);
      for (int c = 0; c < np; c++) {
        ri += wj[c];
        rho[nb[c]] += wj[c];
      }
    }
    rho[i] += ri;
  }
}

/* Pair terms f_ij r_ij of np listed neighbours nb of particle i (at ui, q_i = qi) into
 * fd, their sum into ai. f > 0 pushes i away from j for positive pressure. */
SPAM_INLINE void ForceChunk(const int dim, const int uniform, const int img, const SpamImage *im, const SpamNeighbours *nl, const SpamKernel *k, double coef, const double *q, double qi, const double *ui, const int *nb, int np, double fd[3][SPAM_PAIR_CHUNK], double *ai)
{
  const double cq = coef * (qi + qi);
  double       a0 = 0.0, a1 = 0.0, a2 = 0.0;
#pragma omp simd reduction(+ : a0, a1, a2)
  for (int c = 0; c < np; c++) {
    const double x = Delta(dim, img, im, nl, ui, nb[c], 0), y = Delta(dim, img, im, nl, ui, nb[c], 1), z = Delta(dim, img, im, nl, ui, nb[c], 2);
    double       t = 1.0 - sqrt(x * x + y * y + z * z) * k->hinv;
    t              = t > 0.0 ? t : 0.0;
    const double f = (uniform ? cq : coef * (qi + q[nb[c]])) * t * t;
    fd[0][c]       = f * x;
    a0 += fd[0][c];
    if (dim > 1) {
      fd[1][c] = f * y;
      a1 += fd[1][c];
    }
    if (dim > 2) {
      fd[2][c] = f * z;
      a2 += fd[2][c];
    }
  }
  ai[0] += a0;
  ai[1] += a1;
  ai[2] += a2;
}

SPAM_INLINE void ForcePass(const int dim, const int uniform, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, const double *q, double *acc)
{
  const SpamImage im   = SpamBoxImage(box);
  const double    coef = -mass * k->gnorm; /* -m (w'/r) / (1-s)^2 > 0 */
  for (size_t k = 0; k < (size_t)nl->n * dim; k++) acc[k] = 0.0;
  for (int i = 0; i < nl->n; i++) {
    double ai[3] = {0, 0, 0}, ui[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) ui[d] = nl->u[d][i];
    for (int p0 = nl->start[i]; p0 < nl->start[i + 1]; p0 += SPAM_PAIR_CHUNK) {
      const int *nb = nl->nbr + p0, np = PetscMin(SPAM_PAIR_CHUNK, nl->start[i + 1] - p0);
      double     fd[3][SPAM_PAIR_CHUNK];
      if (nl->image[i]) ForceChunk(dim, uniform, 1, &im, nl, k, coef, q, q[i], ui, nb, np, fd, ai);
      else ForceChunk(dim, uniform, 0, &im, nl, k, coef, q, q[i], ui, nb, np, fd, ai);
      for (int c = 0; c < np; c++) {
        double *aj = acc + (size_t)nb[c] * dim;
        aj[0] -= fd[0][c];
        if (dim > 1) aj[1] -= fd[1][c];
        if (dim > 2) aj[2] -= fd[2][c];
      }
    }
    for (int d = 0; d < dim; d++) acc[(size_t)i * dim + d] += ai[d];
  }
}

/* One loop for each of uniform and per-particle P/rho^2. */
SPAM_INLINE void ForcePassQ(const int dim, PetscBool uniform, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, const double *q, double *acc)
{
  if (uniform) ForcePass(dim, 1, nl, box, k, mass, q, acc);
  else ForcePass(dim, 0, nl, box, k, mass, q, acc);
}

/* The two passes below are compiled twice, for the x86-64 baseline (SSE2) and for AVX2,
 * and the loader picks the clone the processor runs (an ifunc): the binary stays
 * portable, and on the benchmark machine the AVX2 force pass took 0.87 of the SSE2
 * one's time. AVX-512 was no faster (rows hold ~13 pairs, so 8-wide loops are mostly
 * remainder) and FMA is not enabled: contracted products would round differently on
 * different machines. */
#define SPAM_CLONES __attribute__((target_clones("avx2", "default")))

/* Summation density of the current list into sim->rho (one loop per dimension). */
SPAM_CLONES static PetscErrorCode Density(SpamSim *sim)
{
  const SpamModel *m = &sim->model;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->ev.density, 0, 0, 0, 0));
  switch (m->dim) {
  case 1: DensityPass(1, &sim->nl, &sim->box, &m->kernel, m->mass, sim->rho); break;
  case 2: DensityPass(2, &sim->nl, &sim->box, &m->kernel, m->mass, sim->rho); break;
  default: DensityPass(3, &sim->nl, &sim->box, &m->kernel, m->mass, sim->rho); break;
  }
  PetscCall(PetscLogEventEnd(sim->ev.density, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Accelerations from sim->q = P/rho^2 into sim->acc. */
SPAM_CLONES static PetscErrorCode Force(SpamSim *sim)
{
  const SpamModel *m = &sim->model;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(sim->ev.force, 0, 0, 0, 0));
  switch (m->dim) {
  case 1: ForcePassQ(1, m->density_free, &sim->nl, &sim->box, &m->kernel, m->mass, sim->q, sim->acc); break;
  case 2: ForcePassQ(2, m->density_free, &sim->nl, &sim->box, &m->kernel, m->mass, sim->q, sim->acc); break;
  default: ForcePassQ(3, m->density_free, &sim->nl, &sim->box, &m->kernel, m->mass, sim->q, sim->acc); break;
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
  PetscCall(Density(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamAccelIsentrope(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  const SpamModel *m = &sim->model;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, x, stride, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  if (!m->density_free) {
    PetscCall(Density(sim));
    for (PetscInt i = 0; i < sim->n; i++) sim->q[i] = SpamEosPOverRho2(&m->eos, sim->rho[i]);
  }
  PetscCall(Force(sim));
  sim->stats.pair_visits += (double)sim->nl.npairs;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsIsentrope(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim, nv = l->nvar;

  PetscFunctionBeginUser;
  PetscCall(SpamAccelIsentrope(sim, y + l->x, nv, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->n; i++) {
    for (int d = 0; d < dim; d++) {
      ydot[(size_t)i * nv + l->x + d] = y[(size_t)i * nv + l->v + d];
      ydot[(size_t)i * nv + l->v + d] = sim->acc[(size_t)i * dim + d];
    }
  }
  PetscFunctionReturn(0);
}
