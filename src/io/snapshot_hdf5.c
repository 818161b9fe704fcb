/* The HDF5 particle snapshot: positions, velocities, density, mass, id, and energy and
 * stress where the model carries them, rows in gid order (global input order), with the
 * attributes a reader needs to use it alone (snapshot_attributes.c).
 *
 * One file whatever the number of ranks P, and on P ranks the same datasets, shapes,
 * attributes and values as on one: the rows are first moved by gid to a block of
 * consecutive gids per rank (particle_rows.c), then every rank writes its block of each
 * dataset as one hyperslab, collectively through MPI-IO (HDF5's mpio driver). Why blocks
 * and not each rank writing its own particles where they belong: after a migration a
 * rank's gids are scattered over the whole range, and a point selection of scattered rows
 * turns one large write per rank into a write per row. On one rank the file is written
 * with HDF5's default driver, as before there were ranks. */
#define _DEFAULT_SOURCE /* lstat: POSIX, not C11 */
#include "snapshot_hdf5.h"
#include "particle_rows.h"

#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

/* The snapshot's fields for this rank's block of rows (row r is gid first + r). */
typedef struct {
  double    *x, *v, *rho, *e, *s6, *m;
  long long *id;   /* the gid: the file scene's id column                                */
  double     t;
  long       step;
  int        carried; /* the density is state, not summed                                */
  char       model[2048];
} Fields;

/* The file being written, on every rank. */
typedef struct {
  const char    *path;
  char           tmp[PETSC_MAX_PATH_LEN + 32];
  struct stat    made;     /* the temporary as rank 0 created it                        */
  const SpamSim *sim;
  MPI_Comm       comm;
  PetscMPIInt    size;
  hid_t          file, dxpl;
  long           writes, fail_at; /* test-only injected failure, see output.h            */
  hsize_t        N, first, n;     /* rows in all, this rank's first row and its count    */
  const Fields  *f;
} H5Out;

#define PetscCallH5(h, call) SpamCallH5((h)->path, call)

static PetscErrorCode FieldsFromRows(const SpamSim *sim, const SpamRows *rows, Fields *f)
{
  const SpamLayout *l = &sim->model.layout;
  const PetscInt    n = rows->n;

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
    const double *p = rows->y + (size_t)r * l->nvar;
    f->rho[r]       = SpamRowsDensity(sim, rows, r);
    f->m[r]         = rows->m[r];
    f->id[r]        = rows->gid[r];
    if (f->e) f->e[r] = p[l->e];
    if (f->s6) SpamSnapshotStress6(sim, rows->y, r, f->s6 + 6 * r);
    for (int d = 0; d < sim->model.dim; d++) {
      f->x[3 * r + d] = SpamSnapshotPosition(sim, d, p[l->x + d]);
      f->v[3 * r + d] = p[l->v + d];
    }
  }
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

/* Whether a write succeeded on every rank: a failure on one rank only must send all of
 * them down the failure path together, or the others wait in the next collective call. */
static PetscErrorCode Agreed(const H5Out *h, herr_t *w)
{
  int ok = *w >= 0;

  PetscFunctionBeginUser;
  if (h->size > 1) PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_LAND, h->comm));
  if (!ok && *w >= 0) *w = -1;
  PetscFunctionReturn(0);
}

/* This rank's rows [first, first + n) of an [N][ncomp] dataset: the file's hyperslab and
 * the memory's whole extent (both empty on a rank that holds no rows). */
static herr_t SelectBlock(const H5Out *h, hid_t file_space, hid_t *mem_space, hsize_t ncomp)
{
  const hsize_t start[2] = {h->first, 0}, count[2] = {h->n, ncomp};
  const int     rank     = ncomp > 1 ? 2 : 1;

  if ((*mem_space = H5Screate_simple(rank, count, NULL)) < 0) return -1;
  if (!h->n) return H5Sselect_none(file_space) < 0 || H5Sselect_none(*mem_space) < 0 ? -1 : 0;
  return H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, NULL, count, NULL);
}

