/* A checkpoint of several ranks (checkpoint_file.h): each rank's per-particle entries go
 * into one dataset per entry, /particles/NAME, every rank's block at its offset in rank
 * order; rank 0 gathers the blocks one entry at a time into the file it builds in memory,
 * adds the shared entries and the table that says where each rank's block is, and writes
 * and renames the temporary as a one-rank checkpoint (checkpoint_write.c). Why rank 0 and
 * not every rank through MPI-IO: MPI-IO opens the temporary by name on every rank, and a
 * name opened again after its exclusive create can be swapped for a symlink in between.
 * Why blocks in rank order and not rows by gid: a restart on the same ranks takes each
 * rank's particles back in their local order, which is what makes it bitwise, and each
 * rank then reads one contiguous piece of each dataset. */
#define _DEFAULT_SOURCE /* getenv of the test's failure rank: C11, but kept beside the others */
#include "checkpoint_layout.h"
#include "snapshot_hdf5.h"
#include <spam/output.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>

typedef struct {
  MPI_Comm          comm;
  PetscMPIInt       rank, size;
  const char       *path;
  SpamCkFile       *shared;
  const SpamCkFile *mine;
  int64_t          *len;      /* [size * mine->n]: rank r's length of entry b at r * n + b */
  long              fail_at;  /* test only: this rank's block write that fails (0: none)    */
  long              fail_root; /* test only: rank 0's entry write that fails (0: none)      */
  SpamCkTemp        t;
  hid_t             file, group; /* rank 0: the file in memory and its /particles        */
  size_t            bytes;
} RanksWriter;

/* The test's injected failure (SPAM_TEST_FAIL_WRITE=checkpoint.h5:K): the K-th dataset
 * write of rank SPAM_TEST_FAIL_RANK (default 0), counting this rank's blocks first and
 * then, on rank 0, the shared entries. */
static void InjectedFailure(RanksWriter *w)
{
  const long  k   = SpamTestFailWriteAt(w->path);
  const char *env = getenv("SPAM_TEST_FAIL_RANK");
  const long  on  = env ? strtol(env, NULL, 10) : 0;

  w->fail_at   = on == w->rank && k <= w->mine->n ? k : 0;
  w->fail_root = on == 0 && k > w->mine->n ? k - w->mine->n : 0;
}

/* Every rank's lengths and checksum, and into shared the entries that describe them. */
static PetscErrorCode DescribeBlocks(RanksWriter *w)
{
  const int  nb = w->mine->n;
  int64_t   *mylen, *sums, sum;
  uint64_t   hash = SpamCkChecksum(w->mine);
  size_t     chars = 1;
  char      *names;

  PetscFunctionBeginUser;
  memcpy(&sum, &hash, sizeof sum); /* the hash's bits as an integer entry */
  for (int b = 0; b < nb; b++) PetscCheck(w->mine->e[b].kind != SPAM_CK_TEXT, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "checkpoint entry '%s': a rank's entries are reals or integers", w->mine->e[b].name);
  PetscCall(PetscMalloc1(nb + 1, &mylen));
  PetscCall(PetscMalloc1((size_t)w->size * nb + 1, &w->len));
  PetscCall(PetscMalloc1(w->size, &sums));
  for (int b = 0; b < nb; b++) {
    mylen[b] = (int64_t)w->mine->e[b].n;
    chars += strlen(w->mine->e[b].name) + 1;
  }
  PetscCallMPI(MPI_Allgather(mylen, nb, MPI_INT64_T, w->len, nb, MPI_INT64_T, w->comm));
  PetscCallMPI(MPI_Allgather(&sum, 1, MPI_INT64_T, sums, 1, MPI_INT64_T, w->comm));
  PetscCall(PetscCalloc1(chars, &names));
  for (int b = 0; b < nb; b++) {
    if (b) PetscCall(PetscStrlcat(names, ",", chars));
    PetscCall(PetscStrlcat(names, w->mine->e[b].name, chars));
  }
  PetscCall(SpamCkPutText(w->shared, SPAM_CK_RANK_BLOCKS, names, strlen(names)));
  PetscCall(SpamCkPutInt(w->shared, SPAM_CK_RANK_LENGTHS, (size_t)w->size * nb, w->len));
  PetscCall(SpamCkPutInt(w->shared, SPAM_CK_RANK_CHECKSUMS, (size_t)w->size, sums));
  PetscCall(PetscFree(names));
  PetscCall(PetscFree(mylen));
  PetscCall(PetscFree(sums));
  PetscFunctionReturn(0);
}

