/* The command line before PETSc reads it (core/argv_check.c). */
#ifndef SPAM_ARGV_H
#define SPAM_ARGV_H
#include <mpi.h>

/* Before MPI_Init: rewrites --help and --version to -help and -version and answers
 * -version ("spam-ark VERSION"). Returns -1 to go on, else the exit code (0). */
int SpamArgvEarly(int argc, char **argv);

/* After MPI_Init, before PetscInitialize (collective on comm): checks the command line,
 * every -options_file argument (and the -options_file lines inside those files), the
 * petscrc files PETSc reads by itself and PETSC_OPTIONS the way PETSc would read them, so that a missing, unreadable or malformed file, an option name
 * PETSc cannot read, or more options than its table holds is one line of bad input, printed
 * by one rank, not PETSc's abort on every rank. Returns -1 to go on, else the exit code (2
 * after the line was printed). An installed spam-ark reads a relative -options_file missing
 * from the working directory from its share directory ($PREFIX/share/spam/options/...),
 * saying so (core/argv_check.c). */
int SpamArgvCheck(MPI_Comm comm, int argc, char **argv);
#endif
