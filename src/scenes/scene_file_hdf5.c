/* The file scene from one of the program's own HDF5 snapshots (snapshot_xdmf.c writes
 * them): positions, velocities, and the mass, id, energy, carried density and stress
 * where the snapshot has them. Dimension, box and periodicity are the snapshot's root
 * attributes; -dim must match (the kernel and the gas default of gamma are read before the
 * scene), and -box_lo, -box_len or -periodic given as well must be equal to the snapshot's
 * (else one line naming both): a restart in another box would not continue the run. */
#include "particle_file.h"
#include <spam/errors.h>
#include <hdf5.h>

/* Reads an attribute of the root group as n values of the given native type; false if
 * the file has no such attribute or it holds another count. */
static PetscBool ReadAttribute(hid_t file, const char *name, hid_t type, void *buf, hssize_t n)
{
  hid_t     a, space;
  PetscBool ok = PETSC_FALSE;

  if (H5Aexists(file, name) <= 0) return PETSC_FALSE;
  if ((a = H5Aopen(file, name, H5P_DEFAULT)) < 0) return PETSC_FALSE;
  if ((space = H5Aget_space(a)) >= 0) {
    ok = (PetscBool)(H5Sget_simple_extent_npoints(space) == n && H5Aread(a, type, buf) >= 0);
    (void)H5Sclose(space);
  }
  (void)H5Aclose(a);
  return ok;
}

/* Reads attribute name of obj (the root group or a dataset) as n <= 3 whole numbers:
 * through double, so that a value stored as floating point (dim = 2.7) is seen, not
 * truncated by HDF5's conversion to int. 1: read; 0: no such attribute of n values; -1:
 * a value that is not a whole number in int's range. */
static int ReadIntAttribute(hid_t obj, const char *name, int *buf, hssize_t n)
{
  double v[3];
  hid_t  a, space;
  int    ok = 0;

  if (n < 1 || n > 3 || H5Aexists(obj, name) <= 0) return 0;
  if ((a = H5Aopen(obj, name, H5P_DEFAULT)) < 0) return 0;
  if ((space = H5Aget_space(a)) >= 0) {
    ok = H5Sget_simple_extent_npoints(space) == n && H5Aread(a, H5T_NATIVE_DOUBLE, v) >= 0;
    (void)H5Sclose(space);
  }
  (void)H5Aclose(a);
  for (hssize_t k = 0; ok && k < n; k++) {
    if (!(v[k] == floor(v[k]) && fabs(v[k]) <= INT_MAX)) return -1; /* NaN fails too */
    buf[k] = (int)v[k];
  }
  return ok;
}

/* Reads dataset name as n rows of ncomp values of the native type into buf; *found is
 * false if the file has no such dataset. A dataset of another shape is bad input. HDF5
 * converts the stored type (a snapshot's little-endian doubles) to the native one. */
static PetscErrorCode ReadDataset(hid_t file, const char *path, const char *name, hid_t type, hsize_t n, hsize_t ncomp, void *buf, PetscBool *found)
{
  hid_t   set, space;
  hsize_t dims[2] = {0, 0};
  int     rank;
  herr_t  got = -1;

  PetscFunctionBeginUser;
  *found = (PetscBool)(H5Lexists(file, name, H5P_DEFAULT) > 0);
  if (!*found) PetscFunctionReturn(0);
  if ((set = H5Dopen2(file, name, H5P_DEFAULT)) < 0) SPAM_BAD_INPUT("-file_path", path, "cannot open the dataset %s", name);
  space = H5Dget_space(set);
  rank  = space >= 0 ? H5Sget_simple_extent_dims(space, dims, NULL) : -1;
  if (rank == (ncomp > 1 ? 2 : 1) && dims[0] == n && (ncomp == 1 || dims[1] == ncomp)) got = H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  if (space >= 0) (void)H5Sclose(space);
  (void)H5Dclose(set);
  if (got < 0) SPAM_BAD_INPUT("-file_path", path, "the dataset %s is not %llu x %llu numbers as the positions say", name, (unsigned long long)n, (unsigned long long)ncomp);
  PetscFunctionReturn(0);
}

