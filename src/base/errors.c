/* Error reporting: bad input, file-system failures and memory exhaustion print one line
 * each; other errors (a bug) keep PETSc's traceback. Every printed byte outside printable
 * ASCII is escaped as \xNN, so a hostile file name or value can neither break the line nor
 * reach the terminal raw. */
#define _DEFAULT_SOURCE /* S_ISSOCK: POSIX, not C11 */
#include <spam/errors.h>
#include <sys/stat.h>
#include <arkode/arkode_erkstep.h>
#include <arkode/arkode_arkstep.h>
#include <cvode/cvode.h>

void SpamEscape(const char *in, char *out, size_t len)
{
  static const char hex[] = "0123456789abcdef";
  size_t            k     = 0;

  if (!len) return;
  for (const unsigned char *p = (const unsigned char *)in; p && *p; p++) {
    if (*p >= 0x20 && *p < 0x7f) {
      if (k + 1 >= len) break;
      out[k++] = (char)*p;
    } else {
      if (k + 4 >= len) break;
      out[k++] = '\\';
      out[k++] = 'x';
      out[k++] = hex[*p >> 4];
      out[k++] = hex[*p & 15];
    }
  }
  out[k] = 0;
}

void SpamClip(const char *in, char *out, size_t len)
{
  const size_t keep = len > 84 ? 80 : (len > 4 ? len - 4 : 0);

  if (!len) return;
  if (strlen(in) < len && strlen(in) <= 80) {
    (void)snprintf(out, len, "%s", in);
    return;
  }
  (void)snprintf(out, len, "%.*s...", (int)keep, in);
}

PetscErrorCode SpamOptionText(const char *opt, double v, char *buf, size_t len)
{
  char      raw[256] = "";
  PetscBool set      = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, opt, raw, sizeof raw, &set));
  if (set && raw[0]) SpamClip(raw, buf, len);
  else (void)snprintf(buf, len, "%.17g", v);
  PetscFunctionReturn(0);
}

/* The text between 'start' and 'stop' in mess (PETSc's "Input string X has no numeric
 * value"), or the rest of the message after 'start'. */
static PetscBool Between(const char *mess, const char *start, const char *stop, char *out, size_t len)
{
  const char *p = strstr(mess, start), *q;

  if (!p) return PETSC_FALSE;
  p += strlen(start);
  q = stop ? strstr(p, stop) : NULL;
  if (!q) q = p + strlen(p);
  (void)snprintf(out, len, "%.*s", (int)(q - p), p);
  return PETSC_TRUE;
}

/* True when value is the whole of tok or one of its comma-separated elements. A value as
 * long as the buffer it was copied into was cut (PETSc's message or ours): then its start
 * must match. */
