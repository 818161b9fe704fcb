/* Wendland's C2 kernel: normalisation C_D (Dehnen & Aly 2012, Table 1) and smoothness
 * at r = h (the factor t^3 in 1D, t^4 in 2D and 3D). */
#include "kernel_registry.h"

PetscErrorCode SpamKernelWendlandC2Describe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 5.0 / 4.0 : dim == 2 ? 7.0 / SPAM_PI : 21.0 / (2.0 * SPAM_PI);
  d->cgrad  = dim == 1 ? -12.0 : -20.0;
  d->smooth = dim == 1 ? 2 : 3;
  PetscFunctionReturn(0);
}
