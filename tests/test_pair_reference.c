/* The optimised pair loops (neighbour list, half pairs, whatever sorting or vector code
 * they use; the pair driver of src/pair/ with ghost slots) give the same right-hand side
 * as a plain O(N^2) loop over every ordered pair, written here straight from
 * docs/equations.md, to 1e-12 relative. Only the public entry
 * points are called (SpamRhs, SpamDensitySummation, SpamAccel and the model set-ups);
 * nothing here reads the neighbour list or the ghost slots. Masses m_j are per particle
 * (all 1, or uniform in [0.5, 1.5]); periodic directions use the minimum image here, in
 * the library either the minimum image or periodic images as ghost slots
 * (sim.pair.periodic_ghosts).
 *
 * Isentropic gas, D = 1, 2, 3:
 *   rho_i = sum_j m_j w_ij (self term included),  q = P/rho^2 from the model's EOS,
 *   dv_i/dt = -sum_j m_j (q_i + q_j) grad_i w_ij,  grad_i w_ij = (w'/r) r_ij.
 * Lucy's kernel with equal masses at full size (the chunked fast loops) in periodic, open
 * and (D >= 2) mixed boxes, gamma = 1 + 2/D (in 2D the density-free gamma = 2 path) and
 * 1.4 (the density pass); then for every kernel of kernels/kernel_list.h five smaller cases: periodic equal masses; open unequal; periodic with
 * ghost images, unequal; mixed (1D: periodic) with ghost images, equal; mixed unequal
 * (D >= 2) -- every case but Lucy with equal masses and no ghosts runs the pair driver.
 * Each configuration is random (seeded), with some particles exactly on box faces and on
 * the faces of the cells the current binning uses; it is evaluated four times:
 *   E0  the first evaluation (the list is built);
 *   E1  every particle moved by less than skin/2 (the list must be kept), particles near
 *       a periodic face pushed across it;
 *   E2  a tenth of the particles moved by up to h per direction and another tenth shifted
 *       by a whole periodic edge (a rebuild);
 *   E3  moves below skin/2 again (the rebuilt list kept), and SpamAccel on a compact
 *       position array of another stride.
 * At E0 the law's other traversals run on the same particles and are compared with the
 * case's: the half-list rows with the ghost setting flipped (minimum image against
 * periodic images as ghost slots, which take the pairs' reactions) and the canonical rows
 * of -reproducible; the law itself is coded once (src/pair/pair_density.h,
 * pair_pressure_force.h), so a traversal that drops, doubles or misplaces a pair, or
 * weighs it with the wrong mass, differs from the others by a whole term.
 *
 * Tensor path (elastic solid and gas with the energy equation), D = 1, 2, 3, every
 * kernel, random positions, velocities, energies, densities and stresses (D(D+1)/2
 * components, upper triangle row by row), evaluated at E0, E1, E2 as above:
 *   rho_i summed, or the state's (continuity, chain rule);  T = (gamma - 1) e;
 *   G_i^{ab} = dv^b/dx^a = sum_j m_j (v_j - v_i)^b (grad_i w_ij)^a / rho_ij (/ rho_i for an
 *   elastic solid with summed density),
 *   grad T_i = sum_j m_j (T_j - T_i) grad_i w_ij / rho_ij,  rho_ij = mean or sqrt(rho_i rho_j);
 *   dr/dt: R0 v_i; R1 sum_j v_j w_ij / sum_j w_ij (j = i included);
 *          R2 v_i + eps sum_j m_j (v_j - v_i) w_ij / rho_ij;
 *   Q = sigma/rho^2: the state's stress (elastic) or -P/rho^2 I, P = (gamma - 1) rho e (gas),
 *       plus eta_s (G + G^T - (2/D) div v I) + eta_b div v I (Newtonian) and, for div v < 0,
 *       -rho [beta (h div v)^2 - alpha c h div v] I (von Neumann), all over rho^2;
 *   F_ij = m_i m_j (Q_i + Q_j).grad_i w_ij, in 2D with the part perpendicular to r_ij
 *       scaled (T_ij: 1/R for a positive pair torque, else R; T_i: (f_i + f_j)/2 with the
 *       particle torques 1/2 sum_j L_ij), minus m_i m_j Pi_ij grad_i w_ij (Monaghan, an
 *       approaching pair); dv_i/dt = sum_j F_ij / m_i, plus Gauss's -alpha v_i + beta z x r_i
 *       in the centre-of-mass frame (2D);
 *   de_i/dt = sum_j (v_j - v_i).F_ij / (2 m_i) - sum_j m_j (H_i + H_j).grad_i w_ij,
 *       H = -kappa grad T / rho^2;
 *   drho_i/dt = sum_j m_j (u_i - u_j).grad_i w_ij, u = v (continuity) or dr/dt (chain rule);
 *   dsigma/dt = lambda tr(G) I + eta (G + G^T) + Omega sigma - sigma Omega (elastic),
 *       Omega_ab = (dv_a/dx_b - dv_b/dx_a)/2.
 * Five cases per dimension and kernel cover every option value:
 *   elastic, summation, R0, arithmetic rho_ij, equal masses, periodic, no viscosity, T_i (2D);
 *   elastic, continuity, R1, geometric, unequal, periodic with ghost images, Monaghan +
 *     Newtonian (Kelvin-Voigt) + heat, T_ij (2D);
 *   gas, chain rule, R2, arithmetic, unequal, open, von Neumann + Newtonian + heat, Gauss (2D);
 *   gas, summation, R1, geometric, equal, mixed (1D periodic) with ghost images, Monaghan + heat;
 *   elastic, chain rule, R2, geometric, equal, mixed (1D open), von Neumann, T_i (2D);
 * and in 2D two more with torque scaling per body (per_body) on two jittered lattice blobs
 * 10 apart (the reference labels its own connected parts, pairs nearer than h):
 *   elastic, continuity, R0, unequal, open, T_ij;  gas, summation, R2, Monaghan +
 *   Newtonian, open, T_i.
 * The other cases scale with one global body (per_body off).
 *
 * The scale of each comparison: the optimised sum and the reference add the same pair
 * terms F_ij in different orders (half list, sorted or vectorised, against j = 0..N-1),
 * so their difference is the round-off of adding those terms, a few ulp of
 * S_i = sum_j |F_ij| / m, the sum of the magnitudes. The total |sum_j F_ij| may cancel to
 * far below S_i (a particle in a uniform region feels almost no force), so a tolerance
 * relative to the total would fail on correct code; one relative to S_i still fails for
 * any missing, duplicated, misplaced or mis-weighted pair, whose error is a whole term.
 * The density has only positive terms, so its total is its scale. In the tensor path a
 * quantity built from a pair sum (G, grad T, dr/dt) carries that sum's round-off into the
 * next walk, so the scales use the sums of magnitudes throughout: |Q| is taken with
 * sum_j |G terms| in place of G, a scaled force with max(1, factor), the chain-rule u
 * with the scale of dr/dt, Gauss's force with the round-off of Ldot through beta, alpha.
 *
 * -reference_perturb self|factor spoils the reference (no self term in the summed
 * density; every reference rate and summed density times 1.000001) to show that the
 * test then fails: every check fails under one of the two (under `factor` alone a ratio
 * such as G ~ 1/rho of a summed density cancels the factor, under `self` alone a state
 * density is untouched). */
#include <spam/physics.h>
#include <spam/scene.h>
#include "test_util.h"

#define TOL 1e-12

/* How -reference_perturb spoils the reference, passed down to the reference loops. */
typedef struct {
  int    self;   /* include the self term m w(0) in the reference density */
  double factor; /* multiplies every reference rate and summed density    */
} Spoil;

/* Largest |difference| / scale over particles, and where. */
typedef struct {
  double worst;
  int    at;
} Worst;

static void Track(Worst *w, double diff, double scale, int i)
{
  const double r = scale > 0.0 ? diff / scale : (diff > 0.0 ? INFINITY : diff);
  if (isnan(w->worst)) return; /* a NaN anywhere fails the check */
  if (!(r <= w->worst)) {
    w->worst = r;
    w->at    = i;
  }
}

/* Box-local (wrapped) coordinates of every particle, u[i*dim + d]. */
static void Local(const SpamBox *b, int n, const double *y, int stride, double *u)
{
  for (int i = 0; i < n; i++)
    for (int d = 0; d < b->dim; d++) u[i * b->dim + d] = SpamBoxLocal(b, d, y[(size_t)i * stride + d]);
}

