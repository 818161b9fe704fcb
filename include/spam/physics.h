/* The modules of the general tensor path (elastic solid) and of the spring model, and
 * the scratch they share. Every array is allocated once, at set-up (SpamPhysicsScratchCreate),
 * never inside the right-hand side. */
#ifndef SPAM_PHYSICS_H
#define SPAM_PHYSICS_H
#include <spam/sim.h>

typedef struct SpamPhysicsScratch {
  PetscInt n;
  double  *gradv;          /* [4n] (dv^b/dx^a) of particle i at 4i + 2a + b           */
  double  *xdot;           /* [2n] dr/dt (R0, R1 or R2)                               */
  double  *u;              /* [2n] velocity used by the continuity equation          */
  double  *qs;             /* [3n] sigma/rho^2: xx, xy, yy                            */
  double  *edot, *rhodot;  /* [n]                                                      */
  double  *ltorque;        /* [n] Ldot_i = 1/2 sum_j Ldot_ij                          */
  double  *heat;           /* [2n] temperature gradient, then the heat flux Q         */
  double  *tfac;           /* [n] T_i scaling factor of each particle                 */
  int     *body, nbody;    /* connected body of each particle at set-up              */
  double  *bpos, *bneg, *bfac; /* [nbody] positive / negative torque sums, factor     */
  int     *bond_start, *bond_nbr; /* CSR half list of spring bonds (each pair once)  */
  int      nbonds;
  /* Gauss's principle: evaluations found singular, and whether that was reported.     */
  long     gauss_singular;
  PetscBool gauss_reported;
  double   gauss_accel_max; /* largest |constraint acceleration| of any particle so far:  */
                            /* the scale of the round-off its sum adds to the momentum   */
} SpamPhysicsScratch;

/* Separation r_i - r_j (minimum image) of a listed pair in 2D from the neighbour list's
 * box-local positions; returns r^2. */
static inline double SpamPairDelta2(const SpamNeighbours *nl, const SpamImage *im, int i, int j, double dx[2])
{
  dx[0] = SpamImageDelta(im, 0, nl->u[0][i] - nl->u[0][j]);
  dx[1] = SpamImageDelta(im, 1, nl->u[1][i] - nl->u[1][j]);
  return dx[0] * dx[0] + dx[1] * dx[1];
}
/* The pair-averaged density rho_ij: arithmetic mean or geometric mean. */
static inline double SpamPairDensity(PetscBool geometric, double ri, double rj)
{
  return geometric ? sqrt(ri * rj) : 0.5 * (ri + rj);
}

/* Allocates sim->ps for sim->n particles; it is freed with the swarm. */
PetscErrorCode SpamPhysicsScratchCreate(SpamSim *sim);
/* Labels the connected bodies: particles closer than range at the current positions y
 * share a body (union-find over the neighbour list). */
PetscErrorCode SpamBodiesLabel(SpamSim *sim, const double *y, double range);

/* Pass 1 of the tensor path: velocity gradient (CiSE Eq. 18 with the PRE sign fixed),
 * (grad v)_i^{ab} = m sum_j (v_j - v_i)^b (grad_i w_ij)^a / rho_ij. */
void SpamVelocityGradient(const SpamSim *sim, const double *y, const double *rho, double *gradv);
/* dr/dt by R0 (v), R1 (<v>) or R2 (v + eps m sum_j (v_j - v_i) w_ij / rho_ij). */
void SpamCoordinateRate(const SpamSim *sim, const double *y, const double *rho, double *xdot);
/* Hooke's stress rate with the rotation terms, from grad v and the stress of y. */
void SpamElasticStressRate(const SpamSim *sim, const double *y, const double *gradv, double *ydot);
/* Torque of a pair force F_ij (on i) about the pair: x_ij F^y - y_ij F^x. */
static inline double SpamPairTorque(const double dx[2], const double F[2])
{
  return dx[0] * F[1] - dx[1] * F[0];
}
/* The tensor pair force F_ij = m^2 (Q_i + Q_j).grad_i w_ij with Q = sigma/rho^2. */
static inline void SpamPairForceTensor(double mass, const double *qi, const double *qj, double g, const double dx[2], double F[2])
{
  const double sxx = qi[0] + qj[0], sxy = qi[1] + qj[1], syy = qi[2] + qj[2], c = mass * mass * g;
  F[0]                                                                      = c * (sxx * dx[0] + sxy * dx[1]);
  F[1]                                                                      = c * (sxy * dx[0] + syy * dx[1]);
}
/* Sums the pair torques of Q (positive and negative, per body, and per particle into
 * ltorque) and sets the scaling factors bfac (T_ij) or tfac (T_i) so that the scaled
 * torques add to zero. Returns the unscaled sum in *total. */
