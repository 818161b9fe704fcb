/* Lucy's kernel: normalisation C_D in 1, 2 and 3D and smoothness at r = h. */
#include "kernel_registry.h"

PetscErrorCode SpamKernelLucyDescribe(int dim, SpamKernelShapeInfo *d)
{
  PetscFunctionBeginUser;
  d->cnorm  = dim == 1 ? 5.0 / 4.0 : dim == 2 ? 5.0 / SPAM_PI : 105.0 / (16.0 * SPAM_PI);
  d->cgrad  = -12.0;
  d->smooth = 2; /* t^3: w, w', w'' vanish at h and w''' = 6 C_D / h^(D+3) does not: the force is C^1 */
  PetscFunctionReturn(0);
}