/* Creates the dataset name [N][ncomp] (or [N] when ncomp is 1) of file type ftype and
 * writes this rank's block of it from data (memory type mtype); components (or NULL)
 * names the columns, e.g. the order of the stress's six, so that a script reading the
 * file alone needs no index. */
static PetscErrorCode WriteDataset(H5Out *h, const char *name, hid_t ftype, hid_t mtype, const void *data, hsize_t ncomp, const char *components)
{
  const hsize_t dims[2] = {h->N, ncomp};
  hid_t         space, mem = -1, set, dcpl;
  herr_t        w;

  PetscFunctionBeginUser;
  PetscCallH5(h, dcpl = SpamH5Untimed(H5P_DATASET_CREATE));
  /* Parallel HDF5 allocates a dataset when it is created and by default writes the fill
   * value into all of it first: the whole file twice. Every row is written here. */
  if (h->size > 1) PetscCallH5(h, H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER));
  PetscCallH5(h, space = H5Screate_simple(ncomp > 1 ? 2 : 1, dims, NULL));
  set = H5Dcreate2(h->file, name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  (void)H5Pclose(dcpl);
  if (set < 0) {
    (void)H5Sclose(space);
    PetscCall(SpamH5Failed(h->path));
  }
  errno = 0;
  w     = SelectBlock(h, space, &mem, ncomp);
  if (w >= 0) w = ++h->writes == h->fail_at ? (errno = ENOSPC, -1) : H5Dwrite(set, mtype, mem, space, h->dxpl, data);
  {
    const int e = errno;
    PetscCall(Agreed(h, &w));
    errno = e;
  }
  if (w >= 0 && components) w = SpamH5StringAttribute(set, "components", components);
  if (mem >= 0 && H5Sclose(mem) < 0) w = -1;
  if (H5Dclose(set) < 0) w = -1;
  if (H5Sclose(space) < 0) w = -1;
  if (w < 0) PetscCall(SpamH5Failed(h->path));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteDoubles(H5Out *h, const char *name, const double *data, hsize_t ncomp, const char *components)
{
  PetscFunctionBeginUser;
  PetscCall(WriteDataset(h, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data, ncomp, components));
  PetscFunctionReturn(0);
}

static PetscErrorCode FieldsWrite(H5Out *h)
{
  const Fields *f = h->f;

  PetscFunctionBeginUser;
  PetscCall(WriteDoubles(h, "/positions", f->x, 3, "x,y,z (0 beyond dim)"));
  PetscCall(WriteDoubles(h, "/velocities", f->v, 3, "vx,vy,vz (0 beyond dim)"));
  PetscCall(WriteDoubles(h, "/density", f->rho, 1, NULL));
  PetscCallH5(h, SpamSnapshotDensityCarried(h->file, f->carried));
  PetscCall(WriteDoubles(h, "/mass", f->m, 1, NULL));
  /* the ids as 64-bit integers: a run may hold more particles than a 32-bit int counts */
  PetscCall(WriteDataset(h, "/id", H5T_STD_I64LE, H5T_NATIVE_LLONG, f->id, 1, NULL));
  PetscCallH5(h, SpamSnapshotAttributes(h->file, h->sim, f->t, f->step, f->model));
  if (f->e) PetscCall(WriteDoubles(h, "/energy", f->e, 1, NULL));
  if (f->s6) PetscCall(WriteDoubles(h, "/stress", f->s6, 6, "sxx,sxy,sxz,syy,syz,szz (ParaView's Tensor6 order; 0 beyond dim)"));
  PetscFunctionReturn(0);
}

/* Rank 0 creates the temporary new (O_EXCL | O_NOFOLLOW) and keeps what it is, so that
 * before the rename it can check it is still the regular file it made. */
static PetscErrorCode CreateTemp(void *ctx)
{
  H5Out *h = ctx;
  int    fd;

  PetscFunctionBeginUser;
  PetscCall(SpamTempCreate(h->path, h->tmp, sizeof h->tmp, &fd));
  if (fstat(fd, &h->made)) {
    const int e = errno;
    (void)close(fd);
    (void)unlink(h->tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s: %s", h->path, strerror(e));
  }
  (void)close(fd); /* HDF5 opens it by name */
  PetscFunctionReturn(0);
}

/* Every rank: the file (through MPI-IO on several ranks) and its contents. */
static PetscErrorCode WriteAll(void *ctx)
{
  H5Out         *h = ctx;
  hid_t          fcpl, fapl = H5P_DEFAULT;
  herr_t         w;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* no error-stack dump: one line instead */
  h->dxpl = H5P_DEFAULT;
  if (h->size > 1) {
    PetscCallH5(h, fapl = H5Pcreate(H5P_FILE_ACCESS));
    PetscCallH5(h, H5Pset_fapl_mpio(fapl, h->comm, MPI_INFO_NULL));
    PetscCallH5(h, h->dxpl = H5Pcreate(H5P_DATASET_XFER));
    PetscCallH5(h, H5Pset_dxpl_mpio(h->dxpl, H5FD_MPIO_COLLECTIVE));
  }
  PetscCallH5(h, fcpl = SpamH5Untimed(H5P_FILE_CREATE));
  errno   = 0;
  h->file = H5Fcreate(h->tmp, H5F_ACC_TRUNC, fcpl, fapl);
  (void)H5Pclose(fcpl);
  if (fapl != H5P_DEFAULT) (void)H5Pclose(fapl);
  w = h->file < 0 ? -1 : 0;
  PetscCall(Agreed(h, &w));
  if (w < 0) {
    if (h->file >= 0) (void)H5Fclose(h->file);
    PetscCall(SpamH5Failed(h->path));
  }
  ierr  = FieldsWrite(h);
  errno = 0;
  if (H5Fclose(h->file) < 0 && !ierr) ierr = SpamH5Failed(h->path);
  if (h->dxpl != H5P_DEFAULT) (void)H5Pclose(h->dxpl);
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckAndRename(void *ctx)
{
  H5Out      *h = ctx;
  struct stat now;

  PetscFunctionBeginUser;
  if (lstat(h->tmp, &now) || !S_ISREG(now.st_mode) || now.st_ino != h->made.st_ino || now.st_dev != h->made.st_dev) {
    (void)unlink(h->tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: its temporary %s was replaced during the write", h->path, h->tmp);
  }
  if (rename(h->tmp, h->path)) {
    const int e = errno;
    (void)unlink(h->tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s: %s", h->tmp, h->path, strerror(e));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode RemoveTemp(void *ctx)
{
  const H5Out *h = ctx;

  PetscFunctionBeginUser;
  (void)unlink(h->tmp);
  PetscFunctionReturn(0);
}

/* Collective on sim->comm. */
PetscErrorCode SpamSnapshotHdf5Write(const char *path, const SpamSim *sim, const double *y, double t, long step)
{
  H5Out          h;
  SpamRows       rows;
  Fields         f;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&h, sizeof h));
  h.path    = path;
  h.sim     = sim;
  h.comm    = sim->comm;
  h.fail_at = SpamTestFailWriteAt(path);
  PetscCallMPI(MPI_Comm_size(sim->comm, &h.size));
  PetscCall(SpamRowsGather(sim, y, SPAM_ROWS_BLOCKS, &rows));
  h.N     = (hsize_t)rows.nglobal;
  h.first = (hsize_t)rows.first;
  h.n     = (hsize_t)rows.n;
  ierr    = FieldsFromRows(sim, &rows, &f);
  PetscCall(SpamRowsFree(&rows));
  f.t    = t;
  f.step = step;
  h.f    = &f;
  if (!ierr) ierr = SpamRunAgreed(sim->comm, PETSC_TRUE, CreateTemp, &h);
  if (!ierr) {
    PetscCallMPI(MPI_Bcast(h.tmp, (int)sizeof h.tmp, MPI_CHAR, 0, sim->comm));
    ierr = SpamRunAgreed(sim->comm, PETSC_FALSE, WriteAll, &h);
    if (ierr) (void)SpamRunAgreed(sim->comm, PETSC_TRUE, RemoveTemp, &h);
    else ierr = SpamRunAgreed(sim->comm, PETSC_TRUE, CheckAndRename, &h);
  }
  PetscCall(FieldsFree(&f));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
