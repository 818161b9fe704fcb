/* The isentropic gas's density and force passes over the half list (pass context:
 * pair_pass.h), for every kernel of kernels/kernel_list.h: the chunked, vectorised rows.
 * Every pair is visited once and updates both particles with opposite signs, so the total
 * momentum is conserved to round-off. Nothing here allocates.
 *
 * A row is taken in chunks of CHUNK pairs: a first loop, which has no stores but to a small
 * stack buffer, computes the pair terms of pair_density.h and pair_pressure_force.h and is
 * vectorised by the compiler (gathers of u[j] and q[j], a vector sqrt); a second, scalar
 * loop subtracts them from particle j and adds them to particle i in list order. The
 * accelerations are interleaved (a[j*dim + d]), so that each j's update touches one cache
 * line, not dim of them: in alternating runs this made the force pass 0.96-0.98 of its
 * time with SoA arrays. Particle i's own sum is taken in list order in the second loop, so
 * its rounding does not depend on the vector width of the clone that runs (SPAM_CLONES
 * below); test_pair_reference bounds it against a plain loop and the other traversals.
 *
 * A ghost neighbour (the row's second segment) is another rank's particle, whose owner
 * computes its own share (newton off across ranks; ghosts.h), or, with periodic images or
 * mirror walls on this rank, a local ghost slot that takes the pair's reaction like a local
 * particle: the slots are then folded onto their sources, the mirrors' kept for the walls'
 * books, and the pass is one thread's (the thread buffers hold the local particles). */
#include <omp.h>
#include "../pair/pair_pass.h"
#include "../pair/pair_density.h"
#include "../pair/pair_pressure_force.h"

#define CHUNK 64

/* The parameters named const int below are literals at every call, so that each
 * combination is its own loop without branches: dim, the kernel kind, equal masses (uni:
 * the mass is folded into the law's scale), uniform P/rho^2 (uq, gamma = 2: q[j] is not
 * read) and img (the row's pairs may cross a periodic face: minimum image). */
#define SPAM_INLINE static inline __attribute__((always_inline))

/* What the rows read, as local values: the law's scale c (pair_density.h,
 * pair_pressure_force.h) and the list. */
typedef struct {
  const SpamNeighbours *nl;
  SpamImage             im;
  double                c, hinv;
  const double         *m, *q;
  int                   newton; /* ghost slots take the reaction */
  /* The list's arrays, copied here so that the rows' loops hold them in registers: read
   * through nl they were loaded again after every store to acc or rho, which may alias
   * the list's struct (about 8 loads a row). */
  const double         *u[3];
  const int            *start, *nbr, *gstart, *gnbr;
  const unsigned char  *image;
  int                   ghosts; /* the list has ghost rows (else every ghost segment is empty) */
} Rows;

/* Separation u_i - u_j of pair (i, j) along d (zero for d >= dim). Written without a
 * loop over d: gcc 12 keeps a local dx[3] indexed in a loop as memory and then does not
 * vectorise the pair loop. */
SPAM_INLINE double Delta(const int dim, const int img, const Rows *R, const double *ui, int j, int d)
{
  if (d >= dim) return 0.0;
  const double dx = ui[d] - R->u[d][j];
  return img ? SpamImageDelta(&R->im, d, dx) : dx;
}

/* np pair terms rounded up to whole vectors of SPAM_LIST_PAD: the chunk loops compute the
 * extra lanes from the list's next entries or its padding, and the scatter loops ignore
 * them. A loop of whole vectors needs no scalar remainder (about 40% of the instructions
 * of a row's terms at 13 pairs a row), and fewer values stay live around it. */
SPAM_INLINE int Lanes(int np)
{
  return (np + SPAM_LIST_PAD - 1) & -SPAM_LIST_PAD;
}

/* The squared distance x^2 + y^2 + z^2 of a pair. The directions the box lacks (zero
 * separations) are left out, not added: a sum of squares is +0 or more, and adding +0
 * leaves it as it is, bit for bit. */
SPAM_INLINE double Dist2(const int dim, double x, double y, double z)
{
  return dim == 1 ? x * x : dim == 2 ? x * x + y * y : x * x + y * y + z * z;
}

