/* fuzz_server: the fuzz corpus's fork server (tests/run_fuzz.py). A start of spam-ark costs
 * about 0.2 CPU-s, most of it the dynamic loader binding the symbols of the hundred-odd
 * shared libraries PETSc brings; this program is linked like spam-ark, is loaded once, and
 * runs each case in a forked child, which calls the program's entry (src/app/program.c) as
 * main() would and exits with its code: atexit handlers, stdio flushes and the sanitizers'
 * exit checks run as in a process of its own. This parent calls neither MPI nor PETSc: each
 * child starts them from nothing, as a fresh process does.
 *
 * Requests on stdin, each a list of NUL-terminated fields:
 *   DIR OUT ERR TIMEOUT LIMIT NENV ENV... NARG ARG...
 * DIR the working directory, OUT and ERR the files stdout and stderr go to (created or
 * truncated; stdin is /dev/null), TIMEOUT in seconds, LIMIT the address space in bytes (0:
 * unlimited), NENV assignments NAME=VALUE (a NAME without '=' is unset), NARG arguments
 * (ARG 0 is the program's name as argv[0]). One line answers each on stdout: "exit N",
 * "signal N" (the child died on signal N) or "timeout" (its process group was killed at
 * TIMEOUT). The server ends at the end of its input. */
#define _GNU_SOURCE
#include "program.h"
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

typedef struct {
  char        *buf; /* the request: its fields, NUL-terminated, in order */
  size_t       len, cap, pos;
  const char  *dir, *out, *err;
  double       timeout;
  rlim_t       limit;
  long         nenv, narg;
  const char **env;
  char       **argv; /* narg + 1 entries, the last NULL */
} Request;

/* Reads input into r->buf until it holds n more fields from r->pos on; 0 at the end of
 * input before a request (first: nothing of one read), -1 on a read error or an input that
 * ends inside a request. */
static int ReadFields(Request *r, long n, int first)
{
  size_t scan = r->pos;

  for (long got = 0; got < n;) {
    char   *nul = memchr(r->buf + scan, 0, r->len - scan);
    ssize_t k;

    if (nul) {
      scan = (size_t)(nul - r->buf) + 1;
      got++;
      continue;
    }
    if (r->len == r->cap) {
      char *more = realloc(r->buf, r->cap * 2);

      if (!more) return -1;
      r->buf = more;
      r->cap *= 2;
    }
    do k = read(0, r->buf + r->len, r->cap - r->len);
    while (k < 0 && errno == EINTR);
    if (k <= 0) return k == 0 && first && r->len == 0 ? 0 : -1;
    r->len += (size_t)k;
  }
  return 1;
}

/* The next field from r->pos (ReadFields made sure it is there). */
static const char *Next(Request *r)
{
  const char *f = r->buf + r->pos;

  r->pos += strlen(f) + 1;
  return f;
}

static int ParseCount(const char *s, long *n)
{
  char *end;

  errno = 0;
  *n    = strtol(s, &end, 10);
  return errno || end == s || *end || *n < 0 || *n > 1 << 20 ? -1 : 0;
}

/* One request into r (its fields stay in r->buf until the next one); 0 at the end of input.
 * The pointers into r->buf are taken once every field is in: reading may move it. */
static int ReadRequest(Request *r)
{
  int   rc;
  char *end;

  memmove(r->buf, r->buf + r->pos, r->len - r->pos); /* the next request's start, if read */
  r->len -= r->pos;
  r->pos = 0;
  if ((rc = ReadFields(r, 6, 1)) <= 0) return rc;
  for (int k = 0; k < 5; k++) (void)Next(r);
  if (ParseCount(Next(r), &r->nenv) || ReadFields(r, r->nenv + 1, 0) < 0) return -1;
  for (long k = 0; k < r->nenv; k++) (void)Next(r);
  if (ParseCount(Next(r), &r->narg) || r->narg < 1 || ReadFields(r, r->narg, 0) < 0) return -1;
  free(r->env);
  free(r->argv);
  r->env  = malloc(sizeof *r->env * (size_t)(r->nenv + 1));
  r->argv = malloc(sizeof *r->argv * (size_t)(r->narg + 1));
  if (!r->env || !r->argv) return -1;
  r->pos     = 0;
  r->dir     = Next(r);
  r->out     = Next(r);
  r->err     = Next(r);
  r->timeout = strtod(Next(r), &end);
  if (*end || !(r->timeout > 0)) return -1;
  r->limit = (rlim_t)strtoull(Next(r), &end, 10);
  if (*end) return -1;
  (void)Next(r);
  for (long k = 0; k < r->nenv; k++) r->env[k] = Next(r);
  (void)Next(r);
  for (long k = 0; k < r->narg; k++) r->argv[k] = (char *)Next(r);
  r->argv[r->narg] = NULL;
  return 1;
}

