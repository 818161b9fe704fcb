/* Neighbour search: cell binning plus a half Verlet list (each pair once) with a
 * skin, and under -reproducible also full rows sorted by partner id (canonical rows). The list is kept while no particle has moved more than half the skin since the
 * last build, so it serves many RK stages and steps. Positions are read from a strided
 * array (the packed state) and copied, wrapped into the box, into SoA scratch arrays so
 * that the pair loops stream through memory. */
#ifndef SPAM_NEIGHBOURS_H
#define SPAM_NEIGHBOURS_H
#include <spam/box.h>
#include <spam/ghosts.h>

#define SPAM_MAX_THREADS 256
/* The half list and the ghost rows keep this many valid entries (particle 0) after their
 * last pair, so that a pair loop may compute whole vectors of terms past a row's end
 * (lanes it then ignores) and read neighbour indices no further than the list's room. */
#define SPAM_LIST_PAD 8
/* Rows of the half list per row block (SpamNeighbours blk_zero, blk_final). */
#define SPAM_ROW_BLOCK 128

/* Pair entries being appended: the list itself, or one thread's part of it. */
typedef struct {
  int   *nbr;
  size_t cap, n;
} SpamPairBuffer;

typedef struct {
  int     dim, n;
  double  cutoff, skin, rc2;     /* rc = cutoff + skin                             */
  int     ncell[3], ncells;
  double  cellw[3];
  int    *cell_of;               /* [n] cell index of each particle at the build     */
  int    *cell_start, *cell_list;/* CSR: particles of each cell                      */
  int    *slot;                  /* [n] position of particle i in cell_list          */
  int    *start, *nbr;           /* CSR half list: each pair once, in the row of one */
                                 /* of its two particles                             */
  unsigned char *image;          /* [n] 1: particle i's pairs may cross a periodic   */
                                 /* face (needs the minimum image); 0: they cannot   */
  size_t  npairs, cap;
  /* Row blocks of the half list, made at every build: block b holds rows [b B, (b + 1) B)
   * (B = SPAM_ROW_BLOCK). Once the rows of blocks 0..b are done, every local particle a
   * row of those blocks names lies below blk_zero[b], and no later row names a particle
   * below blk_final[b], so that a pass can clear its sums just ahead of the rows and use
   * a particle's sum as soon as it is complete, while both are still in the cache. */
  int    *blk_zero, *blk_final, nblk;
  double *xref[3];               /* [n] per direction: positions at the last build   */
  double *off[3];                /* [n] x - u, the periodic shift fixed at the build */
  double *ucell[3];              /* [n] u at the build in cell order (build scratch) */
  double *u[3];                  /* [n] box-local positions x - off (wrapped at the  */
                                 /* build, within skin/2 of the box since)           */
  /* Ghost slots (ghosts.h): positions u[d][n + k] of ghost k, and a second CSR list of
   * each local particle's ghost neighbours (every pair once: a periodic image's pair is
   * listed in the row of the lower of its two particles). */
  SpamGhosts ghosts;
  int     ucap;                  /* room of u[d]: local + ghost slots                 */
  int    *gstart, *gnbr;         /* [n+1], [gcap]: ghost rows, j = n + k              */
  size_t  ngpairs, gcap;
  int    *gcell_start, *gcell_list, gcell_cap; /* ghosts binned into the cells       */
  unsigned char *gcell_near; /* [ncells] a ghost lies in this cell or one adjacent to it */
  SpamBox lbox;                  /* the box of the list: ghost-periodic directions    */
                                 /* are open here (their images are ghosts)          */
  SpamImage im;                  /* minimum image of the list's pairs (from lbox)     */
  int     threads;               /* threads of a build (SpamNeighboursSetThreads)     */
  SpamPairBuffer *tbuf;          /* [threads] each thread's rows of a threaded build */
  int     bad_rank;              /* lowest rank holding a non-finite position at the */
                                 /* last update, -1 if none (halo.h: all ranks agree) */
  /* Canonical full rows (-reproducible; neighbours_canonical.c): every local particle's
   * partners within the list range, local and ghost slots alike (periodic images and
   * other ranks' particles), each row sorted by the partner's (gid, image) key, so that a
   * sum over a row in row order has the same bits whichever rank or thread holds the
   * partners. Built at every list build after the half list and the ghost rows, which
   * stay as they are for the passes that use them (entropy, bodies). */
  PetscBool   canonical;         /* the rows are made (SpamNeighboursSetCanonical)       */
  const PetscInt64 *gid;         /* [n] global ids of the local particles (the caller's */
                                 /* array, read at every build)                          */
  PetscInt64 *key;               /* [kcap] key of every slot: gid * 27 + image code      */
  double     *gidbuf;            /* [kcap] gids as doubles: sent to remote ghost slots  */
  int         kcap;
  int        *cstart, *cnbr;     /* [n+1], [ccap]: the rows, slot indices               */
  int        *ccur;              /* [n+1] build scratch: a row's next free entry        */
  size_t      ncpairs, ccap;
  int        *csort;             /* [threads * csort_row] merge-sort scratch of a build */
  int         csort_row;
  /* The transposed list (SpamNeighboursTranspose, made on demand for the passes over
   * the pairs of a few marked particles): for each local particle p the rows that list p
   * or a ghost slot of p, trows[tstart[p] .. tstart[p + 1]), ascending; made at build
   * tbuilt (0: never). */
  int    *tstart, *trows;
  size_t  tcap;
  long    tbuilt;
  long    builds, grows;         /* statistics                                       */
  double *keep;                  /* SpamNeighboursKeep's [n*dim], filled at the next */
                                 /* change of xref or build (NULL: none pending)     */
  long    updates;               /* calls of SpamNeighboursUpdate                     */
  long    placements;            /* ghost slots' positions placed (an exchange through */
                                 /* the halo on several ranks): one per update or build */
  PetscLogEvent ev_build;        /* -log_view event of a list build (0: none)         */
} SpamNeighbours;

