/* Gauss's principle of least constraint for the total angular momentum and energy
 * (PRE Sec. VII, with the signs made consistent with its own force). In the centre-of-mass
 * frame the constraint acceleration -alpha v_i + beta z x r_i keeps both fixed when
 *   beta = -Ldot / [I - L^2/(2K)],  alpha = beta L / (2K),
 * with I = sum m r^2, K = sum m v^2 / 2 and Ldot = sum m (rdot x v + r x a). The
 * denominator vanishes for rigid rotation (at t = 0 of the rotor) and where K = 0: those
 * evaluations are counted as singular and the constraint is skipped, never divided by
 * zero. The first one is reported on stdout. */
#include <spam/physics.h>

#define GAUSS_SINGULAR_TOL 1e-9 /* |I - L^2/2K| below this fraction of I is singular */

/* Sums: m, m r, m v, m rdot (0..6); then about the centre: L, K, I, Ldot (0..3). */
static PetscErrorCode Moments(SpamSim *sim, const double *y, double c[4], double rc[2], double vc[2])
{
  const SpamLayout *l = &sim->model.layout;
  const double     *mass = sim->pair.f.m;
  double            s[7] = {0, 0, 0, 0, 0, 0, 0}, xc[2];

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, m = mass[i];
    s[0] += m;
    for (int d = 0; d < 2; d++) {
      s[1 + d] += m * p[l->x + d];
      s[3 + d] += m * p[l->v + d];
      s[5 + d] += m * sim->pair.f.xdot[2 * i + d];
    }
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, s, 7, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  for (int d = 0; d < 2; d++) {
    rc[d] = s[1 + d] / s[0];
    vc[d] = s[3 + d] / s[0];
    xc[d] = s[5 + d] / s[0];
  }
  c[0] = c[1] = c[2] = c[3] = 0.0;
  for (PetscInt i = 0; i < sim->p.n; i++) {
    const double *p = y + (size_t)i * l->nvar, m = mass[i];
    const double  r[2] = {p[l->x] - rc[0], p[l->x + 1] - rc[1]}, v[2] = {p[l->v] - vc[0], p[l->v + 1] - vc[1]};
    const double  rd[2] = {sim->pair.f.xdot[2 * i] - xc[0], sim->pair.f.xdot[2 * i + 1] - xc[1]};
    c[0] += m * (r[0] * v[1] - r[1] * v[0]);
    c[1] += 0.5 * m * (v[0] * v[0] + v[1] * v[1]);
    c[2] += m * (r[0] * r[0] + r[1] * r[1]);
    c[3] += m * (rd[0] * v[1] - rd[1] * v[0] + r[0] * sim->pair.f.acc[2 * i + 1] - r[1] * sim->pair.f.acc[2 * i]);
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, c, 4, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReportSingular(SpamSim *sim, double den, double inertia, double K)
{
  char msg[256];

  PetscFunctionBeginUser;
  sim->ps->gauss_singular++;
  if (sim->ps->gauss_reported) PetscFunctionReturn(0);
  sim->ps->gauss_reported = PETSC_TRUE;
  (void)snprintf(msg, sizeof msg, "spam-ark: Gauss's principle is singular (I - L^2/2K = %.3e, I = %.6g, K = %.6g: rigid rotation or rest); the constraint force is skipped while singular (counted in timeseries column gauss_singular)\n", den, inertia, K);
  PetscCall(PetscPrintf(sim->p.comm, "%s", msg));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamGaussConstraint(SpamSim *sim, const double *y)
{
  const SpamLayout *l = &sim->model.layout;
  double            c[4], rc[2] = {0, 0}, vc[2] = {0, 0};

  PetscFunctionBeginUser;
  PetscCall(Moments(sim, y, c, rc, vc));
  {
    const double L = c[0], K = c[1], inertia = c[2], Ldot = c[3];
    const double den = K > 0.0 ? inertia - L * L / (2.0 * K) : 0.0;
    if (!(K > 0.0) || !(fabs(den) > GAUSS_SINGULAR_TOL * inertia)) {
      PetscCall(ReportSingular(sim, den, inertia, K));
      PetscFunctionReturn(0);
    }
    const double beta = -Ldot / den, alpha = beta * L / (2.0 * K);
    double       amax = 0.0, pm[2] = {0.0, 0.0};
    for (PetscInt i = 0; i < sim->p.n; i++) {
      const double *p = y + (size_t)i * l->nvar;
      const double  r[2] = {p[l->x] - rc[0], p[l->x + 1] - rc[1]};
      const double  a[2] = {-alpha * (p[l->v] - vc[0]) - beta * r[1], -alpha * (p[l->v + 1] - vc[1]) + beta * r[0]};
      sim->pair.f.acc[2 * i] += a[0];
      sim->pair.f.acc[2 * i + 1] += a[1];
      amax = PetscMax(amax, PetscMax(fabs(a[0]), fabs(a[1])));
      pm[0] += sim->pair.f.m[i] * a[0];
      pm[1] += sim->pair.f.m[i] * a[1];
    }
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, pm, 2, MPI_DOUBLE, MPI_SUM, sim->p.comm));
    sim->ps->gauss_accel_max = PetscMax(sim->ps->gauss_accel_max, amax);
    /* sum m a of the constraint is zero only in exact arithmetic: r_i - rc rounds at the
     * scale of the absolute positions, so near a rigid rotation (beta large) this residual,
     * not the pair terms, sets the momentum drift of a Gauss run; it is reported so that a
     * test can bound the drift by it. */
    sim->ps->gauss_momentum_residual = PetscMax(sim->ps->gauss_momentum_residual, PetscSqrtReal(pm[0] * pm[0] + pm[1] * pm[1]));
  }
  PetscFunctionReturn(0);
}
