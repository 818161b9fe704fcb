/* The gas beyond a mirror wall (gas_images.c): what a mirror image of a gas particle
 * carries so that the wall's rows see the gas continued, not reflected.
 *
 * A mirror image copies its source: mass, density, energy, stress (with the walls' rules
 * for velocity, temperature and heat flux). Where the gas is uniform that continues it.
 * Where it is stratified it does not:
 *  - under gravity the image stands deeper in the field than its source, so its pressure
 *    is the hydrostatic continuation P_g = P_i + rho_i g.(x_g - x_i) (every gas scheme);
 *  - in the flow scheme the image also carries the density of its own place: its volume
 *    is its source's (the images continue the arrangement), its density
 *    rho_g = rho_i (T_i + g.(x_g - x_i)) / T_g, which makes P_g = rho_g T_g the pressure
 *    above and T_g the wall's temperature rule. The wall rows' summed density is then the
 *    continued field to first order; with the source's mass it is off by a first-order
 *    term that the transport shift reads as a gradient of volume and turns into a steady
 *    flow at the wall (0.1-0.2 % of the sound speed in the convection cell at rest).
 * The ratio rho_g / rho_i is bounded to [1/2, 2] (a wall whose temperature differs from
 * the gas beside it by more than a factor two). Where it is 1 (an adiabatic wall without
 * gravity) nothing changes. */
#ifndef SPAM_GAS_IMAGES_H
#define SPAM_GAS_IMAGES_H
#include <spam/sim.h>
#include <spam/gas_flow.h>

/* Whether the images carry the density of their place (flow scheme, gas, mirror walls). */
PetscBool SpamGasImagesOfPlace(const SpamSim *sim);
/* rho_g / rho_i of mirror ghost k (the ghost slot n + k) at the gathered temperatures. */
double SpamGasImagesPlaceRatio(const SpamSim *sim, int k);
/* e and T of the local particles from y, gathered to the ghosts with the walls' rules: the
 * tensor path's fields, and what a density pass alone needs for the images' densities. */
PetscErrorCode SpamGasImagesTemperatures(SpamSim *sim, const double *y);
/* The images' masses scaled to their place (before the density walk); the next caller of
 * SpamSimGhostMasses gathers the sources' masses again. */
void SpamGasImagesMasses(SpamSim *sim);
/* The images' densities scaled to their place (after the densities are gathered). */
void SpamGasImagesDensities(SpamSim *sim);
/* The images' sigma/rho^2: the hydrostatic pressure and the background at their place,
 * over their own density (after the stresses are gathered). */
void SpamGasImagesStresses(SpamSim *sim, const SpamBackground *bg);
#endif
