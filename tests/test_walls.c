/* Mirror walls: one right-hand-side evaluation of the gas between walls.
 *   1. A square lattice at rest whose walls lie half a spacing beyond its outer rows is
 *      continued exactly by its mirror images: every acceleration and energy rate is zero
 *      to round-off, as in the same lattice made periodic (free-slip and no-slip walls,
 *      isothermal walls at the gas's own temperature).
 *   2. On a disordered moving state with viscosity and conduction, a no-slip moving wall,
 *      an isothermal and an adiabatic one, the walls' books balance the fluid's rates to
 *      round-off: sum m a = sum of the walls' forces, sum m (v.a + de/dt) = their work +
 *      heat, and the per-particle book rates sum to the same totals. (Every pair, wall
 *      pairs included, exchanges momentum and energy antisymmetrically.)
 *   3. The ghosts carry what the wall prescribes: a no-slip image v_g = 2 v_w - v_i, a
 *      free-slip one the normal velocity reversed, an isothermal one T_g = 2 T_w - T_i,
 *      an adiabatic one T_g = T_i; the image of a particle at height y sits at -y or
 *      2H - y. */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

#define NX 12
#define NY 10

/* The gas on the lattice (i + 1/2, j + 1/2) of a periodic-x box NX x NY, walls w on the
 * y faces, jittered by amp with random velocities of size amp and energies e0 (1 +- amp). */
static PetscErrorCode MakeGas(const SpamSolidParams *sp, const SpamWalls *w, double amp, uint64_t seed, SpamSim *sim)
{
  SpamParticles p;
  SpamModel     m;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, NX * NY, &p));
  PetscCall(SpamParticlesAllocateFields(&p));
  for (PetscInt i = 0; i < p.n; i++) {
    p.x[2 * i]     = (double)(i % NX) + 0.5 + amp * (TestUniform(&seed) - 0.5);
    p.x[2 * i + 1] = (double)(i / NX) + 0.5 + amp * (TestUniform(&seed) - 0.5);
    for (int d = 0; d < 2; d++) p.v[2 * i + d] = amp * (TestUniform(&seed) - 0.5);
    p.e[i]   = sp->gas_e0 * (1.0 + amp * (TestUniform(&seed) - 0.5));
    p.rho[i] = 1.0;
  }
  p.mass    = 1.0;
  p.box.dim = 2;
  p.box.len[0] = NX;
  p.box.len[1] = NY;
  p.box.periodic[0] = PETSC_TRUE;
  p.box.periodic[1] = (PetscBool)!SpamWallsAny(w, 2);
  PetscCall(SpamTestModelSolid(2, 3.0, sp, &m));
  m.energy_given = PETSC_TRUE;
  if (SpamWallsAny(w, 2)) PetscCall(SpamLayoutAddWallBooks(&m.layout));
  PetscCall(SpamSimCreate(PETSC_COMM_WORLD, &m, &p.box, p.n, 0.3, sim));
  sim->geo.walls = *w;
  PetscCall(SpamSimFill(sim, p.x, p.v, NULL));
  PetscCall(SpamSimFillFields(sim, &p));
  PetscCall(SpamParticlesFree(&p));
  PetscCall(SpamSimSetUp(sim));
  PetscCall(sim->model.setup(sim));
  PetscFunctionReturn(0);
}

static void GasParams(SpamSolidParams *sp, double visc, double cond)
{
  SpamSolidDefaults(sp);
  sp->material     = SPAM_MATERIAL_GAS;
  sp->density      = SPAM_DENSITY_SUMMATION;
  sp->gas_e0       = 1.0;
  sp->gamma        = 1.4;
  sp->shear_visc   = visc;
  sp->conductivity = cond;
}

static void Wall(SpamWalls *w, int f, SpamWallSlip slip, double u, double T)
{
  w->slip[f]        = slip;
  w->velocity[f][0] = u;
  w->isothermal[f]  = (PetscBool)(T > 0);
  w->temperature[f] = T;
}

