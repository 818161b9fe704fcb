/* The error-controlled bins of the block steps (-block_criterion error): each particle's
 * local error estimate at the end of its step, and the step the controller asks for next.
 *
 * Kick-drift-kick is second order; the embedded lower-order update of a particle is the
 * step with its old rate alone (the kicks of the fields taken with the rate at the step's
 * start, the drift with the start's velocity plus half the step's kick). The difference of
 * the two, dt/2 (r_new - r_old) for every kicked field and dt/2 times the velocity's
 * difference for the position (the drift with the mean of the step's end velocities
 * against KDK's half-kicked one: dt^2/4 (a_new - a_old)), is of order dt^2 |dr/dt|: no
 * evaluation beyond the two the step makes anyway.
 *
 * The estimate is weighed as ARKODE's error (weights.c): positions against rtol h + atol,
 * velocities against rtol max(|v_i|, c0) + atol, the other fields against their declared
 * scales, at the particle's state at the step's end; and measured in -error_norm's norm
 * over the particle's own fields (rms: the square root of the mean square over its nvar
 * fields; max: the largest). Every particle held to 1 holds the whole state's norm to 1
 * in either norm. */
#include "block_kdk.h"

double SpamBlockError(const SpamSim *sim, const SpamBlockErrorCtx *e, const double *p, const double *f, const double *g, double dt, double *w)
{
  const SpamModel  *m   = &sim->model;
  const SpamLayout *l   = &m->layout;
  const int         dim = m->dim;
  const double      wx  = 1.0 / (e->rtol * m->kernel.h + e->atol), half = 0.5 * dt;
  double            v2 = 0.0, sum = 0.0, mx = 0.0;

  for (int d = 0; d < dim; d++) v2 += p[l->v + d] * p[l->v + d];
  SpamLayoutFieldWeights(l, p, e->rtol, e->atol, w); /* the fields after x and v */
  for (int d = 0; d < dim; d++) {
    w[l->x + d] = wx;
    w[l->v + d] = 1.0 / (e->rtol * PetscMax(sqrt(v2), e->vscale) + e->atol);
  }
  for (int k = 0; k < l->nvar; k++) {
    const int    rk = (k >= l->x && k < l->x + dim) ? l->v + (k - l->x) : k; /* a position: its velocity's difference */
    const double dk = half * (g[rk] - f[rk]) * ((k >= l->x && k < l->x + dim) ? half : 1.0);
    const double t  = fabs(dk * w[k]);
    sum += t * t;
    mx = PetscMax(mx, t);
  }
  return e->norm == SPAM_ERROR_NORM_MAX ? mx : sqrt(sum / (double)l->nvar);
}

/* The step the estimate err of a step of length dt asks for next: err is of order dt^2,
 * so dt safety err^(-1/2) would bring it to safety^2 of the tolerance; at most
 * SPAM_BLOCK_GROWTH times longer (one bin up), at least SPAM_BLOCK_SHRINK times dt (also
 * for a non-finite err). */
double SpamBlockErrorStep(double dt, double err)
{
  double fac;

  if (!(err >= 0.0) || isinf(err)) return SPAM_BLOCK_SHRINK * dt;
  fac = err > 0.0 ? SPAM_BLOCK_SAFETY / sqrt(err) : SPAM_BLOCK_GROWTH;
  return dt * PetscMax(SPAM_BLOCK_SHRINK, PetscMin(SPAM_BLOCK_GROWTH, fac));
}
