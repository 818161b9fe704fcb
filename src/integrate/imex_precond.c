/* The stage preconditioner of arkode_imex (imex_precond.h).
 *
 * ARKStep's stage system is (I - gamma J) x = b with gamma = h a_ii. The diffusion part is
 * linear in v and e at the fixed positions and densities of a stage but for the viscous
 * work, so P = I - gamma J with J assembled from the pair list (the work's derivative at
 * J's state included) is the system itself at that state: GMRES, preconditioned on the
 * right (its residual test stays on the system's own residual), then needs a few products
 * where it needed tens. ARKODE asks
 * for a set-up when its Jacobian data are due (every few steps, after a convergence
 * failure, or when gamma moved): J is assembled only when ARKODE says they are stale (jok
 * false) and P refactored from it for each new gamma. */
#include "imex_precond.h"
#include <spam/sim.h>
#include <nvector/nvector_petsc.h>
#include <arkode/arkode_arkstep.h>

PetscErrorCode SpamImexPCCreate(SpamImexPC *pc)
{
  PC p;

  PetscFunctionBeginUser;
  pc->jac.builds = -1;
  if (!pc->ksp) {
    PetscCall(KSPCreate(PETSC_COMM_SELF, &pc->ksp));
    PetscCall(KSPSetOptionsPrefix(pc->ksp, SPAM_IMEX_PC_PREFIX));
    PetscCall(KSPSetType(pc->ksp, KSPPREONLY)); /* one application: a fixed linear operator for GMRES */
    PetscCall(KSPGetPC(pc->ksp, &p));
    /* ILU(1): its fill stays within the pairs of pairs (LU's grows with the size); on
     * Couette at Re 0.32 it takes as few GMRES iterations as LU (1.6 per Newton
     * iteration, ILU(0) 2.8), on the 192 x 12 heat mode 3.9 (LU 1.1, ILU(0) 5.2) */
    PetscCall(PCSetType(p, PCILU));
    PetscCall(PCFactorSetLevels(p, 1));
    PetscCall(KSPSetErrorIfNotConverged(pc->ksp, PETSC_FALSE));
  }
  PetscCall(KSPSetFromOptions(pc->ksp));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamImexPCHelp(void)
{
  SpamImexPC pc;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&pc, sizeof pc));
  PetscCall(SpamImexPCCreate(&pc));
  PetscCall(SpamImexPCDestroy(&pc));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamImexPCDestroy(SpamImexPC *pc)
{
  PetscFunctionBeginUser;
  PetscCall(KSPDestroy(&pc->ksp));
  PetscCall(MatDestroy(&pc->P));
  PetscCall(VecDestroy(&pc->r));
  PetscCall(VecDestroy(&pc->z));
  PetscCall(VecDestroy(&pc->ys));
  PetscCall(VecDestroy(&pc->jx));
  PetscCall(VecDestroy(&pc->jy));
  if (pc->ewt) N_VDestroy(pc->ewt);
  pc->ewt = NULL;
  PetscCall(SpamDiffusionJacDestroy(&pc->jac));
  PetscFunctionReturn(0);
}

/* The state J is assembled at: the iterate y with the stage's own positions and densities.
 * The diffusion part leaves x and rho alone, so there the stage residual
 * zcor - gamma Fi - sdata vanishes at zcor = sdata: x = zpred + sdata, where the stage's
 * first iterate still stands at the predictor's. */