/* r_i - r_j by the minimum image; returns r^2. */
static double Sep(const SpamBox *b, const double *u, int i, int j, double dx[3])
{
  double r2 = 0.0;
  for (int d = 0; d < b->dim; d++) {
    dx[d] = SpamBoxMinImage(u[i * b->dim + d] - u[j * b->dim + d], b->len[d], 0.5 * b->len[d], b->periodic[d]);
    r2 += dx[d] * dx[d];
  }
  return r2;
}

/* ---------------------------------------------------------------- isentropic gas --- */

/* Plain reference of the gas: density, accelerations a[i*dim + d] and their scales S. */
static void GasReference(const Spoil *spoil, const SpamModel *m, const SpamBox *b, int n, const double *u, const double *mass, double *rho, double *q, double *a, double *S)
{
  const int dim = m->dim;
  for (int i = 0; i < n; i++) {
    double r = 0.0;
    for (int j = 0; j < n; j++) {
      double dx[3];
      if (j == i && !spoil->self) continue;
      r += mass[j] * SpamKernelW(&m->kernel, Sep(b, u, i, j, dx)); /* j = i: m_i w(0) */
    }
    rho[i] = spoil->factor * r;
    q[i]   = SpamEosPOverRho2(&m->eos, rho[i]);
  }
  for (int i = 0; i < n; i++) {
    double ai[3] = {0, 0, 0}, s = 0.0;
    for (int j = 0; j < n; j++) {
      double dx[3], len = 0.0;
      if (j == i) continue; /* grad w vanishes at r = 0 */
      const double g = SpamKernelDWOverR(&m->kernel, Sep(b, u, i, j, dx));
      const double c = -mass[j] * (q[i] + q[j]) * g;
      for (int d = 0; d < dim; d++) {
        ai[d] += c * dx[d];
        len += dx[d] * dx[d];
      }
      s += fabs(c) * sqrt(len);
    }
    for (int d = 0; d < dim; d++) a[i * dim + d] = spoil->factor * ai[d];
    S[i] = s;
  }
}

/* Exact faces: a particle has, in random directions, a coordinate on a cell face or at a
 * cell centre (k cw / 2, cw = len / floor(len / (h + skin)) as the current binning
 * makes its cells; the edges below make cw exact), on the box faces included. In 1D
 * (and now and then in 2D and 3D) two particles get the same face value, so some pairs
 * sit at r = 0 exactly, where grad w = 0 and w = w(0). */
static double FaceValue(const SpamBox *b, int d, double rc, uint64_t *seed)
{
  const int    nc = (int)floor(b->len[d] / rc);
  const double cw = b->len[d] / nc;
  const int    k  = (int)((2 * nc + 1) * TestUniform(seed)); /* 0 .. 2 nc: lo .. lo + len */
  return b->lo[d] + 0.5 * cw * k;
}

/* Moves below skin/2 from the current positions: at most 0.2 skin at random, or, for a
 * particle within 0.15 skin of a periodic face, 0.3 skin straight across it. Returns the
 * number of face crossings. */
static int SmallMove(const SpamBox *b, int n, double *y, int nv, double skin, uint64_t *seed)
{
  const int dim = b->dim;
  int       crossed = 0;
  for (int i = 0; i < n; i++) {
    double *x = y + (size_t)i * nv, r[3], norm = 0.0;
    int     across = 0;
    for (int d = 0; d < dim && !across; d++) {
      if (!b->periodic[d]) continue;
      const double ul = SpamBoxLocal(b, d, x[d]);
      if (ul < 0.15 * skin) across = -(d + 1);
      else if (ul > b->len[d] - 0.15 * skin) across = d + 1;
    }
    if (across) {
      const int d = abs(across) - 1;
      x[d] += (across > 0 ? 0.3 : -0.3) * skin;
      crossed++;
      continue;
    }
    for (int d = 0; d < dim; d++) {
      r[d] = 2.0 * TestUniform(seed) - 1.0;
      norm += r[d] * r[d];
    }
    const double f = 0.2 * skin * TestUniform(seed) / sqrt(norm + 1e-300);
    for (int d = 0; d < dim; d++) x[d] += f * r[d];
  }
  return crossed;
}

/* Moves past skin/2: a tenth of the particles by up to h per direction, another tenth by
 * a whole edge in a periodic direction (the same physics, far in raw coordinates). */
static void LargeMove(const SpamBox *b, int n, double *y, int nv, double h, uint64_t *seed)
{
  for (int i = 0; i < n; i++) {
    double    *x = y + (size_t)i * nv;
    const double p = TestUniform(seed);
    if (p < 0.1) {
      for (int d = 0; d < b->dim; d++) x[d] += h * (2.0 * TestUniform(seed) - 1.0);
    } else if (p < 0.2) {
      for (int d = 0; d < b->dim; d++)
        if (b->periodic[d] && TestUniform(seed) < 0.7) x[d] += (TestUniform(seed) < 0.5 ? -1.0 : 1.0) * b->len[d];
    }
  }
}

typedef struct {
  int          dim;
  double       h, lo[3], len[3];
  int          n;
  const char  *name;
} GasGeometry;

/* One gas case: kernel, box, EOS, masses (all 1, or uniform in [0.5, 1.5]) and whether
 * the periodic directions are made by ghost slots (then the pair driver runs). */
typedef struct {
  const char *kernel, *bname;
  PetscBool   periodic[3], unequal, ghosts;
  double      gamma;
  int         n; /* 0: the geometry's */
} GasOpts;

/* Compares SpamRhs (and SpamDensitySummation, and at E3 SpamAccel) with the reference. */
static PetscErrorCode GasCompare(TestCount *c, const Spoil *spoil, SpamSim *sim, const char *label, int stage, int crossed, const double *mass, double *u, double *rho, double *q, double *a, double *S, double *ydot, double *xc)
{
  const SpamModel *m = &sim->model;
  const int        dim = m->dim, nv = m->layout.nvar, n = (int)sim->p.n;
  PetscScalar     *y;
  PetscInt         bad = -1, bad2 = -1, bad3 = -1;
  Worst            wa = {0, -1}, wr = {0, -1}, wacc = {0, -1};
  double           xerr = 0.0;
  static const char *what[4] = {"E0 first", "E1 moves < skin/2", "E2 rebuild", "E3 rebuilt list kept"};

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  Local(&sim->geo.box, n, y, nv, u);
  GasReference(spoil, m, &sim->geo.box, n, u, mass, rho, q, a, S);
  PetscCall(SpamRhs(sim, y, ydot, &bad));
  for (int i = 0; i < n; i++) {
    double d2 = 0.0;
    for (int d = 0; d < dim; d++) {
      const double e = ydot[(size_t)i * nv + m->layout.v + d] - a[i * dim + d];
      d2 += e * e;
      xerr = PetscMax(xerr, fabs(ydot[(size_t)i * nv + m->layout.x + d] - y[(size_t)i * nv + m->layout.v + d]));
    }
    Track(&wa, sqrt(d2), S[i], i);
  }
  PetscCall(SpamDensitySummation(sim, y, &bad2));
  for (int i = 0; i < n; i++) Track(&wr, fabs(sim->pair.f.rho[i] - rho[i]), rho[i], i);
  if (stage == 3) { /* SpamAccel on a compact copy of the positions (stride dim) */
    for (int i = 0; i < n; i++)
      for (int d = 0; d < dim; d++) xc[i * dim + d] = y[(size_t)i * nv + m->layout.x + d];
    PetscCall(SpamAccel(sim, xc, dim, &bad3));
    for (int i = 0; i < n; i++) {
      double d2 = 0.0;
      for (int d = 0; d < dim; d++) {
        const double e = sim->pair.f.acc[(size_t)i * dim + d] - a[i * dim + d];
        d2 += e * e;
      }
      Track(&wacc, sqrt(d2), S[i], i);
    }
  }
  PetscCall(VecRestoreArray(sim->p.X, &y));
  char extra[64] = "";
  if (crossed) (void)snprintf(extra, sizeof extra, ", %d across a periodic face", crossed);
  TestCheck(c, bad < 0 && wa.worst <= TOL && xerr == 0.0, "%s %s%s: SpamRhs max |a - a_ref| / S_i = %.2e (particle %d; < 1e-12), dr/dt = v exactly (%.0e)", label, what[stage], extra, wa.worst, wa.at, xerr);
  TestCheck(c, bad2 < 0 && wr.worst <= TOL, "%s %s: SpamDensitySummation max |rho - rho_ref| / rho_ref = %.2e (< 1e-12)", label, what[stage], wr.worst);
  if (stage == 3) TestCheck(c, bad3 < 0 && wacc.worst <= TOL, "%s %s: SpamAccel (stride %d) max |a - a_ref| / S_i = %.2e (< 1e-12)", label, what[stage], dim, wacc.worst);
  PetscFunctionReturn(0);
}

