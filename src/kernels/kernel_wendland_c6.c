/* Wendland's C6 kernel: normalisation C_D (Dehnen & Aly 2012, Table 1) and smoothness
 * at r = h (the factor t^7 in 1D, t^8 in 2D and 3D). */
#include "kernel_registry.h"

PetscErrorCode SpamKernelWendlandC6Describe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 55.0 / 32.0 : dim == 2 ? 78.0 / (7.0 * SPAM_PI) : 1365.0 / (64.0 * SPAM_PI);
  d->cgrad  = dim == 1 ? -6.0 : -22.0;
  d->smooth = dim == 1 ? 6 : 7;
  PetscFunctionReturn(0);
}
