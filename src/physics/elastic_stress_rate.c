/* Hooke's law in rate form with the rotation terms (PRE Sec. II; the printed text drops
 * the dots: these are stress rates, a Jaumann-type correction that makes a rigidly
 * rotating stress turn with the body, sigma_xy = cos 2wt, sigma_xx = -sin 2wt):
 *   dsxx/dt = lambda div v + 2 eta dvx/dx - 2 w sxy
 *   dsyy/dt = lambda div v + 2 eta dvy/dy + 2 w sxy
 *   dsxy/dt = eta (dvx/dy + dvy/dx) + w (sxx - syy),   w = (dvy/dx - dvx/dy)/2. */
#include <spam/physics.h>

void SpamElasticStressRate(const SpamSim *sim, const double *y, const double *gradv, double *ydot)
{
  const SpamLayout *l = &sim->model.layout;
  const double      lambda = sim->model.solid.lambda, eta = sim->model.solid.eta;

  for (PetscInt i = 0; i < sim->n; i++) {
    const double *g = gradv + 4 * i; /* g[2a+b] = dv^b/dx^a */
    const double *s = y + (size_t)i * l->nvar + l->s;
    double       *r = ydot + (size_t)i * l->nvar + l->s;
    const double  div = g[0] + g[3], w = 0.5 * (g[1] - g[2]);
    r[0] = lambda * div + 2.0 * eta * g[0] - 2.0 * w * s[1];
    r[1] = eta * (g[2] + g[1]) + w * (s[0] - s[2]);
    r[2] = lambda * div + 2.0 * eta * g[3] + 2.0 * w * s[1];
  }
}
