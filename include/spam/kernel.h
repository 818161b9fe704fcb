/* Smoothing kernels by name (-kernel): w(r) = wnorm F(r/h), zero for r >= h, normalised so
 * that its integral over D-space is one. The shapes F and G (w'(r)/r = gnorm G) of every
 * kernel are in src/kernels/kernel_shape.h, one header per row of kernels/kernel_list.h,
 * the list that also makes the kinds below and the names; the pair loops call
 * them with literal kind and dim. The inline evaluators below take r^2, so that callers
 * test the range before the sqrt. Adding a kernel: docs/kernels.md. */
#ifndef SPAM_KERNEL_H
#define SPAM_KERNEL_H
#include <math.h>
#include <petscsys.h>

#include <kernels/kernel_list.h>

/* One kind per row of kernel_list.h, in its order (Lucy first: 0), then the count. */
#define SPAM_KERNEL_ENUM_ROW(ctx, KIND, name, Prefix) SPAM_KERNEL_##KIND,
typedef enum { SPAM_KERNEL_LIST(SPAM_KERNEL_ENUM_ROW, ~) SPAM_KERNEL_KINDS } SpamKernelKind;
#undef SPAM_KERNEL_ENUM_ROW

typedef struct {
  SpamKernelKind kind;
  const char    *name; /* as given to -kernel (a string literal) */
  int            dim;
  double         h, hinv, h2;
  double         wnorm;  /* w(r)     = wnorm * F(s), s = r/h: C_D h^-D; F(0) = 1, so     */
                         /* wnorm = w(0), the density's self term                      */
  double         gnorm;  /* w'(r)/r  = gnorm * G(s): cgrad C_D h^-(D+2) (Lucy: -12)      */
  int            smooth; /* derivatives of w continuous at r = h (Lucy: 2: w, w', w''    */
                         /* vanish there; w''' jumps, so the force is only C^1)          */
  int            fourier_positive; /* positive Fourier transform in dim: no pairing */
} SpamKernel;

/* The kernel called name in dim dimensions with support radius h; an unknown name is bad
 * input naming -kernel and the allowed names. */
PetscErrorCode SpamKernelCreate(const char *name, int dim, double h, SpamKernel *k);
/* SpamKernelCreate("lucy", dim, h, k). */
PetscErrorCode SpamKernelLucyInit(int dim, double h, SpamKernel *k);
/* The kernel named by -kernel (default lucy; listed by -help). */
PetscErrorCode SpamKernelOptions(int dim, double h, SpamKernel *k);
/* The names -kernel accepts, ", "-separated, into buf. */
PetscErrorCode SpamKernelNames(char *buf, size_t len);

#include <kernels/kernel_shape.h>

/* The kind is known here only at run time: Lucy's kernel is taken apart from the switch
 * over the others, a compare the branch predictor gets right every time. Loops that are
 * specialised on the kind call kernel_shape.h directly, without either. */

/* w(r) from r^2; zero outside the support. */
static inline double SpamKernelW(const SpamKernel *k, double r2)
{
  if (r2 >= k->h2) return 0.0;
  const double s = sqrt(r2) * k->hinv;
  if (k->kind == SPAM_KERNEL_LUCY) return SpamLucyF(k->dim, k->wnorm, s);
  return SpamKernelShapeScaledF(k->kind, k->dim, k->wnorm, s);
}

/* w'(r)/r from r^2, so that grad_i w_ij = (w'/r) r_ij; zero outside the support. */
static inline double SpamKernelDWOverR(const SpamKernel *k, double r2)
{
  if (r2 >= k->h2) return 0.0;
  const double s = sqrt(r2) * k->hinv;
  if (k->kind == SPAM_KERNEL_LUCY) return SpamLucyG(k->dim, k->gnorm, s);
  return SpamKernelShapeScaledG(k->kind, k->dim, k->gnorm, s);
}

/* w'(r) and w''(r) for r >= 0, zero for r >= h (the tests and the linearised analyses). */
double SpamKernelDW(const SpamKernel *k, double r);
double SpamKernelD2W(const SpamKernel *k, double r);
#endif
