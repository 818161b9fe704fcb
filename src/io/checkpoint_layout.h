/* Internal to src/io: what the checkpoint writer (checkpoint_write.c) and reader
 * (checkpoint_read.c) share with the in-memory file (checkpoint_file.c). */
#ifndef SPAM_CHECKPOINT_LAYOUT_H
#define SPAM_CHECKPOINT_LAYOUT_H
#include <spam/checkpoint_file.h>
#include <hdf5.h>

#define SPAM_CK_GROUP "/checkpoint"

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
#endif
