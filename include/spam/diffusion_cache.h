/* The diffusion part's position fields, kept between its evaluations (IMEX). Within a
 * stage's Newton iterations and GMRES products the diffusion part is evaluated again and
 * again at the same positions (it moves none, and with the minimum-correction predictor
 * the stage's positions are fixed from its first iterate): the summed densities and the
 * moment that normalises the pair Laplacian, two of its three pair walks, depend on the
 * positions alone there, so they are kept and reused while every slot's position is
 * bitwise the same, in the same list build, and so is every mirror image's density ratio
 * to its source (gas_images.h: 1 beside an adiabatic wall without gravity, else it
 * follows the temperatures). Reuse gives the bits a fresh computation would. Kept only
 * where nothing else enters those fields: summed density, one smoothing length, no
 * linear conduction correction (its gradient reads T), one rank (a rank that reuses would skip the halo's
 * exchange of densities its neighbours make). */
#ifndef SPAM_DIFFUSION_CACHE_H
#define SPAM_DIFFUSION_CACHE_H
#include <petscsys.h>

typedef struct {
  double   *u[3];       /* [slots] box-local positions of the kept fields        */
  double   *rho, *lapn; /* [slots] densities and the Laplacian's norms           */
  double   *gmom;       /* [n * dim * dim] the local particles' moments           */
  double   *ratio;      /* [slots - n] the ghosts' density ratios to their sources */
  size_t    cap;        /* room of the slot arrays (gmom: cap * 9)               */
  int       slots, n, dim;
  long      build;      /* the list build of the kept fields                      */
  PetscBool valid;
  PetscBool enabled;    /* set by the IMEX type (-arkode_imex_reuse_fields)       */
  long      hits, misses; /* statistics (-sundials_stats)                         */
} SpamDiffusionCache;

struct SpamSim;
/* PETSC_TRUE when the fields may be kept for this evaluation at all (see above). */
PetscBool SpamDiffusionCacheApplies(const struct SpamSim *sim, PetscBool heatlin);
/* At a hit (positions and build as kept) copies the kept fields into sim->pair.f and
 * sets *hit; otherwise leaves them. Call after the list update of the evaluation. */
void SpamDiffusionCacheRestore(struct SpamSim *sim, PetscBool *hit);
/* Keeps the fields the evaluation has just computed (grows at list growth only). */
PetscErrorCode SpamDiffusionCacheKeep(struct SpamSim *sim);
PetscErrorCode SpamDiffusionCacheDestroy(SpamDiffusionCache *c);
#endif
