/* Evaluation of the smooth-particle fields at the points of a regular grid (grid.h). It runs
 * at output times only, so it bins the particles itself into cells at least h wide (the
 * neighbour list's cells belong to the right-hand side and may be built for another state)
 * and visits, for each point, the particles of its cell and the adjacent ones. */
#include <spam/grid.h>
#include <limits.h>

double SpamGridPointCount(const SpamBox *box, double dx)
{
  double total = 1.0;
  for (int d = 0; d < box->dim; d++) total *= PetscMax(1.0, ceil(box->len[d] / dx));
  return total;
}

PetscErrorCode SpamGridSetUp(const SpamBox *box, double dx, SpamGrid *g)
{
  const double points = SpamGridPointCount(box, dx);

  PetscFunctionBeginUser;
  PetscCheck(dx > 0.0 && isfinite(dx) && points <= SPAM_GRID_MAX_POINTS, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "grid spacing %g gives %g points, at most %g", dx, points, SPAM_GRID_MAX_POINTS);
  PetscCall(PetscMemzero(g, sizeof *g));
  g->dim       = box->dim;
  g->requested = dx;
  g->npoints   = 1;
  for (int d = 0; d < 3; d++) {
    g->n[d]       = d < box->dim ? (PetscInt)PetscMax(1.0, ceil(box->len[d] / dx)) : 1;
    g->spacing[d] = d < box->dim ? box->len[d] / (double)g->n[d] : 0.0;
    g->origin[d]  = d < box->dim ? box->lo[d] + 0.5 * g->spacing[d] : 0.0;
    g->npoints *= g->n[d];
  }
  PetscFunctionReturn(0);
}

/* The particles binned into cells (CSR), with their box-local coordinates. */
typedef struct {
  int       dim, ncell[3];
  double    width[3];
  PetscBool periodic[3];
  SpamImage im;           /* minimum image of the box's periodic directions           */
  PetscInt *start, *list; /* particles of cell c: list[start[c] .. start[c+1])           */
  double   *u;            /* [n*3] box-local positions (wrapped in periodic directions)  */
} Bins;

/* Cells at least h wide, halved along every direction while there are many more cells
 * than particles (a tiny h in a big box would otherwise ask for a huge empty array). */
static void BinsShape(const SpamBox *box, double h, PetscInt n, Bins *b)
{
  double total = 1.0;

  b->dim = box->dim;
  for (int d = 0; d < 3; d++) {
    b->ncell[d]    = d < box->dim ? (int)PetscMin(1e6, PetscMax(1.0, floor(box->len[d] / h))) : 1;
    b->periodic[d] = d < box->dim ? box->periodic[d] : PETSC_FALSE;
    total *= b->ncell[d];
  }
  while (total > 8.0 * (double)n + 64.0) {
    total = 1.0;
    for (int d = 0; d < box->dim; d++) {
      b->ncell[d] = PetscMax(1, b->ncell[d] / 2);
      total *= b->ncell[d];
    }
  }
  for (int d = 0; d < box->dim; d++) b->width[d] = box->len[d] / b->ncell[d];
}

/* Cell of a box-local coordinate along d; a particle outside the box in an open direction
 * goes to the edge cell: it is farther from every point than that cell's particles. */
static int CellAlong(const Bins *b, int d, double u)
{
  const double c = floor(u / b->width[d]);
  return c < 0 ? 0 : c >= b->ncell[d] ? b->ncell[d] - 1 : (int)c;
}

static int CellOf(const Bins *b, const double *u)
{
  int c = 0;
  for (int d = b->dim - 1; d >= 0; d--) c = c * b->ncell[d] + CellAlong(b, d, u[d]);
  return c;
}

