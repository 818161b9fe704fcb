/* The cubic spline M4 with support h: C_D = sigma_D 2^D from the usual sigma_D = 2/3,
 * 10/(7 pi), 1/pi for support 2 h' (h' = h/2). C^2 at r = h (the factor t^3). */
#include "kernel_registry.h"

PetscErrorCode SpamKernelCubicSplineDescribe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 4.0 / 3.0 : dim == 2 ? 40.0 / (7.0 * SPAM_PI) : 8.0 / SPAM_PI;
  d->cgrad  = -6.0;
  d->smooth = 2;
  PetscFunctionReturn(0);
}
