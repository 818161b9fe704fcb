/* SIGINT and SIGTERM during a run: the time loop finishes the step it is in, writes every
 * output at the time reached and ends with status "interrupted" (exit 130 or 143). A
 * second signal of the same kind ends the process at once (the handler resets itself). */
#ifndef SPAM_INTERRUPT_H
#define SPAM_INTERRUPT_H
#include <signal.h>
#include <petscsys.h>

/* The handlers that were there before (opaque: struct sigaction is POSIX, not C11). */
typedef struct SpamInterrupt SpamInterrupt;

/* Clears the flag and takes SIGINT and SIGTERM until SpamInterruptRestore, which puts
 * back the handlers found (PETSc's or the default) and frees *s (NULL: nothing to do). */
PetscErrorCode SpamInterruptInstall(SpamInterrupt **s);
PetscErrorCode SpamInterruptRestore(SpamInterrupt **s);
/* The signal received since SpamInterruptInstall (SIGINT or SIGTERM), or 0. */
int SpamInterruptSignal(void);
#endif
