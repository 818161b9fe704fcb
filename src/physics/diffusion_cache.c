/* The diffusion part's position fields kept between its evaluations (diffusion_cache.h). */
#include <string.h>
#include <spam/sim.h>
#include <spam/diffusion_cache.h>
#include <spam/gas_images.h>

PetscBool SpamDiffusionCacheApplies(const SpamSim *sim, PetscBool heatlin)
{
  PetscMPIInt size;
  if (!sim->pair.dcache.enabled) return PETSC_FALSE;
  if (heatlin || sim->pair.f.adaptive || sim->model.solid.density != SPAM_DENSITY_SUMMATION) return PETSC_FALSE;
  if (sim->model.layout.h >= 0) return PETSC_FALSE;
  if (MPI_Comm_size(sim->p.comm, &size) || size != 1) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* The images' density ratios to their sources (1 but beside an isothermal wall or under
 * gravity, where they follow the temperatures): part of the key with the positions. */
static double Ratio(const SpamSim *sim, int k)
{
  const SpamGhosts *gh = &sim->pair.nl.ghosts;
  return SpamGasImagesOfPlace(sim) && gh->kind[k] == SPAM_GHOST_MIRROR ? SpamGasImagesPlaceRatio(sim, k) : 1.0;
}

static PetscBool SamePositions(const SpamDiffusionCache *c, const SpamSim *sim, int slots, int dim)
{
  const SpamNeighbours *nl = &sim->pair.nl;
  const int             n  = (int)sim->p.n;
  if (!c->valid || c->build != nl->builds || c->slots != slots || c->dim != dim || c->n != n) return PETSC_FALSE;
  for (int d = 0; d < dim; d++)
    if (memcmp(c->u[d], nl->u[d], (size_t)slots * sizeof(double))) return PETSC_FALSE;
  for (int k = 0; k < slots - n; k++)
    if (Ratio(sim, k) != c->ratio[k]) return PETSC_FALSE;
  return PETSC_TRUE;
}

void SpamDiffusionCacheRestore(SpamSim *sim, PetscBool *hit)
{
  SpamDiffusionCache *c   = &sim->pair.dcache;
  SpamFields         *f   = &sim->pair.f;
  const int           dim = f->dim, slots = SpamNeighboursSlots(&sim->pair.nl);

  *hit = SamePositions(c, sim, slots, dim);
  if (!*hit) {
    c->misses++;
    return;
  }
  c->hits++;
  if (SpamGasImagesOfPlace(sim)) SpamGasImagesMasses(sim); /* as the density pass scales them */
  memcpy(f->rho, c->rho, (size_t)slots * sizeof(double));
  memcpy(f->lapn, c->lapn, (size_t)slots * sizeof(double));
  memcpy(f->gmom, c->gmom, (size_t)c->n * dim * dim * sizeof(double));
}

PetscErrorCode SpamDiffusionCacheKeep(SpamSim *sim)
{
  SpamDiffusionCache *c   = &sim->pair.dcache;
  const SpamFields   *f   = &sim->pair.f;
  const int           dim = f->dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);

  PetscFunctionBeginUser;
  if ((size_t)slots > c->cap) { /* the list grew (the fields grew with it) */
    const size_t cap = (size_t)slots + (size_t)slots / 4 + 16;
    PetscCall(SpamDiffusionCacheDestroy(c));
    for (int d = 0; d < 3; d++) PetscCall(PetscMalloc1(cap, &c->u[d]));
    PetscCall(PetscMalloc4(cap, &c->rho, cap, &c->lapn, cap * 9, &c->gmom, cap, &c->ratio));
    c->cap = cap;
  }
  for (int d = 0; d < dim; d++) memcpy(c->u[d], sim->pair.nl.u[d], (size_t)slots * sizeof(double));
  memcpy(c->rho, f->rho, (size_t)slots * sizeof(double));
  memcpy(c->lapn, f->lapn, (size_t)slots * sizeof(double));
  memcpy(c->gmom, f->gmom, (size_t)n * dim * dim * sizeof(double));
  for (int k = 0; k < slots - n; k++) c->ratio[k] = Ratio(sim, k);
  c->slots = slots;
  c->n     = n;
  c->dim   = dim;
  c->build = sim->pair.nl.builds;
  c->valid = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDiffusionCacheDestroy(SpamDiffusionCache *c)
{
  PetscFunctionBeginUser;
  for (int d = 0; d < 3; d++) PetscCall(PetscFree(c->u[d]));
  PetscCall(PetscFree4(c->rho, c->lapn, c->gmom, c->ratio));
  c->cap   = 0;
  c->valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}
