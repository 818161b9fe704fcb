/* The simulation box: lower corner, edge lengths and which directions are periodic. */
#ifndef SPAM_BOX_H
#define SPAM_BOX_H
#include <petscsys.h>

typedef struct {
  int       dim;
  double    lo[3], len[3];
  PetscBool periodic[3];
} SpamBox;

/* Coordinate relative to the lower corner, wrapped into [0, len) in periodic directions.
 * Working relative to the corner keeps every pair computation translation invariant. */
static inline double SpamBoxLocal(const SpamBox *b, int d, double x)
{
  double u = x - b->lo[d];
  if (b->periodic[d]) {
    u -= b->len[d] * floor(u / b->len[d]);
    if (u >= b->len[d]) u -= b->len[d]; /* floor round-off at the upper face */
  }
  return u;
}

/* Minimum image of a separation whose two ends were both wrapped by SpamBoxLocal. */
static inline double SpamBoxMinImage(double dx, double len, double half, int periodic)
{
  if (periodic) {
    dx = dx > half ? dx - len : dx;
    dx = dx < -half ? dx + len : dx;
  }
  return dx;
}

/* What the pair loops need of the box, unpacked once per pass: edge, half edge and
 * periodicity per direction (zero edges in directions the box does not have). */
typedef struct {
  double len[3], half[3];
  int    periodic[3];
} SpamImage;

static inline SpamImage SpamBoxImage(const SpamBox *b)
{
  SpamImage im = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  for (int d = 0; d < b->dim; d++) {
    im.len[d]      = b->len[d];
    im.half[d]     = 0.5 * b->len[d];
    im.periodic[d] = b->periodic[d] ? 1 : 0;
  }
  return im;
}

/* Minimum image of the separation u_i - u_j of two box-local coordinates along d. */
static inline double SpamImageDelta(const SpamImage *im, int d, double du)
{
  return SpamBoxMinImage(du, im->len[d], im->half[d], im->periodic[d]);
}

/* Checks the box against the kernel range: each periodic edge at least 2h so that a
 * particle meets at most one image of another. Raises a bad-input error naming `what`,
 * the option that set the box, otherwise. */
PetscErrorCode SpamBoxValidate(const SpamBox *b, double h, const char *what);
double         SpamBoxVolume(const SpamBox *b);
#endif
