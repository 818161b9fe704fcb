/* Translation-invariant error weights (ARKODE's ARKEwtFn). */
#ifndef SPAM_WEIGHTS_H
#define SPAM_WEIGHTS_H
#include <sundials/sundials_nvector.h>
#include <spam/sim.h>

typedef struct {
  const SpamSim *sim;
  double         rtol, atol;
  double         vscale; /* declared velocity scale: the initial sound speed */
  /* a fixed step: no error test reads the weights (weights.c); the array last zeroed */
  int            fixed_step;
  const void    *zeroed;
} SpamWeightsCtx;

int SpamErrorWeights(N_Vector y, N_Vector ewt, void *ctx);
#endif
