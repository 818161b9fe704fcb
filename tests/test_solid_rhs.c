/* One evaluation of the elastic solid's right-hand side on a disordered hexagon with
 * random velocities and stresses conserves, to round-off, for every choice:
 *   momentum       sum m dv/dt = 0 (antisymmetric pair forces, Gauss's force sums to 0);
 *   energy         sum m (v.dv/dt + de/dt) = 0 (the same, possibly scaled, F_ij does
 *                  the work), Gauss included (its multiplier alpha removes the work);
 *   angular mom.   sum m (dr/dt x v + r x dv/dt) = 0 with T_i or T_ij and R0 or R2, and
 *                  with Gauss's principle (R0, R2); not with R1 or without a treatment.
 *                  (Gauss with R1 keeps L about the centre of mass, which then moves
 *                  differently from sum m v / M, so the origin-frame check is skipped.)
 * The same holds for the ideal gas with Newtonian viscosity and Fourier conduction (the
 * heat-flux pair terms cancel in sum m de/dt). */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

typedef struct {
  double p[2], e, l, scale_p, scale_e, scale_l;
} Rates;

static PetscErrorCode MakeSolid(const SpamSolidParams *sp, uint64_t seed, double amp, SpamSim *sim)
{
  SpamParticles p;
  SpamModel     m;

  PetscFunctionBeginUser;
  PetscCall(SpamParticlesAllocate(2, 1 + 3 * 4 + 3 * 16, &p));
  PetscCall(SpamParticlesAllocateFields(&p));
  (void)SpamLatticeHexagon(4, 1.0, p.x);
  for (PetscInt i = 0; i < p.n; i++) {
    for (int d = 0; d < 2; d++) {
      p.x[2 * i + d] += amp * (TestUniform(&seed) - 0.5);
      p.v[2 * i + d] = 0.05 * (TestUniform(&seed) - 0.5) + 0.02 * (d ? p.x[2 * i] : -p.x[2 * i + 1]);
    }
    for (int k = 0; k < 3; k++) p.sigma[3 * i + k] = 0.02 * (TestUniform(&seed) - 0.5);
    p.rho[i] = sp->rho0 * (1.0 + 0.02 * (TestUniform(&seed) - 0.5));
    p.e[i]   = 0.01;
  }
  p.mass = 1.0;
  SpamParticlesOpenBox(&p, 5.0);
  PetscCall(SpamTestModelSolid(2, 3.0, sp, &m));
  PetscCall(SpamSimCreate(PETSC_COMM_WORLD, &m, &p.box, p.n, 0.3, sim));
  PetscCall(SpamSimFill(sim, p.x, p.v, NULL));
  PetscCall(SpamSimFillFields(sim, &p));
  PetscCall(SpamParticlesFree(&p));
  PetscCall(SpamSimSetUp(sim));
  PetscCall(sim->model.setup(sim));
  PetscFunctionReturn(0);
}

static PetscErrorCode Evaluate(SpamSim *sim, Rates *r)
{
  const SpamLayout  *l = &sim->model.layout;
  const PetscScalar *y;
  double            *f;
  PetscInt           bad;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  PetscCall(PetscMalloc1((size_t)sim->p.n * l->nvar, &f));
  PetscCall(VecGetArrayRead(sim->p.X, &y));
  PetscCall(SpamRhs(sim, y, f, &bad));
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, *q = f + (size_t)i * l->nvar;
    const double  xv = q[l->x] * p[l->v + 1] - q[l->x + 1] * p[l->v], ra = p[l->x] * q[l->v + 1] - p[l->x + 1] * q[l->v];
    for (int d = 0; d < 2; d++) {
      r->p[d] += q[l->v + d];
      r->scale_p += fabs(q[l->v + d]);
      r->e += p[l->v + d] * q[l->v + d];
      r->scale_e += fabs(p[l->v + d] * q[l->v + d]);
    }
    r->e += q[l->e];
    r->scale_e += fabs(q[l->e]);
    r->l += xv + ra;
    r->scale_l += fabs(xv) + fabs(ra);
  }
  PetscCall(VecRestoreArrayRead(sim->p.X, &y));
  PetscCall(PetscFree(f));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  for (int dens = 0; dens < 3; dens++)
    for (int coords = 0; coords < 3; coords++)
      for (int am = 0; am < 4; am++)
        for (int visc = 0; visc < 4; visc += 1) { /* 3: ideal gas with Newtonian viscosity and conduction */
          SpamSolidParams sp;
          SpamSim         sim;
          Rates           r;
          SpamSolidDefaults(&sp);
          sp.density   = (SpamDensityMode)dens;
          sp.coords    = (SpamCoordsMode)coords;
          sp.angmom    = (SpamAngmomMode)am;
          sp.viscosity = visc < 3 ? (SpamViscosityMode)visc : SPAM_VISCOSITY_MONAGHAN;
          if (visc == 3) {
            sp.material     = SPAM_MATERIAL_GAS;
            sp.gas_e0       = 0.01;
            sp.shear_visc   = 0.2;
            sp.bulk_visc    = 0.1;
            sp.conductivity = 0.3;
          }
          PetscCall(MakeSolid(&sp, 7 + (uint64_t)(dens * 100 + coords * 10 + am), 0.2, &sim));
          PetscCall(Evaluate(&sim, &r));
          const char *name[4] = {SpamDensityModeNames[dens], SpamCoordsModeNames[coords], SpamAngmomModeNames[am], visc < 3 ? SpamViscosityModeNames[visc] : "gas+newtonian+fourier"};
          TestCheck(&c, fabs(r.p[0]) + fabs(r.p[1]) < 1e-14 * r.scale_p, "%s %s %s %s: sum m a = (%.1e, %.1e) of %.1e", name[0], name[1], name[2], name[3], r.p[0], r.p[1], r.scale_p);
          TestCheck(&c, fabs(r.e) < 1e-13 * r.scale_e, "%s %s %s %s: dE/dt = %.1e of %.1e", name[0], name[1], name[2], name[3], r.e, r.scale_e);
          if (am != SPAM_ANGMOM_NONE && coords != SPAM_COORDS_R1)
            TestCheck(&c, fabs(r.l) < 1e-12 * r.scale_l, "%s %s %s %s: dL/dt = %.1e of %.1e", name[0], name[1], name[2], name[3], r.l, r.scale_l);
          else if (!(am == SPAM_ANGMOM_GAUSS && coords == SPAM_COORDS_R1)) TestCheck(&c, fabs(r.l) > 1e-6 * r.scale_l, "%s %s %s %s: dL/dt = %.1e of %.1e (not conserved, as expected)", name[0], name[1], name[2], name[3], r.l, r.scale_l);
          PetscCall(SpamSimDestroy(&sim));
        }
  PetscCall(PetscFinalize());
  return TestFinish(&c);
}
