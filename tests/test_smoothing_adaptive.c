/* The adaptive kernel range (smoothing_adaptive.c, rhs_gas_adaptive.c), for every kernel
 * of the table in 1D, 2D and 3D:
 *   uniform lattice: every h_i is the same to round-off, the density is the fixed range's
 *     at that h to round-off (a brute-force sum with the kernel made at h), h is eta times
 *     the spacing up to the lattice sum's own error, and Omega is 1 + (h/(D rho)) drho/dh
 *     of the brute-force sums at h (1 +- 1e-4) (central difference: O(1e-8));
 *   disordered, compressed set with unequal masses (h_i spread by more than 1.3):
 *     one right-hand side conserves momentum and energy to round-off
 *     (sum m a = 0, sum m (v.a + de/dt) = 0, Monaghan's viscosity on), and without
 *     viscosity de_i/dt = (P_i/rho_i^2) drho_i/dt with drho_i/dt the central difference of
 *     the solved density along the velocities: the first law of each particle, which
 *     holds only with the grad-h factor Omega_i in both equations;
 *   the near rows: the first right-hand side moves h_i from -h beyond the reach of the
 *     solve's later passes, so it walks the whole list; a second one at the same state
 *     starts from the solved h_i, walks only the near rows, and gives the same bits (the
 *     pairs it leaves out are beyond both ranges). */
#define _POSIX_C_SOURCE 200809L /* strtok_r */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

typedef struct {
  int    dim, n;  /* lattice points per direction */
  double eta;     /* = -h: unit spacing           */
} Shape;

static const Shape Shapes[3] = {{1, 64, 4.0}, {2, 24, 3.0}, {3, 12, 2.5}};

/* A gas sim at the adaptive range with kernel name; x, v, m for N particles. */
static PetscErrorCode MakeGas(const char *name, const Shape *s, PetscInt N, const double *x, const double *v, const double *m, double visc, SpamSim *sim)
{
  SpamSolidParams sp;
  SpamKernel      k;
  SpamModel       model;
  SpamBox         b = {s->dim, {0, 0, 0}, {1, 1, 1}, {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}};

  PetscFunctionBeginUser;
  for (int d = 0; d < s->dim; d++) b.len[d] = s->n;
  SpamSolidGasDefaults(1.0, &sp);
  sp.gamma      = 1.4;
  sp.viscosity  = visc > 0.0 ? SPAM_VISCOSITY_MONAGHAN : SPAM_VISCOSITY_NONE;
  sp.visc_alpha = visc;
  sp.visc_beta  = 2.0 * visc;
  sp.smoothing  = SPAM_SMOOTHING_ADAPTIVE;
  sp.h_eta      = s->eta;
  sp.h_min      = 0.25;
  sp.h_max      = 2.0;
  PetscCall(SpamKernelCreate(name, s->dim, s->eta, &k));
  PetscCall(SpamModelSolidSetUp(s->dim, &k, 1.0, &sp, &model));
  PetscCall(SpamSimCreate(PETSC_COMM_SELF, &model, &b, N, 0.1 * s->eta, sim));
  PetscCall(SpamSimFill(sim, x, v, m));
  PetscCall(SpamSimSetUp(sim));
  PetscCall(sim->model.setup(sim));
  PetscFunctionReturn(0);
}

static PetscInt LatticeCount(const Shape *s)
{
  PetscInt N = 1;
  for (int d = 0; d < s->dim; d++) N *= s->n;
  return N;
}

/* Point k of the n^D lattice of unit spacing, cell centres. */
static void LatticePoint(const Shape *s, PetscInt k, double *x)
{
  for (int d = 0; d < s->dim; d++, k /= s->n) x[d] = (double)(k % s->n) + 0.5;
}

