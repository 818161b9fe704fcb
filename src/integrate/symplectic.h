/* Verlet on the interleaved state: the step spam-ark takes for the schemes it registers
 * with PETSc's basicsymplectic (symplectic_step.c), and the kick's force cache that step
 * shares with the kick PETSc's own schemes call (ts_symplectic.c). */
#ifndef SPAM_SYMPLECTIC_H
#define SPAM_SYMPLECTIC_H
#include <spam/integrator.h>

/* A two-stage scheme of spam-ark's: stage k kicks v += c[k] dt a(x), then drifts
 * x += d[k] dt v (PETSc's order within a stage). */
typedef struct {
  const char *name;
  PetscReal   c[2], d[2];
} SpamSympScheme;

/* The scheme named name, or NULL when it is one of PETSc's (ts_symplectic.c). */
const SpamSympScheme *SpamSympSchemeNamed(const char *name);

/* The cache: app->acache holds the force at the positions app->xcache (compact, stride
 * dim) while app->cache_valid. Made once (the particles never change rank under this
 * method). */
PetscErrorCode SpamKickCacheCreate(SpamTsApp *app);
/* Whether the cache holds the force at positions x (stride doubles from one particle to
 * the next), bit for bit (same: the caller knows the bits are the cache's, nothing is
 * compared); on several ranks only when it does on every rank, so that all evaluate
 * together. */
PetscErrorCode SpamKickCached(SpamTsApp *app, const double *x, int stride, PetscBool same, PetscBool *cached);
/* The force at x into sim->pair.f.acc (one right-hand-side evaluation). *ok false: a
 * particle went bad, booked in app (the loop reports it after the step), the cached force
 * zeroed so that the step ends on it, the cache no longer valid. */
PetscErrorCode SpamKickEvaluate(SpamTsApp *app, double t, const double *x, int stride, PetscBool *ok);
/* After a good evaluation at x: the cache holds it (what the step's own kick does in the
 * same pass as its kick). */
PetscErrorCode SpamKickKeep(SpamTsApp *app, const double *x, int stride);

/* TSStep of the schemes SpamSympSchemeNamed knows, on the state vector itself. */
PetscErrorCode SpamSymplecticStep(TS ts);
#endif
