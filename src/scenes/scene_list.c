/* The scenes of scene_list.h as a constant table of descriptor functions, in the list's
 * order: -scene's list by name, and each scene's descriptor for the registry's users
 * (scene.c, option_use.c). */
#include <spam/scene.h>
#include <scenes/scene_list.h>

#define SPAM_SCENE_DECLARE(Prefix) PetscErrorCode SpamScene##Prefix(SpamSceneOps *ops);
SPAM_SCENE_LIST(SPAM_SCENE_DECLARE)
#undef SPAM_SCENE_DECLARE

#define SPAM_SCENE_ROW(Prefix) SpamScene##Prefix,
static const SpamSceneOpsFn Scenes[] = {SPAM_SCENE_LIST(SPAM_SCENE_ROW)};
#undef SPAM_SCENE_ROW

int SpamSceneCount(void)
{
  return (int)(sizeof Scenes / sizeof Scenes[0]);
}

PetscErrorCode SpamSceneGet(int i, SpamSceneOps *ops)
{
  PetscFunctionBeginUser;
  PetscCheck(i >= 0 && i < SpamSceneCount(), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "scene %d of %d", i, SpamSceneCount());
  PetscCall(PetscMemzero(ops, sizeof *ops));
  PetscCall(Scenes[i](ops));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamSceneRegisterAll(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  for (int i = 0; i < SpamSceneCount(); i++) {
    SpamSceneOps ops;
    PetscCall(SpamSceneGet(i, &ops));
    PetscCall(PetscFunctionListAdd(list, ops.name, Scenes[i]));
  }
  PetscFunctionReturn(0);
}
