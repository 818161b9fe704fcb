/* The model: which physics a scene switches on. It fixes the state layout and which
 * right-hand-side passes run. */
#ifndef SPAM_MODEL_H
#define SPAM_MODEL_H
#include <spam/kernel.h>
#include <spam/layout.h>
#include <spam/eos.h>

typedef struct {
  int              dim;
  double           mass;
  SpamKernel       kernel;
  SpamEosIsentrope eos;
  PetscBool        density_free; /* force pass only, no density pass */
  SpamLayout       layout;
} SpamModel;

PetscErrorCode SpamModelIsentropeSetUp(int dim, double h, double mass, double gamma, double kappa, SpamModel *m);
#endif
