/* The optimised pair loops (neighbour list, half pairs, whatever sorting or vector code
 * they use) give the same right-hand side as a plain O(N^2) loop over every ordered pair,
 * written here straight from shared/design/EQUATIONS.md, to 1e-12 relative (issue 6,
 * point 5). Only the public entry points are called (SpamRhs, SpamDensitySummation,
 * SpamAccel and the model set-up of the scenes); nothing here reads the neighbour list.
 *
 * Isentropic gas, D = 1, 2, 3, in periodic, open and (D >= 2) mixed boxes, gamma = 1 + 2/D
 * (in 2D the density-free gamma = 2 path) and gamma = 1.4 (the density pass):
 *   rho_i = m sum_j w_ij (self term included),  q = P/rho^2 from the model's EOS,
 *   dv_i/dt = -m sum_j (q_i + q_j) grad_i w_ij,  grad_i w_ij = (w'/r) r_ij,
 * with the minimum image in periodic directions. Each configuration is random (seeded),
 * with some particles exactly on box faces and on the faces of the cells the current
 * binning uses; it is evaluated four times:
 *   E0  the first evaluation (the list is built);
 *   E1  every particle moved by less than skin/2 (the list must be kept), particles near
 *       a periodic face pushed across it;
 *   E2  a tenth of the particles moved by up to h per direction and another tenth shifted
 *       by a whole periodic edge (a rebuild);
 *   E3  moves below skin/2 again (the rebuilt list kept), and SpamAccel on a compact
 *       position array of another stride.
 * Elastic solid (continuity density with R2, and summation density with R1 and the
 * geometric rho_ij) on a perturbed periodic triangular lattice with random velocities,
 * stresses and densities: every component of ydot (dr/dt, dv/dt, de/dt, drho/dt, the
 * Hooke stress rate with its rotation terms) against its plain-loop value. Torque
 * scaling, Gauss's principle, the artificial and Newtonian viscosities, heat conduction,
 * the gas material and the chain-rule density are not reproduced here (test_solid_rhs
 * checks their conservation laws).
 *
 * The scale of each comparison: the optimised sum and the reference add the same pair
 * terms F_ij in different orders (half list, sorted or vectorised, against j = 0..N-1),
 * so their difference is the round-off of adding those terms, a few ulp of
 * S_i = sum_j |F_ij| / m, the sum of the magnitudes. The total |sum_j F_ij| may cancel to
 * far below S_i (a particle in a uniform region feels almost no force), so a tolerance
 * relative to the total would fail on correct code; one relative to S_i still fails for
 * any missing, duplicated, misplaced or mis-weighted pair, whose error is a whole term.
 * The density has only positive terms, so its total is its scale.
 *
 * -reference_perturb self|factor spoils the reference (no self term in the summed
 * density; every reference rate and summed density times 1.000001) to show that the
 * test then fails. */
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
static void GasReference(const Spoil *spoil, const SpamModel *m, const SpamBox *b, int n, const double *u, double *rho, double *q, double *a, double *S)
{
  const int dim = m->dim;
  for (int i = 0; i < n; i++) {
    double r = 0.0;
    for (int j = 0; j < n; j++) {
      double dx[3];
      if (j == i && !spoil->self) continue;
      r += m->mass * SpamKernelW(&m->kernel, Sep(b, u, i, j, dx)); /* j = i: m w(0) */
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
      const double c = -m->mass * (q[i] + q[j]) * g;
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

/* Compares SpamRhs (and SpamDensitySummation, and at E3 SpamAccel) with the reference. */
static PetscErrorCode GasCompare(TestCount *c, const Spoil *spoil, SpamSim *sim, const char *label, int stage, int crossed, double *u, double *rho, double *q, double *a, double *S, double *ydot, double *xc)
{
  const SpamModel *m = &sim->model;
  const int        dim = m->dim, nv = m->layout.nvar, n = (int)sim->n;
  PetscScalar     *y;
  PetscInt         bad = -1, bad2 = -1, bad3 = -1;
  Worst            wa = {0, -1}, wr = {0, -1}, wacc = {0, -1};
  double           xerr = 0.0;
  static const char *what[4] = {"E0 first", "E1 moves < skin/2", "E2 rebuild", "E3 rebuilt list kept"};

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->X, &y));
  Local(&sim->box, n, y, nv, u);
  GasReference(spoil, m, &sim->box, n, u, rho, q, a, S);
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
  for (int i = 0; i < n; i++) Track(&wr, fabs(sim->f.rho[i] - rho[i]), rho[i], i);
  if (stage == 3) { /* SpamAccel on a compact copy of the positions (stride dim) */
    for (int i = 0; i < n; i++)
      for (int d = 0; d < dim; d++) xc[i * dim + d] = y[(size_t)i * nv + m->layout.x + d];
    PetscCall(SpamAccel(sim, xc, dim, &bad3));
    for (int i = 0; i < n; i++) {
      double d2 = 0.0;
      for (int d = 0; d < dim; d++) {
        const double e = sim->f.acc[(size_t)i * dim + d] - a[i * dim + d];
        d2 += e * e;
      }
      Track(&wacc, sqrt(d2), S[i], i);
    }
  }
  PetscCall(VecRestoreArray(sim->X, &y));
  char extra[64] = "";
  if (crossed) (void)snprintf(extra, sizeof extra, ", %d across a periodic face", crossed);
  TestCheck(c, bad < 0 && wa.worst <= TOL && xerr == 0.0, "%s %s%s: SpamRhs max |a - a_ref| / S_i = %.2e (particle %d; < 1e-12), dr/dt = v exactly (%.0e)", label, what[stage], extra, wa.worst, wa.at, xerr);
  TestCheck(c, bad2 < 0 && wr.worst <= TOL, "%s %s: SpamDensitySummation max |rho - rho_ref| / rho_ref = %.2e (< 1e-12)", label, what[stage], wr.worst);
  if (stage == 3) TestCheck(c, bad3 < 0 && wacc.worst <= TOL, "%s %s: SpamAccel (stride %d) max |a - a_ref| / S_i = %.2e (< 1e-12)", label, what[stage], dim, wacc.worst);
  PetscFunctionReturn(0);
}

static PetscErrorCode GasCase(TestCount *c, const Spoil *spoil, const GasGeometry *gg, const PetscBool periodic[3], const char *bname, double gamma, uint64_t seed)
{
  const int    dim = gg->dim, n = gg->n;
  const double h = gg->h, skin = 0.1 * h; /* TestMakeSim's skin */
  SpamBox      b = {dim, {0, 0, 0}, {0, 0, 0}, {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}};
  SpamSim      sim;
  double      *x, *v, *u, *rho, *q, *a, *S, *ydot, *xc;
  PetscScalar *y;
  char         label[96];
  int          nv, crossed;

  PetscFunctionBeginUser;
  for (int d = 0; d < dim; d++) {
    b.lo[d]       = gg->lo[d];
    b.len[d]      = gg->len[d];
    b.periodic[d] = periodic[d];
  }
  (void)snprintf(label, sizeof label, "D=%d %s gamma=%g N=%d", dim, bname, gamma, n);
  PetscCall(PetscMalloc2((size_t)n * dim, &x, (size_t)n * dim, &v));
  for (int i = 0; i < n; i++) {
    /* one particle in eight has coordinates on exact faces (in 1D: all of them) */
    const PetscBool special = (PetscBool)(i % 8 == 0);
    for (int d = 0; d < dim; d++) {
      const PetscBool face = (PetscBool)(special && (dim == 1 || TestUniform(&seed) < 0.6));
      x[i * dim + d]       = face ? FaceValue(&b, d, h + skin, &seed) : b.lo[d] + b.len[d] * TestUniform(&seed);
      v[i * dim + d]       = TestUniform(&seed) - 0.5;
    }
  }
  PetscCall(TestMakeSim(&b, h, gamma, n, x, v, &sim));
  nv = sim.model.layout.nvar;
  PetscCall(PetscMalloc5((size_t)n * dim, &u, n, &rho, n, &q, (size_t)n * dim, &a, n, &S));
  PetscCall(PetscMalloc2((size_t)n * nv, &ydot, (size_t)n * dim, &xc));

  PetscCall(GasCompare(c, spoil, &sim, label, 0, 0, u, rho, q, a, S, ydot, xc));
  PetscCall(VecGetArray(sim.X, &y));
  crossed = SmallMove(&b, n, y, nv, skin, &seed);
  PetscCall(VecRestoreArray(sim.X, &y));
  PetscCall(GasCompare(c, spoil, &sim, label, 1, crossed, u, rho, q, a, S, ydot, xc));
  PetscCall(VecGetArray(sim.X, &y));
  LargeMove(&b, n, y, nv, h, &seed);
  PetscCall(VecRestoreArray(sim.X, &y));
  PetscCall(GasCompare(c, spoil, &sim, label, 2, 0, u, rho, q, a, S, ydot, xc));
  PetscCall(VecGetArray(sim.X, &y));
  crossed = SmallMove(&b, n, y, nv, skin, &seed);
  PetscCall(VecRestoreArray(sim.X, &y));
  PetscCall(GasCompare(c, spoil, &sim, label, 3, crossed, u, rho, q, a, S, ydot, xc));

  PetscCall(PetscFree2(ydot, xc));
  PetscCall(PetscFree5(u, rho, q, a, S));
  PetscCall(PetscFree2(x, v));
  PetscCall(SpamSimDestroy(&sim));
  PetscFunctionReturn(0);
}

/* --------------------------------------------------------------- elastic solid --- */

/* Reference of the elastic solid's ydot (layout l) and the scale of every component. */
static void SolidReference(const Spoil *spoil, const SpamModel *m, const SpamBox *b, int n, const double *y, const double *u, double *ref, double *scl, double *rho)
{
  const SpamLayout      *l  = &m->layout;
  const SpamSolidParams *sp = &m->solid;
  const int              nv = l->nvar;
  const double           mass = m->mass;

  for (int i = 0; i < n; i++) {
    if (sp->density == SPAM_DENSITY_SUMMATION) {
      double r = 0.0;
      for (int j = 0; j < n; j++) {
        double dx[3];
        if (j == i && !spoil->self) continue;
        r += mass * SpamKernelW(&m->kernel, Sep(b, u, i, j, dx));
      }
      rho[i] = spoil->factor * r;
    } else rho[i] = y[(size_t)i * nv + l->rho];
  }
  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv, *vi = yi + l->v, *si = yi + l->s;
    double       *ri = ref + (size_t)i * nv, *ci = scl + (size_t)i * nv;
    double        gv[4] = {0, 0, 0, 0}, gs[4] = {0, 0, 0, 0}; /* grad v [2a+b] = dv^b/dx^a, its scale */
    double        xs[2] = {0, 0}, xsc = 0.0, wsum = 0.0;      /* R1/R2 pair sums                      */
    double        acc[2] = {0, 0}, asc = 0.0, ed = 0.0, esc = 0.0, rd = 0.0, rsc = 0.0;
    const double  r2i = rho[i] * rho[i], qi[3] = {si[0] / r2i, si[1] / r2i, si[2] / r2i};
    for (int j = 0; j < n; j++) {
      const double *yj = y + (size_t)j * nv, *vj = yj + l->v, *sj = yj + l->s;
      double        dx[3];
      const double  r2 = Sep(b, u, i, j, dx);
      const double  w  = SpamKernelW(&m->kernel, r2);
      if (sp->coords == SPAM_COORDS_R1) { /* <v>_i = sum_j v_j w_ij / sum_j w_ij, j = i included */
        wsum += w;
        for (int d = 0; d < 2; d++) xs[d] += w * vj[d];
        xsc += w * hypot(vj[0], vj[1]);
      }
      if (j == i) continue;
      const double g      = SpamKernelDWOverR(&m->kernel, r2);
      const double rhoij  = sp->rho_geometric ? sqrt(rho[i] * rho[j]) : 0.5 * (rho[i] + rho[j]);
      const double dv[2]  = {vj[0] - vi[0], vj[1] - vi[1]};
      const double r2j    = rho[j] * rho[j];
      const double Sxx = qi[0] + sj[0] / r2j, Sxy = qi[1] + sj[1] / r2j, Syy = qi[2] + sj[2] / r2j;
      /* F_ij = m^2 [(sigma/rho^2)_i + (sigma/rho^2)_j].grad_i w_ij */
      const double F[2] = {mass * mass * g * (Sxx * dx[0] + Sxy * dx[1]), mass * mass * g * (Sxy * dx[0] + Syy * dx[1])};
      for (int a = 0; a < 2; a++)
        for (int bb = 0; bb < 2; bb++) {
          const double t = mass * dv[bb] * g * dx[a] / rhoij;
          gv[2 * a + bb] += t;
          gs[2 * a + bb] += fabs(t);
        }
      if (sp->coords == SPAM_COORDS_R2) {
        const double cw = sp->xsph_eps * mass * w / rhoij;
        for (int d = 0; d < 2; d++) xs[d] += cw * dv[d];
        xsc += fabs(cw) * hypot(dv[0], dv[1]);
      }
      for (int d = 0; d < 2; d++) acc[d] += F[d] / mass;
      asc += hypot(F[0], F[1]) / mass;
      const double work = (dv[0] * F[0] + dv[1] * F[1]) / (2.0 * mass);
      ed += work;
      esc += fabs(work);
      if (l->rho >= 0) { /* continuity with u = v: m sum_j (v_i - v_j).grad_i w_ij */
        const double t = -mass * g * (dv[0] * dx[0] + dv[1] * dx[1]);
        rd += t;
        rsc += fabs(t);
      }
    }
    /* dr/dt: R0 v; R1 <v>; R2 v + eps m sum_j (v_j - v_i) w_ij / rho_ij */
    for (int d = 0; d < 2; d++) {
      if (sp->coords == SPAM_COORDS_R1) {
        ri[l->x + d] = spoil->factor * xs[d] / wsum;
        ci[l->x + d] = xsc / wsum;
      } else {
        ri[l->x + d] = vi[d] + spoil->factor * xs[d];
        ci[l->x + d] = hypot(vi[0], vi[1]) + xsc;
      }
      ri[l->v + d] = spoil->factor * acc[d];
      ci[l->v + d] = asc;
    }
    ri[l->e] = spoil->factor * ed;
    ci[l->e] = esc;
    if (l->rho >= 0) {
      ri[l->rho] = spoil->factor * rd;
      ci[l->rho] = rsc;
    }
    /* Hooke's law in rate form with the rotation terms (EQUATIONS.md, Elastic solid) */
    for (int k = 0; k < 4; k++) gv[k] *= spoil->factor;
    const double div = gv[0] + gv[3], om = 0.5 * (gv[1] - gv[2]);             /* w = (dvy/dx - dvx/dy)/2 */
    const double sdiv = gs[0] + gs[3], som = 0.5 * (gs[1] + gs[2]), lam = sp->lambda, eta = sp->eta;
    ri[l->s + 0] = lam * div + 2.0 * eta * gv[0] - 2.0 * om * si[1];         /* dsxx/dt */
    ri[l->s + 1] = eta * (gv[2] + gv[1]) + om * (si[0] - si[2]);             /* dsxy/dt */
    ri[l->s + 2] = lam * div + 2.0 * eta * gv[3] + 2.0 * om * si[1];         /* dsyy/dt */
    ci[l->s + 0] = lam * sdiv + 2.0 * eta * gs[0] + 2.0 * som * fabs(si[1]);
    ci[l->s + 1] = eta * (gs[2] + gs[1]) + som * (fabs(si[0]) + fabs(si[2]));
    ci[l->s + 2] = lam * sdiv + 2.0 * eta * gs[3] + 2.0 * som * fabs(si[1]);
  }
}

