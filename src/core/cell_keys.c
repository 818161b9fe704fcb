/* Cell coordinates and the keys of the cell orders (cell_keys.h). */
#include <spam/cell_keys.h>

void SpamCellGridInit(const SpamBox *box, double width, SpamCellGrid *g)
{
  int most = 1;

  g->dim = box->dim;
  for (int d = 0; d < 3; d++) {
    /* Clamped in floating point: the conversion of NaN or of a huge ratio is undefined. */
    double nc = d < box->dim ? floor(box->len[d] / width) : 1.0;
    if (!(nc >= 1.0)) nc = 1.0;
    if (nc > SPAM_CELL_MAX_PER_DIM) nc = SPAM_CELL_MAX_PER_DIM;
    g->ncell[d] = (int)nc;
    most        = PetscMax(most, g->ncell[d]);
  }
  for (g->bits = 0; (1 << g->bits) < most; g->bits++) {}
}

void SpamCellOf(const SpamCellGrid *g, const SpamBox *box, const double *x, int c[3])
{
  c[0] = c[1] = c[2] = 0;
  for (int d = 0; d < box->dim; d++) {
    const double ncell = g->ncell[d];
    double       k     = floor(SpamBoxLocal(box, d, x[d]) / box->len[d] * ncell);
    if (!(k >= 0.0)) k = 0.0; /* NaN fails this test too */
    if (k > ncell - 1.0) k = ncell - 1.0;
    c[d] = (int)k;
  }
}

/* Spreads the low 21 bits of v so that two zero bits follow each one. */
static uint64_t Spread3(uint64_t v)
{
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

uint64_t SpamCellOrderKey(const SpamCellGrid *g, const int c[3])
{
  uint64_t morton = 0, rowmajor = 0;
  for (int d = g->dim - 1; d >= 0; d--) {
    morton |= Spread3((uint64_t)c[d]) << d;
    rowmajor = rowmajor * (uint64_t)g->ncell[d] + (uint64_t)c[d];
  }
  return g->dim < 3 ? rowmajor : morton;
}

/* Hilbert index by Skilling's method (AIP Conf. Proc. 707, 381, 2004): the coordinates
 * are turned in place into the "transposed" index, whose bits, read plane by plane from
 * the most significant, are the curve position. */
uint64_t SpamCellHilbertKey(const SpamCellGrid *g, const int c[3])
{
  const int n = g->dim;
  uint32_t  a[3] = {(uint32_t)c[0], (uint32_t)c[1], (uint32_t)c[2]}, t = 0;
  uint64_t  key = 0;

  if (n == 1) return (uint64_t)c[0]; /* the curve of a line is the line */
  if (g->bits == 0) return 0;
  for (uint32_t q = 1u << (g->bits - 1); q > 1; q >>= 1) { /* undo the excess turns */
    const uint32_t p = q - 1;
    for (int i = 0; i < n; i++) {
      if (a[i] & q) a[0] ^= p; /* invert the low bits of the first axis */
      else {                   /* or swap them with axis i's */
        const uint32_t s = (a[0] ^ a[i]) & p;
        a[0] ^= s;
        a[i] ^= s;
      }
    }
  }
  for (int i = 1; i < n; i++) a[i] ^= a[i - 1]; /* Gray encoding */
  for (uint32_t q = 1u << (g->bits - 1); q > 1; q >>= 1)
    if (a[n - 1] & q) t ^= q - 1;
  for (int i = 0; i < n; i++) a[i] ^= t;
  for (int b = g->bits - 1; b >= 0; b--)
    for (int i = 0; i < n; i++) key = key << 1 | ((a[i] >> b) & 1u);
  return key;
}
