/* A checkpoint file: named arrays (reals, integers, text) in one HDF5 file. This is the
 * storage layer only: what a run puts into its checkpoint is decided by the time loop.
 *
 * Layout (read it with `h5dump -A file.h5`, one entry with `h5dump -d /checkpoint/NAME`):
 *   /                    root attributes
 *     format             "spam-ark checkpoint 1" (fixed-length string): layout and version
 *     units_convention   what the numbers mean (reduced units), as in the snapshots
 *     entries            int64: the number of datasets in /checkpoint
 *     checksum           uint64: 64-bit FNV-1a over every entry in name order (strcmp) of
 *                        its name and NUL, kind ('R', 'I' or 'T'), length as 8 bytes
 *                        little-endian, and its bytes (each value 8 bytes little-endian;
 *                        text as is). Each byte passes through an invertible step of the
 *                        hash, so a change confined to one byte always changes the sum.
 *   /checkpoint          one dataset per entry, contiguous:
 *     REAL               [n] 64-bit IEEE little-endian (bits kept: NaN payloads, -0.0,
 *                        subnormals)
 *     INT                [n] 64-bit signed little-endian
 *     TEXT               scalar fixed-length string of len + 1 bytes: the text and a NUL
 *                        (any bytes, NULs included; "" is one NUL byte)
 * The file uses the HDF5 1.8 object format, whose metadata carries checksums that the
 * library verifies; HDF5 1.8 or later reads it.
 *
 * Names: 1 to 63 bytes of letters, digits, '_', '-' and '.', not starting with '.'.
 *
 * Written on P > 1 ranks (SpamCkFileWriteRanks) the file holds, besides the entries
 * above (rank 0's: the same on every rank), each rank's own entries (its particles):
 *   /particles           one dataset per entry name, every rank's values in rank order:
 *     NAME               [sum of the ranks' lengths] 64-bit reals or integers as above
 *   /checkpoint/rank_blocks     TEXT: the names of /particles, comma-separated, in order
 *   /checkpoint/rank_lengths    INT [P * blocks]: rank r's length of block b at r*blocks + b
 *   /checkpoint/rank_checksums  INT [P]: each rank's entries hashed as the root checksum
 *                               hashes /checkpoint (the 64 bits as a signed integer)
 * The root checksum covers the table, each rank's checksum its block: one damaged byte
 * anywhere is refused. A file without rank_checksums was written on one rank. */
#ifndef SPAM_CHECKPOINT_FILE_H
#define SPAM_CHECKPOINT_FILE_H
#include <petscsys.h>
#include <stdint.h>

#define SPAM_CK_FORMAT "spam-ark checkpoint 1"

typedef enum { SPAM_CK_REAL, SPAM_CK_INT, SPAM_CK_TEXT } SpamCkKind;

typedef struct {
  char       name[64];
  SpamCkKind kind;
  size_t     n;    /* values; for TEXT its length in bytes                     */
  void      *data; /* n doubles or int64_t; TEXT: n bytes and a NUL after them */
} SpamCkEntry;

typedef struct {
  SpamCkEntry *e; /* [cap], the first n in use, sorted by name (strcmp) */
  int          n, cap;
  char         path[PETSC_MAX_PATH_LEN]; /* the file it was read from (messages); "" if none */
} SpamCkFile;

PetscErrorCode SpamCkFileInit(SpamCkFile *c);
/* Frees every entry; c is then empty, as after Init. */
PetscErrorCode SpamCkFileDestroy(SpamCkFile *c);

/* Put* copy the data (n may be 0, then v may be NULL); a name put twice replaces the entry,
 * whatever its kind. A name outside the rule above is a program error (PETSC_ERR_ARG_WRONG). */
PetscErrorCode SpamCkPutReal(SpamCkFile *c, const char *name, size_t n, const double *v);
PetscErrorCode SpamCkPutInt(SpamCkFile *c, const char *name, size_t n, const int64_t *v);
/* len bytes of s, any bytes including NUL. */
PetscErrorCode SpamCkPutText(SpamCkFile *c, const char *name, const char *s, size_t len);
/* One value: a REAL or INT entry of length 1. */
PetscErrorCode SpamCkPutScalar(SpamCkFile *c, const char *name, double v);
PetscErrorCode SpamCkPutLong(SpamCkFile *c, const char *name, long v);

