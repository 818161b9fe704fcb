/* Right-hand side of the ideal gas with the energy equation at the adaptive kernel range
 * (smoothing_adaptive.c: h_i, rho_i, Omega_i), the grad-h equations of Springel &
 * Hernquist 2002 and Price 2012 (J. Comput. Phys. 231, 759, Eqs. 56, 57), with
 * p_i = P_i / (Omega_i rho_i^2), P = (gamma - 1) rho e and g_a = w'(r, h_a)/r:
 *   dv_i/dt = -sum_j m_j (p_i g_i + p_j g_j) (r_i - r_j) + Monaghan's viscosity,
 *   de_i/dt =  p_i sum_j m_j g_i (v_i - v_j).(r_i - r_j)  + half the viscosity's work,
 *   dr_i/dt = v_i.
 * Each side of a pair takes the gradient of its own kernel. The pressure force of a pair
 * is central and opposite on i and j, and the pressure's share of the energy equation is
 * each particle's own p dV work, so m_i dv_i + m_j dv_j = 0 and the pair's kinetic and
 * internal energy rates cancel. Monaghan's Pi_ij (pair_stress_force.h) takes the mean range
 * h_ij = (h_i + h_j)/2 and the mean gradient (g_i + g_j)/2, each particle half its work.
 * One list update per evaluation; nothing here allocates. On several ranks the other
 * ranks' particles are ghost slots with their v, e, h, rho and q gathered (each rank
 * computes its own particles' pairs with them; what a pair adds to a slot is dropped);
 * under -reproducible the force pass walks the canonical rows, each particle adding its
 * own terms in its row's order (the same bits on any number of ranks).
 * At -smoothing_length evolved h_i is the state's (smoothing_adaptive.c, SpamSmoothingAt),
 * integrated with d(rho_i h_i^D)/dt = 0 at the continuity equation's rate of rho_i:
 *   dh_i/dt = -h_i/(D rho_i) drho_i/dt,  drho_i/dt = sum_j m_j g_i (v_i - v_j).(r_i - r_j)
 * (Benz 1990), summed in the force pass beside the forces. Not the summed density's own
 * rate, which divides this by Omega_i (Price 2012, Eq. 64): Omega_i falls to 0 as a
 * particle leaves the gas (its density becomes its self term, rho h^D no longer grows with
 * h), and dh_i/dt with it would diverge there. An h_i at a bound does not move beyond it. */
#include <spam/physics.h>
#include "../pair/pair_walk_adaptive.h"
#include "../pair/pair_stress_force.h"
#include "../pair/pair_gradients.h"

typedef struct {
  SpamFields            *f;
  const SpamSolidParams *p;
} ForcePass;

static inline __attribute__((always_inline)) void ForcePair(const int dim, ForcePass *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  SpamFields   *f  = c->f;
  const double *vi = f->v + (size_t)i * dim, *vj = f->v + (size_t)j * dim;
  const double  pi = f->q[i] * gi, pj = f->q[j] * gj, mm = f->m[i] * f->m[j];
  double        vr = 0.0, k = -mm * (pi + pj); /* F = k (r_i - r_j) */
  (void)wi;
  (void)wj;
  for (int d = 0; d < dim; d++) vr += (vi[d] - vj[d]) * dx[d];
  f->edot[i] += f->m[j] * pi * vr;
  f->edot[j] += f->m[i] * pj * vr;
  if (c->p->viscosity == SPAM_VISCOSITY_MONAGHAN && vr < 0.0) {
    const double rho_ij = SpamPairMeanDensity(c->p->rho_geometric, f->rho[i], f->rho[j]);
    const double Pi     = SpamPairMonaghan(dim, c->p->visc_alpha, c->p->visc_beta, c->p->sound_speed, 0.5 * (f->h[i] + f->h[j]), dx, vi, vj, r2, rho_ij);
    const double kv     = -mm * Pi * 0.5 * (gi + gj);
    const double work   = -0.5 * kv * vr; /* half of (v_j - v_i).F_visc each */
    k += kv;
    f->edot[i] += work * f->minv[i];
    f->edot[j] += work * f->minv[j];
  }
  for (int d = 0; d < dim; d++) {
    f->acc[(size_t)i * dim + d] += k * dx[d] * f->minv[i];
    f->acc[(size_t)j * dim + d] -= k * dx[d] * f->minv[j];
  }
}
#define SPAM_EVERY_PAIR(ctx, i, j) 0
SPAM_PAIR_WALK_ADAPTIVE(WalkForces, ForcePass, ForcePair, SPAM_EVERY_PAIR, SPAM_NEAR_NONE)

