/* The flow scheme's per-particle steps (gas_flow.h): the background pressure fitted to the
 * particles, the transport shift's velocity and the corrections that go with both. The
 * pair sums they need run inside the tensor path's walks (rhs_tensor.c). */
#include <spam/physics.h>
#include <spam/gas_flow.h>

/* Solves the 3 x 3 system A c = r by Gaussian elimination with partial pivoting; returns
 * 0 when A is singular (then c is left alone). */
static int Solve3(double A[3][3], double r[3], double c[3])
{
  for (int k = 0; k < 3; k++) {
    int p = k;
    for (int i = k + 1; i < 3; i++)
      if (fabs(A[i][k]) > fabs(A[p][k])) p = i;
    if (!(fabs(A[p][k]) > 1e-300)) return 0;
    for (int j = 0; j < 3; j++) {
      const double t = A[k][j];
      A[k][j]        = A[p][j];
      A[p][j]        = t;
    }
    const double t = r[k];
    r[k]           = r[p];
    r[p]           = t;
    for (int i = k + 1; i < 3; i++) {
      const double f = A[i][k] / A[k][k];
      for (int j = k; j < 3; j++) A[i][j] -= f * A[k][j];
      r[i] -= f * r[k];
    }
  }
  for (int k = 2; k >= 0; k--) {
    double s = r[k];
    for (int j = k + 1; j < 3; j++) s -= A[k][j] * c[j];
    c[k] = s / A[k][k];
  }
  return 1;
}

/* |g|^2 where gravity crosses no periodic face, else 0: a pressure that falls along a
 * periodic direction is not periodic (the Poiseuille channel's driving gravity runs along
 * its periodic axis, and the pressure there is uniform), so B is fitted along gravity only
 * where this is positive. */
static double GravityAcross(const SpamSim *sim)
{
  double gn = 0.0;

  for (int d = 0; d < sim->model.layout.dim; d++) {
    if (sim->geo.box.periodic[d] && sim->model.gravity[d] != 0.0) return 0.0;
    gn += sim->model.gravity[d] * sim->model.gravity[d];
  }
  return gn;
}

/* The background B: the mean of the particles' pressures P = (gamma - 1) rho e, or under
 * gravity their least-squares quadratic in the height (a layer in hydrostatic balance has
 * a pressure that falls with height; a constant would leave its stiffness at the top and
 * the bottom). Refitted at every evaluation so that it follows the mean pressure as the
 * flow heats the gas or the arrangement changes the summed density (a mismatch of 0.3 %
 * already shows as ringing of a shear wave). One reduction of 8 sums over the ranks. */
PetscErrorCode SpamGasFlowFit(SpamSim *sim, const double *y, SpamBackground *b)
{
  const SpamLayout      *l   = &sim->model.layout;
  const SpamSolidParams *p   = &sim->model.solid;
  const int              dim = l->dim;
  double                 m[8] = {0, 0, 0, 0, 0, 0, 0, 0}, gn = GravityAcross(sim); /* sum s^k (k = 0..4), sum P s^k (k = 0..2) */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(b, sizeof *b));
  if (p->background == SPAM_BACKGROUND_NONE) PetscFunctionReturn(0);
  if (gn > 0.0)
    for (int d = 0; d < dim; d++) {
      b->up[d]     = -sim->model.gravity[d] / sqrt(gn);
      b->origin[d] = sim->geo.box.lo[d] + 0.5 * sim->geo.box.len[d];
    }
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double s = SpamBackgroundHeight(b, dim, y + (size_t)i * l->nvar + l->x), P = (p->gamma - 1.0) * sim->pair.f.rho[i] * sim->pair.f.e[i];
    const double s2 = s * s;
    m[0] += 1.0;
    m[1] += s;
    m[2] += s2;
    m[3] += s2 * s;
    m[4] += s2 * s2;
    m[5] += P;
    m[6] += P * s;
    m[7] += P * s2;
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, m, 8, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  if (!(m[0] > 0.0)) PetscFunctionReturn(0);
  b->c[0] = m[5] / m[0];
  if (gn > 0.0) {
    double A[3][3] = {{m[0], m[1], m[2]}, {m[1], m[2], m[3]}, {m[2], m[3], m[4]}}, r[3] = {m[5], m[6], m[7]}, c[3];
    if (Solve3(A, r, c))
      for (int k = 0; k < 3; k++) b->c[k] = c[k];
  }
  PetscFunctionReturn(0);
}

/* The shift velocity dv_i = -C h c_i S_i / V_i from the folded pair sums S (f->shift, which
 * then holds dv), added to dr/dt; and the energy rate of the drift, dv . grad e, from
 * grad T = (gamma - 1) grad e (f->heat, before it becomes the heat flux). c_i is the
 * particle's own sound speed, so the shift is a diffusion of coefficient ~ C c h wherever
 * the gas is. */
