/* The model: which physics a scene switches on. It fixes the state layout and which
 * right-hand-side passes run. */
#ifndef SPAM_MODEL_H
#define SPAM_MODEL_H
#include <spam/kernel.h>
#include <spam/layout.h>
#include <spam/eos.h>

struct SpamSim;

/* The right-hand side of a model: ydot = f(y) on raw arrays of n*nvar reals. Sets *bad to
 * the first particle with a non-finite or unphysical state (else -1) and returns 0. */
typedef PetscErrorCode (*SpamRhsFn)(struct SpamSim *sim, const double *y, double *ydot, PetscInt *bad);
/* Accelerations from positions alone, into sim->acc (models whose state is r and v only:
 * the force half of a symplectic split). x has stride 'stride' between particles. */
typedef PetscErrorCode (*SpamAccelFn)(struct SpamSim *sim, const double *x, int stride, PetscInt *bad);

/* Largest sound speed of state y (for the CFL step bound and the error weights). */
typedef PetscErrorCode (*SpamSoundSpeedFn)(struct SpamSim *sim, const double *y, double *cmax);

typedef struct {
  char             name[32];     /* e.g. "isentrope"                                  */
  SpamRhsFn        rhs;
  SpamAccelFn      accel;        /* NULL unless the state is exactly [x, v]            */
  SpamSoundSpeedFn max_sound_speed;
  int              dim;
  double           mass;
  SpamKernel       kernel;
  SpamEosIsentrope eos;
  PetscBool        density_free; /* force pass only, no density pass */
  SpamLayout       layout;
} SpamModel;

PetscErrorCode SpamModelIsentropeSetUp(int dim, double h, double mass, double gamma, double kappa, SpamModel *m);
#endif