static PetscErrorCode StageState(SpamTsApp *app, SpamImexPC *pc, N_Vector y)
{
  const SpamLayout  *l = &app->sim->model.layout;
  const PetscScalar *za, *sa;
  PetscScalar       *ya;
  N_Vector           zpred, z, fi, sdata;
  void              *data;
  realtype           t, gamma;
  PetscInt           len;
  int                flag;

  PetscFunctionBeginUser;
  flag = ARKStepGetNonlinearSystemData(pc->ark, &t, &zpred, &z, &fi, &gamma, &sdata, &data);
  PetscCheck(flag == ARK_SUCCESS, PETSC_COMM_SELF, PETSC_ERR_LIB, "ARKStepGetNonlinearSystemData failed: %s", ARKStepGetReturnFlagName(flag));
  if (!pc->ys) PetscCall(VecDuplicate(N_VGetVector_Petsc(y), &pc->ys));
  PetscCall(VecCopy(N_VGetVector_Petsc(y), pc->ys));
  PetscCall(VecGetLocalSize(pc->ys, &len));
  PetscCall(VecGetArray(pc->ys, &ya));
  PetscCall(VecGetArrayRead(N_VGetVector_Petsc(zpred), &za));
  PetscCall(VecGetArrayRead(N_VGetVector_Petsc(sdata), &sa));
  for (PetscInt b = 0; b < len; b += l->nvar) {
    for (int d = 0; d < l->dim; d++) ya[b + l->x + d] = za[b + l->x + d] + sa[b + l->x + d];
    if (l->rho >= 0) ya[b + l->rho] = za[b + l->rho] + sa[b + l->rho];
  }
  PetscCall(VecRestoreArrayRead(N_VGetVector_Petsc(sdata), &sa));
  PetscCall(VecRestoreArrayRead(N_VGetVector_Petsc(zpred), &za));
  PetscCall(VecRestoreArray(pc->ys, &ya));
  PetscFunctionReturn(0);
}

/* J at y where ARKODE says its data are stale; P = I - gamma J, made anew (with the work
 * vectors) only when J's pattern changed. */
static PetscErrorCode Setup(SpamTsApp *app, SpamImexPC *pc, N_Vector y, PetscBool jok, double gamma, PetscBool *jcur)
{
  PetscFunctionBeginUser;
  *jcur = PETSC_FALSE;
  if (!jok || !pc->jac.J) {
    const PetscScalar *ya;
    Vec                at = N_VGetVector_Petsc(y);
    if (pc->ark) { /* the products' J too: at the stage's positions */
      PetscCall(StageState(app, pc, y));
      at = pc->ys;
    }
    PetscCall(VecGetArrayRead(at, &ya));
    PetscCall(app->sim->model.diffusion_jac(app->sim, ya, &pc->jac, &app->bad));
    PetscCall(VecRestoreArrayRead(at, &ya));
    if (app->bad >= 0) PetscFunctionReturn(0);
    *jcur = PETSC_TRUE;
    pc->assemblies++;
  }
  if (!pc->P || pc->patterns != pc->jac.patterns) {
    PetscInt rows;
    PetscCall(MatDestroy(&pc->P));
    PetscCall(VecDestroy(&pc->r));
    PetscCall(VecDestroy(&pc->z));
    PetscCall(MatDuplicate(pc->jac.J, MAT_DO_NOT_COPY_VALUES, &pc->P));
    PetscCall(MatGetSize(pc->P, &rows, NULL));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, NULL, &pc->r));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, NULL, &pc->z));
    pc->patterns = pc->jac.patterns;
  }
  PetscCall(MatCopy(pc->jac.J, pc->P, SAME_NONZERO_PATTERN));
  PetscCall(MatScale(pc->P, -gamma));
  PetscCall(MatShift(pc->P, 1.0));
  PetscCall(KSPSetOperators(pc->ksp, pc->P, pc->P));
  PetscCall(KSPSetUp(pc->ksp)); /* the factorisation, here rather than in the first solve */
  pc->setups++;
  PetscFunctionReturn(0);
}

int SpamImexPCSetup(realtype t, N_Vector y, N_Vector fy, booleantype jok, booleantype *jcur, realtype gamma, void *data)
{
  SpamTsApp *app = (SpamTsApp *)data;
  PetscBool  cur = PETSC_FALSE;

  (void)t;
  (void)fy;
  app->perr = Setup(app, (SpamImexPC *)app->imex_pc, y, (PetscBool)jok, gamma, &cur);
  *jcur     = cur ? SUNTRUE : SUNFALSE;
  return app->perr || app->bad >= 0 ? -1 : 0;
}

