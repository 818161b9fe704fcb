/* Reads a checkpoint (layout in checkpoint_file.h) and trusts nothing in it: the format
 * string, every entry's type, shape and stored size, the entry count and the checksum over
 * every byte are checked, and anything else is refused as bad input in one line naming the
 * file. A damaged file never costs more memory than its own size. */
#define _DEFAULT_SOURCE /* O_CLOEXEC, stat: POSIX, not C11 */
#include "checkpoint_layout.h"
#include <spam/errors.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#define BAD(path, fmt, ...) PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_USER_INPUT, PETSC_ERROR_INITIAL, "checkpoint %s: " fmt, path, ##__VA_ARGS__)

typedef struct {
  const char *path;
  hid_t       file;
  off_t       size; /* bytes on disk: no entry can hold more */
} CkReader;

/* Missing or not readable: the system's reason; anything but a regular file (a FIFO, a
 * device, a directory) is refused before it is read. O_NONBLOCK: opening a FIFO without a
 * writer would otherwise wait forever before fstat could refuse it; on a regular file the
 * flag has no effect. */
static PetscErrorCode CheckReadable(const char *path, off_t *size)
{
  struct stat st;
  int         fd, failed;

  PetscFunctionBeginUser;
  if ((fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) < 0) PetscCall(BAD(path, "%s", strerror(errno)));
  failed = fstat(fd, &st) ? errno : 0;
  (void)close(fd);
  if (failed) PetscCall(BAD(path, "%s", strerror(failed)));
  if (!S_ISREG(st.st_mode)) PetscCall(BAD(path, "is %s; a checkpoint (a regular file) is required", SpamFileKind(st.st_mode)));
  *size = st.st_size;
  PetscFunctionReturn(0);
}

/* A scalar attribute of the root as the native type mem_type, which the stored type must be
 * (file_type); false if missing or of another type or shape. */
static PetscBool ReadScalarAttribute(hid_t file, const char *name, hid_t file_type, hid_t mem_type, void *buf)
{
  hid_t     a = H5Aexists(file, name) > 0 ? H5Aopen(file, name, H5P_DEFAULT) : -1, t = -1, s = -1;
  PetscBool ok = PETSC_FALSE;

  if (a >= 0 && (t = H5Aget_type(a)) >= 0 && (s = H5Aget_space(a)) >= 0)
    ok = (PetscBool)(H5Tequal(t, file_type) > 0 && H5Sget_simple_extent_type(s) == H5S_SCALAR && H5Aread(a, mem_type, buf) >= 0);
  if (s >= 0) (void)H5Sclose(s);
  if (t >= 0) (void)H5Tclose(t);
  if (a >= 0) (void)H5Aclose(a);
  return ok;
}

/* The root attribute format as text (at most len - 1 bytes); false if missing or not a
 * fixed-length string. */
static PetscBool ReadFormat(hid_t file, char *buf, size_t len)
{
  hid_t     a = H5Aexists(file, "format") > 0 ? H5Aopen(file, "format", H5P_DEFAULT) : -1, t = -1, s = -1;
  PetscBool ok = PETSC_FALSE;
  size_t    size;

  if (a >= 0 && (t = H5Aget_type(a)) >= 0 && (s = H5Aget_space(a)) >= 0 && H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) == 0 && H5Sget_simple_extent_type(s) == H5S_SCALAR) {
    size = H5Tget_size(t);
    if (size > 0 && size < len && H5Aread(a, t, buf) >= 0) {
      buf[size] = 0;
      ok        = PETSC_TRUE;
    }
  }
  if (s >= 0) (void)H5Sclose(s);
  if (t >= 0) (void)H5Tclose(t);
  if (a >= 0) (void)H5Aclose(a);
  return ok;
}

