/* Layout of the packed state: per particle one block of nvar reals. Each field has an
 * offset inside the block, or -1 when the model does not carry it. */
#ifndef SPAM_LAYOUT_H
#define SPAM_LAYOUT_H
#include <petscsys.h>

#define SPAM_MAX_NVAR 24

typedef struct {
  int dim, nvar;
  int x, v, e, rho; /* offsets of position, velocity, energy, density (or -1)          */
  int s;            /* offset of the stress, D(D+1)/2 components: the upper triangle     */
                    /* row by row (2D: xx xy yy; 3D: xx xy xz yy yz zz), or -1           */
  int fb;           /* offset of the flow scheme's energy book (gas_flow.h), or -1     */
  int h;            /* offset of the kernel range h_i (-smoothing_length evolved), or -1 */
  int wb;           /* offset of the wall books (walls.h), or -1: the work and heat the  */
                    /* walls gave this particle's ghosts' partners and their impulse (D) */
  /* Error-weight scale of every component other than x and v: a component y is weighed
   * 1/(rtol max(|y|, scale) + atol), so a field near zero (stress at rest) is measured
   * against its natural size rather than against atol alone. */
  double scale[SPAM_MAX_NVAR];
} SpamLayout;

/* Positions and velocities only: the isentropic gas. */
PetscErrorCode SpamLayoutPositionsVelocities(int dim, SpamLayout *l);
/* Tensor path: [x v e (rho) (stress)]; rho only when it is integrated
 * (continuity density), the stress only for the elastic solid (a gas has P(rho, e)). rho_scale and stress_scale set the error weights of those fields
 * (energy per mass is weighed against stress_scale / rho_scale). */
PetscErrorCode SpamLayoutSolid(int dim, PetscBool with_rho, PetscBool with_stress, double rho_scale, double stress_scale, SpamLayout *l);
/* Appends the kernel range h_i (-smoothing_length evolved), weighed against h0. */
PetscErrorCode SpamLayoutAddSmoothing(SpamLayout *l, double h0);
/* Appends the wall books [work heat impulse(D)] to a tensor-path layout: integrated with
 * the state, so that E(t) - E(0) = work + heat to the integrator's accuracy; they take no
 * part in the error control (their weight is zero). */
PetscErrorCode SpamLayoutAddWallBooks(SpamLayout *l);
/* Appends the gas flow scheme's energy book (one value: the energy its laws gave the
 * particle per unit mass), integrated with the state like the wall books. */
PetscErrorCode SpamLayoutAddFlowBook(SpamLayout *l);
PetscErrorCode SpamLayoutDescribe(const SpamLayout *l, char *buf, size_t len);
/* Sets the error weights w of the fields other than x and v of one particle's block p. */
void SpamLayoutFieldWeights(const SpamLayout *l, const double *p, double rtol, double atol, double *w);
#endif
