/* The pair-loop driver of the adaptive kernel range: each particle has its own range h_i
 * (fields.h: h, hinv, wn, gn). SPAM_PAIR_WALK_ADAPTIVE(Name, Ctx, Fn, Skip, Near) defines
 *   static PetscErrorCode Name(const SpamNeighbours *nl, const SpamKernel *k, const SpamFields *f, Ctx *ctx)
 * which visits every listed local pair within the larger of the two ranges (gather and
 * scatter: r < max(h_i, h_j)) and calls
 *   Fn(dim, ctx, i, j, dx, r2, wi, gi, wj, gj)   (dim a literal)
 * for every pair for which Skip(ctx, i, j) is false (tested before the distance: a pass
 * that needs only some particles' sums leaves the others' pairs unevaluated; Near(ctx, i,
 * j, r2) sees every such pair before the range test: the h solve's first pass keeps
 * there the pairs its later passes and the force pass walk), with
 * dx = r_i - r_j (minimum image where the row may cross a periodic face), r2 = |dx|^2,
 * wi = w(r, h_i), gi = w'(r, h_i)/r and wj, gj the same at h_j, so that the gradient of
 * particle i's kernel is gi dx. A kernel's shape is exactly zero beyond its edge
 * (kernel_shape.h), so the side whose range the pair exceeds gets w = g = 0. The list's
 * range is the upper bound of every h_i (SpamModelListRange); nl may be a view of it whose
 * rows hold fewer of its pairs (SpamSmoothingPairs). Each row's ghost neighbours (other
 * ranks' particles, j >= n: their h_j, scales and fields gathered into the slots) follow
 * the row, whole: Near sees only the local pairs (the near rows are local rows), Fn sees
 * both, and what it adds to a remote slot is dropped (its owner computes its own pairs).
 *
 * SPAM_PAIR_ROWS_ADAPTIVE(Name, Ctx, Fn, Skip) defines the same walk over the canonical
 * full rows (-reproducible, neighbours_canonical.c): every partner of particle i, local
 * or ghost slot, in the order of i's row, and Fn(dim, ctx, i, j, ...) adds to particle i
 * only (rows for which Skip(ctx, i) is true are left out), so that i's sums have the same
 * bits whichever rank holds each partner. */
#ifndef SPAM_PAIR_WALK_ADAPTIVE_H
#define SPAM_PAIR_WALK_ADAPTIVE_H
#include <spam/neighbours.h>
#include <spam/fields.h>
#include "pair_walk.h"

/* The Near of a walk that keeps no pairs. */
#define SPAM_NEAR_NONE(ctx, i, j, r2) ((void)0)

/* One candidate pair of both walks below: within max(h_i, h_j), Fn gets each side's kernel
 * value and derivative at its own range. */
#define SPAM_ADAPTIVE_PAIR(Fn, dim, kind, f, ctx, i, j, hi, dx, r2) \
  do { \
    const double hm = (hi) > (f)->h[j] ? (hi) : (f)->h[j]; \
    if ((r2) < hm * hm) { \
      const double r = sqrt(r2), si = r * (f)->hinv[i], sj = r * (f)->hinv[j]; \
      Fn(dim, ctx, i, j, dx, r2, SpamKernelShapeScaledF(kind, dim, (f)->wn[i], si), SpamKernelShapeScaledG(kind, dim, (f)->gn[i], si), \
         SpamKernelShapeScaledF(kind, dim, (f)->wn[j], sj), SpamKernelShapeScaledG(kind, dim, (f)->gn[j], sj)); \
    } \
  } while (0)

/* The entry both walks below end with: the kernel's dimension and kind dispatched once, to
 * the inlined body made for them. */
#define SPAM_WALK_ADAPTIVE_ENTRY(Name, Ctx) \
  static PetscErrorCode Name(const SpamNeighbours *nl, const SpamKernel *k, const SpamFields *f, Ctx *ctx) \
  { \
    PetscFunctionBeginUser; \
    SPAM_WALK_DISPATCH(Name, k->dim, k->kind, SPAM_WALK_UNKNOWN(k->kind), nl, f, ctx) \
    PetscFunctionReturn(0); \
  }

