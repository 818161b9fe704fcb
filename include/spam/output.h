/* Output files. The run owns its directory (a lock file held with flock) and lists every
 * file it writes in manifest.json. Every file is written to a new temporary name (created
 * with O_EXCL | O_NOFOLLOW, never through a name someone left there) and renamed when
 * complete, so a reader never sees a half-written file. Every write is checked: the first
 * failure is an error naming the file (PETSC_ERR_FILE_WRITE) and its temporary is removed. */
#ifndef SPAM_OUTPUT_H
#define SPAM_OUTPUT_H
#include <spam/diagnostics.h>
#include <spam/errors.h> /* SpamRunAgreed: collective writes */
#include <spam/decimal.h>

/* A file being written: stdio on a temporary that SpamFileCommit renames to path. */
typedef struct {
  FILE *f;
  char  path[PETSC_MAX_PATH_LEN];     /* the final name                                   */
  char  tmp[PETSC_MAX_PATH_LEN + 32]; /* the temporary: path.PID.tmp                      */
  int   err;                          /* errno of the first failed write (0: none yet)    */
  long  writes;                       /* write calls so far                               */
  long  fail_at;                      /* test only: this write fails (0: none), see below */
} SpamFile;

/* Test only: SPAM_TEST_FAIL_WRITE=NAME:N makes the N-th write call (1: the first) to the
 * output file whose base name is NAME fail as if the disk were full (ENOSPC); for an HDF5
 * snapshot or checkpoint (checkpoint_file.h) the N-th dataset write. It exists so the tests can prove that a failed write
 * stops the run; it is an environment variable, not an option, so users never see it. */
long SpamTestFailWriteAt(const char *path);
/* Test only: SPAM_TEST_PAUSE_TEMP=NAME:GOFILE makes the writer of the output file whose base
 * name is NAME wait, right after creating its temporary, until the file GOFILE exists (at
 * most 60 s), so that a test can replace the temporary meanwhile (a symlink race). */
void SpamTestPauseAfterTemp(const char *path);


/* The HDF5 snapshot's checksum (snapshot_checksum.c): its first SPAM_SNAPSHOT_USERBLOCK
 * bytes, an HDF5 user block, hold the hash of the rest. SpamSnapshotStamp fills the block
 * of a complete file image; SpamSnapshotVerify refuses (exit 2, naming -file_path = path) a
 * file whose block does not match its bytes. A file with HDF5's signature at its start has
 * no block (a snapshot of an earlier version): nothing to verify. f is rewound. */
#define SPAM_SNAPSHOT_USERBLOCK 512
void           SpamSnapshotStamp(unsigned char *image, size_t len);
PetscErrorCode SpamSnapshotVerify(FILE *f, const char *path);

/* Creates path.PID.tmp new (O_CREAT | O_EXCL | O_NOFOLLOW); tmp receives its name. */
PetscErrorCode SpamTempCreate(const char *path, char *tmp, size_t len, int *fd);
PetscErrorCode SpamFileBegin(const char *path, SpamFile *f);
/* Writes unless an earlier write of f failed; a failure is recorded in f->err and
 * reported by the next SpamFileCheck or SpamFileCommit. */