/* The snapshot's box; options given as well must agree with it. */
static PetscErrorCode ReadBox(hid_t file, const SpamCommonParams *c, const char *path, SpamBox *box)
{
  int       dim = 0, per[3] = {0, 0, 0}, got;
  PetscBool set_lo, set_per;
  char      val[32];

  PetscFunctionBeginUser;
  got = ReadIntAttribute(file, "dim", &dim, 1);
  if (got < 0) SPAM_BAD_INPUT("-file_path", path, "the snapshot attribute dim is not a whole number (1, 2 or 3)");
  if (got == 0 || dim < 1 || dim > 3) SPAM_BAD_INPUT("-file_path", path, "is an HDF5 file without the snapshot attribute dim (1, 2 or 3): not a snapshot of this program (0.2 or later)");
  (void)snprintf(val, sizeof val, "%d", c->dim);
  if (dim != c->dim) SPAM_BAD_INPUT("-dim", val, "the snapshot %s is %d-dimensional: add -dim %d", path, dim, dim);
  box->dim = dim;
  if (!ReadAttribute(file, "box_lo", H5T_NATIVE_DOUBLE, box->lo, dim) || !ReadAttribute(file, "box_len", H5T_NATIVE_DOUBLE, box->len, dim) || ReadIntAttribute(file, "periodic", per, dim) == 0) SPAM_BAD_INPUT("-file_path", path, "the snapshot lacks its box (attributes box_lo, box_len, periodic of %d values)", dim);
  if (ReadIntAttribute(file, "periodic", per, dim) < 0) SPAM_BAD_INPUT("-file_path", path, "the snapshot attribute periodic holds a value that is not a whole number (0 or 1)");
  for (int d = 0; d < dim; d++) box->periodic[d] = (PetscBool)(per[d] != 0);
  PetscCall(PetscOptionsHasName(NULL, NULL, "-box_lo", &set_lo));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-periodic", &set_per));
  for (int d = 0; d < dim; d++) {
    char mine[64], theirs[64];
    (void)snprintf(theirs, sizeof theirs, "%.17g", box->len[d]);
    PetscCall(SpamOptionText("-box_len", c->box_len[d], mine, sizeof mine));
    if (c->box_len_set && c->box_len[d] != box->len[d]) SPAM_BAD_INPUT("-box_len", mine, "the snapshot %s has box_len %s in direction %d; give the snapshot's box or none", path, theirs, d + 1);
    (void)snprintf(theirs, sizeof theirs, "%.17g", box->lo[d]);
    PetscCall(SpamOptionText("-box_lo", c->box_lo[d], mine, sizeof mine));
    if (set_lo && c->box_lo[d] != box->lo[d]) SPAM_BAD_INPUT("-box_lo", mine, "the snapshot %s has box_lo %s in direction %d; give the snapshot's box or none", path, theirs, d + 1);
    PetscCall(SpamOptionText("-periodic", 0.0, mine, sizeof mine));
    if (set_per && c->periodic[d] != box->periodic[d]) SPAM_BAD_INPUT("-periodic", mine, "the snapshot %s is %s in direction %d; give the snapshot's periodicity or none", path, box->periodic[d] ? "periodic" : "open", d + 1);
  }
  PetscCall(SpamBoxValidate(box, c->h, "the snapshot's box"));
  PetscFunctionReturn(0);
}

/* The number of particles: the rows of /positions. */
static PetscErrorCode CountParticles(hid_t file, const char *path, PetscInt *n)
{
  hid_t   set, space;
  hsize_t dims[2] = {0, 0};
  int     rank = -1;

  PetscFunctionBeginUser;
  if (H5Lexists(file, "/positions", H5P_DEFAULT) <= 0 || (set = H5Dopen2(file, "/positions", H5P_DEFAULT)) < 0) SPAM_BAD_INPUT("-file_path", path, "the snapshot has no dataset /positions");
  if ((space = H5Dget_space(set)) >= 0) {
    rank = H5Sget_simple_extent_dims(space, dims, NULL);
    (void)H5Sclose(space);
  }
  (void)H5Dclose(set);
  if (rank != 2 || dims[1] != 3 || dims[0] < 1 || (double)dims[0] > SpamMaxParticles()) SPAM_BAD_INPUT("-file_path", path, "/positions must be n x 3 numbers with 1 <= n <= %.4g", SpamMaxParticles());
  *n = (PetscInt)dims[0];
  PetscFunctionReturn(0);
}

