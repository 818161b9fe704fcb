/* Options of the output directory: whether an earlier run's files may be replaced, how
 * many snapshots a run may write, and the spacing of the grid fields written with them. */
#include <spam/output_run.h>
#include <spam/errors.h>
#include <spam/grid.h>

/* Snapshots at t = 0, at every interval up to t_end, and one more at the end (a last good
 * state, an interrupted run's state). A tiny interval would otherwise fill the disk with
 * files (measured: 2710 in 40 s); refuse it before anything is written. */
static PetscErrorCode CheckSnapshotCount(const SpamRunOptions *ro, const SpamOutputOptions *o, const char *from)
{
  char         name[PETSC_MAX_PATH_LEN + 128], val[64], why[160];
  const double n = ro->snapshot_interval > 0 ? ceil(ro->t_end / ro->snapshot_interval) + 2.0 : 0.0;

  PetscFunctionBeginUser;
  if (n <= (double)o->snapshot_max) PetscFunctionReturn(0);
  /* snprintf: PETSc's printf writes 16 as "16." */
  if (from) { /* a checkpoint's entry: its value as stored */
    (void)snprintf(val, sizeof val, "%.17g", ro->snapshot_interval);
    (void)snprintf(name, sizeof name, "%s (its -snapshot_interval)", from);
  } else {
    (void)snprintf(val, sizeof val, "%g", ro->snapshot_interval);
    (void)snprintf(name, sizeof name, "-snapshot_interval");
  }
  (void)snprintf(why, sizeof why, "would write %.3g snapshots up to t = %g, more than -snapshot_max = %ld", n, ro->t_end, (long)o->snapshot_max);
  SPAM_BAD_INPUT(name, val, "%s; raise -snapshot_interval (or -snapshot_max)", why);
}

/* The grid fields are written at the snapshot times, in the snapshots' formats: a spacing
 * without snapshots, or without a format, would be given in vain. A tiny spacing would
 * ask for more memory and disk than any run should: the count is named. */
static PetscErrorCode CheckGrid(const SpamGeometry *geo, const SpamRunOptions *ro, const SpamOutputOptions *o)
{
  char   val[128];
  double points;

  PetscFunctionBeginUser;
  if (o->grid_interval == 0.0) PetscFunctionReturn(0);
  PetscCall(SpamOptionText("-grid_interval", o->grid_interval, val, sizeof val));
  if (!(o->grid_interval > 0.0 && isfinite(o->grid_interval))) SPAM_BAD_INPUT("-grid_interval", val, "must be zero (off) or a positive finite grid spacing");
  points = SpamGridPointCount(&geo->box, o->grid_interval);
  if (!isfinite(points)) SPAM_BAD_INPUT("-grid_interval", val, "the box would hold more than 1e308 grid points, at most %.0e; raise the spacing", SPAM_GRID_MAX_POINTS);
  if (!(points <= SPAM_GRID_MAX_POINTS)) SPAM_BAD_INPUT("-grid_interval", val, "the box would hold %.3g grid points, at most %.0e; raise the spacing", points, SPAM_GRID_MAX_POINTS);
  if (!(ro->snapshot_interval > 0)) SPAM_BAD_INPUT("-grid_interval", val, "the grid fields are written at the snapshot times, and -snapshot_interval is 0 (no snapshots)");
  if (!ro->hdf5 && !ro->csv) SPAM_BAD_INPUT("-grid_interval", val, "the grid fields are written in the snapshots' formats, and -snapshot_hdf5 and -snapshot_csv are both off");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputOptionsParse(const SpamSim *sim, const SpamRunOptions *ro, SpamOutputOptions *o)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(o, sizeof *o));
  o->overwrite    = PETSC_FALSE;
  o->snapshot_max = 10000;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Output directory", "spam-ark");
  PetscCall(PetscOptionsBool("-output_overwrite", "Remove the files of an earlier run in -output_dir before starting (default: refuse a directory that holds them)", "README", o->overwrite, &o->overwrite, NULL));
  PetscCall(PetscOptionsInt("-snapshot_max", "Most snapshot files a run may write", "README", o->snapshot_max, &o->snapshot_max, NULL));
  PetscCall(PetscOptionsReal("-grid_interval", "Grid spacing of the smooth-particle fields written at every snapshot time, grid_NNNNN.h5/.csv + grid.xmf (0: none)", "README", o->grid_interval, &o->grid_interval, NULL));
  PetscOptionsEnd();
  if (o->snapshot_max < 1) {
    char val[32];
    (void)snprintf(val, sizeof val, "%" PetscInt_FMT, o->snapshot_max);
    SPAM_BAD_INPUT("-snapshot_max", val, "must be a positive integer");
  }
  PetscCall(SpamOutputOptionsCheckSnapshots(sim, ro, o, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputOptionsCheckSnapshots(const SpamSim *sim, const SpamRunOptions *ro, const SpamOutputOptions *o, const char *from)
{
  PetscFunctionBeginUser;
  PetscCall(CheckSnapshotCount(ro, o, from));
  PetscCall(CheckGrid(&sim->geo, ro, o));
  PetscFunctionReturn(0);
}
