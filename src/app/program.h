/* The spam-ark program (program.c): main() and the fuzz corpus's fork server call it. */
#ifndef SPAM_PROGRAM_H
#define SPAM_PROGRAM_H

/* Runs spam-ark on its command line; returns its exit code (0 done, 1 failure, 2 bad input,
 * 3 unstable). Starts and finalizes MPI and PETSc: once per process. */
int SpamArkProgram(int argc, char **argv);
#endif
