/* Stress and the particle laws of the tensor path (Hoover, Hoover & Merritt 2004, with the
 * corrections of docs/equations.md), in one to three dimensions. The state holds
 * the upper triangle of sigma row by row, D(D+1)/2 values (2D: xx xy yy; 3D: xx xy xz yy
 * yz zz); the pair passes use sigma/rho^2 as a full D x D array. */
#ifndef SPAM_STRESS_H
#define SPAM_STRESS_H

/* Position of component (a, b), a <= b, in the state's upper triangle. */
static inline int SpamStressIndex(int dim, int a, int b)
{
  if (a > b) {
    const int t = a;
    a = b;
    b = t;
  }
  return a * dim - a * (a - 1) / 2 + (b - a);
}
static inline int SpamStressComponents(int dim)
{
  return dim * (dim + 1) / 2;
}
/* The full symmetric D x D tensor S of the state's components s. */
void SpamStressUnpack(int dim, const double *s, double *S);
/* Hooke's stress rate with the rotation terms, from G^{ab} = dv^b/dx^a (stress_hooke.c). */
void SpamHookeStressRate(int dim, double lambda, double eta, const double *g, const double *s, double *rate);
/* Newtonian viscous stress over rho^2, added to q (D x D) (viscosity_newtonian.c):
 *   sigma_v = eta_s (G + G^T - (2/D) (div v) I) + eta_b (div v) I. */
void SpamNewtonianViscosity(int dim, double eta_s, double eta_b, const double *g, double rho, double *q);
/* von Neumann-Richtmyer viscosity (viscosity_vonneumann.c): under compression (div v < 0)
 * q_i = rho (beta h^2 (div v)^2 - alpha c h div v), subtracted over rho^2 from the diagonal. */
void SpamVonNeumannViscosity(int dim, double alpha, double beta, double c, double h, const double *g, double rho, double *q);
#endif
