/* Hooke's law in rate form with the rotation terms (PRE Sec. II; the printed text drops the
 * dots: these are stress rates, a Jaumann-type correction that makes a rigidly rotating
 * stress turn with the body), in D dimensions:
 *   dsigma/dt = lambda (div v) I + eta (G + G^T) + Omega sigma - sigma Omega,
 * G^{ab} = dv^b/dx^a, Omega_ab = (dv_a/dx_b - dv_b/dx_a)/2. In 2D this is
 *   dsxx/dt = lambda div v + 2 eta dvx/dx - 2 w sxy,  dsxy/dt = eta (dvx/dy + dvy/dx) + w (sxx - syy),
 *   dsyy/dt = lambda div v + 2 eta dvy/dy + 2 w sxy,   w = (dvy/dx - dvx/dy)/2. */
#include <spam/stress.h>

void SpamStressUnpack(int dim, const double *s, double *S)
{
  for (int a = 0; a < dim; a++)
    for (int b = a; b < dim; b++) S[a * dim + b] = S[b * dim + a] = s[SpamStressIndex(dim, a, b)];
}

void SpamHookeStressRate(int dim, double lambda, double eta, const double *g, const double *s, double *rate)
{
  double S[9], div = 0.0;

  SpamStressUnpack(dim, s, S);
  for (int a = 0; a < dim; a++) div += g[a * dim + a];
  for (int a = 0; a < dim; a++)
    for (int b = a; b < dim; b++) {
      double r = eta * (g[a * dim + b] + g[b * dim + a]) + (a == b ? lambda * div : 0.0);
      for (int c = 0; c < dim; c++) { /* (Omega S - S Omega)_ab */
        const double om_ac = 0.5 * (g[c * dim + a] - g[a * dim + c]), om_cb = 0.5 * (g[b * dim + c] - g[c * dim + b]);
        r += om_ac * S[c * dim + b] - S[a * dim + c] * om_cb;
      }
      rate[SpamStressIndex(dim, a, b)] = r;
    }
}
