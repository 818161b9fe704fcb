/* The diffusion part's Jacobian (spam/diffusion_jacobian.h), assembled from the neighbour
 * list into a preallocated AIJ matrix.
 *
 * The pair (i, j) of pair_diffusion.h adds c_i (f_i - f_j) to the rate of particle i and
 * -c_j (f_i - f_j) to j's, per velocity component f = v_d with c_i = 2 eta k m_j, and for the
 * energy with f = T = (gamma - 1) e and c_i = 2 kappa k m_j (gamma - 1), where k is the
 * pair's factor (negative: the pair relaxes). A ghost slot j stands for a source particle s:
 * f_j = a f_s + b, a = +1 for a periodic image, and what a wall's rule gives (-1 for a
 * no-slip wall's velocity, per component at a free-slip one, the temperature's at an
 * isothermal or adiabatic one); a periodic image's own rate is folded onto s, a mirror
 * image's is the wall's. The coefficients a are read off the walls' gathers themselves
 * (the gather of ones minus that of zeros), so the rules live in one place (ghosts.c).
 * The work's and the books' entries read the velocities of the slots themselves (the wall's
 * own velocity b included).
 *
 * The pair conduction's linear correction (-conduction_linear, pair_diffusion.h) adds to
 * each particle's rate -b_i . G_i, with b_i = sum_j m_j 2 kappa k_ij (x_i - x_j) over its
 * pairs (the sides it takes) and G_i = -M_i^-1 S_i, S_i = sum_j m_j g_ij (T_j - T_i)
 * (x_i - x_j) / rho_ij its SPAM grad T: so u_i . S_i with u_i = M_i^-1 b_i, linear in the
 * T of i's own neighbours, and the matrix keeps the pairs' pattern. Per pair the row of i
 * takes alpha_i (T_j - T_i), alpha_i = m_j g_ij (u_i . (x_i - x_j)) / rho_ij, and the row
 * of j (where j takes its side) alpha_j (T_j - T_i) with u_j; the same entries go into the
 * rows of the flow scheme's book, which carries the correction's heat. Exact, as the
 * correction is linear in T at the stage's fixed positions and densities. */
#include <spam/physics.h>
#include <spam/diffusion_jacobian.h>
#include "../pair/pair_walk.h"
#include "../pair/pair_gradients.h"
#include "../pair/pair_diffusion.h"

typedef struct {
  SpamFields       *f;
  Mat               J;
  const SpamGhosts *gh;
  const double     *coef; /* [ghosts (dim + 1)] */
  int               n, nvar, off[4], ncomp, wb;
  double            c[4];    /* per component: 2 eta, or 2 kappa (gamma - 1) */
  int               heatlin; /* the linear correction's entries (energy and book rows) */
  int               fb;      /* the flow scheme's book's offset, or -1                */
  double            kappa2, tcoef; /* 2 kappa; gamma - 1 (T = (gamma - 1) e)            */
  PetscBool         rho_geometric;
  PetscErrorCode    ierr;
} JacPass;

/* The coefficient a of component q of slot j's value on its source's (1: a particle). */
static inline double Coef(const JacPass *c, int j, int s, int q)
{
  return j >= c->n && s >= 0 ? c->coef[(size_t)(j - c->n) * c->ncomp + q] : 1.0;
}

/* The slot of j and how its rows read: s its local source (-1: another rank's), fold
 * whether its own rate is the source's (a periodic image) rather than the wall's. */
static inline __attribute__((always_inline)) int SourceOf(const JacPass *c, int j, int *fold)
{
  *fold = 1;
  if (j < c->n) return j;
  const int gk = j - c->n, s = gk < c->gh->nlocal ? c->gh->src[gk] : -1;
  *fold = s >= 0 && c->gh->kind[gk] == SPAM_GHOST_PERIODIC;
  return s;
}

/* The correction's alpha_i, alpha_j of the pair (f->heat holds -u, LinearMoments). */
static inline __attribute__((always_inline)) void LinearAlphas(const int dim, const JacPass *c, int i, int j, const double dx[3], double g, double *ai, double *aj)
{
  const SpamFields *f  = c->f;
  const double      gr = c->tcoef * g / SpamPairMeanDensity(c->rho_geometric, f->rho[i], f->rho[j]);
  double            ui = 0.0, uj = 0.0;
  for (int d = 0; d < dim; d++) {
    ui -= f->heat[(size_t)i * dim + d] * dx[d];
    uj -= f->heat[(size_t)j * dim + d] * dx[d];
  }
  *ai = f->m[j] * gr * ui;
  *aj = f->m[i] * gr * uj;
}

