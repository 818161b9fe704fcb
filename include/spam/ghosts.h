/* Ghost slots: copies of particles that the pair loops see beyond the local ones, at
 * indices n .. n + nghost - 1 of every per-particle array. Each ghost has a source
 * particle and a map from the source's position to its own: x_g = flip * x_src + shift
 * per direction (a periodic image has flip +1 and shift +-L; a mirror image in a wall at
 * W has flip -1 and shift 2W). What a ghost's pairs do to it is folded back onto its
 * source where the ghost stands for the same particle (periodic images: each physical
 * pair is then evaluated once) and dropped where it stands for a boundary (mirror walls:
 * the wall takes the reaction). Other ranks' particles (halo.h) are the remote ghosts,
 * after the local ones: their source is on another rank (src = -1), gather fills them
 * through the halo's PetscSF, and fold drops them (each rank computes its own particles'
 * pairs with them: no reverse communication). A remote ghost may be the mirror image of
 * another rank's particle (kind SPAM_GHOST_MIRROR, src = -1): the owner sends the source's
 * values and the receiver applies the mirror and the walls' rules to them. */
#ifndef SPAM_GHOSTS_H
#define SPAM_GHOSTS_H
#include <spam/box.h>
#include <spam/walls.h>
#include <spam/halo.h>

typedef enum { SPAM_GHOST_PERIODIC, SPAM_GHOST_MIRROR, SPAM_GHOST_REMOTE } SpamGhostKind;

typedef struct {
  int            n, cap;   /* ghosts, room                                            */
  int            nlocal;   /* ghosts 0 .. nlocal-1 are images of local particles;     */
                           /* nlocal .. n-1 remote (halo.ghost_owner/_index/_shift    */
                           /* [k - nlocal] say whose particle and which image)         */
  int           *src;      /* [cap] local source of each ghost (-1: remote)           */
  double        *rbook;    /* [bcap * 5] the walls' books of remote mirror images      */
  int            bcap;
  double        *shift[3]; /* [cap] per direction: x_g = flip x_src + shift            */
  unsigned char *flip;     /* [cap] bit d set: direction d mirrored                    */
  unsigned char *kind;     /* [cap] SpamGhostKind                                      */
  unsigned char *face;     /* [cap] bit d set: mirrored in the upper face of direction d */
  PetscBool      periodic[3]; /* periodic directions made by ghosts (not minimum image) */
  SpamWalls      walls;    /* the mirror walls of the box faces (walls.h)              */
  double         depth[SPAM_FACES]; /* how far beyond each wall the farthest particle of */
                           /* any rank stood at the last build (0 if none): a particle */
                           /* out there pairs with images from deeper in the box       */
  PetscBool      mirror;   /* some face has a wall                                     */
  SpamHalo       halo;     /* other ranks' particles (inactive on one rank)            */
} SpamGhosts;

PetscErrorCode SpamGhostsDestroy(SpamGhosts *g);
/* Chooses the ghosts of the n local particles at box-local positions u[d][i] (wrapped
 * into the box at a list build): the periodic images, along the directions in
 * g->periodic, and the mirror images in the walls of g->walls, of every particle within
 * `range` of a face (of a wall: range + g->depth; corner images, periodic or mirrored in
 * two or three faces, included).
 * Grows the arrays when needed (at list builds only). */
PetscErrorCode SpamGhostsSelect(SpamGhosts *g, const SpamBox *box, int n, double *const u[3], double range);
/* Collective (halo.h). Appends the remote ghosts of the n local particles at u (wrapped at
 * this build) after the local ghosts: the other ranks' particles and periodic images
 * (along g->periodic) within range of this rank's particles. */
PetscErrorCode SpamGhostsSelectRemote(SpamGhosts *g, const SpamBox *box, int n, double *const u[3], double range);
/* Positions of the ghost slots from their sources: u[d][n + k] for every ghost k; the
 * remote ones arrive from their owners with the shift added (collective). */
PetscErrorCode SpamGhostsPositions(const SpamGhosts *g, int dim, int n, double *const u[3]);
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
 * shear it transmits), mirrored at a free-slip one (no shear). Drift (ncomp = dim): a
 * velocity relative to the fluid's (the flow scheme's transport shift), under the
 * velocity's rule with the wall at rest, so that the fluid's velocity plus the drift has
 * the image the velocity's rule gives their sum. */
typedef enum { SPAM_WALL_FIELD_VELOCITY, SPAM_WALL_FIELD_TEMPERATURE, SPAM_WALL_FIELD_HEAT_FLUX, SPAM_WALL_FIELD_STRESS, SPAM_WALL_FIELD_DRIFT } SpamWallField;
/* Both gathers fill the remote slots from their owners, mirrored as local ghosts are;
 * collective on more than one rank, every rank must call them. */
PetscErrorCode SpamGhostsGatherWall(const SpamGhosts *g, int dim, int n, SpamWallField what, double *field);
PetscErrorCode SpamGhostsGather(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field);
/* Fold: adds each periodic ghost's ncomp accumulated values to its source, and zeroes
 * the slot; mirror ghosts' values are left (the boundary's share), and so are the remote
 * ones' (their owner computes its own pairs). Vector and tensor parities as in gather. */
void SpamGhostsFold(const SpamGhosts *g, int dim, int n, int ncomp, SpamGhostParity parity, double *field);
#endif
