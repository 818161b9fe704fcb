/* The output directory and atomic file writes. */
#include <spam/output.h>
#include <errno.h>
#include <sys/stat.h>

static PetscErrorCode MakeDirs(const char *dir)
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

PetscErrorCode SpamFileBegin(const char *path, FILE **f)
{
  char tmp[PETSC_MAX_PATH_LEN + 8];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s.tmp", path));
  *f = fopen(tmp, "w");
  PetscCheck(*f, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s: %s", tmp, strerror(errno));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFileCommit(const char *path, FILE *f)
{
  char tmp[PETSC_MAX_PATH_LEN + 8];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s.tmp", path));
  PetscCheck(fclose(f) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot finish %s: %s", tmp, strerror(errno));
  PetscCheck(rename(tmp, path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s: %s", tmp, strerror(errno));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputOpen(const char *dir, PetscBool hdf5, PetscBool csv, SpamOutput *o)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(o, sizeof *o));
  PetscCall(PetscStrncpy(o->dir, dir, sizeof o->dir));
  o->hdf5 = hdf5;
  o->csv  = csv;
  PetscCall(MakeDirs(dir));
  PetscCall(SpamOutputPath(o, "timeseries.csv", path, sizeof path));
  PetscCall(SpamFileBegin(path, &o->timeseries));
  fprintf(o->timeseries, "t,step,rejected,rhs_evals,dt,mass,px,py,pz,lx,ly,lz,kinetic,internal,total,entropy_sum,entropy_grid,dS_sum_ratio,dS_grid_ratio,bound_limited,rhs_s,wall_s,torque_sum,bodies,l_body0,l_body1,gauss_singular\n");
  PetscCall(SpamOutputPath(o, "steps.csv", path, sizeof path));
  PetscCall(SpamFileBegin(path, &o->steps));
  fprintf(o->steps, "step,t,dt,rejected,rhs_evals,limit\n");
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputClose(SpamOutput *o)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (o->timeseries) {
    PetscCall(SpamOutputPath(o, "timeseries.csv", path, sizeof path));
    PetscCall(SpamFileCommit(path, o->timeseries));
    o->timeseries = NULL;
  }
  if (o->steps) {
    PetscCall(SpamOutputPath(o, "steps.csv", path, sizeof path));
    PetscCall(SpamFileCommit(path, o->steps));
    o->steps = NULL;
  }
  PetscCall(PetscFree(o->snap_times));
  PetscFunctionReturn(0);
}
