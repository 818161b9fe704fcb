/* Right-hand side of the isentropic gas (Hoover & Hoover 2001, Eqs. 8 and 13):
 *   dr_i/dt = v_i,
 *   dv_i/dt = -m sum_j [(P/rho^2)_i + (P/rho^2)_j] grad_i w_ij.
 * With gamma = 2 the bracket is constant and the density pass is skipped (Eq. 20). Every
 * pair is visited once and updates both particles with opposite signs, so the total
 * momentum is conserved to round-off. Nothing here allocates. */
#include <spam/sim.h>

/* Forced inline with a literal dim so that the compiler emits one loop per dimension. */
static inline __attribute__((always_inline)) void DensityPass(const int dim, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, double *rho)
{
  const SpamImage im = SpamBoxImage(box);
  const double self = mass * k->wnorm; /* w(0) */
  for (int i = 0; i < nl->n; i++) rho[i] = self;
  for (int i = 0; i < nl->n; i++) {
    double ri = 0.0;
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j  = nl->nbr[p];
      double    r2 = 0.0;
      for (int d = 0; d < dim; d++) {
        const double dx = SpamImageDelta(&im, d, nl->u[d][i] - nl->u[d][j]);
        r2 += dx * dx;
      }
      const double s = sqrt(r2) * k->hinv;
      double       t = 1.0 - s;
      t              = t > 0.0 ? t : 0.0;
      const double w = mass * k->wnorm * (1.0 + 3.0 * s) * t * t * t;
      ri += w;
      rho[j] += w;
    }
    rho[i] += ri;
  }
}

static inline __attribute__((always_inline)) void ForcePass(const int dim, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, const double *q, double **acc)
{
  const SpamImage im = SpamBoxImage(box);
  const double coef = -mass * k->gnorm; /* -m (w'/r) / (1-s)^2 > 0 */
  for (int d = 0; d < dim; d++)
    for (int i = 0; i < nl->n; i++) acc[d][i] = 0.0;
  for (int i = 0; i < nl->n; i++) {
    double ai[3] = {0, 0, 0}, ui[3];
    for (int d = 0; d < dim; d++) ui[d] = nl->u[d][i];
    const double qi = q[i];
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int j = nl->nbr[p];
      double    dx[3], r2 = 0.0;
      for (int d = 0; d < dim; d++) {
        dx[d] = SpamImageDelta(&im, d, ui[d] - nl->u[d][j]);
        r2 += dx[d] * dx[d];
      }
      double t = 1.0 - sqrt(r2) * k->hinv;
      t        = t > 0.0 ? t : 0.0;
      /* f > 0 pushes i away from j for positive pressure. */
      const double f = coef * (qi + q[j]) * t * t;
      for (int d = 0; d < dim; d++) {
        ai[d] += f * dx[d];
        acc[d][j] -= f * dx[d];
      }
    }
    for (int d = 0; d < dim; d++) acc[d][i] += ai[d];
  }
}

static void Density(int dim, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, double *rho)
{
  switch (dim) {
  case 1: DensityPass(1, nl, box, k, mass, rho); break;
  case 2: DensityPass(2, nl, box, k, mass, rho); break;
  default: DensityPass(3, nl, box, k, mass, rho); break;
  }
}

static void Force(int dim, const SpamNeighbours *nl, const SpamBox *box, const SpamKernel *k, double mass, const double *q, double **acc)
{
  switch (dim) {
  case 1: ForcePass(1, nl, box, k, mass, q, acc); break;
  case 2: ForcePass(2, nl, box, k, mass, q, acc); break;
  default: ForcePass(3, nl, box, k, mass, q, acc); break;
  }
}

PetscErrorCode SpamDensitySummation(SpamSim *sim, const double *y, PetscInt *bad)
{
  const SpamLayout *l = &sim->model.layout;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, y + l->x, l->nvar, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  Density(sim->model.dim, &sim->nl, &sim->box, &sim->model.kernel, sim->model.mass, sim->rho);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamAccelIsentrope(SpamSim *sim, const double *x, int stride, PetscInt *bad)
{
  const SpamModel *m = &sim->model;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->nl, &sim->box, x, stride, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  if (!m->density_free) {
    Density(m->dim, &sim->nl, &sim->box, &m->kernel, m->mass, sim->rho);
    for (PetscInt i = 0; i < sim->n; i++) sim->q[i] = SpamEosPOverRho2(&m->eos, sim->rho[i]);
  }
  Force(m->dim, &sim->nl, &sim->box, &m->kernel, m->mass, sim->q, sim->acc);
  sim->stats.pair_visits += (double)sim->nl.npairs;
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsIsentrope(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  const int         dim = sim->model.dim, nv = l->nvar;

  PetscFunctionBeginUser;
  PetscCall(SpamAccelIsentrope(sim, y + l->x, nv, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < sim->n; i++) {
    for (int d = 0; d < dim; d++) {
      ydot[(size_t)i * nv + l->x + d] = y[(size_t)i * nv + l->v + d];
      ydot[(size_t)i * nv + l->v + d] = sim->acc[d][i];
    }
  }
  PetscFunctionReturn(0);
}
