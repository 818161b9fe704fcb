/* Box checks. */
#include <spam/box.h>
#include <spam/errors.h>

PetscErrorCode SpamBoxValidate(const SpamBox *b, double h)
{
  static const char *names[3] = {"-box_len[0]", "-box_len[1]", "-box_len[2]"};
  char               val[64];

  PetscFunctionBeginUser;
  for (int d = 0; d < b->dim; d++) {
    PetscCall(PetscSNPrintf(val, sizeof val, "%g", b->len[d]));
    if (!(b->len[d] > 0.0) || !isfinite(b->len[d])) SPAM_BAD_INPUT(names[d], val, "box edges must be positive and finite");
    if (b->periodic[d] && b->len[d] < 2.0 * h) SPAM_BAD_INPUT(names[d], val, "a periodic box edge must be at least 2h = %g so that a particle meets one image of another", 2.0 * h);
  }
  PetscFunctionReturn(0);
}

double SpamBoxVolume(const SpamBox *b)
{
  double v = 1.0;
  for (int d = 0; d < b->dim; d++) v *= b->len[d];
  return v;
}