PetscErrorCode SpamTorqueScalingFactors(SpamSim *sim, const double *qs, double *total);
/* Unscaled spurious torque sum_{i<j} Ldot_ij of Q (diagnostics). */
double SpamTorqueSum(const SpamSim *sim, const double *qs);
/* Monaghan's artificial viscosity of an approaching pair (v_ij.r_ij < 0):
 *   Pi_ij = (-alpha c h mu + beta mu^2) / rho_ij,  mu = h v_ij.r_ij / (r^2 + 0.01 h^2),
 * entering the pair force as an extra pressure: F_ij += -m^2 Pi_ij grad_i w_ij (central,
 * so no torque; the energy equation picks it up through F_ij). 0 for receding pairs. */
static inline double SpamViscosityMonaghan(const SpamSolidParams *s, double h, const double dx[2], const double dv[2], double r2, double rho_ij)
{
  const double vr = dv[0] * dx[0] + dv[1] * dx[1];
  if (vr >= 0.0) return 0.0;
  const double mu = h * vr / (r2 + 0.01 * h * h);
  return (-s->visc_alpha * s->sound_speed * mu + s->visc_beta * mu * mu) / rho_ij;
}
/* von Neumann-Richtmyer viscosity per particle: under compression (div v < 0) the
 * pressure q_i = rho_i (beta h^2 (div v)^2 - alpha c h div v) is subtracted from the
 * diagonal of sigma_i / rho_i^2 in qs (isotropic, so central and torque-free). */
void SpamViscosityVonNeumann(const SpamSim *sim, const double *gradv, double *qs);
/* Newtonian viscous stress (2D) from grad v, added to sigma/rho^2 in qs:
 *   sigma_v = eta_s (grad v + grad v^T - (div v) I) + eta_b (div v) I. */
void SpamNewtonianViscosity(const SpamSim *sim, const double *gradv, double *qs);
/* Temperature T = (gamma - 1) e (k = m = 1; the ideal gas has P = rho T) and its gradient
 * (CiSE Eq. 19): (grad T)_i = m sum_j (T_j - T_i) grad_i w_ij / rho_ij, into gradT [2n]. */
void SpamTemperatureGradient(const SpamSim *sim, const double *y, const double *rho, double *gradT);
/* Fourier conduction: Q_i = -kappa (grad T)_i (in place in heat) and its term of the
 * energy equation, de_i/dt += -m sum_j [(Q/rho^2)_i + (Q/rho^2)_j].grad_i w_ij, added to
 * ps->edot; the pair terms cancel in sum m de/dt. */
void SpamFourierConduction(SpamSim *sim, double *heat);
/* Pass 2: accelerations, de/dt and (continuity) drho/dt from Q, with the torque-carrying
 * part of each pair force scaled when torque scaling is on. */
void SpamForceTensor(SpamSim *sim, const double *y, const double *qs);
/* Gauss's principle: adds -alpha (v - v_cm) + beta z x (r - r_cm) to the accelerations
 * so that the total L and E are constant; skipped (and counted) when singular. */
PetscErrorCode SpamGaussConstraint(SpamSim *sim, const double *y);
/* The elastic solid's right-hand side, diagnostics and set-up (the model's hooks). */
PetscErrorCode SpamRhsSolid(SpamSim *sim, const double *y, double *ydot, PetscInt *bad);
PetscErrorCode SpamDiagSolid(SpamSim *sim, const double *y, SpamModelDiag *d);
PetscErrorCode SpamSetUpSolid(SpamSim *sim);

/* Linearised SPAM on the perfect triangular lattice (spacing a, so number density
 * 2/(sqrt(3) a^2)) of an elastic solid at rest and free of stress, with Lucy's kernel of
 * range h: angular frequencies of the transverse and longitudinal plane waves of wave
 * vector k. Independent of R0/R1/R2 and of the density choice, which enter at second
 * order only when the initial stress vanishes. */
/* Closest-approach reflection (PRE Sec. IV): every pair closer than dmin that is still
 * approaching (v_ij.r_ij < 0) has the radial part of its relative velocity reversed,
 * v_i -= (v_ij.e) e, v_j += (v_ij.e) e (equal masses: momentum and kinetic energy are
 * kept). It changes the state y in place and returns the number of reflections. This is
 * a jump between steps, not a right-hand side: the driver must call it after each
 * accepted step and restart the integrator when it reflected (the solid model's
 * post_step with -closest_approach > 0). */
PetscErrorCode SpamClosestApproachReflect(SpamSim *sim, double *y, double dmin, PetscInt *nreflected);
/* The lattice sum G(k) = sum_l sin(k.l) (w'/r)(|l|) l of the linearised analyses. */
void SpamLatticeGradientSum(double h, double a, const double k[2], double G[2]);
void SpamDispersionLucy(double h, double a, double mass, double rho0, double lambda, double eta, const double k[2], double *omega_t, double *omega_l);
#endif
