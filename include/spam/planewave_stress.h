/* The initial stress of the plane-wave scene: SPAM's own strain of the displaced periodic
 * triangular lattice, put through Hooke's law (src/scenes/planewave_stress.c). */
#ifndef SPAM_PLANEWAVE_STRESS_H
#define SPAM_PLANEWAVE_STRESS_H
#include <spam/kernel.h>

/* A periodic triangular lattice in the order of SpamLatticeTriangular (row-major, nx per
 * row, ny rows, ny even so that a row and its periodic image have the same offset) and
 * the displacement of each of its particles. */
typedef struct {
  PetscInt      nx, ny;
  double        a;        /* lattice spacing                                         */
  const double *x0;       /* reference positions [2 nx ny]                           */
  const double *u;        /* displacements [2 nx ny]                                 */
  double        mass;
  double        lambda, eta;
} SpamDisplacedLattice;

/* Density of the reference lattice by summation, sum_j m w(|l_j|) over the lattice
 * vectors l_j (self included): the pair density rho_ij of a model that sums density. */
double SpamLatticeSummedDensity(const SpamKernel *ker, const SpamDisplacedLattice *L);

/* For every particle i, SPAM's displacement gradient on the reference lattice,
 *   g_i^{ab} = du^b/dx^a = (m / rho_ref) sum_j (u_j - u_i)^b (grad_i w_ij)^a,
 * and from it Hooke's stress sigma_i = lambda tr(eps) I + 2 eta eps, eps = sym(g)
 * ([sxx sxy syy] per particle), the continuity density rho_ref / (1 + tr g) and the
 * elastic energy per unit mass e_i = sigma_i : eps_i / (2 rho_ref). */
void SpamPlanewaveStressSpam(const SpamKernel *ker, const SpamDisplacedLattice *L, double rho_ref, double *sigma, double *rho, double *e);
#endif