/* Which optional datasets the snapshot has: the density only where the model carried it
 * (attribute carried = 1); a summed density is derived from positions, not state. */
static PetscErrorCode Columns(hid_t file, const char *path, unsigned *columns)
{
  int carried = 0, got = 0;

  PetscFunctionBeginUser;
  *columns = SPAM_COLUMN_X | SPAM_COLUMN_V;
  if (H5Lexists(file, "/mass", H5P_DEFAULT) > 0) *columns |= SPAM_COLUMN_M;
  if (H5Lexists(file, "/id", H5P_DEFAULT) > 0) *columns |= SPAM_COLUMN_ID;
  if (H5Lexists(file, "/energy", H5P_DEFAULT) > 0) *columns |= SPAM_COLUMN_E;
  if (H5Lexists(file, "/stress", H5P_DEFAULT) > 0) *columns |= SPAM_COLUMN_STRESS;
  if (H5Lexists(file, "/density", H5P_DEFAULT) > 0 && H5Aexists_by_name(file, "/density", "carried", H5P_DEFAULT) > 0) {
    hid_t set = H5Dopen2(file, "/density", H5P_DEFAULT);
    if (set >= 0) got = ReadIntAttribute(set, "carried", &carried, 1);
    if (set >= 0) (void)H5Dclose(set);
    if (got < 0) SPAM_BAD_INPUT("-file_path", path, "the attribute carried of /density is not a whole number (0 or 1)");
    if (got == 0) carried = 0;
  }
  if (carried) *columns |= SPAM_COLUMN_RHO;
  PetscFunctionReturn(0);
}

/* Rows of 3 (positions, velocities) or 6 (Tensor6 stress) into the dimension's layout. */
static void Unpad(const double *in, PetscInt n, int dim, PetscBool stress, double *out)
{
  static const int t6[3][6] = {{0}, {0, 1, 3}, {0, 1, 2, 3, 4, 5}};
  const int        k = stress ? SpamStressComponents(dim) : dim, w = stress ? 6 : 3;

  for (PetscInt i = 0; i < n; i++)
    for (int c = 0; c < k; c++) out[(size_t)i * k + c] = in[(size_t)i * w + (stress ? t6[dim - 1][c] : c)];
}

/* Every particle inside the box, every value finite, masses and densities positive. */
static PetscErrorCode CheckValues(const char *path, const SpamParticles *p)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < p->n; i++) {
    PetscBool ok = PETSC_TRUE;
    for (int d = 0; d < p->dim; d++) {
      const double x = p->x[i * p->dim + d];
      ok             = (PetscBool)(ok && x >= p->box.lo[d] && x <= p->box.lo[d] + p->box.len[d] && isfinite(p->v[i * p->dim + d]));
    }
    if (p->m && SpamPositiveNormalProblem(p->m[i])) SPAM_BAD_INPUT("-file_path", path, "particle %" PetscInt_FMT ": mass %.17g: %s", i + 1, p->m[i], SpamPositiveNormalProblem(p->m[i]));
    if (p->e) ok = (PetscBool)(ok && isfinite(p->e[i]) && (!(p->columns & SPAM_COLUMN_RHO) || (p->rho[i] > 0.0 && isfinite(p->rho[i]))));
    for (int k = 0; p->sigma && k < SpamStressComponents(p->dim); k++) ok = (PetscBool)(ok && isfinite(p->sigma[(size_t)i * SpamStressComponents(p->dim) + k]));
    if (!ok) SPAM_BAD_INPUT("-file_path", path, "particle %" PetscInt_FMT " lies outside the snapshot's box or has a value that is not finite (or a density that is not positive)", i + 1);
  }
  PetscFunctionReturn(0);
}

/* Positions, velocities and stress through buf ([6n]: rows padded to 3 or 6). */
static PetscErrorCode ReadVectors(hid_t file, const char *path, int dim, PetscInt n, double *buf, SpamParticles *out)
{
  PetscBool found;

  PetscFunctionBeginUser;
  PetscCall(ReadDataset(file, path, "/positions", H5T_NATIVE_DOUBLE, (hsize_t)n, 3, buf, &found));
  Unpad(buf, n, dim, PETSC_FALSE, out->x);
  PetscCall(ReadDataset(file, path, "/velocities", H5T_NATIVE_DOUBLE, (hsize_t)n, 3, buf, &found));
  if (!found) SPAM_BAD_INPUT("-file_path", path, "the snapshot has no dataset /velocities");
  Unpad(buf, n, dim, PETSC_FALSE, out->v);
  if (out->columns & SPAM_COLUMN_STRESS) {
    PetscCall(ReadDataset(file, path, "/stress", H5T_NATIVE_DOUBLE, (hsize_t)n, 6, buf, &found));
    Unpad(buf, n, dim, PETSC_TRUE, out->sigma);
  }
  PetscFunctionReturn(0);
}