/* The gas model with kernel kname, the particles' masses (NULL: all 1) and, on request,
 * periodic images as ghost slots and -reproducible; -threads T as in TestMakeSim. */
static PetscErrorCode MakeGasSim(const SpamBox *box, const char *kname, double h, double gamma, PetscInt n, const double *x, const double *v, const double *mass, PetscBool ghosts, PetscBool reproducible, SpamSim *sim)
{
  SpamModel  model;
  SpamKernel kern;
  PetscInt   threads = 1;

  PetscFunctionBeginUser;
  PetscCall(SpamKernelCreate(kname, box->dim, h, &kern));
  PetscCall(SpamModelIsentropeSetUp(box->dim, &kern, 1.0, gamma, 1.0 / gamma, &model));
  PetscCall(SpamSimCreate(PETSC_COMM_SELF, &model, box, n, 0.1 * h, sim));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-threads", &threads, NULL));
  sim->pair.threads         = (int)threads;
  sim->pair.periodic_ghosts = ghosts;
  sim->pair.reproducible    = reproducible;
  PetscCall(SpamSimFill(sim, x, v, mass));
  PetscCall(SpamSimSetUp(sim));
  PetscFunctionReturn(0);
}

/* Masses: all 1, or uniform in [0.5, 1.5]. */
static void Masses(PetscBool unequal, int n, double *mass, uint64_t *seed)
{
  for (int i = 0; i < n; i++) mass[i] = unequal ? 0.5 + TestUniform(seed) : 1.0;
}

/* The law's other traversals on the particles of sim at their first positions x: the
 * half-list rows with the ghost setting flipped (periodic images as ghost slots, which take
 * the pairs' reactions, or the minimum image) and the canonical rows of -reproducible. The
 * three add the same pair terms (pair_density.h, pair_pressure_force.h) in different
 * orders, so they agree to round-off of the sums of magnitudes S_i (rho_i for the
 * density); compared by input row, whatever order each sim keeps its particles in. */
static PetscErrorCode TraversalCompare(TestCount *c, SpamSim *sim, const GasOpts *o, const char *label, const double *x, const double *v, const double *mass, const double *S, double *ydot)
{
  static const char *names[2] = {"half-list rows, ghost setting flipped", "canonical rows (-reproducible)"};
  const int          n = (int)sim->p.n, dim = sim->model.dim;
  double            *a0, *r0, *s0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3((size_t)n * dim, &a0, n, &r0, n, &s0));
  for (int i = 0; i < n; i++) { /* sim's values and scales by input row */
    const PetscInt row = SpamSimRowOf(sim, i);
    r0[row]            = sim->pair.f.rho[i];
    s0[row]            = S[i];
    for (int d = 0; d < dim; d++) a0[(size_t)row * dim + d] = sim->pair.f.acc[(size_t)i * dim + d];
  }
  for (int t = 0; t < 2; t++) {
    SpamSim      other;
    PetscScalar *y;
    PetscInt     bad = -1, bad2 = -1;
    Worst        wa = {0, -1}, wr = {0, -1};
    PetscCall(MakeGasSim(&sim->geo.box, o->kernel, sim->model.kernel.h, o->gamma, n, x, v, o->unequal ? mass : NULL, (PetscBool)(t == 0 ? !o->ghosts : o->ghosts), (PetscBool)(t == 1), &other));
    PetscCall(VecGetArray(other.p.X, &y));
    PetscCall(SpamRhs(&other, y, ydot, &bad));
    PetscCall(SpamDensitySummation(&other, y, &bad2));
    PetscCall(VecRestoreArray(other.p.X, &y));
    for (int i = 0; i < n; i++) {
      const PetscInt row = SpamSimRowOf(&other, i);
      double         d2  = 0.0;
      for (int d = 0; d < dim; d++) {
        const double e = other.pair.f.acc[(size_t)i * dim + d] - a0[(size_t)row * dim + d];
        d2 += e * e;
      }
      Track(&wa, sqrt(d2), s0[row], (int)row);
      Track(&wr, fabs(other.pair.f.rho[i] - r0[row]), r0[row], (int)row);
    }
    TestCheck(c, bad < 0 && bad2 < 0 && wa.worst <= TOL && wr.worst <= TOL, "%s E0: %s against the case's traversal: max |a - a'| / S_i = %.2e, |rho - rho'| / rho = %.2e (< 1e-12)", label, names[t], wa.worst, wr.worst);
    PetscCall(SpamSimDestroy(&other));
  }
  PetscCall(PetscFree3(a0, r0, s0));
  PetscFunctionReturn(0);
}