static PetscErrorCode BinsBuild(const SpamSim *sim, const double *y, Bins *b)
{
  const SpamLayout *l = &sim->model.layout;
  const PetscInt    n = sim->p.n;
  PetscInt          ncells, *fill;

  PetscFunctionBeginUser;
  BinsShape(&sim->geo.box, sim->model.kernel.h, n, b);
  b->im = SpamBoxImage(&sim->geo.box);
  ncells = (PetscInt)b->ncell[0] * b->ncell[1] * b->ncell[2];
  PetscCall(PetscCalloc1(ncells + 1, &b->start));
  PetscCall(PetscCalloc1(n + 1, &b->list));
  PetscCall(PetscCalloc1(3 * n + 1, &b->u));
  PetscCall(PetscCalloc1(ncells + 1, &fill));
  for (PetscInt i = 0; i < n; i++) {
    for (int d = 0; d < b->dim; d++) b->u[3 * i + d] = SpamBoxLocal(&sim->geo.box, d, y[(size_t)i * l->nvar + l->x + d]);
    b->start[CellOf(b, b->u + 3 * i) + 1]++;
  }
  for (PetscInt c = 0; c < ncells; c++) b->start[c + 1] += b->start[c];
  for (PetscInt i = 0; i < n; i++) {
    const int c                   = CellOf(b, b->u + 3 * i);
    b->list[b->start[c] + fill[c]++] = i;
  }
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(0);
}

static PetscErrorCode BinsFree(Bins *b)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(b->start));
  PetscCall(PetscFree(b->list));
  PetscCall(PetscFree(b->u));
  PetscFunctionReturn(0);
}

/* The distinct cells along d that can hold a particle within h of a point in cell c:
 * c - 1 .. c + 1, wrapped when periodic (all of them when there are fewer than 3),
 * clipped when open. Returns how many. */
static int Neighbouring(const Bins *b, int d, int c, int out[3])
{
  int k = 0;
  if (b->periodic[d] && b->ncell[d] < 3) {
    for (int a = 0; a < b->ncell[d]; a++) out[k++] = a;
    return k;
  }
  for (int a = c - 1; a <= c + 1; a++) {
    int w = a;
    if (b->periodic[d]) w = (a + b->ncell[d]) % b->ncell[d];
    else if (a < 0 || a >= b->ncell[d]) continue;
    out[k++] = w;
  }
  return k;
}

/* Where a particle's fields go among the columns (rho is summed with m_j itself, the
 * others with m_j / rho_j, S with m_j / rho_j alone). */
typedef struct {
  int    ne, nt, ns; /* columns of e, T and the first stress (-1: none)                 */
  int    nstress;
  double gamma1;     /* gamma - 1 of the gas (T = (gamma - 1) e)                         */
} ColumnMap;

/* Particle j's fields in column order into val. */
static void ParticleValues(const SpamModel *model, const double *y, PetscInt j, const ColumnMap *lc, const SpamGridFields *f, double *val)
{
  const SpamLayout *l = &model->layout;
  const double     *p = y + (size_t)j * l->nvar;

  for (int d = 0; d < model->dim; d++) val[f->v + d] = p[l->v + d];
  if (lc->ne >= 0) val[lc->ne] = p[l->e];
  if (lc->nt >= 0) val[lc->nt] = lc->gamma1 * p[l->e];
  for (int k = 0; k < lc->nstress; k++) val[lc->ns + k] = p[l->s + k];
}

/* The fields at the point at box-local u: one pass over the neighbouring cells. */
static void EvaluatePoint(const SpamSim *sim, const double *y, const Bins *b, const ColumnMap *lc, const SpamGridFields *f, const double *u, double *sum)
{
  const int       dim = b->dim;
  int             cell[3] = {0, 0, 0}, nb[3][3], nn[3] = {1, 1, 1};
  double          val[SPAM_GRID_MAX_COLUMNS] = {0};

  for (int c = 0; c < f->ncol; c++) sum[c] = 0.0;
  for (int d = 0; d < dim; d++) {
    cell[d] = CellAlong(b, d, u[d]);
    nn[d]   = Neighbouring(b, d, cell[d], nb[d]);
  }
  for (int d = dim; d < 3; d++) nb[d][0] = 0;
  for (int a = 0; a < nn[2]; a++)
    for (int bb = 0; bb < nn[1]; bb++)
      for (int cc = 0; cc < nn[0]; cc++) {
        const int c = nb[0][cc] + b->ncell[0] * (nb[1][bb] + b->ncell[1] * nb[2][a]);
        for (PetscInt k = b->start[c]; k < b->start[c + 1]; k++) {
          const PetscInt j  = b->list[k];
          double         r2 = 0.0;
          for (int d = 0; d < dim; d++) {
            const double dx = SpamImageDelta(&b->im, d, u[d] - b->u[3 * j + d]);
            r2 += dx * dx;
          }
          const double w = SpamKernelW(&sim->model.kernel, r2);
          if (w == 0.0) continue;
          const double mw = sim->pair.f.m[j] * w, vw = mw / SpamSnapshotDensity(sim, y, j);
          ParticleValues(&sim->model, y, j, lc, f, val);
          sum[0] += mw;
          for (int col = 1; col < f->ncol - 1; col++) sum[col] += vw * val[col];
          sum[f->ncol - 1] += vw;
        }
      }
}

