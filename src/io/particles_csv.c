/* Particles as CSV in the one format the file scene reads (src/scenes/particle_header.c):
 * a header naming the columns, one particle per row in input order, full precision. Both
 * -initial_csv/-final_csv and the CSV snapshots write it, so every such file reads back.
 * On several ranks the rows are gathered to rank 0 in gid order (particle_rows.c) and
 * rank 0 writes the one file: CSV is for runs small enough to read as text. */
#include <spam/output.h>
#include "particle_rows.h"

/* Stress component names of the state's order (the upper triangle row by row). */
static const char *StressName(int dim, int k)
{
  static const char *s2[3] = {"sxx", "sxy", "syy"};
  static const char *s3[6] = {"sxx", "sxy", "sxz", "syy", "syz", "szz"};
  return dim == 1 ? "sxx" : dim == 2 ? s2[k] : s3[k];
}

/* The header: x..,vx..,m[,e][,rho][,stress],id[,rho_sum]. */
static void Header(SpamFile *f, const SpamLayout *l, PetscBool rho_sum)
{
  static const char *ax[3] = {"x", "y", "z"};
  const int          dim   = l->dim;

  for (int d = 0; d < dim; d++) SpamFilePrintf(f, "%s%s", d ? "," : "", ax[d]);
  for (int d = 0; d < dim; d++) SpamFilePrintf(f, ",v%s", ax[d]);
  SpamFilePrintf(f, ",m");
  if (l->e >= 0) SpamFilePrintf(f, ",e");
  if (l->rho >= 0) SpamFilePrintf(f, ",rho");
  for (int k = 0; l->s >= 0 && k < dim * (dim + 1) / 2; k++) SpamFilePrintf(f, ",%s", StressName(dim, k));
  SpamFilePrintf(f, ",id%s\n", rho_sum ? ",rho_sum" : "");
}

/* sep (if any) and "%.17g" of v at p, without printf's digits; returns the new end. */
static char *Value(char *p, char sep, double v)
{
  if (sep) *p++ = sep;
  return p + SpamFormatG17(v, p);
}

/* ",%" PetscInt64_FMT " of id at p; returns the new end. */
static char *Id(char *p, PetscInt64 id)
{
  char buf[24], *q = buf + sizeof buf;

  if (id < 0) return p + snprintf(p, 24, ",%" PetscInt64_FMT, id);
  do *--q = (char)('0' + id % 10);
  while ((id /= 10) > 0);
  *p++ = ',';
  memcpy(p, q, (size_t)(buf + sizeof buf - q));
  return p + (buf + sizeof buf - q);
}

/* The rows gathered on rank 0 and what to write around them. */
typedef struct {
  const char     *path, *comment;
  const SpamSim  *sim;
  const SpamRows *rows;
  PetscBool       rho_sum;
} CsvWork;

/* rho_sum: the summed density of a model that does not carry it (sim->pair.f.rho of state y),
 * for charts; the file scene recognises the column and does not read it. Rank 0 only. */
static PetscErrorCode WriteRowsOnRoot(void *ctx)
{
  const CsvWork    *w   = ctx;
  const SpamSim    *sim = w->sim;
  const SpamRows   *rows = w->rows;
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim;
  SpamFile          f;

  PetscFunctionBeginUser;
  PetscCall(SpamFileBegin(w->path, &f));
  if (w->comment) SpamFilePrintf(&f, "# %s\n", w->comment);
  Header(&f, l, w->rho_sum);
  /* A row is one write: a write a value took 0.4 of the row's instructions in the C
   * library's stream functions (callgrind, 65536 particles). At most 16 values of 32 bytes
   * (SpamFormatG17) and an id in the row's buffer. */
  for (PetscInt r = 0; r < rows->n; r++) {
    const double *p = rows->y + (size_t)r * l->nvar;
    char          row[640], *e = row;
    for (int d = 0; d < dim; d++) e = Value(e, d ? ',' : 0, SpamSnapshotPosition(&sim->geo.box, d, p[l->x + d]));
    for (int d = 0; d < dim; d++) e = Value(e, ',', p[l->v + d]);
    e = Value(e, ',', rows->m[r]);
    if (l->e >= 0) e = Value(e, ',', p[l->e]);
    if (l->rho >= 0) e = Value(e, ',', p[l->rho]);
    for (int k = 0; l->s >= 0 && k < dim * (dim + 1) / 2; k++) e = Value(e, ',', p[l->s + k]);
    e = Id(e, rows->gid[r]);
    if (w->rho_sum) e = Value(e, ',', rows->rho_sum[r]);
    *e++ = '\n';
    *e   = 0;
    SpamFilePuts(&f, row);
  }
  PetscCall(SpamFileCommit(&f));
  PetscFunctionReturn(0);
}

/* Collective on sim->p.comm. */
static PetscErrorCode WriteRows(const char *path, const SpamSim *sim, const double *y, const char *comment, PetscBool with_rho_sum)
{
  SpamRows       rows;
  CsvWork        w = {path, comment, sim, &rows, (PetscBool)(with_rho_sum && sim->model.layout.rho < 0)};
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(SpamRowsGather(sim, y, SPAM_ROWS_ON_ROOT, &rows));
  ierr = SpamRunAgreed(sim->p.comm, PETSC_TRUE, WriteRowsOnRoot, &w);
  PetscCall(SpamRowsFree(&rows));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamParticlesCsvWrite(const char *path, const SpamSim *sim, const double *y)
{
  PetscFunctionBeginUser;
  PetscCall(WriteRows(path, sim, y, NULL, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* A snapshot: the time as a leading comment, and the summed density for charts. */
PetscErrorCode SpamSnapshotCsvWrite(const char *path, const SpamSim *sim, const double *y, double t)
{
  char comment[64];

  PetscFunctionBeginUser;
  (void)snprintf(comment, sizeof comment, "t=%.10g", t);
  PetscCall(WriteRows(path, sim, y, comment, PETSC_TRUE));
  PetscFunctionReturn(0);
}