/* Adds the entries of rows ri (and rs when fold) at columns (ri, rs): row i c_i (f_i - f_j),
 * row s -c_j (f_i - f_j), with f_j = a f_s (+ a constant); s < 0: row i's diagonal only. */
static inline __attribute__((always_inline)) PetscErrorCode AddPair(Mat J, PetscInt ri, PetscInt rs, PetscInt ci_col, PetscInt cs_col, int s, int fold, double a, double ci, double cj)
{
  if (s < 0) return MatSetValue(J, ri, ci_col, ci, ADD_VALUES);
  const PetscInt    rows[2] = {ri, rs}, cols[2] = {ci_col, cs_col};
  const PetscScalar v[4]    = {ci, -ci * a, -cj, cj * a};
  return MatSetValues(J, fold ? 2 : 1, rows, 2, cols, v, ADD_VALUES);
}

/* The linear part: each component's rate c_i (f_i - f_j) on i and -c_j (f_i - f_j) on a
 * folded j, f_j = a f_s + b; with the conduction's linear correction its alphas in the
 * energy's rows and in the book's. */
static inline void LinearPair(const int dim, JacPass *c, int i, int j, int s, int fold, double k, const double dx[3], double g)
{
  for (int q = 0; q < c->ncomp && !c->ierr; q++) {
    const double   a  = Coef(c, j, s, q);
    double         ci = c->c[q] * k * c->f->m[j], cj = c->c[q] * k * c->f->m[i], ai = 0.0, aj = 0.0;
    const PetscInt ri = (PetscInt)i * c->nvar + c->off[q], rs = s >= 0 ? (PetscInt)s * c->nvar + c->off[q] : -1;
    if (c->heatlin && q == c->ncomp - 1) { /* the energy: row i alpha_i (T_j - T_i), row s alpha_j (T_j - T_i) */
      LinearAlphas(dim, c, i, j, dx, g, &ai, &aj);
      ci -= ai;
      cj += aj;
    }
    c->ierr = AddPair(c->J, ri, rs, ri, rs, s, fold, a, ci, cj);
    if (c->heatlin && q == c->ncomp - 1 && c->fb >= 0 && !c->ierr) /* the book's rows: the correction alone */
      c->ierr = AddPair(c->J, (PetscInt)i * c->nvar + c->fb, s >= 0 ? (PetscInt)s * c->nvar + c->fb : -1, ri, rs, s, fold, a, -ai, aj);
  }
}

/* The viscous force's work W = -C |u|^2 / 2, u = v_i - v_j, C = 2 eta k m_i m_j, heats i
 * and j by W/m each: de_i/dt by -c_i u . dv_i + c_i u . a dv_s (c_i = C/m_i), and a
 * folded j's alike with c_j. Another rank's j keeps i's own column. */
static inline void WorkPair(const int dim, JacPass *c, int i, int j, int s, int fold, double k)
{
  const double  *vi = c->f->v + (size_t)i * dim, *vj = c->f->v + (size_t)j * dim;
  const double   ci = c->c[0] * k * c->f->m[j], cj = c->c[0] * k * c->f->m[i];
  const PetscInt rows[2] = {(PetscInt)i * c->nvar + c->off[dim], (PetscInt)(s < 0 ? 0 : s) * c->nvar + c->off[dim]};
  PetscInt       cols[6];
  PetscScalar    v[12];

  if (c->ierr) return;
  for (int d = 0; d < dim; d++) {
    const double u = vi[d] - vj[d], a = Coef(c, j, s, d);
    cols[d]            = (PetscInt)i * c->nvar + c->off[d];
    cols[dim + d]      = (PetscInt)(s < 0 ? 0 : s) * c->nvar + c->off[d];
    v[d]               = -ci * u;
    v[dim + d]         = ci * u * a;
    v[2 * dim + d]     = -cj * u;
    v[3 * dim + d]     = cj * u * a;
  }
  c->ierr = MatSetValues(c->J, s >= 0 && fold ? 2 : 1, rows, s < 0 ? dim : 2 * dim, cols, v, ADD_VALUES);
}

