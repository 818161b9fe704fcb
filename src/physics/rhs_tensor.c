/* Right-hand side of the tensor path (PRE Secs. I-II, VI-VIII): the elastic solid and the
 * gas with the energy equation, in one to three dimensions, in this order:
 *   fields from y (v, e, T; rho from the state or the density walk), gathered to ghosts
 *   walk 1 (gradients): grad v, R1/R2 coordinate averages, grad T
 *   particle laws: sigma/rho^2 (Hooke's stress in the state, or -P/rho^2 I of the gas),
 *     Newtonian and von Neumann viscosity, Hooke's stress rate, heat flux Q/rho^2
 *   walk 2 (2D torque scaling only): the pair torques and their scaling factors
 *   walk 3 (forces): pair force with Monaghan's viscosity, work, continuity, heat flux
 *     (or, in the flow scheme's pair form, viscosity and conduction as pair Laplacians)
 *   Gauss's constraint, gravity.
 * Each walk runs the pair functions of src/pair/ in one pass over the list. Accumulations
 * on ghost slots are folded onto their sources after each walk. Nothing here allocates
 * except when a list build adds ghosts beyond the slots reserved so far. */
#include <spam/physics.h>
#include <spam/stress.h>
#include <spam/wall_books.h>
#include <spam/gas_flow.h>
#include <spam/gas_images.h>
#include "../pair/pair_walk.h"
#include "../pair/pair_gradients.h"
#include "../pair/pair_coordinates.h"
#include "../pair/pair_stress_force.h"
#include "../pair/pair_heat_flux.h"
#include "../pair/pair_torque.h"
#include "../pair/pair_shift.h"
#include "../pair/pair_diffusion.h"

typedef struct {
  SpamFields            *f;
  const SpamSolidParams *p;
  double                 h;
  int                    coords;     /* SpamCoordsMode                                  */
  int                    conduction; /* heat flux in walk 3                            */
  int                    gradT;      /* grad T in walk 1 (conduction, the shift's drift) */
  int                    shift;      /* the transport shift's pair sum in walk 1       */
  int                    shift_own;  /* the shift's kernel is the walk's (model.h)     */
  double                 shift_gnorm, shift_hinv; /* else its gradient's scale and 1/h */
  int                    flow;       /* the flow scheme's corrections after walk 3     */
  int                    moment;     /* the gradient's moment in walk 1 (flow, pairdiff) */
  int                    pairdiff;   /* viscosity and conduction as pair Laplacians    */
  int                    diffuse;    /* ... added by this evaluation (SpamRhsPart)      */
  int                    heatlin;    /* the pair conduction's linear correction (-conduction_linear) */
  int                    nown;       /* this rank's particles: slots below are not ghosts */
  int                    scale;      /* torque scaling (Ti or Tij) in walk 3           */
  int                    continuity; /* drho/dt in walk 3 (the state's, or B's work)    */
  int                    shiftwork;  /* B's work on the shift's compression (walk 3's drho/dt) */
  SpamBackground         bg;         /* the flow scheme's background pressure         */
  const SpamPhysicsScratch *ps;      /* bodies and torque sums                          */
  double                 torque;     /* walk 2: sum of the unscaled pair torques        */
  int                    remote0;    /* first slot of other ranks' particles: a pair with */
                                     /* one is walked on both ranks, so each adds half    */
                                     /* (not a mirror image's: it pairs on this rank only) */
  const unsigned char   *rkind;      /* SpamGhostKind of slots remote0 ..                */
  const unsigned char   *gkind;      /* SpamGhostKind of the ghost slots nown ..         */
  int                    own_rho;    /* grad v over each particle's own density (PassOf) */
} TensorPass;

/* Walk 1: the gradients and averages that read v, T and rho. own (a literal) chooses the
 * velocity gradient over each particle's own density; the pair-mean form is a walk of its
 * own, so that its one factor g / rho_ij is one product per entry, not two. extras (a
 * literal) admits the gas flow scheme's sums (shift, moment): the solid's and the plain
 * gas's walk does not test for them at every pair. */
static inline __attribute__((always_inline)) void GradientPairOwn(const int dim, const int own, const int extras, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields  *f      = c->f;
  const double rho_ij = SpamPairMeanDensity(c->p->rho_geometric, f->rho[i], f->rho[j]);
  if (own) SpamPairVelocityGradient(dim, f, i, j, dx, g / f->rho[i], g / f->rho[j]);
  else SpamPairVelocityGradient(dim, f, i, j, dx, g / rho_ij, g / rho_ij);
  if (c->coords == SPAM_COORDS_R1) SpamPairAverageVelocity(dim, f, i, j, w);
  else if (c->coords == SPAM_COORDS_R2) SpamPairXsph(dim, f, i, j, c->p->xsph_eps * w / rho_ij);
  if (c->gradT) SpamPairTemperatureGradient(dim, f, i, j, dx, g / rho_ij);
  if (extras && c->shift) SpamPairShift(dim, f, i, j, dx, c->shift_own ? g : SpamKernelShapeScaledG(SPAM_KERNEL_WENDLAND_C2, dim, c->shift_gnorm, sqrt(r2) * c->shift_hinv));
  if (extras && c->moment) SpamPairGradientMoment(dim, f, i, j, dx, g / rho_ij);
}
static inline __attribute__((always_inline)) void GradientPairMean(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  GradientPairOwn(dim, 0, 0, c, i, j, dx, r2, w, g);
}
static inline __attribute__((always_inline)) void GradientPairExtras(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  GradientPairOwn(dim, 0, 1, c, i, j, dx, r2, w, g);
}
static inline __attribute__((always_inline)) void GradientPairOwnRho(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  GradientPairOwn(dim, 1, 1, c, i, j, dx, r2, w, g);
}
SPAM_PAIR_WALK(WalkGradients, TensorPass, GradientPairMean)
SPAM_PAIR_WALK(WalkGradientsExtras, TensorPass, GradientPairExtras)
SPAM_PAIR_WALK(WalkGradientsOwnRho, TensorPass, GradientPairOwnRho)

static inline __attribute__((always_inline)) int BodyOf(const TensorPass *c, int i)
{
  return c->p->per_body ? c->ps->body[i] : 0;
}

/* Walk 2 (2D): the pair torques of the unscaled stress force, summed per body (T_ij) or
 * per particle (T_i). */