/* What the root says: this layout and version, how many entries, their checksum. */
static PetscErrorCode ReadRoot(const CkReader *r, int64_t *entries, uint64_t *sum)
{
  char format[256];

  PetscFunctionBeginUser;
  if (!ReadFormat(r->file, format, sizeof format)) PetscCall(BAD(r->path, "an HDF5 file without the root attribute format: not a spam-ark checkpoint"));
  if (strcmp(format, SPAM_CK_FORMAT)) PetscCall(BAD(r->path, "format '%s', this spam-ark reads '%s'", format, SPAM_CK_FORMAT));
  if (!ReadScalarAttribute(r->file, "entries", H5T_STD_I64LE, H5T_NATIVE_INT64, entries)) PetscCall(BAD(r->path, "no root attribute entries (int64): damaged"));
  if (!ReadScalarAttribute(r->file, "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64, sum)) PetscCall(BAD(r->path, "no root attribute checksum (uint64): damaged"));
  PetscFunctionReturn(0);
}

/* The kind and length a dataset has in this layout; false if it has none. */
static PetscBool Classify(hid_t set, SpamCkKind *kind, size_t *n)
{
  hid_t     t = H5Dget_type(set), s = H5Dget_space(set);
  hsize_t   dims[1];
  PetscBool ok = PETSC_FALSE;

  if (t >= 0 && s >= 0) {
    const H5S_class_t shape = H5Sget_simple_extent_type(s);
    if (H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) == 0 && shape == H5S_SCALAR && H5Tget_size(t) > 0) {
      *kind = SPAM_CK_TEXT;
      *n    = H5Tget_size(t) - 1;
      ok    = PETSC_TRUE;
    } else if (shape == H5S_SIMPLE && H5Sget_simple_extent_ndims(s) == 1 && H5Sget_simple_extent_dims(s, dims, NULL) == 1) {
      *n = (size_t)dims[0];
      if (H5Tequal(t, H5T_IEEE_F64LE) > 0) *kind = SPAM_CK_REAL, ok = PETSC_TRUE;
      else if (H5Tequal(t, H5T_STD_I64LE) > 0) *kind = SPAM_CK_INT, ok = PETSC_TRUE;
    }
  }
  if (s >= 0) (void)H5Sclose(s);
  if (t >= 0) (void)H5Tclose(t);
  return ok;
}

/* The dataset's bytes into data (n values of kind; text: its n + 1 bytes with the NUL). */
static herr_t ReadData(hid_t set, SpamCkKind kind, size_t n, void *data)
{
  hid_t  t;
  herr_t st;

  if (kind != SPAM_CK_TEXT && !n) return 0;
  t = kind == SPAM_CK_REAL ? H5Tcopy(H5T_NATIVE_DOUBLE) : kind == SPAM_CK_INT ? H5Tcopy(H5T_NATIVE_INT64) : H5Dget_type(set);
  if (t < 0) return -1;
  st = H5Dread(set, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  (void)H5Tclose(t);
  return st;
}

/* One entry, checked for its type, for the bytes it stores (exactly its values: no more
 * than the file holds) and, for text, for its closing NUL. */
static PetscErrorCode ReadEntryFrom(const CkReader *r, hid_t set, const char *name, SpamCkFile *c)
{
  SpamCkKind kind = SPAM_CK_REAL;
  size_t     n = 0, bytes;
  hsize_t    stored;
  char      *data, why[256];

  PetscFunctionBeginUser;
  if (!Classify(set, &kind, &n)) PetscCall(BAD(r->path, "entry '%s' is neither 64-bit reals, 64-bit integers nor a fixed-length string", name));
  if (kind != SPAM_CK_TEXT && n > (size_t)r->size / 8) PetscCall(BAD(r->path, "entry '%s' claims %zu values, more than the file's %lld bytes hold: damaged", name, n, (long long)r->size));
  bytes  = kind == SPAM_CK_TEXT ? n + 1 : n * 8;
  stored = H5Dget_storage_size(set);
  if ((hsize_t)bytes != stored || bytes > (size_t)r->size) PetscCall(BAD(r->path, "entry '%s' needs %zu bytes but stores %llu: truncated or damaged", name, bytes, (unsigned long long)stored));
  PetscCall(PetscMalloc1(bytes + 1, &data));
  if (ReadData(set, kind, n, data) < 0) {
    SpamH5Reason(why, sizeof why);
    PetscCall(PetscFree(data));
    PetscCall(BAD(r->path, "cannot read entry '%s': %s", name, why));
  }
  if (kind == SPAM_CK_TEXT && data[n]) {
    PetscCall(PetscFree(data));
    PetscCall(BAD(r->path, "entry '%s': text without its closing NUL: damaged", name));
  }
  data[bytes] = 0;
  PetscCall(SpamCkAdopt(c, name, kind, n, data));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadEntry(const CkReader *r, hid_t group, hsize_t i, SpamCkFile *c)
{
  char           name[64], why[256];
  const ssize_t  len = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, NULL, 0, H5P_DEFAULT);
  hid_t          set;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (len < 0) {
    SpamH5Reason(why, sizeof why);
    PetscCall(BAD(r->path, "cannot read the name of entry %llu: %s", (unsigned long long)i, why));
  }
  if (len >= (ssize_t)sizeof name) PetscCall(BAD(r->path, "entry %llu has a name of %zd bytes, more than 63", (unsigned long long)i, len));
  if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) != len || !SpamCkNameValid(name)) PetscCall(BAD(r->path, "entry %llu has a name outside 1-63 letters, digits, '_', '-', '.'", (unsigned long long)i));
  if ((set = H5Dopen2(group, name, H5P_DEFAULT)) < 0) {
    SpamH5Reason(why, sizeof why);
    PetscCall(BAD(r->path, "entry '%s' is not a readable dataset: %s", name, why));
  }
  ierr = ReadEntryFrom(r, set, name, c);
  (void)H5Dclose(set);
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadEntries(const CkReader *r, SpamCkFile *c)
{
  int64_t        entries;
  uint64_t       sum, computed;
  hid_t          group;
  H5G_info_t     info;
  PetscErrorCode ierr = 0;
  char           why[256];

  PetscFunctionBeginUser;
  PetscCall(ReadRoot(r, &entries, &sum));
  if ((group = H5Gopen2(r->file, SPAM_CK_GROUP, H5P_DEFAULT)) < 0) PetscCall(BAD(r->path, "no group " SPAM_CK_GROUP ": damaged"));
  if (H5Gget_info(group, &info) < 0) {
    SpamH5Reason(why, sizeof why);
    ierr = BAD(r->path, "cannot list " SPAM_CK_GROUP ": %s", why);
  } else if (entries < 0 || (uint64_t)entries != (uint64_t)info.nlinks) ierr = BAD(r->path, SPAM_CK_GROUP " holds %llu entries, the root attribute entries says %lld: damaged", (unsigned long long)info.nlinks, (long long)entries);
  for (hsize_t i = 0; !ierr && i < info.nlinks; i++) ierr = ReadEntry(r, group, i, c);
  (void)H5Gclose(group);
  PetscCall(ierr);
  computed = SpamCkChecksum(c);
  PetscCheck(computed == sum, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: its checksum disagrees with its contents (stored %016llx, computed %016llx): damaged", r->path, (unsigned long long)sum, (unsigned long long)computed);
  PetscFunctionReturn(0);
}

/* The file opened as HDF5 (only if it is one), read, and closed. */
static PetscErrorCode ReadHdf5(CkReader *r, SpamCkFile *c)
{
  const htri_t   is = H5Fis_hdf5(r->path);
  hid_t          fapl;
  PetscErrorCode ierr;
  char           why[256];

  PetscFunctionBeginUser;
  if (is <= 0) PetscCall(BAD(r->path, "not an HDF5 file (%lld bytes)", (long long)r->size));
  if ((fapl = SpamCkFileAccess()) >= 0) r->file = H5Fopen(r->path, H5F_ACC_RDONLY, fapl);
  if (r->file < 0) SpamH5Reason(why, sizeof why);
  if (fapl >= 0) (void)H5Pclose(fapl);
  if (r->file < 0) PetscCall(BAD(r->path, "HDF5 cannot open it (%s): truncated or damaged", why));
  ierr = ReadEntries(r, c);
  (void)H5Fclose(r->file);
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* This rank's read; on failure c is left empty. */
static PetscErrorCode ReadHere(const char *path, SpamCkFile *c)
{
  CkReader       r = {path, -1, 0};
  SpamH5Quiet    quiet;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(CheckReadable(path, &r.size));
  SpamH5QuietBegin(&quiet);
  ierr = ReadHdf5(&r, c);
  /* After a refusal HDF5's printing stays off: HDF5 1.10.8 leaks an object header's prefix
   * on some damaged files (HDFGroup/hdf5 issue 3790, fixed in 1.14.5) and then, at exit,
   * prints "HDF5: infinite loop closing library" unless its automatic printing is off. */
  if (!ierr) SpamH5QuietEnd(&quiet);
  else { /* nothing of a refused file is kept */
    (void)H5Eclear2(H5E_DEFAULT);
    PetscCall(SpamCkFileDestroy(c));
    PetscCall(PetscStrncpy(c->path, path, sizeof c->path));
  }
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkFileRead(MPI_Comm comm, const char *path, SpamCkFile *c)
{
  PetscErrorCode ierr;
  int            failed, any;

  PetscFunctionBeginUser;
  PetscCall(SpamCkFileInit(c));
  PetscCall(PetscStrncpy(c->path, path, sizeof c->path));
  ierr   = ReadHere(path, c);
  failed = ierr ? 1 : 0;
  /* Every rank learns whether all could read it, so that none goes on alone. */
  PetscCallMPI(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm));
  PetscCall(ierr);
  if (any) {
    PetscCall(SpamCkFileDestroy(c));
    PetscCall(PetscStrncpy(c->path, path, sizeof c->path));
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: another rank cannot read it", path);
  }
  PetscFunctionReturn(0);
}
