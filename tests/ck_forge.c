/* ck_forge IN OUT EDIT... [-- OUT EDIT...]...: a checkpoint edited as an attacker would, then written through the
 * library's own writer so that its entry count and checksum match the forged contents (a
 * test tool of the fuzz corpus, tests/run_fuzz.py: a restart must then refuse the forgery
 * by its values, not by its checksum). The edits, applied in order:
 *   set NAME K VALUE    element K of a real or integer entry (strtod / strtoll: nan, inf)
 *   real NAME V,V,...   the entry replaced by these reals ("" : none)
 *   int NAME V,V,...    the entry replaced by these integers
 *   text NAME STRING    the entry replaced by this text
 *   drop NAME           the entry removed
 *   poke NAME OFF BYTE  byte OFF of a text entry set to BYTE (0-255)
 *   fill NAME OFF LEN BYTE  bytes OFF to OFF + LEN - 1 of a text entry set to BYTE
 *   status V            the status field of run_result (the result as its bytes)
 *   unterminated X      run_result's reason filled with 'A' to its last byte (no NUL)
 * Each group after "--" is another forgery of IN (one start for a whole corpus: a start
 * under the sanitizers takes seconds). Exit 0 written, 1 on a failure (PETSc's message on
 * stderr). One rank's checkpoints only. */
#include <spam/checkpoint_file.h>
#include <spam/run.h>
#include <stddef.h>
#include <stdlib.h>

static PetscErrorCode Find(const SpamCkFile *c, const char *name, SpamCkEntry **e)
{
  PetscFunctionBeginUser;
  *e = NULL;
  for (int k = 0; k < c->n; k++)
    if (!strcmp(c->e[k].name, name)) *e = &c->e[k];
  PetscCheck(*e, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "ck_forge: no entry '%s' to edit", name);
  PetscFunctionReturn(0);
}

static PetscErrorCode Drop(SpamCkFile *c, const char *name)
{
  SpamCkEntry *e;

  PetscFunctionBeginUser;
  PetscCall(Find(c, name, &e));
  PetscCall(PetscFree(e->data));
  /* the rest moves down one: the entries stay sorted by name */
  memmove(e, e + 1, sizeof *e * (size_t)(c->n - 1 - (e - c->e)));
  c->n--;
  PetscFunctionReturn(0);
}

