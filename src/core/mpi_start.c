/* A spam-ark started on its own is one MPI process, yet OpenMPI's defaults start a helper
 * daemon for the singleton and probe the UCX network layer at MPI_Init: most of the start-up
 * of a short run (measured in bench/README.md "Start-up"). An isolated singleton with the
 * ob1 messaging layer needs neither and runs the same program. Only defaults: a variable the
 * user set is kept, and a process started by mpiexec (which sets OMPI_COMM_WORLD_SIZE or
 * PMIX_RANK) is left to its launcher's choices. The environment is the one place OpenMPI
 * reads these from before MPI_Init. */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <stdlib.h>
#include <spam/mpi_start.h>

void SpamMpiSingletonDefaults(void)
{
  if (getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_RANK")) return;
  (void)setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  (void)setenv("OMPI_MCA_pml", "ob1", 0);
}
