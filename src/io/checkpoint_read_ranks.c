/* Reading this rank's part of a checkpoint of several ranks (checkpoint_write_ranks.c):
 * the table in the shared entries (already read and checksummed) says where its block of
 * each /particles dataset lies; the block is read and checked against the rank's own
 * checksum, so a damaged byte of the particles is refused as one of the entries is. */
#define _DEFAULT_SOURCE /* strtok_r: POSIX, not C11 */
#include "checkpoint_layout.h"

#define BAD(path, fmt, ...) PetscError(PETSC_COMM_SELF, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_USER_INPUT, PETSC_ERROR_INITIAL, "checkpoint %s: " fmt, path, ##__VA_ARGS__)

PetscErrorCode SpamCkFileRanks(const SpamCkFile *shared, PetscMPIInt *ranks)
{
  size_t n = 1;

  PetscFunctionBeginUser;
  if (SpamCkHas(shared, SPAM_CK_RANK_CHECKSUMS)) PetscCall(SpamCkGetLength(shared, SPAM_CK_RANK_CHECKSUMS, &n));
  PetscCheck(n >= 1 && n <= INT32_MAX, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: written on %zu ranks: damaged", shared->path, n);
  *ranks = (PetscMPIInt)n;
  PetscFunctionReturn(0);
}

typedef struct {
  const char    *path;
  hid_t          group;
  PetscMPIInt    rank, size;
  int            nb;
  const int64_t *len; /* [size * nb] */
} RankReader;

/* Block b (named name) of this rank: kind from the dataset's type, checked against the
 * table (total length) and read from its offset. */
static PetscErrorCode ReadBlock(const RankReader *r, int b, const char *name, SpamCkFile *mine)
{
  hsize_t    total = 0, off = 0, count, dims[1];
  hid_t      set = -1, space = -1, type = -1, mem = -1;
  SpamCkKind kind  = SPAM_CK_REAL;
  PetscBool  shape = PETSC_FALSE;
  herr_t     st    = -1;
  double    *data;

  PetscFunctionBeginUser;
  for (PetscMPIInt q = 0; q < r->size; q++) {
    const int64_t l = r->len[(size_t)q * r->nb + b];
    if (l < 0) PetscCall(BAD(r->path, "rank %d's entry '%s' has length %lld: damaged", (int)q, name, (long long)l));
    total += (hsize_t)l;
    if (q < r->rank) off += (hsize_t)l;
  }
  count = (hsize_t)r->len[(size_t)r->rank * r->nb + b];
  if (!SpamCkNameValid(name) || (set = H5Dopen2(r->group, name, H5P_DEFAULT)) < 0) PetscCall(BAD(r->path, "no dataset " SPAM_CK_RANKS_GROUP "/%s: damaged", name));
  if ((space = H5Dget_space(set)) >= 0 && (type = H5Dget_type(set)) >= 0 && H5Sget_simple_extent_ndims(space) == 1 && H5Sget_simple_extent_dims(space, dims, NULL) == 1 && dims[0] == total) {
    if (H5Tequal(type, H5T_IEEE_F64LE) > 0) shape = PETSC_TRUE;
    else if (H5Tequal(type, H5T_STD_I64LE) > 0) shape = PETSC_TRUE, kind = SPAM_CK_INT;
  }
  data = NULL;
  if (shape && PetscMalloc1(count + 1, &data) == 0 && (mem = H5Screate_simple(1, &count, NULL)) >= 0) {
    if (!count) st = 0;
    else if (H5Sselect_hyperslab(space, H5S_SELECT_SET, &off, NULL, &count, NULL) >= 0) st = H5Dread(set, kind == SPAM_CK_REAL ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT64, mem, space, H5P_DEFAULT, data);
  }
  if (mem >= 0) (void)H5Sclose(mem);
  if (type >= 0) (void)H5Tclose(type);
  if (space >= 0) (void)H5Sclose(space);
  (void)H5Dclose(set);
  if (st < 0) {
    PetscCall(PetscFree(data));
    if (!shape) PetscCall(BAD(r->path, "dataset " SPAM_CK_RANKS_GROUP "/%s is not [%llu] 64-bit reals or integers as its table says: damaged", name, (unsigned long long)total));
    PetscCall(BAD(r->path, "cannot read rank %d's block of " SPAM_CK_RANKS_GROUP "/%s: truncated or damaged", (int)r->rank, name));
  }
  PetscCall(SpamCkAdopt(mine, name, kind, (size_t)count, data));
  PetscFunctionReturn(0);
}

/* This rank's blocks, named in the table, from the open file. */
static PetscErrorCode ReadBlocks(const SpamCkFile *shared, hid_t file, PetscMPIInt rank, SpamCkFile *mine)
{
  RankReader     r = {shared->path, -1, rank, 0, 0, NULL};
  const char    *names;
  const int64_t *sums;
  char           list[4096], *name, *save = NULL;
  size_t         len, nlen;
  uint64_t       want, got;
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCall(SpamCkFileRanks(shared, &r.size));
  PetscCall(SpamCkGetText(shared, SPAM_CK_RANK_BLOCKS, &names, &len));
  PetscCheck(len < sizeof list, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: its list of particle entries is %zu bytes long: damaged", r.path, len);
  PetscCall(PetscStrncpy(list, names, sizeof list));
  for (size_t i = 0; i < len; i++) r.nb += list[i] == ',';
  r.nb += len > 0;
  PetscCall(SpamCkGetLength(shared, SPAM_CK_RANK_LENGTHS, &nlen));
  PetscCheck(nlen == (size_t)r.size * r.nb, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: its table of particle blocks has %zu lengths for %d ranks and %d entries: damaged", r.path, nlen, (int)r.size, r.nb);
  PetscCall(SpamCkGetInt(shared, SPAM_CK_RANK_LENGTHS, nlen, &r.len));
  PetscCall(SpamCkGetInt(shared, SPAM_CK_RANK_CHECKSUMS, (size_t)r.size, &sums));
  if ((r.group = H5Gopen2(file, SPAM_CK_RANKS_GROUP, H5P_DEFAULT)) < 0) PetscCall(BAD(r.path, "no group " SPAM_CK_RANKS_GROUP ": damaged"));
  name = strtok_r(list, ",", &save);
  for (int b = 0; !ierr && b < r.nb; b++, name = strtok_r(NULL, ",", &save)) ierr = name ? ReadBlock(&r, b, name, mine) : BAD(r.path, "an empty name in its list of particle entries: damaged");
  (void)H5Gclose(r.group);
  PetscCall(ierr);
  got = SpamCkChecksum(mine);
  memcpy(&want, &sums[rank], sizeof want);
  PetscCheck(got == want, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: rank %d's particles disagree with their checksum (stored %016llx, computed %016llx): damaged", r.path, (int)rank, (unsigned long long)want, (unsigned long long)got);
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadHere(const SpamCkFile *shared, PetscMPIInt rank, SpamCkFile *mine)
{
  SpamH5Quiet    quiet;
  hid_t          fapl, file = -1;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  SpamH5QuietBegin(&quiet);
  if ((fapl = SpamCkFileAccess()) >= 0) file = H5Fopen(shared->path, H5F_ACC_RDONLY, fapl);
  if (fapl >= 0) (void)H5Pclose(fapl);
  ierr = file < 0 ? BAD(shared->path, "HDF5 cannot open it again for the particles") : ReadBlocks(shared, file, rank, mine);
  if (file >= 0) (void)H5Fclose(file);
  /* after a refusal HDF5's printing stays off, as checkpoint_read.c says why */
  if (!ierr) SpamH5QuietEnd(&quiet);
  else (void)H5Eclear2(H5E_DEFAULT);
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

PetscErrorCode SpamCkFileReadRank(MPI_Comm comm, const SpamCkFile *shared, SpamCkFile *mine)
{
  PetscMPIInt    rank;
  PetscErrorCode ierr;
  int            failed, any;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(SpamCkFileInit(mine));
  PetscCall(PetscStrncpy(mine->path, shared->path, sizeof mine->path));
  ierr   = ReadHere(shared, rank, mine);
  failed = ierr ? 1 : 0;
  /* Every rank learns whether all could read their part, so that none goes on alone. */
  PetscCallMPI(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm));
  if (ierr) PetscCall(SpamCkFileDestroy(mine));
  PetscCall(ierr);
  PetscCheck(!any, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint %s: another rank cannot read its particles", shared->path);
  PetscFunctionReturn(0);
}
