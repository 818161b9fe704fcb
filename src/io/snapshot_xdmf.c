/* Particle snapshots: one HDF5 file per snapshot (positions, velocities, density, and
 * energy and stress where the model carries them) and an
 * XDMF index over all of them that ParaView opens as a time series of point clouds. */
#include <spam/output.h>
#include <hdf5.h>

PetscErrorCode SpamSnapshotCsvWrite(const char *path, const SpamSim *sim, const double *y, double t);

#define PetscCallH5(call) \
  do { \
    if ((call) < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "HDF5 call failed: %s", #call); \
  } while (0)

static PetscErrorCode WriteDataset(hid_t file, const char *name, const double *data, hsize_t n, hsize_t ncomp)
{
  hsize_t dims[2] = {n, ncomp};
  hid_t   space, set;

  PetscFunctionBeginUser;
  space = H5Screate_simple(ncomp > 1 ? 2 : 1, dims, NULL);
  PetscCallH5(space);
  set = H5Dcreate2(file, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  PetscCallH5(set);
  PetscCallH5(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data));
  PetscCallH5(H5Dclose(set));
  PetscCallH5(H5Sclose(space));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteHdf5(const char *path, const SpamSim *sim, const double *y)
{
  const SpamLayout *l = &sim->model.layout;
  const PetscInt    n = sim->n;
  double           *x, *v, *rho, *e = NULL, *s6 = NULL;
  char              tmp[PETSC_MAX_PATH_LEN + 8];
  hid_t             file;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(3 * n + 1, &x));
  PetscCall(PetscCalloc1(3 * n + 1, &v));
  PetscCall(PetscCalloc1(n + 1, &rho));
  if (l->e >= 0) PetscCall(PetscCalloc1(n + 1, &e));
  if (l->s >= 0) PetscCall(PetscCalloc1(6 * n + 1, &s6));
  for (PetscInt r = 0; r < n; r++) { /* row r of every dataset: input row r */
    const PetscInt i = SpamSimAtRow(sim, r);
    rho[r]           = SpamSnapshotDensity(sim, y, i);
    if (e) e[r] = y[(size_t)i * l->nvar + l->e];
    if (s6) SpamSnapshotStress6(sim, y, i, s6 + 6 * r);
    for (int d = 0; d < sim->model.dim; d++) {
      x[3 * r + d] = sim->box.lo[d] + SpamBoxLocal(&sim->box, d, y[(size_t)i * l->nvar + l->x + d]);
      v[3 * r + d] = y[(size_t)i * l->nvar + l->v + d];
    }
  }
  PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s.tmp", path));
  file = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  PetscCallH5(file);
  PetscCall(WriteDataset(file, "/positions", x, (hsize_t)n, 3));
  PetscCall(WriteDataset(file, "/velocities", v, (hsize_t)n, 3));
  PetscCall(WriteDataset(file, "/density", rho, (hsize_t)n, 1));
  if (e) PetscCall(WriteDataset(file, "/energy", e, (hsize_t)n, 1));
  if (s6) PetscCall(WriteDataset(file, "/stress", s6, (hsize_t)n, 6));
  PetscCallH5(H5Fclose(file));
  PetscCheck(rename(tmp, path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s", tmp);
  PetscCall(PetscFree(x));
  PetscCall(PetscFree(v));
  PetscCall(PetscFree(rho));
  PetscCall(PetscFree(e));
  PetscCall(PetscFree(s6));
  PetscFunctionReturn(0);
}

static void XdmfItem(FILE *f, PetscInt n, int ncomp, int snap, const char *set)
{
  if (ncomp > 1) fprintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT " %d\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:%s</DataItem>\n", n, ncomp, snap, set);
  else fprintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:%s</DataItem>\n", n, snap, set);
}

/* Rewrites the whole index so that it always lists exactly the snapshots on disk. */
static void XdmfAttribute(FILE *f, PetscInt n, int snap, const char *name, const char *type, int ncomp, const char *set)
{
  fprintf(f, "      <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name, type);
  XdmfItem(f, n, ncomp, snap, set);
  fprintf(f, "      </Attribute>\n");
}

static PetscErrorCode WriteXdmfIndex(const SpamOutput *o, const SpamLayout *l, PetscInt n)
{
  char  path[PETSC_MAX_PATH_LEN];
  FILE *f;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, "snapshots.xmf", path, sizeof path));
  PetscCall(SpamFileBegin(path, &f));
  fprintf(f, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
  for (int s = 0; s < o->nsnap; s++) {
    fprintf(f, "    <Grid Name=\"snap_%05d\" GridType=\"Uniform\">\n      <Time Value=\"%.10g\"/>\n", s, o->snap_times[s]);
    fprintf(f, "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%" PetscInt_FMT "\" NodesPerElement=\"1\"/>\n      <Geometry GeometryType=\"XYZ\">\n", n);
    XdmfItem(f, n, 3, s, "/positions");
    fprintf(f, "      </Geometry>\n");
    XdmfAttribute(f, n, s, "velocity", "Vector", 3, "/velocities");
    XdmfAttribute(f, n, s, "density", "Scalar", 1, "/density");
    if (l->e >= 0) XdmfAttribute(f, n, s, "energy", "Scalar", 1, "/energy");
    if (l->s >= 0) XdmfAttribute(f, n, s, "stress", "Tensor6", 6, "/stress");
    fprintf(f, "    </Grid>\n");
  }
  fprintf(f, "    </Grid>\n  </Domain>\n</Xdmf>\n");
  PetscCall(SpamFileCommit(path, f));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSnapshotWrite(SpamOutput *o, SpamSim *sim, const double *y, double t, const char *tag)
{
  char name[64], path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (o->hdf5) {
    if (o->nsnap == o->snap_cap) {
      o->snap_cap = 2 * o->snap_cap + 16;
      PetscCall(PetscRealloc(sizeof(double) * o->snap_cap, &o->snap_times));
    }
    PetscCall(PetscSNPrintf(name, sizeof name, "snap_%05d.h5", o->nsnap));
    PetscCall(SpamOutputPath(o, name, path, sizeof path));
    PetscCall(WriteHdf5(path, sim, y));
    o->snap_times[o->nsnap] = t;
  }
  if (o->csv) {
    if (tag) PetscCall(PetscSNPrintf(name, sizeof name, "particles_%s.csv", tag));
    else PetscCall(PetscSNPrintf(name, sizeof name, "particles_%05d.csv", o->nsnap));
    PetscCall(SpamOutputPath(o, name, path, sizeof path));
    PetscCall(SpamSnapshotCsvWrite(path, sim, y, t));
  }
  if (o->hdf5) {
    o->nsnap++;
    PetscCall(WriteXdmfIndex(o, &sim->model.layout, sim->n));
  } else o->nsnap++;
  PetscFunctionReturn(0);
}