static PetscErrorCode GasCase(TestCount *c, const Spoil *spoil, const GasGeometry *gg, const GasOpts *o, uint64_t seed)
{
  const int    dim = gg->dim, n = o->n ? o->n : gg->n;
  const double h = gg->h, skin = 0.1 * h; /* MakeGasSim's skin */
  SpamBox      b = {dim, {0, 0, 0}, {0, 0, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
  SpamSim      sim;
  double      *x, *v, *mass, *u, *rho, *q, *a, *S, *ydot, *xc;
  PetscScalar *y;
  char         label[160];
  int          nv, crossed;

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) {
    b.lo[d]       = gg->lo[d];
    b.len[d]      = gg->len[d];
    b.periodic[d] = o->periodic[d];
  }
  (void)snprintf(label, sizeof label, "gas %s D=%d %s%s gamma=%g %s masses N=%d", o->kernel, dim, o->bname, o->ghosts ? " (ghost images)" : "", o->gamma, o->unequal ? "unequal" : "equal", n);
  PetscCall(PetscMalloc3((size_t)n * dim, &x, (size_t)n * dim, &v, n, &mass));
  for (int i = 0; i < n; i++) {
    /* one particle in eight has coordinates on exact faces (in 1D: all of them) */
    const PetscBool special = (PetscBool)(i % 8 == 0);
    for (int d = 0; d < dim; d++) {
      const PetscBool face = (PetscBool)(special && (dim == 1 || TestUniform(&seed) < 0.6));
      x[i * dim + d]       = face ? FaceValue(&b, d, h + skin, &seed) : b.lo[d] + b.len[d] * TestUniform(&seed);
      v[i * dim + d]       = TestUniform(&seed) - 0.5;
    }
  }
  Masses(o->unequal, n, mass, &seed);
  PetscCall(MakeGasSim(&b, o->kernel, h, o->gamma, n, x, v, o->unequal ? mass : NULL, o->ghosts, PETSC_FALSE, &sim));
  nv = sim.model.layout.nvar;
  PetscCall(PetscMalloc5((size_t)n * dim, &u, n, &rho, n, &q, (size_t)n * dim, &a, n, &S));
  PetscCall(PetscMalloc2((size_t)n * nv, &ydot, (size_t)n * dim, &xc));

  PetscCall(GasCompare(c, spoil, &sim, label, 0, 0, mass, u, rho, q, a, S, ydot, xc));
  PetscCall(TraversalCompare(c, &sim, o, label, x, v, mass, S, ydot));
  PetscCall(VecGetArray(sim.p.X, &y));
  crossed = SmallMove(&b, n, y, nv, skin, &seed);
  PetscCall(VecRestoreArray(sim.p.X, &y));
  PetscCall(GasCompare(c, spoil, &sim, label, 1, crossed, mass, u, rho, q, a, S, ydot, xc));
  PetscCall(VecGetArray(sim.p.X, &y));
  LargeMove(&b, n, y, nv, h, &seed);
  PetscCall(VecRestoreArray(sim.p.X, &y));
  PetscCall(GasCompare(c, spoil, &sim, label, 2, 0, mass, u, rho, q, a, S, ydot, xc));
  PetscCall(VecGetArray(sim.p.X, &y));
  crossed = SmallMove(&b, n, y, nv, skin, &seed);
  PetscCall(VecRestoreArray(sim.p.X, &y));
  PetscCall(GasCompare(c, spoil, &sim, label, 3, crossed, mass, u, rho, q, a, S, ydot, xc));

  PetscCall(PetscFree2(ydot, xc));
  PetscCall(PetscFree5(u, rho, q, a, S));
  PetscCall(PetscFree3(x, v, mass));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------------ tensor path --- */

/* Offset of sigma_ab in the state: the upper triangle row by row (2D xx xy yy; 3D xx xy
 * xz yy yz zz). */
static int StressAt(int dim, int a, int b)
{
  if (a > b) {
    const int t = a;
    a           = b;
    b           = t;
  }
  return a * dim - a * (a - 1) / 2 + (b - a);
}

/* Per-particle intermediates of the tensor reference: D x D arrays [i*9 + a*D + b]. */
typedef struct {
  double *rho, *T;     /* density (summed or the state's), temperature (gamma - 1) e     */
  double *G, *Gs;      /* grad v (G^{ab} = dv^b/dx^a) and the sums of its terms' |.|     */
  double *Q, *qa;      /* sigma/rho^2 with the viscous stresses, and its magnitude       */
  double *H, *Ha;      /* grad T, then the heat flux -kappa grad T / rho^2; magnitude    */
  double *xd, *xs;     /* dr/dt and its scale                                            */
  double *lt, *tf;     /* T_i: particle torque 1/2 sum_j L_ij and factor                 */
  double *acc, *as;    /* acceleration and its scale (before Gauss's force)              */
  int    *body, nbody; /* torque scaling's bodies (per_body), else all 0                 */
  double *bpos, *bneg, *bR; /* per body: torque sums and the ratio R                     */
} TensorWork;

/* Sound speed of the viscosities: c_L of Hooke's solid, or the gas's at its initial state. */
static double SoundSpeed(const SpamSolidParams *p)
{
  if (p->material == SPAM_MATERIAL_GAS) return sqrt(p->gamma * (p->gamma - 1.0) * p->gas_e0);
  return sqrt((p->lambda + 2.0 * p->eta) / p->rho0);
}

static double Norm(int dim, const double *a)
{
  double s = 0.0;
  for (int d = 0; d < dim; d++) s += a[d] * a[d];
  return sqrt(s);
}

/* Density, temperature; grad v, grad T and dr/dt (R0 v; R1 sum_j v_j w_ij / sum_j w_ij
 * with j = i; R2 v_i + eps sum_j m_j (v_j - v_i) w_ij / rho_ij). */
static void TensorGradients(const Spoil *spoil, const SpamModel *m, const SpamBox *b, int n, const double *y, const double *u, const double *mass, TensorWork *w)
{
  const SpamLayout      *l = &m->layout;
  const SpamSolidParams *p = &m->solid;
  const int              D = m->dim, nv = l->nvar;

  for (int i = 0; i < n; i++) {
    if (p->density == SPAM_DENSITY_SUMMATION) {
      double r = 0.0;
      for (int j = 0; j < n; j++) {
        double dx[3];
        if (j == i && !spoil->self) continue;
        r += mass[j] * SpamKernelW(&m->kernel, Sep(b, u, i, j, dx));
      }
      w->rho[i] = spoil->factor * r;
    } else w->rho[i] = y[(size_t)i * nv + l->rho];
    w->T[i] = (p->gamma - 1.0) * y[(size_t)i * nv + l->e];
  }
  for (int i = 0; i < n; i++) {
    const double *vi = y + (size_t)i * nv + l->v;
    double       *G = w->G + 9 * i, *Gs = w->Gs + 9 * i, *H = w->H + 3 * i, *xd = w->xd + 3 * i, wsum = 0.0, xs = 0.0;
    for (int k = 0; k < 9; k++) G[k] = Gs[k] = 0.0;
    for (int d = 0; d < 3; d++) H[d] = xd[d] = 0.0;
    w->Ha[i] = 0.0;
    for (int j = 0; j < n; j++) {
      const double *vj = y + (size_t)j * nv + l->v;
      double        dx[3], dv[3];
      const double  r2 = Sep(b, u, i, j, dx), wij = SpamKernelW(&m->kernel, r2);
      for (int d = 0; d < D; d++) dv[d] = vj[d] - vi[d];
      if (p->coords == SPAM_COORDS_R1) {
        wsum += wij;
        for (int d = 0; d < D; d++) xd[d] += wij * vj[d];
        xs += wij * Norm(D, vj);
      }
      if (j == i || r2 >= m->kernel.h2) continue;
      const double g   = SpamKernelDWOverR(&m->kernel, r2);
      const double rij = p->rho_geometric ? sqrt(w->rho[i] * w->rho[j]) : 0.5 * (w->rho[i] + w->rho[j]);
      /* An elastic solid with summed density divides by its own density (rhs_tensor.c). */
      const double rg = p->material == SPAM_MATERIAL_ELASTIC && p->density == SPAM_DENSITY_SUMMATION ? w->rho[i] : rij;
      for (int a = 0; a < D; a++)
        for (int bb = 0; bb < D; bb++) {
          const double t = mass[j] * dv[bb] * g * dx[a] / rg;
          G[a * D + bb] += t;
          Gs[a * D + bb] += fabs(t);
        }
      if (p->coords == SPAM_COORDS_R2) {
        const double cw = p->xsph_eps * mass[j] * wij / rij;
        for (int d = 0; d < D; d++) xd[d] += cw * dv[d];
        xs += fabs(cw) * Norm(D, dv);
      }
      if (p->conductivity > 0.0) {
        const double t = mass[j] * (w->T[j] - w->T[i]) * g / rij;
        for (int d = 0; d < D; d++) H[d] += t * dx[d];
        w->Ha[i] += fabs(t) * sqrt(r2);
      }
    }
    if (p->coords == SPAM_COORDS_R1)
      for (int d = 0; d < D; d++) xd[d] /= wsum;
    else
      for (int d = 0; d < D; d++) xd[d] += vi[d];
    w->xs[i] = p->coords == SPAM_COORDS_R1 ? xs / wsum : xs + Norm(D, vi);
  }
}

/* sigma/rho^2: the state's stress (elastic) or -P/rho^2 I, P = (gamma - 1) rho e (gas);
 * plus Newtonian sigma_v = eta_s (G + G^T - (2/D) div v I) + eta_b div v I and von
 * Neumann's -q I, q = rho [beta (h div v)^2 - alpha c h div v] for div v < 0; the heat
 * flux -kappa grad T / rho^2; and the elastic stress rate
 * lambda tr(G) I + eta (G + G^T) + Omega sigma - sigma Omega into ref, its scale into scl. */
static void TensorLaws(const SpamModel *m, int n, const double *y, TensorWork *w, double *ref, double *scl)
{
  const SpamLayout      *l = &m->layout;
  const SpamSolidParams *p = &m->solid;
  const int              D = m->dim, nv = l->nvar;
  const double           h = m->kernel.h, c = SoundSpeed(p);

  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv, *G = w->G + 9 * i, *Gs = w->Gs + 9 * i, rho = w->rho[i], r2 = rho * rho;
    double       *Q = w->Q + 9 * i, S[9] = {0}, div = 0.0, sdiv = 0.0, qa = 0.0;
    for (int a = 0; a < D; a++) {
      div += G[a * D + a];
      sdiv += Gs[a * D + a];
    }
    for (int a = 0; a < D; a++)
      for (int bb = 0; bb < D; bb++) {
        if (l->s >= 0) S[a * D + bb] = yi[l->s + StressAt(D, a, bb)];
        Q[a * D + bb] = p->material == SPAM_MATERIAL_GAS ? (a == bb ? -(p->gamma - 1.0) * rho * yi[l->e] / r2 : 0.0) : S[a * D + bb] / r2;
        qa += fabs(Q[a * D + bb]);
        /* Newtonian viscosity */
        const double bulk = a == bb ? p->bulk_visc - 2.0 * p->shear_visc / D : 0.0;
        Q[a * D + bb] += (p->shear_visc * (G[a * D + bb] + G[bb * D + a]) + bulk * div) / r2;
        qa += (p->shear_visc * (Gs[a * D + bb] + Gs[bb * D + a]) + fabs(bulk) * sdiv) / r2;
      }
    if (p->viscosity == SPAM_VISCOSITY_VON_NEUMANN && div < 0.0) {
      const double q = rho * (p->visc_beta * h * h * div * div - p->visc_alpha * c * h * div);
      for (int a = 0; a < D; a++) Q[a * D + a] -= q / r2;
      qa += D * rho * (2.0 * p->visc_beta * h * h * fabs(div) * sdiv + p->visc_alpha * c * h * sdiv) / r2;
    }
    w->qa[i] = qa;
    for (int d = 0; d < D; d++) w->H[3 * i + d] *= -p->conductivity / r2;
    w->Ha[i] *= p->conductivity / r2;
    if (p->material != SPAM_MATERIAL_ELASTIC) continue;
    for (int a = 0; a < D; a++)
      for (int bb = a; bb < D; bb++) {
        const int k = l->s + StressAt(D, a, bb);
        double    r = p->eta * (G[a * D + bb] + G[bb * D + a]) + (a == bb ? p->lambda * div : 0.0);
        double    s = p->eta * (Gs[a * D + bb] + Gs[bb * D + a]) + (a == bb ? p->lambda * sdiv : 0.0);
        for (int cc = 0; cc < D; cc++) {
          /* Omega_ab = (dv_a/dx_b - dv_b/dx_a)/2, dv_a/dx_b = G^{ba} */
          const double om_ac = 0.5 * (G[cc * D + a] - G[a * D + cc]), om_cb = 0.5 * (G[bb * D + cc] - G[cc * D + bb]);
          r += om_ac * S[cc * D + bb] - S[a * D + cc] * om_cb;
          s += 0.5 * (Gs[cc * D + a] + Gs[a * D + cc]) * fabs(S[cc * D + bb]) + fabs(S[a * D + cc]) * 0.5 * (Gs[bb * D + cc] + Gs[cc * D + bb]);
        }
        ref[(size_t)i * nv + k] = r;
        scl[(size_t)i * nv + k] = s;
      }
  }
}

/* F_ij = m_i m_j (Q_i + Q_j).grad_i w_ij, unscaled; returns the pair torque (2D). */
static double PairForce(int D, const TensorWork *w, const double *mass, int i, int j, const double dx[3], double g, double F[3])
{
  const double *Qi = w->Q + 9 * i, *Qj = w->Q + 9 * j;
  for (int a = 0; a < 3; a++) F[a] = 0.0;
  for (int a = 0; a < D; a++)
    for (int bb = 0; bb < D; bb++) F[a] += mass[i] * mass[j] * g * (Qi[a * D + bb] + Qj[a * D + bb]) * dx[bb];
  return D == 2 ? dx[0] * F[1] - dx[1] * F[0] : 0.0;
}

/* Torque scaling (2D): per body, R = sqrt(sum of positive torques / -sum of negative
 * ones) over the pairs i < j (T_ij) or over the particle torques L_i = 1/2 sum_j L_ij
 * (T_i, with the particle factors f_i = 1/R for L_i > 0, else R); 1 where either sum is
 * zero. A pair's torque counts in the body of its particles (one body: the cases with
 * bodies keep them apart by more than h). */
static void TorqueRatio(const SpamModel *m, const SpamBox *b, int n, const double *u, const double *mass, TensorWork *w)
{
  const int tij = m->solid.angmom == SPAM_ANGMOM_TIJ;

  for (int k = 0; k < w->nbody; k++) w->bpos[k] = w->bneg[k] = 0.0;
  for (int i = 0; i < n; i++) {
    const int k = w->body[i];
    w->lt[i]    = 0.0;
    for (int j = 0; j < n; j++) {
      double       dx[3], F[3];
      const double r2 = Sep(b, u, i, j, dx);
      if (j == i || r2 >= m->kernel.h2) continue;
      const double L = PairForce(2, w, mass, i, j, dx, SpamKernelDWOverR(&m->kernel, r2), F);
      w->lt[i] += 0.5 * L;
      if (tij && j > i) {
        if (L > 0.0) w->bpos[k] += L;
        else w->bneg[k] += L;
      }
    }
    if (!tij) {
      if (w->lt[i] > 0.0) w->bpos[k] += w->lt[i];
      else w->bneg[k] += w->lt[i];
    }
  }
  for (int k = 0; k < w->nbody; k++) w->bR[k] = w->bpos[k] > 0.0 && w->bneg[k] < 0.0 ? sqrt(w->bpos[k] / -w->bneg[k]) : 1.0;
  for (int i = 0; i < n; i++) w->tf[i] = w->lt[i] > 0.0 ? 1.0 / w->bR[w->body[i]] : w->bR[w->body[i]];
}

/* Gauss's constraint (2D, centre-of-mass frame): a_i += -alpha v_i + beta (-y_i, x_i),
 * beta = -Ldot / (I - L^2/2K), alpha = beta L / 2K, with I = sum m r^2, K = sum m v^2/2,
 * Ldot = sum m (rdot x v + r x a); skipped where singular. The scale adds the round-off of
 * Ldot (from the accelerations' scales) carried through beta and alpha. */
static void GaussReference(const SpamModel *m, int n, const double *y, const double *mass, TensorWork *w)
{
  const SpamLayout *l  = &m->layout;
  const int         nv = l->nvar;
  double            M = 0.0, rc[2] = {0, 0}, vc[2] = {0, 0}, xc[2] = {0, 0}, L = 0.0, K = 0.0, inertia = 0.0, Ld = 0.0, Ls = 0.0;

  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv;
    M += mass[i];
    for (int d = 0; d < 2; d++) {
      rc[d] += mass[i] * yi[l->x + d];
      vc[d] += mass[i] * yi[l->v + d];
      xc[d] += mass[i] * w->xd[3 * i + d];
    }
  }
  for (int d = 0; d < 2; d++) {
    rc[d] /= M;
    vc[d] /= M;
    xc[d] /= M;
  }
  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv;
    const double  r[2] = {yi[l->x] - rc[0], yi[l->x + 1] - rc[1]}, v[2] = {yi[l->v] - vc[0], yi[l->v + 1] - vc[1]};
    const double  rd[2] = {w->xd[3 * i] - xc[0], w->xd[3 * i + 1] - xc[1]}, *a = w->acc + 3 * i;
    L += mass[i] * (r[0] * v[1] - r[1] * v[0]);
    K += 0.5 * mass[i] * (v[0] * v[0] + v[1] * v[1]);
    inertia += mass[i] * (r[0] * r[0] + r[1] * r[1]);
    Ld += mass[i] * (rd[0] * v[1] - rd[1] * v[0] + r[0] * a[1] - r[1] * a[0]);
    Ls += mass[i] * (hypot(rd[0], rd[1]) * hypot(v[0], v[1]) + hypot(r[0], r[1]) * (w->as[i] + w->xs[i]));
  }
  const double den = K > 0.0 ? inertia - L * L / (2.0 * K) : 0.0;
  if (!(K > 0.0) || !(fabs(den) > 1e-9 * inertia)) return;
  const double beta = -Ld / den, alpha = beta * L / (2.0 * K), sb = Ls / fabs(den), sa = sb * fabs(L) / (2.0 * K);
  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv;
    const double  r[2] = {yi[l->x] - rc[0], yi[l->x + 1] - rc[1]}, v[2] = {yi[l->v] - vc[0], yi[l->v + 1] - vc[1]};
    w->acc[3 * i] += -alpha * v[0] - beta * r[1];
    w->acc[3 * i + 1] += -alpha * v[1] + beta * r[0];
    w->as[i] += (sa + fabs(alpha)) * hypot(v[0], v[1]) + (sb + fabs(beta)) * hypot(r[0], r[1]);
  }
}