/* The pair's share of sum_j m_j g_i (v_i - v_j).(r_i - r_j) on each side. */
static inline __attribute__((always_inline)) double PairVr(const int dim, const SpamFields *f, int i, int j, const double dx[3])
{
  const double *vi = f->v + (size_t)i * dim, *vj = f->v + (size_t)j * dim;
  double        vr = 0.0;
  for (int d = 0; d < dim; d++) vr += (vi[d] - vj[d]) * dx[d];
  return vr;
}
static inline __attribute__((always_inline)) void ForcePairEvolved(const int dim, ForcePass *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  SpamFields  *f  = c->f;
  const double vr = PairVr(dim, f, i, j, dx);
  ForcePair(dim, c, i, j, dx, r2, wi, gi, wj, gj);
  f->divv[i] += f->m[j] * gi * vr;
  f->divv[j] += f->m[i] * gj * vr;
}
SPAM_PAIR_WALK_ADAPTIVE(WalkForcesEvolved, ForcePass, ForcePairEvolved, SPAM_EVERY_PAIR, SPAM_NEAR_NONE)

/* The canonical rows' pair: ForcePair's terms on particle i alone (F_i = k (r_i - r_j),
 * i's work and its half of the viscosity's), in the same roundings. */
static inline __attribute__((always_inline)) void ForceRowPair(const int dim, ForcePass *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  SpamFields   *f  = c->f;
  const double *vi = f->v + (size_t)i * dim, *vj = f->v + (size_t)j * dim;
  const double  pi = f->q[i] * gi, pj = f->q[j] * gj, mm = f->m[i] * f->m[j];
  double        vr = 0.0, k = -mm * (pi + pj);
  (void)wi;
  (void)wj;
  for (int d = 0; d < dim; d++) vr += (vi[d] - vj[d]) * dx[d];
  f->edot[i] += f->m[j] * pi * vr;
  if (c->p->viscosity == SPAM_VISCOSITY_MONAGHAN && vr < 0.0) {
    const double rho_ij = SpamPairMeanDensity(c->p->rho_geometric, f->rho[i], f->rho[j]);
    const double Pi     = SpamPairMonaghan(dim, c->p->visc_alpha, c->p->visc_beta, c->p->sound_speed, 0.5 * (f->h[i] + f->h[j]), dx, vi, vj, r2, rho_ij);
    const double kv     = -mm * Pi * 0.5 * (gi + gj);
    k += kv;
    f->edot[i] += -0.5 * kv * vr * f->minv[i];
  }
  for (int d = 0; d < dim; d++) f->acc[(size_t)i * dim + d] += k * dx[d] * f->minv[i];
}
#define SPAM_NO_ROW(ctx, i) 0
SPAM_PAIR_ROWS_ADAPTIVE(WalkForceCanon, ForcePass, ForceRowPair, SPAM_NO_ROW)
static inline __attribute__((always_inline)) void ForceRowPairEvolved(const int dim, ForcePass *c, int i, int j, const double dx[3], double r2, double wi, double gi, double wj, double gj)
{
  SpamFields *f = c->f;
  ForceRowPair(dim, c, i, j, dx, r2, wi, gi, wj, gj);
  f->divv[i] += f->m[j] * gi * PairVr(dim, f, i, j, dx);
}
SPAM_PAIR_ROWS_ADAPTIVE(WalkForceCanonEvolved, ForcePass, ForceRowPairEvolved, SPAM_NO_ROW)

