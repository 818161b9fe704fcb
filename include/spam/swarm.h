/* The particles as the core layers know them: a DMSwarm whose one packed field is the
 * state vector, each particle named by its gid, and what a move of particles between
 * ranks (decompose.h) needs to know of the state and of its owner. No law of motion. */
#ifndef SPAM_SWARM_H
#define SPAM_SWARM_H
#include <petscdmswarm.h>

#define SPAM_STATE_FIELD "spam_state"
/* The particle's identity: its input row (file line, lattice site) over all ranks. */
#define SPAM_GID_FIELD "spam_gid"

typedef struct {
  MPI_Comm    comm;
  DM          swarm;
  Vec         X;       /* state: view on the swarm's packed field                      */
  PetscInt    n;       /* local particles                                              */
  PetscInt    nglobal;
  PetscInt64 *gid;     /* [n] the swarm's gid field, held open (as X holds the state)   */
  PetscInt   *at_row;  /* [n] local particles in increasing gid, NULL when in order     */
} SpamSwarm;

/* Input row (file line, lattice site) of particle i, its gid: outputs and messages use
 * it, so the spatial reordering (set-up sort, migrations) is invisible to users. */
static inline PetscInt SpamSwarmRowOf(const SpamSwarm *p, PetscInt i)
{
  return p->gid ? (PetscInt)p->gid[i] : i;
}
/* The local particle with the r-th smallest gid of this rank: on one rank the particle
 * at input row r (outputs written in input order use it). */
static inline PetscInt SpamSwarmAtRow(const SpamSwarm *p, PetscInt r)
{
  return p->at_row ? p->at_row[r] : r;
}
/* The gids of a set-up reordering: particle i came from local input row row_of[i]. */
PetscErrorCode SpamSwarmSetRows(SpamSwarm *p, const PetscInt *row_of);
/* After the gids changed (a set-up reordering, a migration): at_row made anew. */
PetscErrorCode SpamSwarmIndexRows(SpamSwarm *p);

/* X made over the swarm's state field, which stays open while X lives (local sizes from
 * the swarm), and destroyed with the field restored (nothing when X is NULL). */
PetscErrorCode SpamSwarmOpenState(SpamSwarm *p);
PetscErrorCode SpamSwarmCloseState(SpamSwarm *p);

/* A move of particles between ranks as their owner describes it: where the position sits
 * in the state, the swarm's other per-particle fields (permuted with the state), and what
 * the owner does around the move with the data it keeps outside the swarm. */
typedef struct {
  int                dim, nvar, x;  /* dimension, reals per particle, offset of the position */
  const char *const *carried;       /* [ncarried] names of the other per-particle fields     */
  int                ncarried;
  void              *ctx;
  /* Collective, before the swarm closes (the old gids and order): the owner's data into
   * the carried fields, and what travels otherwise sent by dest. */
  PetscErrorCode (*depart)(void *ctx, const PetscInt *dest);
  /* Collective, once X is re-made over the particles in their new order: the owner's
   * scratch fitted to them, the carried data taken back. */
  PetscErrorCode (*arrive)(void *ctx);
} SpamMigration;
#endif