/* The density terms c F(s) of np listed neighbours nb of a particle at ui, into wj. */
SPAM_INLINE void DensityChunk(const int dim, const int kind, const int img, const Rows *R, const double *ui, const int *nb, int np, double *wj)
{
  for (int c = 0; c < np; c++) {
    const double x = Delta(dim, img, R, ui, nb[c], 0), y = Delta(dim, img, R, ui, nb[c], 1), z = Delta(dim, img, R, ui, nb[c], 2);
    wj[c]          = SpamPairDensityTerm(kind, dim, R->c, sqrt(Dist2(dim, x, y, z)) * R->hinv);
  }
}

/* One segment of row i (its local or its ghost neighbours): its terms added to rho[j]
 * where the partner takes the reaction; returns ri plus particle i's terms. */
SPAM_INLINE double DensitySegment(const int dim, const int kind, const int uni, const int img, const int newton, const Rows *R, int i, const double *ui, const int *nbr, int p0, int p1, double *rho, double ri)
{
  const double mi = uni ? 1.0 : R->m[i];
  for (; p0 < p1; p0 += CHUNK) {
    const int *nb = nbr + p0, np = PetscMin(CHUNK, p1 - p0);
    double     wj[CHUNK];
    DensityChunk(dim, kind, img, R, ui, nb, Lanes(np), wj);
    if (uni && newton)
      for (int c = 0; c < np; c++) {
        ri += wj[c];
        rho[nb[c]] += wj[c];
      }
    else if (uni)
      for (int c = 0; c < np; c++) ri += wj[c];
    else
      for (int c = 0; c < np; c++) {
        ri += R->m[nb[c]] * wj[c];
        if (newton) rho[nb[c]] += mi * wj[c];
      }
  }
  return ri;
}

/* Rows [i0, i1) of the density pass, added to rho. */
SPAM_INLINE void DensityRows(const int dim, const int kind, const int uni, const Rows *R, double *rho, int i0, int i1)
{
  for (int i = i0; i < i1; i++) {
    double ri = 0.0, ui[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) ui[d] = R->u[d][i];
    if (R->image[i]) {
      ri = DensitySegment(dim, kind, uni, 1, 1, R, i, ui, R->nbr, R->start[i], R->start[i + 1], rho, ri);
      if (R->ghosts) ri = R->newton ? DensitySegment(dim, kind, uni, 1, 1, R, i, ui, R->gnbr, R->gstart[i], R->gstart[i + 1], rho, ri)
                                    : DensitySegment(dim, kind, uni, 1, 0, R, i, ui, R->gnbr, R->gstart[i], R->gstart[i + 1], rho, ri);
    } else {
      ri = DensitySegment(dim, kind, uni, 0, 1, R, i, ui, R->nbr, R->start[i], R->start[i + 1], rho, ri);
      if (R->ghosts) ri = R->newton ? DensitySegment(dim, kind, uni, 0, 1, R, i, ui, R->gnbr, R->gstart[i], R->gstart[i + 1], rho, ri)
                                    : DensitySegment(dim, kind, uni, 0, 0, R, i, ui, R->gnbr, R->gstart[i], R->gstart[i + 1], rho, ri);
    }
    rho[i] += ri;
  }
}

/* The force terms f (u_i - u_j) of np listed neighbours nb of particle i (at ui, q_i = qi)
 * into fd. f > 0 pushes i away from j for positive pressure. The loop only stores:
 * particle i's sum is taken in the scatter loop, because gcc 12 made this loop's vector
 * reduction an epilogue of eight serial adds per component, reloaded from the stack, for
 * rows of about 13 pairs: 18% of the force pass's samples (perf annotate, N = 16384). */
SPAM_INLINE void ForceChunk(const int dim, const int kind, const int uq, const int img, const Rows *R, double qi, const double *ui, const int *nb, int np, double fd[3][CHUNK])
{
  const double *q = R->q;
#pragma omp simd
  for (int c = 0; c < np; c++) {
    const double x = Delta(dim, img, R, ui, nb[c], 0), y = Delta(dim, img, R, ui, nb[c], 1), z = Delta(dim, img, R, ui, nb[c], 2);
    const double f = SpamPairPressureFactor(kind, dim, R->c, qi, uq ? qi : q[nb[c]], sqrt(Dist2(dim, x, y, z)) * R->hinv);
    fd[0][c]       = f * x;
    if (dim > 1) fd[1][c] = f * y;
    if (dim > 2) fd[2][c] = f * z;
  }
}

/* Two doubles as one SSE2 register: the x and y of a 2D pair term, its partner's sum. */
typedef double Pair2 __attribute__((vector_size(16)));

