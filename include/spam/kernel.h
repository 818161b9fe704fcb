/* Smoothing kernels. Lucy's kernel w(r) = C_D h^-D (1 + 3s)(1 - s)^3, s = r/h < 1.
 * The inline evaluators take r^2 so that pair loops test the range before the sqrt. */
#ifndef SPAM_KERNEL_H
#define SPAM_KERNEL_H
#include <math.h>
#include <petscsys.h>

typedef enum { SPAM_KERNEL_LUCY = 0, SPAM_KERNEL_WENDLAND_C2, SPAM_KERNEL_WENDLAND_C4, SPAM_KERNEL_WENDLAND_C6, SPAM_KERNEL_CUBIC_SPLINE, SPAM_KERNEL_QUINTIC_SPLINE, SPAM_KERNEL_KINDS } SpamKernelKind;

typedef struct {
  SpamKernelKind kind;
  const char    *name;
  int            smooth;
  int    dim;
  double h, hinv, h2;
  double wnorm;  /* C_D h^-D: w = wnorm (1+3s)(1-s)^3                        */
  double gnorm;  /* -12 C_D h^-(D+2): w'(r)/r = gnorm (1-s)^2               */
} SpamKernel;

PetscErrorCode SpamKernelLucyInit(int dim, double h, SpamKernel *k);
/* TEMPORARY until the kernels branch: reads -kernel (lucy only). */
PetscErrorCode SpamKernelOptions(int dim, double h, SpamKernel *k);

/* w(r) from r^2; zero outside the support. */
static inline double SpamKernelW(const SpamKernel *k, double r2)
{
  if (r2 >= k->h2) return 0.0;
  const double s = sqrt(r2) * k->hinv, t = 1.0 - s;
  return k->wnorm * (1.0 + 3.0 * s) * t * t * t;
}

/* w'(r)/r from r^2, so that grad_i w_ij = (w'/r) r_ij; zero outside the support. */
static inline double SpamKernelDWOverR(const SpamKernel *k, double r2)
{
  if (r2 >= k->h2) return 0.0;
  const double t = 1.0 - sqrt(r2) * k->hinv;
  return k->gnorm * t * t;
}

/* w'(r) and w''(r) for r >= 0 (used by tests and by the linearised analyses). */
double SpamKernelDW(const SpamKernel *k, double r);
double SpamKernelD2W(const SpamKernel *k, double r);
#endif
