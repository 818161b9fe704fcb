/* Per-particle field arrays of the pair passes, with ghost slots: every array holds the
 * n local particles first and then the ghosts (ghosts.h), so a pair function indexes
 * i and j alike. The model fills them from the state y before a pass (positions live in
 * the neighbour list's u), gathers them into the ghost slots, and folds what the passes
 * accumulated on ghosts back onto their sources. Only the arrays a model uses are
 * allocated (NULL otherwise). */
#ifndef SPAM_FIELDS_H
#define SPAM_FIELDS_H
#include <petscsys.h>

typedef struct {
  int     dim, n, cap;     /* local particles; slots allocated (local + ghost)         */
  double *m, *minv;        /* [cap] mass and its inverse (pair updates multiply by it;  */
                           /* the tensor path's and the springs': NULL for the gas)    */
  double *v;               /* [cap*dim] velocity                                        */
  double *rho;             /* [cap] density: summed, or the state's (continuity)       */
  double *q;               /* [cap] P/rho^2 (isentropic gas)                            */
  double *e, *T;           /* [cap] energy per unit mass, temperature                  */
  double *qs;              /* [cap*dim*dim] sigma/rho^2 (full symmetric tensor)        */
  double *gradv;           /* [cap*dim*dim] (grad v)^{ab} = dv^b/dx^a at a*dim + b     */
  double *heat;            /* [cap*dim] grad T, then Q/rho^2                           */
  double *xdot;            /* [cap*dim] dr/dt                                           */
  double *shift;           /* [cap*dim] the transport shift's pair sum, then its velocity (gas_flow.h) */
  double *gmom;            /* [cap*dim*dim] sum_j m_j g dx dx^T / rho_ij, the gradient's moment (gas_flow.h) */
  double *vol2;            /* [cap] (m / rho)^2 of every slot, for the shift's pair sum  */
  double *divv;            /* [cap] corrected div v less its volume mean (gas_flow.h)   */
  double *lapn;            /* [cap] the pair Laplacian's normalisation -D / tr M (pair_diffusion.h) */
  double *edrift;          /* [cap] de/dt of the shift's drift, dv . grad e (gas_flow.h) */
  double *uc;              /* [cap*dim] velocity of the continuity equation            */
  double *acc;             /* [cap*dim] acceleration                                    */
  double *edot, *rhodot;   /* [cap] de/dt (work), drho/dt                               */
  double *qdot;            /* [cap] de/dt by heat conduction (kept apart for the walls' books) */
  double *qlin;            /* [cap] de/dt of the pair conduction's linear correction (pair_diffusion.h) */
  double *wsum;            /* [cap] sum_j w_ij (R1's normalisation)                    */
  double *ltorque, *tfac;  /* [cap] particle torque and its scaling factor (T_i)       */
  /* The adaptive kernel range (smoothing_adaptive.c), each [cap]: h_i and the kernel's
   * scales at it (1/h_i, w(0) = wnorm (h/h_i)^D, gnorm (h/h_i)^(D+2)), the grad-h factor
   * Omega_i, d rho_i/d h_i, the bracket of the h solve and whether h_i is settled (1) or
   * still moving (0) in it. */
  double *h, *hinv, *wn, *gn, *omega, *drho, *hlo, *hhi, *settled;
  /* The near rows, the pairs the h solve and the force pass walk: the list's pairs closer
   * than max(hcap_i, hcap_j) + the list's skin at the positions xnear ([cap*dim]) where
   * they were kept, hcap_i ([cap]) a reach above the h_i of that solve, as CSR rows in
   * the list's order (near_start [cap+1], near_nbr [near_cap]). They serve while the list
   * is the one of build near_builds, no particle moved half the skin from xnear and no h_i
   * passed its reach; near_valid 0 has the next solve keep them anew; near_wide when an
   * h_i went beyond its reach in this solve (its walks then take the whole list). */
  double *hcap, *xnear;
  int    *near_start, *near_nbr;
  size_t  near_cap;
  int     near_wide, near_valid;
  long    near_builds;
  /* Scratch of the pass restricted to the active particles on several ranks
   * (rhs_tensor.c): two byte masks over the slots (active, near) and a value per slot
   * for the halo's exchange of the marks, [mcap] each, grown with the slots. */
  unsigned char *amark;
  double        *mbuf;
  int            mcap;
  PetscBool tensor;        /* the tensor-path arrays are allocated                     */
  int       uniform_mass;  /* every particle has mass m[0] (set at set-up)             */
  int       adaptive;      /* the adaptive range's arrays are allocated               */
  int       inverse_mass;  /* minv is allocated                                       */
} SpamFields;

/* Allocates the arrays for n local particles and at least cap slots: m, rho, q and acc
 * always, the tensor path's (and minv) when tensor is set. */
PetscErrorCode SpamFieldsCreate(int dim, int n, int cap, PetscBool tensor, SpamFields *f);
/* minv for a model outside the tensor path whose pair updates divide by the mass
 * (springs), filled from m. */
PetscErrorCode SpamFieldsAddInverseMass(SpamFields *f);
/* Room for `slots` (local + ghost) in every allocated array, keeping the values of the
 * local ones; called after a list build added ghosts (rare: not in the steady state). */
PetscErrorCode SpamFieldsReserve(SpamFields *f, int slots);
PetscErrorCode SpamFieldsDestroy(SpamFields *f);
/* Room for slots in the restricted pass's masks (amark: 2 * mcap bytes, mbuf: mcap values). */
PetscErrorCode SpamFieldsReserveMarks(SpamFields *f, int slots);
/* Allocates the adaptive range's arrays (h, ..., hhi) at the current capacity; Reserve
 * grows them with the others. */
PetscErrorCode SpamFieldsAddSmoothing(SpamFields *f);
/* The local masses: m[i] (or `uniform` for every particle when m is NULL), their
 * inverses, and whether they are all equal. */
void SpamFieldsSetMasses(SpamFields *f, const double *m, double uniform);
/* Whether every particle has the same mass (the gas passes then fold m into a constant). */
PetscBool SpamFieldsUniformMass(const SpamFields *f);
#endif
