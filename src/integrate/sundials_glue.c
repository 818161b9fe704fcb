/* Callbacks shared by the ARKODE and CVODE TS types: the right-hand side on PETSc
 * N_Vectors, the error handler that keeps SUNDIALS' last message, and the failure text. */
#include <spam/integrator.h>
#include <nvector/nvector_petsc.h>

int SpamSundialsRhs(realtype t, N_Vector y, N_Vector ydot, void *data)
{
  SpamTsApp         *app = (SpamTsApp *)data;
  const PetscScalar *ya;
  PetscScalar       *fa;

  if ((app->perr = VecGetArrayRead(N_VGetVector_Petsc(y), &ya))) return -1;
  if ((app->perr = VecGetArrayWrite(N_VGetVector_Petsc(ydot), &fa))) return -1;
  app->perr = SpamRhs(app->sim, ya, fa, &app->bad);
  if (VecRestoreArrayWrite(N_VGetVector_Petsc(ydot), &fa) || VecRestoreArrayRead(N_VGetVector_Petsc(y), &ya)) return -1;
  if (app->perr) return -1;
  if (app->bad >= 0) app->tbad = t;
  /* Not recoverable: a non-finite stage is reported by the loop as an unstable run. */
  return app->bad >= 0 ? -1 : 0;
}

void SpamSundialsErrHandler(int code, const char *module, const char *function, char *msg, void *data)
{
  SpamTsApp *app = (SpamTsApp *)data;
  (void)code;
  (void)module;
  (void)snprintf(app->fail, sizeof app->fail, "%s: %s", function, msg);
}

void SpamSundialsFailure(SpamTsApp *app, const char *call, char *(*namefn)(long), int flag)
{
  char  msg[160];
  char *name = namefn(flag);
  (void)snprintf(msg, sizeof msg, "%.150s", app->fail);
  (void)snprintf(app->fail, sizeof app->fail, "%s returned %s (%.150s)", call, name ? name : "?", msg);
  free(name);
}
