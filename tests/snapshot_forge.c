/* A test tool, not a test: forges an HDF5 snapshot as someone editing it would, then stamps
 * its checksum again (SpamSnapshotStamp), so that what the file scene refuses is the forged
 * content, not the checksum. The fuzz corpus (run_fuzz.py, its snapshot family) runs it.
 *   snapshot_forge IN OUT OP
 * OP: restamp (nothing changed), float_ids_half (ids as doubles, the first 0.5),
 * float_ids_whole (ids as doubles 0.0, 1.0, ...), int32_ids (ids as 32-bit integers),
 * string_ids (ids as text), dup_ids, nan_position, negative_mass, no_velocities,
 * positions_2col (n x 2). Exit 0 when forged, 1 on any failure. */
#include <spam/output.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int Copy(const char *in, const char *out)
{
  FILE  *f = fopen(in, "rb"), *g = fopen(out, "wb");
  char   buf[65536];
  size_t n;
  int    ok = f && g;

  while (ok && (n = fread(buf, 1, sizeof buf, f)) > 0) ok = fwrite(buf, 1, n, g) == n;
  if (f) ok = !ferror(f) && !fclose(f) && ok;
  if (g) ok = !fclose(g) && ok;
  return ok;
}

/* The checksum of the edited file stamped again, as a forger who knows the format would. */
static int Restamp(const char *path)
{
  FILE          *f = fopen(path, "r+b");
  unsigned char *buf;
  long           n;
  int            ok;

  if (!f || fseek(f, 0, SEEK_END) || (n = ftell(f)) <= 0 || fseek(f, 0, SEEK_SET) || !(buf = malloc((size_t)n))) return 0;
  ok = fread(buf, 1, (size_t)n, f) == (size_t)n;
  SpamSnapshotStamp(buf, (size_t)n);
  ok = ok && !fseek(f, 0, SEEK_SET) && fwrite(buf, 1, SPAM_SNAPSHOT_USERBLOCK, f) == SPAM_SNAPSHOT_USERBLOCK;
  free(buf);
  return !fclose(f) && ok;
}

/* Dataset name replaced by n x k values of type (memory type mtype from data). */
static int Replace(hid_t file, const char *name, hid_t type, hid_t mtype, hsize_t n, hsize_t k, const void *data)
{
  const hsize_t dims[2] = {n, k};
  hid_t         space, set;
  int           ok;

  if (H5Lexists(file, name, H5P_DEFAULT) > 0 && H5Ldelete(file, name, H5P_DEFAULT) < 0) return 0;
  if ((space = H5Screate_simple(k > 1 ? 2 : 1, dims, NULL)) < 0) return 0;
  set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ok  = set >= 0 && H5Dwrite(set, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
  if (set >= 0) ok = H5Dclose(set) >= 0 && ok;
  (void)H5Sclose(space);
  return ok;
}

static int Read(hid_t file, const char *name, hid_t mtype, void *buf)
{
  const hid_t set = H5Dopen2(file, name, H5P_DEFAULT);
  const int   ok  = set >= 0 && H5Dread(set, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0;

  if (set >= 0) (void)H5Dclose(set);
  return ok;
}

static int ForgeIds(hid_t file, const char *op, hsize_t n, long long *id)
{
  double *d = malloc(n * sizeof *d);
  int    *i = malloc(n * sizeof *i);
  char   *s = malloc(n * 8);
  hid_t   str = H5Tcopy(H5T_C_S1);
  int     ok  = d && i && s && str >= 0 && H5Tset_size(str, 8) >= 0 && Read(file, "/id", H5T_NATIVE_LLONG, id);

  for (hsize_t r = 0; ok && r < n; r++) {
    d[r] = (double)id[r];
    i[r] = (int)id[r];
    (void)snprintf(s + 8 * r, 8, "%lld", id[r]);
  }
  if (ok && !strcmp(op, "float_ids_half")) {
    d[0] += 0.5; /* truncated, 0.5 would read as 0 */
    ok = Replace(file, "/id", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 1, d);
  } else if (ok && !strcmp(op, "float_ids_whole")) ok = Replace(file, "/id", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 1, d);
  else if (ok && !strcmp(op, "int32_ids")) ok = Replace(file, "/id", H5T_STD_I32LE, H5T_NATIVE_INT, n, 1, i);
  else if (ok && !strcmp(op, "string_ids")) ok = Replace(file, "/id", str, str, n, 1, s);
  else if (ok && !strcmp(op, "dup_ids")) {
    id[1] = id[0];
    ok    = Replace(file, "/id", H5T_STD_I64LE, H5T_NATIVE_LLONG, n, 1, id);
  } else ok = 0;
  if (str >= 0) (void)H5Tclose(str);
  free(d), free(i), free(s);
  return ok;
}

static int Forge(hid_t file, const char *op)
{
  hid_t     set = H5Dopen2(file, "/positions", H5P_DEFAULT), space = set >= 0 ? H5Dget_space(set) : -1;
  hsize_t   dims[2] = {0, 0};
  double   *x;
  long long *id;
  int       ok = space >= 0 && H5Sget_simple_extent_dims(space, dims, NULL) == 2 && dims[0] > 1;

  if (space >= 0) (void)H5Sclose(space);
  if (set >= 0) (void)H5Dclose(set);
  x  = malloc(dims[0] * 3 * sizeof *x);
  id = malloc(dims[0] * sizeof *id);
  ok = ok && x && id && Read(file, "/positions", H5T_NATIVE_DOUBLE, x);
  if (!ok) ok = 0;
  else if (strstr(op, "ids")) ok = ForgeIds(file, op, dims[0], id);
  else if (!strcmp(op, "nan_position")) {
    x[0] = NAN;
    ok   = Replace(file, "/positions", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims[0], 3, x);
  } else if (!strcmp(op, "positions_2col")) ok = Replace(file, "/positions", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims[0], 2, x);
  else if (!strcmp(op, "negative_mass")) {
    ok = Read(file, "/mass", H5T_NATIVE_DOUBLE, x);
    x[0] = -x[0];
    ok   = ok && Replace(file, "/mass", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims[0], 1, x);
  } else if (!strcmp(op, "no_velocities")) ok = H5Ldelete(file, "/velocities", H5P_DEFAULT) >= 0;
  else ok = !strcmp(op, "restamp");
  free(x), free(id);
  return ok;
}

int main(int argc, char **argv)
{
  hid_t file;
  int   ok;

  if (argc != 4) {
    fprintf(stderr, "usage: snapshot_forge IN OUT OP\n");
    return 1;
  }
  if (!Copy(argv[1], argv[2]) || (file = H5Fopen(argv[2], H5F_ACC_RDWR, H5P_DEFAULT)) < 0) return 1;
  ok = Forge(file, argv[3]);
  ok = H5Fclose(file) >= 0 && ok && Restamp(argv[2]);
  if (!ok) fprintf(stderr, "snapshot_forge: %s failed on %s\n", argv[3], argv[1]);
  return ok ? 0 : 1;
}