/* The scatter of np terms fd of equal masses in 2D, the reaction taken: x and y as one
 * pair of lanes, so each term is one load, one add to particle i's sum s and one
 * subtraction from acc[j] (the same roundings, lane by lane, as two scalar sums): 13
 * instructions a pair instead of 15. */
SPAM_INLINE Pair2 Scatter2One(const int *nb, int c, const double fd[3][CHUNK], double *acc, Pair2 s)
{
  const Pair2 f = {fd[0][c], fd[1][c]};
  Pair2       a;
  double     *aj = acc + (size_t)nb[c] * 2;
  __builtin_memcpy(&a, aj, sizeof a);
  a -= f;
  __builtin_memcpy(aj, &a, sizeof a);
  return s + f;
}

SPAM_INLINE Pair2 Scatter2(const int *nb, int np, const double fd[3][CHUNK], double *acc, Pair2 s)
{
  int c = 0;
  for (; c + 2 <= np; c += 2) {
    s = Scatter2One(nb, c, fd, acc, s);
    s = Scatter2One(nb, c + 1, fd, acc, s);
  }
  if (c < np) s = Scatter2One(nb, c, fd, acc, s);
  return s;
}

/* One segment of row i: its terms subtracted from acc[j] where the partner takes the
 * reaction, and added to particle i's sum a (one variable per direction: an array here
 * was kept in memory). */
SPAM_INLINE void ForceSegment(const int dim, const int kind, const int uni, const int uq, const int img, const int newton, const Rows *R, int i, const double *ui, const int *nbr, int p0, int p1, double *acc, double *a0, double *a1, double *a2)
{
  const double mi = uni ? 1.0 : R->m[i];
  double       s0 = *a0, s1 = *a1, s2 = *a2;
  for (; p0 < p1; p0 += CHUNK) {
    const int *nb = nbr + p0, np = PetscMin(CHUNK, p1 - p0);
    double     fd[3][CHUNK];
    ForceChunk(dim, kind, uq, img, R, R->q[i], ui, nb, Lanes(np), fd);
    if (dim == 2 && uni && newton) {
      Pair2 sp = {s0, s1};
      sp       = Scatter2(nb, np, (const double(*)[CHUNK])fd, acc, sp);
      s0       = sp[0];
      s1       = sp[1];
      continue;
    }
    for (int c = 0; c < np; c++) {
      double      *aj = acc + (size_t)nb[c] * dim;
      const double mj = uni ? 1.0 : R->m[nb[c]];
      if (newton) aj[0] -= uni ? fd[0][c] : mi * fd[0][c];
      s0 += uni ? fd[0][c] : mj * fd[0][c];
      if (dim > 1) {
        if (newton) aj[1] -= uni ? fd[1][c] : mi * fd[1][c];
        s1 += uni ? fd[1][c] : mj * fd[1][c];
      }
      if (dim > 2) {
        if (newton) aj[2] -= uni ? fd[2][c] : mi * fd[2][c];
        s2 += uni ? fd[2][c] : mj * fd[2][c];
      }
    }
  }
  *a0 = s0;
  *a1 = s1;
  *a2 = s2;
}

/* Rows [i0, i1) of the force pass, added to acc; newton (the ghost slots take the
 * reaction) a literal too: tested in the row loop it cost about 3 instructions a row,
 * 0.5 % of the pass (callgrind, gas N = 16384). The rows read a local copy of *Rp: a
 * store to acc may alias the doubles behind the pointer, and with the pointer the
 * compiler kept more values on the stack around the pair loop (callgrind, gas h = 3,
 * N = 16384: 0.9 % of the RHS's instructions). */
SPAM_INLINE void ForceRows(const int dim, const int kind, const int uni, const int uq, const int newton, const Rows *Rp, double *acc, int i0, int i1)
{
  const Rows L = *Rp, *R = &L;
  for (int i = i0; i < i1; i++) {
    double a0 = 0.0, a1 = 0.0, a2 = 0.0, ui[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) ui[d] = R->u[d][i];
#define SPAM_FORCE_SEGMENT(IMG, NEWTON, nbr, start) ForceSegment(dim, kind, uni, uq, IMG, NEWTON, R, i, ui, R->nbr, R->start[i], R->start[i + 1], acc, &a0, &a1, &a2)
    if (R->image[i]) {
      SPAM_FORCE_SEGMENT(1, 1, nbr, start);
      if (R->ghosts) SPAM_FORCE_SEGMENT(1, newton, gnbr, gstart);
    } else {
      SPAM_FORCE_SEGMENT(0, 1, nbr, start);
      if (R->ghosts) SPAM_FORCE_SEGMENT(0, newton, gnbr, gstart);
    }
#undef SPAM_FORCE_SEGMENT
    acc[(size_t)i * dim] += a0;
    if (dim > 1) acc[(size_t)i * dim + 1] += a1;
    if (dim > 2) acc[(size_t)i * dim + 2] += a2;
  }
}

