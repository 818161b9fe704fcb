/* What an HDF5 snapshot carries so that a reader can use it alone (the file scene reads it
 * back, scene_file_hdf5.c): root attributes time, step, dim, box_lo, box_len, periodic,
 * kernel_h, units, units_convention, version and model (a JSON object, model_settings.c). */
#include "snapshot_hdf5.h"
#include <errno.h>
#include <spam/version.h>

static herr_t Attribute(hid_t file, const char *name, hid_t file_type, hid_t mem_type, hsize_t n, const void *data)
{
  hid_t  space = n ? H5Screate_simple(1, &n, NULL) : H5Screate(H5S_SCALAR), a;
  herr_t w     = -1;

  if (space < 0) return -1;
  if ((a = H5Acreate2(file, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT)) >= 0) {
    w = H5Awrite(a, mem_type, data);
    if (H5Aclose(a) < 0) w = -1;
  }
  (void)H5Sclose(space);
  return w;
}

/* A fixed-length string attribute (ASCII, NUL-terminated). */
static herr_t StringAttribute(hid_t loc, const char *name, const char *s)
{
  hid_t  type = H5Tcopy(H5T_C_S1);
  herr_t w    = -1;

  if (type < 0) return -1;
  if (H5Tset_size(type, strlen(s) + 1) >= 0 && H5Tset_strpad(type, H5T_STR_NULLTERM) >= 0) w = Attribute(loc, name, type, type, 0, s);
  (void)H5Tclose(type);
  return w;
}

herr_t SpamSnapshotAttributes(hid_t file, const SpamSim *sim, double t, long step, const char *model)
{
  const int dim = sim->model.dim;
  int       periodic[3];
  long long st = step;

  for (int d = 0; d < dim; d++) periodic[d] = sim->geo.box.periodic[d] ? 1 : 0;
  if (Attribute(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, &t) < 0) return -1;
  if (Attribute(file, "step", H5T_STD_I64LE, H5T_NATIVE_LLONG, 0, &st) < 0) return -1;
  if (Attribute(file, "dim", H5T_STD_I32LE, H5T_NATIVE_INT, 0, &dim) < 0) return -1;
  if (Attribute(file, "box_lo", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, (hsize_t)dim, sim->geo.box.lo) < 0) return -1;
  if (Attribute(file, "box_len", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, (hsize_t)dim, sim->geo.box.len) < 0) return -1;
  if (Attribute(file, "periodic", H5T_STD_I32LE, H5T_NATIVE_INT, (hsize_t)dim, periodic) < 0) return -1;
  if (Attribute(file, "kernel_h", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, &sim->model.kernel.h) < 0) return -1;
  if (StringAttribute(file, "units", "reduced") < 0) return -1;
  if (StringAttribute(file, "units_convention", SPAM_UNITS_CONVENTION) < 0) return -1;
  if (StringAttribute(file, "version", "spam-ark " SPAM_VERSION) < 0) return -1;
  return StringAttribute(file, "model", model);
}

herr_t SpamSnapshotDensityCarried(hid_t file, int carried)
{
  hid_t  set = H5Dopen2(file, "/density", H5P_DEFAULT);
  herr_t w;

  if (set < 0) return -1;
  w = Attribute(set, "carried", H5T_STD_I32LE, H5T_NATIVE_INT, 0, &carried);
  if (H5Dclose(set) < 0) w = -1;
  return w;
}

herr_t SpamH5Attribute(hid_t loc, const char *name, hid_t file_type, hid_t mem_type, hsize_t n, const void *data)
{
  return Attribute(loc, name, file_type, mem_type, n, data);
}

herr_t SpamH5StringAttribute(hid_t loc, const char *name, const char *s)
{
  return StringAttribute(loc, name, s);
}

PetscErrorCode SpamH5Failed(const char *path)
{
  const int e = errno ? errno : EIO; /* HDF5 keeps the system call's errno */

  PetscFunctionBeginUser;
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: %s", path, strerror(e));
}

hid_t SpamH5Untimed(hid_t kind)
{
  const hid_t plist = H5Pcreate(kind);
  if (plist < 0) return plist;
  if (H5Pset_obj_track_times(plist, 0) < 0) {
    (void)H5Pclose(plist);
    return -1;
  }
  return plist;
}
