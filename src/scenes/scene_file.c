/* Particles read from a CSV file: header x[,y[,z]],vx[,vy[,vz]][,m] matching -dim, one
 * particle per line, every value a finite number, every particle inside the box
 * -box_lo/-box_len. Every line that is not so is bad input naming file:line: the file is
 * the user's, and a run from a half-read file would be a wrong result, not a failure. */
/* O_CLOEXEC and S_ISSOCK are POSIX 2008, which -std=c11 does not declare by default. */
#define _POSIX_C_SOURCE 200809L
#include <spam/scene.h>
#include <spam/errors.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

/* The longest line accepted, its end excluded, comments and header included. A data line
 * holds at most seven numbers; a longer line is refused whole rather than split into
 * two particles or cut short, and the limit bounds the memory a line takes. */
#define CSV_MAX_LINE 4095
/* Room for the quote of an offending line: SpamClip keeps 80 bytes and "..." (the error
 * handler escapes them). */
#define CSV_ECHO 80

typedef struct {
  FILE       *f;
  const char *path;
  PetscInt    lineno;
  char        line[CSV_MAX_LINE + 1]; /* the line without its end, NUL-terminated  */
  size_t      len;                    /* its length, CSV_MAX_LINE + 1 if longer          */
  size_t      nul;                    /* 1-based column of its first NUL byte, or 0 */
  char        where[PETSC_MAX_PATH_LEN + 32], echo[CSV_ECHO + 4];
} CsvReader;

static PetscErrorCode SpamFileOptions(SpamFileParams *p)
{
  PetscFunctionBeginUser;
  p->path[0] = 0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene file", "spam-ark");
  PetscCall(PetscOptionsString("-file_path", "CSV file of particles: header x,y[,z],vx,vy[,vz][,m]", "README", p->path, p->path, sizeof p->path, NULL));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* Expected header for dim, with or without the mass column. */
static void Header(int dim, PetscBool mass, char *buf, size_t len)
{
  static const char *ax[3] = {"x", "y", "z"};
  size_t             k     = 0;
  buf[0]                   = 0;
  for (int d = 0; d < dim; d++) k += (size_t)snprintf(buf + k, len - k, "%s%s", d ? "," : "", ax[d]);
  for (int d = 0; d < dim; d++) k += (size_t)snprintf(buf + k, len - k, ",v%s", ax[d]);
  if (mass) (void)snprintf(buf + k, len - k, ",m");
}

/* Drops a CR (CRLF line ends) and trailing spaces. */
static void Chomp(char *s)
{
  size_t n = strlen(s);
  while (n && (s[n - 1] == '\r' || s[n - 1] == ' ')) s[--n] = 0;
}

/* What a file that is not a regular file is, for the message. */
static const char *Kind(mode_t m)
{
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO (named pipe)";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

/* Opens path for reading if it is a regular file. O_NONBLOCK: opening a FIFO without a
 * writer would otherwise wait forever before fstat could refuse it; on a regular file
 * the flag has no effect. */
static PetscErrorCode OpenRegular(const char *path, FILE **f)
{
  struct stat st;
  int         fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);

  PetscFunctionBeginUser;
  if (fd < 0) SPAM_BAD_INPUT("-file_path", path, "cannot open the file (%s)", strerror(errno));
  if (fstat(fd, &st)) {
    const int e = errno;
    (void)close(fd);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read %s: %s", path, strerror(e));
  }
  if (!S_ISREG(st.st_mode)) {
    (void)close(fd);
    SPAM_BAD_INPUT("-file_path", path, "is %s; a CSV file of particles (a regular file) is required", Kind(st.st_mode));
  }
  *f = fdopen(fd, "r");
  if (!*f) {
    const int e = errno;
    (void)close(fd);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s: %s", path, strerror(e));
  }
  PetscFunctionReturn(0);
}

/* Reads the next line (to its '\n' or the end of the file); *more is false at the end
 * of the file. Reading stops one byte past CSV_MAX_LINE: such a line is refused, and a
 * file of gigabytes without a line end is not read to its end first. */
static PetscErrorCode ReadLine(CsvReader *r, PetscBool *more)
{
  int ch = EOF;

  PetscFunctionBeginUser;
  r->len = 0;
  r->nul = 0;
  while (r->len <= CSV_MAX_LINE && (ch = getc_unlocked(r->f)) != EOF && ch != '\n') {
    if (r->len < CSV_MAX_LINE) r->line[r->len] = (char)ch;
    r->len++;
    if (!ch && !r->nul) r->nul = r->len;
  }
  PetscCheck(!ferror(r->f), PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "cannot read %s: %s", r->path, strerror(errno));
  r->line[PetscMin(r->len, (size_t)CSV_MAX_LINE)] = 0;
  *more = (PetscBool)(ch != EOF || r->len > 0);
  if (*more) r->lineno++;
  PetscFunctionReturn(0);
}

/* Names the line (file:line) and quotes at most 80 bytes of it for a message (SpamClip). */
static PetscErrorCode Describe(CsvReader *r)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(r->where, sizeof r->where, "%s:%" PetscInt_FMT, r->path, r->lineno));
  SpamClip(r->line, r->echo, sizeof r->echo);
  PetscFunctionReturn(0);
}

