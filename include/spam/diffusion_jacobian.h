/* The Jacobian of the diffusion part (model.h's SPAM_RHS_DIFFUSION) with respect to the
 * state, for a preconditioner of the implicit stages of -ts_type arkode_imex. The part is
 * the pair Laplacians of viscosity and conduction (pair_diffusion.h) at the positions and
 * densities of the state, which that part leaves fixed; it is linear in v and T = (gamma-1) e
 * but for the viscous force's work, which heats by the square of the velocity differences.
 * The matrix holds the linear part: per pair, velocity component by component and energy
 * by energy, the images' rules (a wall's image moves or heats against its source) taken
 * as the coefficient of the source; the work's dependence on v is left out (the Krylov
 * method's own products carry it). Rows and columns are this rank's particles only: the
 * pairs with other ranks' particles keep their diagonal term and drop the column (block
 * Jacobi across ranks). Rows of the other variables (positions, density, books) are zero. */
#ifndef SPAM_DIFFUSION_JACOBIAN_H
#define SPAM_DIFFUSION_JACOBIAN_H
#include <petscmat.h>

struct SpamSim;

typedef struct {
  Mat       J;           /* SEQAIJ, n nvar rows: the pattern of the list's pairs            */
  PetscInt *nnz;         /* [rows] preallocation                                          */
  double   *coef, *ones; /* [slots (dim + 1)] images' coefficients; [slots dim] scratch    */
  int       rows_cap, slots_cap;
  long      builds;      /* the list's build whose pattern J holds (-1: none)             */
  size_t    npairs, ngpairs;
  int       n, slots;
  long      patterns;    /* matrices made (a new pattern each)                            */
} SpamDiffusionJac;

/* Assembles J at state y (the local n nvar values), making the matrix anew only where the
 * neighbour list's pattern changed since the last call. *bad as for the right-hand side.
 * Collective on several ranks (the ghosts' gathers). */
PetscErrorCode SpamDiffusionJacAssemble(struct SpamSim *sim, const double *y, SpamDiffusionJac *jac, PetscInt *bad);
PetscErrorCode SpamDiffusionJacDestroy(SpamDiffusionJac *jac);
#endif
