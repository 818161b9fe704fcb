/* The HDF5 snapshot's checksum: its first 512 bytes are an HDF5 user block (the library
 * skips it; h5py, h5dump and ParaView read the file as before) holding one line of text,
 * the 64-bit FNV-1a hash of every byte after the block, padded with NULs.
 *
 * Why the whole file and not the datasets: a checksum over the bytes covers every byte
 * HDF5 will parse (object headers, attributes, the ids' type), and the reader checks it
 * before HDF5 sees the file, so a damaged header never reaches the library's parser. Why
 * a user block and not an attribute: the hash must be found without parsing the file. */
#include <spam/errors.h>
#include <spam/output.h>

#define FNV_OFFSET 0xcbf29ce484222325ULL
#define FNV_PRIME  0x100000001b3ULL

static const char Prefix[] = "spam-ark snapshot; FNV-1a 64 of the bytes from 512 on: ";

static uint64_t Hash(uint64_t h, const unsigned char *p, size_t n)
{
  for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * FNV_PRIME;
  return h;
}

/* The block as the writer makes it for hash h: the line, then NULs. */
static void Block(uint64_t h, unsigned char block[SPAM_SNAPSHOT_USERBLOCK])
{
  memset(block, 0, SPAM_SNAPSHOT_USERBLOCK);
  (void)snprintf((char *)block, SPAM_SNAPSHOT_USERBLOCK, "%s%016llx\n", Prefix, (unsigned long long)h);
}

void SpamSnapshotStamp(unsigned char *image, size_t len)
{
  if (len < SPAM_SNAPSHOT_USERBLOCK) return;
  Block(Hash(FNV_OFFSET, image + SPAM_SNAPSHOT_USERBLOCK, len - SPAM_SNAPSHOT_USERBLOCK), image);
}

/* Hash of f's bytes from 512 to the end; false on a read error. */
static PetscBool HashRest(FILE *f, uint64_t *h)
{
  unsigned char buf[65536];
  size_t        n;

  *h = FNV_OFFSET;
  if (fseek(f, SPAM_SNAPSHOT_USERBLOCK, SEEK_SET)) return PETSC_FALSE;
  while ((n = fread(buf, 1, sizeof buf, f)) > 0) *h = Hash(*h, buf, n);
  return (PetscBool)!ferror(f);
}

PetscErrorCode SpamSnapshotVerify(FILE *f, const char *path)
{
  static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  unsigned char              head[SPAM_SNAPSHOT_USERBLOCK], want[SPAM_SNAPSHOT_USERBLOCK];
  uint64_t                   h;
  size_t                     got;

  PetscFunctionBeginUser;
  rewind(f);
  got = fread(head, 1, sizeof head, f);
  rewind(f);
  /* HDF5's signature first: no user block, a snapshot of an earlier version (or one made
   * by hand), which carries no checksum to verify */
  if (got >= sizeof sig && !memcmp(head, sig, sizeof sig)) PetscFunctionReturn(0);
  if (got != sizeof head || !HashRest(f, &h)) SPAM_BAD_INPUT("-file_path", path, "cannot read the snapshot's checksum");
  rewind(f);
  Block(h, want);
  if (memcmp(head, want, sizeof head)) SPAM_BAD_INPUT("-file_path", path, "the snapshot's checksum (its first 512 bytes) does not match its contents: the file was damaged or changed after it was written");
  PetscFunctionReturn(0);
}
