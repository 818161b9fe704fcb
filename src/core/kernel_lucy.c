/* Lucy's kernel in one, two and three dimensions. */
#include <spam/kernel.h>

#define SPAM_PI 3.14159265358979323846

/* C_D makes the integral of w over D-dimensional space equal to one. */
static double LucyNormalisation(int dim)
{
  switch (dim) {
  case 1: return 5.0 / 4.0;
  case 2: return 5.0 / SPAM_PI;
  default: return 105.0 / (16.0 * SPAM_PI);
  }
}

PetscErrorCode SpamKernelLucyInit(int dim, double h, SpamKernel *k)
{
  PetscFunctionBeginUser;
  PetscCheck(dim >= 1 && dim <= 3, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "kernel dimension %d not in 1..3", dim);
  PetscCheck(h > 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "kernel range h = %g must be positive", h);
  k->kind  = SPAM_KERNEL_LUCY;
  k->name  = "lucy";
  k->smooth = 2;
  k->dim   = dim;
  k->h     = h;
  k->hinv  = 1.0 / h;
  k->h2    = h * h;
  k->wnorm = LucyNormalisation(dim) * pow(h, -dim);
  k->gnorm = -12.0 * LucyNormalisation(dim) * pow(h, -(dim + 2));
  PetscFunctionReturn(0);
}

double SpamKernelDW(const SpamKernel *k, double r)
{
  if (r >= k->h) return 0.0;
  const double s = r * k->hinv, t = 1.0 - s;
  return k->gnorm * k->h * s * t * t; /* w'(r) = (w'/r) r */
}

double SpamKernelD2W(const SpamKernel *k, double r)
{
  if (r >= k->h) return 0.0;
  const double s = r * k->hinv;
  return k->gnorm * (1.0 - s) * (1.0 - 3.0 * s);
}

PetscErrorCode SpamKernelOptions(int dim, double h, SpamKernel *k)
{
  char name[64] = "lucy";
  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Kernel", "spam-ark");
  PetscCall(PetscOptionsString("-kernel", "Smoothing kernel", "README", name, name, sizeof name, NULL));
  PetscOptionsEnd();
  PetscCall(SpamKernelLucyInit(dim, h, k));
  PetscFunctionReturn(0);
}
