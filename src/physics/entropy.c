/* Entropy of Hoover & Hoover (2001), Eq. 22 with the printed sign corrected:
 *   s = k (rho/m) ln[(e + <(v - <v>)^2>/2)^(D/2) / rho]   per unit volume,
 * where <f> = m sum_j f_j w_ij / rho is the smooth-particle average. The velocity
 * fluctuation about the local mean flow counts as internal energy, which is what makes
 * the free expansion produce N k ln(V2/V1). Two estimates: a sum over particles (volume
 * m/rho_i each) and an integral of s over a regular grid. Results are S/k. The isentrope's
 * e is P/((gamma - 1) rho) of its summed density; the gas's (-diag_entropy true) is each
 * particle's own e_i, in the sum only. At the adaptive range each particle's averages and
 * density take its own h_i. */
#include <spam/entropy.h>
#include "../pair/pair_walk.h"
#include "../pair/pair_walk_adaptive.h"

/* ln[(e + dv2/2)^(D/2) / rho] for one point of energy e per unit mass. */
static double EntropyPerMass(const SpamModel *m, double e, double rho, double v2mean, const double *vmean)
{
  double dv2 = v2mean;
  for (int d = 0; d < m->dim && d < 3; d++) dv2 -= vmean[d] * vmean[d]; /* d < 3: vmean[3] */
  dv2 = dv2 > 0.0 ? dv2 : 0.0; /* a variance; round-off can make it slightly negative */
  return 0.5 * m->dim * log(e + 0.5 * dv2) - log(rho);
}

/* The pair walk of the entropy sum: kernel-weighted moments of the neighbours' velocities,
 * mom_i += m_j w_ij (v_j, |v_j|^2) and alike for j, on arrays with ghost slots. */
typedef struct {
  const double *v, *m;
  double       *mom; /* [slots * (dim + 1)] */
} Moments;

static inline __attribute__((always_inline)) void MomentPair(const int dim, Moments *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  const double *vi = c->v + (size_t)i * dim, *vj = c->v + (size_t)j * dim;
  double        vi2 = 0.0, vj2 = 0.0;
  (void)dx;
  (void)r2;
  (void)g;
  for (int d = 0; d < dim; d++) {
    c->mom[(size_t)i * (dim + 1) + d] += c->m[j] * w * vj[d];
    c->mom[(size_t)j * (dim + 1) + d] += c->m[i] * w * vi[d];
    vi2 += vi[d] * vi[d];
    vj2 += vj[d] * vj[d];
  }
  c->mom[(size_t)i * (dim + 1) + dim] += c->m[j] * w * vj2;
  c->mom[(size_t)j * (dim + 1) + dim] += c->m[i] * w * vi2;
}
SPAM_PAIR_WALK(WalkMoments, Moments, MomentPair)

/* The same moments at the adaptive range: each particle averages over its own range h_i,
 * mom_i += m_j w(r_ij, h_i) (v_j, |v_j|^2), as its density rho_i(h_i) sums (gather form;
 * pair_walk_adaptive.h). What a pair adds to another rank's slot is dropped. */
static inline __attribute__((always_inline)) void MomentPairAdaptive(const int dim, Moments *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  const double *vi = c->v + (size_t)i * dim, *vj = c->v + (size_t)j * dim;
  double        vi2 = 0.0, vj2 = 0.0;
  (void)dx;
  (void)r2;
  (void)gi;
  (void)gj;
  for (int d = 0; d < dim; d++) {
    c->mom[(size_t)i * (dim + 1) + d] += c->m[j] * wi * vj[d];
    c->mom[(size_t)j * (dim + 1) + d] += c->m[i] * wj * vi[d];
    vi2 += vi[d] * vi[d];
    vj2 += vj[d] * vj[d];
  }
  c->mom[(size_t)i * (dim + 1) + dim] += c->m[j] * wi * vj2;
  c->mom[(size_t)j * (dim + 1) + dim] += c->m[i] * wj * vi2;
}
#define SPAM_ENTROPY_EVERY_PAIR(ctx, i, j) 0
#define SPAM_ENTROPY_NO_ROW(ctx, i) 0
SPAM_PAIR_WALK_ADAPTIVE(WalkMomentsAdaptive, Moments, MomentPairAdaptive, SPAM_ENTROPY_EVERY_PAIR, SPAM_NEAR_NONE)