void SpamGasFlowShift(SpamSim *sim)
{
  const SpamSolidParams *p   = &sim->model.solid;
  SpamFields            *f   = &sim->pair.f;
  const int              dim = f->dim;
  const double           ch  = p->shift_coef * sim->model.kernel.h;

  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double c  = sqrt(p->gamma * (p->gamma - 1.0) * PetscMax(f->e[i], 0.0));
    const double k  = -ch * c * f->rho[i] / f->m[i]; /* 1 / V_i */
    double      *dv = f->shift + (size_t)i * dim, de = 0.0;
    for (int d = 0; d < dim; d++) {
      dv[d] *= k;
      f->xdot[(size_t)i * dim + d] += dv[d];
      de += dv[d] * f->heat[(size_t)i * dim + d];
    }
    f->edrift[i] = de / (p->gamma - 1.0);
  }
}

/* grad T of this rank's particles, in f->heat, from their SPAM gradient S: the G of
 * M G = -S (M the gradient's moment; a linear T's SPAM gradient is -M G), exact for a
 * linear temperature on any arrangement; 0 where M is singular (an isolated particle).
 * The pair conduction's linear correction reads it (-conduction_linear, pair_diffusion.h);
 * the shift's drift has read the SPAM gradient before. */
void SpamGasFlowTemperatureGradient(SpamSim *sim)
{
  SpamFields *f   = &sim->pair.f;
  const int   dim = f->dim;

  for (PetscInt i = 0; i < sim->p.n; i++) {
    double  A[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, r[3] = {0, 0, 0}, G[3] = {0, 0, 0};
    double *s = f->heat + (size_t)i * dim;
    for (int a = 0; a < dim; a++) {
      r[a] = -s[a];
      for (int b = 0; b < dim; b++) A[a][b] = f->gmom[(size_t)i * dim * dim + a * dim + b];
    }
    if (!Solve3(A, r, G))
      for (int a = 0; a < 3; a++) G[a] = 0.0;
    for (int a = 0; a < dim; a++) s[a] = G[a];
  }
}

/* div v of particle i from its SPAM velocity gradient G and the gradient's moment M:
 * -tr(M^-1 G), exact for a linear velocity field on any arrangement (-tr G where M is
 * singular: an isolated particle). */
static double CorrectedDivergence(int dim, const double *M, const double *G)
{
  double det, inv[9];

  if (dim == 1) {
    det = M[0];
    if (!(fabs(det) > 1e-300)) return G[0];
    return -G[0] / det;
  }
  if (dim == 2) {
    det = M[0] * M[3] - M[1] * M[2];
    if (!(fabs(det) > 1e-300)) return G[0] + G[3];
    inv[0] = M[3] / det, inv[1] = -M[1] / det, inv[2] = -M[2] / det, inv[3] = M[0] / det;
    return -(inv[0] * G[0] + inv[1] * G[2] + inv[2] * G[1] + inv[3] * G[3]);
  }
  inv[0] = M[4] * M[8] - M[5] * M[7], inv[1] = M[2] * M[7] - M[1] * M[8], inv[2] = M[1] * M[5] - M[2] * M[4];
  inv[3] = M[5] * M[6] - M[3] * M[8], inv[4] = M[0] * M[8] - M[2] * M[6], inv[5] = M[2] * M[3] - M[0] * M[5];
  inv[6] = M[3] * M[7] - M[4] * M[6], inv[7] = M[1] * M[6] - M[0] * M[7], inv[8] = M[0] * M[4] - M[1] * M[3];
  det = M[0] * inv[0] + M[1] * inv[3] + M[2] * inv[6];
  if (!(fabs(det) > 1e-300)) return G[0] + G[4] + G[8];
  double tr = 0.0;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) tr += inv[a * 3 + b] * G[b * 3 + a];
  return -tr / det;
}

/* The velocity divergence that B's compression work reads: the corrected one, less its
 * volume-weighted mean over all particles. In a closed box (periodic faces, walls that do
 * not move along their normals) the volume does not change, so the mean of div v is zero
 * in the continuum; the SPAM sum is not, and B times it would heat or cool the gas for
 * nothing (a constant B's work then cancels exactly, so the pair force's rearrangements
 * cost no energy). One reduction of two sums over the ranks. */
PetscErrorCode SpamGasFlowDivergence(SpamSim *sim)
{
  SpamFields *f   = &sim->pair.f;
  const int   dim = f->dim;
  double      s[2] = {0.0, 0.0};

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double V = f->m[i] / f->rho[i];
    f->divv[i]     = CorrectedDivergence(dim, f->gmom + (size_t)i * dim * dim, f->gradv + (size_t)i * dim * dim);
    s[0] += V * f->divv[i];
    s[1] += V;
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, s, 2, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  for (PetscInt i = 0; i < sim->p.n && s[1] > 0.0; i++) f->divv[i] -= s[0] / s[1];
  PetscFunctionReturn(0);
}

/* Whether B works on the shift's compression in this run (-shift_compression): the flow
 * scheme's gas with a background pressure, the transport shift, a summed density and one
 * smoothing length; by default (stratified) only where B is fitted along gravity and no
 * no-slip wall moves. Where B is uniform the term does no net work (its volume mean is
 * taken out) but moves heat between particles by the shift's repair of their disorder,
 * and that was measured to harm: the Taylor-Green vortex at Re = 100, L = 48, decayed
 * more slowly (KE at one e-folding 1.0283 of the continuum's, 1.0181 without), and under
 * a moving lid the sheared rows heated without bound (docs/gas-flow.md). Where B varies
 * the shift's drift through the stratification is what it is for (the convection cell's
 * roll grew below onset without it). */
