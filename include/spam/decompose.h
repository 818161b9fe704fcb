/* The particles over the ranks: a balanced cut of the occupied cells of the global
 * h-cell grid along a Hilbert curve (decompose.c), and the migration that sends every
 * particle to the owner of its cell between steps (migrate.c).
 *
 * Why a curve cut and not a brick of equal boxes: the expansion starts in one corner of
 * its box, so equal boxes would leave most ranks empty; pieces of equal particle count
 * along a space-filling curve follow the particles wherever they are, and a Hilbert piece
 * is compact (consecutive cells are face neighbours), which keeps the halo small.
 *
 * The cut is nranks + 1 curve keys, replicated on every rank: the table cell -> rank in
 * its compact form (rank r owns the cells whose key lies in [cut[r], cut[r+1])), the
 * same on every rank, of size O(ranks) rather than O(cells): a dense table for a 10^8
 * particle run would hold ~10^7 cells on each rank. Empty cells have owners too, so a
 * particle moving into a cell nobody occupied still has a destination. */
#ifndef SPAM_DECOMPOSE_H
#define SPAM_DECOMPOSE_H
#include <spam/swarm.h>
#include <spam/box.h>
#include <spam/cell_keys.h>

/* Default of SpamDecomp.recut_above: a re-cut when the fullest rank holds 25 % more than
 * the mean. Every RHS takes the fullest rank's time, so an imbalance I loses I - 1 RHS
 * evaluations of the balanced run per evaluation. A re-cut is a migration that moves
 * many particles: moving half of 10^5 particles on 2 ranks took 0.097-0.109 s, 33-37
 * RHS evaluations of the same particles (2.9-3.0 ms), and a migration that moves 0.4 %
 * 20-21 ms, about 7 (test_migrate_np2, `ctest -R test_migrate_np2 -V`, two
 * runs, two cores shared with other jobs). At 1.25 a re-cut pays for itself within about
 * 150 RHS evaluations, a fraction of a run; a threshold nearer 1 would re-cut for gains
 * that the next few list rebuilds undo, and would fall within a cut's own granularity
 * (1 + cmax P / N for cells of cmax particles) when ranks hold few particles. */
#define SPAM_RECUT_ABOVE_DEFAULT 1.25

typedef struct SpamDecomp {
  MPI_Comm     comm;
  PetscMPIInt  nranks, rank;
  SpamBox      box;
  SpamCellGrid grid;          /* the global cells, of the kernel's width h           */
  uint64_t    *cut;           /* [nranks + 1] the curve keys that bound the pieces    */
  PetscInt64  *count;         /* [nranks] particles each rank got at the last cut     */
  PetscBool    has_cut;
  double       recut_above;   /* re-cut when max/mean of the counts passes this       */
  double       cut_imbalance; /* max/mean the last cut achieved (its cell granularity) */
  double       imbalance;     /* max/mean after the last migration                    */
  long         cuts, migrations;
} SpamDecomp;

typedef struct {
  PetscBool  changed;  /* on some rank particles left, came or were re-sorted: X, the gid
                          field and the owner's scratch were re-made on EVERY rank, so every
                          vector an integrator holds must follow on every rank
                          (ERKStepResize, TSReset + TSSetSolution; CVODE re-created)      */
  PetscBool  resized;  /* this rank's local count changed                                */
  PetscBool  recut;    /* a cut was made (the first, or the imbalance passed the threshold) */
  double     imbalance_before; /* max/mean by the cut in force before (or, without one,  */
                                /* of the particles where they are)                      */
  double     imbalance;         /* max/mean after this migration                         */
  PetscInt64 sent, received;    /* by this rank                                          */
  PetscInt64 moved;             /* particles that changed rank, over all ranks           */
  PetscInt64 bad;      /* smallest gid with a non-finite position, or -1; when >= 0 (the
                          same on every rank) nothing was changed                          */
} SpamMigrateInfo;

/* A decomposition of the box into cells of width h for comm; no cut yet (the first
 * migration makes it). recut_above <= 1 asks for the default. */
PetscErrorCode SpamDecompCreate(MPI_Comm comm, const SpamBox *box, double h, double recut_above, SpamDecomp *dec);
PetscErrorCode SpamDecompDestroy(SpamDecomp *dec);
/* Hilbert key of the cell of point x (wrapped in periodic directions). */
uint64_t SpamDecompKey(const SpamDecomp *dec, const double *x);
/* The rank that owns the cell of curve key `key` (after a cut). */
PetscMPIInt SpamDecompOwner(const SpamDecomp *dec, uint64_t key);
/* Collective: cuts the curve into nranks pieces of equal particle count from this rank's
 * n keys, sorted ascending. A piece ends at a cell boundary, so each count is within one
 * cell's particles of N/nranks; deterministic, and independent of which rank holds which
 * particle. */
PetscErrorCode SpamDecompCut(SpamDecomp *dec, PetscInt n, const uint64_t *sorted_keys);
/* max / mean of nranks counts (1 when all are empty). */
double SpamDecompImbalance(PetscMPIInt nranks, const PetscInt64 *count);

/* Collective, at a step boundary (never inside a step): every particle to the owner of
 * its cell (re-cut first when the imbalance would pass dec->recut_above), then the local
 * order sorted by (cell, gid), X and the gid field re-made and m's arrive called. Positions
 * are not changed (wrapping is only for the owner). When nothing moved and every rank's
 * order is already sorted it does nothing (info->changed false). An error on one rank is
 * raised on every rank. */
PetscErrorCode SpamSwarmMigrate(SpamSwarm *p, const SpamMigration *m, SpamDecomp *dec, SpamMigrateInfo *info);
/* The swarm's local particles (with X closed and the gid field restored) sorted by
 * (order key of their cell, gid), the state, the gids and m's carried fields permuted, and
 * those whose DMSwarm_rank names another rank (sent by a migration) dropped. *permuted
 * tells whether the order or the count changed (local_order.c). */
PetscErrorCode SpamSwarmSortLocal(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, PetscBool *permuted);
/* The local particles sorted as the gids of gids[n] (a checkpoint's local order), those
 * sent away dropped, as SpamSwarmSortLocal does; a particle whose gid is not in gids goes
 * last (the caller finds it by the count). */
PetscErrorCode SpamSwarmSortLocalAs(const SpamSwarm *p, const SpamMigration *m, PetscInt n, const PetscInt64 *gids, PetscBool *permuted);
/* A restart on the rank count of its checkpoint (restart_load.c): each particle sent to
 * the rank whose block of the checkpoint holds its gid, and the local order made that of
 * the block, gids[n] (this rank's, in the checkpoint's order); X and the gid field re-made
 * and m's arrive called as after a migration. *changed (the same on every rank):
 * something moved or was re-ordered. A gid outside the scene, one the checkpoint lacks,
 * or another count than the block's is refused (PETSC_ERR_USER_INPUT) on every rank.
 * Collective. */
PetscErrorCode SpamSwarmPlace(SpamSwarm *p, const SpamMigration *m, PetscInt n, const PetscInt64 *gids, PetscBool *changed);
/* The swarm closed so that it may resize (a migration's first half, after the owner's
 * depart): dest[i] into DMSwarm_rank, the gid field restored and X destroyed (local). */
PetscErrorCode SpamSwarmClose(SpamSwarm *p, const PetscInt *dest);
/* Whether the local particles are in that order; y: the state (X's array). */
PetscBool SpamSwarmSortedLocal(const SpamSwarm *p, const SpamMigration *m, const SpamDecomp *dec, const double *y);
#endif
