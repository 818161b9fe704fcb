/* The particle file's columns, shared by its CSV reader (scene_file.c), its header parser
 * (particle_header.c) and its HDF5 reader (scene_file_hdf5.c). Internal to src/scenes. */
#ifndef SPAM_PARTICLE_FILE_H
#define SPAM_PARTICLE_FILE_H
#include <spam/scene.h>

/* Where a column's value goes: one slot per quantity. The stress slots follow the
 * dimension's component order (SpamParticles.sigma). */
enum {
  SLOT_X       = 0,  /* x, y, z: 0..2          */
  SLOT_V       = 3,  /* vx, vy, vz: 3..5       */
  SLOT_M       = 6,
  SLOT_E       = 7,
  SLOT_RHO     = 8,
  SLOT_S       = 9,  /* stress: 9..14          */
  SLOT_ID      = 15,
  SLOT_RHO_SUM = 16, /* a snapshot's summed density: derived from positions, not read */
  NSLOTS       = 17
};

typedef struct {
  int      ncol;          /* fields of a data line                                   */
  int      slot[NSLOTS];  /* slot of column k (k < ncol)                               */
  unsigned columns;       /* SPAM_COLUMN_* bits                                        */
  PetscBool has_rho_sum;
} SpamColumnMap;

/* Parses a header line for dimension dim. Returns 0, or 1 with the reason in why. */
int SpamColumnsParse(const char *header, int dim, SpamColumnMap *map, char *why, size_t len);
/* A header-less (legacy) file: x..,vx.. and, with 2 dim + 1 fields, m. */
void SpamColumnsLegacy(int dim, int nfields, SpamColumnMap *map);
/* The name of stress component k of dimension dim (sxx, sxy, ...). */
const char *SpamStressName(int dim, int k);
/* Allocates the arrays of out for n particles and the given columns (x and v always). */
PetscErrorCode SpamParticlesAllocateColumns(int dim, PetscInt n, unsigned columns, SpamParticles *out);
/* Rows of a file with ids: ids must be 0..n-1 once each; the particle of id k moves to
 * row k so that every output (which names particles by row) keeps the file's ids.
 * Returns the index of the first bad id (else -1) and what is wrong with it. */
PetscErrorCode SpamParticlesOrderById(SpamParticles *p, PetscInt *bad, const char **why);
#endif