/* Writes every entry to path: to a new temporary beside it (path.PID.tmp, created
 * exclusively), flushed and fsync'ed, then renamed over path and the directory fsync'ed, so
 * the previous checkpoint at path stays whole until the new one is complete. A failure
 * removes the temporary and raises PETSC_ERR_FILE_WRITE with one line naming the file and
 * the system's reason. *bytes (may be NULL): the file's size. Rank 0 of comm writes; every
 * rank returns the same error code. */
PetscErrorCode SpamCkFileWrite(MPI_Comm comm, const SpamCkFile *c, const char *path, size_t *bytes);

/* Reads every entry of path into c, which this initialises (pass a destroyed or fresh
 * one). A missing or unreadable file, a file that is not HDF5, a truncated one, one without
 * this layout or format version, or one whose checksum disagrees with its contents raises
 * PETSC_ERR_USER_INPUT with one line "checkpoint PATH: <what is wrong>"; HDF5 prints
 * nothing: its automatic error printing is off during the read and put back after a
 * success, but left off after a refusal (HDF5 1.10.8 would print at exit after some
 * damaged files, see checkpoint_read.c). On failure c is left empty (Destroy is still
 * allowed). Every rank of comm reads the file; if one fails, all fail. */
PetscErrorCode SpamCkFileRead(MPI_Comm comm, const char *path, SpamCkFile *c);

#define SPAM_CK_RANK_BLOCKS    "rank_blocks"
#define SPAM_CK_RANK_LENGTHS   "rank_lengths"
#define SPAM_CK_RANK_CHECKSUMS "rank_checksums"

/* A checkpoint of several ranks: shared's entries (the same on every rank; rank 0 writes
 * them, with the table above added to shared) and each rank's own entries, mine (the same
 * names and kinds on every rank, reals or integers, any lengths), written collectively
 * through MPI-IO into /particles. Atomic as SpamCkFileWrite: one temporary, renamed by
 * rank 0 once every rank has written. A failure on any rank ends every rank with that
 * rank's one line (PETSC_ERR_FILE_WRITE) and leaves the previous checkpoint. Test only:
 * SPAM_TEST_FAIL_WRITE=NAME:K with SPAM_TEST_FAIL_RANK=r fails rank r's K-th write
 * (its blocks, then on rank 0 the shared entries). Collective. */
PetscErrorCode SpamCkFileWriteRanks(MPI_Comm comm, SpamCkFile *shared, const SpamCkFile *mine, const char *path, size_t *bytes);
/* The number of ranks that wrote a checkpoint read by SpamCkFileRead (1: one rank). */
PetscErrorCode SpamCkFileRanks(const SpamCkFile *shared, PetscMPIInt *ranks);
/* This rank's own entries of a checkpoint of as many ranks as comm has, into mine (which
 * this initialises); shared: the file as SpamCkFileRead read it. A damaged block or table
 * is refused as SpamCkFileRead refuses; if one rank fails, all fail. Collective. */
PetscErrorCode SpamCkFileReadRank(MPI_Comm comm, const SpamCkFile *shared, SpamCkFile *mine);

/* The entry of that name and kind. Missing, of another kind, or (n > 0) of another length:
 * PETSC_ERR_USER_INPUT, one line naming the file and the entry. The pointers stay valid
 * until c changes. */
PetscErrorCode SpamCkGetReal(const SpamCkFile *c, const char *name, size_t n, const double **v);
PetscErrorCode SpamCkGetInt(const SpamCkFile *c, const char *name, size_t n, const int64_t **v);
/* s is NUL-terminated as well; *len (may be NULL) counts the bytes without that NUL. */
PetscErrorCode SpamCkGetText(const SpamCkFile *c, const char *name, const char **s, size_t *len);
/* A REAL or INT entry of length 1. */
PetscErrorCode SpamCkGetScalar(const SpamCkFile *c, const char *name, double *v);
PetscErrorCode SpamCkGetLong(const SpamCkFile *c, const char *name, long *v);
/* The length of the entry (values, or bytes of text); missing: as the getters. */
PetscErrorCode SpamCkGetLength(const SpamCkFile *c, const char *name, size_t *n);
PetscBool      SpamCkHas(const SpamCkFile *c, const char *name);
#endif