/* Columns rho, vx.., e, T (gas), the stress components in the state's order, S. */
static PetscErrorCode Columns(const SpamModel *model, const SpamGrid *g, SpamGridFields *f, ColumnMap *lc)
{
  static const char *vn[3] = {"vx", "vy", "vz"};
  static const char *s1[1] = {"sxx"}, *s2[3] = {"sxx", "sxy", "syy"}, *s3[6] = {"sxx", "sxy", "sxz", "syy", "syz", "szz"};
  const SpamLayout  *l   = &model->layout;
  const int          dim = model->dim;
  const char *const *sn  = dim == 1 ? s1 : dim == 2 ? s2 : s3;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof *f));
  lc->ne = lc->nt = lc->ns = -1;
  lc->nstress              = l->s >= 0 ? dim * (dim + 1) / 2 : 0;
  lc->gamma1               = model->solid.gamma - 1.0;
  f->name[f->ncol++]       = "rho";
  f->v                     = f->ncol;
  for (int d = 0; d < dim; d++) f->name[f->ncol++] = vn[d];
  if (l->e >= 0) {
    lc->ne             = f->ncol;
    f->name[f->ncol++] = "e";
    if (model->solid.material == SPAM_MATERIAL_GAS) {
      lc->nt             = f->ncol;
      f->name[f->ncol++] = "T";
    }
  }
  if (lc->nstress) lc->ns = f->ncol;
  for (int k = 0; k < lc->nstress; k++) f->name[f->ncol++] = sn[k];
  f->name[f->ncol++] = "S";
  /* one block, so that one reduction sums every column over the ranks */
  PetscCall(PetscCalloc1((size_t)f->ncol * g->npoints, &f->block));
  for (int c = 0; c < f->ncol; c++) f->col[c] = f->block + (size_t)c * g->npoints;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamGridFieldsEvaluate(const SpamSim *sim, const double *y, const SpamGrid *g, SpamGridFields *f)
{
  Bins   b = {0};
  ColumnMap lc;
  double sum[SPAM_GRID_MAX_COLUMNS];

  PetscFunctionBeginUser;
  PetscCall(Columns(&sim->model, g, f, &lc));
  PetscCall(BinsBuild(sim, y, &b));
  for (PetscInt p = 0; p < g->npoints; p++) {
    const PetscInt idx[3] = {p % g->n[0], (p / g->n[0]) % g->n[1], p / (g->n[0] * g->n[1])};
    double         u[3]   = {0, 0, 0};
    for (int d = 0; d < g->dim; d++) u[d] = ((double)idx[d] + 0.5) * g->spacing[d];
    EvaluatePoint(sim, y, &b, &lc, f, u, sum);
    for (int c = 0; c < f->ncol; c++) f->col[c][p] = sum[c];
  }
  PetscCall(BinsFree(&b));
  /* Every column is a sum over particles, linear in each particle's part: the ranks'
   * partial sums add up to the whole (nothing nonlinear has been applied yet). */
  PetscCheck((double)f->ncol * g->npoints <= INT_MAX, sim->p.comm, PETSC_ERR_SUP, "grid of %" PetscInt_FMT " points: too many to reduce in one call", g->npoints);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, f->block, f->ncol * (int)g->npoints, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamGridFieldsFree(SpamGridFields *f)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(f->block));
  for (int c = 0; c < f->ncol; c++) f->col[c] = NULL;
  f->ncol = 0;
  PetscFunctionReturn(0);
}
