/* The norm in which every adaptive method holds its weighted local error estimate to 1
 * (-error_norm): rms, sqrt(sum (e_i w_i)^2 / L), the default of SUNDIALS and PETSc, or
 * max, max_i |e_i w_i|. The rms norm divides by the length L of the state, so an error
 * confined to a few particles passes with a factor up to sqrt(L) more than the max norm
 * lets through; the max norm holds every particle to its tolerance whatever N is. */
#ifndef SPAM_ERROR_NORM_H
#define SPAM_ERROR_NORM_H
#include <petscts.h>
#include <sundials/sundials_nvector.h>

typedef enum { SPAM_ERROR_NORM_RMS, SPAM_ERROR_NORM_MAX } SpamErrorNorm;
extern const char *const SpamErrorNormNames[]; /* "rms", "max" */

/* Reads -error_norm (listed by -help with its default, rms); a bad value is bad input. */
PetscErrorCode SpamErrorNormOptions(MPI_Comm comm, SpamErrorNorm *norm);
/* max_i |x_i w_i| over every rank: the WRMS-norm operation of a PETSc N_Vector under
 * -error_norm max (NaN if PETSc cannot give the arrays, so that the step is rejected). */
realtype SpamNVWeightedMaxNorm_Petsc(N_Vector x, N_Vector w);
/* Gives the PETSc N_Vector y (and every vector SUNDIALS clones from it afterwards) the
 * norm: ERKStep's and CVODE's error tests call N_VWrmsNorm(error, weights). Call after
 * N_VEnableFusedOps_Petsc, whose array norm would otherwise bypass the max norm. */
PetscErrorCode SpamErrorNormAttach(N_Vector y, SpamErrorNorm norm);
/* The same choice for PETSc's step adaptor (its weighted norm type NORM_2 or
 * NORM_INFINITY); a -ts_adapt_wnormtype that says otherwise is bad input. Call after
 * TSSetFromOptions; nothing to do for arkode and cvode, whose vectors carry the norm. */
PetscErrorCode SpamErrorNormSetTS(TS ts, SpamErrorNorm norm);
#endif
