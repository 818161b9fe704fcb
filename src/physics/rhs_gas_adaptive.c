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
 * One list update per evaluation; nothing here allocates. */
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

/* v and e of the state into the fields (local particles: the adaptive pass has no ghosts). */
static void Velocities(SpamSim *sim, const double *y)
{
  const SpamLayout *l = &sim->model.layout;
  SpamFields       *f = &sim->pair.f;
  const int         dim = l->dim, nv = l->nvar;

  for (PetscInt i = 0; i < sim->p.n; i++) {
    for (int d = 0; d < dim; d++) f->v[(size_t)i * dim + d] = y[(size_t)i * nv + l->v + d];
    f->e[i] = y[(size_t)i * nv + l->e];
  }
}

PetscErrorCode SpamRhsGasAdaptive(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  SpamFields       *f   = &sim->pair.f;
  const int         dim = l->dim, nv = l->nvar, n = (int)sim->p.n;
  ForcePass         c   = {f, &sim->model.solid};
  SpamNeighbours    near;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, nv, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  Velocities(sim, y);
  PetscCall(SpamSmoothingSolve(sim));
  PetscCall(PetscLogEventBegin(sim->run.ev.force, 0, 0, 0, 0));
  for (int i = 0; i < n; i++) {
    f->q[i] = (sim->model.solid.gamma - 1.0) * f->e[i] / (f->omega[i] * f->rho[i]);
    f->edot[i] = 0.0;
    for (int d = 0; d < dim; d++) f->acc[(size_t)i * dim + d] = 0.0;
  }
  SpamSmoothingPairs(sim, &near);
  PetscCall(WalkForces(&near, &sim->model.kernel, f, &c));
  PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
  for (int i = 0; i < n; i++) {
    double *r = ydot + (size_t)i * nv;
    for (int d = 0; d < dim; d++) {
      r[l->x + d] = f->v[(size_t)i * dim + d];
      r[l->v + d] = f->acc[(size_t)i * dim + d] + sim->model.gravity[d];
    }
    r[l->e] = f->edot[i];
  }
  sim->run.stats.pair_visits += (double)near.npairs;
  PetscFunctionReturn(0);
}