PetscErrorCode SpamNeighboursCreate(int n, const SpamBox *box, double cutoff, double skin, SpamNeighbours *nl);
/* Builds with this many OpenMP threads (default 1); before the first build. The list is
 * the same for every count. */
PetscErrorCode SpamNeighboursSetThreads(SpamNeighbours *nl, int threads);
PetscErrorCode SpamNeighboursDestroy(SpamNeighbours *nl);
/* The particles of other ranks of comm become remote ghost slots (halo.h); before the
 * first build. Every update and build is then collective over comm: the rebuild decision
 * (some particle on some rank moved more than skin/2, or some rank forces it) and a
 * non-finite position are agreed by every rank. Mirror walls are refused across ranks. */
PetscErrorCode SpamNeighboursSetComm(SpamNeighbours *nl, MPI_Comm comm);
/* *bad of an update whose non-finite position lies on another rank only. */
#define SPAM_BAD_ON_OTHER_RANK PETSC_MAX_INT
/* Copies positions (x[i*stride + d]) into nl->u, rebuilding the list when needed or when
 * force is set. If a position is not finite, returns at once (0) with *bad the index of
 * this rank's first such particle, or SPAM_BAD_ON_OTHER_RANK on the ranks that have none
 * (nl->bad_rank names the lowest rank that has one); *bad is -1 otherwise. */
PetscErrorCode SpamNeighboursUpdate(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride, PetscBool force, PetscInt *bad);
/* SpamNeighboursUpdate without the copy into u when the list is kept and has no ghost
 * slots (*stale set): the rebuild decision and *bad as there, but u keeps its old values
 * until the caller places each particle (SpamNeighboursPlace) before it reads its u, as
 * the blocked force pass does just ahead of its rows, while the state is in the cache.
 * With *stale unset, u is current as after SpamNeighboursUpdate. */
PetscErrorCode SpamNeighboursUpdateStale(SpamNeighbours *nl, const SpamBox *box, const double *x, int stride, PetscInt *bad, PetscBool *stale);
/* u of particles [i0, i1) from x, as SpamNeighboursUpdate computes it (bitwise). */
static inline void SpamNeighboursPlace(const SpamNeighbours *nl, const double *x, int stride, int i0, int i1)
{
  for (int d = 0; d < nl->dim; d++)
    for (int i = i0; i < i1; i++) nl->u[d][i] = x[(size_t)i * stride + d] - nl->off[d][i];
}
/* Rebuilds the list at the reference positions xref[i*dim + d] of an earlier build (a
 * checkpoint's), as that build made it; the next update moves from there. */
PetscErrorCode SpamNeighboursRestore(SpamNeighbours *nl, const SpamBox *box, const double *xref);
/* Keep and revert: a list build made by work outside the trajectory (the diagnostics and
 * interpolations of an output) is undone, so the method's right-hand sides see the list
 * they would have seen without that output. Keep notes the build count and hands over
 * xref [n*dim], into which the reference positions are copied only when the list is
 * about to change (most outputs build nothing: the buffer stays unwritten, no memory);
 * Revert rebuilds at them if a build happened since. */