/* A mirror image's pair in the walls' books of its source s (wall_books.h): work
 * C (|v_i|^2 - |v_j|^2)/2, heat m_i m_j 2 kappa k (T_i - T_j), impulse C u. */
static inline void BookPair(const int dim, JacPass *c, int i, int j, int s, double k)
{
  const double  *vi = c->f->v + (size_t)i * dim, *vj = c->f->v + (size_t)j * dim;
  const double   C = c->c[0] * k * c->f->m[j] * c->f->m[i], H = c->c[dim] * k * c->f->m[j] * c->f->m[i];
  const PetscInt rb = (PetscInt)s * c->nvar + c->wb;
  PetscInt       cols[8];
  PetscScalar    v[8];

  if (c->ierr) return;
  for (int d = 0; d < dim; d++) {
    const double a = Coef(c, j, s, d);
    cols[d]       = (PetscInt)i * c->nvar + c->off[d];
    cols[dim + d] = (PetscInt)s * c->nvar + c->off[d];
    v[d]          = C * vi[d];
    v[dim + d]    = -C * vj[d] * a;
  }
  c->ierr = MatSetValues(c->J, 1, &rb, 2 * dim, cols, v, ADD_VALUES);
  if (c->ierr) return;
  {
    const PetscInt    row = rb + 1, ce[2] = {(PetscInt)i * c->nvar + c->off[dim], (PetscInt)s * c->nvar + c->off[dim]};
    const PetscScalar ve[2] = {H, -H * Coef(c, j, s, dim)};
    c->ierr = MatSetValues(c->J, 1, &row, 2, ce, ve, ADD_VALUES);
  }
  for (int d = 0; d < dim && !c->ierr; d++) {
    const PetscInt    row = rb + 2 + d, cd[2] = {cols[d], cols[dim + d]};
    const PetscScalar vd[2] = {C, -C * Coef(c, j, s, d)};
    c->ierr = MatSetValues(c->J, 1, &row, 2, cd, vd, ADD_VALUES);
  }
}

static inline __attribute__((always_inline)) void JacobianPair(const int dim, JacPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  const double k = SpamPairDiffusionFactor(c->f, i, j, g);
  int          fold;
  const int    s      = SourceOf(c, j, &fold);
  const int    mirror = j >= c->n && s >= 0 && c->gh->kind[j - c->n] == SPAM_GHOST_MIRROR;
  (void)r2;
  (void)w;
  if (c->ierr) return;
  LinearPair(dim, c, i, j, s, fold, k, dx, g);
  if (c->c[0] != 0.0) WorkPair(dim, c, i, j, s, fold, k);
  if (mirror && c->wb >= 0) BookPair(dim, c, i, j, s, k);
}
SPAM_PAIR_WALK(WalkJacobian, JacPass, JacobianPair)

/* b_i of the correction (f->heat): each pair's sides as SpamPairHeatDiffusionLinear takes
 * them (j's only for a local particle or a periodic image, folded onto the source). */
static inline __attribute__((always_inline)) void LinearMomentPair(const int dim, JacPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields  *f = c->f;
  const double t = c->kappa2 * SpamPairDiffusionFactor(f, i, j, g);
  int          fold;
  const int    s = SourceOf(c, j, &fold);
  (void)r2;
  (void)w;
  for (int d = 0; d < dim; d++) f->heat[(size_t)i * dim + d] += f->m[j] * t * dx[d];
  if (s >= 0 && fold)
    for (int d = 0; d < dim; d++) f->heat[(size_t)j * dim + d] -= f->m[i] * t * dx[d];
}
SPAM_PAIR_WALK(WalkLinearMoments, JacPass, LinearMomentPair)

/* -u_i = -M_i^-1 b_i of every slot, in f->heat: b from the pairs, folded, then the solve
 * the corrected grad T makes (SpamGasFlowTemperatureGradient: s -> -M^-1 s), gathered so
 * that a periodic image holds its source's. */
