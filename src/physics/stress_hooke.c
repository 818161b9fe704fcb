/* Hooke's law in rate form with the rotation terms (PRE Sec. II; the printed text drops the
 * dots: these are stress rates, a Jaumann-type correction that makes a rigidly rotating
 * stress turn with the body), in D dimensions:
 *   dsigma/dt = lambda (div v) I + eta (G + G^T) + Omega sigma - sigma Omega,
 * G^{ab} = dv^b/dx^a, Omega_ab = (dv_a/dx_b - dv_b/dx_a)/2. In 2D this is
 *   dsxx/dt = lambda div v + 2 eta dvx/dx - 2 w sxy,  dsxy/dt = eta (dvx/dy + dvy/dx) + w (sxx - syy),
 *   dsyy/dt = lambda div v + 2 eta dvy/dy + 2 w sxy,   w = (dvy/dx - dvx/dy)/2. */
#include <spam/stress.h>

/* The loops below run over d < dim with dim a literal (the public functions dispatch on
 * it), so that they unroll: in 2D a generic dim made Hooke's rate 3x the old 2D code. */
static inline __attribute__((always_inline)) void Unpack(const int dim, const double *s, double *S)
{
  for (int a = 0; a < dim; a++)
    for (int b = a; b < dim; b++) S[a * dim + b] = S[b * dim + a] = s[SpamStressIndex(dim, a, b)];
}

void SpamStressUnpack(int dim, const double *s, double *S)
{
  switch (dim) {
  case 1: Unpack(1, s, S); break;
  case 2: Unpack(2, s, S); break;
  default: Unpack(3, s, S); break;
  }
}

static inline __attribute__((always_inline)) void HookeRate(const int dim, double lambda, double eta, const double *g, const double *s, double *rate)
{
  double S[9], div = 0.0;

  Unpack(dim, s, S);
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

void SpamHookeStressRate(int dim, double lambda, double eta, const double *g, const double *s, double *rate)
{
  switch (dim) {
  case 1: HookeRate(1, lambda, eta, g, s, rate); break;
  case 2: HookeRate(2, lambda, eta, g, s, rate); break;
  default: HookeRate(3, lambda, eta, g, s, rate); break;
  }
}