PetscBool SpamGasFlowShiftWorks(const SpamSim *sim)
{
  const SpamSolidParams *p = &sim->model.solid;
  const SpamWalls       *w = &sim->geo.walls;

  if (p->shift_work == SPAM_SHIFT_WORK_OFF || p->material != SPAM_MATERIAL_GAS || p->scheme != SPAM_GAS_FLOW || p->background == SPAM_BACKGROUND_NONE || !(p->shift_coef > 0.0) ||
      p->density != SPAM_DENSITY_SUMMATION || p->smoothing == SPAM_SMOOTHING_ADAPTIVE)
    return PETSC_FALSE;
  if (p->shift_work == SPAM_SHIFT_WORK_ALL) return PETSC_TRUE;
  if (!(GravityAcross(sim) > 0.0)) return PETSC_FALSE;
  for (int f = 0; f < SPAM_FACES; f++)
    if (w->slip[f] == SPAM_WALL_NOSLIP && (w->velocity[f][0] != 0.0 || w->velocity[f][1] != 0.0 || w->velocity[f][2] != 0.0)) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* The summed density's rate from the shift (f->rhodot, walk 3) less its volume mean:
 * sum_i V_i (drho_i/dt) / rho_i then vanishes, so a constant B does no net work on the
 * shift's rearrangement. The summed volumes' sum is not the box's and changes as the shift
 * moves the particles (by about 0.3 % of the box in Taylor-Green at Re = 100, L = 48); B
 * times that change went into e (-1.34 KE0 in that run, against -0.03 without the work).
 * The divergence of v has its volume mean taken out for the same reason
 * (SpamGasFlowDivergence). One reduction of two sums over the ranks. */
PetscErrorCode SpamGasFlowShiftCompression(SpamSim *sim)
{
  SpamFields *f = &sim->pair.f;
  double      s[2] = {0.0, 0.0};

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    s[0] += f->m[i] * f->rhodot[i] / (f->rho[i] * f->rho[i]);
    s[1] += f->m[i] / f->rho[i];
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, s, 2, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  for (PetscInt i = 0; i < sim->p.n && s[1] > 0.0; i++) f->rhodot[i] -= f->rho[i] * s[0] / s[1];
  PetscFunctionReturn(0);
}

/* After the force walk: the drift corrections (dv . grad) v and dv . grad e, the body
 * force -grad B / rho that gives back the background's gradient, and B's compression
 * work -B div v / rho (SpamGasFlowDivergence), so that the internal energy follows the
 * full pressure. With shiftwork (-shift_compression) B also works on the compression the
 * shift makes, B / rho^2 times the summed density's rate from the particles' drift dv
 * (f->rhodot, walk 3, less its volume mean: SpamGasFlowShiftCompression): the summed density follows v + dv, and an energy that followed v
 * alone would let P = (gamma - 1) rho e change by the shift's compression at fixed e
 * (a hot column compressed instead of expanded: the convection cell's roll then grew
 * below onset). The book's rate is what these give the particle's energy, with the
 * gravitational energy the drift moves it through (-g . dv). */
void SpamGasFlowCorrect(SpamSim *sim, const double *y, const SpamBackground *b, PetscBool shiftwork)
{
  const SpamLayout      *l     = &sim->model.layout;
  const SpamSolidParams *p     = &sim->model.solid;
  SpamFields            *f     = &sim->pair.f;
  const int              dim   = f->dim;
  const PetscBool        shift = (PetscBool)(p->shift_coef > 0.0), bg = (PetscBool)(p->background != SPAM_BACKGROUND_NONE);

  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *x = y + (size_t)i * l->nvar + l->x, *v = f->v + (size_t)i * dim, *g = f->gradv + (size_t)i * dim * dim, rho = f->rho[i];
    double        da[3] = {0, 0, 0}, de = 0.0, power = 0.0;
    if (shift) {
      const double *dv = f->shift + (size_t)i * dim;
      for (int c = 0; c < dim; c++) {
        for (int d = 0; d < dim; d++) da[c] += dv[d] * g[d * dim + c];
        power -= sim->model.gravity[c] * dv[c];
      }
      de += f->edrift[i];
    }
    if (bg) {
      const double slope = SpamBackgroundSlope(b, dim, x);
      for (int d = 0; d < dim; d++) da[d] -= slope * b->up[d] / rho;
      const double B = SpamBackgroundAt(b, dim, x);
      de -= B * f->divv[i] / rho;
      if (shiftwork) de += B * f->rhodot[i] / (rho * rho);
    }
    for (int d = 0; d < dim; d++) {
      f->acc[(size_t)i * dim + d] += da[d];
      power += v[d] * da[d];
    }
    f->edot[i] += de;
    f->edrift[i] = power + de; /* the book's rate (layout.h), read by the assembly */
  }
}
