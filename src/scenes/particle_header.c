/* The header of a particle file: any order of the named columns x y z vx vy vz m e rho
 * sxx sxy syy sxz syz szz id (and rho_sum, which snapshots write). Positions are
 * required; each column at most once; a column of a direction beyond -dim, an unknown
 * name or a part of the stress tensor is refused, so that no value is dropped. */
#include "particle_file.h"
#include <spam/errors.h>

/* Stress component names in the order of SpamParticles.sigma for each dimension. */
static const char *const Stress1[] = {"sxx"};
static const char *const Stress2[] = {"sxx", "sxy", "syy"};
static const char *const Stress3[] = {"sxx", "sxy", "sxz", "syy", "syz", "szz"};

const char *SpamStressName(int dim, int k)
{
  return dim == 1 ? Stress1[k] : dim == 2 ? Stress2[k] : Stress3[k];
}

/* The slot of a column name in dimension dim, or -1 if unknown; *dim_needed receives the
 * dimension a known name needs (a z in 2D: 3). */
static int SlotOf(const char *name, int dim, int *dim_needed)
{
  static const char *ax[3] = {"x", "y", "z"};
  static const char *va[3] = {"vx", "vy", "vz"};

  *dim_needed = 1;
  for (int d = 0; d < 3; d++) {
    const PetscBool pos = (PetscBool)!strcmp(name, ax[d]), vel = (PetscBool)!strcmp(name, va[d]);
    if (!pos && !vel) continue;
    *dim_needed = d + 1;
    return (pos ? SLOT_X : SLOT_V) + d;
  }
  if (!strcmp(name, "m")) return SLOT_M;
  if (!strcmp(name, "e")) return SLOT_E;
  if (!strcmp(name, "rho")) return SLOT_RHO;
  if (!strcmp(name, "id")) return SLOT_ID;
  if (!strcmp(name, "rho_sum")) return SLOT_RHO_SUM;
  for (int k = 0; k < SpamStressComponents(dim); k++)
    if (!strcmp(name, SpamStressName(dim, k))) return SLOT_S + k;
  for (int k = 0; k < 6; k++) /* a stress name of a higher dimension */
    if (!strcmp(name, Stress3[k])) *dim_needed = strchr(name + 1, 'z') ? 3 : 2;
  return -1;
}

/* Splits off the next comma-separated name of s (spaces around it dropped) into name. */
static const char *NextName(const char *s, char *name, size_t len)
{
  const char *end = strchr(s, ',');
  size_t      n   = end ? (size_t)(end - s) : strlen(s);
  while (n && (*s == ' ' || *s == '\t')) s++, n--;
  while (n && (s[n - 1] == ' ' || s[n - 1] == '\t')) n--;
  if (n >= len) n = len - 1;
  memcpy(name, s, n);
  name[n] = 0;
  return end ? end + 1 : NULL;
}

static unsigned ColumnBit(int slot)
{
  if (slot < SLOT_V) return SPAM_COLUMN_X;
  if (slot < SLOT_M) return SPAM_COLUMN_V;
  if (slot == SLOT_M) return SPAM_COLUMN_M;
  if (slot == SLOT_E) return SPAM_COLUMN_E;
  if (slot == SLOT_RHO) return SPAM_COLUMN_RHO;
  if (slot == SLOT_ID) return SPAM_COLUMN_ID;
  if (slot == SLOT_RHO_SUM) return 0;
  return SPAM_COLUMN_STRESS;
}

/* Every position column of dim is there; the stress is all of its components or none. */
static int CheckComplete(const PetscBool *seen, int dim, char *why, size_t len)
{
  static const char *ax[3] = {"x", "y", "z"};
  int                ns = SpamStressComponents(dim), nstress = 0;

  for (int d = 0; d < dim; d++)
    if (!seen[SLOT_X + d]) return snprintf(why, len, "the header has no column %s: the positions (x%s%s) are required for -dim %d", ax[d], dim > 1 ? ",y" : "", dim > 2 ? ",z" : "", dim), 1;
  for (int k = 0; k < ns; k++) nstress += seen[SLOT_S + k] ? 1 : 0;
  if (nstress && nstress < ns) {
    size_t used = (size_t)snprintf(why, len, "the stress needs all of its %d components for -dim %d (", ns, dim);
    for (int k = 0; k < ns && used < len; k++) used += (size_t)snprintf(why + used, len - used, "%s%s", k ? "," : "", SpamStressName(dim, k));
    if (used < len) (void)snprintf(why + used, len - used, ") or none");
    return 1;
  }
  return 0;
}