/* The whole ydot of the tensor path (layout of m) and the scale of every component. */
static void TensorReference(const Spoil *spoil, const SpamModel *m, const SpamBox *b, int n, const double *y, const double *u, const double *mass, TensorWork *w, double *ref, double *scl)
{
  const SpamLayout      *l = &m->layout;
  const SpamSolidParams *p = &m->solid;
  const int              D = m->dim, nv = l->nvar, chain = p->density == SPAM_DENSITY_CHAIN_RULE;
  const int              scale = D == 2 && (p->angmom == SPAM_ANGMOM_TI || p->angmom == SPAM_ANGMOM_TIJ);
  const double           h = m->kernel.h, c = SoundSpeed(p);

  TensorGradients(spoil, m, b, n, y, u, mass, w);
  TensorLaws(m, n, y, w, ref, scl);
  if (scale) TorqueRatio(m, b, n, u, mass, w);
  for (int i = 0; i < n; i++) {
    const double *vi = y + (size_t)i * nv + l->v, *ui = chain ? w->xd + 3 * i : vi;
    const double  usi = chain ? w->xs[i] : 0.0;
    double       *ri = ref + (size_t)i * nv, *ci = scl + (size_t)i * nv, *acc = w->acc + 3 * i;
    double        ed = 0.0, es = 0.0, rd = 0.0, rs = 0.0;
    w->as[i] = 0.0;
    for (int d = 0; d < 3; d++) acc[d] = 0.0;
    for (int j = 0; j < n; j++) {
      const double *vj = y + (size_t)j * nv + l->v, *uj = chain ? w->xd + 3 * j : vj;
      double        dx[3], F[3], dv[3];
      const double  r2 = Sep(b, u, i, j, dx), r = sqrt(r2);
      if (j == i || r2 >= m->kernel.h2) continue;
      const double g = SpamKernelDWOverR(&m->kernel, r2), mm = mass[i] * mass[j];
      const double L = PairForce(D, w, mass, i, j, dx, g, F);
      double       fs = mm * fabs(g) * r * (w->qa[i] + w->qa[j]), vr = 0.0;
      if (scale) { /* the part of F perpendicular to r_ij times the pair's factor */
        const double fac = p->angmom == SPAM_ANGMOM_TIJ ? (L > 0.0 ? 1.0 / w->bR[w->body[i]] : w->bR[w->body[i]]) : 0.5 * (w->tf[i] + w->tf[j]);
        const double along = (F[0] * dx[0] + F[1] * dx[1]) / r2;
        for (int d = 0; d < 2; d++) F[d] = along * dx[d] + fac * (F[d] - along * dx[d]);
        fs *= PetscMax(1.0, fac);
      }
      for (int d = 0; d < D; d++) {
        dv[d] = vj[d] - vi[d];
        vr -= dv[d] * dx[d];
      }
      if (p->viscosity == SPAM_VISCOSITY_MONAGHAN && vr < 0.0) { /* Pi_ij of an approaching pair */
        const double rij = p->rho_geometric ? sqrt(w->rho[i] * w->rho[j]) : 0.5 * (w->rho[i] + w->rho[j]);
        const double mu = h * vr / (r2 + 0.01 * h * h), Pi = (-p->visc_alpha * c * mu + p->visc_beta * mu * mu) / rij;
        for (int d = 0; d < D; d++) F[d] -= mm * Pi * g * dx[d];
        fs += fabs(mm * Pi * g) * r;
      }
      double work = 0.0, ud = 0.0, hd = 0.0;
      for (int d = 0; d < D; d++) {
        acc[d] += F[d] / mass[i];
        work += dv[d] * F[d];
        ud += (ui[d] - uj[d]) * dx[d];
        hd += (w->H[3 * i + d] + w->H[3 * j + d]) * dx[d];
      }
      w->as[i] += fs / mass[i];
      ed += work / (2.0 * mass[i]) - mass[j] * g * hd;
      es += Norm(D, dv) * fs / (2.0 * mass[i]) + mass[j] * fabs(g) * r * (w->Ha[i] + w->Ha[j]);
      rd += mass[j] * g * ud;
      rs += mass[j] * fabs(g) * r * (Norm(D, ui) + Norm(D, uj) + usi + (chain ? w->xs[j] : 0.0));
    }
    ri[l->e] = ed;
    ci[l->e] = es;
    if (l->rho >= 0) {
      ri[l->rho] = rd;
      ci[l->rho] = rs;
    }
  }
  if (D == 2 && p->angmom == SPAM_ANGMOM_GAUSS) GaussReference(m, n, y, mass, w);
  for (int i = 0; i < n; i++) {
    double *ri = ref + (size_t)i * nv, *ci = scl + (size_t)i * nv;
    for (int d = 0; d < D; d++) {
      ri[l->x + d] = w->xd[3 * i + d];
      ri[l->v + d] = w->acc[3 * i + d];
    }
    ci[l->x] = w->xs[i];
    ci[l->v] = w->as[i];
    for (int k = 0; k < nv; k++) ri[k] *= spoil->factor;
  }
}

