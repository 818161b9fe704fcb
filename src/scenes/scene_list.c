/* The scenes spam-ark knows, by name: a new scene is its own file and one line here. */
#include <spam/scene.h>

PetscErrorCode SpamSceneRegisterAll(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListAdd(list, "expansion", SpamSceneExpansion));
  PetscCall(PetscFunctionListAdd(list, "file", SpamSceneFile));
  PetscCall(PetscFunctionListAdd(list, "chain", SpamSceneChain));
  PetscCall(PetscFunctionListAdd(list, "planewave", SpamScenePlanewave));
  PetscCall(PetscFunctionListAdd(list, "rotor", SpamSceneRotor));
  PetscCall(PetscFunctionListAdd(list, "rotor-pair", SpamSceneRotorPair));
  PetscCall(PetscFunctionListAdd(list, "rotor-md", SpamSceneRotorMd));
  PetscCall(PetscFunctionListAdd(list, "tensile", SpamSceneTensile));
  PetscCall(PetscFunctionListAdd(list, "convection", SpamSceneConvection));
  PetscCall(PetscFunctionListAdd(list, "sod", SpamSceneSod));
  PetscCall(PetscFunctionListAdd(list, "sedov", SpamSceneSedov));
  PetscCall(PetscFunctionListAdd(list, "gresho", SpamSceneGresho));
  PetscCall(PetscFunctionListAdd(list, "taylor-green", SpamSceneTaylorGreen));
  PetscCall(PetscFunctionListAdd(list, "heat-mode", SpamSceneHeatMode));
  PetscCall(PetscFunctionListAdd(list, "couette", SpamSceneCouette));
  PetscCall(PetscFunctionListAdd(list, "poiseuille", SpamScenePoiseuille));
  PetscCall(PetscFunctionListAdd(list, "cavity", SpamSceneCavity));
  PetscFunctionReturn(0);
}
