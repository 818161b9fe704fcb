/* Grid fields (grid.h) written at a snapshot time: grid_NNNNN.h5, one dataset per field
 * shaped like the grid ([nz][ny][nx] in 3D, [ny][nx] in 2D, [1][nx] in 1D: x fastest) plus
 * the velocity as [..][3] for ParaView, the index grid.xmf over all of them (a temporal
 * collection of 2DCoRectMesh/3DCoRectMesh grids, values at the nodes), and
 * grid_NNNNN.csv with columns x,y,(z) and the fields, one row per point in the same order.
 * Every file is written to a new temporary and renamed when complete, as the snapshots.
 * On several ranks rank 0 writes them all, from the fields reduced over the ranks. */
#define _DEFAULT_SOURCE /* close, unlink: POSIX, not C11 */
#include <spam/grid.h>
#include "snapshot_hdf5.h"

#include <errno.h>
#include <unistd.h>

typedef struct {
  hid_t       file;
  const char *path;
  long        writes, fail_at; /* test-only injected failure, see output.h */
} GridH5;

#define PetscCallGridH5(h, call) SpamCallH5((h)->path, call)

/* The grid's shape as HDF5 and XDMF give it, slowest first: z y x (a 1D grid is one row). */
static int Shape(const SpamGrid *g, hsize_t shape[4])
{
  const int rank = g->dim == 1 ? 2 : g->dim;
  for (int r = 0; r < rank; r++) shape[r] = (hsize_t)(g->dim == 1 ? (r ? g->n[0] : 1) : g->n[rank - 1 - r]);
  return rank;
}