/* The dispatch's per-kernel bodies: equal or unequal masses, and for the force uniform or
 * per-particle P/rho^2 and whether the ghost slots take the reaction, as literals. */
SPAM_INLINE void DensityKindRows(const int dim, const int kind, const Rows *R, int uni, double *rho, int i0, int i1)
{
  if (uni) DensityRows(dim, kind, 1, R, rho, i0, i1);
  else DensityRows(dim, kind, 0, R, rho, i0, i1);
}

SPAM_INLINE void ForceNewtonRows(const int dim, const int kind, const int uni, const int uq, const Rows *R, double *acc, int i0, int i1)
{
  if (R->newton) ForceRows(dim, kind, uni, uq, 1, R, acc, i0, i1);
  else ForceRows(dim, kind, uni, uq, 0, R, acc, i0, i1);
}

SPAM_INLINE void ForceKindRows(const int dim, const int kind, const Rows *R, int uni, int uq, double *acc, int i0, int i1)
{
  if (uni && uq) ForceNewtonRows(dim, kind, 1, 1, R, acc, i0, i1);
  else if (uni) ForceNewtonRows(dim, kind, 1, 0, R, acc, i0, i1);
  else if (uq) ForceNewtonRows(dim, kind, 0, 1, R, acc, i0, i1);
  else ForceNewtonRows(dim, kind, 0, 0, R, acc, i0, i1);
}

static Rows RowsOf(const SpamPairPass *p, double c)
{
  const SpamNeighbours *nl = p->nl;
  Rows                  R  = {nl, nl->im, c, p->k->hinv, p->f->m, p->f->q, p->ghost_newton, {nl->u[0], nl->u[1], nl->u[2]}, nl->start, nl->nbr, nl->gstart, nl->gnbr, nl->image, nl->ngpairs > 0};
  return R;
}

/* The rows of one dimension and kernel are one function each, compiled twice, for the
 * x86-64 baseline (SSE2) and for AVX2, and the loader picks the clone the processor runs
 * (an ifunc): the binary stays portable, and on the benchmark machine the AVX2 force pass
 * took 0.87 of the SSE2 one's time. AVX-512 was no faster (rows hold ~13 pairs, so 8-wide
 * loops are mostly remainder) and FMA is not enabled: contracted products would round
 * differently on different machines. (All dimensions and kernels in one function made it
 * too large for gcc to optimise as well: its force pass took 1.07-1.12 of the time of this
 * split, perf samples at N = 65536.) The tables below hold them by kind (kernel_list.h's
 * row order is the kinds' order) and dimension. SPAM_CLONES: src/pair/pair_pass.h. */
typedef void (*DensityRowsFn)(const Rows *R, int uni, double *rho, int i0, int i1);
typedef void (*ForceRowsFn)(const Rows *R, int uni, int uq, double *acc, int i0, int i1);
#ifdef SPAM_ONE_KERNEL_COPY
/* The sanitizer build: the rows once per dimension, the kind a value known at run time, as
 * the pair walks there (src/pair/pair_walk.h says why); the table's entries call them. */
#define SPAM_ROWS_ANY_KIND(D) \
  static __attribute__((noinline)) void DensityAnyKind##D(int kind, const Rows *R, int uni, double *rho, int i0, int i1) \
  { \
    DensityKindRows(D, kind, R, uni, rho, i0, i1); \
  } \
  static __attribute__((noinline)) void ForceAnyKind##D(int kind, const Rows *R, int uni, int uq, double *acc, int i0, int i1) \
  { \
    ForceKindRows(D, kind, R, uni, uq, acc, i0, i1); \
  }
