/* The output series in a checkpoint, and a restart's reopening of the directory. A
 * checkpoint carries the series as they stood when it was written: the text of
 * timeseries.csv and steps.csv (which a run holds in temporaries until it ends, so a killed
 * run leaves none), the XDMF indexes, the snapshot and grid times and the manifest's list.
 * A restart puts exactly that back and removes what was written after, so the continued
 * series have neither a duplicate nor a missing row whatever happened after the checkpoint
 * (an interruption's extra row, a kill -9, a later checkpoint's rows). */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include <spam/output_resume.h>
#include <spam/errors.h>
#include <limits.h>

/* Manifest entries one a line: name, kind, time (%.17g or nan), outside (0 or 1), tab
 * separated (names hold no tab: output_clean.c's PlainName and the option checks). */
static PetscErrorCode SaveEntries(const SpamOutput *o, SpamCkFile *c)
{
  size_t cap = 64, len = 0;
  char  *s;

  PetscFunctionBeginUser;
  for (int k = 0; k < o->nfiles; k++) cap += strlen(o->files[k].name) + strlen(o->files[k].kind) + 48;
  PetscCall(PetscMalloc1(cap, &s));
  s[0] = 0;
  for (int k = 0; k < o->nfiles; k++) len += (size_t)snprintf(s + len, cap - len, "%s\t%s\t%.17g\t%d\n", o->files[k].name, o->files[k].kind, o->files[k].t, (int)o->files[k].outside);
  PetscCall(SpamCkPutText(c, "out_files", s, len));
  PetscCall(PetscFree(s));
  PetscFunctionReturn(0);
}

static PetscErrorCode SaveFile(const SpamOutput *o, const char *name, const char *entry, SpamCkFile *c)
{
  char   path[PETSC_MAX_PATH_LEN], *buf;
  size_t len;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, name, path, sizeof path));
  PetscCall(SpamReadWholeFile(path, &buf, &len));
  if (buf) PetscCall(SpamCkPutText(c, entry, buf, len));
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