/* One case of the tensor path: every option of SpamSolidParams that changes the pair sums,
 * the box (0 periodic, 1 open, 2 mixed: periodic x (and z)), masses and ghost images. */
typedef struct {
  SpamMaterial      material;
  SpamDensityMode   density;
  SpamCoordsMode    coords;
  PetscBool         geometric, unequal, ghosts, newtonian, heat;
  SpamViscosityMode viscosity;
  SpamAngmomMode    angmom; /* 2D only; NONE elsewhere */
  int               box;
  PetscBool         per_body; /* 2D: two lattice blobs far apart, scaled per body */
} TensorOpts;

static PetscErrorCode TensorCompare(TestCount *c, const Spoil *spoil, SpamSim *sim, const char *label, const char *stage, const double *mass, double *u, TensorWork *w, double *ref, double *scl, double *ydot)
{
  const SpamModel  *m = &sim->model;
  const SpamLayout *l = &m->layout;
  const int         D = m->dim, nv = l->nvar, n = (int)sim->p.n, ns = l->s >= 0 ? D * (D + 1) / 2 : 0;
  PetscScalar      *y;
  PetscInt          bad = -1;
  Worst             wx = {0, -1}, wv = {0, -1}, we = {0, -1}, wrd = {0, -1}, ws = {0, -1}, wr = {0, -1};

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->p.X, &y));
  Local(&sim->geo.box, n, y, nv, u);
  TensorReference(spoil, m, &sim->geo.box, n, y, u, mass, w, ref, scl);
  PetscCall(SpamRhs(sim, y, ydot, &bad));
  for (int i = 0; i < n; i++) {
    const double *f = ydot + (size_t)i * nv, *r = ref + (size_t)i * nv, *s = scl + (size_t)i * nv;
    double        ex[3], ev[3];
    for (int d = 0; d < D; d++) {
      ex[d] = f[l->x + d] - r[l->x + d];
      ev[d] = f[l->v + d] - r[l->v + d];
    }
    Track(&wx, Norm(D, ex), s[l->x], i);
    Track(&wv, Norm(D, ev), s[l->v], i);
    Track(&we, fabs(f[l->e] - r[l->e]), s[l->e], i);
    if (l->rho >= 0) Track(&wrd, fabs(f[l->rho] - r[l->rho]), s[l->rho], i);
    for (int k = 0; k < ns; k++) Track(&ws, fabs(f[l->s + k] - r[l->s + k]), s[l->s + k], i);
    if (m->solid.density == SPAM_DENSITY_SUMMATION) Track(&wr, fabs(sim->pair.f.rho[i] - w->rho[i]), w->rho[i], i);
  }
  PetscCall(VecRestoreArray(sim->p.X, &y));
  TestCheck(c, bad < 0 && wx.worst <= TOL, "%s %s: dr/dt (%s) max |diff| / scale = %.2e (< 1e-12)", label, stage, SpamCoordsModeNames[m->solid.coords], wx.worst);
  TestCheck(c, bad < 0 && wv.worst <= TOL, "%s %s: dv/dt max |a - a_ref| / S_i = %.2e (particle %d; < 1e-12)", label, stage, wv.worst, wv.at);
  TestCheck(c, bad < 0 && we.worst <= TOL, "%s %s: de/dt max |diff| / sum|terms| = %.2e (particle %d; < 1e-12)", label, stage, we.worst, we.at);
  if (l->rho >= 0) TestCheck(c, bad < 0 && wrd.worst <= TOL, "%s %s: drho/dt (%s) max |diff| / sum|terms| = %.2e (< 1e-12)", label, stage, SpamDensityModeNames[m->solid.density], wrd.worst);
  if (ns) TestCheck(c, bad < 0 && ws.worst <= TOL, "%s %s: stress rate (%d components) max |diff| / scale = %.2e (particle %d; < 1e-12)", label, stage, ns, ws.worst, ws.at);
  if (m->solid.density == SPAM_DENSITY_SUMMATION) TestCheck(c, bad < 0 && wr.worst <= TOL, "%s %s: summed density max |rho - rho_ref| / rho_ref = %.2e (< 1e-12)", label, stage, wr.worst);
  PetscFunctionReturn(0);
}

static PetscErrorCode TensorWorkAlloc(int n, TensorWork *w)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMalloc7(n, &w->rho, n, &w->T, 9 * n, &w->G, 9 * n, &w->Gs, 9 * n, &w->Q, n, &w->qa, 3 * n, &w->H));
  PetscCall(PetscMalloc7(n, &w->Ha, 3 * n, &w->xd, n, &w->xs, n, &w->lt, n, &w->tf, 3 * n, &w->acc, n, &w->as));
  PetscCall(PetscMalloc4(n, &w->body, n, &w->bpos, n, &w->bneg, n, &w->bR));
  PetscFunctionReturn(0);
}

