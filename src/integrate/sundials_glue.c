/* Callbacks shared by the ARKODE and CVODE TS types: the right-hand side (whole, or one
 * part of an IMEX split) on PETSc N_Vectors, ARKODE's stability function, the error
 * handler that keeps SUNDIALS' last message, and the failure text. */
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

/* One part of the right-hand side, with SpamSundialsRhs's conventions. */
static int RhsOfPart(realtype t, N_Vector y, N_Vector ydot, SpamTsApp *app, SpamRhsPart part)
{
  const PetscScalar *ya;
  PetscScalar       *fa;

  if ((app->perr = VecGetArrayRead(N_VGetVector_Petsc(y), &ya))) return -1;
  if ((app->perr = VecGetArrayWrite(N_VGetVector_Petsc(ydot), &fa))) return -1;
  app->perr = SpamRhsOfPart(app->sim, ya, fa, part, &app->bad);
  if (VecRestoreArrayWrite(N_VGetVector_Petsc(ydot), &fa) || VecRestoreArrayRead(N_VGetVector_Petsc(y), &ya)) return -1;
  if (app->perr) return -1;
  if (app->bad >= 0) app->tbad = t;
  return app->bad >= 0 ? -1 : 0;
}

int SpamSundialsRhsExplicit(realtype t, N_Vector y, N_Vector ydot, void *data)
{
  return RhsOfPart(t, y, ydot, (SpamTsApp *)data, SPAM_RHS_EXPLICIT);
}

int SpamSundialsRhsDiffusion(realtype t, N_Vector y, N_Vector ydot, void *data)
{
  return RhsOfPart(t, y, ydot, (SpamTsApp *)data, SPAM_RHS_DIFFUSION);
}

/* ARKODE's stability function: the physical (CFL, force) bound of the current state. */
int SpamSundialsStability(N_Vector y, realtype t, realtype *hstab, void *data)
{
  SpamTsApp         *app = (SpamTsApp *)data;
  const PetscScalar *ya;
  double             dt;

  (void)t;
  if ((app->perr = VecGetArrayRead(N_VGetVector_Petsc(y), &ya))) return -1;
  app->perr = SpamStepBound(app->sim, app->o, ya, &dt, &app->bound_which);
  if (VecRestoreArrayRead(N_VGetVector_Petsc(y), &ya) || app->perr) return -1;
  app->bound = dt;
  app->bound_calls++;
  /* ARKODE takes SPAM_ARK_CFL_FRACTION of hstab (a fraction of 1 is refused); -step_cfl
   * and -step_force are the fractions already, so hand it the bound divided by that. */
  *hstab = isfinite(dt) ? dt / SPAM_ARK_CFL_FRACTION : -1.0; /* non-positive: no bound */
  return 0;
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
