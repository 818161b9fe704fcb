/* Per-particle field arrays with ghost slots. */
#include <spam/fields.h>
#include <spam/huge_pages.h>

/* Every array with its number of values per slot (0: not allocated for this model). */
static int Arrays(SpamFields *f, double **a[40], int per[40])
{
  const int d = f->dim, t = f->tensor ? 1 : 0, s = f->adaptive ? 1 : 0;
  int       k = 0;
#define SPAM_ARRAY(ptr, w) (a[k] = &(ptr), per[k++] = (w))
  SPAM_ARRAY(f->m, 1);
  SPAM_ARRAY(f->minv, f->inverse_mass);
  SPAM_ARRAY(f->rho, 1);
  SPAM_ARRAY(f->q, 1);
  SPAM_ARRAY(f->acc, d);
  SPAM_ARRAY(f->v, t * d);
  SPAM_ARRAY(f->e, t);
  SPAM_ARRAY(f->T, t);
  SPAM_ARRAY(f->qs, t * d * d);
  SPAM_ARRAY(f->gradv, t * d * d);
  SPAM_ARRAY(f->heat, t * d);
  SPAM_ARRAY(f->xdot, t * d);
  SPAM_ARRAY(f->shift, t * d);
  SPAM_ARRAY(f->edrift, t);
  SPAM_ARRAY(f->divv, t);
  SPAM_ARRAY(f->lapn, t);
  SPAM_ARRAY(f->vol2, t);
  SPAM_ARRAY(f->gmom, t * d * d);
  SPAM_ARRAY(f->uc, t * d);
  SPAM_ARRAY(f->edot, t);
  SPAM_ARRAY(f->qdot, t);
  SPAM_ARRAY(f->qlin, t);
  SPAM_ARRAY(f->rhodot, t);
  SPAM_ARRAY(f->wsum, t);
  SPAM_ARRAY(f->ltorque, t);
  SPAM_ARRAY(f->h, s);
  SPAM_ARRAY(f->hinv, s);
  SPAM_ARRAY(f->wn, s);
  SPAM_ARRAY(f->gn, s);
  SPAM_ARRAY(f->omega, s);
  SPAM_ARRAY(f->drho, s);
  SPAM_ARRAY(f->hlo, s);
  SPAM_ARRAY(f->hhi, s);
  SPAM_ARRAY(f->settled, s);
  SPAM_ARRAY(f->hcap, s);
  SPAM_ARRAY(f->xnear, s * d);
#undef SPAM_ARRAY
  return k;
}

PetscErrorCode SpamFieldsCreate(int dim, int n, int cap, PetscBool tensor, SpamFields *f)
{
  double **a[40];
  int      per[40], na;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof *f));
  f->dim    = dim;
  f->n      = n;
  f->tensor = tensor;
  f->inverse_mass = tensor ? 1 : 0;
  f->cap    = PetscMax(cap, n) + 1;
  na        = Arrays(f, a, per);
  for (int k = 0; k < na; k++)
    if (per[k]) PetscCall(PetscCalloc1((size_t)f->cap * per[k], a[k]));
  if (tensor) PetscCall(PetscCalloc1((size_t)f->cap, &f->tfac));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFieldsReserve(SpamFields *f, int slots)
{
  double **a[40];
  int      per[40], na, old = f->cap;

  PetscFunctionBeginUser;
  if (slots + 1 <= f->cap) PetscFunctionReturn(0);
  f->cap = slots + slots / 8 + 16;
  na     = Arrays(f, a, per);
  for (int k = 0; k < na; k++) {
    if (!per[k]) continue;
    PetscCall(PetscRealloc((size_t)f->cap * per[k] * sizeof(double), a[k]));
    SpamAdviseHugePages(*a[k], (size_t)f->cap * per[k] * sizeof(double)); /* before the zeros below */
    for (size_t z = (size_t)old * per[k]; z < (size_t)f->cap * per[k]; z++) (*a[k])[z] = 0.0;
  }
  if (f->tensor) PetscCall(PetscRealloc((size_t)f->cap * sizeof(double), &f->tfac));
  if (f->adaptive) PetscCall(PetscRealloc((size_t)(f->cap + 1) * sizeof(int), &f->near_start));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFieldsDestroy(SpamFields *f)
{
  double **a[40];
  int      per[40], na = Arrays(f, a, per);

  PetscFunctionBeginUser;
  for (int k = 0; k < na; k++) PetscCall(PetscFree(*a[k]));
  PetscCall(PetscFree(f->tfac));
  PetscCall(PetscFree(f->near_start));
  PetscCall(PetscFree(f->near_nbr));
  PetscCall(PetscFree2(f->amark, f->mbuf));
  f->mcap = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFieldsReserveMarks(SpamFields *f, int slots)
{
  PetscFunctionBeginUser;
  if (slots + 1 <= f->mcap) PetscFunctionReturn(0);
  PetscCall(PetscFree2(f->amark, f->mbuf));
  f->mcap = slots + slots / 8 + 16;
  PetscCall(PetscCalloc2((size_t)2 * f->mcap, &f->amark, (size_t)f->mcap, &f->mbuf));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFieldsAddInverseMass(SpamFields *f)
{
  PetscFunctionBeginUser;
  if (f->minv) PetscFunctionReturn(0);
  f->inverse_mass = 1;
  PetscCall(PetscCalloc1((size_t)f->cap, &f->minv));
  for (int i = 0; i < f->n; i++) f->minv[i] = 1.0 / f->m[i];
  PetscFunctionReturn(0);
}

PetscErrorCode SpamFieldsAddSmoothing(SpamFields *f)
{
  double **a[40];
  int      per[40], na;

  PetscFunctionBeginUser;
  f->adaptive = 1;
  na          = Arrays(f, a, per);
  for (int k = 0; k < na; k++) /* the arrays not yet allocated: the adaptive range's */
    if (per[k] && !*a[k]) PetscCall(PetscCalloc1((size_t)f->cap * per[k], a[k]));
  PetscCall(PetscCalloc1((size_t)f->cap + 1, &f->near_start));
  PetscFunctionReturn(0);
}

PetscBool SpamFieldsUniformMass(const SpamFields *f)
{
  for (int i = 1; i < f->n; i++)
    if (f->m[i] != f->m[0]) return PETSC_FALSE;
  return PETSC_TRUE;
}

void SpamFieldsSetMasses(SpamFields *f, const double *m, double uniform)
{
  for (int i = 0; i < f->n; i++) {
    f->m[i] = m ? m[i] : uniform;
    if (f->minv) f->minv[i] = 1.0 / f->m[i];
  }
  f->uniform_mass = (int)SpamFieldsUniformMass(f);
}