static PetscErrorCode LinearMoments(SpamSim *sim, JacPass *c)
{
  SpamFields *f   = c->f;
  const int   dim = f->dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);

  PetscFunctionBeginUser;
  for (size_t k = 0; k < (size_t)slots * dim; k++) f->heat[k] = 0.0;
  PetscCall(WalkLinearMoments(&sim->pair.nl, &sim->model.kernel, c));
  SpamGhostsFold(c->gh, dim, n, dim, SPAM_GHOST_VECTOR, f->heat);
  SpamGasFlowTemperatureGradient(sim);
  PetscCall(SpamGhostsGather(c->gh, dim, n, dim, SPAM_GHOST_VECTOR, f->heat));
  PetscFunctionReturn(0);
}

/* The components the part diffuses: the velocity's dim, then the energy (through T). */
static JacPass PassOf(SpamSim *sim, SpamDiffusionJac *jac)
{
  const SpamLayout      *l = &sim->model.layout;
  const SpamSolidParams *p = &sim->model.solid;
  JacPass                c = {0};

  c.f     = &sim->pair.f;
  c.J     = jac->J;
  c.gh    = &sim->pair.nl.ghosts;
  c.coef  = jac->coef;
  c.n     = (int)sim->p.n;
  c.nvar  = l->nvar;
  c.ncomp = l->dim + 1;
  c.wb    = l->wb;
  for (int d = 0; d < l->dim; d++) {
    c.off[d] = l->v + d;
    c.c[d]   = 2.0 * p->shear_visc;
  }
  c.off[l->dim]   = l->e;
  c.c[l->dim]     = 2.0 * p->conductivity * (p->gamma - 1.0);
  c.heatlin       = p->heat_linear && p->conductivity > 0.0;
  c.fb            = c.heatlin ? l->fb : -1;
  c.kappa2        = 2.0 * p->conductivity;
  c.tcoef         = p->gamma - 1.0;
  c.rho_geometric = p->rho_geometric;
  return c;
}

/* Room for the pattern's arrays: allocated only when the list outgrew them. */
static PetscErrorCode Reserve(SpamDiffusionJac *jac, int rows, int slots, int dim)
{
  PetscFunctionBeginUser;
  if (rows > jac->rows_cap) {
    PetscCall(PetscFree(jac->nnz));
    PetscCall(PetscMalloc1(rows, &jac->nnz));
    jac->rows_cap = rows;
  }
  if (slots > jac->slots_cap) {
    PetscCall(PetscFree2(jac->coef, jac->ones));
    PetscCall(PetscMalloc2((size_t)slots * (dim + 1), &jac->coef, (size_t)slots * dim, &jac->ones));
    jac->slots_cap = slots;
  }
  PetscFunctionReturn(0);
}

/* Zeros where the pair (i, source s) puts its entries: each component's (i, s) both
 * ways, the energies' rows in both velocities' columns, and for a mirror image the books'
 * rows of s in both velocities' and energies' columns. */
static PetscErrorCode PatternPair(const JacPass *c, int dim, int i, int s, PetscBool mirror)
{
  PetscInt    rows[2] = {(PetscInt)i * c->nvar + c->off[dim], (PetscInt)s * c->nvar + c->off[dim]}, cols[8];
  PetscScalar zero[5 * 8] = {0.0};

  PetscFunctionBeginUser;
  for (int q = 0; q < c->ncomp; q++) {
    const PetscInt ri = (PetscInt)i * c->nvar + c->off[q], rs = (PetscInt)s * c->nvar + c->off[q], rq[2] = {ri, rs};
    PetscCall(MatSetValues(c->J, 2, rq, 2, rq, zero, INSERT_VALUES));
  }
  for (int d = 0; d < dim; d++) {
    cols[d]       = (PetscInt)i * c->nvar + c->off[d];
    cols[dim + d] = (PetscInt)s * c->nvar + c->off[d];
  }
  PetscCall(MatSetValues(c->J, 2, rows, 2 * dim, cols, zero, INSERT_VALUES));
  if (!mirror || c->wb < 0) PetscFunctionReturn(0);
  cols[2 * dim]     = rows[0];
  cols[2 * dim + 1] = rows[1];
  for (int b = 0; b < 2 + dim; b++) {
    const PetscInt rb = (PetscInt)s * c->nvar + c->wb + b;
    PetscCall(MatSetValues(c->J, 1, &rb, 2 * dim + 2, cols, zero, INSERT_VALUES));
  }
  PetscFunctionReturn(0);
}

