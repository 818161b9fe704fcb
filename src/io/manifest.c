/* manifest.json: what the run is (program, version, options), how it stands (status) and
 * every file it wrote. Scripts read it instead of globbing the directory, so they never
 * pick up a file of another run; it is rewritten whole (temporary + rename) whenever a file
 * is added and at the end, so a reader always sees a complete list. */
#include <spam/output.h>
#include <spam/version.h>

/* One entry a line: the earlier-run cleaner reads names back line by line. */
static void Entry(SpamFile *f, const SpamOutputEntry *e, PetscBool last)
{
  SpamFilePrintf(f, "    {%s: ", e->outside ? "\"path\"" : "\"name\"");
  SpamFileJsonString(f, e->name);
  SpamFilePrintf(f, ", \"kind\": \"%s\"", e->kind);
  if (isfinite(e->t)) SpamFilePrintf(f, ", \"t\": %.17g", e->t);
  SpamFilePrintf(f, "}%s\n", last ? "" : ",");
}

PetscErrorCode SpamManifestWrite(SpamOutput *o)
{
  char     path[PETSC_MAX_PATH_LEN], *all = NULL;
  SpamFile f;

  PetscFunctionBeginUser;
  PetscCall(SpamOutputPath(o, "manifest.json", path, sizeof path));
  PetscCall(SpamFileBegin(path, &f));
  PetscCall(PetscOptionsGetAll(NULL, &all));
  for (size_t n = all ? strlen(all) : 0; n > 0 && all[n - 1] == ' '; n--) all[n - 1] = 0;
  SpamFilePrintf(&f, "{\n  \"program\": \"spam-ark\",\n  \"version\": \"%s\",\n  \"status\": \"%s\",\n  \"run\": ", SPAM_VERSION, o->status);
  SpamFileJsonString(&f, o->lock_info);
  SpamFilePrintf(&f, ",\n  \"options\": ");
  SpamFileJsonString(&f, all ? all : "");
  SpamFilePrintf(&f, ",\n  \"files\": [\n");
  for (int k = 0; k < o->nfiles; k++) Entry(&f, &o->files[k], (PetscBool)(k == o->nfiles - 1));
  SpamFilePrintf(&f, "  ]\n}\n");
  PetscCall(PetscFree(all));
  PetscCall(SpamFileCommit(&f));
  PetscFunctionReturn(0);
}

/* Records a file (SpamManifestWrite then lists it). A file rewritten under the same name
 * (the XDMF index, a last_good snapshot) keeps its one entry; its time is the latest. */
PetscErrorCode SpamManifestAdd(SpamOutput *o, const char *name, const char *kind, double t, PetscBool outside)
{
  SpamOutputEntry *e = NULL;

  PetscFunctionBeginUser;
  for (int k = 0; k < o->nfiles && !e; k++)
    if (!strcmp(o->files[k].name, name)) e = &o->files[k];
  if (!e) {
    if (o->nfiles == o->files_cap) {
      o->files_cap = 2 * o->files_cap + 16;
      PetscCall(PetscRealloc(sizeof(SpamOutputEntry) * (size_t)o->files_cap, &o->files));
    }
    e = &o->files[o->nfiles++];
    PetscCall(PetscStrncpy(e->name, name, sizeof e->name));
  }
  PetscCall(PetscStrncpy(e->kind, kind, sizeof e->kind));
  e->t       = t;
  e->outside = outside;
  PetscFunctionReturn(0);
}
