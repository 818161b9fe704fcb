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
  double                 m[8] = {0, 0, 0, 0, 0, 0, 0, 0}, gn = 0.0; /* sum s^k (k = 0..4), sum P s^k (k = 0..2) */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(b, sizeof *b));
  if (p->background == SPAM_BACKGROUND_NONE) PetscFunctionReturn(0);
  for (int d = 0; d < dim; d++) gn += sim->model.gravity[d] * sim->model.gravity[d];
  if (sim->model.gravity_on && gn > 0.0)
    for (int d = 0; d < dim; d++) {
      b->up[d]     = -sim->model.gravity[d] / sqrt(gn);
      b->origin[d] = sim->box.lo[d] + 0.5 * sim->box.len[d];
    }
  for (PetscInt i = 0; i < sim->n; i++) {
    const double s = SpamBackgroundHeight(b, dim, y + (size_t)i * l->nvar + l->x), P = (p->gamma - 1.0) * sim->f.rho[i] * sim->f.e[i];
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
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, m, 8, MPI_DOUBLE, MPI_SUM, sim->comm));
  if (!(m[0] > 0.0)) PetscFunctionReturn(0);
  b->c[0] = m[5] / m[0];
  if (gn > 0.0) {
    double A[3][3] = {{m[0], m[1], m[2]}, {m[1], m[2], m[3]}, {m[2], m[3], m[4]}}, r[3] = {m[5], m[6], m[7]}, c[3];
    if (Solve3(A, r, c))
      for (int k = 0; k < 3; k++) b->c[k] = c[k];
  }
  PetscFunctionReturn(0);
}

/* The shift velocity dv_i = -C h c_i rho_i S_i from the folded pair sums S (f->shift, which
 * then holds dv), added to dr/dt; and the energy rate of the drift, dv . grad e, from
 * grad T = (gamma - 1) grad e (f->heat, before it becomes the heat flux). c_i is the
 * particle's own sound speed, so the shift is a diffusion of coefficient ~ C c h wherever
 * the gas is. */
void SpamGasFlowShift(SpamSim *sim)
{
  const SpamSolidParams *p   = &sim->model.solid;
  SpamFields            *f   = &sim->f;
  const int              dim = f->dim;
  const double           ch  = p->shift_coef * sim->model.kernel.h;

  for (PetscInt i = 0; i < sim->n; i++) {
    const double c  = sqrt(p->gamma * (p->gamma - 1.0) * PetscMax(f->e[i], 0.0));
    const double k  = -ch * c * f->rho[i];
    double      *dv = f->shift + (size_t)i * dim, de = 0.0;
    for (int d = 0; d < dim; d++) {
      dv[d] *= k;
      f->xdot[(size_t)i * dim + d] += dv[d];
      de += dv[d] * f->heat[(size_t)i * dim + d];
    }
    f->edrift[i] = de / (p->gamma - 1.0);
  }
}

/* After the force walk: the drift corrections (dv . grad) v and dv . grad e, the body
 * force -grad B / rho that gives back the background's gradient, and B's compression
 * work B drho/dt / rho^2 (f->rhodot: the summed density's rate under v), so that the
 * internal energy follows the full pressure. */
void SpamGasFlowCorrect(SpamSim *sim, const double *y, const SpamBackground *b)
{
  const SpamLayout      *l     = &sim->model.layout;
  const SpamSolidParams *p     = &sim->model.solid;
  SpamFields            *f     = &sim->f;
  const int              dim   = f->dim;
  const PetscBool        shift = (PetscBool)(p->shift_coef > 0.0), bg = (PetscBool)(p->background != SPAM_BACKGROUND_NONE);

  for (PetscInt i = 0; i < sim->n; i++) {
    const double *x = y + (size_t)i * l->nvar + l->x, *g = f->gradv + (size_t)i * dim * dim, rho = f->rho[i];
    double       *a = f->acc + (size_t)i * dim;
    if (shift) {
      const double *dv = f->shift + (size_t)i * dim;
      for (int c = 0; c < dim; c++)
        for (int d = 0; d < dim; d++) a[c] += dv[d] * g[d * dim + c];
      f->edot[i] += f->edrift[i];
    }
    if (bg) {
      const double slope = SpamBackgroundSlope(b, dim, x);
      for (int d = 0; d < dim; d++) a[d] -= slope * b->up[d] / rho;
      f->edot[i] += SpamBackgroundAt(b, dim, x) * f->rhodot[i] / (rho * rho);
    }
  }
}
