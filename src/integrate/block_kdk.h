/* Block (power-of-two) individual time steps (ts_block_kdk.c): the per-particle step
 * criterion and the neighbour walk behind it (block_bins.c). */
#ifndef SPAM_BLOCK_KDK_H
#define SPAM_BLOCK_KDK_H
#include <spam/sim.h>
#include <spam/run_record.h> /* SpamErrorNorm */

/* What chooses each particle's bin: the CFL and force criteria, or the local error
 * estimate against -ts_rtol, -ts_atol (block_error.c), bounded by the CFL criterion. */
typedef enum { SPAM_BLOCK_CRITERION_CFL, SPAM_BLOCK_CRITERION_ERROR } SpamBlockCriterion;

/* -block_cfl, -block_force, -block_max_level, -block_restricted, -block_wake_delay,
 * -block_criterion, -block_reject. */
typedef struct {
  SpamBlockCriterion criterion;
  double    reject; /* -block_reject: an estimate above it rejects the cycle (0: never) */
  double    cfl, force;
  PetscInt  max_level;
  PetscBool restricted; /* -block_restricted: forces of the active particles only */
  PetscBool wake_delay; /* -block_wake_delay: a wake off the needed bin's grid waits for its next tick */
} SpamBlockSettings;

/* A particle's bin may be at most this many levels longer than any neighbour's
 * (Saitoh and Makino 2009: a factor 4 in step). */
#define SPAM_BLOCK_LIMITER 2

/* What one walk of the neighbour list gives: each particle's signal speed
 * sig_i = max_j (c_i + c_j + 3 max(0, -v_ij . r_ij / |r_ij|)) over its neighbours (at
 * least c_i), and the deepest bin among its neighbours. Arrays over the list's slots
 * (local particles and their ghosts), grown at list builds only. */
typedef struct {
  int     cap;
  double *c, *vel, *sig;
  int    *lev, *nbmax;
  unsigned char *mark; /* the walk's mask over the slots */
  unsigned char *row;  /* [n] the rows of the list the masked walk reads */
  unsigned char *seen; /* [n] sig, nbmax (and c, vel, lev) were set by the last walk */
  double *send, *recv; /* [cap * (SPAM_BLOCK_SENT + dim)] what the halo carries: c, lev,
                        * mark and vel of each particle, to the remote ghost slots */
} SpamBlockWalk;

/* The values per particle the halo carries to the walk besides the velocity. */
#define SPAM_BLOCK_SENT 3

PetscErrorCode SpamBlockWalkDestroy(SpamBlockWalk *w);
/* Per particle from state y (whose positions the list was last updated to) and bins lev
 * (may be NULL: all level 0): w->sig[i] and w->nbmax[i] for i < n. With mask (one byte per
 * local particle; NULL: all) only the pairs with a marked member are walked: sig and
 * nbmax are whole for the marked particles; an unmarked one's nbmax is the deepest of its
 * own bin and its marked neighbours' (what the limiter needs after only those changed).
 * Without ghost slots a masked walk reads and sets only the marked particles and those
 * listed beside one (w->seen[i] set; the others' sig and nbmax are left as they were, and
 * their nbmax would be their own bin): the work is that of the marked particles' pairs.
 * On several ranks the other ranks' particles near this rank's (remote ghost slots) enter
 * through the halo (collective: every rank calls it together). Under -reproducible the
 * walk takes the canonical rows, each pair from its row's side: the same bits on any
 * rank count. */
PetscErrorCode SpamBlockNeighbours(SpamSim *sim, const double *y, const int *lev, const unsigned char *mask, SpamBlockWalk *w);
/* The step particle i wants: min(cfl h_i / sig_i, force sqrt(h_i / |a_i|)), a_i the
 * velocity rate in rate (one particle block); under -block_criterion error
 * min(cfl h_i / sig_i, controlled), the step its error controller asked for; infinity when
 * nothing bounds it. */
double SpamBlockWanted(const SpamSim *sim, const SpamBlockSettings *s, const SpamBlockWalk *w, PetscInt i, const double *rate, double controlled);

/* The error control (block_error.c): the tolerances and norm of the run, the velocity
 * scale of its weights (the initial sound speed, as ARKODE's). */
typedef struct {
  double        rtol, atol, vscale;
  SpamErrorNorm norm;
} SpamBlockErrorCtx;

/* The controller: a step's estimate err asks for dt SAFETY err^(-1/2), at most GROWTH
 * times dt (one bin up), at least SHRINK times dt (ARKODE's smallest cut after a failed
 * step). */
#define SPAM_BLOCK_SAFETY 0.9
#define SPAM_BLOCK_GROWTH 2.0
#define SPAM_BLOCK_SHRINK 0.1

/* The weighted norm of the difference between a particle's kick-drift-kick step of length
 * dt and the embedded first-order one (rates f at its start, g at its end; p its state at
 * the end; w scratch of nvar doubles). */
double SpamBlockError(const SpamSim *sim, const SpamBlockErrorCtx *e, const double *p, const double *f, const double *g, double dt, double *w);
/* The next step the controller asks for after a step dt with estimate err. */
double SpamBlockErrorStep(double dt, double err);
#endif
