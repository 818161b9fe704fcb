/* Internal to src/io: the HDF5 snapshot's attributes (snapshot_attributes.c). Functions
 * return HDF5's status (negative: failed); the writer turns a failure into one line. */
#ifndef SPAM_SNAPSHOT_HDF5_H
#define SPAM_SNAPSHOT_HDF5_H
#include <spam/output.h>
#include <hdf5.h>

/* What the numbers of every output mean, written into each HDF5 file (root attribute
 * units_convention) and the XDMF indexes (Information "units") so that a reader needs no
 * README. Plain ASCII without quotes or angle brackets: it goes into XML as is. */
#define SPAM_UNITS_CONVENTION \
  "reduced units: no physical units, numbers as the options give them: lengths as -box_len and -h " \
  "(the scenes' lattice spacing is 1), masses as -mass (default 1), the time unit the one these and " \
  "the model's constants (eos_kappa, spring and elastic constants) make; Boltzmann's k = 1; density " \
  "is mass per length^dim, energy e per unit mass, stress = -pressure (tension positive)"
/* Root attributes time, step, dim, box_lo, box_len, periodic, kernel_h, units ("reduced"),
 * units_convention, version and model (the JSON of SpamModelSettingsJson). */
herr_t SpamSnapshotAttributes(hid_t file, const SpamSim *sim, double t, long step, const char *model);
/* Attribute carried of /density: 1 when the density is state (the file scene reads it
 * back), 0 when summed from the positions (derived, not read). */
herr_t SpamSnapshotDensityCarried(hid_t file, int carried);
/* An attribute of loc: n values (0: a scalar); a fixed-length ASCII string. */
herr_t SpamH5Attribute(hid_t loc, const char *name, hid_t file_type, hid_t mem_type, hsize_t n, const void *data);
herr_t SpamH5StringAttribute(hid_t loc, const char *name, const char *s);
/* Property lists that keep no modification times (HDF5 stamps every object with the clock
 * by default): the same run then writes the same bytes, so a restarted run's snapshots
 * compare equal to the uninterrupted run's with cmp. kind: H5P_FILE_CREATE or
 * H5P_DATASET_CREATE; the caller closes the list (negative: failed). */
hid_t SpamH5Untimed(hid_t kind);
/* A failed HDF5 call on the file at path: one line naming it and the system's reason (HDF5
 * keeps the system call's errno), as a PETSc error. */
PetscErrorCode SpamH5Failed(const char *path);
#define SpamCallH5(path, call) \
  do { \
    errno = 0; \
    if ((call) < 0) PetscCall(SpamH5Failed(path)); \
  } while (0)
/* HDF5 files written without HDF5 ever opening a name (h5_image.c): the file is built in
 * memory (the core driver, no backing store, closed strong), its image taken, and the
 * image written through the descriptor of the temporary the program created. */
/* A new in-memory file; name is HDF5's label of it (no file of that name is opened).
 * fapl: H5P_DEFAULT or access properties to keep (the driver is replaced). */
hid_t SpamH5MemoryCreate(const char *name, hid_t fcpl, hid_t fapl);
/* Closes it if open (*file = -1): an error path's cleanup. */
void SpamH5MemoryClose(hid_t *file);
/* The file's bytes into *image (PetscMalloc'ed, *len bytes) after lead bytes of zeros: the
 * image HDF5 gives leaves out the user block a file creation asked for, whose room the
 * caller fills (the library finds its superblock after it). The file is closed in every
 * case. A failure names path. */
PetscErrorCode SpamH5ImageTake(hid_t *file, const char *path, size_t lead, unsigned char **image, size_t *len);
/* len bytes to fd, short writes continued; a failure (ENOSPC, EFBIG, ...) names path. */
PetscErrorCode SpamWriteAll(int fd, const void *buf, size_t len, const char *path);
/* Whether the name tmp is still the regular file open as fd (nobody replaced it). */
PetscErrorCode SpamTempStillOurs(int fd, const char *tmp, const char *path);
/* The image written to fd (the temporary tmp), checked to be still ours, fd closed and
 * tmp renamed to path; on any failure tmp is removed. */
PetscErrorCode SpamTempCommitImage(int fd, const char *tmp, const char *path, const unsigned char *image, size_t len);
#endif
