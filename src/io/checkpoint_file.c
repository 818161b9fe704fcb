/* The checkpoint in memory: named entries kept sorted by name, so that lookups are binary
 * searches and the checksum (taken in name order) needs no sorting. */
#include "checkpoint_layout.h"
#include <limits.h>

static const char *KindName(SpamCkKind k) { return k == SPAM_CK_REAL ? "real" : k == SPAM_CK_INT ? "integer" : "text"; }

/* The file as messages name it. */
static const char *FileName(const SpamCkFile *c) { return c->path[0] ? c->path : "(not read from a file)"; }

size_t SpamCkValueSize(SpamCkKind kind) { return kind == SPAM_CK_TEXT ? 1 : 8; }

PetscBool SpamCkNameValid(const char *name)
{
  size_t len = name ? strlen(name) : 0;

  if (len < 1 || len > 63 || name[0] == '.') return PETSC_FALSE;
  for (size_t i = 0; i < len; i++) {
    const char ch = name[i];
    if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '-' || ch == '.')) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

/* The index of name, or (not found) the index where it belongs as -1 - index. */
static int Find(const SpamCkFile *c, const char *name)
{
  int lo = 0, hi = c->n - 1;

  while (lo <= hi) {
    const int mid = lo + (hi - lo) / 2, cmp = strcmp(c->e[mid].name, name);
    if (!cmp) return mid;
    if (cmp < 0) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1 - lo;
}

PetscErrorCode SpamCkFileInit(SpamCkFile *c)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(c, sizeof *c));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkFileDestroy(SpamCkFile *c)
{
  PetscFunctionBeginUser;
  for (int i = 0; i < c->n; i++) PetscCall(PetscFree(c->e[i].data));
  PetscCall(PetscFree(c->e));
  PetscCall(SpamCkFileInit(c));
  PetscFunctionReturn(0);
}

/* A free slot at index at (entries after it moved up by one). */
static PetscErrorCode OpenSlot(SpamCkFile *c, int at)
{
  PetscFunctionBeginUser;
  if (c->n == c->cap) {
    SpamCkEntry *grown;
    const int    cap = c->cap ? 2 * c->cap : 16;
    PetscCall(PetscCalloc1(cap, &grown));
    if (c->n) PetscCall(PetscArraycpy(grown, c->e, c->n));
    PetscCall(PetscFree(c->e));
    c->e   = grown;
    c->cap = cap;
  }
  PetscCall(PetscArraymove(c->e + at + 1, c->e + at, c->n - at));
  c->n++;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkAdopt(SpamCkFile *c, const char *name, SpamCkKind kind, size_t n, void *data)
{
  int at;

  PetscFunctionBeginUser;
  if (!SpamCkNameValid(name)) {
    PetscCall(PetscFree(data));
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "checkpoint entry name '%s': 1 to 63 letters, digits, '_', '-' or '.', not starting with '.'", name ? name : "(null)");
  }
  at = Find(c, name);
  if (at >= 0) PetscCall(PetscFree(c->e[at].data));
  else {
    PetscErrorCode ierr;
    at   = -1 - at;
    ierr = OpenSlot(c, at);
    if (ierr) PetscCall(PetscFree(data));
    PetscCall(ierr);
    PetscCall(PetscStrncpy(c->e[at].name, name, sizeof c->e[at].name));
  }
  c->e[at].kind = kind;
  c->e[at].n    = n;
  c->e[at].data = data;
  PetscFunctionReturn(0);
}

