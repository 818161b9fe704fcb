/* The command line before PetscInitialize: GNU-style --help/--version, -version, and the
 * options files. PETSc 3.18 aborts the whole program (MPI_Abort, exit 62 or 83, a
 * traceback) on an options file it cannot open or parse; checking the files first, with
 * PETSc's own rules, turns that into one line of bad input. */
#define _POSIX_C_SOURCE 200809L /* getline, strtok_r */
#include <spam/argv.h>
#include <spam/errors.h>
#include <spam/version.h>
#include <errno.h>
#include <stdarg.h>
#include <sys/stat.h>
#include <unistd.h>

#define OPTIONS_FILE_DEPTH 8 /* -options_file inside options files, this deep at most */

/* Prints the one line of bad input (escaped) and returns the bad-input exit code. */
static int Refuse(const char *fmt, ...)
{
  char    raw[1200], text[1200];
  va_list ap;

  va_start(ap, fmt);
  (void)vsnprintf(raw, sizeof raw, fmt, ap);
  va_end(ap);
  SpamEscape(raw, text, sizeof text);
  fprintf(stderr, "spam-ark: error: %s\n", text);
  return SPAM_EXIT_BAD_INPUT;
}

static int CheckFile(const char *path, int depth);

/* One line of an options file as PETSc 3.18 reads it: text from '#' or '%' on is a
 * comment; a blank line is skipped; otherwise the first token starts with '-' (an option,
 * then at most one value) or is "alias" with two more tokens. */
static int CheckLine(const char *path, int lineno, char *line, int depth)
{
  char  where[128], file[100], shown[100], *tok[4] = {NULL}, *save = NULL;
  int   n = 0;
  const PetscBool quoted = (PetscBool)(strchr(line, '"') || strchr(line, '\''));

  SpamClip(path, file, sizeof file);
  (void)snprintf(where, sizeof where, "%s:%d", file, lineno);
  line[strcspn(line, "#%\r\n")] = 0;
  SpamClip(line, shown, sizeof shown);
  for (char *t = strtok_r(line, " \t", &save); t && n < 4; t = strtok_r(NULL, " \t", &save)) tok[n++] = t;
  if (!n) return -1;
  if (!strcmp(tok[0], "alias")) {
    if (n != 3 || tok[1][0] != '-' || tok[2][0] != '-') return Refuse("%s: '%s': an alias line is 'alias -new_name -old_name'", where, shown);
    return -1;
  }
  if (tok[0][0] != '-' || !tok[0][1] || tok[0][1] == ' ') return Refuse("%s: '%s': a line of an options file starts with an option (-name [value]), 'alias', or '#' for a comment", where, shown);
  if (n > 2 && !quoted) return Refuse("%s: '%s': one option and at most one value per line (PETSc refuses the rest)", where, shown);
  if (!strcmp(tok[0], "-options_file")) {
    if (n < 2) return Refuse("%s: '%s': -options_file needs a file name", where, shown);
    if (depth >= OPTIONS_FILE_DEPTH) return Refuse("%s: '%s': options files nest too deep (a file includes itself?)", where, shown);
    return CheckFile(tok[1], depth + 1);
  }
  return -1;
}

/* An options file PETSc can read: it exists, is a regular file (a FIFO would block), can
 * be read, holds no NUL byte, and every line passes CheckLine. */
static int CheckFile(const char *path, int depth)
{
  struct stat st;
  FILE       *f;
  char        file[100];
  char       *line = NULL;
  size_t      cap  = 0;
  ssize_t     len;
  int         lineno = 0, rc = -1;

  SpamClip(path, file, sizeof file);
  if (stat(path, &st)) return Refuse("-options_file = '%s': cannot open: %s", file, strerror(errno));
  if (!S_ISREG(st.st_mode)) return Refuse("-options_file = '%s': %s", file, S_ISDIR(st.st_mode) ? "is a directory, not an options file" : "is not a regular file");
  if (!(f = fopen(path, "r"))) return Refuse("-options_file = '%s': cannot open: %s", file, strerror(errno));
  while (rc < 0 && (len = getline(&line, &cap, f)) >= 0) {
    lineno++;
    if ((size_t)len != strlen(line)) {
      rc = Refuse("%s:%d: the line holds a NUL byte: an options file is text", file, lineno);
    } else rc = CheckLine(path, lineno, line, depth);
  }
  if (rc < 0 && ferror(f)) rc = Refuse("-options_file = '%s': cannot read: %s", file, strerror(errno));
  free(line);
  (void)fclose(f);
  return rc;
}

/* An installed spam-ark (CMakeLists.txt, "Install") runs the options files shipped with it
 * by the names README.md gives them, options/expansion.opts, from any directory: a relative
 * -options_file that is not in the working directory is looked up in the share directory
 * found from the executable's own path (bin/../share/spam), so a relocated install works.
 * A file in the working directory always wins; the build tree has no such directory. On
 * success argv[i] points to the installed file's path (allocated once, kept like argv) and
 * a note says which file is read: no option file is taken in silence. */
static void UseInstalledOptionsFile(char **arg)
{
#ifdef SPAM_SHARE_FROM_BIN
  char        exe[4096], path[4096 + 256];
  struct stat st;
  ssize_t     len;
  char       *slash, *copy;

  if ((*arg)[0] == '/' || !stat(*arg, &st) || errno != ENOENT) return;
  len = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len <= 0 || (size_t)len >= sizeof exe - 1) return;
  exe[len] = 0;
  if (!(slash = strrchr(exe, '/'))) return;
  *slash = 0;
  if ((size_t)snprintf(path, sizeof path, "%s/%s/%s", exe, SPAM_SHARE_FROM_BIN, *arg) >= sizeof path) return;
  if (stat(path, &st) || !S_ISREG(st.st_mode) || !(copy = strdup(path))) return;
  {
    char name[300], shown[1200];

    SpamEscape(*arg, name, sizeof name);
    SpamEscape(path, shown, sizeof shown);
    fprintf(stderr, "spam-ark: note: -options_file %s is not in the working directory: reading the installed %s\n", name, shown);
  }
  *arg = copy;
#else
  (void)arg;
#endif
}

int SpamArgvCheck(int argc, char **argv)
{
  for (int i = 1; i < argc; i++) {
    /* "--help" and "--version" become "-help" and "-version": drop one dash in place. */
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "--version")) memmove(argv[i], argv[i] + 1, strlen(argv[i]));
  }
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "-version")) {
      printf("spam-ark %s\n", SPAM_VERSION);
      return SPAM_EXIT_OK;
    }
  }
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "-options_file")) continue;
    if (i + 1 >= argc || !argv[i + 1][0] || argv[i + 1][0] == '-') return Refuse("-options_file: needs a file name (-options_file FILE)");
    UseInstalledOptionsFile(&argv[i + 1]);
    {
      const int rc = CheckFile(argv[i + 1], 0);
      if (rc >= 0) return rc;
    }
  }
  return -1;
}
