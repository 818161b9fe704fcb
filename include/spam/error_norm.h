/* The norm in which every adaptive method holds its weighted local error estimate to 1
 * (-error_norm): rms, sqrt(sum (e_i w_i)^2 / L), the default of SUNDIALS and PETSc, or
 * max, max_i |e_i w_i|. The rms norm divides by the length L of the state, so an error
 * confined to a few particles passes with a factor up to sqrt(L) more than the max norm
 * lets through; the max norm holds every particle to its tolerance whatever N is. */
#ifndef SPAM_ERROR_NORM_H
#define SPAM_ERROR_NORM_H
#include <petscts.h>
#include <sundials/sundials_nvector.h>
#include <spam/run_record.h> /* SpamErrorNorm */

extern const char *const SpamErrorNormNames[]; /* "rms", "max" */

/* Reads -error_norm (listed by -help with its default, rms); a bad value is bad input. */
PetscErrorCode SpamErrorNormOptions(MPI_Comm comm, SpamErrorNorm *norm);
/* max_i |x_i w_i| over every rank: the WRMS-norm operation of a PETSc N_Vector under
 * -error_norm max (NaN if PETSc cannot give the arrays, so that the step is rejected). */
realtype SpamNVWeightedMaxNorm_Petsc(N_Vector x, N_Vector w);
/* -reproducible's rms norm: sqrt(sum_i (x_i w_i)^2 / N) with bits that do not depend on
 * how the vector is split over ranks. The largest term is all-reduced with MAX (exact in
 * any order); each term is rounded to a fixed-point grid that puts that maximum just
 * below 2^62 / (N + 1) units, the int64 sums of the ranks are added exactly by an
 * MPI_Allreduce SUM, and the total is scaled back. Two reductions per norm. A term below
 * 2^-(62 - log2(N+1)) of the largest is rounded to the grid: the norm's relative error is
 * below N 2^-(63 - log2(N+1)) (1e-7 for 10^6 components, 2e-11 at N = 10^4), far below
 * what an error test resolves. NaN when a term is NaN, infinity when one overflows. */
realtype SpamNVReproducibleWrmsNorm_Petsc(N_Vector x, N_Vector w);
/* Gives the PETSc N_Vector y (and every vector SUNDIALS clones from it afterwards) the
 * norm: ERKStep's and CVODE's error tests call N_VWrmsNorm(error, weights); with
 * reproducible (-reproducible) the rms norm is the partition-independent one above (the
 * max norm is partition-independent as it is). Call after N_VEnableFusedOps_Petsc, whose
 * array norm would otherwise bypass the replaced norm. A new N_Vector (after a migration)
 * needs the call again; clones inherit it. */
PetscErrorCode SpamErrorNormAttach(N_Vector y, SpamErrorNorm norm, PetscBool reproducible);
/* At a fixed step, after SpamErrorNormAttach: the norm of y's vectors returns 0 without
 * reading x when every weight is zero on every rank (weights.c's zero weights), and is the
 * attached norm otherwise. ARKODE then reads the norm only for its "too much accuracy"
 * test, uround * norm > 1, which 0 passes as the norm of zero weights (0, or NaN for a
 * non-finite x) does: the same runs, without a pass over the state a step (at 34
 * instructions a component, 4 % of a gas run's instructions). */
PetscErrorCode SpamErrorNormZeroWeights(N_Vector y, SpamErrorNorm norm, PetscBool reproducible);
/* The same choice for PETSc's step adaptor (its weighted norm type NORM_2 or
 * NORM_INFINITY); a -ts_adapt_wnormtype that says otherwise is bad input. Call after
 * TSSetFromOptions; nothing to do for arkode and cvode, whose vectors carry the norm. */
PetscErrorCode SpamErrorNormSetTS(TS ts, SpamErrorNorm norm);
#endif
