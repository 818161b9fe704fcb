/* The command line before PetscInitialize: GNU-style --help/--version, -version, and the
 * options files. PETSc 3.18 aborts the whole program (MPI_Abort, exit 55, 56, 62 or 83, a
 * traceback) on an options file it cannot open or parse, or on more options than its table
 * holds; checking the command line and the files first, with PETSc's own rules, turns that
 * into one line of bad input. */
#define _POSIX_C_SOURCE 200809L /* getline, strtok_r */
#include <spam/argv.h>
#include <spam/errors.h>
#include <spam/version.h>
#include <ctype.h>
#include <errno.h>
#include <strings.h>
#include <stdarg.h>
#include <sys/stat.h>
#include <unistd.h>

#define OPTIONS_FILE_DEPTH 8 /* -options_file inside options files, this deep at most */
/* PETSc 3.18's options table holds 512 names (MAXOPTIONS in options.c) and 25 aliases
 * (MAXALIASES); one more aborts. spam-ark reads far fewer options and refuses every one it
 * does not use, so a run never needs that many; the margin of 2 leaves room for a name
 * PETSc might set itself. */
#define OPTIONS_MAX 510
#define ALIASES_MAX 25

/* What the scan of the command line and its options files found: the distinct option
 * names so far (as PETSc keys them: lower case, without leading dashes), the alias lines,
 * and the first refusal's text (printed once the ranks have agreed, by one of them). */
typedef struct {
  char *names[OPTIONS_MAX + 1];
  int   nnames, naliases;
  int   speak; /* this rank prints the notes (rank 0) */
  char  msg[1200];
} Scan;

/* Keeps the refusal's text (escaped) and returns the bad-input exit code. */
static int Refuse(Scan *s, const char *fmt, ...)
{
  char    raw[1200];
  va_list ap;

  va_start(ap, fmt);
  (void)vsnprintf(raw, sizeof raw, fmt, ap);
  va_end(ap);
  SpamEscape(raw, s->msg, sizeof s->msg);
  return SPAM_EXIT_BAD_INPUT;
}

/* PETSc's test of an option name (PetscOptionsValidKey): '-' or '--', a letter, and not
 * the start of a number ("-inf", "-nan" and "-e5x" are values, "-1" too). A token that fails
 * it is a value on the command line and an error in an options file. */
static int ValidKey(const char *key)
{
  char *end;

  if (!key || key[0] != '-') return 0;
  if (key[1] == '-') key++;
  if (!isalpha((unsigned char)key[1])) return 0;
  (void)strtod(key, &end);
  return end == key || *end == '_' || isalnum((unsigned char)*end);
}

/* Books the option name key (valid); refuses the one that would overflow PETSc's table.
 * -options_file is read, not stored. Names compare as PETSc's do: without the leading
 * dashes and regardless of case. */
static int AddName(Scan *s, const char *key, const char *where)
{
  char name[256], shown[100];
  int  k = 0;

  key += key[1] == '-' ? 2 : 1;
  for (; key[k] && k < (int)sizeof name - 1; k++) name[k] = (char)tolower((unsigned char)key[k]);
  name[k] = 0;
  if (!strcmp(name, "options_file")) return -1;
  for (int i = 0; i < s->nnames; i++)
    if (!strcmp(s->names[i], name)) return -1;
  SpamClip(name, shown, sizeof shown);
  if (s->nnames >= OPTIONS_MAX) return Refuse(s, "%s: -%s: more than %d distinct options (the size of PETSc's options table; spam-ark -help lists the ones it reads)", where, shown, OPTIONS_MAX);
  if (!(s->names[s->nnames] = strdup(name))) return Refuse(s, "%s: out of memory", where);
  s->nnames++;
  return -1;
}

static int CheckFile(Scan *s, const char *path, int depth);

