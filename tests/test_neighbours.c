/* The half Verlet list holds exactly the pairs that brute force finds, in periodic and
 * open boxes of one to three dimensions, in boxes only 2h + skin wide, and with particles
 * exactly on cell faces; it is kept while particles move less than half the skin and
 * still covers every pair within h. */
#include <spam/neighbours.h>
#include "test_util.h"

/* Bit per pair (i < j) of the pairs brute force finds within r2max. */
static void BruteForce(const SpamBox *b, int n, const double *x, double r2max, unsigned char *in)
{
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++) {
      double r2 = 0.0;
      for (int d = 0; d < b->dim; d++) {
        const double dx = SpamBoxMinImage(SpamBoxLocal(b, d, x[i * b->dim + d]) - SpamBoxLocal(b, d, x[j * b->dim + d]), b->len[d], 0.5 * b->len[d], b->periodic[d]);
        r2 += dx * dx;
      }
      in[(size_t)i * n + j] = r2 < r2max;
    }
}

/* Compares the list with brute force; with exact set, equality, else coverage. A pair
 * may sit in the row of either particle, but only once. */
static PetscErrorCode Compare(TestCount *c, const char *name, const SpamBox *b, SpamNeighbours *nl, const double *x, double r2max, PetscBool exact)
{
  const int      n = nl->n;
  unsigned char *bf, *ls;
  long           missing = 0, extra = 0, dup = 0, npairs = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2((size_t)n * n, &bf, (size_t)n * n, &ls));
  BruteForce(b, n, x, r2max, bf);
  for (int i = 0; i < n; i++)
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j = nl->nbr[p], lo = PetscMin(i, j), hi = PetscMax(i, j);
      if (j == i) extra++;
      else if (ls[(size_t)lo * n + hi]++) dup++;
    }
  for (size_t k = 0; k < (size_t)n * n; k++) {
    npairs += bf[k];
    if (bf[k] && !ls[k]) missing++;
    if (exact && ls[k] && !bf[k]) extra++;
  }
  TestCheck(c, missing == 0 && extra == 0 && dup == 0 && npairs > 0, "%s: %ld brute-force pairs, list has %zu; missing %ld, extra %ld, duplicated %ld", name, npairs, nl->npairs, missing, extra, dup);
  PetscCall(PetscFree2(bf, ls));
  PetscFunctionReturn(0);
}

/* A build with three threads gives the very list of one thread. Each thread's buffer
 * is declared full, so that every block also goes through the growth between passes. */
static PetscErrorCode CompareThreaded(TestCount *c, const char *name, const SpamBox *b, const SpamNeighbours *nl1, const double *x)
{
  SpamNeighbours nl;
  PetscInt       bad;
  long           diff = 0;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursCreate(nl1->n, b, nl1->cutoff, nl1->skin, &nl));
  PetscCall(SpamNeighboursSetThreads(&nl, 3));
  for (int t = 0; t < 3; t++) nl.tbuf[t].cap = 1;
  PetscCall(SpamNeighboursUpdate(&nl, b, x, b->dim, PETSC_FALSE, &bad));
  for (int i = 0; i <= nl.n; i++) diff += nl.start[i] != nl1->start[i];
  for (size_t p = 0; p < PetscMin(nl.npairs, nl1->npairs); p++) diff += nl.nbr[p] != nl1->nbr[p];
  TestCheck(c, diff == 0 && nl.npairs == nl1->npairs && nl.grows >= 3, "%s: 3 threads build the same list (%zu pairs, %ld entries differ, %ld buffer grows)", name, nl.npairs, diff, nl.grows);
  PetscCall(SpamNeighboursDestroy(&nl));
  PetscFunctionReturn(0);
}

