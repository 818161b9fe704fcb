/* Particle snapshots: one HDF5 file per snapshot (positions, velocities, density, mass,
 * id, and energy and stress where the model carries them, with the attributes a reader
 * needs to use it alone: snapshot_attributes.c) and an
 * XDMF index over all of them that ParaView opens as a time series of point clouds. */
#define _DEFAULT_SOURCE /* open flags, flock, lstat, gethostname: POSIX, not C11 */
#include "snapshot_hdf5.h"
#include <spam/grid.h>

#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

/* An HDF5 file being written; every failure becomes one line naming the file. */
typedef struct {
  hid_t          file;
  const char    *path;
  long           writes, fail_at; /* test-only injected failure, see output.h */
  const SpamSim *sim;
} H5Out;

#define PetscCallH5(h, call) SpamCallH5((h)->path, call)

/* components (or NULL for a scalar) names the columns of an [n][ncomp] dataset, e.g. the
 * order of the stress's six, so that a script reading the file alone needs no index. */
static PetscErrorCode WriteDataset(H5Out *h, const char *name, const double *data, hsize_t n, hsize_t ncomp, const char *components)
{
  hsize_t dims[2] = {n, ncomp};
  hid_t   space, set;
  herr_t  w;
  hid_t   dcpl;

  PetscFunctionBeginUser;
  PetscCallH5(h, dcpl = SpamH5Untimed(H5P_DATASET_CREATE));
  PetscCallH5(h, space = H5Screate_simple(ncomp > 1 ? 2 : 1, dims, NULL));
  set = H5Dcreate2(h->file, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  (void)H5Pclose(dcpl);
  if (set < 0) {
    (void)H5Sclose(space);
    PetscCall(SpamH5Failed(h->path));
  }
  errno = 0;
  w = ++h->writes == h->fail_at ? (errno = ENOSPC, -1) : H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  if (w < 0) {
    const int e = errno;
    (void)H5Dclose(set);
    (void)H5Sclose(space);
    errno = e;
    PetscCall(SpamH5Failed(h->path));
  }
  if (components && SpamH5StringAttribute(set, "components", components) < 0) {
    (void)H5Dclose(set);
    (void)H5Sclose(space);
    PetscCall(SpamH5Failed(h->path));
  }
  PetscCallH5(h, H5Dclose(set));
  PetscCallH5(h, H5Sclose(space));
  PetscFunctionReturn(0);
}

/* The fields of one snapshot, row r being input row r. */
typedef struct {
  double    *x, *v, *rho, *e, *s6, *m;
  long long *id;   /* the input row: the file scene's id column                          */
  double     t;
  long       step;
  int        carried; /* the density is state, not summed                                */
  char       model[2048];
} Fields;

static PetscErrorCode FieldsGather(const SpamSim *sim, const double *y, Fields *f)
{
  const SpamLayout *l = &sim->model.layout;
  const PetscInt    n = sim->n;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof *f));
  PetscCall(PetscCalloc1(3 * n + 1, &f->x));
  PetscCall(PetscCalloc1(3 * n + 1, &f->v));
  PetscCall(PetscCalloc1(n + 1, &f->rho));
  PetscCall(PetscCalloc1(n + 1, &f->m));
  PetscCall(PetscCalloc1(n + 1, &f->id));
  PetscCall(SpamModelSettingsJson(&sim->model, f->model, sizeof f->model));
  f->carried = l->rho >= 0;
  if (l->e >= 0) PetscCall(PetscCalloc1(n + 1, &f->e));
  if (l->s >= 0) PetscCall(PetscCalloc1(6 * n + 1, &f->s6));
  for (PetscInt r = 0; r < n; r++) {
    const PetscInt i = SpamSimAtRow(sim, r);
    f->rho[r]        = SpamSnapshotDensity(sim, y, i);
    f->m[r]          = sim->f.m[i];
    f->id[r]         = r;
    if (f->e) f->e[r] = y[(size_t)i * l->nvar + l->e];
    if (f->s6) SpamSnapshotStress6(sim, y, i, f->s6 + 6 * r);
    for (int d = 0; d < sim->model.dim; d++) {
      f->x[3 * r + d] = SpamSnapshotPosition(sim, d, y[(size_t)i * l->nvar + l->x + d]);
      f->v[3 * r + d] = y[(size_t)i * l->nvar + l->v + d];
    }
  }
  PetscFunctionReturn(0);
}