/* Largest |dv/dt| and |de/dt| of the state's RHS. */
static PetscErrorCode MaxRates(SpamSim *sim, double *amax, double *emax)
{
  const SpamLayout  *l = &sim->model.layout;
  const PetscScalar *y;
  double            *f;
  PetscInt           bad;

  PetscFunctionBeginUser;
  *amax = *emax = 0.0;
  PetscCall(PetscMalloc1((size_t)sim->p.n * l->nvar, &f));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamRhs(sim, y, f, &bad));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    for (int d = 0; d < 2; d++) *amax = PetscMax(*amax, fabs(f[(size_t)i * l->nvar + l->v + d]));
    *emax = PetscMax(*emax, fabs(f[(size_t)i * l->nvar + l->e]));
  }
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscFree(f));
  PetscFunctionReturn(0);
}

static PetscErrorCode LatticeAtRest(TestCount *c)
{
  const char *names[3] = {"no walls (periodic y):", "free-slip walls:", "no-slip isothermal walls:"};

  PetscFunctionBeginUser;
  for (int k = 0; k < 3; k++) {
    SpamSolidParams sp;
    SpamWalls       w;
    SpamSim         sim;
    double          amax, emax;
    GasParams(&sp, 0.5, 0.5);
    PetscCall(PetscMemzero(&w, sizeof w));
    if (k == 1) Wall(&w, 2, SPAM_WALL_FREESLIP, 0, 0), Wall(&w, 3, SPAM_WALL_FREESLIP, 0, 0);
    if (k == 2) Wall(&w, 2, SPAM_WALL_NOSLIP, 0, 0.4), Wall(&w, 3, SPAM_WALL_NOSLIP, 0, 0.4); /* T = (gamma-1) e0 */
    PetscCall(MakeGas(&sp, &w, 0.0, 1, &sim));
    PetscCall(MaxRates(&sim, &amax, &emax));
    /* The pressure force on one particle is a sum of ~28 terms of size P/rho^2 |grad w| ~ 0.1. */
    TestCheck(c, amax < 1e-13 && emax < 1e-13, "lattice at rest, %s max |a| = %.1e, max |de/dt| = %.1e (round-off: < 1e-13)", names[k], amax, emax);
    TestReading(PETSC_COMM_WORLD, k ? "rest_max_acc_walls" : "rest_max_acc_periodic", amax);
    PetscCall(SpamSimDestroy(&sim));
  }
  PetscFunctionReturn(0);
}

/* The ghost slots after an RHS evaluation against the walls' conditions (the no-slip
 * isothermal wall at y = 0 moving at 0.3 with T_w = 0.5, the adiabatic free-slip one at NY). */
static PetscErrorCode Ghosts(TestCount *c, const SpamSim *sim)
{
  const SpamGhosts *g = &sim->pair.nl.ghosts;
  const SpamFields *f = &sim->pair.f;
  const int         n = (int)sim->p.n;
  double            ex = 0, ev = 0, eT = 0;
  int               lo = 0, hi = 0;

  PetscFunctionBeginUser;
  for (int k = 0; k < g->n; k++) {
    const int    i = g->src[k], j = n + k, up = (g->face[k] >> 1) & 1;
    const double y = sim->pair.nl.u[1][i], vx = f->v[2 * i], vy = f->v[2 * i + 1];
    if (g->kind[k] != SPAM_GHOST_MIRROR || g->flip[k] != 2) continue;
    up ? hi++ : lo++;
    ex = PetscMax(ex, fabs(sim->pair.nl.u[1][j] - (up ? 2.0 * NY - y : -y)) + fabs(sim->pair.nl.u[0][j] - sim->pair.nl.u[0][i]));
    ev = PetscMax(ev, fabs(f->v[2 * j] - (up ? vx : 0.6 - vx)) + fabs(f->v[2 * j + 1] + vy));
    eT = PetscMax(eT, fabs(f->T[j] - (up ? f->T[i] : 1.0 - f->T[i])));
  }
  TestCheck(c, lo > NX && hi > NX, "images: %d of the lower wall, %d of the upper (more than one row each)", lo, hi);
  TestCheck(c, ex < 1e-13 && ev < 1e-15 && eT < 1e-15, "images at -y and 2H - y (%.1e), v_g = 2 v_w - v (no-slip) and (vx, -vy) (free-slip) (%.1e), T_g = 2 T_w - T (isothermal) and T (adiabatic) (%.1e)", ex, ev, eT);
  PetscFunctionReturn(0);
}