/* A copy of n values of kind (text: n bytes and a NUL), then adopted. */
static PetscErrorCode Put(SpamCkFile *c, const char *name, SpamCkKind kind, size_t n, const void *v)
{
  const size_t size = SpamCkValueSize(kind);
  char        *copy;

  PetscFunctionBeginUser;
  PetscCheck(!n || v, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "checkpoint entry '%s': %zu values from a NULL pointer", name, n);
  PetscCheck(n <= (SIZE_MAX - 1) / size, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "checkpoint entry '%s': %zu values overflow size_t", name, n);
  /* One byte more than the data, always: a zero-length entry still owns a buffer, and text ends in NUL. */
  PetscCall(PetscMalloc1(n * size + 1, &copy));
  if (n) PetscCall(PetscMemcpy(copy, v, n * size));
  copy[n * size] = 0;
  PetscCall(SpamCkAdopt(c, name, kind, n, copy));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkPutReal(SpamCkFile *c, const char *name, size_t n, const double *v)
{
  PetscFunctionBeginUser;
  PetscCall(Put(c, name, SPAM_CK_REAL, n, v));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkPutInt(SpamCkFile *c, const char *name, size_t n, const int64_t *v)
{
  PetscFunctionBeginUser;
  PetscCall(Put(c, name, SPAM_CK_INT, n, v));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkPutText(SpamCkFile *c, const char *name, const char *s, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(Put(c, name, SPAM_CK_TEXT, len, s));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkPutScalar(SpamCkFile *c, const char *name, double v)
{
  PetscFunctionBeginUser;
  PetscCall(Put(c, name, SPAM_CK_REAL, 1, &v));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkPutLong(SpamCkFile *c, const char *name, long v)
{
  const int64_t w = v;

  PetscFunctionBeginUser;
  PetscCall(Put(c, name, SPAM_CK_INT, 1, &w));
  PetscFunctionReturn(0);
}

PetscBool SpamCkHas(const SpamCkFile *c, const char *name) { return (PetscBool)(c && name && Find(c, name) >= 0); }

/* The entry of that name and kind; n > 0: of that length too. */
static PetscErrorCode Get(const SpamCkFile *c, const char *name, SpamCkKind kind, size_t n, const SpamCkEntry **e)
{
  const char *file = FileName(c);
  const int   at   = Find(c, name);

  PetscFunctionBeginUser;
  if (at < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: no entry '%s'", file, name);
  *e = &c->e[at];
  PetscCheck((*e)->kind == kind, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry '%s' is %s, expected %s", file, name, KindName((*e)->kind), KindName(kind));
  PetscCheck(!n || (*e)->n == n, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry '%s' has %zu values, expected %zu", file, name, (*e)->n, n);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkGetReal(const SpamCkFile *c, const char *name, size_t n, const double **v)
{
  const SpamCkEntry *e;

  PetscFunctionBeginUser;
  PetscCall(Get(c, name, SPAM_CK_REAL, n, &e));
  *v = (const double *)e->data;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkGetInt(const SpamCkFile *c, const char *name, size_t n, const int64_t **v)
{
  const SpamCkEntry *e;

  PetscFunctionBeginUser;
  PetscCall(Get(c, name, SPAM_CK_INT, n, &e));
  *v = (const int64_t *)e->data;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkGetText(const SpamCkFile *c, const char *name, const char **s, size_t *len)
{
  const SpamCkEntry *e;

  PetscFunctionBeginUser;
  PetscCall(Get(c, name, SPAM_CK_TEXT, 0, &e));
  *s = (const char *)e->data;
  if (len) *len = e->n;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkGetScalar(const SpamCkFile *c, const char *name, double *v)
{
  const double *p = NULL;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(c, name, 1, &p));
  *v = p[0];
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkGetLong(const SpamCkFile *c, const char *name, long *v)
{
  const int64_t *p = NULL;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetInt(c, name, 1, &p));
  PetscCheck(p[0] >= LONG_MIN && p[0] <= LONG_MAX, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: entry '%s' = %lld does not fit a long", FileName(c), name, (long long)p[0]);
  *v = (long)p[0];
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkGetLength(const SpamCkFile *c, const char *name, size_t *n)
{
  const int at = Find(c, name);

  PetscFunctionBeginUser;
  PetscCheck(at >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: no entry '%s'", FileName(c), name);
  *n = c->e[at].n;
  PetscFunctionReturn(0);
}

/* 64-bit FNV-1a: h = (h xor byte) * prime. Both steps are bijections of h, so two byte
 * streams that differ in one byte always hash differently. */
#define FNV_OFFSET 0xcbf29ce484222325ULL
#define FNV_PRIME  0x100000001b3ULL

static uint64_t HashBytes(uint64_t h, const unsigned char *p, size_t n)
{
  for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * FNV_PRIME;
  return h;
}

/* A 64-bit word as 8 bytes little-endian, whatever the machine's byte order. */
static uint64_t HashWord(uint64_t h, uint64_t w)
{
  for (int b = 0; b < 8; b++) h = (h ^ ((w >> (8 * b)) & 0xff)) * FNV_PRIME;
  return h;
}

uint64_t SpamCkChecksum(const SpamCkFile *c)
{
  static const unsigned char code[3] = {'R', 'I', 'T'};
  uint64_t                   h       = FNV_OFFSET;

  for (int i = 0; i < c->n; i++) {
    const SpamCkEntry *e = &c->e[i];
    h                    = HashBytes(h, (const unsigned char *)e->name, strlen(e->name) + 1);
    h                    = HashBytes(h, &code[e->kind], 1);
    h                    = HashWord(h, (uint64_t)e->n);
    if (e->kind == SPAM_CK_TEXT) h = HashBytes(h, (const unsigned char *)e->data, e->n);
    else
      for (size_t k = 0; k < e->n; k++) {
        uint64_t w;
        memcpy(&w, (const char *)e->data + 8 * k, 8);
        h = HashWord(h, w);
      }
  }
  return h;
}
