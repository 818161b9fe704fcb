/* Small helpers shared by the C unit tests: checks that count and report, a seeded
 * generator, and a simulation built from arrays. */
#ifndef SPAM_TEST_UTIL_H
#define SPAM_TEST_UTIL_H
#include <spam/sim.h>
#include <stdint.h>
#include <stdarg.h>

typedef struct {
  int passed, failed;
} TestCount;

/* MPI started as spam-ark starts it (SpamMpiInitThread: in the sanitizer build the leak
 * check then ignores OpenMPI's own allocations), then PETSc; TestFinalize ends both. */
PetscErrorCode TestInitialize(int *argc, char ***argv);
PetscErrorCode TestFinalize(void);

/* Records one check and prints it; the message says what was compared. */
void TestCheck(TestCount *c, int ok, const char *fmt, ...);
/* On several ranks: records a check whose outcome every rank already agrees on (each
 * test agrees on it its own way: all ranks' parts, or rank 0's verdict), printed once by
 * rank 0. */
void TestCheckAgreed(MPI_Comm comm, TestCount *c, int ok, const char *fmt, va_list ap);
/* On several ranks: a check that passes when ok_here holds on every rank (MPI_LAND). */
PetscErrorCode TestCheckAll(MPI_Comm comm, TestCount *c, int ok_here, const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(4, 5);
/* A value the pages quote (tests/README.md): prints "reading KEY VALUE" on the rank 0 of
 * comm, which tools/c_test_readings.py gathers into a readings JSON; a key printed several
 * times becomes its range. */
void TestReading(MPI_Comm comm, const char *key, double value);
/* Prints the closing line "N passed, N failed" and returns the exit code. */
int TestFinish(const TestCount *c);
/* Uniform in [0, 1) from a splitmix64 stream. */
double TestUniform(uint64_t *state);
/* A simulation of the isentropic gas with the given particles. */
/* The tensor-path model with Lucy's kernel of range h and unit mass. */
PetscErrorCode SpamTestModelSolid(int dim, double h, const SpamSolidParams *p, SpamModel *m);
PetscErrorCode TestMakeSim(const SpamBox *box, double h, double gamma, PetscInt n, const double *x, const double *v, SpamSim *sim);
#endif
