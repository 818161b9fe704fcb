/* Spatial order of the particles: cells of width h, taken row by row (y, then x) in 1D
 * and 2D and along a Morton (Z-order) curve in 3D. Particles that are near in space are
 * then near in memory, so the pair loops' gathers and scatters stay in cache. It matters
 * for input in arbitrary order: on a shuffled 1024^2 expansion the force pass took 8x as
 * long as on the same particles in lattice order (bench/README.md). In 2D the row order
 * beats the Morton curve, which jumps between quadrants: a force pass of the 1024^2 gas
 * took 48.7-48.8 ms in row order against 56.3-56.8 ms in Morton order (lattice input) and
 * 49.5-52.8 against 60.1-69.5 ms (shuffled input); three cell rows of 2D particles fit in
 * the cache, three planes of 3D particles may not. The order is fixed at set-up; the
 * lattice scenes are built in an order that is already local. */
#include <spam/scene.h>
#include <stdint.h>

typedef struct {
  uint64_t key;
  PetscInt row;
} OrderKey;

/* Spreads the low 21 bits of c so that two zero bits follow each one. */
static uint64_t Spread3(uint64_t c)
{
  c &= 0x1fffff;
  c = (c | c << 32) & 0x1f00000000ffffULL;
  c = (c | c << 16) & 0x1f0000ff0000ffULL;
  c = (c | c << 8) & 0x100f00f00f00f00fULL;
  c = (c | c << 4) & 0x10c30c30c30c30c3ULL;
  c = (c | c << 2) & 0x1249249249249249ULL;
  return c;
}

/* Key of the cell of point x; points outside an open box fall into edge cells. In 1D
 * and 2D the cells are taken row by row (y, then x); in 3D along a Morton curve. */
static uint64_t CellKey(const SpamBox *b, double width, const double *x)
{
  uint64_t key = 0, rowmajor = 0;
  for (int d = b->dim - 1; d >= 0; d--) {
    /* At most 2^21 cells per direction (the Morton key's bits; 2^42 row-major keys fit
     * too), and c clamped in floating point before the conversion, which is undefined
     * for NaN and out-of-range values: NaN fails the first test. */
    const double ncell = PetscMin(PetscMax(1.0, floor(b->len[d] / width)), 2097152.0);
    double       c     = floor(SpamBoxLocal(b, d, x[d]) / b->len[d] * ncell);
    if (!(c >= 0.0)) c = 0.0;
    if (c > ncell - 1.0) c = ncell - 1.0;
    key |= Spread3((uint64_t)c) << d;
    rowmajor = rowmajor * (uint64_t)ncell + (uint64_t)c;
  }
  return b->dim < 3 ? rowmajor : key;
}

/* Ties keep the input order, so the order is a function of the positions alone. */
static int CompareKeys(const void *a, const void *b)
{
  const OrderKey *p = a, *q = b;
  if (p->key != q->key) return p->key < q->key ? -1 : 1;
  return (p->row > q->row) - (p->row < q->row);
}

/* Gathers rows of k doubles: a[i] = old a[row_of[i]]. */
static PetscErrorCode Permute(double *a, PetscInt n, int k, const PetscInt *row_of)
{
  double *tmp;

  PetscFunctionBeginUser;
  if (!a) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1((size_t)n * k + 1, &tmp));
  PetscCall(PetscArraycpy(tmp, a, (size_t)n * k));
  for (PetscInt i = 0; i < n; i++)
    for (int c = 0; c < k; c++) a[(size_t)i * k + c] = tmp[(size_t)row_of[i] * k + c];
  PetscCall(PetscFree(tmp));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamParticlesSortByCell(SpamParticles *p, double width, PetscInt *row_of)
{
  OrderKey *keys;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(p->n + 1, &keys));
  for (PetscInt i = 0; i < p->n; i++) {
    keys[i].key = CellKey(&p->box, width, p->x + (size_t)i * p->dim);
    keys[i].row = i;
  }
  qsort(keys, (size_t)p->n, sizeof *keys, CompareKeys);
  for (PetscInt i = 0; i < p->n; i++) row_of[i] = keys[i].row;
  PetscCall(PetscFree(keys));
  PetscCall(Permute(p->x, p->n, p->dim, row_of));
  PetscCall(Permute(p->v, p->n, p->dim, row_of));
  PetscCall(Permute(p->e, p->n, 1, row_of));
  PetscCall(Permute(p->rho, p->n, 1, row_of));
  PetscCall(Permute(p->sigma, p->n, SpamStressComponents(p->dim), row_of));
  PetscCall(Permute(p->m, p->n, 1, row_of));
  if (p->id) /* ids follow their particles */
    for (PetscInt i = 0; i < p->n; i++) p->id[i] = row_of[i];
  PetscFunctionReturn(0);
}
