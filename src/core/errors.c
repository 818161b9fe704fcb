/* Error reporting: bad input prints one line; other errors keep PETSc's traceback. */
#include <spam/errors.h>
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>

/* PETSc reports a malformed number as "Input string VALUE has no numeric value" without
 * the option's name: find the option that carries VALUE so the line can name it. */
static void NameMalformedOption(const char *mess, char *out, size_t len)
{
  const char *p = strstr(mess, "Input string "), *q = strstr(mess, "Unknown logical value: ");
  const char *want = q ? "must be true or false" : "must be a number";
  char        value[256], *all = NULL;

  snprintf(out, len, "%s", mess);
  if (!(p && sscanf(p, "Input string %255s", value) == 1) && !(q && sscanf(q, "Unknown logical value: %255s", value) == 1)) return;
  if (PetscOptionsGetAll(NULL, &all) || !all) return;
  for (char *tok = strtok(all, " "), *prev = NULL; tok; prev = tok, tok = strtok(NULL, " ")) {
    if (prev && prev[0] == '-' && !strcmp(tok, value)) {
      snprintf(out, len, "%s = '%s': %s", prev, value, want);
      break;
    }
  }
  PetscFree(all);
}

/* The first report of a PETSC_ERR_USER_INPUT error is the user's message: print it alone
 * and stay silent while the error travels up the call stack. */
static PetscErrorCode SpamErrorHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  (void)ctx;
  /* A malformed option value (say -h abc) is detected inside PetscOptions*: report it as
   * bad input too, and pass the bad-input code up from here on. */
  if (p == PETSC_ERROR_INITIAL && fun && !strncmp(fun, "PetscOptions", 12)) n = PETSC_ERR_USER_INPUT;
  if (n == PETSC_ERR_USER_INPUT) {
    if (p == PETSC_ERROR_INITIAL) {
      PetscMPIInt rank = 0;
      MPI_Comm_rank(comm, &rank);
      char line[512];
      NameMalformedOption(mess, line, sizeof line);
      if (!rank) fprintf(stderr, "spam-ark: error: %s\n", line);
    }
    return n;
  }
  return PetscTraceBackErrorHandler(comm, line, fun, file, n, p, mess, NULL);
}

PetscErrorCode SpamInstallErrorHandler(void)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(SpamErrorHandler, NULL));
  PetscFunctionReturn(0);
}

/* A SUNDIALS flag name, from the package's own (allocating) name function. */
static void FlagName(char *(*namefn)(long), int flag, char *name, size_t len)
{
  char *s = namefn(flag);
  (void)snprintf(name, len, "%s", s ? s : "unknown");
  free(s);
}

static PetscErrorCode CheckSundials(char *(*namefn)(long), int flag, const char *call)
{
  PetscFunctionBeginUser;
  if (flag < 0) {
    char name[64];
    FlagName(namefn, flag, name, sizeof name);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "SUNDIALS call %s returned %d (%s)", call, flag, name);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCheckArkode(int flag, const char *call)
{
  return CheckSundials(ERKStepGetReturnFlagName, flag, call);
}

PetscErrorCode SpamCheckCvode(int flag, const char *call)
{
  return CheckSundials(CVodeGetReturnFlagName, flag, call);
}

PetscErrorCode SpamCheckAllowed(const char *opt, const char *val, const char *const *names, int n)
{
  char allowed[1024] = "";

  PetscFunctionBeginUser;
  for (int k = 0; k < n; k++)
    if (!strcmp(val, names[k])) PetscFunctionReturn(0);
  for (int k = 0; k < n; k++) {
    PetscCall(PetscStrlcat(allowed, k ? ", " : "", sizeof allowed));
    PetscCall(PetscStrlcat(allowed, names[k], sizeof allowed));
  }
  SPAM_BAD_INPUT(opt, val, "allowed: %s", allowed);
}
