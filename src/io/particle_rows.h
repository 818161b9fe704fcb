/* Internal to src/io: the particles of all ranks as rows in gid order (particle_rows.c),
 * what every particle output writes from. On P ranks the local particles lie in the
 * migration's order (cell, gid) and a rank's gids are not contiguous; the outputs are
 * files in global input order whatever P, so the rows are first moved, through one
 * PetscSF, to where their gid puts them: a block of consecutive gids per rank (the HDF5
 * snapshot, each rank writing its block as one hyperslab) or all of them to rank 0 (the
 * CSV files, written by rank 0 alone). On one rank the same code puts row r at gid r. */
#ifndef SPAM_PARTICLE_ROWS_H
#define SPAM_PARTICLE_ROWS_H
#include <spam/sim.h>

typedef struct {
  PetscInt    n;        /* rows held by this rank                                       */
  PetscInt64  first;    /* gid of the first of them                                     */
  PetscInt64  nglobal;  /* rows over all ranks                                          */
  int         nvar;
  double     *y;        /* [n * nvar] the state of gid first + r in row r               */
  double     *m;        /* [n] masses                                                   */
  double     *rho_sum;  /* [n] summed density (sim->pair.f.rho), or NULL when it is state    */
  double     *h;        /* [n] each particle's kernel range (adaptive), or NULL: one h   */
  PetscInt64 *gid;      /* [n] the gids as they arrived: first + r (checked)            */
} SpamRows;

typedef enum { SPAM_ROWS_BLOCKS, SPAM_ROWS_ON_ROOT } SpamRowsTarget;

/* Collective on sim->p.comm: the rows of state y (sim->pair.f.rho holding its summed density
 * when the model does not carry it), moved by gid to blocks of consecutive gids (the
 * split PetscLayout makes) or all to rank 0. Fails on every rank if the gids are not
 * 0 .. N-1 each once. */
PetscErrorCode SpamRowsGather(const SpamSim *sim, const double *y, SpamRowsTarget target, SpamRows *rows);
PetscErrorCode SpamRowsFree(SpamRows *rows);
/* The density a snapshot writes for row r: the carried one, else the summed one. */
double SpamRowsDensity(const SpamLayout *l, const SpamRows *rows, PetscInt r);
#endif
