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
  for (PetscInt r = 0; r < rows->n; r++) {
    const double *p = rows->y + (size_t)r * l->nvar;
    for (int d = 0; d < dim; d++) SpamFilePrintf(&f, "%s%.17g", d ? "," : "", SpamSnapshotPosition(&sim->geo.box, d, p[l->x + d]));
    for (int d = 0; d < dim; d++) SpamFilePrintf(&f, ",%.17g", p[l->v + d]);
    SpamFilePrintf(&f, ",%.17g", rows->m[r]);
    if (l->e >= 0) SpamFilePrintf(&f, ",%.17g", p[l->e]);
    if (l->rho >= 0) SpamFilePrintf(&f, ",%.17g", p[l->rho]);
    for (int k = 0; l->s >= 0 && k < dim * (dim + 1) / 2; k++) SpamFilePrintf(&f, ",%.17g", p[l->s + k]);
    SpamFilePrintf(&f, ",%" PetscInt64_FMT, rows->gid[r]);
    if (w->rho_sum) SpamFilePrintf(&f, ",%.17g", rows->rho_sum[r]);
    SpamFilePrintf(&f, "\n");
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