/* Whether dataset name is stored as integers: HDF5 would convert floating-point ids to
 * integers by truncation (0.5 read as 0), so another type is refused, not converted. */
static PetscBool StoredAsIntegers(hid_t file, const char *name)
{
  const hid_t set  = H5Dopen2(file, name, H5P_DEFAULT);
  const hid_t type = set >= 0 ? H5Dget_type(set) : -1;
  PetscBool   ok   = (PetscBool)(type >= 0 && H5Tget_class(type) == H5T_INTEGER);

  if (type >= 0) (void)H5Tclose(type);
  if (set >= 0) (void)H5Dclose(set);
  return ok;
}

/* The ids through buf ([n] 64-bit integers); an id out of 0..n-1 becomes -1 (refused). */
static PetscErrorCode ReadIds(hid_t file, const char *path, PetscInt n, PetscInt64 *buf, PetscInt *id)
{
  PetscBool found;

  PetscFunctionBeginUser;
  if (!StoredAsIntegers(file, "/id")) SPAM_BAD_INPUT("-file_path", path, "the dataset /id is not stored as integers (ids are 0..n-1, a fraction would be truncated)");
  PetscCall(ReadDataset(file, path, "/id", H5T_NATIVE_INT64, (hsize_t)n, 1, buf, &found));
  for (PetscInt i = 0; i < n; i++) id[i] = buf[i] < 0 || buf[i] >= n ? -1 : (PetscInt)buf[i];
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadParticles(hid_t file, const char *path, int dim, PetscInt n, unsigned columns, SpamParticles *out)
{
  double        *buf;
  PetscBool      found;
  PetscInt       bad;
  const char    *why;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocateColumns(dim, n, columns, out));
  PetscCall(PetscMalloc1((size_t)6 * n, &buf));
  ierr = ReadVectors(file, path, dim, n, buf, out);
  if (!ierr && out->id) ierr = ReadIds(file, path, n, (PetscInt64 *)buf, out->id);
  PetscCall(PetscFree(buf));
  PetscCall(ierr);
  if (out->m) PetscCall(ReadDataset(file, path, "/mass", H5T_NATIVE_DOUBLE, (hsize_t)n, 1, out->m, &found));
  if (columns & SPAM_COLUMN_E) PetscCall(ReadDataset(file, path, "/energy", H5T_NATIVE_DOUBLE, (hsize_t)n, 1, out->e, &found));
  if (columns & SPAM_COLUMN_RHO) PetscCall(ReadDataset(file, path, "/density", H5T_NATIVE_DOUBLE, (hsize_t)n, 1, out->rho, &found));
  PetscCall(SpamParticlesOrderById(out, &bad, &why));
  if (bad >= 0) SPAM_BAD_INPUT("-file_path", path, "the id of particle %" PetscInt_FMT " %s; the ids of %" PetscInt_FMT " particles are 0..%" PetscInt_FMT ", each once", bad + 1, why, n, n - 1);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFileReadHdf5(const SpamCommonParams *c, const char *path, SpamParticles *out)
{
  hid_t          file;
  SpamBox        box;
  PetscInt       n = 0;
  unsigned       columns;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* no error-stack dump: one line instead */
  file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) SPAM_BAD_INPUT("-file_path", path, "has the HDF5 signature but HDF5 cannot open it");
  ierr = ReadBox(file, c, path, &box);
  if (!ierr) ierr = CountParticles(file, path, &n);
  if (!ierr) ierr = Columns(file, path, &columns);
  if (!ierr) ierr = ReadParticles(file, path, c->dim, n, columns, out);
  (void)H5Fclose(file);
  PetscCall(ierr);
  out->box  = box;
  out->mass = out->m ? out->m[0] : -1.0;
  PetscCall(CheckValues(path, out));
  PetscFunctionReturn(0);
}
