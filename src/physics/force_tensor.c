/* Pass 2 of the tensor path (CiSE Eqs. 13-14; PRE Sec. II):
 *   F_ij = m^2 [(sigma/rho^2)_i + (sigma/rho^2)_j].grad_i w_ij = -F_ji,  m dv_i/dt = sum_j F_ij,
 *   de_i/dt = (1/2m) sum_j (v_j - v_i).F_ij,
 *   drho_i/dt = m sum_j (u_i - u_j).grad_i w_ij   (continuity; u = v, or dr/dt for the
 *                                                 chain-rule form of PRE Sec. VI).
 * With torque scaling, the part of F_ij perpendicular to r_ij (the only part with a
 * torque) is scaled, and the same scaled force does the work in de/dt, so that
 * sum m (e + v^2/2) stays exact while the pair torques add to zero. Monaghan's viscosity
 * adds a central pair pressure after the scaling (it carries no torque). */
#include <spam/physics.h>

/* Scaling factor of the torque-carrying part of one pair's force. */
static double TorqueFactor(const SpamSim *sim, int i, int j, double L)
{
  const SpamPhysicsScratch *ps = sim->ps;
  switch (sim->model.solid.angmom) {
  case SPAM_ANGMOM_TIJ: {
    const double R = ps->bfac[sim->model.solid.per_body ? ps->body[i] : 0];
    return L > 0.0 ? 1.0 / R : R;
  }
  case SPAM_ANGMOM_TI: return 0.5 * (ps->tfac[i] + ps->tfac[j]);
  default: return 1.0;
  }
}

/* F <- F_par + f F_perp, with F_par the component along dx. */
static void ScalePerpendicular(const double dx[2], double r2, double f, double F[2])
{
  const double along = (F[0] * dx[0] + F[1] * dx[1]) / r2;
  for (int d = 0; d < 2; d++) F[d] = along * dx[d] + f * (F[d] - along * dx[d]);
}

void SpamForceTensor(SpamSim *sim, const double *y, const double *qs)
{
  const SpamModel      *m  = &sim->model;
  const SpamLayout     *l  = &m->layout;
  const int             nv = l->nvar;
  const SpamImage       im = SpamBoxImage(&sim->box);
  const SpamNeighbours *nl = &sim->nl;
  SpamPhysicsScratch   *ps = sim->ps;
  const PetscBool       scale = (PetscBool)(m->solid.angmom == SPAM_ANGMOM_TIJ || m->solid.angmom == SPAM_ANGMOM_TI);
  const double          minv = 1.0 / m->mass;
  const PetscBool       monaghan = (PetscBool)(m->solid.viscosity == SPAM_VISCOSITY_MONAGHAN);

  for (PetscInt i = 0; i < sim->n; i++) {
    sim->acc[2 * i] = sim->acc[2 * i + 1] = 0.0;
    ps->edot[i] = ps->rhodot[i] = 0.0;
  }
  for (int i = 0; i < nl->n; i++) {
    const double *vi = y + (size_t)i * nv + l->v;
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j = nl->nbr[p];
      double    dx[2], F[2];
      const double r2 = SpamPairDelta2(nl, &im, i, j, dx);
      if (r2 >= m->kernel.h2) continue;
      const double *vj = y + (size_t)j * nv + l->v;
      const double  g  = SpamKernelDWOverR(&m->kernel, r2);
      SpamPairForceTensor(m->mass, qs + 3 * i, qs + 3 * j, g, dx, F);
      if (scale) ScalePerpendicular(dx, r2, TorqueFactor(sim, i, j, SpamPairTorque(dx, F)), F);
      if (monaghan) {
        const double dv[2] = {vi[0] - vj[0], vi[1] - vj[1]};
        const double pi    = SpamViscosityMonaghan(&m->solid, m->kernel.h, dx, dv, r2, SpamPairDensity(m->solid.rho_geometric, sim->rho[i], sim->rho[j]));
        F[0] -= m->mass * m->mass * pi * g * dx[0];
        F[1] -= m->mass * m->mass * pi * g * dx[1];
      }
      const double work = 0.5 * minv * ((vj[0] - vi[0]) * F[0] + (vj[1] - vi[1]) * F[1]);
      const double rhod = m->mass * g * ((ps->u[2 * i] - ps->u[2 * j]) * dx[0] + (ps->u[2 * i + 1] - ps->u[2 * j + 1]) * dx[1]);
      for (int d = 0; d < 2; d++) {
        sim->acc[2 * i + d] += minv * F[d];
        sim->acc[2 * j + d] -= minv * F[d];
      }
      ps->edot[i] += work;
      ps->edot[j] += work;
      ps->rhodot[i] += rhod;
      ps->rhodot[j] += rhod;
    }
  }
}
