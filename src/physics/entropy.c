/* Entropy of Hoover & Hoover (2001), Eq. 22 with the printed sign corrected:
 *   s = k (rho/m) ln[(e + <(v - <v>)^2>/2)^(D/2) / rho]   per unit volume,
 * where <f> = m sum_j f_j w_ij / rho is the smooth-particle average. The velocity
 * fluctuation about the local mean flow counts as internal energy, which is what makes
 * the free expansion produce N k ln(V2/V1). Two estimates: a sum over particles (volume
 * m/rho_i each) and an integral of s over a regular grid. Results are S/k. */
#include <spam/entropy.h>

/* ln[(e + dv2/2)^(D/2) / rho] for one point. */
static double EntropyPerMass(const SpamModel *m, double rho, double v2mean, const double *vmean)
{
  double dv2 = v2mean;
  for (int d = 0; d < m->dim && d < 3; d++) dv2 -= vmean[d] * vmean[d]; /* d < 3: vmean[3] */
  dv2 = dv2 > 0.0 ? dv2 : 0.0; /* a variance; round-off can make it slightly negative */
  return 0.5 * m->dim * log(SpamEosEnergy(&m->eos, rho) + 0.5 * dv2) - log(rho);
}

PetscErrorCode SpamEntropySum(SpamSim *sim, const double *y, double *S)
{
  const SpamModel      *m  = &sim->model;
  const SpamLayout     *l  = &m->layout;
  const SpamNeighbours *nl = &sim->nl;
  const int             dim = m->dim, nv = l->nvar;
  const double          w0 = m->mass * m->kernel.wnorm;
  const SpamImage       im = SpamBoxImage(&sim->box);
  double               *acc, sum = 0.0; /* per particle: sum m w v (dim), sum m w v^2 */

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1((size_t)(dim + 1) * sim->n + 1, &acc));
  for (PetscInt i = 0; i < sim->n; i++) {
    const double *vi = y + (size_t)i * nv + l->v;
    double        v2 = 0.0;
    for (int d = 0; d < dim; d++) {
      acc[i * (dim + 1) + d] = w0 * vi[d];
      v2 += vi[d] * vi[d];
    }
    acc[i * (dim + 1) + dim] = w0 * v2;
  }
  for (int i = 0; i < nl->n; i++) {
    for (int p = nl->start[i]; p < nl->start[i + 1]; p++) {
      const int     j  = nl->nbr[p];
      const double *vi = y + (size_t)i * nv + l->v, *vj = y + (size_t)j * nv + l->v;
      double        r2 = 0.0, vi2 = 0.0, vj2 = 0.0;
      for (int d = 0; d < dim; d++) {
        const double dx = SpamImageDelta(&im, d, nl->u[d][i] - nl->u[d][j]);
        r2 += dx * dx;
      }
      const double w = m->mass * SpamKernelW(&m->kernel, r2);
      if (w == 0.0) continue;
      for (int d = 0; d < dim; d++) {
        acc[i * (dim + 1) + d] += w * vj[d];
        acc[j * (dim + 1) + d] += w * vi[d];
        vi2 += vi[d] * vi[d];
        vj2 += vj[d] * vj[d];
      }
      acc[i * (dim + 1) + dim] += w * vj2;
      acc[j * (dim + 1) + dim] += w * vi2;
    }
  }
  for (PetscInt i = 0; i < sim->n; i++) {
    double vmean[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++) vmean[d] = acc[i * (dim + 1) + d] / sim->f.rho[i];
    sum += EntropyPerMass(m, sim->f.rho[i], acc[i * (dim + 1) + dim] / sim->f.rho[i], vmean);
  }
  PetscCall(PetscFree(acc));
  PetscCallMPI(MPIU_Allreduce(&sum, S, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscFunctionReturn(0);
}

/* Density, mean velocity and mean square speed at a box-local point u. */
static double SampleAt(SpamSim *sim, const double *y, const double *u, double *vmean, double *v2mean)
{
  const SpamModel      *m  = &sim->model;
  const SpamNeighbours *nl = &sim->nl;
  const int             dim = m->dim;
  const SpamImage       im = SpamBoxImage(&sim->box);
  int                   adj[27];
  double                rho = 0.0, v2 = 0.0;
  const int             na  = SpamNeighboursAdjacentCells(nl, &sim->box, SpamNeighboursCellOf(nl, &sim->box, u), adj);

  for (int d = 0; d < dim; d++) vmean[d] = 0.0;
  for (int a = 0; a < na; a++) {
    for (int k = nl->cell_start[adj[a]]; k < nl->cell_start[adj[a] + 1]; k++) {
      const int     j  = nl->cell_list[k];
      const double *vj = y + (size_t)j * m->layout.nvar + m->layout.v;
      double        r2 = 0.0, vj2 = 0.0;
      for (int d = 0; d < dim; d++) {
        const double dx = SpamImageDelta(&im, d, u[d] - nl->u[d][j]);
        r2 += dx * dx;
        vj2 += vj[d] * vj[d];
      }
      const double w = m->mass * SpamKernelW(&m->kernel, r2);
      rho += w;
      v2 += w * vj2;
      for (int d = 0; d < dim; d++) vmean[d] += w * vj[d];
    }
  }
  if (rho > 0.0) {
    for (int d = 0; d < dim; d++) vmean[d] /= rho;
    *v2mean = v2 / rho;
  }
  return rho;
}

/* Most points of the grid: the index is an int. The set-up refuses far fewer
 * (-diag_grid_spacing, run_options.c); this bound only keeps the count in range. */
#define SPAM_GRID_MAX 1073741824.0

/* Points per direction at this spacing, and their product, all in double: a tiny
 * spacing gives a count that no integer holds. */
static double GridPoints(const SpamBox *box, double spacing, double ng[3])
{
  double total = 1.0;
  for (int d = 0; d < 3; d++) {
    ng[d] = d < box->dim ? PetscMax(1.0, ceil(box->len[d] / spacing)) : 1.0;
    total *= ng[d];
  }
  return total;
}

PetscErrorCode SpamEntropyGrid(SpamSim *sim, const double *y, double spacing, double *S)
{
  const SpamModel *m   = &sim->model;
  const int        dim = m->dim;
  PetscInt         ng[3] = {1, 1, 1}, total;
  double           g[3]  = {1, 1, 1}, nd[3], cellvol = 1.0, sum = 0.0;
  /* Below this density the point is empty space: s -> 0 as rho -> 0. */
  const double rho_min = 1e-12 * m->mass * m->kernel.wnorm;
  const double points  = GridPoints(&sim->box, spacing, nd);

  PetscFunctionBeginUser;
  PetscCheck(spacing > 0.0 && isfinite(spacing) && points <= SPAM_GRID_MAX, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "entropy grid spacing %g gives %g points; at most 2^30", spacing, points);
  total = (PetscInt)points;
  for (int d = 0; d < dim; d++) {
    ng[d] = (PetscInt)nd[d];
    g[d]  = sim->box.len[d] / ng[d];
    cellvol *= g[d];
  }
  for (PetscInt k = 0; k < total; k++) {
    double u[3] = {0, 0, 0}, vmean[3] = {0, 0, 0}, v2mean = 0.0;
    for (int d = 0, rem = (int)k; d < dim; d++) {
      u[d] = (rem % ng[d] + 0.5) * g[d];
      rem /= (int)ng[d];
    }
    const double rho = SampleAt(sim, y, u, vmean, &v2mean);
    if (rho > rho_min) sum += (rho / m->mass) * EntropyPerMass(m, rho, v2mean, vmean) * cellvol;
  }
  PetscCallMPI(MPIU_Allreduce(&sum, S, 1, MPI_DOUBLE, MPI_SUM, sim->comm));
  PetscFunctionReturn(0);
}
