/* Ghost slots: copies of particles that the pair loops see beyond the local ones, at
 * indices n .. n + nghost - 1 of every per-particle array. Each ghost has a source
 * particle and a map from the source's position to its own: x_g = flip * x_src + shift
 * per direction (a periodic image has flip +1 and shift +-L; a mirror image in a wall at
 * W has flip -1 and shift 2W). What a ghost's pairs do to it is folded back onto its
 * source where the ghost stands for the same particle (periodic images: each physical
 * pair is then evaluated once) and dropped where it stands for a boundary (mirror walls:
 * the wall takes the reaction). Other ranks' particles (a later issue) fit the same two
 * operations: gather (sources -> ghosts) before a pass, fold (ghosts -> sources) after. */
#ifndef SPAM_GHOSTS_H
#define SPAM_GHOSTS_H
#include <spam/box.h>
#include <spam/walls.h>

typedef enum { SPAM_GHOST_PERIODIC, SPAM_GHOST_MIRROR } SpamGhostKind;

typedef struct {
  int            n, cap;   /* ghosts, room                                            */
  int           *src;      /* [cap] local source of each ghost                        */
  double        *shift[3]; /* [cap] per direction: x_g = flip x_src + shift            */
  unsigned char *flip;     /* [cap] bit d set: direction d mirrored                    */
  unsigned char *kind;     /* [cap] SpamGhostKind                                      */
  unsigned char *face;     /* [cap] bit d set: mirrored in the upper face of direction d */
  PetscBool      periodic[3]; /* periodic directions made by ghosts (not minimum image) */
  SpamWalls      walls;    /* the mirror walls of the box faces (walls.h)              */
  PetscBool      mirror;   /* some face has a wall                                     */
} SpamGhosts;

PetscErrorCode SpamGhostsDestroy(SpamGhosts *g);
/* Chooses the ghosts of the n local particles at box-local positions u[d][i] (wrapped
 * into the box at a list build): the periodic images, along the directions in
 * g->periodic, and the mirror images in the walls of g->walls, of every particle within
 * `range` of a face (corner images, periodic or mirrored in two or three faces, included).
 * Grows the arrays when needed (at list builds only). */
PetscErrorCode SpamGhostsSelect(SpamGhosts *g, const SpamBox *box, int n, double *const u[3], double range);
/* Positions of the ghost slots from their sources: u[d][n + k] for every ghost k. */
void SpamGhostsPositions(const SpamGhosts *g, int dim, int n, double *const u[3]);
/* Gather: copies ncomp values per particle from each source to its ghost slot (slot
 * n + k). parity: for a vector field (ncomp = dim) the mirrored components change sign;
 * for a symmetric tensor stored D x D the mixed components of one mirrored direction do.
 * Pass SPAM_GHOST_SCALAR, SPAM_GHOST_VECTOR or SPAM_GHOST_TENSOR. */
typedef enum { SPAM_GHOST_SCALAR, SPAM_GHOST_VECTOR, SPAM_GHOST_TENSOR } SpamGhostParity;
/* What a mirror wall prescribes (walls.h) for the fields that carry a boundary condition;
 * periodic images copy them. Velocity (ncomp = dim): no-slip or free-slip. Temperature
 * (ncomp = 1): isothermal or adiabatic. Heat flux (ncomp = dim): its normal component is
 * continued through an isothermal wall and reversed at an adiabatic one, the tangential
 * ones follow the temperature. Stress (D x D): continued through a no-slip wall (the
 * shear it transmits), mirrored at a free-slip one (no shear). */
typedef enum { SPAM_WALL_FIELD_VELOCITY, SPAM_WALL_FIELD_TEMPERATURE, SPAM_WALL_FIELD_HEAT_FLUX, SPAM_WALL_FIELD_STRESS } SpamWallField;
void SpamGhostsGatherWall(const SpamGhosts *g, int dim, int n, SpamWallField what, double *field);
void SpamGhostsGather(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field);
/* Fold: adds each periodic ghost's ncomp accumulated values to its source, and zeroes
 * the slot; mirror ghosts' values are left (the boundary's share). Vector and tensor
 * parities as in gather. */
void SpamGhostsFold(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field);
#endif
