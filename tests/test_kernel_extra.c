/* A kernel added from outside the program reaches every use of the kernel list. The
 * test-only kernel test_tent is its header (kernel_extra/kernel_test_tent.h) and one row,
 * appended to src/kernels/kernel_list.h by kernel_extra/kernel_list_extra.h; this program
 * compiles src/kernels/ again with that row. Checked: the enum has the new kind
 * after the others; the registry makes it by name, lists it last and takes it from
 * -kernel; its shapes (the literal-kind switches, the run-time evaluators, w' and w'') are
 * its own and its normalisation is one; the pair walk dispatches it to its own shape; and a
 * kind beyond the list is an error in the walk and NaN in a shape, never Lucy. */
#include <spam/kernel.h>
#include <spam/mpi_start.h>
#include <pair/pair_walk.h>
#include <stdio.h>
#include <string.h>

typedef struct {
  int passed, failed;
} Count;

static void Check(Count *c, int ok, const char *what)
{
  printf("%s%s\n", ok ? "ok  : " : "FAIL: ", what);
  if (ok) c->passed++;
  else c->failed++;
}

static PetscErrorCode CheckEnumAndRegistry(Count *c)
{
  SpamKernel k;
  char       names[256];
  int        ok = 1;

  PetscFunctionBeginUser;
  Check(c, SPAM_KERNEL_TEST_TENT == SPAM_KERNEL_QUINTIC_SPLINE + 1 && SPAM_KERNEL_KINDS == SPAM_KERNEL_TEST_TENT + 1, "enum: SPAM_KERNEL_TEST_TENT follows the list's kinds and is counted in SPAM_KERNEL_KINDS");
  PetscCall(SpamKernelNames(names, sizeof names));
  Check(c, strlen(names) > 11 && !strcmp(names + strlen(names) - 11, ", test_tent"), "registry: the names end with test_tent");
  for (int dim = 1; dim <= 3; dim++) {
    const double cd[3] = {1.0, 10.0 / (3.0 * SPAM_PI), 15.0 / (4.0 * SPAM_PI)}, h = 2.5;
    PetscCall(SpamKernelCreate("test_tent", dim, h, &k));
    ok &= k.kind == SPAM_KERNEL_TEST_TENT && !strcmp(k.name, "test_tent") && k.smooth == 1;
    ok &= k.wnorm == cd[dim - 1] * pow(h, -dim) && k.gnorm == -6.0 * cd[dim - 1] * pow(h, -(dim + 2));
  }
  Check(c, ok, "registry: SpamKernelCreate(\"test_tent\") gives its kind, name, smoothness and norms in 1, 2 and 3D");
  PetscCall(PetscOptionsSetValue(NULL, "-kernel", "test_tent"));
  PetscCall(SpamKernelOptions(2, 3.0, &k));
  PetscCall(PetscOptionsClearValue(NULL, "-kernel"));
  Check(c, k.kind == SPAM_KERNEL_TEST_TENT, "options: -kernel test_tent (the list -help shows) chooses it");
  PetscFunctionReturn(0);
}

/* The integral of w over D-space by the midpoint rule in r (w is a polynomial in r on the
 * support, so the rule's error is O(1/N^2)). */
static double Normalisation(const SpamKernel *k)
{
  const int    N = 20000;
  const double area[3] = {2.0, 2.0 * SPAM_PI, 4.0 * SPAM_PI};
  double       sum = 0.0;

  for (int i = 0; i < N; i++) {
    const double r = (i + 0.5) * k->h / N;
    sum += area[k->dim - 1] * pow(r, k->dim - 1) * SpamKernelW(k, r * r);
  }
  return sum * k->h / N;
}

static PetscErrorCode CheckShapes(Count *c)
{
  int ok = 1, norm = 1, deriv = 1;

  PetscFunctionBeginUser;
  for (int dim = 1; dim <= 3; dim++) {
    SpamKernel k;
    PetscCall(SpamKernelCreate("test_tent", dim, 2.0, &k));
    norm &= fabs(Normalisation(&k) - 1.0) < 1e-8;
    for (double s = 0.0; s <= 1.25; s += 0.0625) {
      const double t = s < 1.0 ? 1.0 - s : 0.0, r = s * k.h, e = 1e-6;
      ok &= SpamKernelShapeF(SPAM_KERNEL_TEST_TENT, dim, s) == (1.0 + 2.0 * s) * t * t && SpamKernelShapeG(SPAM_KERNEL_TEST_TENT, dim, s) == t;
      ok &= SpamKernelShapeH(SPAM_KERNEL_TEST_TENT, dim, s) == (s < 1.0 ? 1.0 - 2.0 * s : 0.0);
      ok &= SpamKernelW(&k, r * r) == (s < 1.0 ? k.wnorm * (1.0 + 2.0 * s) * t * t : 0.0) && SpamKernelDWOverR(&k, r * r) == (s < 1.0 ? k.gnorm * t : 0.0);
      if (s > 0.0 && s < 1.0) deriv &= fabs(SpamKernelDW(&k, r) - (SpamKernelW(&k, (r + e) * (r + e)) - SpamKernelW(&k, (r - e) * (r - e))) / (2.0 * e)) < 1e-7 * k.wnorm;
    }
  }
  Check(c, ok, "shapes: F, G, H by literal kind and w, w'/r by run-time kind are test_tent's, zero beyond h");
  Check(c, deriv, "shapes: w'(r) agrees with a central difference of w");
  Check(c, norm, "shapes: the integral of w over D-space is one in 1, 2 and 3D");
  PetscFunctionReturn(0);
}

