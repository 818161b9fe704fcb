/* Errors the user can fix (bad options or files) versus failures of the run. */
#ifndef SPAM_ERRORS_H
#define SPAM_ERRORS_H
#include <petscsys.h>

/* Exit codes of spam-ark. */
#define SPAM_EXIT_OK        0
#define SPAM_EXIT_ERROR     1 /* a library or system failure                       */
#define SPAM_EXIT_BAD_INPUT 2 /* an option or input file the user must correct     */
#define SPAM_EXIT_UNSTABLE  3 /* the run went unstable and stopped cleanly          */

/* Raise a bad-input error: one line naming the option (or file:line), the value and what
 * is allowed. SpamInstallErrorHandler makes it print as exactly that line. */
#define SPAM_BAD_INPUT(what, value, fmt, ...) \
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s = '%s': " fmt, what, value, ##__VA_ARGS__)

PetscErrorCode SpamInstallErrorHandler(void);
/* Bad input unless val is one of names[0..n-1]; the message lists them. */
PetscErrorCode SpamCheckAllowed(const char *opt, const char *val, const char *const *names, int n);

/* SUNDIALS return codes: a negative flag becomes a PETSc error carrying the flag name. */
PetscErrorCode SpamCheckArkode(int flag, const char *call);
#define PetscCallARK(call) PetscCall(SpamCheckArkode((call), #call))
PetscErrorCode SpamCheckCvode(int flag, const char *call);
#define PetscCallCV(call) PetscCall(SpamCheckCvode((call), #call))
#endif