static PetscErrorCode SaveSeries(SpamFile *f, const char *entry, SpamCkFile *c)
{
  char  *buf;
  size_t len;

  PetscFunctionBeginUser;
  PetscCall(SpamFileContents(f, &buf, &len));
  PetscCall(SpamCkPutText(c, entry, buf, len));
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputSave(SpamOutput *o, SpamCkFile *c)
{
  PetscFunctionBeginUser;
  PetscCall(SaveSeries(&o->timeseries, "out_timeseries", c));
  PetscCall(SaveSeries(&o->steps, "out_steps", c));
  PetscCall(SaveFile(o, "snapshots.xmf", "out_snapshots_xmf", c));
  PetscCall(SaveFile(o, "grid.xmf", "out_grid_xmf", c));
  PetscCall(SaveEntries(o, c));
  PetscCall(SpamCkPutLong(c, "out_nsnap", o->nsnap));
  PetscCall(SpamCkPutLong(c, "out_step", o->step));
  PetscCall(SpamCkPutReal(c, "out_snap_times", o->hdf5 ? (size_t)o->nsnap : 0, o->snap_times));
  PetscCall(SpamCkPutReal(c, "out_grid_times", (size_t)o->grid.n, o->grid.times));
  PetscFunctionReturn(0);
}

/* A name or kind holds no control byte (the manifest's lines, the cleaner's reading). */
static PetscBool Printable(const char *s)
{
  for (; *s; s++)
    if ((unsigned char)*s < 0x20 || *s == 0x7f) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* A kind is a word of lower-case letters, digits and '_' (the manifest prints it as is). */
static PetscBool KindWord(const char *s)
{
  if (!*s) return PETSC_FALSE;
  for (; *s; s++)
    if (!((*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9') || *s == '_')) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* One line of the list cut in place into its fields, each as SaveEntries writes it; NULL
 * if it is one, else what is wrong. */
static const char *ParseEntry(char *line, SpamOutputEntry *e)
{
  char *name = line, *kind = strchr(name, '\t'), *t = kind ? strchr(kind + 1, '\t') : NULL, *out = t ? strchr(t + 1, '\t') : NULL, *end;

  if (!out || strchr(out + 1, '\t')) return "a line without exactly four tab-separated fields";
  *kind++ = 0;
  *t++    = 0;
  *out++  = 0;
  if (strcmp(out, "0") && strcmp(out, "1")) return "a line whose fourth field (outside) is neither 0 nor 1";
  e->outside = (PetscBool)(out[0] == '1');
  if (!name[0] || strlen(name) >= sizeof e->name || !Printable(name)) return "a file name that is empty, too long or holds a control byte";
  /* a file of the directory is a plain name: no path, no hidden name (output_clean.c) */
  if (!e->outside && (name[0] == '.' || strchr(name, '/'))) return "a file of the directory named by a path or a hidden name";
  if (strlen(kind) >= sizeof e->kind || !KindWord(kind)) return "a kind that is not a word of a-z, 0-9 and '_'";
  e->t = strcmp(t, "nan") ? strtod(t, &end) : NAN;
  if (strcmp(t, "nan") && (end == t || *end || !isfinite(e->t))) return "a time that is neither a finite number nor nan";
  (void)snprintf(e->name, sizeof e->name, "%s", name);
  (void)snprintf(e->kind, sizeof e->kind, "%s", kind);
  return NULL;
}

/* The list of files, each line checked (o: NULL to check only). */
static PetscErrorCode RestoreEntries(const SpamCkFile *c, SpamOutput *o)
{
  const char *s, *why = NULL;
  size_t      len;
  char       *copy, *line, *save = NULL;
  int         k = 0;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetText(c, "out_files", &s, &len));
  if (strlen(s) != len) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry 'out_files' (the list of output files) holds a NUL byte", c->path);
  PetscCall(PetscStrallocpy(s, &copy));
  for (line = strtok_r(copy, "\n", &save); line && !why; line = strtok_r(NULL, "\n", &save), k++) {
    SpamOutputEntry e;
    why = ParseEntry(line, &e);
    if (!why && o) PetscCall(SpamManifestAdd(o, e.name, e.kind, e.t, e.outside));
  }
  PetscCall(PetscFree(copy));
  if (why) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry 'out_files' (the list of output files), line %d: %s", c->path, k, why);
  PetscFunctionReturn(0);
}

/* A real entry of any length (the times: as many as were written). */
static PetscErrorCode GetTimes(const SpamCkFile *c, const char *name, const double **v, size_t *n)
{
  PetscFunctionBeginUser;
  for (int k = 0; k < c->n; k++)
    if (!strcmp(c->e[k].name, name) && c->e[k].kind == SPAM_CK_REAL) {
      *v = (const double *)c->e[k].data;
      *n = c->e[k].n;
      PetscFunctionReturn(0);
    }
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: no entry '%s'", c->path, name);
}

static PetscErrorCode RestoreTimes(const SpamCkFile *c, const char *entry, double **times, int *n, int *cap)
{
  const double *v   = NULL;
  size_t        len = 0;

  PetscFunctionBeginUser;
  PetscCall(GetTimes(c, entry, &v, &len));
  *n   = (int)len;
  *cap = (int)len + 16;
  PetscCall(PetscMalloc1((size_t)*cap, times));
  if (len) PetscCall(PetscArraycpy(*times, v, len));
  PetscFunctionReturn(0);
}

/* A file of the directory written back as the checkpoint holds it (an XDMF index). */
static PetscErrorCode RestoreFile(SpamOutput *o, const SpamCkFile *c, const char *entry, const char *name)
{
  char        path[PETSC_MAX_PATH_LEN];
  const char *s;
  size_t      len;
  SpamFile    f;

  PetscFunctionBeginUser;
  if (!SpamCkHas(c, entry)) PetscFunctionReturn(0);
  PetscCall(SpamCkGetText(c, entry, &s, &len));
  PetscCall(SpamOutputPath(o, name, path, sizeof path));
  PetscCall(SpamFileBegin(path, &f));
  SpamFilePrintf(&f, "%s", s);
  PetscCall(SpamFileCommit(&f));
  PetscFunctionReturn(0);
}

static PetscErrorCode RestoreSeries(SpamOutput *o, const SpamCkFile *c, const char *entry, const char *name, SpamFile *f)
{
  char        path[PETSC_MAX_PATH_LEN];
  const char *s;
  size_t      len;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetText(c, entry, &s, &len));
  PetscCall(SpamOutputPath(o, name, path, sizeof path));
  PetscCall(SpamFileBegin(path, f));
  SpamFilePrintf(f, "%s", s);
  PetscCall(SpamFileCheck(f));
  PetscFunctionReturn(0);
}

/* Times of a series: finite, from 0 to the checkpoint's time t, in order. */
static PetscErrorCode CheckTimes(const SpamCkFile *c, const char *entry, double t, size_t *n)
{
  const double *v = NULL;

  PetscFunctionBeginUser;
  PetscCall(GetTimes(c, entry, &v, n));
  if (*n > INT_MAX / 2) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry '%s' holds %zu times, more than a run writes", c->path, entry, *n);
  for (size_t k = 0; k < *n; k++)
    if (!(v[k] >= 0 && v[k] <= t && (k == 0 || v[k] >= v[k - 1]))) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry '%s'[%zu] = %.17g: the times must run in order from 0 to the checkpoint's time %.17g", c->path, entry, k, v[k], t);
  PetscFunctionReturn(0);
}

/* A text entry that must be there, or may be (optional). */
static PetscErrorCode CheckText(const SpamCkFile *c, const char *entry, PetscBool optional)
{
  const char *s;

  PetscFunctionBeginUser;
  if (!optional || SpamCkHas(c, entry)) PetscCall(SpamCkGetText(c, entry, &s, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputResumeCheck(const SpamCkFile *c, PetscBool hdf5, const SpamOutputOptions *opt, double t)
{
  long   nsnap, step;
  size_t ntimes, ngrid;

  PetscFunctionBeginUser;
  PetscCall(RestoreEntries(c, NULL));
  PetscCall(SpamCkGetLong(c, "out_nsnap", &nsnap));
  PetscCall(SpamCkGetLong(c, "out_step", &step));
  if (nsnap < 0 || nsnap > (long)opt->snapshot_max) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry 'out_nsnap' = %ld: the snapshots written must number from 0 to -snapshot_max = %ld", c->path, nsnap, (long)opt->snapshot_max);
  if (step < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry 'out_step' = %ld: a step count is zero or positive", c->path, step);
  PetscCall(CheckTimes(c, "out_snap_times", t, &ntimes));
  PetscCall(CheckTimes(c, "out_grid_times", t, &ngrid));
  /* HDF5 snapshots keep a time each (the XDMF index lists them); a run without them keeps none */
  if (ntimes != (size_t)nsnap && (ntimes || hdf5)) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry 'out_snap_times' holds %zu times for its %ld snapshots (out_nsnap)%s", c->path, ntimes, nsnap, ntimes ? "" : ": it was written without -snapshot_hdf5, so a restart continues without it");
  PetscCall(CheckText(c, "out_timeseries", PETSC_FALSE));
  PetscCall(CheckText(c, "out_steps", PETSC_FALSE));
  PetscCall(CheckText(c, "out_snapshots_xmf", PETSC_TRUE));
  PetscCall(CheckText(c, "out_grid_xmf", PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputResumeLists(const SpamCkFile *c, SpamOutput *o)
{
  long nsnap, step;
  int  ns; /* snapshot times: nsnap with HDF5 snapshots, 0 without */

  PetscFunctionBeginUser;
  PetscCall(RestoreEntries(c, o));
  PetscCall(SpamCkGetLong(c, "out_nsnap", &nsnap));
  PetscCall(SpamCkGetLong(c, "out_step", &step));
  o->nsnap = (int)nsnap;
  o->step  = step;
  PetscCall(RestoreTimes(c, "out_snap_times", &o->snap_times, &ns, &o->snap_cap));
  PetscCall(RestoreTimes(c, "out_grid_times", &o->grid.times, &o->grid.n, &o->grid.cap));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamOutputResume(const char *dir, PetscBool hdf5, PetscBool csv, const SpamOutputOptions *opt, const SpamCkFile *c, SpamOutput *o)
{
  PetscBool created;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputInit(dir, hdf5, csv, opt, o));
  PetscCall(SpamOutputLock(o, &created));
  o->owned = PETSC_TRUE;
  PetscCall(SpamOutputResumeLists(c, o));
  PetscCall(SpamOutputRemoveUnlisted(o));
  PetscCall(RestoreFile(o, c, "out_snapshots_xmf", "snapshots.xmf"));
  PetscCall(RestoreFile(o, c, "out_grid_xmf", "grid.xmf"));
  PetscCall(SpamManifestAdd(o, SPAM_CHECKPOINT_FILE, "checkpoint", NAN, PETSC_FALSE));
  PetscCall(SpamOutputLockWrite(o));
  PetscCall(SpamManifestWrite(o));
  PetscCall(RestoreSeries(o, c, "out_timeseries", "timeseries.csv", &o->timeseries));
  PetscCall(RestoreSeries(o, c, "out_steps", "steps.csv", &o->steps));
  PetscFunctionReturn(0);
}
