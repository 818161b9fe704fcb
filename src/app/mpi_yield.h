/* Whether Open MPI's waiting ranks yield their core (mpi_yield.c). */
#ifndef SPAM_MPI_YIELD_H
#define SPAM_MPI_YIELD_H

/* The decision alone: yield when local_size (OMPI_COMM_WORLD_LOCAL_SIZE, NULL outside
 * mpiexec) names 2 or more ranks and they exceed the idle cores, the online cores less the
 * load average rounded; never when the user chose (user_choice: the variable's value, or
 * NULL) or the cores are unknown (cores < 1). */
int SpamMpiYieldWanted(const char *local_size, const char *user_choice, long cores, double load);
/* Before MPI_Init: applies the decision to this process's environment (sets
 * OMPI_MCA_mpi_yield_when_idle=1). Returns 1 when it set the default, 0 otherwise. */
int SpamMpiYieldDefault(void);
#endif