static inline __attribute__((always_inline)) void TorquePair(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  double F[3];
  (void)r2;
  (void)w;
  SpamPairStressForce(dim, c->f, i, j, dx, g, F);
  const double L = SpamPairTorque(dx, F), share = j >= c->remote0 && c->rkind[j - c->remote0] == SPAM_GHOST_REMOTE ? 0.5 * L : L;
  c->torque += share;
  if (c->p->angmom == SPAM_ANGMOM_TIJ) {
    if (L > 0.0) c->ps->bpos[BodyOf(c, i)] += share;
    else c->ps->bneg[BodyOf(c, i)] += share;
  } else {
    c->f->ltorque[i] += 0.5 * L;
    c->f->ltorque[j] += 0.5 * L;
  }
}
SPAM_PAIR_WALK(WalkTorques, TensorPass, TorquePair)

/* The scaling factor of one pair's torque-carrying force. */
static inline __attribute__((always_inline)) double TorqueFactor(const TensorPass *c, int i, int j, double L)
{
  if (c->p->angmom == SPAM_ANGMOM_TIJ) {
    const double R = c->ps->bfac[BodyOf(c, i)];
    return L > 0.0 ? 1.0 / R : R;
  }
  return 0.5 * (c->f->tfac[i] + c->f->tfac[j]);
}

/* Whether slot j takes its own side of the pair conduction's linear correction: this
 * rank's particles and their periodic ghost slots (folded onto their sources), not a
 * mirror image (its side is the wall's). */
static inline __attribute__((always_inline)) int OwnSide(const TensorPass *c, int j)
{
  return j < c->nown || (j < c->remote0 && c->gkind[j - c->nown] == SPAM_GHOST_PERIODIC);
}

/* Walk 3: the pair force (scaled, with Monaghan's viscosity) and its work, the continuity
 * density rate and the heat flux. pairdiff (a literal) admits the pair Laplacians: the
 * walk without them does not test for them at every pair. */
static inline __attribute__((always_inline)) void ForcePairWith(const int dim, const int pairdiff, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields *f = c->f;
  double      F[3];
  (void)w;
  SpamPairStressForce(dim, f, i, j, dx, g, F);
  if (dim == 2 && c->scale) SpamPairScaleTorque(dx, r2, TorqueFactor(c, i, j, SpamPairTorque(dx, F)), F);
  if (c->p->viscosity == SPAM_VISCOSITY_MONAGHAN) {
    const double rho_ij = SpamPairMeanDensity(c->p->rho_geometric, f->rho[i], f->rho[j]);
    const double pi     = SpamPairMonaghan(dim, c->p->visc_alpha, c->p->visc_beta, c->p->sound_speed, c->h, dx, f->v + (size_t)i * dim, f->v + (size_t)j * dim, r2, rho_ij);
    for (int d = 0; d < dim; d++) F[d] -= f->m[i] * f->m[j] * pi * g * dx[d];
  }
  if (pairdiff && c->pairdiff) {
    if (c->diffuse) {
      const double k = SpamPairDiffusionFactor(f, i, j, g);
      SpamPairViscousDiffusion(dim, f, i, j, c->p->shear_visc, k, F);
      if (c->heatlin) SpamPairHeatDiffusionLinear(dim, f, i, j, c->p->conductivity, k, dx, OwnSide(c, j));
      else if (c->conduction) SpamPairHeatDiffusion(f, i, j, c->p->conductivity, k);
    }
  } else if (c->conduction) SpamPairHeatFlux(dim, f, i, j, dx, g);
  SpamPairApplyForce(dim, f, i, j, dx, g, F, c->continuity);
}
static inline __attribute__((always_inline)) void ForcePair(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  ForcePairWith(dim, 0, c, i, j, dx, r2, w, g);
}
static inline __attribute__((always_inline)) void ForcePairDiffusion(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  ForcePairWith(dim, 1, c, i, j, dx, r2, w, g);
}
SPAM_PAIR_WALK(WalkForces, TensorPass, ForcePair)
SPAM_PAIR_WALK(WalkForcesDiffusion, TensorPass, ForcePairDiffusion)

/* The diffusion part alone (SPAM_RHS_DIFFUSION): the moment that normalises the pair
 * Laplacian, then the Laplacians with the viscous force's work. */
static inline __attribute__((always_inline)) void MomentPair(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields *f = c->f;
  (void)r2;
  (void)w;
  SpamPairGradientMoment(dim, f, i, j, dx, g / SpamPairMeanDensity(c->p->rho_geometric, f->rho[i], f->rho[j]));
}
SPAM_PAIR_WALK(WalkMoments, TensorPass, MomentPair)

/* The moment and the SPAM grad T in one walk: the linear correction's corrected gradient
 * (-conduction_linear) reads both, and in the diffusion part nothing else computes grad T. */
static inline __attribute__((always_inline)) void MomentGradTPair(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields  *f  = c->f;
  const double gr = g / SpamPairMeanDensity(c->p->rho_geometric, f->rho[i], f->rho[j]);
  (void)r2;
  (void)w;
  SpamPairGradientMoment(dim, f, i, j, dx, gr);
  SpamPairTemperatureGradient(dim, f, i, j, dx, gr);
}
SPAM_PAIR_WALK(WalkMomentsGradT, TensorPass, MomentGradTPair)

static inline __attribute__((always_inline)) void DiffusionPair(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields  *f = c->f;
  const double k = SpamPairDiffusionFactor(f, i, j, g);
  double       F[3] = {0.0, 0.0, 0.0};
  (void)r2;
  (void)w;
  SpamPairViscousDiffusion(dim, f, i, j, c->p->shear_visc, k, F);
  if (c->heatlin) SpamPairHeatDiffusionLinear(dim, f, i, j, c->p->conductivity, k, dx, OwnSide(c, j));
  else if (c->conduction) SpamPairHeatDiffusion(f, i, j, c->p->conductivity, k);
  SpamPairApplyForce(dim, f, i, j, dx, g, F, 0);
}
SPAM_PAIR_WALK(WalkDiffusion, TensorPass, DiffusionPair)

static void Zero(double *a, size_t len)
{
  for (size_t k = 0; k < len; k++) a[k] = 0.0;
}

/* Per-particle fields of y for the local slots, then gathered into the ghosts: velocity,
 * energy and temperature, mass, and the density (summed, or the state's). */