/* The canonical rows' pair (-reproducible): particle i's side only, in its row's order. */
static inline __attribute__((always_inline)) void MomentRowAdaptive(const int dim, Moments *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  const double *vj  = c->v + (size_t)j * dim;
  double        vj2 = 0.0;
  (void)dx;
  (void)r2;
  (void)gi;
  (void)wj;
  (void)gj;
  for (int d = 0; d < dim; d++) {
    c->mom[(size_t)i * (dim + 1) + d] += c->m[j] * wi * vj[d];
    vj2 += vj[d] * vj[d];
  }
  c->mom[(size_t)i * (dim + 1) + dim] += c->m[j] * wi * vj2;
}
SPAM_PAIR_ROWS_ADAPTIVE(WalkMomentsCanon, Moments, MomentRowAdaptive, SPAM_ENTROPY_NO_ROW)

PetscErrorCode SpamEntropySum(SpamSim *sim, const double *y, double *S)
{
  const SpamModel  *m   = &sim->model;
  const SpamLayout *l   = &m->layout;
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = m->dim, nv = l->nvar, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);
  const int         adaptive = sim->pair.f.adaptive, own_e = m->tensor && l->e >= 0;
  double           *v, *mom, sum = 0.0;
  Moments           c;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2((size_t)dim * slots + 1, &v, (size_t)(dim + 1) * slots + 1, &mom));
  for (int i = 0; i < n; i++) {
    const double *vi = y + (size_t)i * nv + l->v, w0 = sim->pair.f.m[i] * (adaptive ? sim->pair.f.wn[i] : m->kernel.wnorm); /* the self term */
    double        v2 = 0.0;
    for (int d = 0; d < dim; d++) {
      v[(size_t)i * dim + d]           = vi[d];
      mom[(size_t)i * (dim + 1) + d] = w0 * vi[d];
      v2 += vi[d] * vi[d];
    }
    mom[(size_t)i * (dim + 1) + dim] = w0 * v2;
  }
  PetscCall(SpamGhostsGather(gh, dim, n, dim, SPAM_GHOST_VECTOR, v));
  c = (Moments){v, sim->pair.f.m, mom};
  if (adaptive && SpamNeighboursCanonical(&sim->pair.nl)) PetscCall(WalkMomentsCanon(&sim->pair.nl, &m->kernel, &sim->pair.f, &c));
  else if (adaptive) PetscCall(WalkMomentsAdaptive(&sim->pair.nl, &m->kernel, &sim->pair.f, &c));
  else PetscCall(WalkMoments(&sim->pair.nl, &m->kernel, &c));
  /* |v|^2 is a scalar under a mirror; the mean velocity a vector. The adaptive range
   * takes no periodic image slots but in the canonical rows, whose sums are i's own. */
  for (int k = 0; k < gh->n && !adaptive; k++) {
    if (gh->kind[k] != SPAM_GHOST_PERIODIC) continue; /* a remote ghost has no local source */
    double *t = mom + (size_t)(n + k) * (dim + 1), *s = mom + (size_t)gh->src[k] * (dim + 1);
    for (int d = 0; d <= dim; d++) s[d] += (d < dim && ((gh->flip[k] >> d) & 1) ? -1.0 : 1.0) * t[d];
  }
  for (int i = 0; i < n; i++) {
    double vmean[3] = {0, 0, 0};
    const double rho = sim->pair.f.rho[i], e = own_e ? y[(size_t)i * nv + l->e] : SpamEosEnergy(&m->eos, rho);
    for (int d = 0; d < dim; d++) vmean[d] = mom[(size_t)i * (dim + 1) + d] / rho;
    sum += EntropyPerMass(m, e, rho, mom[(size_t)i * (dim + 1) + dim] / rho, vmean);
  }
  PetscCall(PetscFree2(v, mom));
  PetscCallMPI(MPIU_Allreduce(&sum, S, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}

/* The kernel-weighted sums of this rank's particles at a box-local point u, into
 * mom[0 .. dim + 1]: rho = sum m w, sum m w v_d, sum m w |v|^2. Sums, not means: the
 * ranks' sums are added before any division or logarithm. */
static void SampleAt(const SpamSim *sim, const double *y, const double *u, double *mom)
{
  const SpamModel      *m  = &sim->model;
  const SpamNeighbours *nl = &sim->pair.nl;
  const int             dim = m->dim;
  const SpamImage       im = SpamBoxImage(&sim->geo.box);
  int                   adj[27];
  const int             na  = SpamNeighboursAdjacentCells(nl, &sim->geo.box, SpamNeighboursCellOf(nl, &sim->geo.box, u), adj);

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
      mom[0] += w;
      for (int d = 0; d < dim; d++) mom[1 + d] += w * vj[d];
      mom[1 + dim] += w * vj2;
    }
  }
}

