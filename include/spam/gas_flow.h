/* The flow scheme of the gas (gas_flow.c): what makes a viscous, conducting particle gas
 * flow as a Newtonian fluid where its pressure dominates its viscosity (c h / nu >> 1).
 *
 * The symmetric pair force sum_j m_j (P_i/rho_i^2 + P_j/rho_j^2) grad w_ij has an error
 * of zeroth order in h proportional to the absolute pressure: on a sheared arrangement
 * it acts as a shear stiffness of about 0.02-0.03 P, so a gas at P ~ 1 rings like a soft
 * solid instead of flowing. Two laws, each a named option:
 *  - background pressure: the momentum equation takes P - B(x), B the particles' mean
 *    pressure (without gravity) or its quadratic fit along gravity (a hydrostatic layer),
 *    refitted at every evaluation; B's gradient is put back as a body force, and B's
 *    compression work -B div v / rho stays in the energy equation (div v corrected for the
 *    arrangement, less its volume mean), so the continuum equations are unchanged and
 *    only the stiffness goes;
 *  - transport shifting: without that stiffness nothing keeps the particles ordered, and
 *    where P < B they clump (the tensile instability). The particles move with
 *    v + dv, dv_i = -(C h c_i / V_i) sum_j (V_i^2 + V_j^2) grad_i w_ij, V = m / rho: the
 *    pair force of a unit pressure in volumes (Adami, Hu and Adams's transport velocity),
 *    which vanishes on a lattice of equal volumes and pushes each particle towards more
 *    room, scaled into a diffusion of coefficient ~ C c h; the
 *    fields a particle carries are corrected for its drift relative to the fluid
 *    (dv/dt += (dv . grad) v, de/dt += dv . grad e), as in ALE shifting schemes. The sum
 *    takes the gradient of a kernel whose Fourier transform is positive (model.h's
 *    shift_kernel): with another it runs backwards at the particle scale and pairs them.
 * What each gives up: the background's body force is external where B varies (under
 * gravity); the shifting's drift corrections do not conserve momentum or energy exactly
 * (their totals are booked per particle in the state, layout.h). */
#ifndef SPAM_GAS_FLOW_H
#define SPAM_GAS_FLOW_H
#include <petscsys.h>

/* B(x) = c[0] + c[1] s + c[2] s^2, s = up . (x - origin), up = -g/|g| (degree 0 without
 * gravity: c[1] = c[2] = 0). */
typedef struct {
  double c[3];
  double up[3], origin[3];
} SpamBackground;

static inline double SpamBackgroundHeight(const SpamBackground *b, int dim, const double *x)
{
  double s = 0.0;
  for (int d = 0; d < dim; d++) s += b->up[d] * (x[d] - b->origin[d]);
  return s;
}

static inline double SpamBackgroundAt(const SpamBackground *b, int dim, const double *x)
{
  const double s = SpamBackgroundHeight(b, dim, x);
  return b->c[0] + s * (b->c[1] + s * b->c[2]);
}

/* dB/ds at x (the gradient is this along up). */
static inline double SpamBackgroundSlope(const SpamBackground *b, int dim, const double *x)
{
  return b->c[1] + 2.0 * b->c[2] * SpamBackgroundHeight(b, dim, x);
}
#endif