static PetscErrorCode FillFields(SpamSim *sim, const double *y, PetscBool *reused, PetscInt *bad)
{
  const SpamLayout      *l   = &sim->model.layout;
  const SpamSolidParams *p   = &sim->model.solid;
  SpamFields            *f   = &sim->pair.f;
  const SpamGhosts      *gh  = &sim->pair.nl.ghosts;
  const int              dim = l->dim, n = (int)sim->p.n, nv = l->nvar;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, nv, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  PetscCall(SpamFieldsReserve(f, SpamNeighboursSlots(&sim->pair.nl)));
  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv;
    for (int d = 0; d < dim; d++) f->v[(size_t)i * dim + d] = yi[l->v + d];
  }
  PetscCall(SpamSimGhostMasses(sim));
  PetscCall(SpamGhostsGatherWall(gh, dim, n, SPAM_WALL_FIELD_VELOCITY, f->v));
  PetscCall(SpamGasImagesTemperatures(sim, y));
  if (p->density == SPAM_DENSITY_SUMMATION) {
    if (reused) SpamDiffusionCacheRestore(sim, reused); /* the diffusion part's kept densities */
    if (reused && *reused) PetscFunctionReturn(0);
    PetscCall(SpamDensityOfList(sim)); /* the list of the update above: one per evaluation */
    PetscFunctionReturn(0);
  }
  for (int i = 0; i < n; i++) {
    f->rho[i] = y[(size_t)i * nv + l->rho];
    if (!(f->rho[i] > 0.0) || !isfinite(f->rho[i])) {
      *bad = i;
      PetscFunctionReturn(0);
    }
  }
  PetscCall(SpamGhostsGather(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->rho));
  if (SpamGasImagesOfPlace(sim)) {
    SpamGasImagesMasses(sim);
    SpamGasImagesDensities(sim);
  }
  PetscFunctionReturn(0);
}

/* The pair Laplacian's normalisation N_i = -D / tr M_i of every local particle
 * (pair_diffusion.h), gathered into the ghosts; 1 where the moment vanishes (an isolated
 * particle, which has no pair to scale). */
static PetscErrorCode DiffusionNorms(SpamSim *sim)
{
  SpamFields *f   = &sim->pair.f;
  const int   dim = f->dim, n = (int)sim->p.n;

  PetscFunctionBeginUser;
  for (int i = 0; i < n; i++) {
    double tr = 0.0;
    for (int a = 0; a < dim; a++) tr += f->gmom[(size_t)i * dim * dim + a * dim + a];
    f->lapn[i] = tr < 0.0 ? -dim / tr : 1.0;
  }
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, dim, n, 1, SPAM_GHOST_SCALAR, f->lapn));
  PetscFunctionReturn(0);
}

/* Walk 1 and its folds: grad v, dr/dt (R0: v; R1: the normalised average with the self
 * term; R2: v plus XSPH) and grad T. */
static PetscErrorCode Gradients(SpamSim *sim, TensorPass *c)
{
  SpamFields       *f   = c->f;
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = f->dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);
  const double      w0  = sim->model.kernel.wnorm;

  PetscFunctionBeginUser;
  Zero(f->gradv, (size_t)slots * dim * dim);
  Zero(f->heat, (size_t)slots * dim);
  if (c->shift) {
    Zero(f->shift, (size_t)slots * dim);
    for (int i = 0; i < slots; i++) f->vol2[i] = (f->m[i] / f->rho[i]) * (f->m[i] / f->rho[i]); /* no division per pair */
  }
  if (c->moment) Zero(f->gmom, (size_t)slots * dim * dim);
  for (int i = 0; i < slots; i++) {
    const double self = c->coords == SPAM_COORDS_R1 ? (i < n ? w0 : 0.0) : (i < n ? 1.0 : 0.0);
    for (int d = 0; d < dim; d++) f->xdot[(size_t)i * dim + d] = self * f->v[(size_t)i * dim + d];
    f->wsum[i] = c->coords == SPAM_COORDS_R1 && i < n ? w0 : 0.0;
  }
  if (c->own_rho) PetscCall(WalkGradientsOwnRho(&sim->pair.nl, &sim->model.kernel, c));
  else if (c->shift || c->moment) PetscCall(WalkGradientsExtras(&sim->pair.nl, &sim->model.kernel, c));
  else PetscCall(WalkGradients(&sim->pair.nl, &sim->model.kernel, c));
  SpamGhostsFold(gh, dim, n, dim * dim, SPAM_GHOST_TENSOR, f->gradv);
  SpamGhostsFold(gh, dim, n, dim, SPAM_GHOST_VECTOR, f->xdot);
  SpamGhostsFold(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->wsum);
  SpamGhostsFold(gh, dim, n, dim, SPAM_GHOST_VECTOR, f->heat);
  if (c->shift) SpamGhostsFold(gh, dim, n, dim, SPAM_GHOST_VECTOR, f->shift);
  if (c->moment) SpamGhostsFold(gh, dim, n, dim * dim, SPAM_GHOST_TENSOR, f->gmom);
  if (c->diffuse) PetscCall(DiffusionNorms(sim));
  if (c->coords == SPAM_COORDS_R1)
    for (int i = 0; i < n; i++)
      for (int d = 0; d < dim; d++) f->xdot[(size_t)i * dim + d] /= f->wsum[i];
  if (c->shift) SpamGasFlowShift(sim);
  PetscFunctionReturn(0);
}

/* sigma/rho^2 of particle i into q (D x D): the state's stress (elastic) or -P/rho^2 I
 * with P = (gamma - 1) rho e (gas), plus the viscous stresses. */