/* Most points of the grid: the index is an int. The set-up refuses far fewer
 * (-diag_grid_spacing, run_options.c); this bound only keeps the count in range. */
#define SPAM_GRID_MAX 1073741824.0
/* Points whose sums one reduction adds: the moments of a chunk (dim + 2 doubles a point,
 * 5 MB in 3D) rather than of the whole grid, which may hold 10^8 points. */
#define SPAM_GRID_CHUNK 131072

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

/* Collective. The entropy is a nonlinear function of the sums at a point (a logarithm of
 * their ratios), so on several ranks the sums of the ranks' particles are added first,
 * chunk by chunk with one MPI_Allreduce each, and every rank then evaluates every point
 * of the chunk alike: all ranks get the same S. */
PetscErrorCode SpamEntropyGrid(SpamSim *sim, const double *y, double spacing, double *S)
{
  const SpamModel *m   = &sim->model;
  const int        dim = m->dim, nm = dim + 2;
  PetscInt         ng[3] = {1, 1, 1}, total;
  double           g[3]  = {1, 1, 1}, nd[3], cellvol = 1.0, sum = 0.0, *mom;
  /* Below this density the point is empty space: s -> 0 as rho -> 0. */
  const double rho_min = 1e-12 * m->mass * m->kernel.wnorm;
  const double points  = GridPoints(&sim->geo.box, spacing, nd);

  PetscFunctionBeginUser;
  PetscCheck(spacing > 0.0 && isfinite(spacing) && points <= SPAM_GRID_MAX, sim->p.comm, PETSC_ERR_ARG_OUTOFRANGE, "entropy grid spacing %g gives %g points; at most 2^30", spacing, points);
  total = (PetscInt)points;
  for (int d = 0; d < dim; d++) {
    ng[d] = (PetscInt)nd[d];
    g[d]  = sim->geo.box.len[d] / ng[d];
    cellvol *= g[d];
  }
  PetscCall(PetscMalloc1((size_t)nm * SPAM_GRID_CHUNK, &mom));
  for (PetscInt k0 = 0; k0 < total; k0 += SPAM_GRID_CHUNK) {
    const PetscInt nk = PetscMin(total - k0, SPAM_GRID_CHUNK);
    PetscCall(PetscArrayzero(mom, (size_t)nm * nk));
    for (PetscInt k = k0; k < k0 + nk && sim->p.n > 0; k++) {
      double u[3] = {0, 0, 0};
      for (int d = 0, rem = (int)k; d < dim; d++) {
        u[d] = (rem % ng[d] + 0.5) * g[d];
        rem /= (int)ng[d];
      }
      SampleAt(sim, y, u, mom + (size_t)nm * (k - k0));
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, mom, nm * (int)nk, MPI_DOUBLE, MPI_SUM, sim->p.comm));
    for (PetscInt k = 0; k < nk; k++) {
      const double *p   = mom + (size_t)nm * k, rho = p[0];
      double        vmean[3] = {0, 0, 0};
      if (!(rho > rho_min)) continue;
      for (int d = 0; d < dim; d++) vmean[d] = p[1 + d] / rho;
      sum += (rho / m->mass) * EntropyPerMass(m, SpamEosEnergy(&m->eos, rho), rho, p[1 + dim] / rho, vmean) * cellvol;
    }
  }
  PetscCall(PetscFree(mom));
  *S = sum;
  PetscFunctionReturn(0);
}
