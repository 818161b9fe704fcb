/* The tensor path (elastic solid, gas with the energy equation) and the spring model:
 * their right-hand sides, set-up and the scratch they keep beyond the field arrays of
 * fields.h (connected bodies, torque sums, spring bonds, Gauss's statistics). Every array
 * is allocated at set-up (SpamPhysicsScratchCreate), never inside the right-hand side. */
#ifndef SPAM_PHYSICS_H
#define SPAM_PHYSICS_H
#include <spam/sim.h>
#include <spam/gas_flow.h>

/* The spring bonds of a rank whose partner another rank holds (springs_bonds.c): the
 * partners' positions arrive through a PetscSF made by matching gids, made anew whenever
 * the local order changes (a migration). Empty on one rank. */
typedef struct {
  int          nremote;  /* remote partner slots                                    */
  PetscInt64  *gid;      /* [nremote] their gids, increasing                          */
  PetscSF      sf;       /* roots: the local particles; leaves: the remote slots      */
  MPI_Datatype unit;     /* dim doubles: one position                                  */
  double      *xlocal;   /* [n * dim] local positions packed for the exchange         */
  double      *xremote;  /* [nremote * dim] the remote partners' positions            */
  DM           carrier;  /* during a migration only: the bonds in transit              */
} SpamBondHalo;

typedef struct SpamPhysicsScratch {
  PetscInt n;
  int     *body, nbody;    /* connected body of each particle at set-up              */
  double  *bpos, *bneg, *bfac; /* [nbody] positive / negative torque sums, factor     */
  /* Spring bonds, CSR by local particle: a partner j < n is local (each local pair once,
   * the force added to both), j >= n the remote slot j - n of bond_halo (the bond is kept
   * by both ranks, each adding the force to its own particle only).                  */
  int     *bond_start, *bond_nbr;
  int      nbonds;
  SpamBondHalo bond_halo;
  /* Gauss's principle: evaluations found singular, and whether that was reported.     */
  long     gauss_singular;
  PetscBool gauss_reported;
  double   gauss_accel_max; /* largest |constraint acceleration| of any particle so far:  */
                            /* the scale of the round-off its sum adds to the momentum   */
  double   gauss_momentum_residual; /* largest |sum m a| of the constraint (round-off) */
} SpamPhysicsScratch;

/* Separation r_i - r_j (minimum image) of a listed local pair in 2D from the neighbour
 * list's box-local positions; returns r^2. */
static inline double SpamPairDelta2(const SpamNeighbours *nl, const SpamImage *im, int i, int j, double dx[2])
{
  dx[0] = SpamImageDelta(im, 0, nl->u[0][i] - nl->u[0][j]);
  dx[1] = nl->dim > 1 ? SpamImageDelta(im, 1, nl->u[1][i] - nl->u[1][j]) : 0.0; /* 1D: no u[1] */
  return dx[0] * dx[0] + dx[1] * dx[1];
}

/* The flow scheme of the gas (gas_flow.h, gas_flow.c), called by the tensor path. */
PetscErrorCode SpamGasFlowFit(SpamSim *sim, const double *y, SpamBackground *b);
void           SpamGasFlowShift(SpamSim *sim);
PetscErrorCode SpamGasFlowDivergence(SpamSim *sim);
PetscErrorCode SpamGasFlowShiftCompression(SpamSim *sim);
PetscBool      SpamGasFlowShiftWorks(const SpamSim *sim);
void           SpamGasFlowCorrect(SpamSim *sim, const double *y, const SpamBackground *b, PetscBool shiftwork);
void           SpamGasFlowTemperatureGradient(SpamSim *sim);

/* Allocates sim->ps for sim->p.n particles; it is freed with the swarm. */
PetscErrorCode SpamPhysicsScratchCreate(SpamSim *sim);
/* Labels the connected bodies: particles closer than range at the current positions y
 * share a body (union-find over the neighbour list, ghost pairs joining their sources). */
PetscErrorCode SpamBodiesLabel(SpamSim *sim, const double *y, double range);
/* Lz of every body about its own centre of mass (lbody[nbody]), and the bodies' part of
 * a model's diagnostics (count, Lz of bodies 0 and 1, Gauss's singular evaluations). */
PetscErrorCode SpamBodyAngularMomentum(SpamSim *sim, const double *y, double *lbody);
PetscErrorCode SpamBodiesDiag(SpamSim *sim, const double *y, SpamModelDiag *d);
/* Whether the model keeps spring bonds (set up by the springs model). */
static inline PetscBool SpamBondsAny(const SpamSim *sim)
{
  return (PetscBool)(sim->ps && sim->ps->bond_start);
}
/* Spring bonds through a migration (springs_bonds.c). Collective, both. Depart, before
 * the particles leave (gids and local order still the old ones): every bond, as one
 * record (holder gid, partner gid) per particle that keeps it, goes to the rank its
 * holder goes to (dest[i], by DMSwarmMigrate of a swarm of such records). Arrive, once
 * the arrived particles are in their new local order: the CSR rebuilt from the records,
 * and the PetscSF of the remote partners. */