/* Every id made here is closed also when a call fails. */
static PetscErrorCode WriteDataset(GridH5 *h, const SpamGrid *g, const char *name, const double *data, int ncomp)
{
  hsize_t     shape[4];
  int         rank = Shape(g, shape), e;
  const hid_t dcpl = SpamH5Untimed(H5P_DATASET_CREATE);
  hid_t       space = -1, set = -1;
  herr_t      w = -1;

  PetscFunctionBeginUser;
  if (ncomp > 1) shape[rank++] = (hsize_t)ncomp;
  errno = 0;
  if (dcpl >= 0 && (space = H5Screate_simple(rank, shape, NULL)) >= 0) set = H5Dcreate2(h->file, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (set >= 0) w = ++h->writes == h->fail_at ? (errno = ENOSPC, -1) : H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  e = errno; /* the failure's reason, before the closes */
  if (set >= 0 && H5Dclose(set) < 0) w = -1;
  if (space >= 0) (void)H5Sclose(space);
  if (dcpl >= 0) (void)H5Pclose(dcpl);
  errno = e;
  if (w < 0) PetscCall(SpamH5Failed(h->path));
  PetscFunctionReturn(0);
}

/* The velocity as one [..][3] dataset (vz = 0 below 3D): an XDMF Vector. */
static PetscErrorCode WriteVelocity(GridH5 *h, const SpamGrid *g, const SpamGridFields *f)
{
  double        *v;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(3 * g->npoints, &v));
  for (PetscInt p = 0; p < g->npoints; p++)
    for (int d = 0; d < g->dim; d++) v[3 * p + d] = f->col[f->v + d][p];
  ierr = WriteDataset(h, g, "/velocity", v, 3);
  PetscCall(PetscFree(v));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* The snapshot's root attributes (time, step, box, kernel_h, model, ...) and the grid's:
 * spacing, dims (points along x, y, z), origin (the first point), grid_interval (as
 * asked), kernel, columns and what the sums are. */
static herr_t GridAttributes(hid_t file, const SpamSim *sim, const SpamGrid *g, const SpamGridFields *f, double t, long step)
{
  char      model[2048], columns[256] = "";
  long long dims[3];

  for (int d = 0; d < g->dim; d++) dims[d] = g->n[d];
  for (int c = 0; c < f->ncol; c++) {
    (void)strncat(columns, c ? "," : "", sizeof columns - strlen(columns) - 1);
    (void)strncat(columns, f->name[c], sizeof columns - strlen(columns) - 1);
  }
  if (SpamModelSettingsJson(&sim->model, model, sizeof model)) return -1;
  if (SpamSnapshotAttributes(file, sim, t, step, model) < 0) return -1;
  if (SpamH5Attribute(file, "spacing", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, (hsize_t)g->dim, g->spacing) < 0) return -1;
  if (SpamH5Attribute(file, "dims", H5T_STD_I64LE, H5T_NATIVE_LLONG, (hsize_t)g->dim, dims) < 0) return -1;
  if (SpamH5Attribute(file, "origin", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, (hsize_t)g->dim, g->origin) < 0) return -1;
  if (SpamH5Attribute(file, "grid_interval", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, &g->requested) < 0) return -1;
  if (SpamH5StringAttribute(file, "kernel", sim->model.kernel.name) < 0) return -1;
  if (SpamH5StringAttribute(file, "columns", columns) < 0) return -1;
  return SpamH5StringAttribute(file, "sums", "rho = sum m_j w, A = sum (m_j/rho_j) A_j w, S = sum (m_j/rho_j) w over local particles (minimum image, no wall images: S < 1 near walls and free surfaces)");
}

static PetscErrorCode WriteContents(GridH5 *h, const SpamSim *sim, const SpamGrid *g, const SpamGridFields *f, double t, long step)
{
  char name[32];

  PetscFunctionBeginUser;
  for (int c = 0; c < f->ncol; c++) {
    PetscCall(PetscSNPrintf(name, sizeof name, "/%s", f->name[c]));
    PetscCall(WriteDataset(h, g, name, f->col[c], 1));
  }
  PetscCall(WriteVelocity(h, g, f));
  PetscCallGridH5(h, GridAttributes(h->file, sim, g, f, t, step));
  PetscFunctionReturn(0);
}

/* The file built in memory and written through the temporary's own descriptor (h5_image.c):
 * nothing is opened by name after the temporary's exclusive create. */
static PetscErrorCode WriteHdf5(const char *path, const SpamSim *sim, const SpamGrid *g, const SpamGridFields *f, double t, long step)
{
  char           tmp[PETSC_MAX_PATH_LEN + 32];
  GridH5         h     = {-1, path, 0, SpamTestFailWriteAt(path)};
  unsigned char *image = NULL;
  size_t         len   = 0;
  int            fd;
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCall(SpamTempCreate(path, tmp, sizeof tmp, &fd));
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* no error-stack dump: one line instead */
  errno = 0;
  {
    const hid_t fcpl = SpamH5Untimed(H5P_FILE_CREATE);
    h.file           = fcpl < 0 ? -1 : SpamH5MemoryCreate(tmp, fcpl, H5P_DEFAULT);
    if (fcpl >= 0) (void)H5Pclose(fcpl);
  }
  if (h.file < 0) ierr = SpamH5Failed(h.path);
  if (!ierr) ierr = WriteContents(&h, sim, g, f, t, step);
  if (!ierr) ierr = SpamH5ImageTake(&h.file, path, 0, &image, &len);
  SpamH5MemoryClose(&h.file);
  if (!ierr) ierr = SpamTempCommitImage(fd, tmp, path, image, len);
  else {
    (void)close(fd);
    (void)unlink(tmp);
  }
  PetscCall(PetscFree(image));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteCsv(const char *path, const SpamGrid *g, const SpamGridFields *f, double t, long step)
{
  static const char *ax[3] = {"x", "y", "z"};
  SpamFile           file;

  PetscFunctionBeginUser;
  PetscCall(SpamFileBegin(path, &file));
  SpamFilePrintf(&file, "# t=%.10g step=%ld grid_interval=%.10g dims=%" PetscInt_FMT, t, step, g->requested, g->n[0]);
  for (int d = 1; d < g->dim; d++) SpamFilePrintf(&file, "x%" PetscInt_FMT, g->n[d]);
  SpamFilePrintf(&file, "\n");
  for (int d = 0; d < g->dim; d++) SpamFilePrintf(&file, "%s,", ax[d]);
  for (int c = 0; c < f->ncol; c++) SpamFilePrintf(&file, "%s%s", c ? "," : "", f->name[c]);
  SpamFilePrintf(&file, "\n");
  for (PetscInt p = 0; p < g->npoints; p++) {
    const PetscInt idx[3] = {p % g->n[0], (p / g->n[0]) % g->n[1], p / (g->n[0] * g->n[1])};
    for (int d = 0; d < g->dim; d++) SpamFilePrintf(&file, "%.17g,", g->origin[d] + (double)idx[d] * g->spacing[d]);
    for (int c = 0; c < f->ncol; c++) SpamFilePrintf(&file, "%s%.17g", c ? "," : "", f->col[c][p]);
    SpamFilePrintf(&file, "\n");
  }
  PetscCall(SpamFileCommit(&file));
  PetscFunctionReturn(0);
}

static void XdmfItem(SpamFile *x, const char *dims, int k, const char *set)
{
  SpamFilePrintf(x, "        <DataItem Dimensions=\"%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">grid_%05d.h5:/%s</DataItem>\n", dims, k, set);
}

/* Three numbers (or two) slowest direction first, as XDMF's CoRectMesh wants them. */
static void Reversed(char *buf, size_t len, const SpamGrid *g, const double *v, double fill)
{
  if (g->dim == 3) (void)snprintf(buf, len, "%.17g %.17g %.17g", v[2], v[1], v[0]);
  else (void)snprintf(buf, len, "%.17g %.17g", g->dim == 2 ? v[1] : fill, v[0]);
}

/* Rewrites the whole index so that it lists exactly the grid files on disk. */
static PetscErrorCode WriteXdmfIndex(SpamOutput *o, const SpamGrid *g, const SpamGridFields *f)
{
  char     path[PETSC_MAX_PATH_LEN], dims[96] = "", vdims[100], org[128], dx[128];
  hsize_t  shape[4];
  const int rank = Shape(g, shape);
  SpamFile file, *x = &file;

  PetscFunctionBeginUser;
  for (int r = 0; r < rank; r++) (void)snprintf(dims + strlen(dims), sizeof dims - strlen(dims), "%s%llu", r ? " " : "", (unsigned long long)shape[r]);
  (void)snprintf(vdims, sizeof vdims, "%s 3", dims);
  Reversed(org, sizeof org, g, g->origin, 0.0);
  Reversed(dx, sizeof dx, g, g->spacing, 1.0);
  PetscCall(SpamOutputPath(o, "grid.xmf", path, sizeof path));
  PetscCall(SpamFileBegin(path, x));
  SpamFilePrintf(x, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Information Name=\"units\" Value=\"%s\"/>\n    <Grid Name=\"grid\" GridType=\"Collection\" CollectionType=\"Temporal\">\n", SPAM_UNITS_CONVENTION);
  for (int k = 0; k < o->grid.n; k++) {
    SpamFilePrintf(x, "    <Grid Name=\"grid_%05d\" GridType=\"Uniform\">\n      <Time Value=\"%.10g\"/>\n", k, o->grid.times[k]);
    SpamFilePrintf(x, "      <Topology TopologyType=\"%s\" Dimensions=\"%s\"/>\n", rank == 3 ? "3DCoRectMesh" : "2DCoRectMesh", dims);
    SpamFilePrintf(x, "      <Geometry GeometryType=\"%s\">\n", rank == 3 ? "ORIGIN_DXDYDZ" : "ORIGIN_DXDY");
    SpamFilePrintf(x, "        <DataItem Dimensions=\"%d\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">%s</DataItem>\n", rank, org);
    SpamFilePrintf(x, "        <DataItem Dimensions=\"%d\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">%s</DataItem>\n      </Geometry>\n", rank, dx);
    for (int c = 0; c < f->ncol; c++) {
      SpamFilePrintf(x, "      <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Node\">\n", f->name[c]);
      XdmfItem(x, dims, k, f->name[c]);
      SpamFilePrintf(x, "      </Attribute>\n");
    }
    SpamFilePrintf(x, "      <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n");
    XdmfItem(x, vdims, k, "velocity");
    SpamFilePrintf(x, "      </Attribute>\n    </Grid>\n");
  }
  SpamFilePrintf(x, "    </Grid>\n  </Domain>\n</Xdmf>\n");
  PetscCall(SpamFileCommit(x));
  PetscFunctionReturn(0);
}

/* What rank 0 writes alone: the grid file(s) of this time, then the index. */
typedef struct {
  SpamOutput           *o;
  const SpamSim        *sim;
  const SpamGrid       *g;
  const SpamGridFields *f;
  double                t;
} GridWork;

static PetscErrorCode GridFileName(const SpamOutput *o, const char *ext, char *name, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(name, len, "grid_%05d.%s", o->grid.n, ext));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteGridFiles(void *ctx)
{
  GridWork *w = ctx;
  char      name[64], path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (w->o->hdf5) {
    PetscCall(GridFileName(w->o, "h5", name, sizeof name));
    PetscCall(SpamOutputPath(w->o, name, path, sizeof path));
    PetscCall(WriteHdf5(path, w->sim, w->g, w->f, w->t, w->o->step));
  }
  if (w->o->csv) {
    PetscCall(GridFileName(w->o, "csv", name, sizeof name));
    PetscCall(SpamOutputPath(w->o, name, path, sizeof path));
    PetscCall(WriteCsv(path, w->g, w->f, w->t, w->o->step));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteGridIndex(void *ctx)
{
  GridWork *w = ctx;

  PetscFunctionBeginUser;
  PetscCall(WriteXdmfIndex(w->o, w->g, w->f));
  PetscFunctionReturn(0);
}

/* Collective: every rank keeps the same list of files, rank 0 writes them. */
static PetscErrorCode WriteFiles(SpamOutput *o, const SpamSim *sim, const SpamGrid *g, const SpamGridFields *f, double t)
{
  char     name[64];
  GridWork w = {o, sim, g, f, t};

  PetscFunctionBeginUser;
  if (o->grid.n == o->grid.cap) {
    o->grid.cap = 2 * o->grid.cap + 16;
    PetscCall(PetscRealloc(sizeof(double) * o->grid.cap, &o->grid.times));
  }
  PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, WriteGridFiles, &w));
  if (o->hdf5) {
    PetscCall(GridFileName(o, "h5", name, sizeof name));
    PetscCall(SpamManifestAdd(o, name, "grid_h5", t, PETSC_FALSE));
  }
  if (o->csv) {
    PetscCall(GridFileName(o, "csv", name, sizeof name));
    PetscCall(SpamManifestAdd(o, name, "grid_csv", t, PETSC_FALSE));
  }
  o->grid.times[o->grid.n++] = t;
  if (o->hdf5) {
    PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, WriteGridIndex, &w));
    PetscCall(SpamManifestAdd(o, "grid.xmf", "grid_xdmf_index", NAN, PETSC_FALSE));
  }
  PetscFunctionReturn(0);
}

/* Collective on sim->p.comm: the fields are sums over every rank's particles
 * (SpamGridFieldsEvaluate reduces them); rank 0 writes the files. */
PetscErrorCode SpamGridWrite(SpamOutput *o, const SpamSim *sim, const double *y, double t)
{
  SpamGrid       g;
  SpamGridFields f = {0};
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(SpamGridSetUp(&sim->geo.box, o->opt.grid_interval, &g));
  ierr = SpamGridFieldsEvaluate(sim, y, &g, &f);
  if (!ierr) ierr = WriteFiles(o, sim, &g, &f, t);
  PetscCall(SpamGridFieldsFree(&f));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
