/* Files of an earlier run in the output directory: found (to refuse them) or removed (with
 * -output_overwrite), so that no stale snapshot or summary sits beside a new run's files.
 * An earlier run's files are those its manifest.json lists and every name spam-ark writes;
 * stale temporaries (NAME.tmp, NAME.PID.tmp) are never a result and always go. */
#define _DEFAULT_SOURCE /* open flags, flock, lstat, gethostname: POSIX, not C11 */
#include <spam/output.h>
#include <dirent.h>
#include <errno.h>
#include <unistd.h>

/* s is at least five digits followed by exactly suffix. */
static PetscBool DigitsThen(const char *s, const char *suffix)
{
  size_t n = strspn(s, "0123456789");
  return (PetscBool)(n >= 5 && !strcmp(s + n, suffix));
}

static PetscBool IsRunFile(const char *name)
{
  static const char *fixed[] = {"timeseries.csv", "steps.csv", "summary.json", "snapshots.xmf", "manifest.json", "particles_last_good.csv", "grid.xmf", "checkpoint.h5"};

  for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++)
    if (!strcmp(name, fixed[k])) return PETSC_TRUE;
  if (!strncmp(name, "snap_", 5) && DigitsThen(name + 5, ".h5")) return PETSC_TRUE;
  if (!strncmp(name, "particles_", 10) && DigitsThen(name + 10, ".csv")) return PETSC_TRUE;
  if (!strncmp(name, "grid_", 5) && (DigitsThen(name + 5, ".h5") || DigitsThen(name + 5, ".csv"))) return PETSC_TRUE;
  return PETSC_FALSE;
}

static PetscBool IsTemporary(const char *name)
{
  char   base[256];
  size_t n = strlen(name);

  if (n < 5 || n >= sizeof base || strcmp(name + n - 4, ".tmp")) return PETSC_FALSE;
  memcpy(base, name, n - 4);
  base[n - 4] = 0;
  if (IsRunFile(base)) return PETSC_TRUE;
  {
    char *dot = strrchr(base, '.');
    if (!dot || !dot[1] || strspn(dot + 1, "0123456789") != strlen(dot + 1)) return PETSC_FALSE;
    *dot = 0;
  }
  return IsRunFile(base);
}

/* A manifest entry names a file of the directory only: no path, no hidden name. */
static PetscBool PlainName(const char *name)
{
  return (PetscBool)(name[0] && name[0] != '.' && !strchr(name, '/'));
}

static PetscErrorCode Remove(const SpamOutput *o, const char *name)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, name, path, sizeof path));
  PetscCheck(!unlink(path) || errno == ENOENT, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot remove %s of an earlier run: %s", path, strerror(errno));
  PetscFunctionReturn(0);
}

/* The "name" entries of the earlier manifest (written by SpamManifestWrite: one entry a
 * line, names without quotes or backslashes). Unreadable or odd lines are skipped: the
 * name patterns still catch every file spam-ark writes. */
static PetscErrorCode RemoveListed(const SpamOutput *o)
{
  char  path[PETSC_MAX_PATH_LEN], line[PETSC_MAX_PATH_LEN + 128];
  FILE *f;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, "manifest.json", path, sizeof path));
  if (!(f = fopen(path, "r"))) PetscFunctionReturn(0);
  while (fgets(line, sizeof line, f)) {
    char *p = strstr(line, "\"name\": \""), *q;
    if (!p || !(q = strchr(p += 9, '"'))) continue;
    *q = 0;
    if (PlainName(p) && strcmp(p, "manifest.json")) {
      PetscErrorCode ierr = Remove(o, p);
      if (ierr) (void)fclose(f);
      PetscCall(ierr);
    }
  }
  (void)fclose(f);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputFindEarlier(const SpamOutput *o, char *name, size_t len)
{
  DIR           *d;
  struct dirent *e;

  PetscFunctionBeginUser;
  name[0] = 0;
  PetscCheck(d = opendir(o->dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot read directory %s: %s", o->dir, strerror(errno));
  while ((e = readdir(d))) {
    if (!IsRunFile(e->d_name)) continue;
    /* The manifest first: it says best that a whole run is there. */
    if (!name[0] || !strcmp(e->d_name, "manifest.json")) (void)snprintf(name, len, "%s", e->d_name);
  }
  (void)closedir(d);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputRemoveEarlier(const SpamOutput *o, PetscBool all)
{
  DIR           *d;
  struct dirent *e;
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  if (all) PetscCall(RemoveListed(o));
  PetscCheck(d = opendir(o->dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot read directory %s: %s", o->dir, strerror(errno));
  while (!ierr && (e = readdir(d)))
    if (IsTemporary(e->d_name) || (all && IsRunFile(e->d_name) && strcmp(e->d_name, "manifest.json"))) ierr = Remove(o, e->d_name);
  (void)closedir(d);
  PetscCall(ierr);
  /* The manifest last: should removal stop half-way, it still lists what is left. */
  if (all) PetscCall(Remove(o, "manifest.json"));
  PetscFunctionReturn(0);
}

/* A restart: every file of the run that the checkpoint's manifest does not list was
 * written after the checkpoint (a snapshot, the summary) and goes, with stale temporaries;
 * the checkpoint itself stays. */
PetscErrorCode SpamOutputRemoveUnlisted(const SpamOutput *o)
{
  DIR           *d;
  struct dirent *e;
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCheck(d = opendir(o->dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot read directory %s: %s", o->dir, strerror(errno));
  while (!ierr && (e = readdir(d))) {
    PetscBool listed = (PetscBool)(!strcmp(e->d_name, "checkpoint.h5") || !strcmp(e->d_name, "manifest.json"));
    for (int k = 0; k < o->nfiles && !listed; k++) listed = (PetscBool)(!o->files[k].outside && !strcmp(o->files[k].name, e->d_name));
    if (IsTemporary(e->d_name) || (IsRunFile(e->d_name) && !listed)) ierr = Remove(o, e->d_name);
  }
  (void)closedir(d);
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
