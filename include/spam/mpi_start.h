/* MPI start-up defaults for a spam-ark started alone (core/mpi_start.c). */
#ifndef SPAM_MPI_START_H
#define SPAM_MPI_START_H

/* Before PetscInitialize: when no MPI launcher started this process, make OpenMPI start it
 * as an isolated singleton with the ob1 messaging layer and hwloc without its I/O-device
 * plugins, unless the user's environment says otherwise. Under mpiexec nothing changes. */
void SpamMpiSingletonDefaults(void);

/* MPI_Init_thread. In the AddressSanitizer build, LeakSanitizer is told to ignore what it
 * allocates (OpenMPI keeps it to the end of the process and frees none of it); elsewhere the
 * call alone. Returns MPI_Init_thread's code. */
int SpamMpiInitThread(int *argc, char ***argv, int required, int *provided);
#endif
