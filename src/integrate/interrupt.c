/* Catching SIGINT and SIGTERM so that an interrupted run still ends with complete files. */
#define _DEFAULT_SOURCE /* sigaction's SA_RESETHAND and SA_RESTART are POSIX, not C11 */
#include <spam/interrupt.h>
#include <errno.h>

/* PETSc 3.18 (Debian's build) leaves SIGINT and SIGTERM at their default after
 * PetscInitialize (its handler takes SIGHUP, SIGQUIT, SIGSEGV and others), so nothing
 * fights this handler; Restore puts back whatever was there in any case. */
struct SpamInterrupt {
  struct sigaction old_int, old_term;
};

/* The program's one global: a signal handler has no argument through which it could reach
 * the run, and a volatile sig_atomic_t is the only object C lets a handler write safely.
 * The handler only records which signal came; the time loop does the work. */
static volatile sig_atomic_t spam_signal_received = 0;

static void OnSignal(int sig)
{
  spam_signal_received = sig;
}

/* SA_RESETHAND: the first signal is caught once and the disposition goes back to the
 * default, so a second of the same kind ends the process at once (a user who presses
 * Ctrl-C twice means it). SA_RESTART: a write or read under way is resumed, not failed
 * with EINTR. */
static PetscErrorCode Take(int sig, struct sigaction *old)
{
  struct sigaction sa;

  PetscFunctionBeginUser;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = OnSignal;
  sa.sa_flags   = SA_RESETHAND | SA_RESTART;
  sigemptyset(&sa.sa_mask);
  PetscCheck(!sigaction(sig, &sa, old), PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install a handler for signal %d: %s", sig, strerror(errno));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamInterruptInstall(SpamInterrupt **s)
{
  PetscFunctionBeginUser;
  spam_signal_received = 0;
  PetscCall(PetscNew(s));
  PetscCall(Take(SIGINT, &(*s)->old_int));
  PetscCall(Take(SIGTERM, &(*s)->old_term));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamInterruptRestore(SpamInterrupt **s)
{
  int e = 0;

  PetscFunctionBeginUser;
  if (!*s) PetscFunctionReturn(0);
  if (sigaction(SIGINT, &(*s)->old_int, NULL) || sigaction(SIGTERM, &(*s)->old_term, NULL)) e = errno;
  PetscCall(PetscFree(*s));
  PetscCheck(!e, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot restore the signal handlers: %s", strerror(e));
  PetscFunctionReturn(0);
}

int SpamInterruptSignal(void)
{
  return (int)spam_signal_received;
}
