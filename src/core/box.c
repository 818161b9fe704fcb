/* Box checks. */
#include <spam/box.h>
#include <spam/errors.h>

PetscErrorCode SpamBoxValidate(const SpamBox *b, double h, const char *what)
{
  static const char *axes[3] = {"x", "y", "z"};
  char               val[64], name[128];

  PetscFunctionBeginUser;
  for (int d = 0; d < b->dim; d++) {
    (void)snprintf(val, sizeof val, "%g", b->len[d]);
    (void)snprintf(name, sizeof name, "box edge %s (%s)", axes[d], what);
    if (!(b->len[d] > 0.0) || !isfinite(b->len[d])) SPAM_BAD_INPUT(name, val, "box edges must be positive and finite");
    if (b->periodic[d] && b->len[d] < 2.0 * h) SPAM_BAD_INPUT(name, val, "a periodic box edge must be at least 2h = %g (h = %g) so that a particle meets one image of another", 2.0 * h, h);
  }
  PetscFunctionReturn(0);
}

double SpamBoxVolume(const SpamBox *b)
{
  double v = 1.0;
  for (int d = 0; d < b->dim; d++) v *= b->len[d];
  return v;
}