static inline __attribute__((always_inline)) void StressOverRho2(const SpamSim *sim, const SpamBackground *bg, const double *yi, int i, double *q)
{
  const SpamLayout      *l   = &sim->model.layout;
  const SpamSolidParams *p   = &sim->model.solid;
  const SpamFields      *f   = &sim->pair.f;
  const int              dim = l->dim;
  const double           rho = f->rho[i], *g = f->gradv + (size_t)i * dim * dim;

  for (int k = 0; k < dim * dim; k++) q[k] = 0.0;
  if (p->material == SPAM_MATERIAL_GAS) {
    const double B = p->background != SPAM_BACKGROUND_NONE ? SpamBackgroundAt(bg, dim, yi + l->x) / (rho * rho) : 0.0;
    for (int a = 0; a < dim; a++) q[a * dim + a] = -(p->gamma - 1.0) * yi[l->e] / rho + B;
  }
  else {
    SpamStressUnpack(dim, yi + l->s, q);
    for (int k = 0; k < dim * dim; k++) q[k] /= rho * rho;
  }
  /* The pair form carries eta lap v; what the shear stress adds beyond it in 3D,
   * (1 - 2/D) eta grad div v, stays here with the bulk viscosity's grad div v. */
  if (p->diffusion == SPAM_DIFFUSION_PAIR) SpamNewtonianViscosity(dim, 0.0, p->bulk_visc + (1.0 - 2.0 / dim) * p->shear_visc, g, rho, q);
  else if (p->shear_visc > 0.0 || p->bulk_visc > 0.0) SpamNewtonianViscosity(dim, p->shear_visc, p->bulk_visc, g, rho, q);
  if (p->viscosity == SPAM_VISCOSITY_VON_NEUMANN) SpamVonNeumannViscosity(dim, p->visc_alpha, p->visc_beta, p->sound_speed, sim->model.kernel.h, g, rho, q);
}

/* The particle laws: Q, the stress rate (into ydot), the heat flux Q/rho^2 and the
 * velocity of the continuity equation; then gathered into the ghosts. */
static PetscErrorCode ParticleLaws(SpamSim *sim, const TensorPass *c, const double *y, double *ydot)
{
  const SpamLayout      *l   = &sim->model.layout;
  const SpamSolidParams *p   = &sim->model.solid;
  SpamFields            *f   = &sim->pair.f;
  const SpamGhosts      *gh  = &sim->pair.nl.ghosts;
  const int              dim = l->dim, n = (int)sim->p.n, nv = l->nvar;

  PetscFunctionBeginUser;
  for (int i = 0; i < n; i++) {
    const double *yi = y + (size_t)i * nv, *g = f->gradv + (size_t)i * dim * dim;
    StressOverRho2(sim, &c->bg, yi, i, f->qs + (size_t)i * dim * dim);
    if (p->material == SPAM_MATERIAL_ELASTIC) SpamHookeStressRate(dim, p->lambda, p->eta, g, yi + l->s, ydot + (size_t)i * nv + l->s);
    for (int d = 0; d < dim; d++) {
      if (!c->pairdiff) f->heat[(size_t)i * dim + d] *= -p->conductivity / (f->rho[i] * f->rho[i]);
      f->uc[(size_t)i * dim + d] = p->density == SPAM_DENSITY_CHAIN_RULE ? f->xdot[(size_t)i * dim + d] : f->v[(size_t)i * dim + d];
      if (c->shiftwork) f->uc[(size_t)i * dim + d] = f->shift[(size_t)i * dim + d];
    }
  }
  PetscCall(SpamGhostsGatherWall(gh, dim, n, SPAM_WALL_FIELD_STRESS, f->qs));
  if (gh->mirror && p->material == SPAM_MATERIAL_GAS && (sim->model.gravity_on || SpamGasImagesOfPlace(sim))) SpamGasImagesStresses(sim, &c->bg);
  if (!c->pairdiff) PetscCall(SpamGhostsGatherWall(gh, dim, n, SPAM_WALL_FIELD_HEAT_FLUX, f->heat));
  /* The shift's velocity of an image follows the walls' velocity rule (wall at rest), as
   * the images' v does in the gradient that B's work on div v reads: the two works then
   * measure v and dv alike, and where a wall particle is held (v = -dv) they cancel. With
   * the images' dv mirrored instead (their positions' motion: at a no-slip wall the same
   * tangential dv as the source's, where the rule reverses v's) the shift's tangential
   * compression of a wall row counted its images and the fluid's did not: a held wall
   * particle cooled or heated steadily, its pressure fell below its neighbours' and its
   * image pulled it further in; the wall rows of the 32 x 16 convection cell broke up
   * from 2.5 Ra_c (docs/gas-flow.md). */
  PetscCall(SpamGhostsGatherWall(gh, dim, n, c->shiftwork ? SPAM_WALL_FIELD_DRIFT : SPAM_WALL_FIELD_VELOCITY, f->uc));
  PetscFunctionReturn(0);
}

/* Walk 2: R per body from the positive and negative torque sums (1 where either is 0),
 * then T_i's particle factors. */
static PetscErrorCode TorqueFactors(SpamSim *sim, TensorPass *c)
{
  SpamPhysicsScratch *ps   = sim->ps;
  SpamFields         *f    = &sim->pair.f;
  const int           n    = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);
  const int           nb   = sim->model.solid.per_body ? ps->nbody : 1;
  const PetscBool     pair = (PetscBool)(sim->model.solid.angmom == SPAM_ANGMOM_TIJ);

  PetscFunctionBeginUser;
  for (int b = 0; b < ps->nbody; b++) ps->bpos[b] = ps->bneg[b] = 0.0;
  Zero(f->ltorque, (size_t)slots);
  c->torque = 0.0;
  PetscCall(WalkTorques(&sim->pair.nl, &sim->model.kernel, c));
  SpamGhostsFold(&sim->pair.nl.ghosts, 2, n, 1, SPAM_GHOST_SCALAR, f->ltorque);
  if (!pair)
    for (int i = 0; i < n; i++) {
      if (f->ltorque[i] > 0.0) ps->bpos[BodyOf(c, i)] += f->ltorque[i];
      else ps->bneg[BodyOf(c, i)] += f->ltorque[i];
    }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, ps->bpos, nb, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, ps->bneg, nb, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  for (int b = 0; b < nb; b++) ps->bfac[b] = (ps->bpos[b] > 0.0 && ps->bneg[b] < 0.0) ? sqrt(ps->bpos[b] / -ps->bneg[b]) : 1.0;
  if (!pair) {
    for (int i = 0; i < n; i++) {
      const double R = ps->bfac[BodyOf(c, i)];
      f->tfac[i]     = f->ltorque[i] > 0.0 ? 1.0 / R : R;
    }
    PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, 2, n, 1, SPAM_GHOST_SCALAR, f->tfac));
  }
  PetscFunctionReturn(0);
}

/* The rates a force or diffusion walk accumulates on particles and ghost slots, zeroed
 * before it (drho/dt only where the walk has one), and the ghosts' shares folded back onto
 * their owners after it. */