static PetscErrorCode TensorWorkFree(TensorWork *w)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree7(w->rho, w->T, w->G, w->Gs, w->Q, w->qa, w->H));
  PetscCall(PetscFree7(w->Ha, w->xd, w->xs, w->lt, w->tf, w->acc, w->as));
  PetscCall(PetscFree4(w->body, w->bpos, w->bneg, w->bR));
  PetscFunctionReturn(0);
}

/* The model of case o with kernel kname; rho0 the mean density of n unit-mass particles
 * in the geometry's box (the scale of the random state). */
static PetscErrorCode TensorModel(const GasGeometry *gg, const char *kname, const TensorOpts *o, int n, SpamModel *m)
{
  SpamSolidParams sp;
  SpamKernel      k;
  double          vol = 1.0;

  PetscFunctionBeginUser;
  for (int d = 0; d < gg->dim; d++) vol *= gg->len[d];
  SpamSolidDefaults(&sp);
  sp.material      = o->material;
  sp.density       = o->density;
  sp.coords        = o->coords;
  sp.rho_geometric = o->geometric;
  sp.xsph_eps      = 0.7; /* not 1, so that a lost epsilon shows */
  sp.angmom        = o->angmom;
  sp.per_body      = o->per_body;
  sp.viscosity     = o->viscosity;
  sp.visc_alpha    = 0.8;
  sp.visc_beta     = 1.7;
  sp.gamma         = 1.4;
  sp.gas_e0        = 0.6;
  sp.rho0          = n / vol;
  sp.shear_visc    = o->newtonian ? 0.3 : 0.0;
  sp.bulk_visc     = o->newtonian ? 0.2 : 0.0;
  sp.conductivity  = o->heat ? 0.9 : 0.0;
  PetscCall(SpamKernelCreate(kname, gg->dim, gg->h, &k));
  PetscCall(SpamModelSolidSetUp(gg->dim, &k, 1.0, &sp, m));
  PetscFunctionReturn(0);
}

/* Random fields of the state: e in [0.3, 0.6], rho within 20% of rho0, stress components
 * of size 0.05 (lambda + 2 eta), velocities of size 0.1 c. */
static void TensorState(const SpamModel *m, int n, double *y, uint64_t *seed)
{
  const SpamLayout      *l  = &m->layout;
  const SpamSolidParams *p  = &m->solid;
  const int              ns = m->dim * (m->dim + 1) / 2;

  for (int i = 0; i < n; i++) {
    double *yi = y + (size_t)i * l->nvar;
    for (int d = 0; d < m->dim; d++) yi[l->v + d] = 0.2 * SoundSpeed(p) * (TestUniform(seed) - 0.5);
    yi[l->e] = 0.3 * (1.0 + TestUniform(seed));
    if (l->rho >= 0) yi[l->rho] = p->rho0 * (1.0 + 0.4 * (TestUniform(seed) - 0.5));
    for (int k = 0; l->s >= 0 && k < ns; k++) yi[l->s + k] = 0.1 * (p->lambda + 2.0 * p->eta) * (TestUniform(seed) - 0.5);
  }
}

/* Connected parts (pairs nearer than h, minimum image) of the positions x: body[i] and
 * their number, by spreading labels until nothing changes. */
static int LabelBodies(const SpamBox *b, int n, const double *x, double h, int *body, double *u)
{
  int nbody = 0;

  Local(b, n, x, b->dim, u);
  for (int i = 0; i < n; i++) body[i] = -1;
  for (int s = 0; s < n; s++) {
    int grown = 1;
    if (body[s] >= 0) continue;
    body[s] = nbody;
    while (grown) {
      grown = 0;
      for (int i = 0; i < n; i++)
        for (int j = 0; body[i] == nbody && j < n; j++) {
          double dx[3];
          if (body[j] < 0 && Sep(b, u, i, j, dx) < h * h) {
            body[j] = nbody;
            grown   = 1;
          }
        }
    }
    nbody++;
  }
  return nbody;
}

/* Two blobs of a jittered square lattice (spacing 1, 7 columns) at the left and right
 * ends of the box, 10 apart: two bodies that the moves below cannot join. */
static void TwoBlobs(const SpamBox *b, int n, double *x, uint64_t *seed)
{
  for (int i = 0; i < n; i++) {
    const int k = i % ((n + 1) / 2), right = i >= (n + 1) / 2;
    x[2 * i]     = b->lo[0] + (right ? b->len[0] - 7.0 : 0.0) + (k % 7) + 0.5 + 0.3 * (TestUniform(seed) - 0.5);
    x[2 * i + 1] = b->lo[1] + (k / 7) + 0.5 + 0.3 * (TestUniform(seed) - 0.5);
  }
}