typedef struct {
  double w, g;
} Sums;

static inline __attribute__((always_inline)) void SumPair(const int dim, Sums *a, int i, int j, const double dx[3], double r2, double w, double g)
{
  (void)dim;
  (void)i;
  (void)j;
  (void)dx;
  (void)r2;
  a->w += w;
  a->g += g;
}
SPAM_PAIR_WALK(WalkSums, Sums, SumPair)

/* Three particles on a line, 0.5 and 1.5 apart (all pairs within h = 2.5), no images, no
 * ghosts: the half list 0-1, 0-2, 1-2. */
typedef struct {
  double         x[3], y[3];
  int            start[4], nbr[3], gstart[4];
  unsigned char  image[3];
  SpamNeighbours nl;
} Line;

static void LineInit(Line *L, int dim)
{
  *L = (Line){{0.0, 0.5, 2.0}, {0.0, 0.0, 0.0}, {0, 2, 3, 3}, {1, 2, 2}, {0, 0, 0, 0}, {0, 0, 0}, {0}};
  L->nl.dim = dim;
  L->nl.n   = 3;
  for (int d = 0; d < 3; d++) L->nl.u[d] = d ? L->y : L->x;
  L->nl.start  = L->start;
  L->nl.nbr    = L->nbr;
  L->nl.gstart = L->gstart;
  L->nl.gnbr   = L->nbr;
  L->nl.image  = L->image;
}

static PetscErrorCode CheckWalk(Count *c)
{
  int            ok = 1, other = 1;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  for (int dim = 1; dim <= 3; dim++) {
    const double r2[3] = {0.25, 4.0, 2.25};
    Line         L;
    SpamKernel   k, lucy;
    Sums         got = {0, 0}, want = {0, 0}, with_lucy = {0, 0};
    LineInit(&L, dim);
    PetscCall(SpamKernelCreate("test_tent", dim, 2.5, &k));
    PetscCall(SpamKernelCreate("lucy", dim, 2.5, &lucy));
    lucy.wnorm = k.wnorm; /* Lucy's shape with test_tent's norms: differs only in the shape */
    lucy.gnorm = k.gnorm;
    PetscCall(WalkSums(&L.nl, &k, &got));
    PetscCall(WalkSums(&L.nl, &lucy, &with_lucy));
    for (int p = 0; p < 3; p++) {
      want.w += SpamKernelW(&k, r2[p]);
      want.g += SpamKernelDWOverR(&k, r2[p]);
    }
    ok &= got.w == want.w && got.g == want.g;
    other &= got.w != with_lucy.w && got.g != with_lucy.g;
  }
  Check(c, ok, "walk: the pair walk runs test_tent's shape (sums of w and w'/r over a list equal the evaluators')");
  Check(c, other, "walk: the sums differ from Lucy's shape with the same norms");
  {
    Line       L;
    SpamKernel k;
    Sums       s = {0, 0};
    LineInit(&L, 2);
    PetscCall(SpamKernelCreate("test_tent", 2, 2.5, &k));
    k.kind = (SpamKernelKind)SPAM_KERNEL_KINDS; /* a kind beyond the list */
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    ierr = WalkSums(&L.nl, &k, &s);
    PetscCall(PetscPopErrorHandler());
    Check(c, ierr == PETSC_ERR_PLIB && s.w == 0.0 && s.g == 0.0, "walk: a kind beyond the list is an error and visits no pair");
    Check(c, isnan(SpamKernelShapeF(SPAM_KERNEL_KINDS, 2, 0.5)) && isnan(SpamKernelW(&k, 1.0)), "shapes: a kind beyond the list is NaN, not another kernel's shape");
  }
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  Count c = {0, 0};
  int   provided;

  /* MPI started as spam-ark starts it (out of LeakSanitizer's sight: OpenMPI keeps what its
   * start allocates); PETSc then leaves MPI_Finalize to this program. */
  if (SpamMpiInitThread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return 1;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(CheckEnumAndRegistry(&c));
  PetscCall(CheckShapes(&c));
  PetscCall(CheckWalk(&c));
  printf("%d passed, %d failed\n", c.passed, c.failed);
  PetscCall(PetscFinalize());
  if (MPI_Finalize() != MPI_SUCCESS) return 1;
  return c.failed ? 1 : 0;
}
