/* Open MPI's ranks wait for messages by polling: a waiting rank keeps its core at 100 %. With
 * a core per rank that costs nothing, but when the ranks outnumber the idle cores a polling
 * rank takes CPU time from the rank it waits for: 2 ranks on a 2-core machine busy with
 * other work ran several times slower than one rank, and faster once the waiting ranks
 * yielded (measured in docs/parallel.md). Open MPI yields by itself only when it counts more ranks
 * than slots, which it does not when other programs keep the cores busy. So the default is
 * set here, in the environment Open MPI reads at MPI_Init, when this node's ranks
 * (OMPI_COMM_WORLD_LOCAL_SIZE, set by mpiexec) exceed its idle cores: the online cores less
 * the one-minute load average (rounded), the cores other work keeps busy. Not the affinity
 * mask: mpiexec binds each rank to its own core, so every rank would see one. A choice the
 * user made (OMPI_MCA_mpi_yield_when_idle set to anything) is kept. */
#define _DEFAULT_SOURCE /* getloadavg, setenv */
#include <math.h>
#include <stdlib.h>
#include <unistd.h>
#include "mpi_yield.h"

int SpamMpiYieldWanted(const char *local_size, const char *user_choice, long cores, double load)
{
  const long busy = load > 0 ? (long)lround(load) : 0;
  long       ranks;
  char      *end;

  if (!local_size || user_choice || cores < 1) return 0;
  ranks = strtol(local_size, &end, 10);
  if (end == local_size || *end || ranks < 2) return 0;
  return ranks > (cores > busy ? cores - busy : 0);
}

int SpamMpiYieldDefault(void)
{
  double load[1] = {0.0};

  if (getloadavg(load, 1) != 1) load[0] = 0.0; /* unknown: count every core idle */
  if (!SpamMpiYieldWanted(getenv("OMPI_COMM_WORLD_LOCAL_SIZE"), getenv("OMPI_MCA_mpi_yield_when_idle"), sysconf(_SC_NPROCESSORS_ONLN), load[0])) return 0;
  return setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0) == 0;
}
