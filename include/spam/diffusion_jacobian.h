/* The Jacobian of the diffusion part (model.h's SPAM_RHS_DIFFUSION) with respect to the
 * state, for -ts_type arkode_imex's stage systems (a preconditioner's matrix, and with
 * -arkode_imex_jv assembled the products J v themselves). The part is the pair Laplacians
 * of viscosity and conduction (pair_diffusion.h) at the positions and densities of the
 * state, which that part leaves fixed: linear in v and T = (gamma - 1) e but for the
 * viscous force's work, which heats by the square of the velocity differences, and the
 * walls' books, which take a mirror image's exchanges. The matrix holds the derivatives in
 * v and e at the state: per pair, velocity component by component and energy by energy,
 * the work's in the energies' rows and the velocities' columns, and a mirror image's in its
 * source's book rows (work, heat, impulse); the images' rules (a wall's image moves or
 * heats against its source) taken as the coefficient of the source. The positions' and
 * densities' columns are left out (they stay fixed within a stage). Rows and columns are
 * this rank's particles only: the pairs with other ranks' particles keep their diagonal
 * terms and drop the column (block Jacobi across ranks). Rows of the other variables
 * (positions, density, the flow book) are zero. */
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