SPAM_ROWS_ANY_KIND(1)
SPAM_ROWS_ANY_KIND(2)
SPAM_ROWS_ANY_KIND(3)
#define SPAM_ROWS_DIM(Prefix, D, KIND) \
  static void Density##D##Prefix(const Rows *R, int uni, double *rho, int i0, int i1) \
  { \
    DensityAnyKind##D(SPAM_KERNEL_##KIND, R, uni, rho, i0, i1); \
  } \
  static void Force##D##Prefix(const Rows *R, int uni, int uq, double *acc, int i0, int i1) \
  { \
    ForceAnyKind##D(SPAM_KERNEL_##KIND, R, uni, uq, acc, i0, i1); \
  }
#else
#define SPAM_ROWS_DIM(Prefix, D, KIND) \
  SPAM_CLONES static void Density##D##Prefix(const Rows *R, int uni, double *rho, int i0, int i1) \
  { \
    DensityKindRows(D, SPAM_KERNEL_##KIND, R, uni, rho, i0, i1); \
  } \
  SPAM_CLONES static void Force##D##Prefix(const Rows *R, int uni, int uq, double *acc, int i0, int i1) \
  { \
    ForceKindRows(D, SPAM_KERNEL_##KIND, R, uni, uq, acc, i0, i1); \
  }
#endif
#define SPAM_ROWS_KIND(ctx, KIND, name, Prefix) SPAM_ROWS_DIM(Prefix, 1, KIND) SPAM_ROWS_DIM(Prefix, 2, KIND) SPAM_ROWS_DIM(Prefix, 3, KIND)
SPAM_KERNEL_LIST(SPAM_ROWS_KIND, ~)
#define SPAM_DENSITY_ROW(ctx, KIND, name, Prefix) {Density1##Prefix, Density2##Prefix, Density3##Prefix},
#define SPAM_FORCE_ROW(ctx, KIND, name, Prefix)   {Force1##Prefix, Force2##Prefix, Force3##Prefix},
static const DensityRowsFn density_rows[SPAM_KERNEL_KINDS][3] = {SPAM_KERNEL_LIST(SPAM_DENSITY_ROW, ~)};
static const ForceRowsFn   force_rows[SPAM_KERNEL_KINDS][3]   = {SPAM_KERNEL_LIST(SPAM_FORCE_ROW, ~)};

/* One block of rows of a pass: thread t of the pass's T sums rows [i0, i1) into its own
 * buffer of len values, which it zeroes first (thread 0's is the output itself, whose
 * local densities start at the self term m_i w(0)). */
static void DensityBlock(const SpamPairPass *p, const Rows *R, double *rho, int len, int i0, int i1, int t)
{
  const double w0 = p->k->wnorm;
  for (int i = 0; i < len; i++) rho[i] = t || i >= p->n ? 0.0 : p->uniform_mass ? p->mass * w0 : p->f->m[i] * w0;
  density_rows[p->k->kind][p->dim - 1](R, p->uniform_mass, rho, i0, i1);
}

static void ForceBlock(const SpamPairPass *p, const Rows *R, double *acc, size_t len, int i0, int i1)
{
  for (size_t k = 0; k < len; k++) acc[k] = 0.0;
  force_rows[p->k->kind][p->dim - 1](R, p->uniform_mass, p->uniform_q, acc, i0, i1);
}

/* With T > 1 threads the rows are split into T blocks of about equal pair counts, and
 * each thread sums its block into its own buffer (thread 0 into the output, the others
 * into the pass's tacc or trho); the buffers are then added in thread order. No two
 * threads write one address, and every sum is taken in an order fixed by the list and
 * T alone, so the results are the same run to run (and differ from T = 1 only by the
 * order of the additions). */

/* Adds the T - 1 scratch buffers of len values to out, in thread order (inside a parallel
 * region: the values are shared out among the threads). */
static inline void AddThreadBuffers(double *out, const double *scratch, size_t len, int T)
{
#pragma omp for schedule(static)
  for (size_t k = 0; k < len; k++)
    for (int s = 1; s < T; s++) out[k] += scratch[(size_t)(s - 1) * len + k];
}

/* The kind indexes the tables above, inside a parallel region, which cannot return an
 * error: it is checked before. */
static PetscErrorCode KnownKind(const SpamKernel *k)
{
  PetscFunctionBeginUser;
  PetscCheck(k->kind >= 0 && k->kind < SPAM_KERNEL_KINDS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the pair passes have no kernel of kind %d (kernel_list.h lists %d)", (int)k->kind, (int)SPAM_KERNEL_KINDS);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamChunkedDensity(const SpamPairPass *p)
{
  const Rows R   = RowsOf(p, p->uniform_mass ? p->mass * p->k->wnorm : p->k->wnorm);
  const int  T   = p->threads, len = p->ghost_newton ? p->slots : p->n;
  double    *rho = p->f->rho;

  PetscFunctionBeginUser;
  PetscCall(KnownKind(p->k));
  if (T == 1) DensityBlock(p, &R, rho, len, 0, p->nl->n, 0);
  else {
#pragma omp parallel num_threads(T)
    {
      const int t = omp_get_thread_num();
      int       rows[2];
      SpamNeighboursSplitRows(p->nl, T, t, rows);
      DensityBlock(p, &R, t == 0 ? rho : p->trho + (size_t)(t - 1) * p->n, p->n, rows[0], rows[1], t);
#pragma omp barrier
      AddThreadBuffers(rho, p->trho, (size_t)p->n, T);
    }
  }
  if (p->ghost_newton) SpamGhostsFold(p->gh, p->dim, p->n, 1, SPAM_GHOST_SCALAR, rho);
  PetscFunctionReturn(0);
}

PetscBool SpamChunkedForceFits(const SpamPairPass *p)
{
  return (PetscBool)(p->threads == 1 && !p->ghost_newton && !p->canonical);
}

/* Each particle's sum is cleared (and its position placed) before the first row that
 * names it and handed on after the last: a pass over the whole list between a clearing
 * pass and a reading pass would take the accelerations from memory three times, and at
 * 2^18 particles and more in 2D these streams, not the pairs, made the time per particle
 * grow with N (callgrind: the same instructions and first-level misses per particle as
 * at 16384, seven times the last-level misses). */
PetscErrorCode SpamChunkedForceBlocks(const SpamPairPass *p, const double *x, int stride, SpamRowsDone done, void *ctx)
{
  const Rows            R    = RowsOf(p, p->uniform_mass ? -p->mass * p->k->gnorm : -p->k->gnorm);
  const SpamNeighbours *nl   = p->nl;
  const int             dim  = p->dim;
  double               *acc  = p->f->acc;
  size_t                zero = 0;
  int                   fin  = 0;

  PetscFunctionBeginUser;
  PetscCall(KnownKind(p->k));
  PetscCheck(SpamChunkedForceFits(p) && nl->nblk * SPAM_ROW_BLOCK >= nl->n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the blocked force pass needs one thread, no ghost reactions and the list's row blocks");
  for (int b = 0; b < nl->nblk; b++) {
    const int    i0 = b * SPAM_ROW_BLOCK, i1 = PetscMin(nl->n, i0 + SPAM_ROW_BLOCK);
    const size_t z  = (size_t)nl->blk_zero[b] * dim;
    if (x) SpamNeighboursPlace(nl, x, stride, (int)(zero / dim), nl->blk_zero[b]);
    for (; zero < z; zero++) acc[zero] = 0.0;
    force_rows[p->k->kind][dim - 1](&R, p->uniform_mass, p->uniform_q, acc, i0, i1);
    if (nl->blk_final[b] > fin) {
      done(ctx, fin, nl->blk_final[b]);
      fin = nl->blk_final[b];
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamChunkedForce(const SpamPairPass *p)
{
  const Rows   R   = RowsOf(p, p->uniform_mass ? -p->mass * p->k->gnorm : -p->k->gnorm);
  const int    T   = p->threads;
  const size_t len = (size_t)(p->ghost_newton ? p->slots : p->n) * p->dim;
  double      *acc = p->f->acc;

  PetscFunctionBeginUser;
  PetscCall(KnownKind(p->k));
  if (T == 1) ForceBlock(p, &R, acc, len, 0, p->nl->n);
  else {
#pragma omp parallel num_threads(T)
    {
      const int t = omp_get_thread_num();
      int       rows[2];
      SpamNeighboursSplitRows(p->nl, T, t, rows);
      ForceBlock(p, &R, t == 0 ? acc : p->tacc + (size_t)(t - 1) * len, len, rows[0], rows[1]);
#pragma omp barrier
      AddThreadBuffers(acc, p->tacc, len, T);
    }
  }
  if (p->ghost_newton) SpamGhostsFold(p->gh, p->dim, p->n, p->dim, SPAM_GHOST_VECTOR, acc);
  PetscFunctionReturn(0);
}