/* Brute-force summed density of particle i at the fixed range h (minimum image). */
static PetscErrorCode BruteDensity(const char *name, const SpamSim *sim, const double *y, int i, double h, double *rho)
{
  const SpamLayout *l = &sim->model.layout;
  const int         dim = sim->model.dim, nv = l->nvar;
  SpamKernel        k;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelCreate(name, dim, h, &k));
  *rho = 0.0;
  for (PetscInt j = 0; j < sim->p.n; j++) {
    double r2 = 0.0;
    for (int d = 0; d < dim; d++) {
      const double len = sim->geo.box.len[d], dx = SpamBoxMinImage(y[(size_t)i * nv + l->x + d] - y[(size_t)j * nv + l->x + d], len, 0.5 * len, PETSC_TRUE);
      r2 += dx * dx;
    }
    *rho += sim->pair.f.m[j] * SpamKernelW(&k, r2);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Lattice(TestCount *c, const char *name, const Shape *s)
{
  const PetscInt     N = LatticeCount(s);
  double            *x, *v, hmin = PETSC_INFINITY, hmax = 0.0, err = 0.0, rho_eta, omega_fd, rp, rm;
  const double       dh = 1e-4 * s->eta;
  SpamSim            sim;
  const PetscScalar *y;
  PetscInt           bad;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2((size_t)N * s->dim, &x, (size_t)N * s->dim, &v));
  for (PetscInt k = 0; k < N; k++) LatticePoint(s, k, x + k * s->dim);
  PetscCall(MakeGas(name, s, N, x, v, NULL, 0.0, &sim));
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  PetscCall(SpamDensitySummation(&sim, y, &bad));
  for (PetscInt i = 0; i < N; i++) {
    hmin = PetscMin(hmin, sim.pair.f.h[i]);
    hmax = PetscMax(hmax, sim.pair.f.h[i]);
  }
  for (PetscInt i = 0; i < N; i += 1 + N / 50) { /* fifty particles against the brute force */
    double rf;
    PetscCall(BruteDensity(name, &sim, y, (int)i, sim.pair.f.h[i], &rf));
    err = PetscMax(err, fabs(sim.pair.f.rho[i] / rf - 1.0));
  }
  PetscCall(BruteDensity(name, &sim, y, 0, s->eta, &rho_eta));
  PetscCall(BruteDensity(name, &sim, y, 0, sim.pair.f.h[0] + dh, &rp));
  PetscCall(BruteDensity(name, &sim, y, 0, sim.pair.f.h[0] - dh, &rm));
  omega_fd = 1.0 + sim.pair.f.h[0] * (rp - rm) / (2.0 * dh) / (s->dim * sim.pair.f.rho[0]);
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  {
    /* rho(h) h^D = eta^D m: with the lattice sum's error eps = rho(eta) - 1 at eta, to first
     * order h/eta - 1 = -eps / (D Omega); bounded with a factor 2 for Omega and the second order. */
    const double eps = rho_eta - 1.0, dev = sim.pair.f.h[0] / s->eta - 1.0;
    TestCheck(c, (hmax - hmin) <= 1e-12 * hmax, "%s D=%d lattice: h_i all equal: spread %.2e of h (<= 1e-12)", name, s->dim, (hmax - hmin) / hmax);
    TestCheck(c, err <= 1e-13, "%s D=%d lattice: density against the brute-force fixed-range sum at h_i: %.2e (<= 1e-13)", name, s->dim, err);
    TestCheck(c, fabs(dev) <= 2.0 * fabs(eps) / s->dim + 1e-10, "%s D=%d lattice: h/(eta spacing) - 1 = %.2e, lattice sum error at eta %.2e (bound 2|eps|/D)", name, s->dim, dev, eps);
    TestCheck(c, fabs(sim.pair.f.omega[0] - omega_fd) <= 1e-6, "%s D=%d lattice: Omega = %.10f, central difference %.10f (Omega - 1 = %.1e; bound 1e-6)", name, s->dim, sim.pair.f.omega[0], omega_fd, sim.pair.f.omega[0] - 1.0);
  }
  PetscCall(SpamSimDestroy(&sim));
  PetscCall(PetscFree2(x, v));
  PetscFunctionReturn(0);
}

/* The compressed, jittered lattice: each coordinate u -> u + a L sin(2 pi u/L)/(2 pi), so
 * that the density varies by 1/(1 -+ a) along each direction; masses 1 +- 0.2. */
