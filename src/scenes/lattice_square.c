/* The unit square (simple-cubic) lattice of the gas scenes on a periodic box. */
#include <spam/scene.h>

void SpamLatticeSquare(int dim, const PetscInt n[], double *x)
{
  PetscInt count = 1;

  for (int d = 0; d < dim; d++) count *= n[d];
  for (PetscInt i = 0; i < count; i++) {
    PetscInt rem = i;
    for (int d = 0; d < dim; d++) { /* x fastest: rows of x, as the expansion lattice */
      x[i * dim + d] = (double)(rem % n[d]) + 0.5;
      rem /= n[d];
    }
  }
}

PetscErrorCode SpamLatticeCube(int dim, PetscInt n, double mass, SpamParticles *out)
{
  PetscInt count = 1, side[3];

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) {
    side[d] = n;
    count *= n;
  }
  PetscCall(SpamParticlesAllocate(dim, count, out));
  out->mass = mass;
  SpamLatticeSquare(dim, side, out->x);
  PetscFunctionReturn(0);
}