static PetscErrorCode SolidCompare(TestCount *c, const Spoil *spoil, SpamSim *sim, const char *label, const char *stage, double *u, double *ref, double *scl, double *rho, double *ydot)
{
  const SpamModel *m = &sim->model;
  const SpamLayout *l = &m->layout;
  const int        nv = l->nvar, n = (int)sim->n;
  PetscScalar     *y;
  PetscInt         bad = -1;
  Worst            wx = {0, -1}, wv = {0, -1}, we = {0, -1}, wrd = {0, -1}, ws = {0, -1}, wr = {0, -1};

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(sim->X, &y));
  Local(&sim->box, n, y, nv, u);
  SolidReference(spoil, m, &sim->box, n, y, u, ref, scl, rho);
  PetscCall(SpamRhs(sim, y, ydot, &bad));
  for (int i = 0; i < n; i++) {
    const double *f = ydot + (size_t)i * nv, *r = ref + (size_t)i * nv, *s = scl + (size_t)i * nv;
    Track(&wx, hypot(f[l->x] - r[l->x], f[l->x + 1] - r[l->x + 1]), s[l->x], i);
    Track(&wv, hypot(f[l->v] - r[l->v], f[l->v + 1] - r[l->v + 1]), s[l->v], i);
    Track(&we, fabs(f[l->e] - r[l->e]), s[l->e], i);
    if (l->rho >= 0) Track(&wrd, fabs(f[l->rho] - r[l->rho]), s[l->rho], i);
    for (int k = 0; k < 3; k++) Track(&ws, fabs(f[l->s + k] - r[l->s + k]), s[l->s + k], i);
    if (m->solid.density == SPAM_DENSITY_SUMMATION) Track(&wr, fabs(sim->f.rho[i] - rho[i]), rho[i], i);
  }
  PetscCall(VecRestoreArray(sim->X, &y));
  TestCheck(c, bad < 0 && wx.worst <= TOL, "%s %s: dr/dt (%s) max |diff| / scale = %.2e (< 1e-12)", label, stage, SpamCoordsModeNames[m->solid.coords], wx.worst);
  TestCheck(c, bad < 0 && wv.worst <= TOL, "%s %s: dv/dt max |a - a_ref| / S_i = %.2e (particle %d; < 1e-12)", label, stage, wv.worst, wv.at);
  TestCheck(c, bad < 0 && we.worst <= TOL, "%s %s: de/dt max |diff| / sum|terms| = %.2e (< 1e-12)", label, stage, we.worst);
  if (l->rho >= 0) TestCheck(c, bad < 0 && wrd.worst <= TOL, "%s %s: drho/dt (continuity) max |diff| / sum|terms| = %.2e (< 1e-12)", label, stage, wrd.worst);
  TestCheck(c, bad < 0 && ws.worst <= TOL, "%s %s: stress rate max |diff| / scale = %.2e (< 1e-12)", label, stage, ws.worst);
  if (m->solid.density == SPAM_DENSITY_SUMMATION) TestCheck(c, bad < 0 && wr.worst <= TOL, "%s %s: summed density max |rho - rho_ref| / rho_ref = %.2e (< 1e-12)", label, stage, wr.worst);
  PetscFunctionReturn(0);
}

