/* Particles read from a file: CSV whose header names its columns (particle_header.c), a
 * header-less CSV of x..,vx..[,m] as earlier versions wrote it, or the program's own HDF5
 * snapshot (scene_file_hdf5.c, told by its signature, not by its name). Every value a
 * finite number, every particle inside the box -box_lo/-box_len. Every line that is not so
 * is bad input naming file:line: the file is the user's, and a run from a half-read file
 * would be a wrong result, not a failure. */
/* O_CLOEXEC and S_ISSOCK are POSIX 2008, which -std=c11 does not declare by default. */
#define _POSIX_C_SOURCE 200809L
#include "particle_file.h"
#include <spam/errors.h>
#include <spam/output.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
  char path[PETSC_MAX_PATH_LEN];
} SpamFileParams;

static const SpamSceneOption Table[] = {
  {"file_path", SPAM_SCENE_OPTION_STRING, "Particle file: CSV with a header naming columns x y z vx vy vz m e rho sxx sxy syy sxz syz szz id (any order), or an HDF5 snapshot of this program", ", which builds its own box"},
  /* read with the common options (scene.c) */
  {"box_lo", SPAM_SCENE_OPTION_REALS, NULL, ", which builds its own box"},
  {"box_len", SPAM_SCENE_OPTION_REALS, NULL, ", which builds its own box"},
  {"periodic", SPAM_SCENE_OPTION_BOOLS, NULL, ", which builds its own box"},
  {NULL, SPAM_SCENE_OPTION_INT, NULL, NULL},
};

/* The longest line accepted, its end excluded, comments and header included. A data line
 * holds at most seventeen numbers; a longer line is refused whole rather than split into
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
  double      max_particles;          /* SpamMaxParticles(), once: it asks the kernel (sysinfo) */
} CsvReader;