static PetscErrorCode TensorCase(TestCount *c, const Spoil *spoil, const GasGeometry *gg, const char *kname, const TensorOpts *o, int n, uint64_t seed)
{
  static const char *boxes[3] = {"periodic", "open", "mixed"};
  const int          dim = gg->dim;
  const double       h = gg->h, skin = 0.1 * h;
  SpamBox            b = {dim, {0, 0, 0}, {0, 0, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
  SpamModel          m;
  SpamSim            sim;
  TensorWork         w;
  double            *x, *v, *mass, *u, *ref, *scl, *ydot;
  PetscScalar       *y;
  char               label[256], stage[64];
  int                nv, crossed;
  const int          nv_max = SPAM_MAX_NVAR;

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) {
    b.lo[d]       = gg->lo[d];
    b.len[d]      = gg->len[d];
    b.periodic[d] = (PetscBool)(o->box == 0 || (o->box == 2 && d != 1));
  }
  PetscCall(TensorModel(gg, kname, o, n, &m));
  (void)snprintf(label, sizeof label, "%s %s D=%d %s%s %s %s rho_ij=%s %s masses visc=%s%s%s angmom=%s N=%d", kname, SpamMaterialNames[o->material], dim, boxes[o->box], o->ghosts ? " (ghost images)" : "",
                 SpamDensityModeNames[o->density], SpamCoordsModeNames[o->coords], o->geometric ? "geometric" : "arithmetic", o->unequal ? "unequal" : "equal", SpamViscosityModeNames[o->viscosity], o->newtonian ? " +newtonian" : "", o->heat ? " +heat" : "",
                 SpamAngmomModeNames[o->angmom], n);
  PetscCall(PetscMalloc3((size_t)n * dim, &x, (size_t)n * dim, &v, n, &mass));
  for (int i = 0; i < n * dim; i++) {
    const int d = i % dim;
    x[i]        = b.lo[d] + b.len[d] * TestUniform(&seed);
    v[i]        = 0.0; /* set with the state below */
  }
  if (o->per_body) TwoBlobs(&b, n, x, &seed);
  Masses(o->unequal, n, mass, &seed);
  PetscCall(TensorWorkAlloc(n, &w));
  PetscCall(PetscMalloc4((size_t)n * dim, &u, (size_t)n * nv_max, &ref, (size_t)n * nv_max, &scl, (size_t)n * nv_max, &ydot));
  w.nbody = 1;
  for (int i = 0; i < n; i++) w.body[i] = 0;
  if (o->per_body) {
    const size_t len = strlen(label);
    w.nbody          = LabelBodies(&b, n, x, h, w.body, u);
    (void)snprintf(label + len, sizeof label - len, " per body");
    TestCheck(c, w.nbody == 2, "%s: the reference finds %d bodies (2)", label, w.nbody);
  }
  PetscCall(SpamSimCreate(PETSC_COMM_SELF, &m, &b, n, skin, &sim));
  sim.pair.periodic_ghosts = o->ghosts;
  PetscCall(SpamSimFill(&sim, x, v, o->unequal ? mass : NULL));
  PetscCall(SpamSimSetUp(&sim));
  PetscCall(sim.model.setup(&sim));
  nv = sim.model.layout.nvar;
  PetscCall(VecGetArray(sim.p.X, &y));
  TensorState(&sim.model, n, y, &seed);
  PetscCall(VecRestoreArray(sim.p.X, &y));

  PetscCall(TensorCompare(c, spoil, &sim, label, "E0 first", mass, u, &w, ref, scl, ydot));
  PetscCall(VecGetArray(sim.p.X, &y));
  crossed = SmallMove(&sim.geo.box, n, y, nv, skin, &seed);
  PetscCall(VecRestoreArray(sim.p.X, &y));
  (void)snprintf(stage, sizeof stage, "E1 moves < skin/2, %d across a face", crossed);
  PetscCall(TensorCompare(c, spoil, &sim, label, stage, mass, u, &w, ref, scl, ydot));
  PetscCall(VecGetArray(sim.p.X, &y));
  LargeMove(&sim.geo.box, n, y, nv, 0.5 * h, &seed);
  PetscCall(VecRestoreArray(sim.p.X, &y));
  PetscCall(TensorCompare(c, spoil, &sim, label, "E2 rebuild", mass, u, &w, ref, scl, ydot));

  PetscCall(PetscFree4(u, ref, scl, ydot));
  PetscCall(TensorWorkFree(&w));
  PetscCall(PetscFree3(x, v, mass));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount      c = {0, 0};
  char           perturb[32] = "none";
  Spoil          spoil       = {1, 1.0};
  PetscLogDouble t0, t1;
  /* Edges chosen so that the current binning's cells (len / floor(len / 1.1 h)) have an
   * exact width: 1D 16 cells of 4, 2D 8 x 6 cells of 3, 3D 4 x 5 x 4 cells of 3. */
  const GasGeometry geo[3] = {
    {1, 3.5, {-20.0, 0, 0}, {64.0, 0, 0}, 600, "1D"},
    {2, 2.5, {-4.0, 6.0, 0}, {24.0, 18.0, 0}, 1200, "2D"},
    {3, 2.5, {1.0, -2.0, 0.5}, {12.0, 15.0, 12.0}, 1500, "3D"},
  };
#define NAME_ROW(ctx, KIND, name, Prefix) #name,
  static const char *kernels[SPAM_KERNEL_KINDS] = {SPAM_KERNEL_LIST(NAME_ROW, ~)}; /* every kernel of the list */
#undef NAME_ROW
  const int          ngas[3]    = {150, 300, 400}; /* per kernel: smaller than the Lucy sweep */
  const int          ntensor[3] = {100, 250, 300};

  PetscCall(TestInitialize(&argc, &argv));
  PetscCall(PetscTime(&t0));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-reference_perturb", perturb, sizeof perturb, NULL));
  if (!strcmp(perturb, "self")) spoil.self = 0;
  else if (!strcmp(perturb, "factor")) spoil.factor = 1.000001;
  else PetscCheck(!strcmp(perturb, "none"), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-reference_perturb %s: none, self or factor", perturb);
  if (spoil.self == 0 || spoil.factor != 1.0) printf("reference perturbed (%s): the checks must fail\n", perturb);

  for (int dim = 1; dim <= 3; dim++) {
    const char *mixed = dim == 2 ? "periodic x, open y" : "periodic x z, open y";
    const double gD   = 1.0 + 2.0 / dim;
    /* Lucy's kernel, equal masses, full size: the fast loops, both EOS passes */
    for (int g = 0; g < 2; g++) {
      const uint64_t s    = 1000 * (uint64_t)dim + 10 * (uint64_t)g;
      const double   gam  = g ? 1.4 : gD;
      const GasOpts  per  = {"lucy", "periodic", {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}, PETSC_FALSE, PETSC_FALSE, gam, 0};
      const GasOpts  open = {"lucy", "open", {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}, PETSC_FALSE, PETSC_FALSE, gam, 0};
      const GasOpts  mix  = {"lucy", mixed, {PETSC_TRUE, PETSC_FALSE, PETSC_TRUE}, PETSC_FALSE, PETSC_FALSE, gam, 0};
      PetscCall(GasCase(&c, &spoil, &geo[dim - 1], &per, s + 1));
      PetscCall(GasCase(&c, &spoil, &geo[dim - 1], &open, s + 2));
      if (dim >= 2) PetscCall(GasCase(&c, &spoil, &geo[dim - 1], &mix, s + 3));
    }
    /* every kernel: equal and unequal masses, minimum image and ghost images */
    for (int k = 0; k < SPAM_KERNEL_KINDS; k++) {
      const int      n = ngas[dim - 1];
      const uint64_t s = 20000 + 1000 * (uint64_t)dim + 100 * (uint64_t)k;
      const GasOpts  cases[5] = {
        {kernels[k], "periodic", {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}, PETSC_FALSE, PETSC_FALSE, gD, n},
        {kernels[k], "open", {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}, PETSC_TRUE, PETSC_FALSE, 1.4, n},
        {kernels[k], "periodic", {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE}, PETSC_TRUE, PETSC_TRUE, 1.4, n},
        {kernels[k], dim >= 2 ? mixed : "periodic", {PETSC_TRUE, dim == 1, PETSC_TRUE}, PETSC_FALSE, PETSC_TRUE, gD, n},
        {kernels[k], mixed, {PETSC_TRUE, PETSC_FALSE, PETSC_TRUE}, PETSC_TRUE, PETSC_FALSE, 1.4, n},
      };
      for (int q = 0; q < (dim >= 2 ? 5 : 4); q++) PetscCall(GasCase(&c, &spoil, &geo[dim - 1], &cases[q], s + (uint64_t)q));
    }
  }
  /* The tensor path: a covering set per dimension and kernel (every option value in some
   * case); torque scaling and Gauss exist in 2D only. */
  for (int dim = 1; dim <= 3; dim++)
    for (int k = 0; k < SPAM_KERNEL_KINDS; k++) {
      const int        two = dim == 2;
      const TensorOpts cases[7] = {
        {SPAM_MATERIAL_ELASTIC, SPAM_DENSITY_SUMMATION, SPAM_COORDS_R0, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, SPAM_VISCOSITY_NONE, two ? SPAM_ANGMOM_TI : SPAM_ANGMOM_NONE, 0, PETSC_FALSE},
        {SPAM_MATERIAL_ELASTIC, SPAM_DENSITY_CONTINUITY, SPAM_COORDS_R1, PETSC_TRUE, PETSC_TRUE, PETSC_TRUE, PETSC_TRUE, PETSC_TRUE, SPAM_VISCOSITY_MONAGHAN, two ? SPAM_ANGMOM_TIJ : SPAM_ANGMOM_NONE, 0, PETSC_FALSE},
        {SPAM_MATERIAL_GAS, SPAM_DENSITY_CHAIN_RULE, SPAM_COORDS_R2, PETSC_FALSE, PETSC_TRUE, PETSC_FALSE, PETSC_TRUE, PETSC_TRUE, SPAM_VISCOSITY_VON_NEUMANN, two ? SPAM_ANGMOM_GAUSS : SPAM_ANGMOM_NONE, 1, PETSC_FALSE},
        {SPAM_MATERIAL_GAS, SPAM_DENSITY_SUMMATION, SPAM_COORDS_R1, PETSC_TRUE, PETSC_FALSE, PETSC_TRUE, PETSC_FALSE, PETSC_TRUE, SPAM_VISCOSITY_MONAGHAN, SPAM_ANGMOM_NONE, dim >= 2 ? 2 : 0, PETSC_FALSE},
        {SPAM_MATERIAL_ELASTIC, SPAM_DENSITY_CHAIN_RULE, SPAM_COORDS_R2, PETSC_TRUE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, SPAM_VISCOSITY_VON_NEUMANN, two ? SPAM_ANGMOM_TI : SPAM_ANGMOM_NONE, dim >= 2 ? 2 : 1, PETSC_FALSE},
        /* 2D: torque scaling per body, two bodies */
        {SPAM_MATERIAL_ELASTIC, SPAM_DENSITY_CONTINUITY, SPAM_COORDS_R0, PETSC_FALSE, PETSC_TRUE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, SPAM_VISCOSITY_NONE, SPAM_ANGMOM_TIJ, 1, PETSC_TRUE},
        {SPAM_MATERIAL_GAS, SPAM_DENSITY_SUMMATION, SPAM_COORDS_R2, PETSC_TRUE, PETSC_FALSE, PETSC_FALSE, PETSC_TRUE, PETSC_FALSE, SPAM_VISCOSITY_MONAGHAN, SPAM_ANGMOM_TI, 1, PETSC_TRUE},
      };
      for (int q = 0; q < (two ? 7 : 5); q++) PetscCall(TensorCase(&c, &spoil, &geo[dim - 1], kernels[k], &cases[q], ntensor[dim - 1], 50000 + 1000 * (uint64_t)dim + 100 * (uint64_t)k + (uint64_t)q));
    }
  PetscCall(PetscTime(&t1));
  printf("runtime %.2f s\n", (double)(t1 - t0));
  PetscCall(TestFinalize());
  return TestFinish(&c);
}
