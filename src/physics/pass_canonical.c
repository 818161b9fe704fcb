/* The isentropic gas's density and force passes under -reproducible, over the canonical
 * rows of the neighbour list (neighbours_canonical.c): each local particle sums its own
 * terms in the order of its row, sorted by partner (gid, image), and writes only its own
 * value -- no Newton update of the partner, no fold of ghost shares, no thread buffers.
 * So rho_i and a_i are the same bits whichever rank holds each partner, whether the
 * partner is a local particle, a periodic image or another rank's particle, and whatever
 * -threads is (a row is one thread's). The pair terms are those of pair_density.h and
 * pair_pressure_force.h (the chunked passes' too), taken from i's side with the partner's
 * mass outside the kernel's scale (masses may differ):
 *   rho_i = m_i w(0) + sum_j m_j (wnorm F(s)),
 *   a_i   = sum_j m_j f_ij (u_i - u_j),  f_ij = (-gnorm (q_i + q_j)) G(s),  q = P/rho^2.
 * The cost: every pair is evaluated twice (once in each row) instead of once.
 * Compiled with -ffp-contract=off (CMakeLists.txt): the same roundings on every machine. */
#include <omp.h>
#include "../pair/pair_pass.h"
#include "../pair/pair_walk.h"
#include "../pair/pair_density.h"
#include "../pair/pair_pressure_force.h"

#define SPAM_INLINE static inline __attribute__((always_inline))
#define CHUNK       64

/* A row is taken in chunks of CHUNK entries: a first loop computes the pair terms of the
 * chunk with no store but to stack buffers, which the compiler vectorises (gathers of u_j,
 * m_j, q_j, a vector sqrt); a second, scalar loop adds them to particle i's sum in row
 * order. Each term is computed alone, so the vector width changes no bit of it, and the
 * sum's order is the row's.
 * Entries between h and the list range are added too, without a test: every kernel's F
 * and G are exactly zero for s >= 1 (kernel_shape.h), so their terms are +-0, and adding
 * a zero leaves a sum's bits alone unless the sum is -0 -- never here: the density starts
 * at m_i w(0) > 0, and an acceleration starts at +0, which +-0 keep at +0, and a nonzero
 * sum that cancels rounds to +0. So the result is the one of summing only the pairs
 * within h (the default passes' rule), without a branch that the list range's outer
 * shell (a sixth of the entries in 2D) would mispredict. */

/* The arrays a pass reads, as local pointers: the chunk loops are vectorised only when
 * they see plain arrays, not fields reached through the structures the OpenMP region
 * shares. */
typedef struct {
  const double *u0, *u1, *u2, *m, *q;
  const int    *start, *nbr;
  double        wnorm, gnorm, hinv;
} Arrays;

static inline Arrays ArraysOf(int dim, const SpamNeighbours *nl, const SpamKernel *k, const SpamFields *f)
{
  Arrays a = {nl->u[0], dim > 1 ? nl->u[1] : nl->u[0], dim > 2 ? nl->u[2] : nl->u[0], f->m, f->q, nl->cstart, nl->cnbr, k->wnorm, k->gnorm, k->hinv};
  return a;
}

/* m_j w_ij of the np entries nb of the row of a particle at (x0, x1, x2). */
SPAM_INLINE void DensityChunk(const int dim, const int kind, const Arrays *A, double x0, double x1, double x2, const int *restrict nb, int np, double *restrict t)
{
  const double *restrict u0 = A->u0, *restrict u1 = A->u1, *restrict u2 = A->u2, *restrict m = A->m;
  const double wnorm = A->wnorm, hinv = A->hinv;
#pragma omp simd
  for (int c = 0; c < np; c++) {
    const int    j = nb[c];
    const double x = x0 - u0[j], y = dim > 1 ? x1 - u1[j] : 0.0, z = dim > 2 ? x2 - u2[j] : 0.0;
    t[c]           = m[j] * SpamPairDensityTerm(kind, dim, wnorm, sqrt(x * x + y * y + z * z) * hinv);
  }
}

/* The force terms m_j c_ij (u_i - u_j) of the np entries nb of the row of a particle at
 * (x0, x1, x2) with q_i = qi. */
SPAM_INLINE void ForceChunk(const int dim, const int kind, const Arrays *A, double x0, double x1, double x2, double qi, const int *restrict nb, int np, double t[3][CHUNK])
{
  const double *restrict u0 = A->u0, *restrict u1 = A->u1, *restrict u2 = A->u2, *restrict m = A->m, *restrict q = A->q;
  const double gnorm = A->gnorm, hinv = A->hinv;
  double *restrict t0 = t[0], *restrict t1 = t[1], *restrict t2 = t[2];
#pragma omp simd
  for (int c = 0; c < np; c++) {
    const int    j = nb[c];
    const double x = x0 - u0[j], y = dim > 1 ? x1 - u1[j] : 0.0, z = dim > 2 ? x2 - u2[j] : 0.0;
    const double mc = m[j] * SpamPairPressureFactor(kind, dim, -gnorm, qi, q[j], sqrt(x * x + y * y + z * z) * hinv);
    t0[c]           = mc * x;
    if (dim > 1) t1[c] = mc * y;
    if (dim > 2) t2[c] = mc * z;
  }
}