static void ZeroRates(SpamFields *f, int slots, int dim, PetscBool rho)
{
  Zero(f->acc, (size_t)slots * dim);
  Zero(f->edot, (size_t)slots);
  Zero(f->qdot, (size_t)slots);
  if (rho) Zero(f->rhodot, (size_t)slots);
}

static void FoldRates(const SpamGhosts *gh, SpamFields *f, int n, PetscBool rho)
{
  const int dim = f->dim;

  SpamGhostsFold(gh, dim, n, dim, SPAM_GHOST_VECTOR, f->acc);
  SpamGhostsFold(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->edot);
  SpamGhostsFold(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->qdot);
  if (rho) SpamGhostsFold(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->rhodot);
}

/* The linear correction's grad T (f->heat: the SPAM gradient, made exact for a linear T),
 * gathered so that a periodic ghost slot takes its source's for its own side of the
 * correction (accumulated in its slot and folded onto the source after the walk). */
static PetscErrorCode LinearGradient(SpamSim *sim, TensorPass *c)
{
  SpamFields *f   = c->f;
  const int   dim = f->dim;

  PetscFunctionBeginUser;
  SpamGasFlowTemperatureGradient(sim);
  PetscCall(SpamGhostsGather(&sim->pair.nl.ghosts, dim, (int)sim->p.n, dim, SPAM_GHOST_VECTOR, f->heat));
  Zero(f->qlin, (size_t)SpamNeighboursSlots(&sim->pair.nl));
  PetscFunctionReturn(0);
}

/* Walk 3 and its folds: accelerations, de/dt (work, then plus heat), drho/dt. The heat
 * rate stays apart on the ghost slots, where the walls' books read it. */
static PetscErrorCode Forces(SpamSim *sim, TensorPass *c, const double *y)
{
  SpamFields       *f   = c->f;
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = f->dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);

  PetscFunctionBeginUser;
  ZeroRates(f, slots, dim, PETSC_TRUE);
  if (c->heatlin) PetscCall(LinearGradient(sim, c));
  if (c->pairdiff) PetscCall(WalkForcesDiffusion(&sim->pair.nl, &sim->model.kernel, c));
  else PetscCall(WalkForces(&sim->pair.nl, &sim->model.kernel, c));
  FoldRates(gh, f, n, PETSC_TRUE);
  if (c->heatlin) SpamGhostsFold(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->qlin);
  for (int i = 0; i < n; i++) f->edot[i] += f->qdot[i];
  if (c->shiftwork) PetscCall(SpamGasFlowShiftCompression(sim));
  if (c->flow) SpamGasFlowCorrect(sim, y, &c->bg, (PetscBool)c->shiftwork);
  if (c->heatlin) /* the correction's heat, not conserved pair by pair, goes into the book */
    for (int i = 0; i < n; i++) {
      f->edot[i] += f->qlin[i];
      f->edrift[i] += f->qlin[i];
    }
  PetscFunctionReturn(0);
}

static void Assemble(const SpamSim *sim, double *ydot)
{
  const SpamLayout *l   = &sim->model.layout;
  const SpamFields *f   = &sim->pair.f;
  const int         dim = l->dim;

  for (PetscInt i = 0; i < sim->p.n; i++) {
    double *r = ydot + (size_t)i * l->nvar;
    for (int d = 0; d < dim; d++) {
      r[l->x + d] = f->xdot[(size_t)i * dim + d];
      r[l->v + d] = f->acc[(size_t)i * dim + d] + sim->model.gravity[d];
    }
    r[l->e] = f->edot[i];
    if (l->rho >= 0) r[l->rho] = f->rhodot[i];
    if (l->fb >= 0) r[l->fb] = f->edrift[i]; /* the flow scheme's power per unit mass */
  }
}

/* An elastic solid with summed density takes its velocity gradient over the particle's own
 * density, (grad v)_i = sum_j m_j (v_j - v_i) grad_i w_ij / rho_i: the stress power of that
 * gradient, sum_i (m_i / rho_i) sigma_i : (grad v)_i, is exactly the work of the pair forces
 * that de/dt books, so the energy Hooke's rate stores in the stress is the internal energy
 * of the books. Over the pair mean rho_ij the two part wherever a summed density differs
 * from its neighbours' (at the rotor's free surface rho_i is about 0.55 of the interior's):
 * there Hooke's rate stores energy that no force spent, and the forces of that stress hand
 * it to the motion while e goes negative (rotor, R2 + T_ij, one revolution: KE/KE0 = 2.35,
 * sum m e = -0.69, stress energy 2.5). Continuity densities stay near rho0, where the two
 * forms differ little, and keep CiSE Eq. 18's rho_ij; so do the gas's viscous stresses,
 * which store nothing. */
static TensorPass PassOf(SpamSim *sim, SpamRhsPart part)
{
  const SpamSolidParams *p    = &sim->model.solid;
  const int              gas  = p->material == SPAM_MATERIAL_GAS && p->scheme == SPAM_GAS_FLOW;
  const int              bg   = gas && p->background != SPAM_BACKGROUND_NONE, shift = gas && p->shift_coef > 0.0;
  TensorPass             c    = {0};
  c.f                         = &sim->pair.f;
  c.p                         = p;
  c.h                         = sim->model.kernel.h;
  c.coords                    = (int)p->coords;
  c.conduction                = p->conductivity > 0.0;
  c.pairdiff                  = p->material == SPAM_MATERIAL_GAS && p->diffusion == SPAM_DIFFUSION_PAIR;
  c.diffuse                   = c.pairdiff && part != SPAM_RHS_EXPLICIT;
  c.gradT                     = (c.conduction && !c.pairdiff) || shift; /* the pair form reads T, not its gradient */
  c.shift                     = shift;
  c.shift_own                 = sim->model.shift_kernel.kind == sim->model.kernel.kind;
  c.shift_gnorm               = sim->model.shift_kernel.gnorm;
  c.shift_hinv                = sim->model.shift_kernel.hinv;
  c.flow                      = bg || shift;
  c.moment                    = c.flow || c.diffuse;
  c.heatlin                   = c.diffuse && c.conduction && c.flow && p->heat_linear;
  c.gradT                     = c.gradT || c.heatlin;
  c.nown                      = (int)sim->p.n;
  c.scale                     = p->angmom == SPAM_ANGMOM_TI || p->angmom == SPAM_ANGMOM_TIJ;
  c.shiftwork                 = bg && shift && SpamGasFlowShiftWorks(sim);
  c.continuity                = p->density != SPAM_DENSITY_SUMMATION || c.shiftwork; /* the shift's drho/dt */
  c.ps                        = sim->ps;
  c.remote0                   = (int)sim->p.n + sim->pair.nl.ghosts.nlocal;
  c.rkind                     = sim->pair.nl.ghosts.kind ? sim->pair.nl.ghosts.kind + sim->pair.nl.ghosts.nlocal : NULL;
  c.gkind                     = sim->pair.nl.ghosts.kind;
  c.own_rho                   = p->material == SPAM_MATERIAL_ELASTIC && p->density == SPAM_DENSITY_SUMMATION;
  return c;
}

