/* Output files. Every file is written to a temporary name and renamed when complete, so
 * a reader never sees a half-written file. */
#ifndef SPAM_OUTPUT_H
#define SPAM_OUTPUT_H
#include <spam/diagnostics.h>

typedef struct {
  char  dir[PETSC_MAX_PATH_LEN];
  FILE *timeseries, *steps;   /* appended during the run, renamed at the end          */
  int   nsnap;                /* snapshots written so far                             */
  double *snap_times;         /* [capacity] times of the snapshots, for the XDMF index */
  int   snap_cap;
  PetscBool hdf5, csv;
} SpamOutput;

/* Creates the directory (and parents). Call only after every input is validated. */
PetscErrorCode SpamOutputOpen(const char *dir, PetscBool hdf5, PetscBool csv, SpamOutput *o);
PetscErrorCode SpamOutputClose(SpamOutput *o);
PetscErrorCode SpamOutputPath(const SpamOutput *o, const char *name, char *path, size_t len);
/* Opens path.tmp for writing; SpamFileCommit closes it and renames it to path. */
PetscErrorCode SpamFileBegin(const char *path, FILE **f);
PetscErrorCode SpamFileCommit(const char *path, FILE *f);

typedef struct {
  double      t;
  long        steps, rejected, rhs_evals;
  long        limited;   /* steps set by the physical (CFL or force) bound            */
  const char *limit;     /* what set the last step: accuracy, fixed, output, cfl, force */
  double      dt, wall, rhs_time;
} SpamProgress;

PetscErrorCode SpamTimeseriesAppend(SpamOutput *o, const SpamSim *sim, const SpamProgress *pr, const SpamDiagnostics *d, const SpamDiagnostics *d0);
PetscErrorCode SpamStepsAppend(SpamOutput *o, const SpamProgress *pr);

/* Per-particle snapshot fields: the density the model uses, the stress in Tensor6 order. */
double SpamSnapshotDensity(const SpamSim *sim, const double *y, PetscInt i);
void   SpamSnapshotStress6(const SpamSim *sim, const double *y, PetscInt i, double t6[6]);
/* Particle snapshot: HDF5 + XDMF (ParaView) and/or CSV (positions, velocities, density,
 * and energy and stress where the state has them). Needs sim->rho of state y. */
PetscErrorCode SpamSnapshotWrite(SpamOutput *o, SpamSim *sim, const double *y, double t, const char *tag);
/* Particles as a file-scene CSV (x,y[,z],vx,vy[,vz],m) at full precision. */
PetscErrorCode SpamParticlesCsvWrite(const char *path, const SpamSim *sim, const double *y);
#endif