static PetscErrorCode RandomCase(TestCount *c, const char *name, const SpamBox *b, int n, double h, double skin, uint64_t seed)
{
  SpamNeighbours nl;
  double        *x;
  PetscInt       bad;
  const double   rc = h + skin;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1((size_t)n * b->dim, &x));
  for (int i = 0; i < n; i++)
    for (int d = 0; d < b->dim; d++) x[i * b->dim + d] = b->lo[d] + b->len[d] * TestUniform(&seed);
  PetscCall(SpamNeighboursCreate(n, b, h, skin, &nl));
  PetscCall(SpamNeighboursUpdate(&nl, b, x, b->dim, PETSC_FALSE, &bad));
  PetscCall(Compare(c, name, b, &nl, x, rc * rc, PETSC_TRUE));
  PetscCall(CompareThreaded(c, name, b, &nl, x));
  /* Move every particle by less than skin/2: no rebuild, and all pairs within h listed. */
  for (int i = 0; i < n; i++) {
    double u[3], norm = 0.0;
    for (int d = 0; d < b->dim; d++) {
      u[d] = TestUniform(&seed) - 0.5;
      norm += u[d] * u[d];
    }
    for (int d = 0; d < b->dim; d++) x[i * b->dim + d] += 0.49 * skin * u[d] / sqrt(norm + 1e-300);
  }
  const long builds = nl.builds;
  PetscCall(SpamNeighboursUpdate(&nl, b, x, b->dim, PETSC_FALSE, &bad));
  TestCheck(c, nl.builds == builds, "%s: moves below skin/2 keep the list (builds %ld -> %ld)", name, builds, nl.builds);
  PetscCall(Compare(c, name, b, &nl, x, h * h, PETSC_FALSE));
  /* One particle past skin/2: the list is rebuilt and exact again. */
  x[0] = nl.xref[0][0] + 0.51 * skin;
  PetscCall(SpamNeighboursUpdate(&nl, b, x, b->dim, PETSC_FALSE, &bad));
  TestCheck(c, nl.builds == builds + 1, "%s: a move past skin/2 rebuilds the list", name);
  PetscCall(Compare(c, name, b, &nl, x, rc * rc, PETSC_TRUE));
  PetscCall(SpamNeighboursDestroy(&nl));
  PetscCall(PetscFree(x));
  PetscFunctionReturn(0);
}

/* Particles on every cell face of a periodic box (and on the box faces themselves). */
static PetscErrorCode FaceCase(TestCount *c, int dim, double h, double skin)
{
  SpamBox        b = {dim, {-2, -2, -2}, {0, 0, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}};
  SpamNeighbours nl;
  int            m = 1, n = 1;
  double        *x;
  PetscInt       bad;
  char           name[64];

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) b.len[d] = 4.0 * (h + skin);
  PetscCall(SpamNeighboursCreate(1, &b, h, skin, &nl));
  const double w = nl.cellw[0];
  PetscCall(SpamNeighboursDestroy(&nl));
  m = (int)(b.len[0] / (0.5 * w) + 0.5) + 1; /* faces and mid-planes, both box faces */
  for (int d = 0; d < dim; d++) n *= m;
  PetscCall(PetscMalloc1((size_t)n * dim, &x));
  for (int i = 0; i < n; i++)
    for (int d = 0, r = i; d < dim; d++, r /= m) x[i * dim + d] = b.lo[d] + 0.5 * w * (r % m);
  PetscCall(SpamNeighboursCreate(n, &b, h, skin, &nl));
  PetscCall(SpamNeighboursUpdate(&nl, &b, x, dim, PETSC_TRUE, &bad));
  PetscCall(PetscSNPrintf(name, sizeof name, "D=%d particles on cell and box faces", dim));
  PetscCall(Compare(c, name, &b, &nl, x, (h + skin) * (h + skin), PETSC_TRUE));
  PetscCall(SpamNeighboursDestroy(&nl));
  PetscCall(PetscFree(x));
  PetscFunctionReturn(0);
}

/* Hostile boxes and positions: a box of 1e300 or a sparse one gets a capped
 * cell count and the exact list; a non-finite box is an error, not an index out of
 * range; a cell is in range for every coordinate, NaN and infinities included. */