/* Bad input naming the current line: file:line and the quoted line are formatted only
 * when a line is refused, not for every line read. */
#define CSV_BAD_LINE(r, ...) \
  do { \
    PetscCall(Describe(r)); \
    SPAM_BAD_INPUT((r)->where, (r)->echo, __VA_ARGS__); \
  } while (0)

/* A line too long or holding a NUL byte (which would cut it short as a C string) is
 * refused; otherwise its end is trimmed. */
static PetscErrorCode CheckLine(CsvReader *r)
{
  PetscFunctionBeginUser;
  if (r->len > CSV_MAX_LINE) CSV_BAD_LINE(r, "the line is longer than %d bytes, the limit for every line (comments included)", CSV_MAX_LINE);
  if (r->nul) CSV_BAD_LINE(r, "the line contains a NUL byte (column %zu); the file must be text", r->nul);
  Chomp(r->line);
  PetscFunctionReturn(0);
}

/* Parses one data line into vals; returns the number of fields, or -1 on a field that is
 * empty (or blank), not a number, or not finite: its 1-based index goes to *badfield and
 * the reason to *why. An underflow to zero or a subnormal is a number, an overflow not. */
static int ParseLine(const char *line, double *vals, int max, int *badfield, const char **why)
{
  int         k = 0;
  const char *s = line;
  for (;;) {
    char  *end;
    double v;
    errno = 0;
    v     = strtod(s, &end);
    *why  = NULL;
    if (end == s) { /* nothing converted: strtod skipped any blanks, so test before ours */
      const char *t = s;
      while (*t == ' ' || *t == '\t') t++;
      *why = *t == ',' || *t == 0 ? "is empty" : "is not a number";
    } else {
      while (*end == ' ' || *end == '\t') end++;
      if (*end != ',' && *end != 0) *why = "is not a number";
      else if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0)) *why = "is not a finite number";
    }
    if (*why) {
      *badfield = k + 1;
      return -1;
    }
    if (k < max) vals[k] = v;
    k++;
    if (*end == 0) return k;
    s = end + 1;
  }
}

/* Every coordinate must lie in the box (closed at both ends): a particle outside a
 * periodic box is not wrapped silently, and one outside an open box would be binned
 * with the edge cells as if near them. */
static PetscErrorCode CheckInBox(CsvReader *r, const SpamCommonParams *c, const double *x)
{
  static const char *ax[3] = {"x", "y", "z"};

  PetscFunctionBeginUser;
  for (int d = 0; d < c->dim; d++) {
    const double lo = c->box_lo[d], hi = c->box_lo[d] + c->box_len[d];
    char         why[160]; /* formatted here: PETSc's %g writes 8 as "8." */
    if (x[d] >= lo && x[d] <= hi) continue;
    (void)snprintf(why, sizeof why, "%s = %.10g lies outside the box, %.10g <= %s <= %.10g", ax[d], x[d], lo, ax[d], hi);
    CSV_BAD_LINE(r, "%s (-box_lo, -box_len; %s direction)", why, c->periodic[d] ? "periodic" : "open");
  }
  PetscFunctionReturn(0);
}

/* Checks one data line (nf fields) and returns its values in vals. */
static PetscErrorCode ParseParticle(CsvReader *r, const SpamCommonParams *c, int nf, double *vals, double *mass)
{
  const int   dim = c->dim;
  const char *why;
  char        first[32];
  int         bad = 0, k;

  PetscFunctionBeginUser;
  k = ParseLine(r->line, vals, 8, &bad, &why);
  if (k < 0) CSV_BAD_LINE(r, "field %d %s; each of the %d fields must be a finite number", bad, why, nf);
  if (k != nf) CSV_BAD_LINE(r, "expected %d comma-separated numbers, found %d", nf, k);
  PetscCall(CheckInBox(r, c, vals));
  if (nf == 2 * dim + 1) {
    if (!(vals[2 * dim] > 0.0)) CSV_BAD_LINE(r, "mass must be positive");
    if (*mass < 0.0) *mass = vals[2 * dim];
    if (vals[2 * dim] != *mass) {
      (void)snprintf(first, sizeof first, "%g", *mass); /* PETSc's %g writes 1 as "1." */
      CSV_BAD_LINE(r, "every particle must have the same mass (%s on the first line); unequal masses are not supported yet", first);
    }
  }
  PetscFunctionReturn(0);
}

/* Reads the particles into out->x, out->v (allocated here; the caller frees them on an
 * error as on success). */
