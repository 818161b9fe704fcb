/* State layouts. */
#include <spam/layout.h>

PetscErrorCode SpamLayoutPositionsVelocities(int dim, SpamLayout *l)
{
  PetscFunctionBeginUser;
  l->dim  = dim;
  l->x    = 0;
  l->v    = dim;
  l->e    = -1;
  l->rho  = -1;
  l->nvar = 2 * dim;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLayoutDescribe(const SpamLayout *l, char *buf, size_t len)
{
  static const char *ax[3] = {"x", "y", "z"};
  size_t             used  = 0;

  PetscFunctionBeginUser;
  buf[0] = 0;
  for (int d = 0; d < l->dim; d++) used += (size_t)snprintf(buf + used, len - used, "%s%s", used ? " " : "", ax[d]);
  for (int d = 0; d < l->dim && l->v >= 0; d++) used += (size_t)snprintf(buf + used, len - used, " v%s", ax[d]);
  if (l->e >= 0) used += (size_t)snprintf(buf + used, len - used, " e");
  if (l->rho >= 0) (void)snprintf(buf + used, len - used, " rho");
  PetscFunctionReturn(0);
}