static PetscErrorCode Disorder(const Shape *s, uint64_t seed, double *x, double *v, double *m, double *e)
{
  const PetscInt N = LatticeCount(s);
  const double   a = 0.4, L = s->n;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < N; k++) {
    LatticePoint(s, k, x + k * s->dim);
    for (int d = 0; d < s->dim; d++) {
      double *u = x + k * s->dim + d;
      *u += 0.2 * (TestUniform(&seed) - 0.5);
      *u += a * L * sin(2.0 * PETSC_PI * *u / L) / (2.0 * PETSC_PI);
      *u = fmod(*u + L, L);
      v[k * s->dim + d] = TestUniform(&seed) - 0.5;
    }
    m[k] = 1.0 + 0.4 * (TestUniform(&seed) - 0.5);
    e[k] = 0.5 + TestUniform(&seed);
  }
  PetscFunctionReturn(0);
}

/* The state's energies set to e. */
static PetscErrorCode SetEnergies(SpamSim *sim, const double *e)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  for (PetscInt i = 0; i < sim->p.n; i++) y[(size_t)i * l->nvar + l->e] = e[i];
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscFunctionReturn(0);
}

/* Solved densities at the positions x + t v into rho. */
static PetscErrorCode DensityAlong(SpamSim *sim, double t, double *rho)
{
  const SpamLayout *l = &sim->model.layout;
  PetscScalar      *y;
  double           *z;
  PetscInt          bad;
  const size_t      len = (size_t)sim->p.n * l->nvar;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(len, &z));
  PetscCall(VecGetArray(sim->p.X, &y));
  for (size_t k = 0; k < len; k++) z[k] = y[k];
  for (PetscInt i = 0; i < sim->p.n; i++)
    for (int d = 0; d < l->dim; d++) z[(size_t)i * l->nvar + l->x + d] += t * y[(size_t)i * l->nvar + l->v + d];
  PetscCall(SpamDensitySummation(sim, z, &bad));
  for (PetscInt i = 0; i < sim->p.n; i++) rho[i] = sim->pair.f.rho[i];
  PetscCall(VecRestoreArray(sim->p.X, &y));
  PetscCall(PetscFree(z));
  PetscFunctionReturn(0);
}

/* A second right-hand side at the same state walks the near rows and gives ydot's bits. */
static PetscErrorCode NearRows(TestCount *c, const char *name, const Shape *s, SpamSim *sim, const PetscScalar *y, const double *ydot)
{
  const size_t len  = (size_t)sim->p.n * sim->model.layout.nvar;
  const int    wide = sim->pair.f.near_wide;
  double      *again;
  PetscInt     bad;
  size_t       differ = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(len, &again));
  PetscCall(SpamRhs(sim, y, again, &bad));
  for (size_t k = 0; k < len; k++) differ += memcmp(&again[k], &ydot[k], sizeof again[k]) != 0;
  TestCheck(c, wide && !sim->pair.f.near_wide && !differ, "%s D=%d: the first right-hand side walks the whole list (%d), the second the near rows (%d), %zu of %zu values differ (0)", name, s->dim, wide, !sim->pair.f.near_wide, differ, len);
  PetscCall(PetscFree(again));
  PetscFunctionReturn(0);
}

