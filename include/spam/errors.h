/* Errors the user can fix (bad options or files) versus failures of the run. */
#ifndef SPAM_ERRORS_H
#define SPAM_ERRORS_H
#include <petscsys.h>
#include <sys/types.h>

/* Exit codes of spam-ark. */
#define SPAM_EXIT_OK        0
#define SPAM_EXIT_ERROR     1 /* a library or system failure                       */
#define SPAM_EXIT_BAD_INPUT 2 /* an option or input file the user must correct     */
#define SPAM_EXIT_UNSTABLE  3 /* the run went unstable and stopped cleanly          */

/* Raise a bad-input error: one line naming the option (or file:line), the value and what
 * is allowed. SpamInstallErrorHandler makes it print as exactly that line. */
#define SPAM_BAD_INPUT(what, value, fmt, ...) \
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s = '%s': " fmt, what, value, ##__VA_ARGS__)

/* Installs the handler that prints bad input (PETSC_ERR_USER_INPUT) and file-system
 * failures (PETSC_ERR_FILE_OPEN, _WRITE, _READ, _UNEXPECTED) as one line
 * "spam-ark: error: <message>", bytes outside printable ASCII escaped as \xNN; main exits
 * 2 for the first, 1 for the others. Other errors keep PETSc's traceback. */
PetscErrorCode SpamInstallErrorHandler(void);
/* Until PetscPopErrorHandler: an argument error while PETSc reads its options (prefix
 * "ts_*" names them in the message) is bad input, as one line. */
PetscErrorCode SpamPushPetscOptionsErrorHandler(const char *prefix);
/* in copied to out with every byte outside 0x20..0x7e written as \xNN (truncated to fit). */
void SpamEscape(const char *in, char *out, size_t len);
/* An error first reported by fun with code n is the system refusing memory (PETSc's
 * allocators, or PETSC_ERR_MEM): then the one line that says so, for an error handler that
 * raises it again elsewhere (as SpamRunAgreed does) with PETSC_ERR_MEM. */
PetscBool SpamErrorIsOutOfMemory(PetscErrorCode n, const char *fun);
void      SpamOutOfMemoryText(const char *fun, const char *mess, char *out, size_t len);
/* in copied to out, cut to 80 bytes with "..." when longer (a user's value in a message). */
void SpamClip(const char *in, char *out, size_t len);
/* The text of option opt as the user typed it (clipped), or v printed with %.17g when the
 * option is absent: bad-input messages show what the user wrote. */
PetscErrorCode SpamOptionText(const char *opt, double v, char *buf, size_t len);
/* What a file that is not a regular file is, for a refusal ("a FIFO (named pipe)", "a
 * directory", ...): an input that must be a regular file is checked before it is read. */
const char *SpamFileKind(mode_t mode);
/* Bad input unless val is one of names[0..n-1]; the message lists them. */
PetscErrorCode SpamCheckAllowed(const char *opt, const char *val, const char *const *names, int n);

/* Collective: every rank learns whether a local phase (its error code `local`) failed on
 * any rank, and all of them raise: the failing rank its own error, the others one naming
 * `what` (so that one rank's failure inside a collective sequence never hangs the others). */
PetscErrorCode SpamAgreeOnFailure(MPI_Comm comm, PetscErrorCode local, const char *what);
/* Collective on comm: fn(ctx) on rank 0 alone (root_only: a text file written once) or on
 * every rank. An error in it on any rank is raised on every rank, with the code and the
 * message of the lowest rank that failed, and printed once (agree.c): no rank is
 * left waiting in a collective for one that failed. */
PetscErrorCode SpamRunAgreed(MPI_Comm comm, PetscBool root_only, PetscErrorCode (*fn)(void *), void *ctx);
/* SUNDIALS return codes: a negative flag becomes a PETSc error carrying the flag name. */
PetscErrorCode SpamCheckArkode(int flag, const char *call);
#define PetscCallARK(call) PetscCall(SpamCheckArkode((call), #call))
/* ARKODE's linear-solver interface (ARKStepSetLinearSolver, ARKStepSetEpsLin, ...), whose
 * flags (ARKLS_*) have their own names. */
PetscErrorCode SpamCheckArkodeLs(int flag, const char *call);
#define PetscCallARKLS(call) PetscCall(SpamCheckArkodeLs((call), #call))
PetscErrorCode SpamCheckCvode(int flag, const char *call);
#define PetscCallCV(call) PetscCall(SpamCheckCvode((call), #call))
#endif