/* Rows [i0, i1) of the density pass into rho. */
SPAM_INLINE void CanonDensityRows(const int dim, const int kind, const Arrays *A, double *rho, int i0, int i1)
{
  for (int i = i0; i < i1; i++) {
    const double x0 = A->u0[i], x1 = A->u1[i], x2 = A->u2[i];
    double       r  = A->m[i] * A->wnorm;
    for (int p0 = A->start[i]; p0 < A->start[i + 1]; p0 += CHUNK) {
      const int np = PetscMin(CHUNK, A->start[i + 1] - p0);
      double    t[CHUNK];
      DensityChunk(dim, kind, A, x0, x1, x2, A->nbr + p0, np, t);
      for (int c = 0; c < np; c++) r += t[c];
    }
    rho[i] = r;
  }
}

/* Rows [i0, i1) of the force pass into acc. */
SPAM_INLINE void CanonForceRows(const int dim, const int kind, const Arrays *A, double *acc, int i0, int i1)
{
  for (int i = i0; i < i1; i++) {
    const double x0 = A->u0[i], x1 = A->u1[i], x2 = A->u2[i];
    double       a[3] = {0.0, 0.0, 0.0};
    for (int p0 = A->start[i]; p0 < A->start[i + 1]; p0 += CHUNK) {
      const int np = PetscMin(CHUNK, A->start[i + 1] - p0);
      double    t[3][CHUNK];
      ForceChunk(dim, kind, A, x0, x1, x2, A->q[i], A->nbr + p0, np, t);
      for (int c = 0; c < np; c++) {
        a[0] += t[0][c];
        if (dim > 1) a[1] += t[1][c];
        if (dim > 2) a[2] += t[2][c];
      }
    }
    for (int d = 0; d < dim; d++) acc[(size_t)i * dim + d] = a[d];
  }
}

/* Compiled for the x86-64 baseline and for AVX2, as the chunked passes are (pass_chunked.c):
 * without contraction into FMA every lane rounds as the scalar code does, so both clones
 * give the same bits and a mixed cluster stays reproducible. The threads take blocks of
 * consecutive rows (rows are independent: any split gives the same bits); the dimension
 * and kernel are dispatched inside the parallel region, so that the loops the region runs
 * are compiled with them as literals. */
/* A parallel region cannot return an error: the kind is checked before it, so the
 * dispatch's unknown case inside it is never taken. */
static PetscErrorCode KnownKind(const SpamKernel *k)
{
  PetscFunctionBeginUser;
  PetscCheck(k->kind >= 0 && k->kind < SPAM_KERNEL_KINDS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the canonical passes have no kernel of kind %d (kernel_list.h lists %d)", (int)k->kind, (int)SPAM_KERNEL_KINDS);
  PetscFunctionReturn(0);
}

SPAM_CLONES PetscErrorCode SpamCanonicalDensity(const SpamPairPass *p)
{
  const SpamKernel *k = p->k;
  const Arrays      A = ArraysOf(k->dim, p->nl, k, p->f);
  const int         T = p->threads, n = p->n;
  double           *rho = p->f->rho;

  PetscFunctionBeginUser;
  PetscCall(KnownKind(k));
#pragma omp parallel if (T > 1) num_threads(T)
  {
    const int t = omp_get_thread_num(), i0 = (int)((size_t)n * t / T), i1 = (int)((size_t)n * (t + 1) / T);
    SPAM_WALK_DISPATCH(CanonDensity, k->dim, k->kind, break, &A, rho, i0, i1)
  }
  PetscFunctionReturn(0);
}

SPAM_CLONES PetscErrorCode SpamCanonicalForce(const SpamPairPass *p)
{
  const SpamKernel *k = p->k;
  const Arrays      A = ArraysOf(k->dim, p->nl, k, p->f);
  const int         T = p->threads, n = p->n;
  double           *acc = p->f->acc;

  PetscFunctionBeginUser;
  PetscCall(KnownKind(k));
#pragma omp parallel if (T > 1) num_threads(T)
  {
    const int t = omp_get_thread_num(), i0 = (int)((size_t)n * t / T), i1 = (int)((size_t)n * (t + 1) / T);
    SPAM_WALK_DISPATCH(CanonForce, k->dim, k->kind, break, &A, acc, i0, i1)
  }
  PetscFunctionReturn(0);
}