/* z = P^-1 r on this rank's rows; a failed KSP is recoverable (ARKODE sets up again with
 * fresh data or a smaller step), on every rank if on one (ARKODE's decisions must agree). */
static PetscErrorCode Solve(SpamImexPC *pc, MPI_Comm comm, N_Vector r, N_Vector z, int *flag)
{
  PetscMPIInt size;

  const PetscScalar *ra;
  PetscScalar       *za;
  KSPConvergedReason reason;
  PetscInt           its;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(N_VGetVector_Petsc(r), &ra));
  PetscCall(VecGetArrayWrite(N_VGetVector_Petsc(z), &za));
  PetscCall(VecPlaceArray(pc->r, (PetscScalar *)(uintptr_t)ra)); /* read only: KSPSolve does not write b */
  PetscCall(VecPlaceArray(pc->z, za));
  PetscCall(KSPSolve(pc->ksp, pc->r, pc->z));
  PetscCall(VecResetArray(pc->r));
  PetscCall(VecResetArray(pc->z));
  PetscCall(VecRestoreArrayWrite(N_VGetVector_Petsc(z), &za));
  PetscCall(VecRestoreArrayRead(N_VGetVector_Petsc(r), &ra));
  PetscCall(KSPGetConvergedReason(pc->ksp, &reason));
  PetscCall(KSPGetIterationNumber(pc->ksp, &its));
  pc->solves++;
  pc->ksp_its += its;
  *flag = reason < 0 ? 1 : 0;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size > 1) PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, flag, 1, MPI_INT, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

int SpamImexPCSolve(realtype t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z, realtype gamma, realtype delta, int lr, void *data)
{
  SpamTsApp *app  = (SpamTsApp *)data;
  int        flag = 0;

  (void)t;
  (void)y;
  (void)fy;
  (void)gamma;
  (void)delta;
  (void)lr;
  app->perr = Solve((SpamImexPC *)app->imex_pc, app->sim->p.comm, r, z, &flag);
  return app->perr ? -1 : flag;
}

PetscErrorCode SpamImexPCPrintStats(const SpamImexPC *pc, FILE *file)
{
  KSPType ktype;
  PCType  ptype;
  PC      p;

  PetscFunctionBeginUser;
  PetscCall(KSPGetType(pc->ksp, &ktype));
  PetscCall(KSPGetPC(pc->ksp, &p));
  PetscCall(PCGetType(p, &ptype));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "Stage preconditioner      = diffusion Jacobian, -%sksp_type %s -%spc_type %s (this rank's rows)\n", SPAM_IMEX_PC_PREFIX, ktype, SPAM_IMEX_PC_PREFIX, ptype ? ptype : "none"));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "Jacobian assemblies       = %ld\n", pc->assemblies));
  if (pc->ark) PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "J v by difference         = %ld\n", pc->jv_dq_products));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "Jacobian patterns         = %ld\n", pc->jac.patterns));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "Preconditioner factorings = %ld\n", pc->setups));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, file, "Preconditioner KSP iters  = %ld\n", pc->ksp_its));
  PetscFunctionReturn(0);
}

/* Which product the linear solve of this Newton iteration takes. J leaves out the
 * positions' columns, and a stage's first iterate stands at the predictor's positions, not
 * the stage's: its Newton step then lacks the positions' pull on v and e, and ARKODE may
 * accept that iterate on the previous stage's convergence rate. So the first linear solve
 * of each stage (a new time or gamma) takes the difference quotient, as ARKStep's own
 * product; from the second on the positions are the stage's and J v stands for it. */
