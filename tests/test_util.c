#include "test_util.h"
#include <spam/mpi_start.h>
#include <stdarg.h>

void TestCheck(TestCount *c, int ok, const char *fmt, ...)
{
  va_list ap;
  printf("%s: ", ok ? "ok  " : "FAIL");
  va_start(ap, fmt);
  vprintf(fmt, ap);
  va_end(ap);
  printf("\n");
  if (ok) c->passed++;
  else c->failed++;
}

void TestCheckAgreed(MPI_Comm comm, TestCount *c, int ok, const char *fmt, va_list ap)
{
  int rank = 0;
  (void)MPI_Comm_rank(comm, &rank);
  if (ok) c->passed++;
  else c->failed++;
  if (rank) return;
  printf("%s: ", ok ? "ok  " : "FAIL");
  vprintf(fmt, ap);
  printf("\n");
  fflush(stdout);
}

PetscErrorCode TestCheckAll(MPI_Comm comm, TestCount *c, int ok_here, const char *fmt, ...)
{
  int     ok;
  va_list ap;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&ok_here, &ok, 1, MPI_INT, MPI_LAND, comm));
  va_start(ap, fmt);
  TestCheckAgreed(comm, c, ok, fmt, ap);
  va_end(ap);
  PetscFunctionReturn(0);
}

void TestReading(MPI_Comm comm, const char *key, double value)
{
  int rank = 0;
  (void)MPI_Comm_rank(comm, &rank);
  if (rank) return;
  printf("reading %s %.17g\n", key, value);
  fflush(stdout);
}

int TestFinish(const TestCount *c)
{
  printf("%d passed, %d failed\n", c->passed, c->failed);
  return c->failed ? 1 : 0;
}

double TestUniform(uint64_t *state)
{
  uint64_t z = (*state += 0x9E3779B97F4A7C15ULL);
  z          = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z          = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1.0p-53;
}

PetscErrorCode TestMakeSim(const SpamBox *box, double h, double gamma, PetscInt n, const double *x, const double *v, SpamSim *sim)
{
  SpamModel  model;
  SpamKernel kern;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelLucyInit(box->dim, h, &kern));
  PetscCall(SpamModelIsentropeSetUp(box->dim, &kern, 1.0, gamma, 1.0 / gamma, &model));
  PetscCall(SpamSimCreate(PETSC_COMM_SELF, &model, box, n, 0.1 * h, sim));
  { /* -threads T runs the pair passes and list builds with T OpenMP threads */
    PetscInt threads = 1;
    PetscCall(PetscOptionsGetInt(NULL, NULL, "-threads", &threads, NULL));
    sim->pair.threads = (int)threads;
  }
  PetscCall(SpamSimFill(sim, x, v, NULL));
  PetscCall(SpamSimSetUp(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTestModelSolid(int dim, double h, const SpamSolidParams *p, SpamModel *m)
{
  SpamKernel k;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelLucyInit(dim, h, &k));
  PetscCall(SpamModelSolidSetUp(dim, &k, 1.0, p, m));
  PetscFunctionReturn(0);
}

PetscErrorCode TestInitialize(int *argc, char ***argv)
{
  int provided;

  if (SpamMpiInitThread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return PETSC_ERR_LIB;
  return PetscInitialize(argc, argv, NULL, NULL);
}

/* PETSc leaves MPI_Finalize to whoever started MPI. */
PetscErrorCode TestFinalize(void)
{
  PetscErrorCode ierr = PetscFinalize();

  if (MPI_Finalize() != MPI_SUCCESS && !ierr) ierr = PETSC_ERR_LIB;
  return ierr;
}
