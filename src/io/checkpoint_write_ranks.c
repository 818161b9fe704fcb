/* A checkpoint of several ranks (checkpoint_file.h): each rank's per-particle entries go
 * into one dataset per entry, /particles/NAME, every rank writing its own block at its
 * offset, collectively through MPI-IO as the snapshots are written (snapshot_hdf5.c);
 * then rank 0 adds the shared entries and the table that says where each rank's block is,
 * and renames the temporary as a one-rank checkpoint is renamed (checkpoint_write.c).
 * Why blocks in rank order and not rows by gid: a restart on the same ranks takes each
 * rank's particles back in their local order, which is what makes it bitwise, and each
 * rank then reads one contiguous piece of each dataset. */
#define _DEFAULT_SOURCE /* getenv of the test's failure rank: C11, but kept beside the others */
#include "checkpoint_layout.h"
#include "snapshot_hdf5.h"
#include <spam/output.h>
#include <errno.h>
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

/* Whether a write succeeded on every rank (a failure on one rank must send all of them
 * down the failure path together, or the others wait in the next collective call). */
static PetscErrorCode Agreed(const RanksWriter *w, herr_t mine, PetscBool *all)
{
  int ok = mine >= 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_LAND, w->comm));
  *all = (PetscBool)ok;
  PetscFunctionReturn(0);
}

/* Entry b of every rank as /particles/NAME, this rank's block at its offset. *mine: this
 * rank's own write failed (errno kept), *all: some rank's did. */
static PetscErrorCode WriteBlock(RanksWriter *w, hid_t group, hid_t dxpl, int b, long *writes, herr_t *mine, PetscBool *all)
{
  const SpamCkEntry *e  = &w->mine->e[b];
  const int          nb = w->mine->n;
  hsize_t            total = 0, off = 0, count = e->n;
  hid_t              dcpl, space, mem = -1, set = -1;
  const hid_t        ftype = e->kind == SPAM_CK_REAL ? H5T_IEEE_F64LE : H5T_STD_I64LE, mtype = e->kind == SPAM_CK_REAL ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT64;

  PetscFunctionBeginUser;
  for (PetscMPIInt r = 0; r < w->size; r++) {
    total += (hsize_t)w->len[(size_t)r * nb + b];
    if (r < w->rank) off += (hsize_t)w->len[(size_t)r * nb + b];
  }
  *mine = -1;
  dcpl  = SpamH5Untimed(H5P_DATASET_CREATE);
  /* Every value is written: no fill value first (parallel HDF5 would write the file twice). */
  if (dcpl >= 0 && H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER) >= 0 && (space = H5Screate_simple(1, &total, NULL)) >= 0) {
    set = H5Dcreate2(group, e->name, ftype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    if (set >= 0 && (mem = H5Screate_simple(1, &count, NULL)) >= 0) {
      /* The injected failure still joins the collective write, with nothing selected. */
      const PetscBool fail = (PetscBool)(++*writes == w->fail_at);
      const herr_t    sel  = count && !fail ? H5Sselect_hyperslab(space, H5S_SELECT_SET, &off, NULL, &count, NULL) : (H5Sselect_none(space) < 0 || H5Sselect_none(mem) < 0 ? -1 : 0);
      errno = 0;
      if (sel >= 0) *mine = H5Dwrite(set, mtype, mem, space, dxpl, e->data);
      if (fail) *mine = -1, errno = ENOSPC;
    }
    (void)H5Sclose(space);
  }
  {
    const int err = errno;
    PetscCall(Agreed(w, *mine, all));
    errno = err;
  }
  if (mem >= 0) (void)H5Sclose(mem);
  if (set >= 0 && H5Dclose(set) < 0 && *mine >= 0) *mine = -1;
  if (dcpl >= 0) (void)H5Pclose(dcpl);
  PetscFunctionReturn(0);
}

/* Every rank: the temporary made by rank 0 opened through MPI-IO and every block written.
 * Only a rank whose own write failed reports (its reason, one line for all). */
static PetscErrorCode WriteBlocks(void *ctx)
{
  RanksWriter *w    = ctx;
  hid_t        fapl = SpamCkFileAccess(), fcpl = SpamH5Untimed(H5P_FILE_CREATE), gcpl = SpamH5Untimed(H5P_GROUP_CREATE), dxpl = H5Pcreate(H5P_DATASET_XFER), file = -1, group = -1;
  herr_t       mine = -1;
  PetscBool    all  = PETSC_FALSE;
  long         writes = 0;
  int          err = 0;

  PetscFunctionBeginUser;
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* one line instead of HDF5's error stack */
  errno = 0;
  if (fapl >= 0 && fcpl >= 0 && gcpl >= 0 && dxpl >= 0 && H5Pset_fapl_mpio(fapl, w->comm, MPI_INFO_NULL) >= 0 && H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE) >= 0) file = H5Fcreate(w->t.tmp, H5F_ACC_TRUNC, fcpl, fapl);
  if (file >= 0) group = H5Gcreate2(file, SPAM_CK_RANKS_GROUP, H5P_DEFAULT, gcpl, H5P_DEFAULT);
  err = errno;
  PetscCall(Agreed(w, group >= 0 ? 0 : -1, &all));
  mine = group >= 0 ? 0 : -1;
  for (int b = 0; all && b < w->mine->n; b++) {
    PetscCall(WriteBlock(w, group, dxpl, b, &writes, &mine, &all));
    err = errno;
  }
  if (group >= 0 && H5Gclose(group) < 0 && mine >= 0) mine = -1;
  if (file >= 0 && H5Fclose(file) < 0 && mine >= 0) mine = -1, err = errno;
  if (dxpl >= 0) (void)H5Pclose(dxpl);
  if (gcpl >= 0) (void)H5Pclose(gcpl);
  if (fcpl >= 0) (void)H5Pclose(fcpl);
  if (fapl >= 0) (void)H5Pclose(fapl);
  (void)H5Eclear2(H5E_DEFAULT);
  PetscCheck(mine >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s (rank %d's particles): %s", w->path, (int)w->rank, strerror(err ? err : EIO));
  PetscFunctionReturn(0);
}

static PetscErrorCode CreateTemp(void *ctx)
{
  RanksWriter *w = ctx;

  PetscFunctionBeginUser;
  PetscCall(SpamCkTempCreate(w->path, &w->t));
  PetscFunctionReturn(0);
}

static PetscErrorCode Finish(void *ctx)
{
  RanksWriter *w = ctx;

  PetscFunctionBeginUser;
  PetscCall(SpamCkTempFinish(w->shared, w->path, &w->t, PETSC_TRUE, w->fail_root, &w->bytes));
  PetscFunctionReturn(0);
}

static PetscErrorCode Discard(void *ctx)
{
  RanksWriter *w = ctx;

  PetscFunctionBeginUser;
  SpamCkTempDiscard(&w->t);
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
  PetscCallMPI(MPI_Comm_rank(comm, &w.rank));
  PetscCallMPI(MPI_Comm_size(comm, &w.size));
  InjectedFailure(&w);
  ierr = DescribeBlocks(&w); /* the same entries on every rank: fails alike on all, if at all */
  if (!ierr) ierr = SpamRunAgreed(comm, PETSC_TRUE, CreateTemp, &w);
  if (!ierr) {
    PetscCallMPI(MPI_Bcast(w.t.tmp, (int)sizeof w.t.tmp, MPI_CHAR, 0, comm));
    ierr = SpamRunAgreed(comm, PETSC_FALSE, WriteBlocks, &w);
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
