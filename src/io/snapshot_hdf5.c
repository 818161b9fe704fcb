/* The HDF5 particle snapshot: positions, velocities, density, mass, id, and energy and
 * stress where the model carries them, rows in gid order (global input order), with the
 * attributes a reader needs to use it alone (snapshot_attributes.c) and a checksum of its
 * bytes in its first 512 (snapshot_checksum.c).
 *
 * One file whatever the number of ranks P, the same bytes on P ranks as on one: the rows
 * are moved by gid to rank 0 (particle_rows.c), which builds the file in memory and writes
 * it through the temporary it created (h5_image.c). Why not every rank writing its block
 * through MPI-IO: MPI-IO, like HDF5, opens the file by name on every rank, and a name
 * opened again after its exclusive create can be swapped for a symlink in between. */
#define _DEFAULT_SOURCE /* close, unlink: POSIX, not C11 */
#include "snapshot_hdf5.h"
#include "particle_rows.h"

#include <errno.h>
#include <unistd.h>

/* The snapshot's fields, every row (row r is gid r). */
typedef struct {
  double    *x, *v, *rho, *e, *s6, *m, *h;
  long long *id;   /* the gid: the file scene's id column                                */
  double     t;
  long       step;
  int        carried; /* the density is state, not summed                                */
  char       model[2048];
} Fields;

/* The file being written, on rank 0. */
typedef struct {
  const char     *path;
  char            tmp[PETSC_MAX_PATH_LEN + 32];
  int             fd;             /* the temporary, as created                          */
  const SpamSim  *sim;
  const SpamRows *rows;
  double          t;
  long            step;
  hid_t           file;           /* in memory                                          */
  long            writes, fail_at; /* test-only injected failure, see output.h           */
  hsize_t         N;              /* rows                                               */
  const Fields   *f;
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
  if (rows->h) PetscCall(PetscCalloc1(n + 1, &f->h));
  for (PetscInt r = 0; r < n; r++) {
    const double *p = rows->y + (size_t)r * l->nvar;
    f->rho[r]       = SpamRowsDensity(&sim->model.layout, rows, r);
    f->m[r]         = rows->m[r];
    f->id[r]        = rows->gid[r];
    if (f->e) f->e[r] = p[l->e];
    if (f->h) f->h[r] = rows->h[r];
    if (f->s6) SpamSnapshotStress6(&sim->model.layout, rows->y, r, f->s6 + 6 * r);
    for (int d = 0; d < sim->model.dim; d++) {
      f->x[3 * r + d] = SpamSnapshotPosition(&sim->geo.box, d, p[l->x + d]);
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
  PetscCall(PetscFree(f->h));
  PetscCall(PetscFree(f->m));
  PetscCall(PetscFree(f->id));
  PetscFunctionReturn(0);
}

/* Creates the dataset name [N][ncomp] (or [N] when ncomp is 1) of file type ftype and
 * writes it from data (memory type mtype); components (or NULL) names the columns, e.g. the
 * order of the stress's six, so that a script reading the file alone needs no index. Every
 * id made here is closed also when a call fails. */
static PetscErrorCode WriteDataset(H5Out *h, const char *name, hid_t ftype, hid_t mtype, const void *data, hsize_t ncomp, const char *components)
{
  const hsize_t dims[2] = {h->N, ncomp};
  const hid_t   dcpl    = SpamH5Untimed(H5P_DATASET_CREATE);
  hid_t         space = -1, set = -1;
  herr_t        w = -1;
  int           e;

  PetscFunctionBeginUser;
  errno = 0;
  if (dcpl >= 0 && (space = H5Screate_simple(ncomp > 1 ? 2 : 1, dims, NULL)) >= 0) set = H5Dcreate2(h->file, name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (set >= 0) w = ++h->writes == h->fail_at ? (errno = ENOSPC, -1) : H5Dwrite(set, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  if (w >= 0 && components) w = SpamH5StringAttribute(set, "components", components);
  e = errno; /* the failure's reason, before the closes */
  if (set >= 0 && H5Dclose(set) < 0) w = -1;
  if (space >= 0) (void)H5Sclose(space);
  if (dcpl >= 0) (void)H5Pclose(dcpl);
  errno = e;
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
  if (f->h) PetscCall(WriteDoubles(h, "/smoothing_length", f->h, 1, NULL)); /* the adaptive range's h_i */
  PetscFunctionReturn(0);
}

/* The whole file in memory, its image in *image (with room for the checksum's block). */
static PetscErrorCode BuildImage(H5Out *h, unsigned char **image, size_t *len)
{
  const hid_t    fcpl = SpamH5Untimed(H5P_FILE_CREATE);
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* no error-stack dump: one line instead */
  errno   = 0;
  h->file = -1;
  if (fcpl >= 0 && H5Pset_userblock(fcpl, SPAM_SNAPSHOT_USERBLOCK) >= 0) h->file = SpamH5MemoryCreate(h->tmp, fcpl, H5P_DEFAULT);
  if (fcpl >= 0) (void)H5Pclose(fcpl);
  if (h->file < 0) PetscCall(SpamH5Failed(h->path));
  ierr = FieldsWrite(h);
  if (ierr) SpamH5MemoryClose(&h->file);
  PetscCall(ierr);
  PetscCall(SpamH5ImageTake(&h->file, h->path, SPAM_SNAPSHOT_USERBLOCK, image, len));
  PetscFunctionReturn(0);
}

/* Rank 0: the temporary created new (O_EXCL | O_NOFOLLOW), the file built in memory and
 * written through the temporary's descriptor, then renamed; nothing is opened by name. */
static PetscErrorCode WriteOnRoot(void *ctx)
{
  H5Out         *h     = ctx;
  unsigned char *image = NULL;
  size_t         len   = 0;
  Fields         f;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(FieldsFromRows(h->sim, h->rows, &f));
  f.t    = h->t;
  f.step = h->step;
  h->f   = &f;
  ierr   = SpamTempCreate(h->path, h->tmp, sizeof h->tmp, &h->fd);
  if (!ierr) {
    ierr = BuildImage(h, &image, &len);
    if (!ierr) {
      SpamSnapshotStamp(image, len);
      ierr = SpamTempCommitImage(h->fd, h->tmp, h->path, image, len);
    } else {
      (void)close(h->fd);
      (void)unlink(h->tmp);
    }
  }
  PetscCall(PetscFree(image));
  PetscCall(FieldsFree(&f));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* Collective on sim->p.comm. */
PetscErrorCode SpamSnapshotHdf5Write(const char *path, const SpamSim *sim, const double *y, double t, long step)
{
  H5Out          h;
  SpamRows       rows;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&h, sizeof h));
  h.path    = path;
  h.sim     = sim;
  h.t       = t;
  h.step    = step;
  h.fd      = -1;
  h.fail_at = SpamTestFailWriteAt(path);
  PetscCall(SpamRowsGather(sim, y, SPAM_ROWS_ON_ROOT, &rows));
  h.rows = &rows;
  h.N    = (hsize_t)rows.nglobal;
  ierr   = SpamRunAgreed(sim->p.comm, PETSC_TRUE, WriteOnRoot, &h);
  PetscCall(SpamRowsFree(&rows));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
