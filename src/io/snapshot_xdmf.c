/* Particle snapshots: one HDF5 file per snapshot (snapshot_hdf5.c), the CSV file
 * (particles_csv.c), and an XDMF index over all of them that ParaView opens as a time
 * series of point clouds. On several ranks every file is one file, whatever the rank
 * count: the HDF5 file written by all ranks together, the CSV, the index and the manifest
 * by rank 0 alone. */
#include "snapshot_hdf5.h"
#include <spam/grid.h>

static void XdmfItem(SpamFile *f, PetscInt n, int ncomp, int snap, const char *set)
{
  if (ncomp > 1) SpamFilePrintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT " %d\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:%s</DataItem>\n", n, ncomp, snap, set);
  else SpamFilePrintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:%s</DataItem>\n", n, snap, set);
}

/* The 64-bit ids, as the point cloud's connectivity and as an attribute. */
static void XdmfIdItem(SpamFile *f, PetscInt n, int snap)
{
  SpamFilePrintf(f, "        <DataItem Dimensions=\"%" PetscInt_FMT "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">snap_%05d.h5:/id</DataItem>\n", n, snap);
}

static void XdmfAttribute(SpamFile *f, PetscInt n, int snap, const char *name, const char *type, int ncomp, const char *set)
{
  SpamFilePrintf(f, "      <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name, type);
  XdmfItem(f, n, ncomp, snap, set);
  SpamFilePrintf(f, "      </Attribute>\n");
}

static void XdmfIdAttribute(SpamFile *f, PetscInt n, int snap)
{
  SpamFilePrintf(f, "      <Attribute Name=\"id\" AttributeType=\"Scalar\" Center=\"Node\">\n");
  XdmfIdItem(f, n, snap);
  SpamFilePrintf(f, "      </Attribute>\n");
}

/* One vertex cell per particle. The connectivity must be written out: ParaView's Xdmf3
 * reader makes no cells from a Polyvertex without it (an empty view), while the legacy
 * XDMF reader numbered the nodes itself. Row r of a snapshot holds the particle of id r
 * (gid order, snapshot_hdf5.c), so /id is that list 0..n-1 and no further dataset is needed. */
static void XdmfTopology(SpamFile *f, PetscInt n, int snap)
{
  SpamFilePrintf(f, "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%" PetscInt_FMT "\" NodesPerElement=\"1\">\n", n);
  XdmfIdItem(f, n, snap);
  SpamFilePrintf(f, "      </Topology>\n");
}

/* Rewrites the whole index so that it always lists exactly the snapshots on disk; n is
 * the global particle count. */
static PetscErrorCode WriteXdmfIndex(const SpamOutput *o, const SpamLayout *l, PetscInt n)
{
  char     path[PETSC_MAX_PATH_LEN];
  SpamFile file, *f = &file;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, "snapshots.xmf", path, sizeof path));
  PetscCall(SpamFileBegin(path, f));
  SpamFilePrintf(f, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Information Name=\"units\" Value=\"%s\"/>\n    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n", SPAM_UNITS_CONVENTION);
  for (int s = 0; s < o->nsnap; s++) {
    SpamFilePrintf(f, "    <Grid Name=\"snap_%05d\" GridType=\"Uniform\">\n      <Time Value=\"%.10g\"/>\n", s, o->snap_times[s]);
    XdmfTopology(f, n, s);
    SpamFilePrintf(f, "      <Geometry GeometryType=\"XYZ\">\n");
    XdmfItem(f, n, 3, s, "/positions");
    SpamFilePrintf(f, "      </Geometry>\n");
    XdmfAttribute(f, n, s, "velocity", "Vector", 3, "/velocities");
    XdmfAttribute(f, n, s, "density", "Scalar", 1, "/density");
    XdmfAttribute(f, n, s, "mass", "Scalar", 1, "/mass");
    XdmfIdAttribute(f, n, s);
    if (l->e >= 0) XdmfAttribute(f, n, s, "energy", "Scalar", 1, "/energy");
    if (l->s >= 0) XdmfAttribute(f, n, s, "stress", "Tensor6", 6, "/stress");
    SpamFilePrintf(f, "    </Grid>\n");
  }
  SpamFilePrintf(f, "    </Grid>\n  </Domain>\n</Xdmf>\n");
  PetscCall(SpamFileCommit(f));
  PetscFunctionReturn(0);
}

/* What rank 0 writes alone: the index, the manifest. */
typedef struct {
  SpamOutput    *o;
  const SpamSim *sim;
} IndexWork;

static PetscErrorCode WriteIndex(void *ctx)
{
  IndexWork *w = ctx;

  PetscFunctionBeginUser;
  PetscCall(WriteXdmfIndex(w->o, &w->sim->model.layout, w->sim->p.nglobal));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteManifest(void *ctx)
{
  IndexWork *w = ctx;

  PetscFunctionBeginUser;
  PetscCall(SpamManifestWrite(w->o));
  PetscFunctionReturn(0);
}

/* A run writes no more than -snapshot_max snapshots: a tiny -snapshot_interval must not
 * fill the disk with files. Parsing refuses an interval that would pass the cap; this is
 * the writer's own guard. Collective on sim->p.comm; every rank keeps the same list of
 * files (the manifest's), rank 0 writes the text files. */
PetscErrorCode SpamSnapshotWrite(SpamOutput *o, SpamSim *sim, const double *y, double t, const char *tag)
{
  char      name[64], path[PETSC_MAX_PATH_LEN];
  IndexWork w = {o, sim};

  PetscFunctionBeginUser;
  PetscCheck(o->opt.snapshot_max <= 0 || o->nsnap < o->opt.snapshot_max, sim->p.comm, PETSC_ERR_FILE_WRITE, "cannot write another snapshot into %s: -snapshot_max = %" PetscInt_FMT " reached", o->dir, o->opt.snapshot_max);
  if (o->hdf5) {
    if (o->nsnap == o->snap_cap) {
      o->snap_cap = 2 * o->snap_cap + 16;
      PetscCall(PetscRealloc(sizeof(double) * o->snap_cap, &o->snap_times));
    }
    PetscCall(PetscSNPrintf(name, sizeof name, "snap_%05d.h5", o->nsnap));
    PetscCall(SpamOutputPath(o, name, path, sizeof path));
    PetscCall(SpamSnapshotHdf5Write(path, sim, y, t, o->step));
    PetscCall(SpamManifestAdd(o, name, "snapshot_h5", t, PETSC_FALSE));
    o->snap_times[o->nsnap] = t;
  }
  if (o->csv) {
    if (tag) PetscCall(PetscSNPrintf(name, sizeof name, "particles_%s.csv", tag));
    else PetscCall(PetscSNPrintf(name, sizeof name, "particles_%05d.csv", o->nsnap));
    PetscCall(SpamOutputPath(o, name, path, sizeof path));
    PetscCall(SpamSnapshotCsvWrite(path, sim, y, t));
    PetscCall(SpamManifestAdd(o, name, tag ? "snapshot_csv_last_good" : "snapshot_csv", t, PETSC_FALSE));
  }
  o->nsnap++;
  if (o->opt.grid_interval > 0) PetscCall(SpamGridWrite(o, sim, y, t)); /* fields on a grid, same time */
  if (o->hdf5) {
    PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, WriteIndex, &w));
    PetscCall(SpamManifestAdd(o, "snapshots.xmf", "xdmf_index", NAN, PETSC_FALSE));
  }
  PetscCall(SpamRunAgreed(sim->p.comm, PETSC_TRUE, WriteManifest, &w));
  PetscFunctionReturn(0);
}
