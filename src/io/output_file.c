/* Checked, atomic file writes: a new temporary, every write checked, rename when complete. */
#define _DEFAULT_SOURCE /* open flags, flock, lstat, gethostname: POSIX, not C11 */
#include <spam/output.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

long SpamTestFailWriteAt(const char *path)
{
  const char *env = getenv("SPAM_TEST_FAIL_WRITE"), *base = strrchr(path, '/'), *colon;
  char       *end;
  long        n;

  if (!env || !(colon = strrchr(env, ':'))) return 0;
  base = base ? base + 1 : path;
  if ((size_t)(colon - env) != strlen(base) || strncmp(env, base, (size_t)(colon - env))) return 0;
  n = strtol(colon + 1, &end, 10);
  return *end || n < 1 ? 0 : n;
}

void SpamTestPauseAfterTemp(const char *path)
{
  const char           *env = getenv("SPAM_TEST_PAUSE_TEMP"), *base = strrchr(path, '/'), *colon;
  const struct timespec tick = {0, 10000000}; /* 10 ms */

  if (!env || !(colon = strchr(env, ':')) || !colon[1]) return;
  base = base ? base + 1 : path;
  if ((size_t)(colon - env) != strlen(base) || strncmp(env, base, (size_t)(colon - env))) return;
  for (int k = 0; k < 6000 && access(colon + 1, F_OK); k++) (void)nanosleep(&tick, NULL); /* at most 60 s */
}

/* The temporary's name carries the pid, so a name left by someone else (a symlink, say)
 * is never opened; O_EXCL | O_NOFOLLOW refuses it even if the pid repeats. */
PetscErrorCode SpamTempCreate(const char *path, char *tmp, size_t len, int *fd)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(tmp, len, "%s.%ld.tmp", path, (long)getpid()));
  /* read-write: what was written is read back through this descriptor (SpamFileContents) */
  *fd = open(tmp, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  PetscCheck(*fd >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create %s: %s", tmp, strerror(errno));
  SpamTestPauseAfterTemp(path);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFileBegin(const char *path, SpamFile *f)
{
  int fd;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof *f));
  PetscCall(PetscStrncpy(f->path, path, sizeof f->path));
  PetscCall(SpamTempCreate(path, f->tmp, sizeof f->tmp, &fd));
  f->f = fdopen(fd, "w");
  if (!f->f) {
    const int e = errno;
    close(fd);
    unlink(f->tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s: %s", path, strerror(e));
  }
  f->fail_at = SpamTestFailWriteAt(path);
  PetscFunctionReturn(0);
}

void SpamFilePrintf(SpamFile *f, const char *fmt, ...)
{
  va_list ap;

  if (!f->f || f->err) return;
  if (++f->writes == f->fail_at) {
    f->err = ENOSPC;
    return;
  }
  va_start(ap, fmt);
  errno = 0;
  if (vfprintf(f->f, fmt, ap) < 0) f->err = errno ? errno : EIO;
  va_end(ap);
}

void SpamFilePuts(SpamFile *f, const char *s)
{
  if (!f->f || f->err) return;
  if (++f->writes == f->fail_at) {
    f->err = ENOSPC;
    return;
  }
  errno = 0;
  if (fputs(s, f->f) == EOF) f->err = errno ? errno : EIO;
}

void SpamFileDiscard(SpamFile *f)
{
  if (!f->f) return;
  (void)fclose(f->f); /* already failing: its result adds nothing */
  (void)unlink(f->tmp);
  f->f = NULL;
}

/* The error names the final file, as the user knows it. */
static PetscErrorCode Fail(SpamFile *f, const char *what)
{
  const int e = f->err ? f->err : EIO;

  PetscFunctionBeginUser;
  SpamFileDiscard(f);
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot %s %s: %s", what, f->path, strerror(e));
}

PetscErrorCode SpamFileCheck(SpamFile *f)
{
  PetscFunctionBeginUser;
  if (!f->f) PetscFunctionReturn(0);
  if (!f->err && fflush(f->f)) f->err = errno ? errno : EIO;
  if (f->err) PetscCall(Fail(f, "write"));
  PetscFunctionReturn(0);
}

/* Whether the name f->tmp is still the file f writes: else the rename would put in place
 * whatever someone left at that name (a symlink, say). */
static PetscBool StillOurs(const SpamFile *f)
{
  struct stat mine, now;

  return (PetscBool)(!fstat(fileno(f->f), &mine) && !lstat(f->tmp, &now) && S_ISREG(now.st_mode) && now.st_ino == mine.st_ino && now.st_dev == mine.st_dev);
}

PetscErrorCode SpamFileCommit(SpamFile *f)
{
  int e;

  PetscFunctionBeginUser;
  PetscCheck(f->f, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "%s is not open", f->path);
  PetscCall(SpamFileCheck(f));
  if (!StillOurs(f)) {
    SpamFileDiscard(f); /* removes the name only: a link is not followed */
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: its temporary %s was replaced during the write", f->path, f->tmp);
  }
  e = fclose(f->f);
  f->f = NULL;
  if (e) {
    f->err = errno ? errno : EIO;
    (void)unlink(f->tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: %s", f->path, strerror(f->err));
  }
  if (rename(f->tmp, f->path)) {
    f->err = errno;
    (void)unlink(f->tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s: %s", f->tmp, f->path, strerror(f->err));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamReadWholeFile(const char *path, char **buf, size_t *len)
{
  FILE *f;
  long  n;

  PetscFunctionBeginUser;
  *buf = NULL;
  *len = 0;
  if (!(f = fopen(path, "rb"))) {
    PetscCheck(errno == ENOENT, PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read %s: %s", path, strerror(errno));
    PetscFunctionReturn(0);
  }
  if (fseek(f, 0, SEEK_END) || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET)) {
    const int e = errno;
    (void)fclose(f);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read %s: %s", path, strerror(e));
  }
  PetscCall(PetscMalloc1((size_t)n + 1, buf));
  if (fread(*buf, 1, (size_t)n, f) != (size_t)n) {
    const int e = errno;
    (void)fclose(f);
    PetscCall(PetscFree(*buf));
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read %s: %s", path, strerror(e));
  }
  (void)fclose(f);
  (*buf)[n] = 0;
  *len      = (size_t)n;
  PetscFunctionReturn(0);
}

/* Through the temporary's own descriptor, not its name: a name swapped for a symlink would
 * put the link target's bytes into the checkpoint. */
PetscErrorCode SpamFileContents(SpamFile *f, char **buf, size_t *len)
{
  struct stat st;
  size_t      got = 0;
  int         fd;

  PetscFunctionBeginUser;
  PetscCall(SpamFileCheck(f));
  PetscCheck(f->f, PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read back %s: it is not open", f->tmp);
  fd = fileno(f->f);
  PetscCheck(!fstat(fd, &st), PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read back %s: %s", f->tmp, strerror(errno));
  PetscCall(PetscMalloc1((size_t)st.st_size + 1, buf));
  while (got < (size_t)st.st_size) {
    const ssize_t r = pread(fd, *buf + got, (size_t)st.st_size - got, (off_t)got);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) {
      const int e = r < 0 ? errno : EIO;
      PetscCall(PetscFree(*buf));
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read back %s: %s", f->tmp, strerror(e));
    }
    got += (size_t)r;
  }
  (*buf)[got] = 0;
  *len        = got;
  PetscFunctionReturn(0);
}