/* Zeros where the conduction's linear correction puts the pair (i, s) in the flow scheme's
 * book: its rows read the energies, both ways. */
static PetscErrorCode PatternBook(const JacPass *c, int i, int s)
{
  const PetscInt e = c->off[c->ncomp - 1];

  PetscFunctionBeginUser;
  if (c->fb < 0) PetscFunctionReturn(0);
  PetscCall(MatSetValue(c->J, (PetscInt)i * c->nvar + c->fb, (PetscInt)s * c->nvar + e, 0.0, INSERT_VALUES));
  PetscCall(MatSetValue(c->J, (PetscInt)s * c->nvar + c->fb, (PetscInt)i * c->nvar + e, 0.0, INSERT_VALUES));
  PetscFunctionReturn(0);
}

/* Every pair of the list as zeros, so that later assemblies never add a nonzero (a pair
 * comes within range between builds); a pair whose column is not this rank's has none
 * but the diagonal blocks, which every particle has. */
static PetscErrorCode InsertPattern(SpamSim *sim, const JacPass *c)
{
  const SpamNeighbours *nl   = &sim->pair.nl;
  const int             dim  = c->ncomp - 1;
  const PetscInt        rows = (PetscInt)c->n * c->nvar;

  PetscFunctionBeginUser;
  for (PetscInt r = 0; r < rows; r++) PetscCall(MatSetValue(c->J, r, r, 0.0, INSERT_VALUES));
  for (int i = 0; i < c->n; i++) {
    PetscCall(PatternPair(c, dim, i, i, PETSC_FALSE));
    PetscCall(PatternBook(c, i, i));
    for (int t = 0; t < 2; t++) {
      const int *nb = t ? nl->gnbr + nl->gstart[i] : nl->nbr + nl->start[i];
      const int  np = t ? nl->gstart[i + 1] - nl->gstart[i] : nl->start[i + 1] - nl->start[i];
      for (int b = 0; b < np; b++) {
        const int j = nb[b], gk = j - c->n;
        const int s = j < c->n ? j : gk < c->gh->nlocal ? c->gh->src[gk] : -1;
        if (s < 0) continue;
        PetscCall(PatternPair(c, dim, i, s, (PetscBool)(j >= c->n && c->gh->kind[gk] == SPAM_GHOST_MIRROR)));
        PetscCall(PatternBook(c, i, s));
      }
    }
  }
  PetscFunctionReturn(0);
}

/* A new matrix for the list's pattern: per particle, its pairs counted at both ends (an
 * overestimate where a particle pairs with several images of one source); a velocity row
 * has a column per partner, an energy row dim + 1, a book row dim + 1 per mirror image's
 * partner (bdeg, counted at the source). */
