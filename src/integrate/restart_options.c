/* Which options a restart may change. A checkpoint continues one run: every option that
 * shapes the trajectory (scene, model, kernel, method, tolerances, bounds, threads: their
 * sums round differently) must be what the checkpoint recorded. What only says where,
 * how often and how much is written, when the run ends, and when to checkpoint may differ:
 * a user extends a run or asks for denser outputs. */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include <spam/checkpoint.h>

static const char *const FreeOptions[] = {
  "output_dir", "output_interval", "snapshot_interval", "snapshot_hdf5", "snapshot_csv", "snapshot_max", "output_overwrite", "monitor", "quiet",
  "grid_interval", "initial_csv", "final_csv", "diag_entropy", "diag_grid_spacing", "ts_max_time", "ts_max_steps", "checkpoint_interval",
  "checkpoint_wall", "restart", "options_file", "ts_view", "ts_adapt_monitor", "sundials_stats", "log_view", "options_left", "help"};

PetscBool SpamRestartOptionFree(const char *name)
{
  for (size_t k = 0; k < sizeof FreeOptions / sizeof FreeOptions[0]; k++)
    if (!strcmp(name, FreeOptions[k])) return PETSC_TRUE;
  /* -ts_monitor and its variants (-ts_monitor_solution, ...) only print */
  return (PetscBool)!strncmp(name, "ts_monitor", 10);
}

/* An option name is '-' then a letter; "-1" or "-inf" is a value. */
static PetscBool IsName(const char *tok)
{
  return (PetscBool)(tok[0] == '-' && ((tok[1] >= 'a' && tok[1] <= 'z') || (tok[1] >= 'A' && tok[1] <= 'Z')) && strcmp(tok, "-inf") && strcmp(tok, "-nan"));
}

typedef struct {
  char       **name;
  const char **value;
  int    n;
} OptionList;

/* Splits PetscOptionsGetAll's "-a 1 -b -c x" into (name, value) pairs, free options
 * dropped; s is cut in place. */
static PetscErrorCode Split(char *s, OptionList *l)
{
  char *save = NULL, *tok;
  int   cap  = 0;

  PetscFunctionBeginUser;
  for (char *p = s; *p; p++) cap += *p == ' ';
  cap += 2;
  PetscCall(PetscMalloc2(cap, &l->name, cap, &l->value));
  l->n = 0;
  for (tok = strtok_r(s, " ", &save); tok;) {
    char *next = strtok_r(NULL, " ", &save);
    if (!IsName(tok)) { /* a stray value: compared as its own entry */
      l->name[l->n]    = tok;
      l->value[l->n++] = "";
      tok              = next;
      continue;
    }
    l->name[l->n]  = tok + 1;
    l->value[l->n] = "";
    if (next && !IsName(next)) {
      l->value[l->n] = next;
      next           = strtok_r(NULL, " ", &save);
    }
    if (!SpamRestartOptionFree(l->name[l->n])) l->n++;
    tok = next;
  }
  PetscFunctionReturn(0);
}

static const char *Lookup(const OptionList *l, const char *name)
{
  for (int k = l->n - 1; k >= 0; k--) /* the last given wins, as in PETSc */
    if (!strcmp(l->name[k], name)) return l->value[k];
  return NULL;
}

/* The first name of a that b lacks or gives another value. */
static void FirstDifference(const OptionList *a, const OptionList *b, const char **name, const char **va, const char **vb)
{
  for (int k = 0; k < a->n && !*name; k++) {
    const char *x = Lookup(a, a->name[k]), *y = Lookup(b, a->name[k]);
    if (!y || strcmp(x, y)) {
      *name = a->name[k];
      *va   = x;
      *vb   = y;
    }
  }
}

PetscErrorCode SpamRestartOptionsDiffer(const char *saved, const char *now, char *name, size_t nlen, char *was, char *is, size_t vlen)
{
  char       *s, *t;
  OptionList  a, b;
  const char *n = NULL, *va = NULL, *vb = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscStrallocpy(saved, &s));
  PetscCall(PetscStrallocpy(now, &t));
  PetscCall(Split(s, &a));
  PetscCall(Split(t, &b));
  FirstDifference(&a, &b, &n, &va, &vb);
  if (!n) FirstDifference(&b, &a, &n, &vb, &va);
  (void)snprintf(name, nlen, "%s", n ? n : "");
  (void)snprintf(was, vlen, "%s", !n ? "" : va ? (va[0] ? va : "(given, no value)") : "(not given)");
  (void)snprintf(is, vlen, "%s", !n ? "" : vb ? (vb[0] ? vb : "(given, no value)") : "(not given)");
  PetscCall(PetscFree2(a.name, a.value));
  PetscCall(PetscFree2(b.name, b.value));
  PetscCall(PetscFree(s));
  PetscCall(PetscFree(t));
  PetscFunctionReturn(0);
}
