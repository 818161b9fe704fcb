/* A scene's options read by their rows in the scene's table (SpamSceneOption): the name,
 * the type and the help come from the row, so what -help shows and what option_use.c
 * accepts are the same table. */
#include <spam/scene.h>
#include <strings.h>

const SpamSceneOption *SpamSceneOptionFind(const SpamSceneOption *table, const char *name)
{
  for (const SpamSceneOption *o = table; o && o->name; o++)
    if (!strcasecmp(o->name, name)) return o; /* PETSc ignores case */
  return NULL;
}

/* The row of name, of type t, and its option's name with the '-'. */
static PetscErrorCode Row(const SpamSceneOption *table, const char *name, SpamSceneOptionType t, const SpamSceneOption **row, char *opt, size_t len)
{
  PetscFunctionBeginUser;
  *row = SpamSceneOptionFind(table, name);
  PetscCheck(*row && (*row)->help, PETSC_COMM_SELF, PETSC_ERR_PLIB, "-%s is read by a scene whose options table does not hold it", name);
  PetscCheck((*row)->type == t, PETSC_COMM_SELF, PETSC_ERR_PLIB, "-%s is read as another type than its scene's table says", name);
  PetscCall(PetscSNPrintf(opt, len, "-%s", name));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneOptionInt(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, PetscInt *value, PetscBool *set)
{
  const SpamSceneOption *o;
  char                   opt[64];

  PetscFunctionBeginUser;
  PetscCall(Row(table, name, SPAM_SCENE_OPTION_INT, &o, opt, sizeof opt));
  PetscCall(PetscOptionsInt(opt, o->help, "README", *value, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneOptionRealHelp(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, const char *help, double *value, PetscBool *set)
{
  const SpamSceneOption *o;
  char                   opt[64];

  PetscFunctionBeginUser;
  PetscCall(Row(table, name, SPAM_SCENE_OPTION_REAL, &o, opt, sizeof opt));
  PetscCall(PetscOptionsReal(opt, help ? help : o->help, "README", *value, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneOptionReal(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, double *value, PetscBool *set)
{
  PetscFunctionBeginUser;
  PetscCall(SpamSceneOptionRealHelp(PetscOptionsObject, table, name, NULL, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneOptionBool(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, PetscBool *value, PetscBool *set)
{
  const SpamSceneOption *o;
  char                   opt[64];

  PetscFunctionBeginUser;
  PetscCall(Row(table, name, SPAM_SCENE_OPTION_BOOL, &o, opt, sizeof opt));
  PetscCall(PetscOptionsBool(opt, o->help, "README", *value, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneOptionString(PetscOptionItems *PetscOptionsObject, const SpamSceneOption *table, const char *name, char *value, size_t len, PetscBool *set)
{
  const SpamSceneOption *o;
  char                   opt[64];

  PetscFunctionBeginUser;
  PetscCall(Row(table, name, SPAM_SCENE_OPTION_STRING, &o, opt, sizeof opt));
  PetscCall(PetscOptionsString(opt, o->help, "README", value, value, len, set));
  PetscFunctionReturn(0);
}