void SpamFilePrintf(SpamFile *f, const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(2, 3);
/* As SpamFilePrintf(f, "%s", s): one write call. */
void SpamFilePuts(SpamFile *f, const char *s);
/* A JSON string (quoted): control bytes as \u00XX, bytes outside well-formed UTF-8 as U+FFFD. */
void SpamFileJsonString(SpamFile *f, const char *s);
/* Flushes; after a failed write removes the temporary and raises the error. */
PetscErrorCode SpamFileCheck(SpamFile *f);
/* Flushes, closes and renames the temporary to path (removing it on any failure). */
PetscErrorCode SpamFileCommit(SpamFile *f);
/* Closes and removes the temporary without reporting (after another failure). */
void SpamFileDiscard(SpamFile *f);

/* Options of the output directory (read by SpamOutputOptionsParse, see run.h). */
typedef struct {
  PetscBool overwrite;     /* -output_overwrite: remove an earlier run's files first  */
  PetscInt  snapshot_max;  /* -snapshot_max: no run writes more snapshots than this   */
  char      timeseries_more[1024]; /* the run's further timeseries columns (",a,b"): walls */
  double    grid_interval; /* -grid_interval: spacing of the grid fields at every      */
                           /* snapshot (grid.h); 0: none                              */
} SpamOutputOptions;

/* One file of the run, as manifest.json lists it. */
typedef struct {
  char   name[512];               /* in the directory, or the path as given (outside) */
  char   kind[24];
  double t;                        /* snapshot time (NaN: not a snapshot)               */
  PetscBool outside;               /* -initial_csv / -final_csv: a path, not a name      */
} SpamOutputEntry;

/* On several ranks rank 0 of the sim's communicator owns the directory (opens, locks,
 * closes it; its text series and summary); the other ranks hold an output with dir,
 * hdf5, csv and opt set and no open file (run_session.c). The snapshot and grid writers
 * below are called by every rank and keep the same counts and list of files on every
 * rank; rank 0 writes the text files. */
typedef struct {
  char      dir[PETSC_MAX_PATH_LEN];
  SpamFile  timeseries, steps; /* appended during the run, renamed at the end       */
  int       nsnap;             /* snapshots written so far                          */
  long      step;              /* step of the last timeseries row (snapshot attribute) */
  double   *snap_times;        /* [capacity] times of the snapshots, for the XDMF index */
  int       snap_cap;
  struct {
    int     n, cap;
    double *times;             /* [cap] times of the grid files, for grid.xmf       */
  } grid;
  PetscBool hdf5, csv;
  SpamOutputOptions opt;
  int       lock_fd;           /* the lock file, held with flock (-1: none)         */
  char      lock_info[160];    /* pid, host and start time, as written in the lock */
  char      status[16];        /* manifest status: running, ok, ..., failed        */
  PetscBool owned;             /* the directory was accepted: the manifest is ours  */
  SpamOutputEntry *files;      /* manifest entries                                  */
  int       nfiles, files_cap;
} SpamOutput;

/* Takes the directory (creating it and its parents): locks it (exit 2 naming the holder if
 * another run has it), refuses an earlier run's files unless opt->overwrite (then removes
 * them), removes stale temporaries, writes manifest.json (status running) and opens the
 * timeseries and steps files. Call only after every input is validated. */
PetscErrorCode SpamOutputOpen(const char *dir, PetscBool hdf5, PetscBool csv, const SpamOutputOptions *opt, SpamOutput *o);
/* Commits timeseries and steps, writes the manifest with the final status, releases the lock. */
PetscErrorCode SpamOutputClose(SpamOutput *o, const char *status);
/* On a rank that does not own the directory (every rank keeps the list of files written,
 * rank 0 writes them): frees that list at the end of a run. */
void SpamOutputRelease(SpamOutput *o);
/* After a failure: removes the open temporaries, writes the manifest with status failed
 * when possible and releases the lock; reports nothing (the failure has been reported). */
void SpamOutputAbandon(SpamOutput *o);
PetscErrorCode SpamOutputPath(const SpamOutput *o, const char *name, char *path, size_t len);

/* The lock (output_lock.c). */
PetscErrorCode SpamOutputLock(SpamOutput *o, PetscBool *created);
PetscErrorCode SpamOutputLockWrite(SpamOutput *o); /* the holder's pid, host and start */
void           SpamOutputUnlock(SpamOutput *o);   /* removes the lock file, drops the lock */
/* The manifest (manifest.json): record (or update) an entry; rewrite the file. */
PetscErrorCode SpamManifestAdd(SpamOutput *o, const char *name, const char *kind, double t, PetscBool outside);
PetscErrorCode SpamManifestWrite(SpamOutput *o);
/* Files of an earlier run (output_clean.c): the first one found, or "" if none. */
PetscErrorCode SpamOutputFindEarlier(const SpamOutput *o, char *name, size_t len);
/* Removes an earlier run's files (all = true) or only stale temporaries. */
PetscErrorCode SpamOutputRemoveEarlier(const SpamOutput *o, PetscBool all);
/* Removes the run files that o->files does not list, and stale temporaries (a restart). */
PetscErrorCode SpamOutputRemoveUnlisted(const SpamOutput *o);
/* o made empty for dir (created with its parents), not yet locked or written. */
PetscErrorCode SpamOutputInit(const char *dir, PetscBool hdf5, PetscBool csv, const SpamOutputOptions *opt, SpamOutput *o);
/* Creates dir and its parents. */
PetscErrorCode SpamOutputMakeDirs(const char *dir);
/* What f has written so far (flushed; malloc'd, NUL-terminated, *len bytes). */
PetscErrorCode SpamFileContents(SpamFile *f, char **buf, size_t *len);
/* A whole file (malloc'd, NUL-terminated); *buf NULL when it does not exist. */
PetscErrorCode SpamReadWholeFile(const char *path, char **buf, size_t *len);

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
double SpamSnapshotPosition(const SpamBox *box, int d, double x);
void   SpamSnapshotStress6(const SpamLayout *l, const double *y, PetscInt i, double t6[6]);
/* Particle snapshot: HDF5 + XDMF (ParaView) and/or CSV (positions, velocities, density,
 * and energy and stress where the state has them). Needs sim->rho of state y. All four
 * are collective on sim->p.comm (every rank calls them) and write one file each whatever
 * the number of ranks, rows in gid order, the same contents as on one rank: the HDF5
 * file through MPI-IO by every rank, the CSV, the XDMF index and the manifest by rank 0
 * (an error on one rank is raised on all, SpamRunAgreed). */
PetscErrorCode SpamSnapshotWrite(SpamOutput *o, SpamSim *sim, const double *y, double t, const char *tag);
PetscErrorCode SpamSnapshotCsvWrite(const char *path, const SpamSim *sim, const double *y, double t);
PetscErrorCode SpamSnapshotHdf5Write(const char *path, const SpamSim *sim, const double *y, double t, long step);
/* Particles as a file-scene CSV at full precision, the format the file scene reads: a
 * header naming the columns x..,vx..,m, then e, rho (carried density) and the stress where
 * the state holds them, and id (the input row); positions wrapped into the box in its
 * periodic directions. Rows in input order (gid order), written by rank 0; collective. */
PetscErrorCode SpamParticlesCsvWrite(const char *path, const SpamSim *sim, const double *y);
/* The model's settings as a JSON object (model_settings.c), for the snapshot attribute
 * "model"; buf of len bytes. */
PetscErrorCode SpamModelSettingsJson(const SpamModel *m, char *buf, size_t len);
#endif
