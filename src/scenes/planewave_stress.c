/* SPAM's own initial stress for the plane wave. Linearised about the stress-free lattice,
 * the solid's stress obeys d(sigma)/dt = Hooke(G v), G SPAM's velocity-gradient operator
 * on the reference lattice (the gradient walk of rhs_tensor.c, stress_hooke.c), so that
 *   sigma(t) - Hooke(G u(t)) is constant in time.
 * Starting from the continuum stress Hooke(grad u) leaves that constant nonzero: the
 * lattice then oscillates about a shifted equilibrium, u = u_off + (A - u_off) cos(wt)
 * with u_off = -(f - 1) A, f = T_spam / T_cont = 1.045 at 24 x 24, so successive zero
 * crossings of the displacement are T/2 -/+ 0.49 apart (17.25 and 18.23). Starting from
 * Hooke(G u) puts the wave at a turning point of the discrete dynamics: it oscillates
 * about the undisplaced lattice. The sums run over the lattice by index arithmetic with
 * periodic images unfolded, so a box shorter than 2h counts every image as SPAM does. */
#include <spam/planewave_stress.h>

typedef struct {
  PetscInt rows, cols; /* reach of the kernel in lattice rows and columns */
  double   ry, lx, ly; /* row spacing, box lengths                        */
} LatticeReach;

static LatticeReach Reach(const SpamKernel *ker, const SpamDisplacedLattice *L)
{
  LatticeReach r;
  r.ry   = 0.5 * sqrt(3.0) * L->a;
  r.rows = (PetscInt)ceil(ker->h / r.ry) + 1;
  r.cols = (PetscInt)ceil(ker->h / L->a) + 2;
  r.lx   = L->a * (double)L->nx;
  r.ly   = r.ry * (double)L->ny;
  return r;
}

static PetscInt Wrap(PetscInt k, PetscInt n, PetscInt *image)
{
  PetscInt w = k % n;
  if (w < 0) w += n;
  *image = (k - w) / n;
  return w;
}

/* Index of the lattice neighbour (row + dr, col + dc) and l = x_i - x_j, its image
 * unfolded; returns |l|^2. */
static double Neighbour(const SpamDisplacedLattice *L, const LatticeReach *R, PetscInt row, PetscInt col, PetscInt dr, PetscInt dc, PetscInt *j, double l[2])
{
  const PetscInt i = row * L->nx + col;
  PetscInt       irow, icol;
  const PetscInt jr = Wrap(row + dr, L->ny, &irow), jc = Wrap(col + dc, L->nx, &icol);

  *j   = jr * L->nx + jc;
  l[0] = L->x0[2 * i] - (L->x0[2 * *j] + (double)icol * R->lx);
  l[1] = L->x0[2 * i + 1] - (L->x0[2 * *j + 1] + (double)irow * R->ly);
  return l[0] * l[0] + l[1] * l[1];
}

double SpamLatticeSummedDensity(const SpamKernel *ker, const SpamDisplacedLattice *L)
{
  const LatticeReach R = Reach(ker, L);
  double             rho = 0.0;

  for (PetscInt dr = -R.rows; dr <= R.rows; dr++)
    for (PetscInt dc = -R.cols; dc <= R.cols; dc++) {
      PetscInt j;
      double   l[2];
      rho += L->mass * SpamKernelW(ker, Neighbour(L, &R, 0, 0, dr, dc, &j, l));
    }
  return rho;
}

/* g^{ab} = du^b/dx^a of particle (row, col). */
static void DisplacementGradient(const SpamKernel *ker, const SpamDisplacedLattice *L, const LatticeReach *R, double rho_ref, PetscInt row, PetscInt col, double g[4])
{
  const double *ui = L->u + 2 * (row * L->nx + col);

  g[0] = g[1] = g[2] = g[3] = 0.0;
  for (PetscInt dr = -R->rows; dr <= R->rows; dr++)
    for (PetscInt dc = -R->cols; dc <= R->cols; dc++) {
      PetscInt     j;
      double       l[2];
      const double r2 = Neighbour(L, R, row, col, dr, dc, &j, l);
      if (r2 == 0.0 || r2 >= ker->h2) continue;
      const double  c  = L->mass * SpamKernelDWOverR(ker, r2) / rho_ref;
      const double *uj = L->u + 2 * j;
      for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) g[2 * a + b] += c * (uj[b] - ui[b]) * l[a];
    }
}

void SpamPlanewaveStressSpam(const SpamKernel *ker, const SpamDisplacedLattice *L, double rho_ref, double *sigma, double *rho, double *e)
{
  const LatticeReach R = Reach(ker, L);

  for (PetscInt row = 0; row < L->ny; row++)
    for (PetscInt col = 0; col < L->nx; col++) {
      const PetscInt i = row * L->nx + col;
      double         g[4], *s = sigma + 3 * i;
      DisplacementGradient(ker, L, &R, rho_ref, row, col, g);
      const double div = g[0] + g[3], exy = 0.5 * (g[1] + g[2]);
      s[0]   = L->lambda * div + 2.0 * L->eta * g[0];
      s[1]   = 2.0 * L->eta * exy;
      s[2]   = L->lambda * div + 2.0 * L->eta * g[3];
      rho[i] = rho_ref / (1.0 + div);
      e[i]   = 0.5 * (s[0] * g[0] + 2.0 * s[1] * exy + s[2] * g[3]) / rho_ref;
    }
}
