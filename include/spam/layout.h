/* Layout of the packed state: per particle one block of nvar reals. Each field has an
 * offset inside the block, or -1 when the model does not carry it. */
#ifndef SPAM_LAYOUT_H
#define SPAM_LAYOUT_H
#include <petscsys.h>

typedef struct {
  int dim, nvar;
  int x, v, e, rho; /* offsets of position, velocity, energy, density (or -1) */
} SpamLayout;

/* Positions and velocities only: the isentropic gas. */
PetscErrorCode SpamLayoutPositionsVelocities(int dim, SpamLayout *l);
PetscErrorCode SpamLayoutDescribe(const SpamLayout *l, char *buf, size_t len);
#endif
