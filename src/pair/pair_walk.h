/* The one pair-loop driver. SPAM_PAIR_WALK(Name, Ctx, Fn) defines
 *   static PetscErrorCode Name(const SpamNeighbours *nl, const SpamKernel *k, Ctx *ctx)
 * which visits every listed pair within the kernel range -- the local rows of the half
 * list, then each row's ghost neighbours (j >= n, ghosts.h) -- and calls
 *   Fn(dim, ctx, i, j, dx, r2, w, g)   (dim a literal)
 * with dx = r_i - r_j (minimum image where the row may cross a periodic face), r2 = |dx|^2,
 * w = w(r) and g = w'(r)/r, so that grad_i w_ij = g dx. Each pair is visited once; a pair
 * function updates both particles (the ghost's share is folded or dropped afterwards).
 * The walk is compiled once per dimension and kernel (literal arguments of always-inline
 * functions, so the kernel's shape and the loops over d are folded), and per row once
 * with and once without the minimum image. A pass that needs several pair functions
 * calls them from one Fn, so they share one walk of the list. */
#ifndef SPAM_PAIR_WALK_H
#define SPAM_PAIR_WALK_H
#include <spam/neighbours.h>
#include <spam/kernel.h>
#include "../kernels/kernel_shape.h"

/* Calls Name##Rows(D, K, args) with the dimension D and kernel kind K as literals: one case
 * per row of kernel_list.h. A kind outside the list runs Unknown (a statement), never some
 * other kernel's shape. */
#define SPAM_WALK_UNPACK(...) __VA_ARGS__
#define SPAM_WALK_ROWS(K, ...) SPAM_WALK_ROWS_(K, __VA_ARGS__)
#define SPAM_WALK_ROWS_(K, Name, D, ...) Name##Rows(D, K, __VA_ARGS__)
#define SPAM_WALK_CASE(call, KIND, name, Prefix) \
  case SPAM_KERNEL_##KIND: SPAM_WALK_ROWS(SPAM_KERNEL_##KIND, SPAM_WALK_UNPACK call); break;
#ifdef SPAM_ONE_KERNEL_COPY
/* The sanitizer build (CMakeLists.txt) compiles each walk once per dimension, with the kind a
 * value known only at run time: the kernel's shape is then a switch inside the pair loop
 * (kernel_shape.h), the arithmetic and the memory the walk touches are the same, and the
 * compiler instruments one copy of the loop instead of one per kernel. */
#define SPAM_WALK_KERNELS(Name, D, kind, Unknown, ...) \
  if ((kind) >= 0 && (kind) < SPAM_KERNEL_KINDS) Name##Rows(D, kind, __VA_ARGS__); \
  else { \
    Unknown; \
  }
#else
#define SPAM_WALK_KERNELS(Name, D, kind, Unknown, ...) \
  switch (kind) { \
    SPAM_KERNEL_LIST(SPAM_WALK_CASE, (Name, D, __VA_ARGS__)) \
  default: Unknown; \
  }
#endif
#define SPAM_WALK_DISPATCH(Name, dim, kind, Unknown, ...) \
  switch (dim) { \
  case 1: SPAM_WALK_KERNELS(Name, 1, kind, Unknown, __VA_ARGS__); break; \
  case 2: SPAM_WALK_KERNELS(Name, 2, kind, Unknown, __VA_ARGS__); break; \
  default: SPAM_WALK_KERNELS(Name, 3, kind, Unknown, __VA_ARGS__); break; \
  }
/* The error of a walk asked for a kind kernel_list.h does not have. */
#define SPAM_WALK_UNKNOWN(kind) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "the pair walk has no kernel of kind %d (kernel_list.h lists %d)", (int)(kind), (int)SPAM_KERNEL_KINDS)

/* The body of a walk's inner loop for the candidate pair (i, j): the separation (minimum
 * image where img), the range test (continue: the macro is the loop body's last statement)
 * and the call of Fn with both kernel values. Shared by the plain and the masked walks. */
#define SPAM_PAIR_VISIT(Fn, dim, kind, img, nl, k, ctx, i, j, ui) \
  double dx[3] = {0.0, 0.0, 0.0}, r2 = 0.0; \
  for (int d = 0; d < dim; d++) { \
    dx[d] = img ? SpamImageDelta(&nl->im, d, ui[d] - nl->u[d][j]) : ui[d] - nl->u[d][j]; \
    r2 += dx[d] * dx[d]; \
  } \
  if (r2 >= k->h2) continue; \
  const double s = sqrt(r2) * k->hinv; \
  Fn(dim, ctx, i, j, dx, r2, SpamKernelShapeScaledF(kind, dim, k->wnorm, s), SpamKernelShapeScaledG(kind, dim, k->gnorm, s));

