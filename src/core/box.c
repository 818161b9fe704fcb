/* Box checks. */
#include <spam/box.h>
#include <spam/errors.h>

PetscErrorCode SpamBoxValidate(const SpamBox *b, double h, const char *what)
{
  static const char *axes[3] = {"x", "y", "z"};
  char               val[64], name[128], far[32], hs[32];

  PetscFunctionBeginUser;
  for (int d = 0; d < b->dim; d++) {
    (void)snprintf(val, sizeof val, "%g", b->len[d]);
    (void)snprintf(name, sizeof name, "box edge %s (%s)", axes[d], what);
    if (!(b->len[d] > 0.0) || !isfinite(b->len[d])) SPAM_BAD_INPUT(name, val, "box edges must be positive and finite");
    if (b->periodic[d] && b->len[d] < 2.0 * h) SPAM_BAD_INPUT(name, val, "a periodic box edge must be at least 2h = %g (h = %g) so that a particle meets one image of another", 2.0 * h, h);
    /* Far from the origin a double cannot resolve a kernel range: beyond 1e9 h its unit
     * in the last place exceeds 2e-7 h (and ARKODE's default tolerances fail near 1e10). */
    (void)snprintf(val, sizeof val, "%g", PetscMax(fabs(b->lo[d]), fabs(b->lo[d] + b->len[d])));
    (void)snprintf(name, sizeof name, "box corner %s (%s)", axes[d], what);
    if (!(PetscMax(fabs(b->lo[d]), fabs(b->lo[d] + b->len[d])) <= 1e9 * h)) {
      (void)snprintf(far, sizeof far, "%g", 1e9 * h); /* PETSc's %g would print 8 as "8." */
      (void)snprintf(hs, sizeof hs, "%g", h);
      SPAM_BAD_INPUT(name, val, "the box, shifted by any -scene_translate, must lie within 1e9 h = %s of the origin (h = %s), so that positions resolve the kernel range", far, hs);
    }
  }
  PetscFunctionReturn(0);
}

int SpamBoxOutside(int dim, const double *lo, const double *len, const PetscBool *faces, const double *x, char *why, size_t n)
{
  static const char *ax[3] = {"x", "y", "z"};

  for (int d = 0; d < dim; d++) {
    const double hi = lo[d] + len[d];
    /* a NaN is on neither side: it is outside whichever face bounds */
    const PetscBool below = (PetscBool)!(x[d] >= lo[d]), above = (PetscBool)!(x[d] <= hi);
    if (!((below && (!faces || faces[2 * d])) || (above && (!faces || faces[2 * d + 1])))) continue;
    /* formatted here: PETSc's %g writes 8 as "8." */
    (void)snprintf(why, n, "%s = %.10g lies outside the box, %.10g <= %s <= %.10g", ax[d], x[d], lo[d], ax[d], hi);
    return d;
  }
  return -1;
}