/* The moment that normalises the pair Laplacian, and the norms N_i from it; with the
 * linear correction also the SPAM grad T (f->heat), folded as walk 1 folds it. */
static PetscErrorCode DiffusionMoments(SpamSim *sim, TensorPass *c)
{
  SpamFields       *f   = c->f;
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = f->dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);

  PetscFunctionBeginUser;
  Zero(f->gmom, (size_t)slots * dim * dim);
  if (c->heatlin) {
    Zero(f->heat, (size_t)slots * dim);
    PetscCall(WalkMomentsGradT(&sim->pair.nl, &sim->model.kernel, c));
    SpamGhostsFold(gh, dim, n, dim, SPAM_GHOST_VECTOR, f->heat);
  } else PetscCall(WalkMoments(&sim->pair.nl, &sim->model.kernel, c));
  SpamGhostsFold(gh, dim, n, dim * dim, SPAM_GHOST_TENSOR, f->gmom);
  PetscCall(DiffusionNorms(sim));
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsSolidDiffusionFields(SpamSim *sim, const double *y, PetscInt *bad)
{
  TensorPass c;

  PetscFunctionBeginUser;
  PetscCall(FillFields(sim, y, NULL, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  c         = PassOf(sim, SPAM_RHS_DIFFUSION);
  c.heatlin = 0; /* the Jacobian reads the moment, not grad T (diffusion_jacobian.c) */
  PetscCall(DiffusionMoments(sim, &c));
  PetscFunctionReturn(0);
}

/* The diffusion part (SPAM_RHS_DIFFUSION): the rates of the pair Laplacians alone, on the
 * fields FillFields left; positions and densities take none, nor does the flow scheme's
 * book (its laws are in the other part). The walls' books take this part's exchanges:
 * the books are linear in the accumulations, so the two parts' books sum to the whole's. */
static PetscErrorCode Diffusion(SpamSim *sim, TensorPass *c, PetscBool keep, PetscBool reused, double *ydot)
{
  const SpamLayout *l   = &sim->model.layout;
  SpamFields       *f   = c->f;
  const SpamGhosts *gh  = &sim->pair.nl.ghosts;
  const int         dim = f->dim, n = (int)sim->p.n, slots = SpamNeighboursSlots(&sim->pair.nl);

  PetscFunctionBeginUser;
  if (!reused) PetscCall(DiffusionMoments(sim, c));
  if (keep && !reused) PetscCall(SpamDiffusionCacheKeep(sim));
  ZeroRates(f, slots, dim, PETSC_FALSE);
  if (c->heatlin) PetscCall(LinearGradient(sim, c));
  PetscCall(WalkDiffusion(&sim->pair.nl, &sim->model.kernel, c));
  FoldRates(gh, f, n, PETSC_FALSE);
  if (c->heatlin) SpamGhostsFold(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->qlin);
  for (int i = 0; i < n; i++) {
    double      *r   = ydot + (size_t)i * l->nvar;
    const double lin = c->heatlin ? f->qlin[i] : 0.0;
    for (int d = 0; d < dim; d++) {
      r[l->x + d] = 0.0;
      r[l->v + d] = f->acc[(size_t)i * dim + d];
    }
    r[l->e] = f->edot[i] + f->qdot[i] + lin;
    if (l->rho >= 0) r[l->rho] = 0.0;
    if (l->fb >= 0) r[l->fb] = lin; /* the correction's heat, booked as the whole RHS books it */
  }
  if (gh->mirror) PetscCall(SpamWallBooks(gh, f, l, n, PETSC_TRUE, &sim->out.wall_rates, ydot));
  sim->run.stats.pair_visits += 2.0 * (double)(sim->pair.nl.npairs + sim->pair.nl.ngpairs);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsSolidPart(SpamSim *sim, const double *y, double *ydot, SpamRhsPart part, PetscInt *bad)
{
  TensorPass c;
  PetscBool  keep = PETSC_FALSE, reused = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (part == SPAM_RHS_DIFFUSION) keep = SpamDiffusionCacheApplies(sim, (PetscBool)PassOf(sim, part).heatlin);
  PetscCall(FillFields(sim, y, keep ? &reused : NULL, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  c = PassOf(sim, part);
  if (part == SPAM_RHS_DIFFUSION) {
    PetscCall(PetscLogEventBegin(sim->run.ev.force, 0, 0, 0, 0));
    PetscCall(Diffusion(sim, &c, keep, reused, ydot));
    PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
    PetscFunctionReturn(0);
  }
  if (c.flow) PetscCall(SpamGasFlowFit(sim, y, &c.bg));
  PetscCall(PetscLogEventBegin(sim->run.ev.force, 0, 0, 0, 0));
  PetscCall(Gradients(sim, &c));
  if (c.flow && sim->model.solid.background != SPAM_BACKGROUND_NONE) PetscCall(SpamGasFlowDivergence(sim));
  PetscCall(ParticleLaws(sim, &c, y, ydot));
  if (c.scale) PetscCall(TorqueFactors(sim, &c));
  PetscCall(Forces(sim, &c, y));
  PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
  if (sim->model.solid.angmom == SPAM_ANGMOM_GAUSS) PetscCall(SpamGaussConstraint(sim, y));
  Assemble(sim, ydot);
  if (sim->pair.nl.ghosts.mirror) PetscCall(SpamWallBooks(&sim->pair.nl.ghosts, &sim->pair.f, &sim->model.layout, (int)sim->p.n, PETSC_TRUE, &sim->out.wall_rates, ydot));
  sim->run.stats.pair_visits += (2.0 + (c.scale ? 1.0 : 0.0)) * (double)(sim->pair.nl.npairs + sim->pair.nl.ngpairs);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsSolid(SpamSim *sim, const double *y, double *ydot, PetscInt *bad)
{
  PetscFunctionBeginUser;
  PetscCall(SpamRhsSolidPart(sim, y, ydot, SPAM_RHS_ALL, bad));
  PetscFunctionReturn(0);
}

/* The pass restricted to the active particles (block steps, ts_block_kdk.c): the rates of
 * the marked particles, each the full pass's sum over the same pairs in the same order.
 * What a force on an active particle reads: the stress sigma/rho^2 and the density of its
 * neighbours, so the densities are summed for the active particles and every particle
 * listed beside one ("near"; the list's skin makes this a superset), the laws evaluated
 * there, and the force walk visits the pairs with an active member. It covers the gas
 * whose laws read no gradient: the plain scheme with one h, no conduction and no viscous
 * stress (Monaghan's pair viscosity or none), R0 coordinates, no torque scaling; others
 * return without it (SpamRhsSolidActiveCovers), and so does a state with ghost slots of a
 * rank's own (walls, periodic images). On several ranks the other ranks' particles enter
 * as remote ghost slots: their active marks through the halo (RemoteMarks), a particle
 * near another rank's active one summed by its owner, whose near fields (rho, v, sigma/rho^2,
 * uc) the halo then carries to the slots the force walk reads. */
PetscBool SpamRhsSolidActiveCovers(const SpamSolidParams *p)
{
  return (PetscBool)(p->material == SPAM_MATERIAL_GAS && p->smoothing == SPAM_SMOOTHING_FIXED && p->scheme == SPAM_GAS_PLAIN && p->conductivity == 0.0 && p->shear_visc == 0.0 && p->bulk_visc == 0.0 && p->viscosity != SPAM_VISCOSITY_VON_NEUMANN &&
                     p->coords == SPAM_COORDS_R0 && p->angmom == SPAM_ANGMOM_NONE);
}

static inline __attribute__((always_inline)) void DensityPair(const int dim, TensorPass *c, int i, int j, const double dx[3], double r2, double w, double g)
{
  SpamFields *f = c->f;
  (void)dim;
  (void)dx;
  (void)r2;
  (void)g;
  f->rho[i] += f->m[j] * w;
  f->rho[j] += f->m[i] * w;
}
SPAM_PAIR_WALK_MASKED(WalkDensityNear, TensorPass, DensityPair)
SPAM_PAIR_WALK_MASKED(WalkForcesActive, TensorPass, ForcePair)

/* The fields the active particles' forces read, at the near particles: velocity, density
 * (summed, or the state's), sigma/rho^2 and the continuity velocity. The other particles'
 * densities are partial sums, read by nothing. */
static PetscErrorCode NearFields(SpamSim *sim, TensorPass *c, const double *y, const unsigned char *near, unsigned char *row, PetscBool remote, PetscInt *bad)
{
  const SpamLayout *l   = &sim->model.layout;
  SpamFields       *f   = c->f;
  const int         dim = l->dim, n = (int)sim->p.n, nv = l->nvar;
  const double      w0  = sim->model.kernel.wnorm;

  PetscFunctionBeginUser;
  for (int i = 0; i < n; i++) {
    if (!near[i]) continue;
    for (int d = 0; d < dim; d++) f->v[(size_t)i * dim + d] = y[(size_t)i * nv + l->v + d];
  }
  if (c->p->density == SPAM_DENSITY_SUMMATION) {
    for (int i = 0; i < n; i++) f->rho[i] = f->m[i] * w0;
    PetscCall(SpamNeighboursMarkedRows(&sim->pair.nl, near, row));
    if (remote) /* a near particle's pairs with other ranks' particles sit in its own row */
      for (int i = 0; i < n; i++) row[i] |= near[i];
    PetscCall(WalkDensityNear(&sim->pair.nl, &sim->model.kernel, near, row, c));
  } else
    for (int i = 0; i < n; i++) {
      if (!near[i]) continue;
      f->rho[i] = y[(size_t)i * nv + l->rho];
      if (!(f->rho[i] > 0.0) || !isfinite(f->rho[i])) {
        *bad = i;
        PetscFunctionReturn(0);
      }
    }
  for (int i = 0; i < n; i++) {
    if (!near[i]) continue;
    StressOverRho2(sim, &c->bg, y + (size_t)i * nv, i, f->qs + (size_t)i * dim * dim);
    for (int d = 0; d < dim; d++) f->uc[(size_t)i * dim + d] = f->v[(size_t)i * dim + d];
  }
  PetscFunctionReturn(0);
}

/* Several ranks: the marks over the slots (f->amark: active, then near, mcap apart). The
 * active marks of the other ranks' particles arrive through the halo; a local particle is
 * near when an active one is listed beside it, another rank's included (its ghost row);
 * the near marks of remote slots stay 0 (their owners sum their densities). Collective. */
static PetscErrorCode RemoteMarks(SpamSim *sim, const unsigned char *active, unsigned char *near)
{
  const SpamNeighbours *nl = &sim->pair.nl;
  SpamFields           *f  = &sim->pair.f;
  const int             n  = (int)sim->p.n, slots = SpamNeighboursSlots(nl);
  unsigned char        *act, *nm;

  PetscFunctionBeginUser;
  PetscCall(SpamFieldsReserveMarks(f, slots));
  act = f->amark;
  nm  = f->amark + f->mcap;
  for (int i = 0; i < n; i++) f->mbuf[i] = active[i];
  PetscCall(SpamHaloForward(&nl->ghosts.halo, 1, f->mbuf, f->mbuf + n)); /* no local ghosts: the remote slots start at n */
  for (int i = 0; i < n; i++) act[i] = active[i];
  for (int j = n; j < slots; j++) act[j] = f->mbuf[j] != 0.0;
  PetscCall(SpamNeighboursMarkedNear(&sim->pair.nl, active, near));
  for (int i = 0; i < n; i++)
    for (int p = nl->gstart[i]; p < nl->gstart[i + 1] && !near[i]; p++) near[i] = act[nl->gnbr[p]];
  for (int i = 0; i < n; i++) nm[i] = near[i];
  for (int j = n; j < slots; j++) nm[j] = 0;
  PetscFunctionReturn(0);
}

/* The rows of the force walk: those the transposed list names, and on several ranks also
 * those with an active partner of another rank (act: the marks over the slots). */
static PetscErrorCode ActiveRows(SpamSim *sim, const unsigned char *active, const unsigned char *act, PetscBool remote, unsigned char *row)
{
  const SpamNeighbours *nl = &sim->pair.nl;

  PetscFunctionBeginUser;
  PetscCall(SpamNeighboursMarkedRows(&sim->pair.nl, active, row));
  if (remote)
    for (int i = 0; i < nl->n; i++)
      for (int p = nl->gstart[i]; p < nl->gstart[i + 1] && !row[i]; p++) row[i] = act[nl->gnbr[p]];
  PetscFunctionReturn(0);
}

PetscErrorCode SpamRhsSolidActive(SpamSim *sim, const double *y, double *ydot, const unsigned char *active, unsigned char *near, PetscBool *done, PetscInt *bad)
{
  const SpamLayout *l      = &sim->model.layout;
  SpamFields       *f      = &sim->pair.f;
  const SpamGhosts *gh     = &sim->pair.nl.ghosts;
  const int         dim    = l->dim, n = (int)sim->p.n, nv = l->nvar;
  const PetscBool   remote = SpamHaloActive(&gh->halo);
  const unsigned char *act = active, *nmask = near;
  PetscBool         images;
  TensorPass        c;

  PetscFunctionBeginUser;
  *done = PETSC_FALSE;
  *bad  = -1;
  if (!SpamRhsSolidActiveCovers(&sim->model.solid)) PetscFunctionReturn(0);
  PetscCall(SpamNeighboursUpdate(&sim->pair.nl, &sim->geo.box, y + l->x, nv, PETSC_FALSE, bad));
  if (*bad >= 0) PetscFunctionReturn(0);
  /* a rank's own ghost slots (walls, periodic images) take the full pass, on every rank */
  images = (PetscBool)(gh->nlocal > 0 || (!remote && SpamNeighboursSlots(&sim->pair.nl) != n));
  if (remote) PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &images, 1, MPIU_BOOL, MPI_LOR, sim->p.comm));
  if (images) PetscFunctionReturn(0);
  PetscCall(SpamFieldsReserve(f, SpamNeighboursSlots(&sim->pair.nl)));
  c = PassOf(sim, SPAM_RHS_ALL);
  if (remote) {
    PetscCall(RemoteMarks(sim, active, near));
    act   = f->amark;
    nmask = f->amark + f->mcap;
    PetscCall(SpamSimGhostMasses(sim));
  } else PetscCall(SpamNeighboursMarkedNear(&sim->pair.nl, active, near));
  PetscCall(PetscLogEventBegin(sim->run.ev.force, 0, 0, 0, 0));
  PetscCall(NearFields(sim, &c, y, nmask, near + n, remote, bad));
  if (remote) { /* a bad density on one rank stops every rank before the exchanges below */
    PetscInt worst = *bad >= 0 ? 1 : 0;
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &worst, 1, MPIU_INT, MPI_MAX, sim->p.comm));
    if (worst && *bad < 0) *bad = SPAM_BAD_ON_OTHER_RANK;
  }
  if (*bad >= 0) {
    PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
    PetscFunctionReturn(0);
  }
  if (remote) { /* the near particles' fields to the other ranks' slots of them */
    PetscCall(SpamGhostsGather(gh, dim, n, 1, SPAM_GHOST_SCALAR, f->rho));
    PetscCall(SpamGhostsGatherWall(gh, dim, n, SPAM_WALL_FIELD_VELOCITY, f->v));
    PetscCall(SpamGhostsGatherWall(gh, dim, n, SPAM_WALL_FIELD_STRESS, f->qs));
    PetscCall(SpamGhostsGatherWall(gh, dim, n, SPAM_WALL_FIELD_VELOCITY, f->uc));
  }
  ZeroRates(f, n, dim, PETSC_TRUE);
  PetscCall(ActiveRows(sim, active, act, remote, near + n));
  PetscCall(WalkForcesActive(&sim->pair.nl, &sim->model.kernel, act, near + n, &c));
  PetscCall(PetscLogEventEnd(sim->run.ev.force, 0, 0, 0, 0));
  for (int i = 0; i < n; i++) { /* Assemble's rows, of the active particles only */
    double *r = ydot + (size_t)i * nv;
    if (!active[i]) continue;
    for (int d = 0; d < dim; d++) {
      r[l->x + d] = f->v[(size_t)i * dim + d];
      r[l->v + d] = f->acc[(size_t)i * dim + d] + sim->model.gravity[d];
    }
    r[l->e] = f->edot[i] + f->qdot[i];
    if (l->rho >= 0) r[l->rho] = f->rhodot[i];
  }
  *done = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* The unscaled spurious torque sum_{i<j} L_ij of the state's stress (2D diagnostics). */
PetscErrorCode SpamTensorTorqueSum(SpamSim *sim, const double *y, double *total)
{
  TensorPass c;
  PetscInt   bad;
  double    *scratch;

  PetscFunctionBeginUser;
  *total = NAN;
  PetscCall(FillFields(sim, y, NULL, &bad));
  if (bad >= 0 || sim->model.dim != 2) PetscFunctionReturn(0);
  c = PassOf(sim, SPAM_RHS_ALL);
  if (c.flow) PetscCall(SpamGasFlowFit(sim, y, &c.bg));
  PetscCall(PetscMalloc1((size_t)sim->p.n * sim->model.layout.nvar + 1, &scratch)); /* the stress rate, unused */
  PetscCall(Gradients(sim, &c));
  PetscCall(ParticleLaws(sim, &c, y, scratch));
  PetscCall(PetscFree(scratch));
  for (int b = 0; b < sim->ps->nbody; b++) sim->ps->bpos[b] = sim->ps->bneg[b] = 0.0;
  Zero(sim->pair.f.ltorque, (size_t)SpamNeighboursSlots(&sim->pair.nl));
  c.torque = 0.0;
  PetscCall(WalkTorques(&sim->pair.nl, &sim->model.kernel, &c));
  PetscCallMPI(MPIU_Allreduce(&c.torque, total, 1, MPI_DOUBLE, MPI_SUM, sim->p.comm));
  PetscFunctionReturn(0);
}