#define SPAM_PAIR_WALK(Name, Ctx, Fn) \
  static inline __attribute__((always_inline)) void Name##Segment(const int dim, const int kind, const int img, const SpamNeighbours *nl, const SpamKernel *k, Ctx *ctx, int i, const int *nb, int np) \
  { \
    const double ui[3] = {nl->u[0][i], dim > 1 ? nl->u[1][i] : 0.0, dim > 2 ? nl->u[2][i] : 0.0}; \
    for (int c = 0; c < np; c++) { \
      const int j = nb[c]; \
      SPAM_PAIR_VISIT(Fn, dim, kind, img, nl, k, ctx, i, j, ui) \
    } \
  } \
  static inline __attribute__((always_inline)) void Name##Rows(const int dim, const int kind, const SpamNeighbours *nl, const SpamKernel *k, Ctx *ctx) \
  { \
    for (int i = 0; i < nl->n; i++) { \
      const int *nb = nl->nbr + nl->start[i], np = nl->start[i + 1] - nl->start[i]; \
      const int *gb = nl->gnbr + nl->gstart[i], ng = nl->gstart[i + 1] - nl->gstart[i]; \
      if (nl->image[i]) { \
        Name##Segment(dim, kind, 1, nl, k, ctx, i, nb, np); \
        if (ng) Name##Segment(dim, kind, 1, nl, k, ctx, i, gb, ng); \
      } else { \
        Name##Segment(dim, kind, 0, nl, k, ctx, i, nb, np); \
        if (ng) Name##Segment(dim, kind, 0, nl, k, ctx, i, gb, ng); \
      } \
    } \
  } \
  static PetscErrorCode Name(const SpamNeighbours *nl, const SpamKernel *k, Ctx *ctx) \
  { \
    PetscFunctionBeginUser; \
    SPAM_WALK_DISPATCH(Name, k->dim, k->kind, SPAM_WALK_UNKNOWN(k->kind), nl, k, ctx) \
    PetscFunctionReturn(0); \
  }

/* SPAM_PAIR_WALK_MASKED(Name, Ctx, Fn): the same walk restricted to the pairs with at least
 * one member marked in mask (one byte per slot of the list), defining
 *   static PetscErrorCode Name(const SpamNeighbours *nl, const SpamKernel *k, const unsigned char *mask, const unsigned char *row, Ctx *ctx)
 * Each pair it visits is visited in the plain walk's order, so a marked particle's sums are
 * the plain walk's, term for term; an unmarked one gets only its pairs with marked ones.
 * Only the rows i with row[i] set are read: row must be set at least where the row holds a
 * pair with a marked member (SpamNeighboursMarkedRows; the half list holds each pair in
 * one row only, which the transposed list names). A macro of its own, so that the plain
 * walk's loop stays as it was. */
#define SPAM_PAIR_WALK_MASKED(Name, Ctx, Fn) \
  static inline __attribute__((always_inline)) void Name##Segment(const int dim, const int kind, const int img, const SpamNeighbours *nl, const SpamKernel *k, const unsigned char *mask, Ctx *ctx, int i, const int *nb, int np) \
  { \
    const int    mi    = mask[i]; \
    const double ui[3] = {nl->u[0][i], dim > 1 ? nl->u[1][i] : 0.0, dim > 2 ? nl->u[2][i] : 0.0}; \
    for (int c = 0; c < np; c++) { \
      const int j = nb[c]; \
      if (!mi && !mask[j]) continue; \
      SPAM_PAIR_VISIT(Fn, dim, kind, img, nl, k, ctx, i, j, ui) \
    } \
  } \
  static inline __attribute__((always_inline)) void Name##Rows(const int dim, const int kind, const SpamNeighbours *nl, const SpamKernel *k, const unsigned char *mask, const unsigned char *row, Ctx *ctx) \
  { \
    for (int i = 0; i < nl->n; i++) { \
      if (!row[i]) continue; \
      const int *nb = nl->nbr + nl->start[i], np = nl->start[i + 1] - nl->start[i]; \
      const int *gb = nl->gnbr + nl->gstart[i], ng = nl->gstart[i + 1] - nl->gstart[i]; \
      if (nl->image[i]) { \
        Name##Segment(dim, kind, 1, nl, k, mask, ctx, i, nb, np); \
        if (ng) Name##Segment(dim, kind, 1, nl, k, mask, ctx, i, gb, ng); \
      } else { \
        Name##Segment(dim, kind, 0, nl, k, mask, ctx, i, nb, np); \
        if (ng) Name##Segment(dim, kind, 0, nl, k, mask, ctx, i, gb, ng); \
      } \
    } \
  } \
  static PetscErrorCode Name(const SpamNeighbours *nl, const SpamKernel *k, const unsigned char *mask, const unsigned char *row, Ctx *ctx) \
  { \
    PetscFunctionBeginUser; \
    SPAM_WALK_DISPATCH(Name, k->dim, k->kind, SPAM_WALK_UNKNOWN(k->kind), nl, k, mask, row, ctx) \
    PetscFunctionReturn(0); \
  }
#endif