/* fd onto path opened with flags, or exit 127 with the reason (on the case's stderr once
 * that is in place). */
static void Redirect(int fd, const char *path, int flags)
{
  int k = open(path, flags, 0644);

  if (k < 0 || dup2(k, fd) < 0) {
    fprintf(stderr, "fuzz_server: %s: %s\n", path, strerror(errno));
    _exit(127);
  }
  if (k != fd) (void)close(k);
}

/* The child: its own process group (a timeout kills the whole group), the signal mask the
 * server was started with (the server blocks SIGCHLD), the request's files, directory, limit
 * and environment; then the program, exit()ing with its code. */
static void Child(const Request *r, const sigset_t *mask)
{
  (void)setpgid(0, 0);
  (void)prctl(PR_SET_PDEATHSIG, SIGKILL); /* a server that dies takes its case along */
  (void)sigprocmask(SIG_SETMASK, mask, NULL);
  Redirect(0, "/dev/null", O_RDONLY);
  Redirect(1, r->out, O_WRONLY | O_CREAT | O_TRUNC);
  Redirect(2, r->err, O_WRONLY | O_CREAT | O_TRUNC);
  if (chdir(r->dir)) {
    fprintf(stderr, "fuzz_server: chdir %s: %s\n", r->dir, strerror(errno));
    _exit(127);
  }
  if (r->limit) {
    struct rlimit l = {r->limit, r->limit};

    if (setrlimit(RLIMIT_AS, &l)) _exit(127);
  }
  for (long k = 0; k < r->nenv; k++) {
    const char *eq = strchr(r->env[k], '=');

    if (eq) {
      char *name = strndup(r->env[k], (size_t)(eq - r->env[k]));

      if (!name || setenv(name, eq + 1, 1)) _exit(127);
      free(name);
    } else if (unsetenv(r->env[k])) _exit(127);
  }
  exit(SpamArkProgram((int)r->narg, r->argv));
}

static double Now(void)
{
  struct timespec t;

  (void)clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Waits for child pid until timeout seconds have passed (SIGCHLD is blocked: sigtimedwait
 * wakes at each child's end); then kills its process group. Writes the result line. */
static int Wait(pid_t pid, double timeout)
{
  const double end = Now() + timeout;
  sigset_t     chld;
  int          status;
  char         line[64];
  pid_t        w;

  (void)sigemptyset(&chld);
  (void)sigaddset(&chld, SIGCHLD);
  while ((w = waitpid(pid, &status, WNOHANG)) == 0) {
    double          left = end - Now();
    struct timespec t;

    if (left <= 0) {
      (void)kill(-pid, SIGKILL);
      (void)kill(pid, SIGKILL);
      do w = waitpid(pid, &status, 0);
      while (w < 0 && errno == EINTR);
      status = -1;
      break;
    }
    t.tv_sec  = (time_t)left;
    t.tv_nsec = (long)((left - (double)t.tv_sec) * 1e9);
    (void)sigtimedwait(&chld, NULL, &t);
  }
  if (w < 0) return -1;
  if (status == -1) (void)snprintf(line, sizeof line, "timeout\n");
  else if (WIFSIGNALED(status)) (void)snprintf(line, sizeof line, "signal %d\n", WTERMSIG(status));
  else (void)snprintf(line, sizeof line, "exit %d\n", WEXITSTATUS(status));
  return write(1, line, strlen(line)) == (ssize_t)strlen(line) ? 0 : -1;
}

int main(void)
{
  Request  r = {0};
  sigset_t chld, mask;
  int      rc;

  r.cap = 1 << 16;
  if (!(r.buf = malloc(r.cap))) return 1;
  (void)sigemptyset(&chld);
  (void)sigaddset(&chld, SIGCHLD);
  (void)sigprocmask(SIG_BLOCK, &chld, &mask);
  while ((rc = ReadRequest(&r)) > 0) {
    pid_t pid = fork();

    if (pid == 0) Child(&r, &mask);
    if (pid < 0) {
      perror("fuzz_server: fork");
      return 1;
    }
    (void)setpgid(pid, pid); /* also here: a timeout may come before the child's own call */
    if (Wait(pid, r.timeout)) {
      perror("fuzz_server: wait");
      return 1;
    }
  }
  if (rc < 0) fprintf(stderr, "fuzz_server: a malformed or truncated request\n");
  free(r.env);
  free(r.argv);
  free(r.buf);
  return rc < 0;
}
