/* -help as a user of spam-ark reads it. PETSc prints every option block the program opens
 * (and, inside PetscInitialize, its own general options), including the nonlinear and
 * linear solvers' a TS creates whether or not its method is implicit: about 600 of 850
 * lines that no explicit run uses. This printer keeps spam-ark's blocks and the time
 * stepping ones, drops PETSc's general, viewer, device and solver blocks, and writes each
 * option with its default in plain words:
 *   PETSc:    -h <6. : 3.>: Kernel range h (README)
 *   here:     -h <real>  Kernel range h  [default 3; this run 6]
 * "-help petsc" leaves PETSc's text whole. */
#include "help_text.h"
#include <stdarg.h>
#include <string.h>
#include <ctype.h>

#define IMEX_PC_PREFIX "imex_pc_" /* src/integrate/imex_precond.h */

/* PETSc's printer (PetscVFPrintf, through which its help, version and option lists all
 * pass) takes no context, so what this filter carries from one call to the next (a line in
 * pieces, the block being skipped, the printer it stands in front of) lives here. It is
 * installed only under -help, by main before PetscInitialize, when nothing else runs. */
static struct {
  char      line[8192];
  size_t    len;
  PetscBool dashes;   /* a block's rule was seen: the next line is its title */
  PetscBool skipping; /* inside a block that is not printed                  */
  PetscBool revealed; /* ... but for the stage preconditioner's options, its title printed */
  char      title[256];
  PetscBool viewer;   /* inside a viewer's block, which PETSc opens in the middle of another
                         block and closes without a rule: its lines name PetscOptionsGetViewer */
  PetscErrorCode (*next)(FILE *, const char[], va_list);
} Help;

/* Blocks that an explicit spam-ark run never reads, by the start of their titles. */
static const char *const Dropped[] = {"Options for all PETSc programs", "PetscDevice", "Root PetscDeviceContext", "Nonlinear solver", "SNES", "Eisenstat", "Preconditioner", "Krylov", "KSP", "Linear solver", "Petsc Release Version", "Vector", "Matrix", "Options for SNES", "DMSwarm", "DM ", "Distributed Mesh", "Line search", "Linesearch"};