static PetscErrorCode SolidCase(TestCount *c, const Spoil *spoil, SpamDensityMode dens, SpamCoordsMode coords, PetscBool geometric, uint64_t seed)
{
  const PetscInt nx = 24, ny = 24, n = nx * ny;
  const double   h = 3.0, skin = 0.3;
  SpamSolidParams sp;
  SpamParticles   p;
  SpamModel       m;
  SpamSim         sim;
  double         *u, *ref, *scl, *rho, *ydot;
  PetscScalar    *y;
  char            label[96];

  PetscFunctionBeginUser;
  SpamSolidDefaults(&sp);
  sp.density       = dens;
  sp.coords        = coords;
  sp.rho_geometric = geometric;
  sp.xsph_eps      = 0.7; /* not 1, so that a lost epsilon shows */
  (void)snprintf(label, sizeof label, "solid %s %s rho_ij=%s N=%d", SpamDensityModeNames[dens], SpamCoordsModeNames[coords], geometric ? "geometric" : "arithmetic", (int)n);
  PetscCall(SpamParticlesAllocate(2, n, &p));
  PetscCall(SpamParticlesAllocateFields(&p));
  SpamLatticeTriangular(nx, ny, 1.0, p.x);
  p.box = (SpamBox){2, {-3.0, 2.0, 0}, {(double)nx, 0.5 * sqrt(3.0) * (double)ny, 0}, {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE}};
  for (PetscInt i = 0; i < n; i++) {
    for (int d = 0; d < 2; d++) {
      /* the lattice shifted so that some particles lie outside [lo, lo + len) */
      p.x[2 * i + d] += p.box.lo[d] + (d ? -0.3 : 0.1) + 0.4 * (TestUniform(&seed) - 0.5);
      p.v[2 * i + d] = 0.1 * (TestUniform(&seed) - 0.5);
    }
    for (int k = 0; k < 3; k++) p.sigma[3 * i + k] = 0.04 * (TestUniform(&seed) - 0.5);
    p.rho[i] = sp.rho0 * (1.0 + 0.04 * (TestUniform(&seed) - 0.5));
    p.e[i]   = 0.01 * (1.0 + TestUniform(&seed));
  }
  p.mass = 1.0;
  PetscCall(SpamTestModelSolid(2, h, &sp, &m));
  PetscCall(SpamSimCreate(PETSC_COMM_SELF, &m, &p.box, n, skin, &sim));
  PetscCall(SpamSimFill(&sim, p.x, p.v, NULL));
  PetscCall(SpamSimFillFields(&sim, &p));
  PetscCall(SpamParticlesFree(&p));
  PetscCall(SpamSimSetUp(&sim));
  PetscCall(sim.model.setup(&sim));
  const int nv = sim.model.layout.nvar;
  PetscCall(PetscMalloc5((size_t)n * 2, &u, (size_t)n * nv, &ref, (size_t)n * nv, &scl, n, &rho, (size_t)n * nv, &ydot));

  PetscCall(SolidCompare(c, spoil, &sim, label, "E0 first", u, ref, scl, rho, ydot));
  PetscCall(VecGetArray(sim.X, &y));
  const int crossed = SmallMove(&sim.box, (int)n, y, nv, skin, &seed);
  PetscCall(VecRestoreArray(sim.X, &y));
  char stage[64];
  (void)snprintf(stage, sizeof stage, "E1 moves < skin/2, %d across a face", crossed);
  PetscCall(SolidCompare(c, spoil, &sim, label, stage, u, ref, scl, rho, ydot));
  PetscCall(VecGetArray(sim.X, &y));
  LargeMove(&sim.box, (int)n, y, nv, 0.3 * h, &seed); /* keeps the lattice from overlapping much */
  PetscCall(VecRestoreArray(sim.X, &y));
  PetscCall(SolidCompare(c, spoil, &sim, label, "E2 rebuild", u, ref, scl, rho, ydot));

  PetscCall(PetscFree5(u, ref, scl, rho, ydot));
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

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscTime(&t0));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-reference_perturb", perturb, sizeof perturb, NULL));
  if (!strcmp(perturb, "self")) spoil.self = 0;
  else if (!strcmp(perturb, "factor")) spoil.factor = 1.000001;
  else PetscCheck(!strcmp(perturb, "none"), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-reference_perturb %s: none, self or factor", perturb);
  if (spoil.self == 0 || spoil.factor != 1.0) printf("reference perturbed (%s): the checks must fail\n", perturb);

  for (int dim = 1; dim <= 3; dim++) {
    const PetscBool per[3]   = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE};
    const PetscBool open[3]  = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
    const PetscBool mixed[3] = {PETSC_TRUE, PETSC_FALSE, PETSC_TRUE};
    const double    gam[2]   = {1.0 + 2.0 / dim, 1.4};
    for (int g = 0; g < 2; g++) {
      const uint64_t s = 1000 * (uint64_t)dim + 10 * (uint64_t)g;
      PetscCall(GasCase(&c, &spoil, &geo[dim - 1], per, "periodic", gam[g], s + 1));
      PetscCall(GasCase(&c, &spoil, &geo[dim - 1], open, "open", gam[g], s + 2));
      if (dim >= 2) PetscCall(GasCase(&c, &spoil, &geo[dim - 1], mixed, dim == 2 ? "periodic x, open y" : "periodic x z, open y", gam[g], s + 3));
    }
  }
  PetscCall(SolidCase(&c, &spoil, SPAM_DENSITY_CONTINUITY, SPAM_COORDS_R2, PETSC_FALSE, 5001));
  PetscCall(SolidCase(&c, &spoil, SPAM_DENSITY_SUMMATION, SPAM_COORDS_R1, PETSC_TRUE, 5002));
  PetscCall(PetscTime(&t1));
  printf("runtime %.2f s\n", (double)(t1 - t0));
  PetscCall(PetscFinalize());
  return TestFinish(&c);
}