/* Balances of a disordered moving state between a moving no-slip isothermal wall and an
 * adiabatic free-slip one. */
static PetscErrorCode Books(TestCount *c)
{
  SpamSolidParams    sp;
  SpamWalls          w;
  SpamSim            sim;
  const SpamLayout  *l;
  const PetscScalar *y;
  double            *f, fm[2] = {0, 0}, pw = 0, sm[2] = {0, 0}, se = 0, bw[2] = {0, 0}, bp[2] = {0, 0}, scale = 0;
  PetscInt           bad;

  PetscFunctionBeginUser;
  GasParams(&sp, 0.3, 0.4);
  PetscCall(PetscMemzero(&w, sizeof w));
  Wall(&w, 2, SPAM_WALL_NOSLIP, 0.3, 0.5);
  Wall(&w, 3, SPAM_WALL_FREESLIP, 0, 0);
  PetscCall(MakeGas(&sp, &w, 0.3, 11, &sim));
  l = &sim.model.layout;
  PetscCall(PetscMalloc1((size_t)sim.p.n * l->nvar, &f));
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  PetscCall(SpamRhs(&sim, y, f, &bad));
  for (PetscInt i = 0; i < sim.p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, *q = f + (size_t)i * l->nvar;
    for (int d = 0; d < 2; d++) {
      sm[d] += q[l->v + d];
      se += p[l->v + d] * q[l->v + d];
      bp[d] += q[l->wb + 2 + d];
      scale += fabs(p[l->v + d] * q[l->v + d]);
    }
    se += q[l->e];
    scale += fabs(q[l->e]);
    bw[0] += q[l->wb];
    bw[1] += q[l->wb + 1];
  }
  for (int s = 0; s < 4; s++) {
    for (int d = 0; d < 2; d++) fm[d] += sim.out.wall_rates.force[s][d];
    pw += sim.out.wall_rates.work[s] + sim.out.wall_rates.heat[s];
  }
  TestCheck(c, fabs(sm[0] - fm[0]) + fabs(sm[1] - fm[1]) < 1e-12 * (fabs(fm[0]) + fabs(fm[1])), "sum m a = (%.6e, %.6e), the walls' force (%.6e, %.6e)", sm[0], sm[1], fm[0], fm[1]);
  TestCheck(c, fabs(se - pw) < 1e-12 * scale, "sum m (v.a + de/dt) = %.6e, the walls' work + heat %.6e (of %.1e)", se, pw, scale);
  TestCheck(c, fabs(bw[0] + bw[1] - pw) < 1e-12 * scale && fabs(bp[0] - fm[0]) + fabs(bp[1] - fm[1]) < 1e-12 * (fabs(fm[0]) + fabs(fm[1])), "book rates: work + heat %.6e, impulse (%.6e, %.6e)", bw[0] + bw[1], bp[0], bp[1]);
  TestCheck(c, sim.out.wall_rates.heat[2] != 0.0 && fabs(sim.out.wall_rates.heat[3]) < 1e-13 * scale, "heat through the isothermal wall %.3e, through the adiabatic one %.1e", sim.out.wall_rates.heat[2], sim.out.wall_rates.heat[3]);
  TestReading(PETSC_COMM_WORLD, "heat_isothermal", sim.out.wall_rates.heat[2]);
  TestReading(PETSC_COMM_WORLD, "heat_adiabatic", fabs(sim.out.wall_rates.heat[3]));
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  PetscCall(PetscFree(f));
  PetscCall(Ghosts(c, &sim));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(LatticeAtRest(&c));
  PetscCall(Books(&c));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
