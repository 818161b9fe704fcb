/* Writes a checkpoint (layout in checkpoint_file.h) so that a crash at any moment leaves
 * either the previous checkpoint or the new one at path, both whole: the new one goes to a
 * fresh temporary, is flushed to disk, and only then renamed over path; the directory is
 * synced so that the rename itself survives a power loss. The file is built in memory and
 * written through the temporary's own descriptor (h5_image.c): no name is opened twice. */
#define _DEFAULT_SOURCE /* fsync, lstat, O_NOFOLLOW, O_DIRECTORY: POSIX, not C11 */
#include "checkpoint_layout.h"
#include "snapshot_hdf5.h"
#include <spam/output.h>
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
  const char *path;          /* the checkpoint as the user names it: every message names it */
  hid_t       file;
  long        writes, fail_at; /* test only: this dataset write fails (SPAM_TEST_FAIL_WRITE) */
  int         err;             /* errno of the failed dataset write (the closes after it may change errno) */
} CkWriter;

#define WRITE_ERROR(...) PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_FILE_WRITE, PETSC_ERROR_INITIAL, __VA_ARGS__)

/* Object modification times off: equal contents make equal files. */
static hid_t CreateProperties(hid_t cls)
{
  hid_t p = H5Pcreate(cls);

  if (p >= 0 && H5Pset_obj_track_times(p, 0) < 0) {
    (void)H5Pclose(p);
    return -1;
  }
  return p;
}

/* The file type of an entry: REAL and INT fixed little-endian 64 bits; TEXT a string of
 * len + 1 bytes (the NUL is written too, so "" is a valid one-byte string). */
static hid_t FileType(const SpamCkEntry *e)
{
  hid_t t;

  if (e->kind == SPAM_CK_REAL) return H5Tcopy(H5T_IEEE_F64LE);
  if (e->kind == SPAM_CK_INT) return H5Tcopy(H5T_STD_I64LE);
  if ((t = H5Tcopy(H5T_C_S1)) < 0) return -1;
  if (H5Tset_size(t, e->n + 1) < 0 || H5Tset_strpad(t, H5T_STR_NULLTERM) < 0) {
    (void)H5Tclose(t);
    return -1;
  }
  return t;
}

/* The memory type: native doubles and int64 (HDF5 converts nothing on a little-endian
 * machine: the bits go to disk as they are); text as its file type (raw bytes). */
static hid_t MemoryType(const SpamCkEntry *e, hid_t file_type)
{
  return H5Tcopy(e->kind == SPAM_CK_REAL ? H5T_NATIVE_DOUBLE : e->kind == SPAM_CK_INT ? H5T_NATIVE_INT64 : file_type);
}

static herr_t WriteEntry(CkWriter *w, hid_t group, hid_t dcpl, const SpamCkEntry *e)
{
  const hsize_t n     = (hsize_t)e->n;
  hid_t         ftype = FileType(e), mtype = ftype >= 0 ? MemoryType(e, ftype) : -1;
  hid_t         space = e->kind == SPAM_CK_TEXT ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, NULL), set = -1;
  herr_t        st    = -1;

  if (ftype >= 0 && mtype >= 0 && space >= 0) set = H5Dcreate2(group, e->name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (set >= 0) {
    errno = 0;
    if (++w->writes == w->fail_at) errno = ENOSPC;
    else if (e->kind == SPAM_CK_TEXT || n) st = H5Dwrite(set, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, e->data);
    else st = 0; /* an empty array: nothing to write */
    if (st < 0) w->err = errno;
    if (H5Dclose(set) < 0) st = -1;
  }
  if (space >= 0) (void)H5Sclose(space);
  if (mtype >= 0) (void)H5Tclose(mtype);
  if (ftype >= 0) (void)H5Tclose(ftype);
  return st;
}

