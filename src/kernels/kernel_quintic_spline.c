/* The quintic spline M6 with support h and F(0) = 1: C_D = sigma_D 3^D 66 from the usual
 * sigma_D = 1/120, 7/(478 pi), 1/(120 pi) for support 3 h' (h' = h/3), 66 being the usual
 * bracket at q = 0. C^4 at r = h (the factor t^5). */
#include "kernel_registry.h"

PetscErrorCode SpamKernelQuinticSplineDescribe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 33.0 / 20.0 : dim == 2 ? 2079.0 / (239.0 * SPAM_PI) : 297.0 / (20.0 * SPAM_PI);
  d->cgrad  = -405.0 / 22.0;
  d->smooth = 4;
  PetscFunctionReturn(0);
}