/* dh_i/dt of the evolved range, held at the bounds. */
static double RangeRate(const SpamSim *sim, const SpamFields *f, int i, double hy)
{
  const double h0 = sim->model.kernel.h, dh = -f->h[i] * f->divv[i] / (sim->model.dim * f->rho[i]);
  if ((hy >= sim->model.solid.h_max * h0 && dh > 0.0) || (hy <= sim->model.solid.h_min * h0 && dh < 0.0)) return 0.0;
  return dh;
}

/* v and e of the state into the fields of the local particles, v gathered into the
 * ghost slots, with their masses after a list build. */
static PetscErrorCode Velocities(SpamSim *sim, const double *y)
{
  const SpamLayout *l = &sim->model.layout;
  SpamFields       *f = &sim->pair.f;
  const int         dim = l->dim, nv = l->nvar;

  PetscFunctionBeginUser;
  PetscCall(SpamFieldsReserve(f, SpamNeighboursSlots(&sim->pair.nl)));
  PetscCall(SpamSimGhostMasses(sim));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    for (int d = 0; d < dim; d++) f->v[(size_t)i * dim + d] = y[(size_t)i * nv + l->v + d];
    f->e[i] = y[(size_t)i * nv + l->e];
  }
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, dim, (int)sim->p.n, dim, SPAM_GHOST_VECTOR, f->v));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsGasAdaptive(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  SpamFields       *f   = &sim->pair.f;
  const int         dim = l->dim, nv = l->nvar, n = (int)sim->p.n, canonical = SpamNeighboursCanonical(&sim->pair.nl), evolved = l->h >= 0;
  int               slots;
  ForcePass         c   = {f, &sim->model.solid};
  SpamNeighbours    near;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, nv, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  slots = SpamNeighboursSlots(&sim->pair.nl);
  PetscCall(Velocities(sim, y));
  if (evolved) PetscCall(SpamSmoothingAt(sim, y));
  else PetscCall(SpamSmoothingSolve(sim));
  for (int i = 0; i < n; i++) f->q[i] = (sim->model.solid.gamma - 1.0) * f->e[i] / (f->omega[i] * f->rho[i]);
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, dim, n, 1, SPAM_GHOST_SCALAR, f->q));
  PetscCall(PetscLogEventBegin(sim->run.ev.force, 0, 0, 0, 0));
  for (int i = 0; i < slots; i++) {
    f->edot[i] = 0.0;
    for (int d = 0; d < dim; d++) f->acc[(size_t)i * dim + d] = 0.0;
    if (evolved) f->divv[i] = 0.0;
  }
  SpamSmoothingPairs(sim, &near);
  if (canonical && evolved) PetscCall(WalkForceCanonEvolved(&sim->pair.nl, &sim->model.kernel, f, &c));
  else if (canonical) PetscCall(WalkForceCanon(&sim->pair.nl, &sim->model.kernel, f, &c));
  else if (evolved) PetscCall(WalkForcesEvolved(&near, &sim->model.kernel, f, &c));
  else PetscCall(WalkForces(&near, &sim->model.kernel, f, &c));
  PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
  for (int i = 0; i < n; i++) {
    double *r = ydot + (size_t)i * nv;
    for (int d = 0; d < dim; d++) {
      r[l->x + d] = f->v[(size_t)i * dim + d];
      r[l->v + d] = f->acc[(size_t)i * dim + d] + sim->model.gravity[d];
    }
    r[l->e] = f->edot[i];
    if (evolved) r[l->h] = RangeRate(sim, f, i, y[(size_t)i * nv + l->h]);
  }
  sim->run.stats.pair_visits += canonical ? (double)sim->pair.nl.ncpairs : (double)(near.npairs + sim->pair.nl.ngpairs);
  PetscFunctionReturn(0);
}