PetscErrorCode SpamBondsDepart(SpamSim *sim, const PetscInt *dest);
PetscErrorCode SpamBondsArrive(SpamSim *sim);
/* Collective once distributed (nothing on one rank): the remote partners' positions into
 * bond_halo.xremote from the positions x (stride doubles per particle) of their owners. */
PetscErrorCode SpamBondsGather(SpamSim *sim, const double *x, int stride);
/* Frees what the bonds across ranks hold. */
PetscErrorCode SpamBondHaloDestroy(SpamBondHalo *bh);
/* Gauss's principle: adds -alpha (v - v_cm) + beta z x (r - r_cm) to the accelerations
 * so that the total L and E are constant; skipped (and counted) when singular. */
PetscErrorCode SpamGaussConstraint(SpamSim *sim, const double *y);
/* The tensor path's right-hand side (rhs_tensor.c), its unscaled spurious torque
 * sum_{i<j} L_ij (2D diagnostics), and the model's hooks (model_tensor.c). */
PetscErrorCode SpamRhsSolid(SpamSim *sim, const double *y, double *ydot, PetscInt *bad);
/* The same restricted to one part (model.h's SpamRhsPart): the gas's flow scheme with the
 * pair form of viscosity and conduction. */
PetscErrorCode SpamRhsSolidPart(SpamSim *sim, const double *y, double *ydot, SpamRhsPart part, PetscInt *bad);
/* What the diffusion part reads besides the list, for its Jacobian (diffusion_jacobian.c):
 * the fields of y (v, e, T, m, rho, gathered to the ghost slots, the list updated) and the
 * pair Laplacian's norms, as an evaluation of that part leaves them. */
PetscErrorCode SpamRhsSolidDiffusionFields(SpamSim *sim, const double *y, PetscInt *bad);
/* The same restricted to the active particles (model.h's SpamRhsActiveFn), for the cases
 * SpamRhsSolidActiveCovers admits (the plain inviscid or Monaghan gas with one h). */
PetscErrorCode SpamRhsSolidActive(SpamSim *sim, const double *y, double *ydot, const unsigned char *active, unsigned char *near, PetscBool *done, PetscInt *bad);
PetscBool      SpamRhsSolidActiveCovers(const SpamSolidParams *p);
PetscErrorCode SpamTensorTorqueSum(SpamSim *sim, const double *y, double *total);
PetscErrorCode SpamDiagSolid(SpamSim *sim, const double *y, SpamModelDiag *d);
PetscErrorCode SpamSetUpSolid(SpamSim *sim);
/* The adaptive kernel range (smoothing_adaptive.c): every local h_i, rho_i and Omega_i
 * from the current list; a particle whose solve does not converge stops the run. */
PetscErrorCode SpamSmoothingSolve(SpamSim *sim);
/* The evolved range: rho_i and Omega_i at the h_i of the state y (one pass, no solve;
 * h_i held within the bounds), on the current list (updated to y). */
PetscErrorCode SpamSmoothingAt(SpamSim *sim, const double *y);
/* The evolved range's start: h_i solved at y's positions into y's h. */
PetscErrorCode SpamSmoothingStart(SpamSim *sim, double *y);
/* The list as the last solve's passes walked it: a view of sim's list whose rows hold only
 * the pairs within reach of its h_i (or the whole list), every pair within max(h_i, h_j)
 * among them in the list's order. Valid until the next list update. */
void SpamSmoothingPairs(const SpamSim *sim, SpamNeighbours *near);
/* The next solve keeps its near rows anew (the list was put back to an earlier build). */
void SpamSmoothingNearReset(SpamFields *f);
/* The ideal gas's right-hand side at the adaptive range (rhs_gas_adaptive.c). */
PetscErrorCode SpamRhsGasAdaptive(SpamSim *sim, const double *y, double *ydot, PetscInt *bad);

/* Closest-approach reflection (PRE Sec. IV): every pair closer than dmin that is still
 * approaching (v_ij.r_ij < 0) has the radial part of its relative velocity reversed,
 * v_i -= (v_ij.e) e, v_j += (v_ij.e) e (equal masses: momentum and kinetic energy are
 * kept). It changes the state y in place and returns the number of reflections. This is
 * a jump between steps, not a right-hand side: the driver must call it after each
 * accepted step and restart the integrator when it reflected (the solid model's
 * post_step with -closest_approach > 0). */
PetscErrorCode SpamClosestApproachReflect(SpamSim *sim, double *y, double dmin, PetscInt *nreflected);
/* Linearised SPAM on the perfect triangular lattice (spacing a, so number density
 * 2/(sqrt(3) a^2)) of an elastic solid at rest and free of stress, with Lucy's kernel of
 * range h: angular frequencies of the transverse and longitudinal plane waves of wave
 * vector k. Independent of R0/R1/R2 and of the density choice, which enter at second
 * order only when the initial stress vanishes. The lattice sum
 * G(k) = sum_l sin(k.l) (w'/r)(|l|) l of the linearised analyses. */
void SpamLatticeGradientSum(double h, double a, const double k[2], double G[2]);
void SpamDispersionLucy(double h, double a, double mass, double rho0, double lambda, double eta, const double k[2], double *omega_t, double *omega_l);
#endif