#define SPAM_PAIR_WALK_ADAPTIVE(Name, Ctx, Fn, Skip, Near) \
  static inline __attribute__((always_inline)) void Name##Segment(const int dim, const int kind, const int img, const int ghost, const SpamNeighbours *nl, const SpamFields *f, Ctx *ctx, int i, const int *nb, int np) \
  { \
    const double ui[3] = {nl->u[0][i], dim > 1 ? nl->u[1][i] : 0.0, dim > 2 ? nl->u[2][i] : 0.0}; \
    const double hi = f->h[i]; \
    for (int c = 0; c < np; c++) { \
      const int j     = nb[c]; \
      double    dx[3] = {0.0, 0.0, 0.0}, r2 = 0.0; \
      if (Skip(ctx, i, j)) continue; \
      for (int d = 0; d < dim; d++) { \
        dx[d] = img ? SpamImageDelta(&nl->im, d, ui[d] - nl->u[d][j]) : ui[d] - nl->u[d][j]; \
        r2 += dx[d] * dx[d]; \
      } \
      if (!ghost) Near(ctx, i, j, r2); \
      SPAM_ADAPTIVE_PAIR(Fn, dim, kind, f, ctx, i, j, hi, dx, r2); \
    } \
  } \
  static inline __attribute__((always_inline)) void Name##Rows(const int dim, const int kind, const SpamNeighbours *nl, const SpamFields *f, Ctx *ctx) \
  { \
    for (int i = 0; i < nl->n; i++) { \
      const int *nb = nl->nbr + nl->start[i], np = nl->start[i + 1] - nl->start[i]; \
      const int *gb = nl->gnbr + nl->gstart[i], ng = nl->gstart[i + 1] - nl->gstart[i]; \
      if (nl->image[i]) { \
        Name##Segment(dim, kind, 1, 0, nl, f, ctx, i, nb, np); \
        if (ng) Name##Segment(dim, kind, 1, 1, nl, f, ctx, i, gb, ng); \
      } else { \
        Name##Segment(dim, kind, 0, 0, nl, f, ctx, i, nb, np); \
        if (ng) Name##Segment(dim, kind, 0, 1, nl, f, ctx, i, gb, ng); \
      } \
    } \
  } \
  SPAM_WALK_ADAPTIVE_ENTRY(Name, Ctx)

/* The canonical rows: separations u_i - u_j of two slots (periodic images are ghost
 * slots there: no minimum image), the pair within max(h_i, h_j) as above. */
#define SPAM_PAIR_ROWS_ADAPTIVE(Name, Ctx, Fn, Skip) \
  static inline __attribute__((always_inline)) void Name##Rows(const int dim, const int kind, const SpamNeighbours *nl, const SpamFields *f, Ctx *ctx) \
  { \
    for (int i = 0; i < nl->n; i++) { \
      if (Skip(ctx, i)) continue; \
      const double ui[3] = {nl->u[0][i], dim > 1 ? nl->u[1][i] : 0.0, dim > 2 ? nl->u[2][i] : 0.0}; \
      const double hi = f->h[i]; \
      for (int c = nl->cstart[i]; c < nl->cstart[i + 1]; c++) { \
        const int j     = nl->cnbr[c]; \
        double    dx[3] = {0.0, 0.0, 0.0}, r2 = 0.0; \
        for (int d = 0; d < dim; d++) { \
          dx[d] = ui[d] - nl->u[d][j]; \
          r2 += dx[d] * dx[d]; \
        } \
        SPAM_ADAPTIVE_PAIR(Fn, dim, kind, f, ctx, i, j, hi, dx, r2); \
      } \
    } \
  } \
  SPAM_WALK_ADAPTIVE_ENTRY(Name, Ctx)
#endif
