/* The test-only kernel test_tent: C_D from the integral of F = (1 + 2s)(1 - s)^2 over the
 * unit D-ball (1D: 2 * 1/2, 2D: 2 pi * 3/20, 3D: 4 pi * 1/15), cgrad = -6, smoothness 1. */
#include <kernels/kernel_registry.h>

PetscErrorCode SpamKernelTestTentDescribe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 1.0 : dim == 2 ? 10.0 / (3.0 * SPAM_PI) : 15.0 / (4.0 * SPAM_PI);
  d->cgrad  = -6.0;
  d->smooth = 1;
  PetscFunctionReturn(0);
}