static PetscErrorCode NewPattern(SpamSim *sim, SpamDiffusionJac *jac)
{
  const SpamNeighbours *nl = &sim->pair.nl;
  const SpamLayout     *l  = &sim->model.layout;
  const int             n = (int)sim->p.n, nvar = l->nvar, slots = SpamNeighboursSlots(nl), nc = l->dim + 1;
  PetscInt             *deg, *bdeg;
  JacPass               c;

  PetscFunctionBeginUser;
  PetscCall(Reserve(jac, n * nvar, slots, l->dim));
  PetscCall(PetscMalloc1(n, &bdeg));
  deg = jac->nnz; /* per particle first, spread over its rows below (from the last down) */
  for (int i = 0; i < n; i++) deg[i] = bdeg[i] = 1;
  for (int i = 0; i < n; i++) {
    for (int t = 0; t < 2; t++) { /* the list's pairs, then the ghosts' (either may hold a ghost slot) */
      const int *nb = t ? nl->gnbr + nl->gstart[i] : nl->nbr + nl->start[i];
      const int  np = t ? nl->gstart[i + 1] - nl->gstart[i] : nl->start[i + 1] - nl->start[i];
      for (int b = 0; b < np; b++) {
        const int j = nb[b], gk = j - n;
        const int s = j < n ? j : gk < nl->ghosts.nlocal ? nl->ghosts.src[gk] : -1;
        if (s < 0) continue;
        deg[i]++;
        deg[s]++;
        if (j >= n && nl->ghosts.kind[gk] == SPAM_GHOST_MIRROR) bdeg[s]++;
      }
    }
  }
  c = PassOf(sim, jac);
  for (int i = n - 1; i >= 0; i--) {
    const PetscInt di = PetscMin(deg[i], (PetscInt)n), bi = PetscMin(bdeg[i], (PetscInt)n);
    for (int v = nvar - 1; v >= 0; v--) {
      PetscInt *r = &deg[(size_t)i * nvar + v];
      if (v >= l->v && v < l->v + l->dim) *r = di;
      else if (v == l->e) *r = nc * di;
      else if (l->wb >= 0 && v >= l->wb && v < l->wb + 2 + l->dim) *r = nc * bi + 1; /* and its diagonal */
      else if (v == c.fb) *r = di + 1; /* the energies and its own diagonal */
      else *r = 1;
    }
  }
  PetscCall(PetscFree(bdeg));
  PetscCall(MatDestroy(&jac->J));
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, n * nvar, n * nvar, 0, jac->nnz, &jac->J));
  PetscCall(MatSetOption(jac->J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  c.J = jac->J;
  PetscCall(InsertPattern(sim, &c));
  PetscCall(MatAssemblyBegin(jac->J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(jac->J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatSetOption(jac->J, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
  jac->builds  = nl->builds;
  jac->npairs  = nl->npairs;
  jac->ngpairs = nl->ngpairs;
  jac->n       = n;
  jac->slots   = slots;
  jac->patterns++;
  PetscFunctionReturn(0);
}

/* The ghosts' coefficients a per component, from the gathers of ones and of zeros. */
static PetscErrorCode ImageCoefficients(SpamSim *sim, SpamDiffusionJac *jac)
{
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = sim->model.dim, n = (int)sim->p.n, nc = dim + 1;

  PetscFunctionBeginUser;
  for (int pass = 0; pass < 2; pass++) {
    for (int q = 0; q < 2; q++) { /* q 0: the velocity, 1: the temperature */
      const int ncomp = q ? 1 : dim;
      for (size_t k = 0; k < (size_t)n * ncomp; k++) jac->ones[k] = pass ? 0.0 : 1.0;
      PetscCall(SpamGhostsGatherWall(gh, dim, n, q ? SPAM_WALL_FIELD_TEMPERATURE : SPAM_WALL_FIELD_VELOCITY, jac->ones));
      for (int k = 0; k < gh->nlocal; k++)
        for (int d = 0; d < ncomp; d++) {
          double *a = &jac->coef[(size_t)k * nc + (q ? dim : d)];
          *a        = pass ? *a - jac->ones[(size_t)(n + k) * ncomp + d] : jac->ones[(size_t)(n + k) * ncomp + d];
        }
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDiffusionJacAssemble(SpamSim *sim, const double *y, SpamDiffusionJac *jac, PetscInt *bad)
{
  const SpamNeighbours *nl = &sim->pair.nl;
  JacPass               c;

  PetscFunctionBeginUser;
  PetscCall(SpamRhsSolidDiffusionFields(sim, y, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  if (!jac->J || jac->builds != nl->builds || jac->npairs != nl->npairs || jac->ngpairs != nl->ngpairs || jac->n != (int)sim->p.n || jac->slots != SpamNeighboursSlots(nl)) PetscCall(NewPattern(sim, jac));
  PetscCall(ImageCoefficients(sim, jac));
  PetscCall(MatZeroEntries(jac->J));
  c = PassOf(sim, jac);
  if (c.heatlin) PetscCall(LinearMoments(sim, &c));
  PetscCall(WalkJacobian(nl, &sim->model.kernel, &c));
  PetscCall(c.ierr);
  PetscCall(MatAssemblyBegin(jac->J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(jac->J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamDiffusionJacDestroy(SpamDiffusionJac *jac)
{
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&jac->J));
  PetscCall(PetscFree(jac->nnz));
  PetscCall(PetscFree2(jac->coef, jac->ones));
  jac->rows_cap = jac->slots_cap = 0;
  jac->builds                    = -1;
  PetscFunctionReturn(0);
}