/* The root attributes: format, units_convention, entries and checksum. */
static herr_t WriteRoot(hid_t file, const SpamCkFile *c)
{
  const int64_t  entries = c->n;
  const uint64_t sum     = SpamCkChecksum(c);

  if (SpamH5StringAttribute(file, "format", SPAM_CK_FORMAT) < 0) return -1;
  if (SpamH5StringAttribute(file, "units_convention", SPAM_UNITS_CONVENTION) < 0) return -1;
  if (SpamH5Attribute(file, "entries", H5T_STD_I64LE, H5T_NATIVE_INT64, 0, &entries) < 0) return -1;
  return SpamH5Attribute(file, "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64, 0, &sum);
}

static PetscErrorCode WriteContents(CkWriter *w, const SpamCkFile *c)
{
  hid_t  gcpl = CreateProperties(H5P_GROUP_CREATE), dcpl = CreateProperties(H5P_DATASET_CREATE), group = -1;
  herr_t st   = gcpl >= 0 && dcpl >= 0 ? 0 : -1;

  PetscFunctionBeginUser;
  if (!st) st = WriteRoot(w->file, c);
  if (!st) st = (group = H5Gcreate2(w->file, SPAM_CK_GROUP, H5P_DEFAULT, gcpl, H5P_DEFAULT)) < 0 ? -1 : 0;
  for (int i = 0; !st && i < c->n; i++) st = WriteEntry(w, group, dcpl, &c->e[i]);
  if (group >= 0 && H5Gclose(group) < 0) st = -1;
  if (dcpl >= 0) (void)H5Pclose(dcpl);
  if (gcpl >= 0) (void)H5Pclose(gcpl);
  if (st < 0) {
    if (w->err) errno = w->err;
    PetscCall(SpamH5Failed(w->path));
  }
  PetscFunctionReturn(0);
}

/* c's entries into *file, an in-memory file (created here, named name, when it is -1; the
 * particles of a checkpoint of several ranks are already in it, checkpoint_write_ranks.c),
 * and its image taken. The file is closed in every case. */
static PetscErrorCode WriteHdf5(const SpamCkFile *c, const char *path, const char *name, hid_t *file, long fail_at, unsigned char **image, size_t *len)
{
  CkWriter       w = {path, *file, 0, fail_at, 0};
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  errno = 0;
  if (w.file < 0) {
    const hid_t fapl = SpamCkFileAccess();
    if (fapl >= 0) w.file = SpamH5MemoryCreate(name, H5P_DEFAULT, fapl);
    if (fapl >= 0) (void)H5Pclose(fapl);
    *file = w.file;
  }
  if (*file < 0) PetscCall(SpamH5Failed(path));
  ierr = WriteContents(&w, c);
  if (ierr) SpamH5MemoryClose(file);
  PetscCall(ierr);
  PetscCall(SpamH5ImageTake(file, path, 0, image, len));
  PetscFunctionReturn(0);
}

/* The image was written through fd: the name must still be the file we created (nobody
 * replaced it, or the rename would put their file in place), and its data must be on disk
 * before the rename. */
static PetscErrorCode SyncTemporary(int fd, const struct stat *made, const char *path, const char *tmp, size_t *bytes)
{
  struct stat now, done;

  PetscFunctionBeginUser;
  if (lstat(tmp, &now) || !S_ISREG(now.st_mode) || now.st_ino != made->st_ino || now.st_dev != made->st_dev) PetscCall(WRITE_ERROR("cannot write %s: its temporary %s was replaced during the write", path, tmp));
  if (fsync(fd) || fstat(fd, &done)) PetscCall(WRITE_ERROR("cannot write %s: %s", path, strerror(errno)));
  *bytes = (size_t)done.st_size;
  PetscFunctionReturn(0);
}

/* The directory entry of the rename made durable. A file system that cannot sync a
 * directory (EINVAL) has nothing more to sync. */
static PetscErrorCode SyncDirectory(const char *path)
{
  char copy[PETSC_MAX_PATH_LEN];
  int  fd, e = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(copy, path, sizeof copy));
  fd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0 || (fsync(fd) && errno != EINVAL)) e = errno;
  if (fd >= 0) (void)close(fd);
  PetscCheck(!e, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: syncing its directory: %s", path, strerror(e));
  PetscFunctionReturn(0);
}

/* As SpamTempCreate (path.PID.tmp, O_EXCL | O_NOFOLLOW), but a failure is the checkpoint's
 * write error, naming the checkpoint. */
PetscErrorCode SpamCkTempCreate(const char *path, SpamCkTemp *t)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(t->tmp, sizeof t->tmp, "%s.%ld.tmp", path, (long)getpid()));
  t->fd = open(t->tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  PetscCheck(t->fd >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: %s", path, strerror(errno));
  if (fstat(t->fd, &t->made)) {
    const int e = errno;
    SpamCkTempDiscard(t);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: %s", path, strerror(e));
  }
  SpamTestPauseAfterTemp(path);
  PetscFunctionReturn(0);
}

void SpamCkTempDiscard(SpamCkTemp *t)
{
  if (t->fd >= 0) (void)close(t->fd);
  t->fd = -1;
  (void)unlink(t->tmp);
}

PetscErrorCode SpamCkTempFinish(const SpamCkFile *c, const char *path, SpamCkTemp *t, hid_t *file, long fail_at, size_t *bytes)
{
  PetscErrorCode ierr;
  SpamH5Quiet    quiet;
  unsigned char *image = NULL;
  size_t         len   = 0;

  PetscFunctionBeginUser;
  SpamH5QuietBegin(&quiet);
  ierr = WriteHdf5(c, path, t->tmp, file, fail_at, &image, &len);
  SpamH5QuietEnd(&quiet);
  if (!ierr) ierr = SpamWriteAll(t->fd, image, len, path);
  if (!ierr) ierr = SyncTemporary(t->fd, &t->made, path, t->tmp, bytes);
  if (close(t->fd) && !ierr) ierr = WRITE_ERROR("cannot write %s: %s", path, strerror(errno));
  t->fd = -1;
  if (!ierr && rename(t->tmp, path)) ierr = WRITE_ERROR("cannot rename %s to %s: %s", t->tmp, path, strerror(errno));
  if (ierr) (void)unlink(t->tmp);
  PetscCall(PetscFree(image));
  PetscCall(ierr);
  PetscCall(SyncDirectory(path));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteHere(const SpamCkFile *c, const char *path, size_t *bytes)
{
  SpamCkTemp t;
  hid_t      file = -1;

  PetscFunctionBeginUser;
  PetscCall(SpamCkTempCreate(path, &t));
  PetscCall(SpamCkTempFinish(c, path, &t, &file, SpamTestFailWriteAt(path), bytes));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkFileWrite(MPI_Comm comm, const SpamCkFile *c, const char *path, size_t *bytes)
{
  PetscMPIInt    rank;
  PetscErrorCode ierr = 0;
  unsigned long long shared[2] = {0, 0}; /* rank 0's error code and the file's size */
  size_t         size = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    ierr      = WriteHere(c, path, &size);
    shared[0] = (unsigned long long)ierr;
    shared[1] = size;
  }
  /* Every rank learns the outcome, so that none goes on alone after a failed write. */
  PetscCallMPI(MPI_Bcast(shared, 2, MPI_UNSIGNED_LONG_LONG, 0, comm));
  PetscCall(ierr);
  PetscCheck(!shared[0], PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: the write on rank 0 failed", path);
  if (bytes) *bytes = (size_t)shared[1];
  PetscFunctionReturn(0);
}