PetscErrorCode SpamNeighboursKeep(SpamNeighbours *nl, double *xref, long *builds);
PetscErrorCode SpamNeighboursRevert(SpamNeighbours *nl, const SpamBox *box, const double *xref, long builds);
/* Periodic images as ghost slots instead of the minimum image along the directions set
 * in per (before the first build; a study of the ghost path, and the way halos work). */
PetscErrorCode SpamNeighboursSetPeriodicGhosts(SpamNeighbours *nl, const SpamBox *box, const PetscBool per[3]);
/* Mirror walls on the box faces (walls.h): their images become ghost slots (before the
 * first build). */
PetscErrorCode SpamNeighboursSetWalls(SpamNeighbours *nl, const SpamWalls *walls);
/* After a build: picks the ghosts, places them and lists each local particle's ghost
 * neighbours (neighbours_ghost.c). Between builds: moves the ghosts with their sources.
 * Both collective when a halo is set (SpamNeighboursSetComm). */
PetscErrorCode SpamNeighboursBuildGhosts(SpamNeighbours *nl, const SpamBox *box);
PetscErrorCode SpamNeighboursMoveGhosts(SpamNeighbours *nl);
/* Writes the SPAM_LIST_PAD entries after the n pairs of a list (nbr, room *cap), growing
 * it if short: the end of every build of the half list and of the ghost rows. */
PetscErrorCode SpamNeighboursPadList(int **nbr, size_t *cap, size_t n);
/* Canonical full rows for -reproducible (before the first build; periodic directions
 * must all be ghost images, SpamNeighboursSetPeriodicGhosts, and no mirror walls): gid[i]
 * is local particle i's global id, read at every build, so the array must live as long
 * as the list (the sim's gid field: a migration re-makes the list). */
PetscErrorCode SpamNeighboursSetCanonical(SpamNeighbours *nl, const PetscInt64 *gid);
static inline PetscBool SpamNeighboursCanonical(const SpamNeighbours *nl)
{
  return nl->canonical;
}
/* After the ghosts of a build: the slots' keys and the sorted full rows (collective when
 * a halo is set: the remote slots' gids arrive through it). Nothing without SetCanonical. */
PetscErrorCode SpamNeighboursBuildCanonical(SpamNeighbours *nl);
/* The image code of shifts s_d in {-1, 0, 1}: (s0 + 1) + 3 (s1 + 1) + 9 (s2 + 1); 13 is
 * the particle itself. */
static inline int SpamImageCode(int s0, int s1, int s2)
{
  return (s0 + 1) + 3 * (s1 + 1) + 9 * (s2 + 1);
}
/* The transposed list of the current build (nl->tstart, nl->trows), made if stale. */
PetscErrorCode SpamNeighboursTranspose(SpamNeighbours *nl);
/* row[i] = 1 for the rows i < n holding a pair with a member marked in mask (one byte per
 * local particle; a ghost slot counts as marked when its source is), 0 for the others,
 * from the transposed list (made if stale): the rows a walk restricted to the marked
 * particles' pairs must read, found without reading the others. */
PetscErrorCode SpamNeighboursMarkedRows(SpamNeighbours *nl, const unsigned char *mask, unsigned char *row);
/* near[i] = 1 for the local particles marked in mask and every local particle listed
 * beside one (no range test; ghost slots not followed), 0 for the others. */
PetscErrorCode SpamNeighboursMarkedNear(SpamNeighbours *nl, const unsigned char *mask, unsigned char *near);
/* Local plus ghost slots (remote ones included): the length every per-particle array of
 * a pass needs. */
static inline int SpamNeighboursSlots(const SpamNeighbours *nl)
{
  return nl->n + nl->ghosts.n;
}
/* Rows [rows[0], rows[1]) of block t when the list is split into T blocks of consecutive
 * rows with about equal pair counts (the blocks of a threaded pass). */
void SpamNeighboursSplitRows(const SpamNeighbours *nl, int T, int t, int rows[2]);
/* Cell of a box-local point, and the distinct cells adjacent to it (itself included). */
int SpamNeighboursCellOf(const SpamNeighbours *nl, const SpamBox *box, const double *u);
int SpamNeighboursAdjacentCells(const SpamNeighbours *nl, const SpamBox *box, int cell, int *adj);
#endif
