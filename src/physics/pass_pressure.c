/* The isentropic gas's density and force passes through the pair driver (pair_walk.h):
 * any kernel, unequal masses and ghost slots. The chunked, vectorised loops of
 * rhs_isentrope.c serve the common case (Lucy's kernel, equal masses, no ghosts) and
 * give the same sums to round-off (test_pair_reference compares them). */
#include <spam/sim.h>
#include "../pair/pair_walk.h"
#include "../pair/pair_density.h"
#include "../pair/pair_pressure_force.h"

static inline __attribute__((always_inline)) void DensityPair(const int dim, SpamFields *f, int i, int j, const double dx[3], double r2, double w, double g)
{
  (void)dim;
  (void)dx;
  (void)r2;
  (void)g;
  SpamPairDensity(f, i, j, w);
}
SPAM_PAIR_WALK(WalkDensity, SpamFields, DensityPair)

static inline __attribute__((always_inline)) void ForcePair(const int dim, SpamFields *f, int i, int j, const double dx[3], double r2, double w, double g)
{
  (void)r2;
  (void)w;
  SpamPairPressureForce(dim, f, i, j, dx, g);
}
SPAM_PAIR_WALK(WalkForce, SpamFields, ForcePair)

PetscErrorCode SpamPressureDensityWalk(SpamSim *sim)
{
  SpamFields *f     = &sim->f;
  const int   slots = SpamNeighboursSlots(&sim->nl);

  PetscFunctionBeginUser;
  for (int i = 0; i < slots; i++) f->rho[i] = i < sim->n ? f->m[i] * sim->model.kernel.wnorm : 0.0;
  PetscCall(WalkDensity(&sim->nl, &sim->model.kernel, f));
  SpamGhostsFold(&sim->nl.ghosts, f->dim, (int)sim->n, 1, SPAM_GHOST_SCALAR, f->rho);
  PetscCall(SpamGhostsGather(&sim->nl.ghosts, f->dim, (int)sim->n, 1, SPAM_GHOST_SCALAR, f->rho));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamPressureForceWalk(SpamSim *sim)
{
  SpamFields  *f   = &sim->f;
  const size_t len = (size_t)SpamNeighboursSlots(&sim->nl) * f->dim;

  PetscFunctionBeginUser;
  for (size_t k = 0; k < len; k++) f->acc[k] = 0.0;
  PetscCall(WalkForce(&sim->nl, &sim->model.kernel, f));
  SpamGhostsFold(&sim->nl.ghosts, f->dim, (int)sim->n, f->dim, SPAM_GHOST_VECTOR, f->acc);
  /* The isentrope's walls: their forces only (its energy has no equation to book work in). */
  if (sim->nl.ghosts.mirror) PetscCall(SpamWallBooks(&sim->nl.ghosts, f, &sim->model.layout, (int)sim->n, PETSC_FALSE, &sim->wall_rates, NULL));
  PetscFunctionReturn(0);
}