static PetscBool HoldsValue(const char *tok, const char *value, size_t cap)
{
  const size_t    n   = strlen(value);
  const PetscBool cut = (PetscBool)(n + 1 >= cap);

  if (!n) return PETSC_FALSE;
  for (const char *p = tok; p; p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL)
    if (!strncmp(p, value, n) && (cut || p[n] == 0 || p[n] == ',')) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* PETSc reports a malformed value as "Input string VALUE has no numeric value" or
 * "Unknown logical value: VALUE" without the option's name: find the option that carries
 * VALUE (alone or as an element of an array) so the line can name it. */
static void NameMalformedOption(const char *mess, char *out, size_t len)
{
  char        value[256], first[256], *all = NULL;
  const char *want = "must be a number";

  (void)snprintf(out, len, "%s", mess);
  if (Between(mess, "Unknown logical value: ", NULL, value, sizeof value)) want = "must be true or false (or 1, 0, yes, no)";
  else if (Between(mess, "Input string ", " has no integer value", value, sizeof value) && strstr(mess, "has no integer value")) want = "must be an integer";
  else if (!Between(mess, "Input string ", " has no numeric value", value, sizeof value)) return;
  if (PetscOptionsGetAll(NULL, &all) || !all) return;
  (void)snprintf(first, sizeof first, "%.*s", (int)strcspn(value, " "), value); /* the listing splits at spaces */
  for (char *tok = strtok(all, " "), *prev = NULL; tok; prev = tok, tok = strtok(NULL, " ")) {
    if (prev && prev[0] == '-' && HoldsValue(tok, first, sizeof first)) {
      char shown[100];
      SpamClip(strchr(value, ' ') ? value : tok, shown, sizeof shown);
      (void)snprintf(out, len, "%s = '%s': %s", prev, shown, want);
      break;
    }
  }
  (void)PetscFree(all);
}

/* Failures of the system rather than of the program: a file that cannot be opened, read
 * or written, and memory the system refused (an allocation failed, or a size past what
 * an array can index). The user can act on them: one line, exit 1, no traceback. */
static PetscBool IsSystemError(PetscErrorCode n)
{
  return (PetscBool)(n == PETSC_ERR_FILE_OPEN || n == PETSC_ERR_FILE_WRITE || n == PETSC_ERR_FILE_READ || n == PETSC_ERR_FILE_UNEXPECTED || n == PETSC_ERR_MEM);
}

/* PETSc's allocators: a failure there is the system refusing memory, whatever code PETSc
 * 3.18 attaches to it (Debian's 3.18.5 was seen to report code 54, with the caller's name
 * as the message). */
static PetscBool IsAllocator(const char *fun)
{
  return (PetscBool)(fun && (!strncmp(fun, "PetscMalloc", 11) || !strncmp(fun, "PetscCalloc", 11) || !strncmp(fun, "PetscRealloc", 12) || !strncmp(fun, "PetscTrMalloc", 13)));
}

PetscBool SpamErrorIsOutOfMemory(PetscErrorCode n, const char *fun)
{
  return (PetscBool)(n == PETSC_ERR_MEM || IsAllocator(fun));
}

/* An allocator's own message names no size the user could act on: say what ran out, and
 * where. */
void SpamOutOfMemoryText(const char *fun, const char *mess, char *out, size_t len)
{
  const char *m = mess && mess[0] ? mess : NULL;

  if (IsAllocator(fun)) (void)snprintf(out, len, "out of memory: %s failed (%s); the run needs more memory than the system gives it", fun, m ? m : "no detail");
  else (void)snprintf(out, len, "%s", m ? m : "out of memory"); /* a size past an index's range says so itself */
}

/* The line of a system failure. */
static void SystemErrorText(PetscErrorCode n, const char *fun, const char *mess, char *out, size_t len)
{
  const char *m = mess && mess[0] ? mess : NULL;

  if (n == PETSC_ERR_MEM) SpamOutOfMemoryText(fun, mess, out, len);
  else (void)snprintf(out, len, "%s", m ? m : "file error");
}

/* The first report of a bad-input, file or memory error is the user's message: print it
 * alone, as one escaped line, and stay silent while the error travels up the call stack. */
static PetscErrorCode SpamErrorHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  (void)ctx;
  /* A malformed option value (say -h abc) is detected inside PetscOptions*: report it as
   * bad input too, and pass the bad-input code up from here on. Likewise a failed
   * allocation goes up as PETSC_ERR_MEM. */
  if (p == PETSC_ERROR_INITIAL && fun && !strncmp(fun, "PetscOptions", 12)) n = PETSC_ERR_USER_INPUT;
  else if (p == PETSC_ERROR_INITIAL && IsAllocator(fun)) n = PETSC_ERR_MEM;
  if (n == PETSC_ERR_USER_INPUT || IsSystemError(n)) {
    if (p == PETSC_ERROR_INITIAL) {
      PetscMPIInt rank = 0;
      char        raw[1024], text[1024];
      /* Bad input is found alike on every rank (each reads the same options and files):
       * rank 0 of the run says it, once. A file or memory error is a rank's own. */
      MPI_Comm_rank(n == PETSC_ERR_USER_INPUT ? PETSC_COMM_WORLD : comm, &rank);
      if (n == PETSC_ERR_USER_INPUT) NameMalformedOption(mess ? mess : "", raw, sizeof raw);
      else SystemErrorText(n, fun, mess, raw, sizeof raw);
      SpamEscape(raw, text, sizeof text);
      if (!rank) fprintf(stderr, "spam-ark: error: %s\n", text);
    }
    return n;
  }
  return PetscTraceBackErrorHandler(comm, line, fun, file, n, p, mess, NULL);
}

/* While PETSc reads its own options (TSSetFromOptions), a wrong argument is a bad value of
 * one of them (say -ts_adapt_dt_max 1e-310 below the smallest step): bad input, one line. */
static PetscErrorCode SpamPetscOptionsErrorHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  if (p == PETSC_ERROR_INITIAL && (n == PETSC_ERR_ARG_OUTOFRANGE || n == PETSC_ERR_ARG_WRONG || n == PETSC_ERR_ARG_UNKNOWN_TYPE || n == PETSC_ERR_ARG_INCOMP)) {
    char raw[1024];
    (void)snprintf(raw, sizeof raw, "a -%s option of PETSc's: %s", (const char *)ctx, mess ? mess : "bad value");
    return SpamErrorHandler(comm, line, fun, file, PETSC_ERR_USER_INPUT, p, raw, NULL);
  }
  return SpamErrorHandler(comm, line, fun, file, n, p, mess, NULL);
}

PetscErrorCode SpamPushPetscOptionsErrorHandler(const char *prefix)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(SpamPetscOptionsErrorHandler, (void *)prefix));
  PetscFunctionReturn(0);
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

PetscErrorCode SpamCheckArkodeLs(int flag, const char *call)
{
  return CheckSundials(ARKStepGetLinReturnFlagName, flag, call);
}

PetscErrorCode SpamCheckCvode(int flag, const char *call)
{
  return CheckSundials(CVodeGetReturnFlagName, flag, call);
}

PetscErrorCode SpamCheckAllowed(const char *opt, const char *val, const char *const *names, int n)
{
  char allowed[1024] = "", shown[100];

  PetscFunctionBeginUser;
  for (int k = 0; k < n; k++)
    if (!strcmp(val, names[k])) PetscFunctionReturn(0);
  for (int k = 0; k < n; k++) {
    PetscCall(PetscStrlcat(allowed, k ? ", " : "", sizeof allowed));
    PetscCall(PetscStrlcat(allowed, names[k], sizeof allowed));
  }
  SpamClip(val, shown, sizeof shown);
  SPAM_BAD_INPUT(opt, shown, "allowed: %s", allowed);
}

const char *SpamFileKind(mode_t m)
{
  if (S_ISREG(m)) return "a regular file";
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}