static PetscErrorCode SpamFileOptions(SpamFileParams *p)
{
  PetscFunctionBeginUser;
  p->path[0] = 0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene file", "spam-ark");
  PetscCall(SpamSceneOptionString(PetscOptionsObject, Table, "file_path", p->path, sizeof p->path, NULL));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* Drops a CR (CRLF line ends) and trailing spaces. */
static void Chomp(char *s)
{
  size_t n = strlen(s);
  while (n && (s[n - 1] == '\r' || s[n - 1] == ' ')) s[--n] = 0;
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
    SPAM_BAD_INPUT("-file_path", path, "is %s; a CSV file of particles (a regular file) is required", SpamFileKind(st.st_mode));
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
    v     = SpamParseDouble(s, &end);
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
  char      why[160];
  const int d = SpamBoxOutside(c->dim, c->box_lo, c->box_len, NULL, x, why, sizeof why);

  PetscFunctionBeginUser;
  if (d >= 0) CSV_BAD_LINE(r, "%s (-box_lo, -box_len; %s direction)", why, c->periodic[d] ? "periodic" : "open");
  PetscFunctionReturn(0);
}

/* The values of one data line by slot; checks the line as a whole: field count, every
 * field a finite number, the position inside the box, mass and density positive, an id a
 * whole number. */
static PetscErrorCode ParseParticle(CsvReader *r, const SpamCommonParams *c, const SpamColumnMap *map, double *slots)
{
  const char *why;
  double      vals[NSLOTS];
  int         bad = 0, k;

  PetscFunctionBeginUser;
  k = ParseLine(r->line, vals, NSLOTS, &bad, &why);
  if (k < 0) CSV_BAD_LINE(r, "field %d %s; each of the %d fields must be a finite number", bad, why, map->ncol);
  if (k != map->ncol) CSV_BAD_LINE(r, "expected %d comma-separated numbers, found %d", map->ncol, k);
  for (int s = 0; s < NSLOTS; s++) slots[s] = 0.0; /* velocities default to rest */
  for (int j = 0; j < k; j++) slots[map->slot[j]] = vals[j];
  PetscCall(CheckInBox(r, c, slots + SLOT_X));
  if ((map->columns & SPAM_COLUMN_M) && SpamPositiveNormalProblem(slots[SLOT_M])) CSV_BAD_LINE(r, "mass m = %.17g: %s", slots[SLOT_M], SpamPositiveNormalProblem(slots[SLOT_M]));
  if ((map->columns & SPAM_COLUMN_RHO) && !(slots[SLOT_RHO] > 0.0)) CSV_BAD_LINE(r, "density rho must be positive");
  if ((map->columns & SPAM_COLUMN_ID) && !(slots[SLOT_ID] >= 0.0 && slots[SLOT_ID] < r->max_particles && slots[SLOT_ID] == floor(slots[SLOT_ID]))) CSV_BAD_LINE(r, "id must be a whole number from 0 to the particle count - 1");
  PetscFunctionReturn(0);
}

/* A file without a header (as earlier versions read): its first line is data, x..,vx..
 * with an optional mass. A line starting like a number is data, not a header. */
static PetscBool LooksLikeData(const char *line)
{
  while (*line == ' ' || *line == '\t') line++;
  return (PetscBool)(strchr("0123456789+-.", *line) && *line);
}

/* The first line that is neither blank nor a comment: the header, or in a header-less file
 * the first particle (*pending: not yet consumed). */
static PetscErrorCode ReadHeader(CsvReader *r, int dim, SpamColumnMap *map, PetscBool *pending)
{
  char      why[256];
  PetscBool more;

  PetscFunctionBeginUser;
  *pending = PETSC_FALSE;
  for (;;) {
    PetscCall(ReadLine(r, &more));
    if (!more) SPAM_BAD_INPUT("-file_path", r->path, "the file holds no header and no particles");
    PetscCall(CheckLine(r));
    if (r->line[0] && r->line[0] != '#') break;
  }
  if (LooksLikeData(r->line)) {
    double      vals[NSLOTS];
    const char *bad_why;
    int         bad, k = ParseLine(r->line, vals, NSLOTS, &bad, &bad_why);
    if (k >= 0 && k != 2 * dim && k != 2 * dim + 1) CSV_BAD_LINE(r, "a file without a header holds %d or %d numbers a line (positions, velocities and optionally the mass for -dim %d), found %d; or give a header naming the columns", 2 * dim, 2 * dim + 1, dim, k);
    SpamColumnsLegacy(dim, k < 0 ? 2 * dim : k, map);
    *pending = PETSC_TRUE;
  } else if (SpamColumnsParse(r->line, dim, map, why, sizeof why)) CSV_BAD_LINE(r, "%s", why);
  PetscFunctionReturn(0);
}

/* Every data line as its slots into *rows ([n][NSLOTS], allocated here). */
static PetscErrorCode ReadRows(CsvReader *r, const SpamCommonParams *c, const SpamColumnMap *map, PetscBool pending, double **rows, size_t *n)
{
  const double maxn = SpamMaxParticles();
  size_t       cap  = 1024;
  PetscBool    more = PETSC_TRUE;

  PetscFunctionBeginUser;
  r->max_particles = maxn; /* the id check of every line (ParseParticle) */
  *n = 0;
  PetscCall(PetscMalloc1(cap * NSLOTS, rows));
  for (;;) {
    if (!pending) {
      PetscCall(ReadLine(r, &more));
      if (!more) break;
      PetscCall(CheckLine(r));
      if (!r->line[0] || r->line[0] == '#') continue;
    }
    pending = PETSC_FALSE;
    if ((double)*n >= maxn) CSV_BAD_LINE(r, "the file holds more than %.4g particles, the most that 32-bit state indices and this machine's physical memory allow", maxn);
    if (*n == cap) {
      cap *= 2;
      PetscCall(PetscRealloc(sizeof(double) * cap * NSLOTS, rows));
    }
    PetscCall(ParseParticle(r, c, map, *rows + *n * NSLOTS));
    ++*n;
  }
  if (*n == 0) SPAM_BAD_INPUT("-file_path", r->path, "the file has a header but no particles");
  PetscFunctionReturn(0);
}

/* The rows into the arrays of out, then the particles in the order of their ids. */
static PetscErrorCode Distribute(const char *path, int dim, const SpamColumnMap *map, const double *rows, PetscInt n, SpamParticles *out)
{
  const int   ns = SpamStressComponents(dim);
  PetscInt    bad;
  const char *why;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocateColumns(dim, n, map->columns, out));
  for (PetscInt i = 0; i < n; i++) {
    const double *s = rows + (size_t)i * NSLOTS;
    for (int d = 0; d < dim; d++) {
      out->x[i * dim + d] = s[SLOT_X + d];
      out->v[i * dim + d] = s[SLOT_V + d];
    }
    if (out->m) out->m[i] = s[SLOT_M];
    if (out->id) out->id[i] = (PetscInt)s[SLOT_ID];
    if (!out->e) continue;
    out->e[i]   = s[SLOT_E];
    out->rho[i] = s[SLOT_RHO];
    for (int k = 0; k < ns; k++) out->sigma[(size_t)i * ns + k] = s[SLOT_S + k];
  }
  out->mass = out->m ? out->m[0] : -1.0;
  PetscCall(SpamParticlesOrderById(out, &bad, &why));
  if (bad >= 0) {
    char row[64];
    (void)snprintf(row, sizeof row, "id %" PetscInt_FMT " of particle %" PetscInt_FMT, out->id[bad], bad + 1);
    SPAM_BAD_INPUT(path, row, "%s; the ids of %" PetscInt_FMT " particles are 0..%" PetscInt_FMT ", each once (particle k is row k of every output)", why, n, n - 1);
  }
  PetscFunctionReturn(0);
}