/* A comma-separated list of numbers (reals or integers) as a new entry. */
static PetscErrorCode PutList(SpamCkFile *c, const char *name, const char *list, PetscBool real)
{
  size_t  n = 0, cap = 1;
  double *r;
  int64_t *i;

  PetscFunctionBeginUser;
  for (const char *p = list; *p; p++) cap += *p == ',';
  PetscCall(PetscMalloc2(cap, &r, cap, &i));
  for (const char *p = list; *p;) {
    char *end;
    if (real) r[n++] = strtod(p, &end);
    else i[n++] = strtoll(p, &end, 10);
    PetscCheck(end != p && (*end == ',' || !*end), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "ck_forge: '%s' is not a list of numbers", list);
    p = *end ? end + 1 : end;
  }
  if (real) PetscCall(SpamCkPutReal(c, name, n, r));
  else PetscCall(SpamCkPutInt(c, name, n, i));
  PetscCall(PetscFree2(r, i));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetOne(SpamCkFile *c, const char *name, const char *k, const char *value)
{
  SpamCkEntry *e;
  const size_t at = (size_t)strtoull(k, NULL, 10);

  PetscFunctionBeginUser;
  PetscCall(Find(c, name, &e));
  PetscCheck(e->kind != SPAM_CK_TEXT && at < e->n, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "ck_forge: entry '%s' has no number %zu", name, at);
  if (e->kind == SPAM_CK_REAL) ((double *)e->data)[at] = strtod(value, NULL);
  else ((int64_t *)e->data)[at] = strtoll(value, NULL, 10);
  PetscFunctionReturn(0);
}

static PetscErrorCode Poke(SpamCkFile *c, const char *name, size_t off, int byte)
{
  SpamCkEntry *e;

  PetscFunctionBeginUser;
  PetscCall(Find(c, name, &e));
  PetscCheck(e->kind == SPAM_CK_TEXT && off < e->n, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "ck_forge: entry '%s' has no byte %zu", name, off);
  ((unsigned char *)e->data)[off] = (unsigned char)byte;
  PetscFunctionReturn(0);
}

/* One edit from argv[0..]; *used: the words it took. */
static PetscErrorCode Edit(SpamCkFile *c, int argc, char **argv, int *used)
{
  const char *op = argv[0];
  const int   need = !strcmp(op, "drop") || !strcmp(op, "status") || !strcmp(op, "unterminated") ? 2 : !strcmp(op, "set") || !strcmp(op, "poke") ? 4 : !strcmp(op, "fill") ? 5 : 3;

  PetscFunctionBeginUser;
  PetscCheck(argc >= need, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "ck_forge: %s needs %d arguments", op, need - 1);
  *used = need;
  if (!strcmp(op, "set")) PetscCall(SetOne(c, argv[1], argv[2], argv[3]));
  else if (!strcmp(op, "real") || !strcmp(op, "int")) PetscCall(PutList(c, argv[1], argv[2], (PetscBool)(op[0] == 'r')));
  else if (!strcmp(op, "text")) PetscCall(SpamCkPutText(c, argv[1], argv[2], strlen(argv[2])));
  else if (!strcmp(op, "drop")) PetscCall(Drop(c, argv[1]));
  else if (!strcmp(op, "poke")) PetscCall(Poke(c, argv[1], (size_t)strtoull(argv[2], NULL, 10), atoi(argv[3])));
  else if (!strcmp(op, "fill"))
    for (size_t b = 0, off = (size_t)strtoull(argv[2], NULL, 10); b < (size_t)strtoull(argv[3], NULL, 10); b++) PetscCall(Poke(c, argv[1], off + b, atoi(argv[4])));
  else if (!strcmp(op, "unterminated"))
    for (size_t b = 0; b < sizeof(((SpamRunResult *)NULL)->reason); b++) PetscCall(Poke(c, "run_result", offsetof(SpamRunResult, reason) + b, 'A'));
  else if (!strcmp(op, "status")) {
    const unsigned status = (unsigned)atoi(argv[1]);
    /* the enum's bytes in the record as this build lays them out (little-endian int) */
    for (size_t b = 0; b < sizeof(SpamStatus); b++) PetscCall(Poke(c, "run_result", offsetof(SpamRunResult, status) + b, (int)((status >> (8 * b)) & 0xff)));
  } else SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "ck_forge: unknown edit '%s'", op);
  PetscFunctionReturn(0);
}

/* One forgery: IN read, the edits in argv[1..argc-1] applied, written to argv[0]. */
static PetscErrorCode Forge(const char *in, int argc, char **argv)
{
  SpamCkFile c;

  PetscFunctionBeginUser;
  PetscCheck(argc >= 1, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "usage: ck_forge IN OUT EDIT... [-- OUT EDIT...]...");
  PetscCall(SpamCkFileRead(PETSC_COMM_SELF, in, &c));
  for (int k = 1, used = 0; k < argc; k += used) PetscCall(Edit(&c, argc - k, argv + k, &used));
  PetscCall(SpamCkFileWrite(PETSC_COMM_SELF, &c, argv[0], NULL));
  PetscCall(SpamCkFileDestroy(&c));
  PetscFunctionReturn(0);
}

static PetscErrorCode ForgeAll(int argc, char **argv)
{
  PetscFunctionBeginUser;
  PetscCheck(argc >= 3, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "usage: ck_forge IN OUT EDIT... [-- OUT EDIT...]...");
  for (int k = 2, end; k < argc; k = end + 1) {
    for (end = k; end < argc && strcmp(argv[end], "--"); end++) continue;
    PetscCall(Forge(argv[1], end - k, argv + k));
  }
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  int            one = 1;
  char          *name[] = {argv[0], NULL}, **fake = name;
  PetscErrorCode ierr;

  /* PETSc sees no arguments: an edit's value such as -1 is not an option */
  PetscCall(PetscInitialize(&one, &fake, NULL, NULL));
  ierr = ForgeAll(argc, argv);
  PetscCall(PetscFinalize());
  return ierr ? 1 : 0;
}