static PetscErrorCode JacTimesSetup(SpamImexPC *pc)
{
  realtype t, gamma;
  N_Vector zpred, z, fi, sdata;
  void    *data;
  int      flag;

  PetscFunctionBeginUser;
  flag = ARKStepGetNonlinearSystemData(pc->ark, &t, &zpred, &z, &fi, &gamma, &sdata, &data);
  PetscCheck(flag == ARK_SUCCESS, PETSC_COMM_SELF, PETSC_ERR_LIB, "ARKStepGetNonlinearSystemData failed: %s", ARKStepGetReturnFlagName(flag));
  pc->jv_dq    = (PetscBool)!(pc->jv_started && t == pc->jv_t && gamma == pc->jv_gamma);
  pc->jv_t     = t;
  pc->jv_gamma = gamma;
  pc->jv_started = PETSC_TRUE;
  if (!pc->jx || pc->jv_patterns != pc->jac.patterns) { /* the product's vectors, J's rows */
    PetscInt rows;
    PetscCall(VecDestroy(&pc->jx));
    PetscCall(VecDestroy(&pc->jy));
    PetscCall(MatGetSize(pc->jac.J, &rows, NULL));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, NULL, &pc->jx));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, rows, NULL, &pc->jy));
    pc->jv_patterns = pc->jac.patterns;
  }
  PetscFunctionReturn(0);
}

int SpamImexPCJacTimesSetup(realtype t, N_Vector y, N_Vector fy, void *data)
{
  SpamTsApp *app = (SpamTsApp *)data;

  (void)t;
  (void)y;
  (void)fy;
  app->perr = JacTimesSetup((SpamImexPC *)app->imex_pc);
  return app->perr ? -1 : 0;
}

/* ARKStep's difference quotient (arkLsDQJtimes): (f(y + sig v) - f(y)) / sig with
 * sig = 1/|v| in the error weights. */
static int DifferenceQuotient(SpamTsApp *app, SpamImexPC *pc, N_Vector v, N_Vector Jv, realtype t, N_Vector y, N_Vector fy, N_Vector work)
{
  double sig;
  int    flag;

  if (!pc->ewt) {
    pc->ewt = N_VClone(y);
    if (!pc->ewt) return -1;
  }
  flag = ARKStepGetErrWeights(pc->ark, pc->ewt);
  if (flag != ARK_SUCCESS) return -1;
  sig = 1.0 / N_VWrmsNorm(v, pc->ewt);
  N_VLinearSum(sig, v, 1.0, y, work);
  flag = SpamSundialsRhsDiffusion(t, work, Jv, app);
  if (flag) return flag;
  N_VLinearSum(1.0 / sig, Jv, -1.0 / sig, fy, Jv);
  pc->jv_dq_products++;
  return 0;
}

/* J v from the assembled J: a sparse product where the difference quotient evaluates the
 * diffusion part. */
static PetscErrorCode JacTimes(SpamImexPC *pc, N_Vector v, N_Vector Jv)
{
  const PetscScalar *va;
  PetscScalar       *ja;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(N_VGetVector_Petsc(v), &va));
  PetscCall(VecGetArrayWrite(N_VGetVector_Petsc(Jv), &ja));
  PetscCall(VecPlaceArray(pc->jx, (PetscScalar *)(uintptr_t)va)); /* read only: MatMult does not write x */
  PetscCall(VecPlaceArray(pc->jy, ja));
  PetscCall(MatMult(pc->jac.J, pc->jx, pc->jy));
  PetscCall(VecResetArray(pc->jx));
  PetscCall(VecResetArray(pc->jy));
  PetscCall(VecRestoreArrayWrite(N_VGetVector_Petsc(Jv), &ja));
  PetscCall(VecRestoreArrayRead(N_VGetVector_Petsc(v), &va));
  PetscFunctionReturn(0);
}

int SpamImexPCJacTimes(N_Vector v, N_Vector Jv, realtype t, N_Vector y, N_Vector fy, void *data, N_Vector tmp)
{
  SpamTsApp  *app = (SpamTsApp *)data;
  SpamImexPC *pc  = (SpamImexPC *)app->imex_pc;

  if (pc->jv_dq) return DifferenceQuotient(app, pc, v, Jv, t, y, fy, tmp);
  app->perr = JacTimes(pc, v, Jv);
  return app->perr ? -1 : 0;
}
