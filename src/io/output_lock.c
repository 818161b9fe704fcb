/* The run owns its output directory: DIR/spam-ark.lock, held with flock for the whole run
 * and holding the pid, host and start time of the holder. The kernel releases an flock
 * when its process dies, so a killed run never leaves the directory locked; a clean end
 * removes the file. */
#define _DEFAULT_SOURCE /* open flags, flock, lstat, gethostname: POSIX, not C11 */
#include <spam/output.h>
#include <spam/errors.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define LOCK_NAME "spam-ark.lock"

/* The holder's line, for the message that refuses a second run. */
static void ReadHolder(int fd, char *info, size_t len)
{
  ssize_t n = pread(fd, info, len - 1, 0);

  info[n > 0 ? n : 0] = 0;
  info[strcspn(info, "\n")] = 0;
  if (!info[0]) (void)snprintf(info, len, "a run that is starting");
}

static void Describe(char *info, size_t len)
{
  char      host[64] = "unknown", when[32] = "unknown";
  time_t    now = time(NULL);
  struct tm tm;

  (void)gethostname(host, sizeof host);
  host[sizeof host - 1] = 0;
  if (gmtime_r(&now, &tm)) (void)strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &tm);
  (void)snprintf(info, len, "pid %ld on %s, started %s", (long)getpid(), host, when);
}

/* Same inode at the path as the one locked? Another run may have removed the file at its
 * end between our open and our flock: then the lock is on a file nobody else will see. */
static PetscBool StillThere(int fd, const char *path)
{
  struct stat a, b;
  return (PetscBool)(!fstat(fd, &a) && !lstat(path, &b) && a.st_dev == b.st_dev && a.st_ino == b.st_ino);
}

PetscErrorCode SpamOutputLock(SpamOutput *o, PetscBool *created)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, LOCK_NAME, path, sizeof path));
  for (int attempt = 0; attempt < 8; attempt++) {
    int fd = open(path, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    *created = (PetscBool)(fd >= 0);
    if (fd < 0 && errno == EEXIST) fd = open(path, O_RDWR | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0 && errno == ENOENT) continue; /* removed in between: try again */
    PetscCheck(fd >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open the lock %s: %s", path, strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB)) {
      const int e = errno;
      char      holder[160];
      ReadHolder(fd, holder, sizeof holder);
      close(fd);
      PetscCheck(e == EWOULDBLOCK, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot lock %s: %s", path, strerror(e));
      SPAM_BAD_INPUT("-output_dir", o->dir, "in use by another run (%s); wait for it to end or choose another -output_dir", holder);
    }
    if (!StillThere(fd, path)) {
      close(fd);
      continue;
    }
    o->lock_fd = fd;
    Describe(o->lock_info, sizeof o->lock_info);
    PetscFunctionReturn(0);
  }
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot lock %s: it keeps being removed", path);
}

/* The holder's line goes in only once the directory has been accepted: a refused run
 * leaves nothing behind. */
PetscErrorCode SpamOutputLockWrite(SpamOutput *o)
{
  char          line[200];
  const size_t  n = (size_t)snprintf(line, sizeof line, "%s\n", o->lock_info);

  PetscFunctionBeginUser;
  PetscCheck(!ftruncate(o->lock_fd, 0) && pwrite(o->lock_fd, line, n, 0) == (ssize_t)n, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s/" LOCK_NAME ": %s", o->dir, strerror(errno));
  PetscFunctionReturn(0);
}

/* Remove the file first, then drop the lock: a run waiting for it then finds the file
 * gone (StillThere) and makes a new one. */
void SpamOutputUnlock(SpamOutput *o)
{
  char path[PETSC_MAX_PATH_LEN];

  if (o->lock_fd < 0) return;
  if (!SpamOutputPath(o, LOCK_NAME, path, sizeof path)) (void)unlink(path);
  (void)close(o->lock_fd);
  o->lock_fd = -1;
}
