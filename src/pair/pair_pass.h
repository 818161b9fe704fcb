/* The context of the isentropic gas's pair passes, made once per right-hand side after its
 * one list update (rhs_isentrope.c makes it from the simulation): the list with its ghosts, the fields, the kernel, the
 * threads and their buffers, and which traversal the passes take. The density and the
 * force (pair_density.h, pair_pressure_force.h, each coded once) are traversed
 *   - by the chunked half-list rows (pass_chunked.c): every kernel, equal or unequal
 *     masses; with local ghost slots (periodic images, mirror walls) each ghost takes the
 *     pair's reaction, folded or booked afterwards (ghosts.h), else only other ranks'
 *     particles are ghosts and a row adds its particle's share alone;
 *   - under -reproducible by the canonical full rows (pass_canonical.c): each particle's
 *     own sum in the order of its row. */
#ifndef SPAM_PAIR_PASS_H
#define SPAM_PAIR_PASS_H
#include <spam/neighbours.h>
#include <spam/kernel.h>
#include <spam/fields.h>
#include <spam/ghosts.h>

/* The passes' rows are compiled for the x86-64 baseline and for AVX2 (pass_chunked.c says
 * why); the loader picks the clone the processor runs. Both clones give the same bits. The
 * sanitizer build (CMakeLists.txt, SPAM_ONE_ISA) compiles the baseline alone: the clones
 * are one source, and each doubled the longest compiles of that build. */
#ifdef SPAM_ONE_ISA
#define SPAM_CLONES
#else
#define SPAM_CLONES __attribute__((target_clones("avx2", "default")))
#endif

typedef struct {
  const SpamNeighbours *nl;
  const SpamKernel     *k;
  SpamFields           *f;
  const SpamGhosts     *gh;
  int                   n, slots, dim;
  int                   threads;        /* threads of the pass (1 where ghosts take reactions) */
  double               *tacc, *trho;    /* thread buffers of threads 1 .. T-1                  */
  int                   canonical;      /* -reproducible: the canonical rows                   */
  int                   uniform_mass;   /* every particle has the mass m: folded into the scale */
  double                mass;           /* that m                                              */
  int                   uniform_q;      /* P/rho^2 is one constant (gamma = 2)                 */
  int                   ghost_newton;   /* local ghost slots take their pairs' reactions       */
} SpamPairPass;

/* Summation density into f->rho (local slots; ghost reactions folded), and the
 * accelerations from f->q = P/rho^2 into f->acc (ghost reactions folded; mirror slots
 * keep theirs for the walls' books): the chunked rows and the canonical rows. */
PetscErrorCode SpamChunkedDensity(const SpamPairPass *p);
PetscErrorCode SpamChunkedForce(const SpamPairPass *p);
/* The chunked force pass by the list's row blocks (neighbours.h), for one thread and no
 * ghost slot taking reactions (SpamChunkedForceFits): the accelerations are cleared just
 * ahead of the rows, and done(ctx, i0, i1) is called as soon as particles [i0, i1) have
 * their final accelerations, in order, once each. With x (the list left stale by
 * SpamNeighboursUpdateStale) the list's positions are placed from x[i*stride + d] just
 * ahead of the rows too. The same sums in the same order as SpamChunkedForce: f->acc ends
 * bitwise the same. */
typedef void (*SpamRowsDone)(void *ctx, int i0, int i1);
PetscBool      SpamChunkedForceFits(const SpamPairPass *p);
PetscErrorCode SpamChunkedForceBlocks(const SpamPairPass *p, const double *x, int stride, SpamRowsDone done, void *ctx);
PetscErrorCode SpamCanonicalDensity(const SpamPairPass *p);
PetscErrorCode SpamCanonicalForce(const SpamPairPass *p);
#endif