/* One line of an options file as PETSc 3.18 reads it: text from '#' or '%' on is a
 * comment; a blank line is skipped; otherwise the first token is an option name that passes
 * ValidKey (then at most one value) or is "alias" with two more tokens. PETSc inserts the
 * line as a string, so a value that is itself an option name is one more option. */
static int CheckLine(Scan *s, const char *path, int lineno, char *line, int depth)
{
  char  where[128], file[100], shown[100], *tok[4] = {NULL}, *save = NULL;
  int   n = 0, rc;
  const PetscBool quoted = (PetscBool)(strchr(line, '"') || strchr(line, '\''));

  SpamClip(path, file, sizeof file);
  (void)snprintf(where, sizeof where, "%s:%d", file, lineno);
  line[strcspn(line, "#%\r\n")] = 0;
  SpamClip(line, shown, sizeof shown);
  for (char *t = strtok_r(line, " \t", &save); t && n < 4; t = strtok_r(NULL, " \t", &save)) tok[n++] = t;
  if (!n) return -1;
  if (!strcmp(tok[0], "alias")) {
    if (n != 3 || tok[1][0] != '-' || tok[2][0] != '-') return Refuse(s, "%s: '%s': an alias line is 'alias -new_name -old_name'", where, shown);
    if (++s->naliases > ALIASES_MAX) return Refuse(s, "%s: '%s': more than %d aliases (PETSc's limit)", where, shown, ALIASES_MAX);
    return -1;
  }
  if (tok[0][0] != '-') return Refuse(s, "%s: '%s': a line of an options file starts with an option (-name [value]), 'alias', or '#' for a comment", where, shown);
  if (!ValidKey(tok[0])) return Refuse(s, "%s: '%s': not an option name (a dash, a letter, then letters, digits or '_')", where, shown);
  if (n > 2 && !quoted) return Refuse(s, "%s: '%s': one option and at most one value per line (PETSc refuses the rest)", where, shown);
  if (!strcmp(tok[0], "-options_file")) {
    if (n < 2) return Refuse(s, "%s: '%s': -options_file needs a file name", where, shown);
    if (depth >= OPTIONS_FILE_DEPTH) return Refuse(s, "%s: '%s': options files nest too deep (a file includes itself?)", where, shown);
    return CheckFile(s, tok[1], depth + 1);
  }
  if ((rc = AddName(s, tok[0], where)) >= 0) return rc;
  return n > 1 && ValidKey(tok[1]) ? AddName(s, tok[1], where) : -1;
}

/* An options file PETSc can read: it exists, is a regular file (a FIFO would block), can
 * be read, holds no NUL byte, and every line passes CheckLine. */
static int CheckFile(Scan *s, const char *path, int depth)
{
  struct stat st;
  FILE       *f;
  char        file[100];
  char       *line = NULL;
  size_t      cap  = 0;
  ssize_t     len;
  int         lineno = 0, rc = -1;

  SpamClip(path, file, sizeof file);
  if (stat(path, &st)) return Refuse(s, "-options_file = '%s': cannot open: %s", file, strerror(errno));
  if (!S_ISREG(st.st_mode)) return Refuse(s, "-options_file = '%s': %s", file, S_ISDIR(st.st_mode) ? "is a directory, not an options file" : "is not a regular file");
  if (!(f = fopen(path, "r"))) return Refuse(s, "-options_file = '%s': cannot open: %s", file, strerror(errno));
  while (rc < 0 && (len = getline(&line, &cap, f)) >= 0) {
    lineno++;
    if ((size_t)len != strlen(line)) {
      rc = Refuse(s, "%s:%d: the line holds a NUL byte: an options file is text", file, lineno);
    } else rc = CheckLine(s, path, lineno, line, depth);
  }
  if (rc < 0 && ferror(f)) rc = Refuse(s, "-options_file = '%s': cannot read: %s", file, strerror(errno));
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
 * a note (from rank 0) says which file is read: no option file is taken in silence. */
static void UseInstalledOptionsFile(char **arg, int speak)
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
  if (speak) {
    char name[300], shown[1200];

    SpamEscape(*arg, name, sizeof name);
    SpamEscape(path, shown, sizeof shown);
    fprintf(stderr, "spam-ark: note: -options_file %s is not in the working directory: reading the installed %s\n", name, shown);
  }
  *arg = copy;
#else
  (void)arg;
  (void)speak;
#endif
}

