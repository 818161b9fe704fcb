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
 * heat-flux pair terms cancel in sum m de/dt).
 * The IMEX split of the flow scheme's gas (pair form, background and shift on): its
 * explicit and diffusion parts sum to the whole to round-off, the diffusion part moves no
 * position, density or book, and it alone conserves momentum and energy. */
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

/* max |a + b - w| over max (|a| + |b|), and the largest |b| on the rows the diffusion
 * part must leave (positions, continuity density, the flow scheme's book). */
static void SplitGaps(const SpamLayout *l, PetscInt n, const double *w, const double *a, const double *b, double *sum_gap, double *still)
{
  double num = 0.0, den = 0.0;

  *still = 0.0;
  for (PetscInt i = 0; i < n; i++) {
    const size_t o = (size_t)i * l->nvar;
    for (int k = 0; k < l->nvar; k++) {
      num = PetscMax(num, fabs(a[o + k] + b[o + k] - w[o + k]));
      den = PetscMax(den, fabs(a[o + k]) + fabs(b[o + k]));
    }
    for (int d = 0; d < l->dim; d++) *still = PetscMax(*still, fabs(b[o + l->x + d]));
    if (l->rho >= 0) *still = PetscMax(*still, fabs(b[o + l->rho]));
    if (l->fb >= 0) *still = PetscMax(*still, fabs(b[o + l->fb]));
  }
  *sum_gap = den > 0.0 ? num / den : 0.0;
}

static PetscErrorCode Parts(TestCount *c, SpamDensityMode dens)
{
  const char     *name = SpamDensityModeNames[dens];
  SpamSolidParams sp;
  SpamSim         sim;
  const PetscScalar *y;
  double         *w, *fe, *fi, p[2] = {0, 0}, ps = 0.0, e = 0.0, es = 0.0, gap, still;
  PetscInt        bad;

  PetscFunctionBeginUser;
  SpamSolidDefaults(&sp);
  sp.density      = dens;
  sp.material     = SPAM_MATERIAL_GAS;
  sp.gas_e0       = 0.01;
  sp.shear_visc   = 0.2;
  sp.conductivity = 0.3;
  sp.scheme       = SPAM_GAS_FLOW;
  sp.diffusion    = SPAM_DIFFUSION_PAIR;
  sp.background   = SPAM_BACKGROUND_MEAN;
  sp.shift_coef   = SPAM_SHIFT_COEF_DEFAULT;
  PetscCall(MakeSolid(&sp, 11 + (uint64_t)dens, 0.2, &sim));
  const SpamLayout *l = &sim.model.layout;
  TestCheck(c, sim.model.rhs_part != NULL, "split %s: the flow scheme's gas has a right-hand side by parts", name);
  PetscCall(PetscMalloc3((size_t)sim.p.n * l->nvar, &w, (size_t)sim.p.n * l->nvar, &fe, (size_t)sim.p.n * l->nvar, &fi));
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  PetscCall(SpamRhs(&sim, y, w, &bad));
  PetscCall(SpamRhsOfPart(&sim, y, fe, SPAM_RHS_EXPLICIT, &bad));
  PetscCall(SpamRhsOfPart(&sim, y, fi, SPAM_RHS_DIFFUSION, &bad));
  SplitGaps(l, sim.p.n, w, fe, fi, &gap, &still);
  for (PetscInt i = 0; i < sim.p.n; i++) {
    const double *yi = y + (size_t)i * l->nvar, *q = fi + (size_t)i * l->nvar;
    for (int d = 0; d < 2; d++) {
      p[d] += q[l->v + d];
      ps += fabs(q[l->v + d]);
      e += yi[l->v + d] * q[l->v + d];
      es += fabs(yi[l->v + d] * q[l->v + d]);
    }
    e += q[l->e];
    es += fabs(q[l->e]);
  }
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  TestCheck(c, gap < 1e-14, "split %s: explicit + diffusion = whole to %.1e of the parts' size", name, gap);
  TestCheck(c, still == 0.0, "split %s: the diffusion part's position, density and book rows are 0 (largest %.1e)", name, still);
  TestCheck(c, ps > 0.0 && fabs(p[0]) + fabs(p[1]) < 1e-14 * ps, "split %s: diffusion part sum m a = (%.1e, %.1e) of %.1e", name, p[0], p[1], ps);
  TestCheck(c, es > 0.0 && fabs(e) < 1e-13 * es, "split %s: diffusion part dE/dt = %.1e of %.1e", name, e, es);
  PetscCall(PetscFree3(w, fe, fi));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};

  PetscCall(TestInitialize(&argc, &argv));
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
  for (int dens = 0; dens < 3; dens++) PetscCall(Parts(&c, (SpamDensityMode)dens));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