static PetscErrorCode ReadBody(CsvReader *r, const SpamCommonParams *c, int nf, SpamParticles *out)
{
  const int    dim  = c->dim;
  const double maxn = SpamMaxParticles();
  size_t       cap  = 1024, n = 0;
  double       vals[8], mass = -1.0;
  PetscBool    more;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(cap * dim, &out->x));
  PetscCall(PetscMalloc1(cap * dim, &out->v));
  for (;;) {
    PetscCall(ReadLine(r, &more));
    if (!more) break;
    PetscCall(CheckLine(r));
    if (!r->line[0] || r->line[0] == '#') continue;
    if ((double)n >= maxn) CSV_BAD_LINE(r, "the file holds more than %.4g particles, the most that 32-bit state indices and this machine's physical memory allow", maxn);
    PetscCall(ParseParticle(r, c, nf, vals, &mass));
    if (n == cap) {
      cap *= 2;
      PetscCall(PetscRealloc(sizeof(double) * cap * dim, &out->x));
      PetscCall(PetscRealloc(sizeof(double) * cap * dim, &out->v));
    }
    for (int d = 0; d < dim; d++) {
      out->x[n * dim + d] = vals[d];
      out->v[n * dim + d] = vals[dim + d];
    }
    n++;
  }
  if (n == 0) SPAM_BAD_INPUT("-file_path", r->path, "the file has a header but no particles");
  out->dim  = dim;
  out->n    = (PetscInt)n;
  out->mass = mass;
  PetscFunctionReturn(0);
}

/* Reads and checks the header: returns the number of fields of a data line. */
static PetscErrorCode ReadHeader(CsvReader *r, int dim, int *nf)
{
  char      with_m[64], without_m[64];
  PetscBool more;

  PetscFunctionBeginUser;
  Header(dim, PETSC_TRUE, with_m, sizeof with_m);
  Header(dim, PETSC_FALSE, without_m, sizeof without_m);
  PetscCall(ReadLine(r, &more));
  r->lineno = 1;
  PetscCall(CheckLine(r));
  if (!strcmp(r->line, with_m)) *nf = 2 * dim + 1;
  else if (!strcmp(r->line, without_m)) *nf = 2 * dim;
  else CSV_BAD_LINE(r, "header must be '%s' or '%s' for -dim %d", without_m, with_m, dim);
  PetscFunctionReturn(0);
}

/* The box is checked before any particle is compared with it, so that a box too small or
 * too far out (SpamBoxValidate: positive finite edges, corners within 1e9 h, NaN included)
 * is named as such rather than by a particle outside it. */
static PetscErrorCode CheckBox(const SpamCommonParams *c)
{
  SpamBox box = {c->dim, {0, 0, 0}, {0, 0, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};

  PetscFunctionBeginUser;
  for (int d = 0; d < c->dim; d++) {
    box.lo[d]       = c->box_lo[d];
    box.len[d]      = c->box_len[d];
    box.periodic[d] = c->periodic[d];
  }
  PetscCall(SpamBoxValidate(&box, c->h, "-box_lo/-box_len"));
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamFileBuild(const SpamCommonParams *c, const SpamFileParams *p, SpamParticles *out)
{
  CsvReader     *r;
  int            nf = 0;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (!p->path[0]) SPAM_BAD_INPUT("-file_path", "README", "the file scene needs a CSV file of particles");
  if (!c->box_len_set) SPAM_BAD_INPUT("-box_len", "README", "the file scene needs the box edge lengths, e.g. -box_len 64,64");
  PetscCall(CheckBox(c));
  PetscCall(PetscMemzero(out, sizeof *out));
  PetscCall(PetscNew(&r));
  r->path = p->path;
  ierr    = OpenRegular(p->path, &r->f);
  if (!ierr) {
    ierr = ReadHeader(r, c->dim, &nf);
    if (!ierr) ierr = ReadBody(r, c, nf, out);
    (void)fclose(r->f);
  }
  PetscCall(PetscFree(r));
  if (ierr) PetscCall(SpamParticlesFree(out)); /* nothing read is kept after an error */
  PetscCall(ierr);
  if (out->mass < 0.0) out->mass = c->mass;
  out->box.dim = c->dim;
  for (int d = 0; d < c->dim; d++) {
    out->box.lo[d]       = c->box_lo[d];
    out->box.len[d]      = c->box_len[d];
    out->box.periodic[d] = c->periodic[d];
  }
  PetscCall(PetscStrncpy(out->info.name, "file", sizeof out->info.name));
  out->info.t_end_default = 10.0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, SpamSceneParams *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  SpamSolidDefaults(solid);
  solid->material        = SPAM_MATERIAL_ISENTROPE;
  solid->density         = SPAM_DENSITY_SUMMATION;
  solid->density_initial = SPAM_DENSITY_INITIAL_SUMMED;
  solid->rho0            = c->mass;
  PetscCall(SpamFileOptions(&p->file));
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const SpamSceneParams *p, const SpamSolidParams *solid, SpamParticles *out)
{
  PetscFunctionBeginUser;
  (void)solid;
  PetscCall(SpamFileBuild(c, &p->file, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneFile(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"file", 2 | 4 | 8, PETSC_FALSE, Options, Build};
  PetscFunctionReturn(0);
}
