/* Wendland's C4 kernel: normalisation C_D (Dehnen & Aly 2012, Table 1) and smoothness
 * at r = h (the factor t^5 in 1D, t^6 in 2D and 3D). */
#include "kernel_registry.h"

PetscErrorCode SpamKernelWendlandC4Describe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 3.0 / 2.0 : dim == 2 ? 9.0 / SPAM_PI : 495.0 / (32.0 * SPAM_PI);
  d->cgrad  = dim == 1 ? -14.0 : -56.0 / 3.0;
  d->smooth = dim == 1 ? 4 : 5;
  PetscFunctionReturn(0);
}