/* Rank 0: the gathered entry b of every rank (data, total values) as /particles/NAME. */
static herr_t WriteGathered(RanksWriter *w, int b, hsize_t total, const void *data)
{
  const SpamCkEntry *e     = &w->mine->e[b];
  const hid_t        ftype = e->kind == SPAM_CK_REAL ? H5T_IEEE_F64LE : H5T_STD_I64LE, mtype = e->kind == SPAM_CK_REAL ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT64;
  const hid_t        dcpl  = SpamH5Untimed(H5P_DATASET_CREATE);
  hid_t              space = -1, set = -1;
  herr_t             st    = -1;

  if (dcpl >= 0 && (space = H5Screate_simple(1, &total, NULL)) >= 0) set = H5Dcreate2(w->group, e->name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (set >= 0) st = total ? H5Dwrite(set, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
  if (set >= 0 && H5Dclose(set) < 0) st = -1;
  if (space >= 0) (void)H5Sclose(space);
  if (dcpl >= 0) (void)H5Pclose(dcpl);
  return st;
}

/* Entry b of every rank gathered on rank 0 (counts from w->len) into buf, [total] values. */
static PetscErrorCode GatherEntry(RanksWriter *w, int b, void *buf, hsize_t *total)
{
  const SpamCkEntry *e  = &w->mine->e[b];
  const int          nb = w->mine->n;
  PetscMPIInt       *counts = NULL, *displs = NULL;
  const MPI_Datatype type = e->kind == SPAM_CK_REAL ? MPI_DOUBLE : MPI_INT64_T;

  PetscFunctionBeginUser;
  *total = 0;
  if (!w->rank) {
    PetscCall(PetscMalloc2(w->size, &counts, w->size, &displs));
    for (PetscMPIInt r = 0; r < w->size; r++) {
      PetscCall(PetscMPIIntCast(w->len[(size_t)r * nb + b], &counts[r]));
      PetscCall(PetscMPIIntCast((PetscInt64)*total, &displs[r]));
      *total += (hsize_t)counts[r];
    }
  }
  /* a rank whose own part failed still sends its block: the counts must match */
  PetscCallMPI(MPI_Gatherv(e->data, (PetscMPIInt)e->n, type, buf, counts, displs, type, 0, w->comm));
  PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* Every rank: each entry's blocks gathered into rank 0's file. A rank whose own part
 * failed (rank 0: its HDF5 write; any rank: the test's injected failure) says so in one
 * line; every rank takes part in every gather first, so none is left waiting. */
static PetscErrorCode GatherBlocks(void *ctx)
{
  RanksWriter *w      = ctx;
  long         writes = 0;
  int          err    = 0;

  PetscFunctionBeginUser;
  for (int b = 0; b < w->mine->n; b++) {
    const PetscBool fail  = (PetscBool)(++writes == w->fail_at);
    int64_t         total = 0;
    hsize_t         got;
    void           *buf  = NULL;
    PetscErrorCode  ierr = 0;
    int             ready;

    if (fail && !err) err = ENOSPC;
    /* the lengths are known on every rank: a count past MPI's int fails on all alike */
    for (PetscMPIInt r = 0; r < w->size; r++) total += w->len[(size_t)r * w->mine->n + b];
    PetscCheck(total <= INT_MAX, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: entry '%s' holds %lld values, more than one gather carries", w->path, w->mine->e[b].name, (long long)total);
    if (!w->rank) ierr = PetscMalloc((size_t)total * 8 + 1, &buf);
    /* rank 0 without its buffer: no rank enters the gather (none would leave it) */
    ready = !ierr;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &ready, 1, MPI_INT, MPI_LAND, w->comm));
    PetscCall(ierr);
    PetscCheck(ready, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s: rank 0 has no memory for the particles", w->path);
    PetscCall(GatherEntry(w, b, buf, &got));
    errno = 0;
    if (!w->rank && !err && WriteGathered(w, b, got, buf) < 0) err = errno ? errno : EIO;
    PetscCall(PetscFree(buf));
  }
  PetscCheck(!err, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s (rank %d's particles): %s", w->path, (int)w->rank, strerror(err));
  PetscFunctionReturn(0);
}

/* Rank 0: the temporary created new and kept open, and the file begun in memory. */
static PetscErrorCode CreateTemp(void *ctx)
{
  RanksWriter *w = ctx;
  hid_t        fapl, fcpl, gcpl;

  PetscFunctionBeginUser;
  PetscCall(SpamCkTempCreate(w->path, &w->t));
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* one line instead of HDF5's error stack */
  fapl  = SpamCkFileAccess();
  fcpl  = SpamH5Untimed(H5P_FILE_CREATE);
  gcpl  = SpamH5Untimed(H5P_GROUP_CREATE);
  errno = 0;
  if (fapl >= 0 && fcpl >= 0 && gcpl >= 0 && (w->file = SpamH5MemoryCreate(w->t.tmp, fcpl, fapl)) >= 0) w->group = H5Gcreate2(w->file, SPAM_CK_RANKS_GROUP, H5P_DEFAULT, gcpl, H5P_DEFAULT);
  if (gcpl >= 0) (void)H5Pclose(gcpl);
  if (fcpl >= 0) (void)H5Pclose(fcpl);
  if (fapl >= 0) (void)H5Pclose(fapl);
  if (w->group < 0) PetscCall(SpamH5Failed(w->path)); /* Discard closes what was made */
  PetscFunctionReturn(0);
}

static PetscErrorCode Finish(void *ctx)
{
  RanksWriter *w = ctx;

  PetscFunctionBeginUser;
  if (H5Gclose(w->group) < 0) {
    SpamH5MemoryClose(&w->file);
    SpamCkTempDiscard(&w->t);
    PetscCall(SpamH5Failed(w->path));
  }
  w->group = -1;
  PetscCall(SpamCkTempFinish(w->shared, w->path, &w->t, &w->file, w->fail_root, &w->bytes));
  PetscFunctionReturn(0);
}

static PetscErrorCode Discard(void *ctx)
{
  RanksWriter *w = ctx;

  PetscFunctionBeginUser;
  if (w->group >= 0) (void)H5Gclose(w->group);
  w->group = -1;
  SpamH5MemoryClose(&w->file); /* closes whatever an error path left open in it */
  if (w->t.fd >= 0) SpamCkTempDiscard(&w->t); /* a failed create left no temporary of ours */
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkFileWriteRanks(MPI_Comm comm, SpamCkFile *shared, const SpamCkFile *mine, const char *path, size_t *bytes)
{
  RanksWriter        w;
  PetscErrorCode     ierr;
  unsigned long long size;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&w, sizeof w));
  w.comm   = comm;
  w.path   = path;
  w.shared = shared;
  w.mine   = mine;
  w.t.fd   = -1;
  w.file   = -1;
  w.group  = -1;
  PetscCallMPI(MPI_Comm_rank(comm, &w.rank));
  PetscCallMPI(MPI_Comm_size(comm, &w.size));
  InjectedFailure(&w);
  ierr = DescribeBlocks(&w); /* the same entries on every rank: fails alike on all, if at all */
  if (!ierr) ierr = SpamRunAgreed(comm, PETSC_TRUE, CreateTemp, &w);
  if (ierr) (void)SpamRunAgreed(comm, PETSC_TRUE, Discard, &w);
  else {
    ierr = SpamRunAgreed(comm, PETSC_FALSE, GatherBlocks, &w);
    if (ierr) (void)SpamRunAgreed(comm, PETSC_TRUE, Discard, &w);
    else ierr = SpamRunAgreed(comm, PETSC_TRUE, Finish, &w);
  }
  PetscCall(PetscFree(w.len));
  PetscCall(ierr);
  size = w.bytes;
  PetscCallMPI(MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, comm));
  if (bytes) *bytes = (size_t)size;
  PetscFunctionReturn(0);
}