int SpamColumnsParse(const char *header, int dim, SpamColumnMap *map, char *why, size_t len)
{
  PetscBool   seen[NSLOTS] = {PETSC_FALSE};
  const char *s            = header;
  char        name[64];

  memset(map, 0, sizeof *map);
  while (s) {
    int need, slot;
    s    = NextName(s, name, sizeof name);
    slot = SlotOf(name, dim, &need);
    if (map->ncol == NSLOTS) return snprintf(why, len, "the header has more than %d columns", NSLOTS), 1;
    if (!name[0]) return snprintf(why, len, "column %d of the header has no name", map->ncol + 1), 1;
    if (need > dim) return snprintf(why, len, "column %s needs -dim %d (this run has -dim %d)", name, need, dim), 1;
    if (slot < 0) return snprintf(why, len, "unknown column '%s'; known: x y z vx vy vz m e rho sxx sxy syy sxz syz szz id rho_sum", name), 1;
    if (seen[slot]) return snprintf(why, len, "column %s appears twice", name), 1;
    seen[slot]            = PETSC_TRUE;
    map->slot[map->ncol++] = slot;
    map->columns |= ColumnBit(slot);
    if (slot == SLOT_RHO_SUM) map->has_rho_sum = PETSC_TRUE;
  }
  return CheckComplete(seen, dim, why, len);
}

void SpamColumnsLegacy(int dim, int nfields, SpamColumnMap *map)
{
  memset(map, 0, sizeof *map);
  for (int d = 0; d < dim; d++) map->slot[map->ncol++] = SLOT_X + d;
  for (int d = 0; d < dim; d++) map->slot[map->ncol++] = SLOT_V + d;
  map->columns = SPAM_COLUMN_X | SPAM_COLUMN_V;
  if (nfields == 2 * dim + 1) {
    map->slot[map->ncol++] = SLOT_M;
    map->columns |= SPAM_COLUMN_M;
  }
}

PetscErrorCode SpamParticlesAllocateColumns(int dim, PetscInt n, unsigned columns, SpamParticles *out)
{
  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(dim, n, out));
  out->columns = columns;
  if (columns & (SPAM_COLUMN_E | SPAM_COLUMN_RHO | SPAM_COLUMN_STRESS)) PetscCall(SpamParticlesAllocateFields(out));
  if (columns & SPAM_COLUMN_M) PetscCall(PetscCalloc1(n + 1, &out->m));
  if (columns & SPAM_COLUMN_ID) PetscCall(PetscCalloc1(n + 1, &out->id));
  PetscFunctionReturn(0);
}

/* Moves k components per particle of a from row i to row to[i]. */
static PetscErrorCode MoveRows(double *a, PetscInt n, int k, const PetscInt *to)
{
  double *tmp;

  PetscFunctionBeginUser;
  if (!a) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1((size_t)n * k + 1, &tmp));
  for (PetscInt i = 0; i < n; i++)
    for (int c = 0; c < k; c++) tmp[(size_t)to[i] * k + c] = a[(size_t)i * k + c];
  PetscCall(PetscArraycpy(a, tmp, (size_t)n * k));
  PetscCall(PetscFree(tmp));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamParticlesOrderById(SpamParticles *p, PetscInt *bad, const char **why)
{
  PetscBool *taken;

  PetscFunctionBeginUser;
  *bad = -1;
  *why = NULL;
  if (!p->id) PetscFunctionReturn(0);
  PetscCall(PetscCalloc1(p->n + 1, &taken));
  for (PetscInt i = 0; i < p->n && *bad < 0; i++) {
    if (p->id[i] < 0 || p->id[i] >= p->n) *bad = i, *why = "is not between 0 and the particle count - 1";
    else if (taken[p->id[i]]) *bad = i, *why = "is the id of an earlier particle too";
    else taken[p->id[i]] = PETSC_TRUE;
  }
  PetscCall(PetscFree(taken));
  if (*bad >= 0) PetscFunctionReturn(0);
  PetscCall(MoveRows(p->x, p->n, p->dim, p->id));
  PetscCall(MoveRows(p->v, p->n, p->dim, p->id));
  PetscCall(MoveRows(p->m, p->n, 1, p->id));
  PetscCall(MoveRows(p->e, p->n, 1, p->id));
  PetscCall(MoveRows(p->rho, p->n, 1, p->id));
  PetscCall(MoveRows(p->sigma, p->n, SpamStressComponents(p->dim), p->id));
  for (PetscInt i = 0; i < p->n; i++) p->id[i] = i;
  PetscFunctionReturn(0);
}