static PetscErrorCode Conservation(TestCount *c, const char *name, const Shape *s, double visc)
{
  const PetscInt     N = LatticeCount(s);
  const SpamLayout  *l;
  double            *x, *v, *m, *e, *ydot, *rp, *rm, p[3] = {0, 0, 0}, pabs = 0.0, power = 0.0, scale = 0.0, hmin = PETSC_INFINITY, hmax = 0.0, law = 0.0, law_scale = 0.0;
  const double       dt = 1e-3;
  SpamSim            sim;
  const PetscScalar *y;
  PetscInt           bad;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4((size_t)N * s->dim, &x, (size_t)N * s->dim, &v, N, &m, N, &e));
  PetscCall(Disorder(s, 17 + s->dim, x, v, m, e));
  PetscCall(MakeGas(name, s, N, x, v, m, visc, &sim));
  PetscCall(SetEnergies(&sim, e));
  l = &sim.model.layout;
  PetscCall(PetscMalloc3((size_t)N * l->nvar, &ydot, N, &rp, N, &rm));
  PetscCall(VecGetArrayRead(sim.p.X, &y));
  PetscCall(SpamRhs(&sim, y, ydot, &bad));
  PetscCall(NearRows(c, name, s, &sim, y, ydot));
  for (PetscInt i = 0; i < N; i++) {
    const double *yi = y + (size_t)i * l->nvar, *fi = ydot + (size_t)i * l->nvar, mi = sim.pair.f.m[i];
    for (int d = 0; d < s->dim; d++) {
      p[d] += mi * fi[l->v + d];
      pabs += mi * fabs(fi[l->v + d]);
      power += mi * yi[l->v + d] * fi[l->v + d];
      scale += mi * fabs(yi[l->v + d] * fi[l->v + d]);
    }
    power += mi * fi[l->e];
    scale += mi * fabs(fi[l->e]);
    hmin = PetscMin(hmin, sim.pair.f.h[i]);
    hmax = PetscMax(hmax, sim.pair.f.h[i]);
  }
  PetscCall(VecRestoreArrayRead(sim.p.X, &y));
  TestCheck(c, hmax > 1.3 * hmin, "%s D=%d disordered: h_i from %.3f to %.3f (spread above 1.3)", name, s->dim, hmin, hmax);
  TestCheck(c, sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) <= 1e-13 * pabs, "%s D=%d disordered%s: |sum m a| / sum m|a| = %.2e (<= 1e-13)", name, s->dim, visc > 0 ? " viscous" : "", sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) / pabs);
  TestCheck(c, fabs(power) <= 1e-13 * scale, "%s D=%d disordered%s: sum m (v.a + de/dt) = %.2e of its terms (<= 1e-13)", name, s->dim, visc > 0 ? " viscous" : "", fabs(power) / scale);
  if (visc == 0.0) {
    /* de_i/dt = (P_i/rho_i^2) drho_i/dt = (gamma - 1) e_i drho_i/dt / rho_i; the central
     * difference errs by O(dt^2 |d3 rho/dt3|) ~ 1e-6 of the rate and the solve's
     * tolerance adds 1e-10 rho / dt ~ 1e-7 rho: bound 1e-4 of the largest rate. */
    PetscCall(DensityAlong(&sim, dt, rp));
    PetscCall(DensityAlong(&sim, -dt, rm));
    PetscCall(VecGetArrayRead(sim.p.X, &y));
    for (PetscInt i = 0; i < N; i++) {
      const double rho = 0.5 * (rp[i] + rm[i]), rate = 0.4 * y[(size_t)i * l->nvar + l->e] * (rp[i] - rm[i]) / (2.0 * dt) / rho;
      law       = PetscMax(law, fabs(ydot[(size_t)i * l->nvar + l->e] - rate));
      law_scale = PetscMax(law_scale, fabs(rate));
    }
    PetscCall(VecRestoreArrayRead(sim.p.X, &y));
    TestCheck(c, law <= 1e-4 * law_scale, "%s D=%d disordered: de/dt against (P/rho^2) drho/dt of the solved density: %.2e of the largest rate (<= 1e-4)", name, s->dim, law / law_scale);
  }
  PetscCall(SpamSimDestroy(&sim));
  PetscCall(PetscFree3(ydot, rp, rm));
  PetscCall(PetscFree4(x, v, m, e));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount c = {0, 0};
  char      names[512], *save = NULL;

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(SpamKernelNames(names, sizeof names));
  for (char *name = strtok_r(names, ", ", &save); name; name = strtok_r(NULL, ", ", &save))
    for (int k = 0; k < 3; k++) {
      PetscCall(Lattice(&c, name, &Shapes[k]));
      PetscCall(Conservation(&c, name, &Shapes[k], 0.0));
      PetscCall(Conservation(&c, name, &Shapes[k], 1.0));
    }
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