/* Reads the whole CSV file into out (the caller frees out on an error as on success). */
static PetscErrorCode ReadCsv(CsvReader *r, const SpamCommonParams *c, SpamParticles *out)
{
  SpamColumnMap  map;
  PetscBool      pending;
  double        *rows = NULL;
  size_t         n    = 0;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(ReadHeader(r, c->dim, &map, &pending));
  ierr = ReadRows(r, c, &map, pending, &rows, &n);
  if (!ierr) ierr = Distribute(r->path, c->dim, &map, rows, (PetscInt)n, out);
  PetscCall(PetscFree(rows));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* The HDF5 signature at the start of the file (or after a user block of 512, 1024 or 2048
 * bytes, where HDF5 also looks): the file's content decides, not its name. */
static PetscBool HasHdf5Signature(FILE *f)
{
  static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  static const long          at[4]  = {0, 512, 1024, 2048};
  unsigned char              buf[8];

  for (int k = 0; k < 4; k++) {
    if (fseek(f, at[k], SEEK_SET) || fread(buf, 1, 8, f) != 8) break;
    if (!memcmp(buf, sig, 8)) return PETSC_TRUE;
  }
  rewind(f);
  return PETSC_FALSE;
}
/* The box is checked before any particle is compared with it, so that a box too small or
 * too far out (SpamBoxValidate: positive finite edges, corners within 1e9 h, NaN included)
 * is named as such rather than by a particle outside it. */
static PetscErrorCode CheckBox(const SpamCommonParams *c)
{
  SpamBox box = {c->dim, {0, 0, 0}, {0, 0, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};

  PetscFunctionBeginUser;
  if (!c->box_len_set) SPAM_BAD_INPUT("-box_len", "(not given)", "the file scene needs the box edge lengths of a CSV file, e.g. -box_len 64,64 (an HDF5 snapshot carries its box)");
  for (int d = 0; d < c->dim; d++) {
    box.lo[d]       = c->box_lo[d];
    box.len[d]      = c->box_len[d];
    box.periodic[d] = c->periodic[d];
  }
  PetscCall(SpamBoxValidate(&box, c->h, "-box_lo/-box_len"));
  PetscFunctionReturn(0);
}

/* The box of a CSV file comes from the options: -box_len is required. */
static PetscErrorCode SetBox(const SpamCommonParams *c, SpamParticles *out)
{
  PetscFunctionBeginUser;
  out->box.dim = c->dim;
  for (int d = 0; d < c->dim; d++) {
    out->box.lo[d]       = c->box_lo[d];
    out->box.len[d]      = c->box_len[d];
    out->box.periodic[d] = c->periodic[d];
  }
  PetscFunctionReturn(0);
}

/* A file with masses (column m, or a snapshot's /mass) and -mass as well: they must agree,
 * else one of the two would be ignored without a word. */
static PetscErrorCode CheckMassOption(const SpamCommonParams *c, const char *path, const SpamParticles *out)
{
  PetscBool set;
  char      val[128], first[32];

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, "-mass", &set));
  if (!set || !out->m) PetscFunctionReturn(0);
  PetscCall(SpamOptionText("-mass", c->mass, val, sizeof val));
  (void)snprintf(first, sizeof first, "%.17g", out->m[0]); /* PETSc's %g writes 1 as "1." */
  for (PetscInt i = 0; i < out->n; i++)
    if (out->m[i] != c->mass) SPAM_BAD_INPUT("-mass", val, "the file %s gives the masses (column m: %s for particle 1); omit -mass or give the file's", path, first);
  PetscFunctionReturn(0);
}

