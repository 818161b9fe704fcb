/* The smoothing kernels: the one list. Each row X(ctx, KIND, name, Prefix) makes
 *   - the kind SPAM_KERNEL_KIND of the enum SpamKernelKind (spam/kernel.h), in row order;
 *   - the name -kernel accepts and -help lists (kernel_registry.c), in row order, and the
 *     registry's entry, which takes the kernel's numbers from SpamPrefixInfo(dim)
 *     (normalisation C_D, cgrad, smoothness at r = h);
 *   - the cases of the shape switches (kernel_shape.h): SpamPrefixF/G/H(dim, c, s);
 *   - the case of the pair walk's dispatch (src/pair/pair_walk.h and the canonical passes).
 * The functions are the kernel's header kernel_<name>.h, included in the second half of
 * this file. ctx is the caller's, passed through to X unchanged (the walk hands its pass
 * name and arguments to each case this way). A kernel is therefore one header and, here,
 * its row and its #include. SPAM_KERNEL_LIST_EXTRA and SPAM_KERNEL_EXTRA_HEADER append a
 * row and a header from outside: only the test program that proves this list drives
 * everything (tests/kernel_extra/) defines them. */
#ifndef SPAM_KERNEL_LIST_H
#define SPAM_KERNEL_LIST_H

#ifndef SPAM_KERNEL_LIST_EXTRA
#define SPAM_KERNEL_LIST_EXTRA(X, ctx)
#endif

#define SPAM_KERNEL_LIST(X, ctx) \
  X(ctx, LUCY, lucy, Lucy) \
  X(ctx, WENDLAND_C2, wendland_c2, WendlandC2) \
  X(ctx, WENDLAND_C4, wendland_c4, WendlandC4) \
  X(ctx, WENDLAND_C6, wendland_c6, WendlandC6) \
  X(ctx, CUBIC_SPLINE, cubic_spline, CubicSpline) \
  X(ctx, QUINTIC_SPLINE, quintic_spline, QuinticSpline) \
  SPAM_KERNEL_LIST_EXTRA(X, ctx)
#endif

/* The shape headers, one per row above. kernel_shape.h includes this file again after it
 * has defined SPAM_INLINE and SpamKernelEdge, which the headers use. */
#if defined(SPAM_KERNEL_SHAPE_H) && !defined(SPAM_KERNEL_LIST_SHAPES)
#define SPAM_KERNEL_LIST_SHAPES
#include <kernels/kernel_lucy.h>
#include <kernels/kernel_wendland_c2.h>
#include <kernels/kernel_wendland_c4.h>
#include <kernels/kernel_wendland_c6.h>
#include <kernels/kernel_cubic_spline.h>
#include <kernels/kernel_quintic_spline.h>
#ifdef SPAM_KERNEL_EXTRA_HEADER
#include SPAM_KERNEL_EXTRA_HEADER
#endif
#endif
