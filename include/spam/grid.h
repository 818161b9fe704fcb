/* Smooth-particle fields on a regular grid (-grid_interval dx): at every snapshot time the
 * summed density rho(x) = sum_j m_j w(x - x_j), the SPH interpolants
 * A(x) = sum_j (m_j / rho_j) A_j w(x - x_j) of the velocity and, where the model carries
 * them, of the energy per unit mass, the temperature (gas: T = (gamma - 1) e) and the
 * stress, and the Shepard sum S(x) = sum_j (m_j / rho_j) w(x - x_j), evaluated at the
 * cell centres of a grid covering the box (grid_fields.c) and written as HDF5 + XDMF and
 * CSV (grid_output.c). The sums run over the particles (of every rank: each rank sums its
 * own, one MPI_Allreduce adds the ranks' sums) with the minimum image in the periodic
 * directions and nothing else: no wall images, so near a wall or a free surface the sums
 * are one-sided and S < 1 says so. On P ranks a sum is the same terms added in another
 * order: equal to the one-rank value within round-off, not bitwise. */
#ifndef SPAM_GRID_H
#define SPAM_GRID_H
#include <spam/output.h>

/* Most grid points a run may ask for: a tiny spacing is refused naming the count. 1e7
 * points hold up to 13 columns of 8 bytes, 1 GB in memory and some GB of CSV per time. */
#define SPAM_GRID_MAX_POINTS 1e7
/* Columns: rho, up to 3 velocities, e, T, up to 6 stresses, S. */
#define SPAM_GRID_MAX_COLUMNS 13

typedef struct {
  int      dim;
  PetscInt n[3];       /* points along x, y, z (1 beyond dim)                          */
  PetscInt npoints;    /* n[0] n[1] n[2]                                               */
  double   spacing[3]; /* box length / n: the requested spacing or a little less, so   */
                       /* that the points tile the box exactly                        */
  double   origin[3];  /* the first point: box corner + spacing / 2 (cell centres)     */
  double   requested;  /* -grid_interval as given                                      */
} SpamGrid;

/* The fields at the points, point p = i + n[0] (j + n[1] k) (x fastest: the C order of an
 * array [nz][ny][nx]); column c is named name[c] (the CSV header and the HDF5 dataset). */
typedef struct {
  int         ncol;
  const char *name[SPAM_GRID_MAX_COLUMNS];
  double     *col[SPAM_GRID_MAX_COLUMNS]; /* column c: block + c npoints              */
  double     *block;
  int         v;  /* column of vx (vy, vz follow)                                       */
} SpamGridFields;

/* Points of a grid of spacing dx over box (in double: a tiny dx gives a count no integer
 * holds); the option check compares it with SPAM_GRID_MAX_POINTS. */
double         SpamGridPointCount(const SpamBox *box, double dx);
PetscErrorCode SpamGridSetUp(const SpamBox *box, double dx, SpamGrid *g);
/* Evaluates the fields of state y (sim->pair.f.rho must hold its summed density when the
 * model does not carry the density) at the points of g; allocates f's columns.
 * Collective on sim->p.comm: every rank gets the sums over all ranks. */
PetscErrorCode SpamGridFieldsEvaluate(const SpamSim *sim, const double *y, const SpamGrid *g, SpamGridFields *f);
PetscErrorCode SpamGridFieldsFree(SpamGridFields *f);
/* grid_NNNNN.h5 (with -snapshot_hdf5, and the index grid.xmf) and grid_NNNNN.csv (with
 * -snapshot_csv) of state y at time t, numbered like the grid files before them.
 * Collective on sim->p.comm; rank 0 writes the files. */
PetscErrorCode SpamGridWrite(SpamOutput *o, const SpamSim *sim, const double *y, double t);
#endif
