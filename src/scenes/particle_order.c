/* Spatial order of the particles: cells of width h, taken row by row (y, then x) in 1D
 * and 2D and along a Morton (Z-order) curve in 3D. Particles that are near in space are
 * then near in memory, so the pair loops' gathers and scatters stay in cache. It matters
 * for input in arbitrary order: on a shuffled 1024^2 expansion the force pass took 8x as
 * long as on the same particles in lattice order (bench/README.md). In 2D the row order
 * beats the Morton curve, which jumps between quadrants: a force pass of the 1024^2 gas
 * took 48.7-48.8 ms in row order against 56.3-56.8 ms in Morton order (lattice input) and
 * 49.5-52.8 against 60.1-69.5 ms (shuffled input); three cell rows of 2D particles fit in
 * the cache, three planes of 3D particles may not. The order is made here at set-up and
 * again, with the same keys (cell_keys.c), after each migration (local_order.c); the
 * lattice scenes are built in an order that is already local. */
#include <spam/scene.h>
#include <spam/cell_keys.h>
#include <stdint.h>

typedef struct {
  uint64_t key;
  PetscInt row;
} OrderKey;

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
  OrderKey    *keys;
  SpamCellGrid grid;

  PetscFunctionBeginUser;
  SpamCellGridInit(&p->box, width, &grid);
  PetscCall(PetscMalloc1(p->n + 1, &keys));
  for (PetscInt i = 0; i < p->n; i++) {
    int c[3];
    SpamCellOf(&grid, &p->box, p->x + (size_t)i * p->dim, c);
    keys[i].key = SpamCellOrderKey(&grid, c);
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
