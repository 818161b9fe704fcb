/* Mirror walls on the faces of the box (CiSE 2001, Fig. 4). Each particle within the list
 * range of a wall makes an image particle beyond it: a ghost slot (ghosts.h) with the
 * mirrored position, whose velocity and temperature are those the wall prescribes:
 *   no-slip    v_g = 2 v_w - v_i   (mirrored relative to the wall's own velocity v_w)
 *   free-slip  v_g = v_i with the normal component reversed
 *   isothermal T_g = 2 T_w - T_i   (the interpolated temperature at the wall is T_w)
 *   adiabatic  T_g = T_i           (no heat crosses the wall)
 * and whose density, energy (pressure) and mass are the source's. The fluxes follow the
 * same conditions: the shear stress is continued through a no-slip wall and reversed at a
 * free-slip one; the heat flux's normal component is continued through an isothermal
 * wall and reversed at an adiabatic one. What the ghost's pairs do to it is the wall's
 * reaction: it is not folded back but booked (momentum, work and heat exchanged). */
#ifndef SPAM_WALLS_H
#define SPAM_WALLS_H
#include <petscsys.h>

/* Faces f = 2 d + side (side 0: the lower face of direction d, 1: the upper). */
#define SPAM_FACES 6
typedef enum { SPAM_WALL_NONE, SPAM_WALL_NOSLIP, SPAM_WALL_FREESLIP } SpamWallSlip;
extern const char *const SpamWallSlipNames[];  /* "none", "noslip", "freeslip"        */
extern const char *const SpamFaceNames[];      /* "xlo", "xhi", "ylo", "yhi", ...     */

typedef struct {
  SpamWallSlip slip[SPAM_FACES];
  double       velocity[SPAM_FACES][3]; /* no-slip: the wall's own (tangential) velocity */
  PetscBool    isothermal[SPAM_FACES];  /* else adiabatic                                */
  double       temperature[SPAM_FACES]; /* isothermal: T_w, with T = (gamma - 1) e        */
  /* Which were given as options (-wall_F, -wall_F_velocity, -wall_F_temperature): a scene
   * fills the faces it needs only where the user gave nothing. */
  PetscBool slip_given[SPAM_FACES], velocity_given[SPAM_FACES], temperature_given[SPAM_FACES];
} SpamWalls;

/* Reads -wall_F noslip|freeslip|none, -wall_F_velocity and -wall_F_temperature for the
 * faces of dim dimensions (with -help: every face). */
PetscErrorCode SpamWallsOptions(int dim, SpamWalls *w);
/* Whether face f has a wall, whether any face has. */
static inline PetscBool SpamWallOn(const SpamWalls *w, int f)
{
  return (PetscBool)(w->slip[f] != SPAM_WALL_NONE);
}
PetscBool SpamWallsAny(const SpamWalls *w, int dim);
/* The temperature of a ghost of source temperature T mirrored in face f. */
static inline double SpamWallGhostTemperature(const SpamWalls *w, int f, double T)
{
  return w->isothermal[f] ? 2.0 * w->temperature[f] - T : T;
}
#endif
