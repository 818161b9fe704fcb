/* HDF5 files built in memory and written through a descriptor the program created itself.
 *
 * Why not let HDF5 write the temporary: HDF5 opens a file by name, so the temporary would
 * be opened a second time after its O_EXCL | O_NOFOLLOW create, and whoever can write the
 * directory could swap the name for a symlink in between (HDF5 would truncate the link's
 * target). The core driver without a backing store never touches the file system; the
 * image it builds is written with write() to the descriptor of the create. It also keeps
 * a full disk away from HDF5: a file whose close failed writing stays open inside the
 * library and is closed again at its shutdown, after PETSc and MPI are gone (a crash). */
#define _DEFAULT_SOURCE /* fsync, lstat: POSIX, not C11 */
#include "snapshot_hdf5.h"

#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

/* The image grows in steps of this many bytes (HDF5 reallocates it). */
#define CORE_INCREMENT ((size_t)1 << 20)

hid_t SpamH5MemoryCreate(const char *name, hid_t fcpl, hid_t fapl)
{
  const hid_t copy = fapl == H5P_DEFAULT ? H5Pcreate(H5P_FILE_ACCESS) : H5Pcopy(fapl);
  hid_t       file = -1;

  if (copy < 0) return -1;
  /* strong: closing the file closes whatever an error path left open in it */
  if (H5Pset_fapl_core(copy, CORE_INCREMENT, 0) >= 0 && H5Pset_fclose_degree(copy, H5F_CLOSE_STRONG) >= 0) file = H5Fcreate(name, H5F_ACC_TRUNC, fcpl, copy);
  (void)H5Pclose(copy);
  return file;
}

void SpamH5MemoryClose(hid_t *file)
{
  if (*file >= 0) (void)H5Fclose(*file); /* in memory: nothing to flush that could fail */
  *file = -1;
}

/* Jenkins' lookup3 (hashlittle, bytes read one at a time), HDF5's metadata checksum. */
static uint32_t Rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

static void Mix(uint32_t *a, uint32_t *b, uint32_t *c)
{
  *a -= *c, *a ^= Rot(*c, 4), *c += *b;
  *b -= *a, *b ^= Rot(*a, 6), *a += *c;
  *c -= *b, *c ^= Rot(*b, 8), *b += *a;
  *a -= *c, *a ^= Rot(*c, 16), *c += *b;
  *b -= *a, *b ^= Rot(*a, 19), *a += *c;
  *c -= *b, *c ^= Rot(*b, 4), *b += *a;
}

static void Final(uint32_t *a, uint32_t *b, uint32_t *c)
{
  *c ^= *b, *c -= Rot(*b, 14);
  *a ^= *c, *a -= Rot(*c, 11);
  *b ^= *a, *b -= Rot(*a, 25);
  *c ^= *b, *c -= Rot(*b, 16);
  *a ^= *c, *a -= Rot(*c, 4);
  *b ^= *a, *b -= Rot(*a, 14);
  *c ^= *b, *c -= Rot(*b, 24);
}

static uint32_t Lookup3(const unsigned char *k, size_t len)
{
  uint32_t abc[3];

  abc[0] = abc[1] = abc[2] = 0xdeadbeefu + (uint32_t)len;
  for (; len > 12; len -= 12, k += 12) {
    for (int i = 0; i < 12; i++) abc[i / 4] += (uint32_t)k[i] << (8 * (i % 4));
    Mix(&abc[0], &abc[1], &abc[2]);
  }
  if (!len) return abc[2];
  for (size_t i = 0; i < len; i++) abc[i / 4] += (uint32_t)k[i] << (8 * (i % 4));
  Final(&abc[0], &abc[1], &abc[2]);
  return abc[2];
}

/* HDF5 1.10's file image clears the superblock's status flags (the file is open for
 * writing) without computing the superblock's checksum again (version 2 and later, the
 * checkpoint's 1.8 format): the library would then refuse the file it wrote. */
static void FixSuperblock(unsigned char *sb, size_t len)
{
  size_t   n;
  uint32_t sum;

  if (len < 12 || sb[8] < 2) return; /* versions 0 and 1 carry no checksum */
  n = 12 + 4 * (size_t)sb[9];        /* signature, versions, sizes, flags, four addresses */
  if (len < n + 4) return;
  sum = Lookup3(sb, n);
  for (int b = 0; b < 4; b++) sb[n + b] = (unsigned char)(sum >> (8 * b));
}

PetscErrorCode SpamH5ImageTake(hid_t *file, const char *path, size_t lead, unsigned char **image, size_t *len)
{
  ssize_t        n = -1;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  *image = NULL;
  *len   = 0;
  errno  = 0;
  if (H5Fflush(*file, H5F_SCOPE_LOCAL) >= 0) n = H5Fget_file_image(*file, NULL, 0);
  if (n <= 0) {
    const int e = errno ? errno : ENOMEM;
    SpamH5MemoryClose(file);
    errno = e;
    PetscCall(SpamH5Failed(path));
  }
  ierr = PetscCalloc1(lead + (size_t)n, image);
  if (!ierr && H5Fget_file_image(*file, *image + lead, (size_t)n) != n) {
    ierr = PetscFree(*image);
    if (!ierr) ierr = PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_FILE_WRITE, PETSC_ERROR_INITIAL, "cannot write %s: HDF5 gave no image of it", path);
  }
  SpamH5MemoryClose(file);
  PetscCall(ierr);
  FixSuperblock(*image + lead, (size_t)n);
  *len = lead + (size_t)n;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamWriteAll(int fd, const void *buf, size_t len, const char *path)
{
  const char *p = buf;

  PetscFunctionBeginUser;
  while (len) {
    const ssize_t w = write(fd, p, len);
    if (w < 0 && errno == EINTR) continue;
    PetscCheck(w > 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: %s", path, strerror(w < 0 ? errno : ENOSPC));
    p += w;
    len -= (size_t)w;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTempStillOurs(int fd, const char *tmp, const char *path)
{
  struct stat made, now;

  PetscFunctionBeginUser;
  PetscCheck(!fstat(fd, &made), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: %s", path, strerror(errno));
  if (lstat(tmp, &now) || !S_ISREG(now.st_mode) || now.st_ino != made.st_ino || now.st_dev != made.st_dev) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: its temporary %s was replaced during the write", path, tmp);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamTempCommitImage(int fd, const char *tmp, const char *path, const unsigned char *image, size_t len)
{
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  ierr = SpamWriteAll(fd, image, len, path);
  if (!ierr) ierr = SpamTempStillOurs(fd, tmp, path);
  if (close(fd) && !ierr) ierr = PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_FILE_WRITE, PETSC_ERROR_INITIAL, "cannot write %s: %s", path, strerror(errno));
  if (!ierr && rename(tmp, path)) ierr = PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_FILE_WRITE, PETSC_ERROR_INITIAL, "cannot rename %s to %s: %s", tmp, path, strerror(errno));
  if (ierr) (void)unlink(tmp); /* the name only: a symlink put there is removed, not followed */
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
