/* The output directory: taken at the start of a run, released at its end. */
#include <spam/output.h>
#include <spam/errors.h>
#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

PetscErrorCode SpamOutputMakeDirs(const char *dir)
{
  char p[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(p, dir, sizeof p));
  for (char *s = p + 1; *s; s++) {
    if (*s != '/') continue;
    *s = 0;
    if (mkdir(p, 0755) && errno != EEXIST) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create directory %s: %s", p, strerror(errno));
    *s = '/';
  }
  if (mkdir(p, 0755) && errno != EEXIST) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create directory %s: %s", p, strerror(errno));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputPath(const SpamOutput *o, const char *name, char *path, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(path, len, "%s/%s", o->dir, name));
  PetscFunctionReturn(0);
}

/* Locked, then checked for an earlier run: refused (bad input, nothing left behind: a
 * lock file this run created goes again) or cleared. */
static PetscErrorCode TakeDirectory(SpamOutput *o)
{
  PetscBool      created;
  char           earlier[256];
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputLock(o, &created));
  ierr = SpamOutputFindEarlier(o, earlier, sizeof earlier);
  if (!ierr && earlier[0] && !o->opt.overwrite) {
    if (created) SpamOutputUnlock(o);
    else {
      (void)close(o->lock_fd);
      o->lock_fd = -1;
    }
    SPAM_BAD_INPUT("-output_dir", o->dir, "holds %s of an earlier run; pass -output_overwrite to replace that run's files, or choose another -output_dir", earlier);
  }
  PetscCall(ierr);
  PetscCall(SpamOutputRemoveEarlier(o, o->opt.overwrite));
  o->owned = PETSC_TRUE;
  PetscCall(SpamOutputLockWrite(o));
  PetscCall(SpamManifestWrite(o));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputInit(const char *dir, PetscBool hdf5, PetscBool csv, const SpamOutputOptions *opt, SpamOutput *o)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(o, sizeof *o));
  o->lock_fd = -1;
  PetscCall(PetscStrncpy(o->dir, dir, sizeof o->dir));
  PetscCall(PetscStrncpy(o->status, "running", sizeof o->status));
  o->hdf5 = hdf5;
  o->csv  = csv;
  o->opt  = *opt;
  PetscCall(SpamOutputMakeDirs(dir));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputOpen(const char *dir, PetscBool hdf5, PetscBool csv, const SpamOutputOptions *opt, SpamOutput *o)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(SpamOutputInit(dir, hdf5, csv, opt, o));
  PetscCall(TakeDirectory(o));
  PetscCall(SpamOutputPath(o, "timeseries.csv", path, sizeof path));
  PetscCall(SpamFileBegin(path, &o->timeseries));
  SpamFilePrintf(&o->timeseries, "t,step,rejected,rhs_evals,dt,mass,px,py,pz,lx,ly,lz,kinetic,internal,total,entropy_sum,entropy_grid,dS_sum_ratio,dS_grid_ratio,bound_limited,rhs_s,wall_s,torque_sum,bodies,l_body0,l_body1,gauss_singular,potential,scheme_energy%s\n", opt->timeseries_more);
  PetscCall(SpamFileCheck(&o->timeseries));
  PetscCall(SpamOutputPath(o, "steps.csv", path, sizeof path));
  PetscCall(SpamFileBegin(path, &o->steps));
  SpamFilePrintf(&o->steps, "step,t,dt,rejected,rhs_evals,limit\n");
  PetscCall(SpamFileCheck(&o->steps));
  PetscFunctionReturn(0);
}

static PetscErrorCode CommitListed(SpamOutput *o, SpamFile *f, const char *name, const char *kind)
{
  PetscFunctionBeginUser;
  if (!f->f) PetscFunctionReturn(0);
  PetscCall(SpamFileCommit(f));
  PetscCall(SpamManifestAdd(o, name, kind, NAN, PETSC_FALSE));
  PetscFunctionReturn(0);
}

static void FreeLists(SpamOutput *o)
{
  (void)PetscFree(o->snap_times);
  (void)PetscFree(o->grid.times);
  o->grid.n = o->grid.cap = 0;
  (void)PetscFree(o->files);
  o->nfiles = o->files_cap = o->snap_cap = 0;
}

void SpamOutputRelease(SpamOutput *o)
{
  FreeLists(o);
}

PetscErrorCode SpamOutputClose(SpamOutput *o, const char *status)
{
  PetscFunctionBeginUser;
  PetscCall(CommitListed(o, &o->timeseries, "timeseries.csv", "timeseries"));
  PetscCall(CommitListed(o, &o->steps, "steps.csv", "steps"));
  PetscCall(PetscStrncpy(o->status, status, sizeof o->status));
  PetscCall(SpamManifestWrite(o));
  SpamOutputUnlock(o);
  FreeLists(o);
  PetscFunctionReturn(0);
}

/* Quiet: the failure that led here has been reported, and a second one (the disk is still
 * full, say) must not add lines. */
void SpamOutputAbandon(SpamOutput *o)
{
  if (PetscPushErrorHandler(PetscIgnoreErrorHandler, NULL)) return;
  SpamFileDiscard(&o->timeseries);
  SpamFileDiscard(&o->steps);
  if (o->owned) {
    (void)PetscStrncpy(o->status, "failed", sizeof o->status);
    (void)SpamManifestWrite(o);
  }
  SpamOutputUnlock(o);
  FreeLists(o);
  (void)PetscPopErrorHandler();
}
