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
 *      2H - y.
 *   4. The diffusion part's assembled Jacobian (diffusion_jacobian.h) on the state of 2
 *      with the flow scheme's pair Laplacians: J w against the central difference of the
 *      part along a random direction w of the velocities and energies. The part is
 *      quadratic in them (the viscous work, the books' work), so the difference is exact
 *      but for round-off in every row: velocities, energies (the work's columns) and the
 *      walls' books of the mirror images' sources. With the wall below isothermal, along
 *      the velocities only (there the images' densities follow the sources' energies). */
#include <spam/physics.h>
#include <spam/scene.h>
#include <spam/diffusion_jacobian.h>
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

/* Largest |a_k| and |a_k - b_k| over the rows k of one kind (rows[r] of each particle's
 * block, r < nr). */
static void RowError(const SpamSim *sim, const double *a, const double *b, const int *rows, int nr, double *amax, double *emax)
{
  const int nv = sim->model.layout.nvar;

  *amax = *emax = 0.0;
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int r = 0; r < nr; r++) {
      const size_t k = (size_t)i * nv + rows[r];
      *amax          = PetscMax(*amax, fabs(a[k]));
      *emax          = PetscMax(*emax, fabs(a[k] - b[k]));
    }
}

/* y + s w into out, the diffusion part there into f. */
static PetscErrorCode PartAt(SpamSim *sim, const double *y, const double *w, double s, double *out, double *f)
{
  const size_t len = (size_t)sim->p.n * sim->model.layout.nvar;
  PetscInt     bad;

  PetscFunctionBeginUser;
  for (size_t k = 0; k < len; k++) out[k] = y[k] + s * w[k];
  PetscCall(sim->model.rhs_part(sim, out, f, SPAM_RHS_DIFFUSION, &bad));
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the diffusion part refused particle %" PetscInt_FMT, bad);
  PetscFunctionReturn(0);
}

/* One case: the moving no-slip wall below isothermal (T_w 0.5) or adiabatic, the direction
 * along the energies too or along the velocities alone. */
static PetscErrorCode JacobianCase(TestCount *c, PetscBool isothermal, PetscBool energies)
{
  const double       eps = 1e-4, tol = 1e-8;
  double             escale = 0.0, work = 0.0;
  SpamSolidParams    sp;
  SpamWalls          w;
  SpamSim            sim;
  SpamDiffusionJac   jac;
  const SpamLayout  *l;
  const PetscScalar *y;
  double            *dir, *yt, *fp, *fm, *jw;
  Vec                vx, vy;
  PetscInt           bad, len;
  uint64_t           seed = 5;
  int                rv[2], re[1], rb[4];
  const char        *names[3] = {"velocity", "energy", "walls' books"};
  const char        *keys[2][3] = {{"jacobian_error_velocity", "jacobian_error_energy", "jacobian_error_books"}, {"jacobian_error_velocity_isothermal", "jacobian_error_energy_isothermal", "jacobian_error_books_isothermal"}};

  PetscFunctionBeginUser;
  GasParams(&sp, 0.3, 0.4);
  sp.scheme    = SPAM_GAS_FLOW;
  sp.diffusion = SPAM_DIFFUSION_PAIR;
  PetscCall(PetscMemzero(&w, sizeof w));
  Wall(&w, 2, SPAM_WALL_NOSLIP, 0.3, isothermal ? 0.5 : 0.0);
  Wall(&w, 3, SPAM_WALL_FREESLIP, 0, 0);
  PetscCall(MakeGas(&sp, &w, 0.3, 11, &sim));
  l   = &sim.model.layout;
  len = sim.p.n * l->nvar;
  PetscCheck(sim.model.diffusion_jac && l->wb >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the flow scheme's gas between walls has no diffusion Jacobian or no books");
  PetscCall(PetscMalloc5(len, &dir, len, &yt, len, &fp, len, &fm, len, &jw));
  for (PetscInt k = 0; k < len; k++) dir[k] = 0.0;
  for (PetscInt i = 0; i < sim.p.n; i++) {
    for (int d = 0; d < 2; d++) dir[(size_t)i * l->nvar + l->v + d] = 0.3 * (TestUniform(&seed) - 0.5);
    dir[(size_t)i * l->nvar + l->e] = energies ? TestUniform(&seed) - 0.5 : 0.0;
  }
  PetscCall(PetscMemzero(&jac, sizeof jac));
  jac.builds = -1;
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  PetscCall(sim.model.diffusion_jac(&sim, y, &jac, &bad));
  PetscCheck(bad < 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the Jacobian refused particle %" PetscInt_FMT, bad);
  PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, len, dir, &vx));
  PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, len, jw, &vy));
  PetscCall(MatMult(jac.J, vx, vy));
  PetscCall(PartAt(&sim, y, dir, eps, yt, fp));
  PetscCall(PartAt(&sim, y, dir, -eps, yt, fm));
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  for (PetscInt k = 0; k < len; k++) fp[k] = (fp[k] - fm[k]) / (2.0 * eps);
  rv[0] = l->v, rv[1] = l->v + 1, re[0] = l->e;
  for (int b = 0; b < 4; b++) rb[b] = l->wb + b;
  for (int g = 0; g < 3; g++) {
    double amax, emax;
    RowError(&sim, jw, fp, g == 0 ? rv : g == 1 ? re : rb, g == 0 ? 2 : g == 1 ? 1 : 4, &amax, &emax);
    if (g == 1) escale = amax;
    TestCheck(c, amax > 0.0 && emax < tol * amax, "diffusion Jacobian, %s wall below, along the velocities%s, %s rows: max |J w - central difference| %.1e of max |J w| %.2e (< %.0e: round-off)", isothermal ? "isothermal" : "adiabatic", energies ? " and energies" : "", names[g], emax, amax, tol);
    TestReading(PETSC_COMM_WORLD, keys[isothermal][g], emax / amax);
  }
  if (energies) { /* the work's share: J w along the velocities alone, in the energies' rows */
    for (PetscInt i = 0; i < sim.p.n; i++) dir[(size_t)i * l->nvar + l->e] = 0.0;
    PetscCall(MatMult(jac.J, vx, vy));
    for (PetscInt i = 0; i < sim.p.n; i++) work = PetscMax(work, fabs(jw[(size_t)i * l->nvar + l->e]));
    TestCheck(c, work > 0.05 * escale, "the work's columns matter: max |J w| along the velocities alone in the energies' rows %.2e, along both %.2e", work, escale);
  }
  PetscCall(VecDestroy(&vx));
  PetscCall(VecDestroy(&vy));
  PetscCall(SpamDiffusionJacDestroy(&jac));
  PetscCall(PetscFree5(dir, yt, fp, fm, jw));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

/* At an isothermal wall the flow scheme's images take the density of their place,
 * rho_g / rho_s = T_s / T_g (gas_images.c), so the summed densities beside it depend on the
 * sources' energies: J, which holds the densities fixed, is exact there along the
 * velocities only. */
static PetscErrorCode Jacobian(TestCount *c)
{
  PetscFunctionBeginUser;
  PetscCall(JacobianCase(c, PETSC_FALSE, PETSC_TRUE));
  PetscCall(JacobianCase(c, PETSC_TRUE, PETSC_FALSE));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(LatticeAtRest(&c));
  PetscCall(Books(&c));
  PetscCall(Jacobian(&c));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
