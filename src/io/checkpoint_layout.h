/* Internal to src/io: what the checkpoint writer (checkpoint_write.c) and reader
 * (checkpoint_read.c) share with the in-memory file (checkpoint_file.c). */
#ifndef SPAM_CHECKPOINT_LAYOUT_H
#define SPAM_CHECKPOINT_LAYOUT_H
#include <spam/checkpoint_file.h>
#include <hdf5.h>
#include <sys/stat.h>

#define SPAM_CK_GROUP "/checkpoint"
/* A checkpoint of several ranks: their per-particle entries (checkpoint_file.h) */
#define SPAM_CK_RANKS_GROUP "/particles"

/* The layout's name rule (checkpoint_file.h): also a valid HDF5 link name. */
PetscBool SpamCkNameValid(const char *name);
/* The root attribute checksum of c's entries (the hash the header describes). */
uint64_t SpamCkChecksum(const SpamCkFile *c);
/* Puts an entry whose data c takes over (PetscMalloc'ed: n doubles, n int64_t, or n + 1
 * bytes of text ending in NUL); on error the data is freed. */
PetscErrorCode SpamCkAdopt(SpamCkFile *c, const char *name, SpamCkKind kind, size_t n, void *data);
/* The bytes one value of kind takes (text: 1). */
size_t SpamCkValueSize(SpamCkKind kind);

/* HDF5 quiet: its automatic error-stack print switched off, and put back as it was. */
typedef struct {
  H5E_auto2_t func;
  void       *data;
} SpamH5Quiet;
void SpamH5QuietBegin(SpamH5Quiet *q);
void SpamH5QuietEnd(const SpamH5Quiet *q);
/* The innermost (most specific) message on HDF5's error stack, e.g. "truncated file: eof =
 * ...", or "no HDF5 reason given". */
void SpamH5Reason(char *buf, size_t len);
/* File access of a checkpoint: the HDF5 1.8 object format (checksummed metadata) and every
 * object closed with the file. Negative on failure. */
hid_t SpamCkFileAccess(void);

/* The temporary a checkpoint is written into (rank 0 makes it, renames it when complete). */
typedef struct {
  char        tmp[PETSC_MAX_PATH_LEN + 32];
  int         fd;
  struct stat made; /* what was created: checked again before the rename */
} SpamCkTemp;
/* path.PID.tmp created new (O_EXCL | O_NOFOLLOW) and kept open; a failure names path. */
PetscErrorCode SpamCkTempCreate(const char *path, SpamCkTemp *t);
/* c's entries written into *file, an in-memory file (SpamH5MemoryCreate; -1: created here),
 * which is then closed, its image written through the temporary's descriptor, synced,
 * renamed over path, the directory synced; on failure the temporary is removed. fail_at:
 * the test's injected failure at that entry (0: none). */
PetscErrorCode SpamCkTempFinish(const SpamCkFile *c, const char *path, SpamCkTemp *t, hid_t *file, long fail_at, size_t *bytes);
/* Closed and removed (a failure elsewhere). */
void SpamCkTempDiscard(SpamCkTemp *t);
#endif