/* The ids as 64-bit integers (a run may hold more particles than a 32-bit int counts). */
static PetscErrorCode WriteIds(H5Out *h, const long long *id, hsize_t n)
{
  hid_t  space, set, dcpl;
  herr_t w;

  PetscFunctionBeginUser;
  PetscCallH5(h, dcpl = SpamH5Untimed(H5P_DATASET_CREATE));
  PetscCallH5(h, space = H5Screate_simple(1, &n, NULL));
  set = H5Dcreate2(h->file, "/id", H5T_STD_I64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  (void)H5Pclose(dcpl);
  if (set < 0) {
    (void)H5Sclose(space);
    PetscCall(SpamH5Failed(h->path));
  }
  errno = 0;
  w     = H5Dwrite(set, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, id);
  if (H5Dclose(set) < 0) w = -1;
  if (H5Sclose(space) < 0) w = -1;
  if (w < 0) PetscCall(SpamH5Failed(h->path));
  PetscFunctionReturn(0);
}

static PetscErrorCode FieldsWrite(H5Out *h, const Fields *f, hsize_t n)
{
  PetscFunctionBeginUser;
  PetscCall(WriteDataset(h, "/positions", f->x, n, 3, "x,y,z (0 beyond dim)"));
  PetscCall(WriteDataset(h, "/velocities", f->v, n, 3, "vx,vy,vz (0 beyond dim)"));
  PetscCall(WriteDataset(h, "/density", f->rho, n, 1, NULL));
  PetscCallH5(h, SpamSnapshotDensityCarried(h->file, f->carried));
  PetscCall(WriteDataset(h, "/mass", f->m, n, 1, NULL));
  PetscCall(WriteIds(h, f->id, n));
  PetscCallH5(h, SpamSnapshotAttributes(h->file, h->sim, f->t, f->step, f->model));
  if (f->e) PetscCall(WriteDataset(h, "/energy", f->e, n, 1, NULL));
  if (f->s6) PetscCall(WriteDataset(h, "/stress", f->s6, n, 6, "sxx,sxy,sxz,syy,syz,szz (ParaView's Tensor6 order; 0 beyond dim)"));
  PetscFunctionReturn(0);
}

/* The temporary is created new by us (O_EXCL | O_NOFOLLOW) before HDF5 opens it by name;
 * before the rename it must still be the regular file we created, not something put in
 * its place. */
static PetscErrorCode WriteFile(const char *path, const char *tmp, const struct stat *made, const SpamSim *sim, const Fields *f, hsize_t n)
{
  H5Out          h = {-1, path, 0, SpamTestFailWriteAt(path), sim};
  struct stat    now;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* no error-stack dump: one line instead */
  {
    hid_t fcpl;
    PetscCallH5(&h, fcpl = SpamH5Untimed(H5P_FILE_CREATE));
    h.file = H5Fcreate(tmp, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    (void)H5Pclose(fcpl);
    PetscCallH5(&h, h.file);
  }
  ierr = FieldsWrite(&h, f, n);
  errno = 0;
  if (H5Fclose(h.file) < 0 && !ierr) ierr = SpamH5Failed(h.path);
  PetscCall(ierr);
  PetscCheck(!lstat(tmp, &now) && S_ISREG(now.st_mode) && now.st_ino == made->st_ino && now.st_dev == made->st_dev, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: its temporary %s was replaced during the write", path, tmp);
  PetscCheck(!rename(tmp, path), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s: %s", tmp, path, strerror(errno));
  PetscFunctionReturn(0);
}

static PetscErrorCode FieldsFree(Fields *f)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(f->x));
  PetscCall(PetscFree(f->v));
  PetscCall(PetscFree(f->rho));
  PetscCall(PetscFree(f->e));
  PetscCall(PetscFree(f->s6));
  PetscCall(PetscFree(f->m));
  PetscCall(PetscFree(f->id));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSnapshotHdf5Write(const char *path, const SpamSim *sim, const double *y, double t, long step)
{
  char           tmp[PETSC_MAX_PATH_LEN + 32];
  Fields         f = {0};
  struct stat    made;
  int            fd;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(SpamTempCreate(path, tmp, sizeof tmp, &fd));
  if (fstat(fd, &made)) {
    const int e = errno;
    (void)close(fd);
    (void)unlink(tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s: %s", path, strerror(e));
  }
  (void)close(fd); /* HDF5 opens it by name; WriteFile checks it is still this file */
  ierr = FieldsGather(sim, y, &f);
  f.t    = t;
  f.step = step;
  if (!ierr) ierr = WriteFile(path, tmp, &made, sim, &f, (hsize_t)sim->n);
  if (ierr) (void)unlink(tmp);
  PetscCall(FieldsFree(&f));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

static void XdmfItem(SpamFile *f, PetscInt n, int ncomp, int snap, const char *set)
{
  if (ncomp > 1) SpamFilePrintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT " %d\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:%s</DataItem>\n", n, ncomp, snap, set);
  else SpamFilePrintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:%s</DataItem>\n", n, snap, set);
}

/* The 64-bit ids, as the point cloud's connectivity and as an attribute. */
static void XdmfIdItem(SpamFile *f, PetscInt n, int snap)
{
  SpamFilePrintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:/id</DataItem>\n", n, snap);
}

static void XdmfAttribute(SpamFile *f, PetscInt n, int snap, const char *name, const char *type, int ncomp, const char *set)
{
  SpamFilePrintf(f, "      <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name, type);
  XdmfItem(f, n, ncomp, snap, set);
  SpamFilePrintf(f, "      </Attribute>\n");
}

static void XdmfIdAttribute(SpamFile *f, PetscInt n, int snap)
{
  SpamFilePrintf(f, "      <Attribute Name=\"id\" AttributeType=\"Scalar\" Center=\"Node\">\n");
  XdmfIdItem(f, n, snap);
  SpamFilePrintf(f, "      </Attribute>\n");
}

/* One vertex cell per particle. The connectivity must be written out: ParaView's Xdmf3
 * reader makes no cells from a Polyvertex without it (an empty view), while the legacy
 * XDMF reader numbered the nodes itself. Row r of a snapshot holds the particle of id r
 * (FieldsGather), so /id is that list 0..n-1 and no further dataset is needed. */
static void XdmfTopology(SpamFile *f, PetscInt n, int snap)
{
  SpamFilePrintf(f, "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%" PetscInt_FMT "\" NodesPerElement=\"1\">\n", n);
  XdmfIdItem(f, n, snap);
  SpamFilePrintf(f, "      </Topology>\n");
}

/* Rewrites the whole index so that it always lists exactly the snapshots on disk. */
static PetscErrorCode WriteXdmfIndex(SpamOutput *o, const SpamLayout *l, PetscInt n)
{
  char     path[PETSC_MAX_PATH_LEN];
  SpamFile file, *f = &file;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, "snapshots.xmf", path, sizeof path));
  PetscCall(SpamFileBegin(path, f));
  SpamFilePrintf(f, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Information Name=\"units\" Value=\"%s\"/>\n    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n", SPAM_UNITS_CONVENTION);
  for (int s = 0; s < o->nsnap; s++) {
    SpamFilePrintf(f, "    <Grid Name=\"snap_%05d\" GridType=\"Uniform\">\n      <Time Value=\"%.10g\"/>\n", s, o->snap_times[s]);
    XdmfTopology(f, n, s);
    SpamFilePrintf(f, "      <Geometry GeometryType=\"XYZ\">\n");
    XdmfItem(f, n, 3, s, "/positions");
    SpamFilePrintf(f, "      </Geometry>\n");
    XdmfAttribute(f, n, s, "velocity", "Vector", 3, "/velocities");
    XdmfAttribute(f, n, s, "density", "Scalar", 1, "/density");
    XdmfAttribute(f, n, s, "mass", "Scalar", 1, "/mass");
    XdmfIdAttribute(f, n, s);
    if (l->e >= 0) XdmfAttribute(f, n, s, "energy", "Scalar", 1, "/energy");
    if (l->s >= 0) XdmfAttribute(f, n, s, "stress", "Tensor6", 6, "/stress");
    SpamFilePrintf(f, "    </Grid>\n");
  }
  SpamFilePrintf(f, "    </Grid>\n  </Domain>\n</Xdmf>\n");
  PetscCall(SpamFileCommit(f));
  PetscFunctionReturn(0);
}

/* A run writes no more than -snapshot_max snapshots: a tiny -snapshot_interval must not
 * fill the disk with files. Parsing refuses an interval that would pass the cap; this is
 * the writer's own guard. */
PetscErrorCode SpamSnapshotWrite(SpamOutput *o, SpamSim *sim, const double *y, double t, const char *tag)
{
  char name[64], path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCheck(o->opt.snapshot_max <= 0 || o->nsnap < o->opt.snapshot_max, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write another snapshot into %s: -snapshot_max = %" PetscInt_FMT " reached", o->dir, o->opt.snapshot_max);
  if (o->hdf5) {
    if (o->nsnap == o->snap_cap) {
      o->snap_cap = 2 * o->snap_cap + 16;
      PetscCall(PetscRealloc(sizeof(double) * o->snap_cap, &o->snap_times));
    }
    PetscCall(PetscSNPrintf(name, sizeof name, "snap_%05d.h5", o->nsnap));
    PetscCall(SpamOutputPath(o, name, path, sizeof path));
    PetscCall(SpamSnapshotHdf5Write(path, sim, y, t, o->step));
    PetscCall(SpamManifestAdd(o, name, "snapshot_h5", t, PETSC_FALSE));
    o->snap_times[o->nsnap] = t;
  }
  if (o->csv) {
    if (tag) PetscCall(PetscSNPrintf(name, sizeof name, "particles_%s.csv", tag));
    else PetscCall(PetscSNPrintf(name, sizeof name, "particles_%05d.csv", o->nsnap));
    PetscCall(SpamOutputPath(o, name, path, sizeof path));
    PetscCall(SpamSnapshotCsvWrite(path, sim, y, t));
    PetscCall(SpamManifestAdd(o, name, tag ? "snapshot_csv_last_good" : "snapshot_csv", t, PETSC_FALSE));
  }
  o->nsnap++;
  if (o->opt.grid_interval > 0) PetscCall(SpamGridWrite(o, sim, y, t)); /* fields on a grid, same time */
  if (o->hdf5) {
    PetscCall(WriteXdmfIndex(o, &sim->model.layout, sim->n));
    PetscCall(SpamManifestAdd(o, "snapshots.xmf", "xdmf_index", NAN, PETSC_FALSE));
  }
  PetscCall(SpamManifestWrite(o));
  PetscFunctionReturn(0);
}
