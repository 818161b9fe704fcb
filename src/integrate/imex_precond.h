/* The preconditioner of -ts_type arkode_imex's stage systems (-arkode_imex_pc diffusion):
 * P = I - gamma J, J the diffusion part's assembled Jacobian (spam/diffusion_jacobian.h),
 * solved by a PETSc KSP of options prefix -imex_pc_ (ILU(0) applied once by default). Each
 * rank solves its own particles' rows: block Jacobi across ranks. */
#ifndef SPAM_IMEX_PRECOND_H
#define SPAM_IMEX_PRECOND_H
#include <petscksp.h>
#include <spam/integrator.h>
#include <spam/diffusion_jacobian.h>
#include "ts_family.h"
#include <sundials/sundials_nvector.h>

#define SPAM_IMEX_PC_PREFIX SPAM_IMEX_PC_PREFIX_TEXT

typedef struct {
  KSP              ksp;
  Mat              P;        /* I - gamma J, J's pattern                          */
  Vec              r, z;     /* the local rows, on the N_Vectors' arrays          */
  SpamDiffusionJac jac;
  long             patterns; /* jac.patterns when P was made                      */
  long             setups, assemblies, solves, ksp_its;
  /* -arkode_imex_jv assembled (ark set): J v from jac.J but in a stage's first solve */
  void            *ark;      /* the ARKStep memory (the stage's data)             */
  Vec              ys;       /* the state J is assembled at                       */
  Vec              jx, jy;   /* J's rows, on the N_Vectors' arrays                */
  N_Vector         ewt;      /* the error weights (the difference quotient's)     */
  long             jv_patterns, jv_dq_products;
  double           jv_t, jv_gamma; /* the stage of the last linear solve          */
  PetscBool        jv_started, jv_dq; /* this solve takes the difference quotient */
} SpamImexPC;

/* The KSP with its prefix and defaults, then its options (listed by -help). */
PetscErrorCode SpamImexPCCreate(SpamImexPC *pc);
/* -help when the preconditioner is not in use: its KSP's options all the same. */
PetscErrorCode SpamImexPCHelp(void);
PetscErrorCode SpamImexPCDestroy(SpamImexPC *pc);
/* ARKODE's preconditioner callbacks (ARKLsPrecSetupFn, ARKLsPrecSolveFn); user data: the
 * SpamTsApp, whose imex_pc is the SpamImexPC. */
int SpamImexPCSetup(realtype t, N_Vector y, N_Vector fy, booleantype jok, booleantype *jcur, realtype gamma, void *data);
int SpamImexPCSolve(realtype t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z, realtype gamma, realtype delta, int lr, void *data);
/* ARKLsJacTimesSetupFn and ARKLsJacTimesVecFn (-arkode_imex_jv assembled): J v from the
 * assembled J instead of a difference quotient, but in each stage's first linear solve. */
int SpamImexPCJacTimesSetup(realtype t, N_Vector y, N_Vector fy, void *data);
int SpamImexPCJacTimes(N_Vector v, N_Vector Jv, realtype t, N_Vector y, N_Vector fy, void *data, N_Vector tmp);
/* Its counters, in the style of SUNDIALS' statistics table. */
PetscErrorCode SpamImexPCPrintStats(const SpamImexPC *pc, FILE *file);
#endif