static PetscErrorCode SpamFileBuild(const SpamCommonParams *c, const SpamFileParams *p, SpamParticles *out)
{
  CsvReader     *r;
  PetscBool      hdf5 = PETSC_FALSE;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(out, sizeof *out));
  if (!p->path[0]) SPAM_BAD_INPUT("-file_path", "(not given)", "the file scene needs a CSV file of particles or an HDF5 snapshot");
  PetscCall(PetscNew(&r));
  r->path = p->path;
  ierr    = OpenRegular(p->path, &r->f);
  if (!ierr) {
    hdf5 = HasHdf5Signature(r->f);
    /* the checksum before HDF5 parses anything: a damaged header never reaches the library */
    if (hdf5) ierr = SpamSnapshotVerify(r->f, p->path);
    if (!ierr && !hdf5) ierr = CheckBox(c);
    if (!ierr && !hdf5) ierr = ReadCsv(r, c, out);
    (void)fclose(r->f);
  }
  PetscCall(PetscFree(r));
  if (!ierr && hdf5) ierr = SpamFileReadHdf5(c, p->path, out);
  if (!ierr) ierr = CheckMassOption(c, p->path, out);
  if (ierr) PetscCall(SpamParticlesFree(out)); /* nothing read is kept after an error */
  PetscCall(ierr);
  if (!hdf5) PetscCall(SetBox(c, out));
  if (out->mass < 0.0) out->mass = c->mass;
  PetscCall(PetscStrncpy(out->info.name, "file", sizeof out->info.name));
  out->info.t_end_default = 10.0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Options(const SpamCommonParams *c, void *p, SpamSolidParams *solid)
{
  PetscFunctionBeginUser;
  SpamSolidDefaults(solid);
  solid->material        = SPAM_MATERIAL_ISENTROPE;
  solid->density = SPAM_DENSITY_SUMMATION; /* a continuity density starts from the file's rho, else summed (scene.c) */
  solid->rho0    = c->mass;
  PetscCall(SpamFileOptions(p));
  PetscFunctionReturn(0);
}

/* -help without a file: one particle at rest in the middle of the box given, or of a box
 * 8 h wide, so that the set-up after the scene lists its options too. The listing needs no
 * file, and a swarm of no particles is one PETSc cannot set up. Nothing runs with -help. */
static PetscErrorCode HelpPlaceholder(const SpamCommonParams *c, SpamParticles *out)
{
  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(c->dim, 1, out));
  out->box.dim = c->dim;
  for (int d = 0; d < c->dim; d++) {
    out->box.lo[d]       = c->box_lo[d];
    out->box.len[d]      = c->box_len_set ? c->box_len[d] : 8.0 * c->h;
    out->box.periodic[d] = c->periodic[d];
    out->x[d]            = out->box.lo[d] + 0.5 * out->box.len[d];
  }
  out->mass = c->mass;
  PetscCall(PetscStrncpy(out->info.name, "file", sizeof out->info.name));
  out->info.t_end_default = 10.0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(const SpamCommonParams *c, const void *p, const SpamSolidParams *solid, SpamParticles *out)
{
  const SpamFileParams *fp = p;
  PetscBool             help;

  PetscFunctionBeginUser;
  (void)solid;
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  if (help && !fp->path[0]) PetscCall(HelpPlaceholder(c, out));
  else PetscCall(SpamFileBuild(c, fp, out));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneFile(SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  *ops = (SpamSceneOps){"file", 2 | 4 | 8, PETSC_FALSE, Table, sizeof(SpamFileParams), PETSC_TRUE, "-box_len", Options, Build};
  PetscFunctionReturn(0);
}
