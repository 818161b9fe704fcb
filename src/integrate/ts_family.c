/* The table of TS types spam-ark runs: the one place a type's name is looked up. */
#include "ts_family.h"
#include <spam/errors.h>
#include <strings.h>

static const SpamTSFamily *const Families[] = {&SpamTSFamilyARKode, &SpamTSFamilyARKodeImex, &SpamTSFamilyCVode, &SpamTSFamilyRK, &SpamTSFamilySSP, &SpamTSFamilyEuler, &SpamTSFamilySymplectic, &SpamTSFamilyBlock};
#define NFAMILIES ((int)(sizeof Families / sizeof Families[0]))

const SpamTSFamily *SpamTSFamilyNamed(const char *type)
{
  for (int k = 0; type && k < NFAMILIES; k++)
    if (!strcmp(type, Families[k]->type)) return Families[k];
  return NULL;
}

PetscErrorCode SpamTSFamilyOf(TS ts, const SpamTSFamily **f)
{
  TSType type;

  PetscFunctionBeginUser;
  PetscCall(TSGetType(ts, &type));
  *f = SpamTSFamilyNamed(type);
  PetscCheck(*f, PetscObjectComm((PetscObject)ts), PETSC_ERR_PLIB, "TS type %s has no row in the table of methods", type ? type : "(none)");
  PetscFunctionReturn(0);
}

int SpamTSFamilyNames(const char *names[], int max)
{
  int n = 0;

  for (int k = 0; k < NFAMILIES && n < max; k++) names[n++] = Families[k]->type;
  return n;
}

const SpamTSFamily *SpamTSFamilyAt(int k)
{
  return k >= 0 && k < NFAMILIES ? Families[k] : NULL;
}

PetscErrorCode SpamTSInterpolatesAlways(TS ts, PetscBool *yes)
{
  (void)ts;
  *yes = PETSC_TRUE;
  return 0;
}

const SpamTSOption *SpamTSFamilyOption(const SpamTSFamily *f, const char *name)
{
  for (const SpamTSOption *o = f->options; o && o->name; o++)
    if (!strcasecmp(o->name, name)) return o; /* PETSc ignores case */
  return NULL;
}