static PetscBool DroppedTitle(const char *title)
{
  for (size_t k = 0; k < sizeof Dropped / sizeof Dropped[0]; k++)
    if (!strncmp(title, Dropped[k], strlen(Dropped[k])) || strstr(title, "SNES") || strstr(title, "KSP")) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* PETSc writes reals as "3." and booleans as TRUE/FALSE: "3", "true". */
static void Plain(const char *in, size_t n, char *out, size_t len)
{
  size_t k = (size_t)snprintf(out, len, "%.*s", (int)n, in);

  if (k >= len) k = len - 1;
  if (!strcmp(out, "TRUE") || !strcmp(out, "FALSE"))
    for (size_t i = 0; i < k; i++) out[i] = (char)tolower((unsigned char)out[i]);
  if (k > 1 && out[k - 1] == '.' && isdigit((unsigned char)out[k - 2])) out[k - 1] = 0;
}

/* "  -name <now X : formerly Y>: text (man)" or "  -name: <X : Y> text (man)" or
 * "  -name <X>: text (man)" into "  -name  text  [default Y; this run X]". A line of
 * another shape is printed as it is. */
static void Rewrite(const char *line, char *out, size_t len)
{
  const char *lt = strchr(line, '<'), *gt = lt ? strchr(lt, '>') : NULL, *text, *man;
  char        name[128], now[256] = "", def[256] = "", body[4096];
  size_t      nlen;

  if (strncmp(line, "  -", 3) || !lt || !gt) {
    (void)snprintf(out, len, "%s", line);
    return;
  }
  nlen = (size_t)(lt - line);
  while (nlen > 0 && (line[nlen - 1] == ' ' || line[nlen - 1] == ':')) nlen--;
  (void)snprintf(name, sizeof name, "%.*s", (int)nlen, line);
  {
    const char *v = lt + 1, *sep = strstr(v, " : ");
    if (!strncmp(v, "now ", 4)) v += 4;
    if (sep && sep < gt) {
      const char *d = sep + 3;
      if (!strncmp(d, "formerly ", 9)) d += 9;
      Plain(v, (size_t)(sep - v), now, sizeof now);
      Plain(d, (size_t)(gt - d), def, sizeof def);
    } else Plain(v, (size_t)(gt - v), def, sizeof def);
  }
  text = gt + 1;
  if (*text == ':') text++;
  while (*text == ' ') text++;
  (void)snprintf(body, sizeof body, "%s", text);
  /* the manual page PETSc appends: ours say README, which the docs replace */
  man = strrchr(body, '(');
  if (man && !strcmp(man, "(README)")) {
    body[man - body] = 0;
    while (strlen(body) && body[strlen(body) - 1] == ' ') body[strlen(body) - 1] = 0;
  }
  if (now[0] && strcmp(now, def)) (void)snprintf(out, len, "%s  %s  [default %s; this run %s]", name, body, def[0] ? def : "none", now);
  else (void)snprintf(out, len, "%s  %s  [default %s]", name, body, def[0] ? def : "none");
}

static void Emit(const char *format, ...)
{
  va_list ap;

  va_start(ap, format);
  (void)Help.next(stdout, format, ap);
  va_end(ap);
}

static void Line(const char *line)
{
  char out[8192];

  if (!strncmp(line, "----------------------------------------", 40)) {
    Help.dashes = PETSC_TRUE;
    return;
  }
  if (Help.dashes) { /* a block's title */
    Help.dashes = PETSC_FALSE;
    Help.viewer = (PetscBool)!strncmp(line, "Viewer (", 8);
    if (Help.viewer) return;
    Help.skipping = DroppedTitle(line);
    Help.revealed = PETSC_FALSE;
    (void)snprintf(Help.title, sizeof Help.title, "%.200s", line);
    if (!Help.skipping) Emit("\n%s\n", line);
    return;
  }
  if (Help.viewer && strstr(line, "(PetscOptionsGetViewer)")) return;
  Help.viewer = PETSC_FALSE; /* the enclosing block goes on */
  /* arkode_imex's stage preconditioner is a KSP and PC of ours (prefix -imex_pc_): their
   * blocks are shown for its options, and for the sub-titles among them */
  if (Help.skipping && !strncmp(line, "  -" IMEX_PC_PREFIX, 3 + strlen(IMEX_PC_PREFIX)) && !Help.revealed) {
    Emit("\n%s (arkode_imex's stage preconditioner, -arkode_imex_pc diffusion)\n", Help.title);
    Help.revealed = PETSC_TRUE;
  }
  if (Help.revealed && !strncmp(line, "  -", 3) && strncmp(line, "  -" IMEX_PC_PREFIX, 3 + strlen(IMEX_PC_PREFIX))) {
    Help.skipping = Help.revealed = PETSC_FALSE; /* the block the KSP's opened inside goes on */
  }
  if (Help.skipping && !(Help.revealed && (strncmp(line, "  -", 3) || !strncmp(line, "  -" IMEX_PC_PREFIX, 3 + strlen(IMEX_PC_PREFIX))))) return;
  Rewrite(line, out, sizeof out);
  Emit("%s\n", out);
}

static PetscErrorCode Filter(FILE *fd, const char format[], va_list ap)
{
  char piece[8192];

  if (fd != stdout) return Help.next(fd, format, ap); /* errors: as they are */
  (void)vsnprintf(piece, sizeof piece, format, ap);
  for (const char *p = piece; *p; p++) {
    if (*p == '\n') {
      Help.line[Help.len] = 0;
      Line(Help.line);
      Help.len = 0;
    } else if (Help.len + 1 < sizeof Help.line) Help.line[Help.len++] = *p;
  }
  return 0;
}

void SpamHelpTextInstall(int argc, char **argv)
{
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "-help")) continue;
    if (i + 1 < argc && !strcmp(argv[i + 1], "petsc")) { /* PETSc's text, whole */
      argv[i + 1] = (char *)"true";                      /* PETSc's -help is a flag */
      return;
    }
    Help.next     = PetscVFPrintf;
    PetscVFPrintf = Filter;
    return;
  }
}
