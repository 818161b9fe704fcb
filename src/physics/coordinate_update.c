/* The coordinate update (PRE Secs. IV, VI):
 *   R0: dr_i/dt = v_i,
 *   R1: dr_i/dt = <v>_i = sum_j v_j w_ij / sum_j w_ij (self term included),
 *   R2: dr_i/dt = v_i + eps m sum_j (v_j - v_i) w_ij / rho_ij (Monaghan's XSPH).
 * R2's pair term is antisymmetric, so it keeps the linear momentum and, when the pair
 * torques add to zero, the angular momentum; R1 keeps neither exactly. */
#include <spam/physics.h>

static void CoordinatesR0(const SpamSim *sim, const double *y, double *xdot)
{
  const SpamLayout *l = &sim->model.layout;
  for (PetscInt i = 0; i < sim->n; i++)
    for (int d = 0; d < 2; d++) xdot[2 * i + d] = y[(size_t)i * l->nvar + l->v + d];
}

/* R1 when eps < 0 (the plain average), R2 otherwise. */
static void CoordinatesAveraged(const SpamSim *sim, const double *y, const double *rho, double *xdot, PetscBool plain)
{
  const SpamModel      *m  = &sim->model;
  const SpamLayout     *l  = &m->layout;
  const int             nv = l->nvar;
  const SpamImage       im = SpamBoxImage(&sim->box);
  const SpamNeighbours *nl = &sim->nl;
  double               *wsum = sim->ps->tfac; /* R1 only: sum_j w_ij, scratch reused before torque scaling */

  CoordinatesR0(sim, y, xdot);
  if (plain) {
    const double w0 = m->kernel.wnorm;
    for (PetscInt i = 0; i < sim->n; i++) {
      wsum[i] = w0;
      for (int d = 0; d < 2; d++) xdot[2 * i + d] *= w0;
    }
  }
  for (int i = 0; i < nl->n; i++) {
    const double *vi = y + (size_t)i * nv + l->v;
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j = nl->nbr[p];
      double    dx[2];
      const double r2 = SpamPairDelta2(nl, &im, i, j, dx);
      if (r2 >= m->kernel.h2) continue;
      const double *vj = y + (size_t)j * nv + l->v;
      const double  w  = SpamKernelW(&m->kernel, r2);
      if (plain) {
        wsum[i] += w;
        wsum[j] += w;
        for (int d = 0; d < 2; d++) {
          xdot[2 * i + d] += w * vj[d];
          xdot[2 * j + d] += w * vi[d];
        }
      } else {
        const double c = m->solid.xsph_eps * m->mass * w / SpamPairDensity(m->solid.rho_geometric, rho[i], rho[j]);
        for (int d = 0; d < 2; d++) {
          xdot[2 * i + d] += c * (vj[d] - vi[d]);
          xdot[2 * j + d] -= c * (vj[d] - vi[d]);
        }
      }
    }
  }
  if (plain)
    for (PetscInt i = 0; i < sim->n; i++)
      for (int d = 0; d < 2; d++) xdot[2 * i + d] /= wsum[i];
}

void SpamCoordinateRate(const SpamSim *sim, const double *y, const double *rho, double *xdot)
{
  switch (sim->model.solid.coords) {
  case SPAM_COORDS_R0: CoordinatesR0(sim, y, xdot); break;
  case SPAM_COORDS_R1: CoordinatesAveraged(sim, y, rho, xdot, PETSC_TRUE); break;
  default: CoordinatesAveraged(sim, y, rho, xdot, PETSC_FALSE); break;
  }
}
