/* MPI start-up defaults for a spam-ark started alone (core/mpi_start.c). */
#ifndef SPAM_MPI_START_H
#define SPAM_MPI_START_H

/* Before PetscInitialize: when no MPI launcher started this process, make OpenMPI start it
 * as an isolated singleton with the ob1 messaging layer and hwloc without its I/O-device
 * plugins, unless the user's environment says otherwise. Under mpiexec nothing changes. */
void SpamMpiSingletonDefaults(void);
#endif