static PetscErrorCode HostileCase(TestCount *c, double h, double skin)
{
  SpamBox        huge = {2, {0, 0, 0}, {1e300, 1e300, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
  SpamBox        sparse = {2, {-5e5, -5e5, 0}, {1e6, 1e6, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  SpamBox        nanbox = {2, {NAN, 0, 0}, {64, 64, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  SpamNeighbours nl;
  const int      n = 200;
  double         x[2 * 200];
  const double   probe[6] = {NAN, INFINITY, -INFINITY, 1e300, -1e300, 5e-324};
  uint64_t       seed = 7;
  PetscInt       bad;
  PetscErrorCode ierr;
  int            inrange = 1;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursCreate(n, &huge, h, skin, &nl));
  TestCheck(c, nl.ncells > 0 && (double)nl.ncells <= 1048576.0, "box edge 1e300: %d cells (%d x %d), capped at 2^20", nl.ncells, nl.ncell[0], nl.ncell[1]);
  for (int k = 0; k < 6; k++)
    for (int l = 0; l < 6; l++) {
      const double u[3] = {probe[k], probe[l], 0.0};
      const int    cell = SpamNeighboursCellOf(&nl, &huge, u);
      inrange &= cell >= 0 && cell < nl.ncells;
    }
  TestCheck(c, inrange, "cells of NaN, +-inf, +-1e300 and subnormal coordinates are in range");
  PetscCall(SpamNeighboursDestroy(&nl));
  /* 200 particles in a 40 x 40 patch of a periodic 1e6 x 1e6 box, some across its faces. */
  for (int i = 0; i < n; i++)
    for (int d = 0; d < 2; d++) x[2 * i + d] = (i % 2 ? 5e5 - 20.0 : -20.0) + 40.0 * TestUniform(&seed);
  PetscCall(SpamNeighboursCreate(n, &sparse, h, skin, &nl));
  PetscCall(SpamNeighboursUpdate(&nl, &sparse, x, 2, PETSC_FALSE, &bad));
  TestCheck(c, bad < 0 && (double)nl.ncells <= 1048576.0, "sparse 1e6 x 1e6 box: %d cells, capped at 2^20", nl.ncells);
  PetscCall(Compare(c, "sparse periodic 1e6 box", &sparse, &nl, x, (h + skin) * (h + skin), PETSC_TRUE));
  /* The same list object against a box whose corner has become NaN: an error. */
  sparse.lo[0] = NAN;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SpamNeighboursUpdate(&nl, &sparse, x, 2, PETSC_TRUE, &bad);
  PetscCall(PetscPopErrorHandler());
  TestCheck(c, ierr == PETSC_ERR_FP, "a NaN box corner at a build is PETSC_ERR_FP (got %d)", (int)ierr);
  PetscCall(SpamNeighboursDestroy(&nl));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SpamNeighboursCreate(n, &nanbox, h, skin, &nl);
  PetscCall(PetscPopErrorHandler());
  TestCheck(c, ierr != 0, "a list for a NaN box is refused (error %d)", (int)ierr);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount    c = {0, 0};
  const double h = 3.0, skin = 0.3;
  PetscCall(TestInitialize(&argc, &argv));
  for (int dim = 1; dim <= 3; dim++) {
    const int n = dim == 1 ? 300 : dim == 2 ? 600 : 700;
    for (int per = 0; per < 2; per++) {
      for (int narrow = 0; narrow < 2; narrow++) {
        SpamBox b = {dim, {0.5, -3.0, 1000.0}, {0, 0, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
        char    name[96];
        for (int d = 0; d < dim; d++) {
          b.len[d]      = narrow ? 2.0 * h + skin : (dim == 3 ? 14.0 : 23.0);
          b.periodic[d] = (PetscBool)per;
        }
        PetscCall(PetscSNPrintf(name, sizeof name, "D=%d %s box %s", dim, per ? "periodic" : "open", narrow ? "2h+skin wide" : "wide"));
        PetscCall(RandomCase(&c, name, &b, narrow && dim == 1 ? 40 : n, h, skin, 1234 + 17 * dim + 5 * per + narrow));
      }
    }
    /* Mixed: periodic in x only. */
    if (dim > 1) {
      SpamBox b = {dim, {0, 0, 0}, {19, 2 * h + skin, 2 * h + skin}, {PETSC_TRUE, PETSC_FALSE, PETSC_TRUE}};
      char    name[64];
      PetscCall(PetscSNPrintf(name, sizeof name, "D=%d mixed periodic/open", dim));
      PetscCall(RandomCase(&c, name, &b, 400, h, skin, 99 + dim));
    }
    PetscCall(FaceCase(&c, dim, h, skin));
  }
  PetscCall(HostileCase(&c, h, skin));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
