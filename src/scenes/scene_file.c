/* Particles read from a CSV file: header x[,y[,z]],vx[,vy[,vz]][,m] matching -dim, one
 * particle per line, every value a finite number. The box comes from -box_lo/-box_len. */
#include <spam/scene.h>
#include <spam/errors.h>
#include <errno.h>

PetscErrorCode SpamFileOptions(SpamFileParams *p)
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

static void Chomp(char *s)
{
  size_t n = strlen(s);
  while (n && (s[n - 1] == '\n' || s[n - 1] == '\r' || s[n - 1] == ' ')) s[--n] = 0;
}

/* Parses one data line into vals; returns the number of fields, or -1 on a field that is
 * not a finite number (its 1-based index in *badfield). */
static int ParseLine(char *line, double *vals, int max, int *badfield)
{
  int   k = 0;
  char *s = line;
  for (;;) {
    char  *end;
    double v;
    errno = 0;
    v     = strtod(s, &end);
    while (*end == ' ' || *end == '\t') end++;
    if (end == s || (*end != ',' && *end != 0) || errno == ERANGE || !isfinite(v)) {
      *badfield = k + 1;
      return -1;
    }
    if (k < max) vals[k] = v;
    k++;
    if (*end == 0) return k;
    s = end + 1;
  }
}

static PetscErrorCode ReadBody(FILE *f, const char *path, int dim, int nf, SpamParticles *out)
{
  char     line[4096], where[PETSC_MAX_PATH_LEN + 32];
  PetscInt cap = 1024, n = 0, lineno = 1;
  double  *x, *v, vals[8], mass = -1.0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(cap * dim, &x));
  PetscCall(PetscMalloc1(cap * dim, &v));
  while (fgets(line, sizeof line, f)) {
    int bad = 0, k;
    lineno++;
    Chomp(line);
    if (!line[0] || line[0] == '#') continue;
    PetscCall(PetscSNPrintf(where, sizeof where, "%s:%" PetscInt_FMT, path, lineno));
    k = ParseLine(line, vals, 8, &bad);
    if (k < 0) SPAM_BAD_INPUT(where, line, "field %d is not a finite number", bad);
    if (k != nf) SPAM_BAD_INPUT(where, line, "expected %d comma-separated numbers, found %d", nf, k);
    if (nf == 2 * dim + 1) {
      if (!(vals[2 * dim] > 0.0)) SPAM_BAD_INPUT(where, line, "mass must be positive");
      if (mass < 0.0) mass = vals[2 * dim];
      if (vals[2 * dim] != mass) SPAM_BAD_INPUT(where, line, "every particle must have the same mass (%g on the first line); unequal masses are not supported yet", mass);
    }
    if (n == cap) {
      cap *= 2;
      PetscCall(PetscRealloc(sizeof(double) * cap * dim, &x));
      PetscCall(PetscRealloc(sizeof(double) * cap * dim, &v));
    }
    for (int d = 0; d < dim; d++) {
      x[n * dim + d] = vals[d];
      v[n * dim + d] = vals[dim + d];
    }
    n++;
  }
  if (n == 0) SPAM_BAD_INPUT("-file_path", path, "the file has a header but no particles");
  out->dim  = dim;
  out->n    = n;
  out->x    = x;
  out->v    = v;
  out->mass = mass;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFileBuild(const SpamCommonParams *c, const SpamFileParams *p, SpamParticles *out)
{
  char  header[4096], with_m[64], without_m[64];
  FILE *f;
  int   nf;

  PetscFunctionBeginUser;
  if (!p->path[0]) SPAM_BAD_INPUT("-file_path", "README", "the file scene needs a CSV file of particles");
  if (!c->box_len_set) SPAM_BAD_INPUT("-box_len", "README", "the file scene needs the box edge lengths, e.g. -box_len 64,64");
  f = fopen(p->path, "r");
  if (!f) SPAM_BAD_INPUT("-file_path", p->path, "cannot open the file (%s)", strerror(errno));
  Header(c->dim, PETSC_TRUE, with_m, sizeof with_m);
  Header(c->dim, PETSC_FALSE, without_m, sizeof without_m);
  if (!fgets(header, sizeof header, f)) header[0] = 0;
  Chomp(header);
  if (!strcmp(header, with_m)) nf = 2 * c->dim + 1;
  else if (!strcmp(header, without_m)) nf = 2 * c->dim;
  else {
    char where[PETSC_MAX_PATH_LEN + 8];
    fclose(f);
    PetscCall(PetscSNPrintf(where, sizeof where, "%s:1", p->path));
    SPAM_BAD_INPUT(where, header, "header must be '%s' or '%s' for -dim %d", without_m, with_m, c->dim);
  }
  PetscCall(PetscMemzero(out, sizeof *out));
  {
    PetscErrorCode ierr = ReadBody(f, p->path, c->dim, nf, out);
    fclose(f);
    PetscCall(ierr);
  }
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
