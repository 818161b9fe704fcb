/* The default that makes Open MPI's waiting ranks yield (src/app/mpi_yield.c): when mpiexec
 * started more ranks on the node than it has idle cores, and only then; a choice the user
 * made is kept. The decision is a function of the environment, the cores and the load, so
 * each case is given here rather than read from this machine. */
#include <stdio.h>
#include "mpi_yield.h"

static int failed;

static void Expect(int got, int want, const char *what)
{
  printf("%s: %s (got %d, want %d)\n", got == want ? "ok  " : "FAIL", what, got, want);
  failed += got != want;
}

int main(void)
{
  Expect(SpamMpiYieldWanted("2", NULL, 2, 0.0), 0, "2 ranks, 2 idle cores: poll");
  Expect(SpamMpiYieldWanted("2", NULL, 2, 0.4), 0, "2 ranks, 2 cores, load 0.4 rounds to 0: poll");
  Expect(SpamMpiYieldWanted("2", NULL, 2, 1.0), 1, "2 ranks, 2 cores, load 1: 1 idle core, yield");
  Expect(SpamMpiYieldWanted("2", NULL, 2, 7.9), 1, "2 ranks, 2 cores under load 8: yield");
  Expect(SpamMpiYieldWanted("3", NULL, 2, 0.0), 1, "3 ranks on 2 idle cores: yield");
  Expect(SpamMpiYieldWanted("8", NULL, 64, 3.0), 0, "8 ranks, 61 idle cores of 64: poll");
  Expect(SpamMpiYieldWanted("3", "0", 2, 5.0), 0, "the user's choice (0) is kept");
  Expect(SpamMpiYieldWanted("3", "1", 2, 5.0), 0, "the user's choice (1) is kept: nothing to set");
  Expect(SpamMpiYieldWanted(NULL, NULL, 2, 5.0), 0, "not started by mpiexec: nothing to decide");
  Expect(SpamMpiYieldWanted("1", NULL, 1, 5.0), 0, "one rank waits for no one: poll");
  Expect(SpamMpiYieldWanted("2x", NULL, 1, 5.0), 0, "a local size that is not a number: nothing");
  Expect(SpamMpiYieldWanted("4", NULL, -1, 0.0), 0, "cores unknown: nothing");
  printf("%d failed\n", failed);
  return failed != 0;
}