int SpamArgvEarly(int argc, char **argv)
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
  return -1;
}

/* The command line's option names and its options files, in PETSc's order. */
static int ScanArgs(Scan *s, int argc, char **argv)
{
  for (int i = 1; i < argc; i++) {
    int rc = -1;
    if (!strcmp(argv[i], "-options_file")) {
      if (i + 1 >= argc || !argv[i + 1][0] || argv[i + 1][0] == '-') return Refuse(s, "-options_file: needs a file name (-options_file FILE)");
      UseInstalledOptionsFile(&argv[i + 1], s->speak);
      rc = CheckFile(s, argv[++i], 0);
    } else if (ValidKey(argv[i])) rc = AddName(s, argv[i], "the command line");
    if (rc >= 0) return rc;
  }
  return -1;
}

/* PETSc also reads ~/.petscrc, ./.petscrc and ./petscrc when they exist (unless
 * -skip_petscrc), and the option names in the environment variable PETSC_OPTIONS: the same
 * rules, the same table. */
static int ScanPetscDefaults(Scan *s, int argc, char **argv)
{
  const char *home = getenv("HOME"), *env = getenv("PETSC_OPTIONS");
  const char *files[3] = {NULL, ".petscrc", "petscrc"};
  char        path[4096];
  int         rc = -1;

  for (int i = 1; i < argc; i++)
    if (!strcmp(argv[i], "-skip_petscrc") && !(i + 1 < argc && (!strcmp(argv[i + 1], "0") || !strcasecmp(argv[i + 1], "false") || !strcasecmp(argv[i + 1], "no")))) files[1] = files[2] = NULL;
  if (files[1] && home && (size_t)snprintf(path, sizeof path, "%s/.petscrc", home) < sizeof path) files[0] = path;
  for (int k = 0; k < 3 && rc < 0; k++) {
    struct stat st;
    if (files[k] && !stat(files[k], &st) && S_ISREG(st.st_mode)) rc = CheckFile(s, files[k], 0);
  }
  if (rc >= 0 || !env) return rc;
  {
    char *copy = strdup(env), *save = NULL;
    if (!copy) return Refuse(s, "PETSC_OPTIONS: out of memory");
    for (char *t = strtok_r(copy, " \t\n", &save); t && rc < 0; t = strtok_r(NULL, " \t\n", &save))
      if (ValidKey(t)) rc = AddName(s, t, "PETSC_OPTIONS");
    free(copy);
  }
  return rc;
}

/* Every rank reads the same command line and files and finds the same fault: the lowest
 * rank that found one prints it, once (rank 0 unless its file system disagrees), and every
 * rank returns the bad-input code. */
int SpamArgvCheck(MPI_Comm comm, int argc, char **argv)
{
  Scan *s = calloc(1, sizeof *s);
  int   rank = 0, size = 1, mine, first, rc;

  (void)MPI_Comm_rank(comm, &rank);
  (void)MPI_Comm_size(comm, &size);
  if (!s) {
    fprintf(stderr, "spam-ark: error: out of memory reading the command line\n");
    return SPAM_EXIT_ERROR;
  }
  s->speak = rank == 0;
  rc       = ScanPetscDefaults(s, argc, argv);
  if (rc < 0) rc = ScanArgs(s, argc, argv);
  mine     = rc >= 0 ? rank : size;
  if (MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS) first = mine;
  if (first < size && rank == first) fprintf(stderr, "spam-ark: error: %s\n", s->msg);
  for (int i = 0; i < s->nnames; i++) free(s->names[i]);
  free(s);
  return first < size ? SPAM_EXIT_BAD_INPUT : -1;
}
