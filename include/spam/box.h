/* The simulation box: lower corner, edge lengths and which directions are periodic. */
#ifndef SPAM_BOX_H
#define SPAM_BOX_H
#include <math.h>
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

/* What the pair loops need of the box, unpacked once per pass: edge and half edge per
 * direction. A direction that is not periodic (or that the box does not have) gets an
 * infinite half edge, so the minimum image below is two selects without a branch on
 * periodicity, which lets the compiler vectorise the pair loops. */
typedef struct {
  double len[3], half[3];
} SpamImage;

static inline SpamImage SpamBoxImage(const SpamBox *b)
{
  SpamImage im = {{0, 0, 0}, {INFINITY, INFINITY, INFINITY}};
  for (int d = 0; d < b->dim; d++) {
    if (!b->periodic[d]) continue;
    im.len[d]  = b->len[d];
    im.half[d] = 0.5 * b->len[d];
  }
  return im;
}

/* Minimum image of the separation u_i - u_j of two box-local coordinates along d; the
 * same value as SpamBoxMinImage. */
static inline double SpamImageDelta(const SpamImage *im, int d, double du)
{
  /* The shift is selected, the subtraction always done (du - 0 is du), so that no
   * floating-point operation is conditional: SSE2 has no masked arithmetic. The edge is
   * read before the choice: read only when chosen, through a pointer the compiler may not
   * assume readable, it kept the force pass's pair loop scalar in the rows of particles
   * near a periodic face (callgrind, gas N = 16384: 34 instructions a pair instead of
   * about 17 in the vector loop). */
  const double len = im->len[d];
  du -= du > im->half[d] ? len : 0.0;
  du += du < -im->half[d] ? len : 0.0;
  return du;
}

/* Checks the box against the kernel range: each periodic edge at least 2h so that a
 * particle meets at most one image of another. Raises a bad-input error naming `what`,
 * the option that set the box, otherwise. */
PetscErrorCode SpamBoxValidate(const SpamBox *b, double h, const char *what);
/* A particle's position x against the closed box [lo, lo + len] in dim directions, as a
 * particle file's rows are checked (and a checkpoint's, restart_check.c): the first
 * direction in which x lies outside it across a face that bounds (faces[2d] low,
 * faces[2d + 1] high; NULL: every face), with the refusal's text in why ("y = -3 lies
 * outside the box, 0 <= y <= 8"); -1 when none. A non-finite coordinate lies outside. */
int SpamBoxOutside(int dim, const double *lo, const double *len, const PetscBool *faces, const double *x, char *why, size_t n);
#endif
