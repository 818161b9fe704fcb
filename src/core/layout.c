/* State layouts. */
#include <spam/layout.h>

PetscErrorCode SpamLayoutPositionsVelocities(int dim, SpamLayout *l)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(l, sizeof *l));
  l->dim  = dim;
  l->x    = 0;
  l->v    = dim;
  l->e    = -1;
  l->rho  = -1;
  l->s    = -1;
  l->wb   = -1;
  l->fb   = -1;
  l->h    = -1;
  l->nvar = 2 * dim;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLayoutSolid(int dim, PetscBool with_rho, PetscBool with_stress, double rho_scale, double stress_scale, SpamLayout *l)
{
  PetscFunctionBeginUser;
  PetscCall(SpamLayoutPositionsVelocities(dim, l));
  l->e = l->nvar++;
  if (with_rho) l->rho = l->nvar++;
  l->scale[l->e] = stress_scale / rho_scale;
  if (with_rho) l->scale[l->rho] = rho_scale;
  if (!with_stress) PetscFunctionReturn(0);
  l->s = l->nvar;
  l->nvar += dim * (dim + 1) / 2;
  for (int k = 0; k < dim * (dim + 1) / 2; k++) l->scale[l->s + k] = stress_scale;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLayoutAddSmoothing(SpamLayout *l, double h0)
{
  PetscFunctionBeginUser;
  PetscCheck(l->nvar + 1 <= SPAM_MAX_NVAR, PETSC_COMM_SELF, PETSC_ERR_SUP, "the state of %d values per particle has no room for h", l->nvar);
  l->h           = l->nvar++;
  l->scale[l->h] = h0; /* h_i's error relative to itself, floored at the range -h */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLayoutAddWallBooks(SpamLayout *l)
{
  PetscFunctionBeginUser;
  PetscCheck(l->nvar + 2 + l->dim <= SPAM_MAX_NVAR, PETSC_COMM_SELF, PETSC_ERR_SUP, "the state of %d values per particle has no room for the wall books", l->nvar);
  l->wb = l->nvar;
  l->nvar += 2 + l->dim;
  for (int k = l->wb; k < l->nvar; k++) l->scale[k] = INFINITY; /* weight 1/inf = 0 */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLayoutAddFlowBook(SpamLayout *l)
{
  PetscFunctionBeginUser;
  PetscCheck(l->nvar + 1 <= SPAM_MAX_NVAR, PETSC_COMM_SELF, PETSC_ERR_SUP, "the state of %d values per particle has no room for the flow book", l->nvar);
  l->fb           = l->nvar++;
  l->scale[l->fb] = INFINITY; /* a book takes no part in the error control */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamLayoutDescribe(const SpamLayout *l, char *buf, size_t len)
{
  static const char *ax[3] = {"x", "y", "z"};
  static const char *st1[1] = {"sxx"}, *st2[3] = {"sxx", "sxy", "syy"}, *st3[6] = {"sxx", "sxy", "sxz", "syy", "syz", "szz"};
  const char *const *st = l->dim == 1 ? st1 : l->dim == 2 ? st2 : st3;
  size_t             used  = 0;

  PetscFunctionBeginUser;
  buf[0] = 0;
  for (int d = 0; d < l->dim; d++) used += (size_t)snprintf(buf + used, len - used, "%s%s", used ? " " : "", ax[d]);
  for (int d = 0; d < l->dim && l->v >= 0; d++) used += (size_t)snprintf(buf + used, len - used, " v%s", ax[d]);
  if (l->e >= 0) used += (size_t)snprintf(buf + used, len - used, " e");
  if (l->rho >= 0) used += (size_t)snprintf(buf + used, len - used, " rho");
  if (l->h >= 0) used += (size_t)snprintf(buf + used, len - used, " h");
  for (int k = 0; l->s >= 0 && k < l->dim * (l->dim + 1) / 2; k++) used += (size_t)snprintf(buf + used, len - used, " %s", st[k]);
  if (l->wb >= 0) used += (size_t)snprintf(buf + used, len - used, " wall_books");
  if (l->fb >= 0) used += (size_t)snprintf(buf + used, len - used, " flow_book");
  PetscFunctionReturn(0);
}

void SpamLayoutFieldWeights(const SpamLayout *l, const double *p, double rtol, double atol, double *w)
{
  for (int k = 2 * l->dim; k < l->nvar; k++) w[k] = 1.0 / (rtol * PetscMax(fabs(p[k]), l->scale[k]) + atol);
}
