/* The checkpoint file layer (checkpoint_file.h): entries come back bit for bit (NaN
 * payloads, -0.0, subnormals, INT64_MIN, text with NULs and non-ASCII bytes, empty arrays,
 * 10^6 reals of random bits); a write over a checkpoint leaves one file, and a write that
 * fails leaves the previous checkpoint byte for byte; every damaged or foreign file is
 * refused as bad input in one line naming it, with nothing printed by HDF5 (stderr is
 * captured during the refusals); a flipped byte anywhere in a small checkpoint is either
 * refused or changes nothing that is read. */
#define _DEFAULT_SOURCE /* mkdtemp, seteuid, truncate, fsync: POSIX, not C11 */
#include <spam/checkpoint_file.h>
#include <hdf5.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include "test_util.h"

#define NBIG 1000000 /* reals in the large entry */

/* The first error raised while a refusal is expected: its code and message. */
typedef struct {
  PetscErrorCode code;
  char           msg[2048];
} Caught;

static PetscErrorCode CatchError(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  Caught *c = (Caught *)ctx;

  (void)comm, (void)line, (void)fun, (void)file;
  if (p == PETSC_ERROR_INITIAL && !c->code) {
    c->code = n;
    (void)snprintf(c->msg, sizeof c->msg, "%s", mess ? mess : "");
  }
  return n;
}

/* stderr (fd 2) sent to a file while a refusal runs, to prove that nothing is printed. */
typedef struct {
  int  saved;
  char file[PETSC_MAX_PATH_LEN];
} Capture;

static void CaptureBegin(Capture *cap, const char *dir)
{
  int fd;

  (void)snprintf(cap->file, sizeof cap->file, "%s/stderr.txt", dir);
  fflush(stderr);
  cap->saved = dup(2);
  fd         = open(cap->file, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  (void)dup2(fd, 2);
  (void)close(fd);
}

/* Bytes written to stderr meanwhile. */
static long CaptureEnd(Capture *cap)
{
  struct stat st;

  fflush(stderr);
  (void)dup2(cap->saved, 2);
  (void)close(cap->saved);
  return stat(cap->file, &st) ? -1 : (long)st.st_size;
}

typedef enum { TRY_READ, TRY_WRITE, TRY_GET } TryWhat;

/* One expected failure: its error code, its message, and what reached stderr. */
static PetscErrorCode Try(TryWhat what, const char *dir, const char *path, SpamCkFile *ck, const char *entry, size_t n, Caught *got, long *printed)
{
  Capture        cap;
  PetscErrorCode ierr;
  size_t         bytes;
  const double  *v;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(got, sizeof *got));
  PetscCall(PetscPushErrorHandler(CatchError, got));
  CaptureBegin(&cap, dir);
  if (what == TRY_READ) ierr = SpamCkFileRead(PETSC_COMM_WORLD, path, ck);
  else if (what == TRY_WRITE) ierr = SpamCkFileWrite(PETSC_COMM_WORLD, ck, path, &bytes);
  else ierr = SpamCkGetReal(ck, entry, n, &v);
  *printed = CaptureEnd(&cap);
  PetscCall(PetscPopErrorHandler());
  if (!got->code) got->code = ierr;
  PetscFunctionReturn(0);
}

/* A refused read: bad input, one line starting "checkpoint PATH: ", nothing on stderr, and
 * nothing kept in c. want (may be NULL) is a phrase the reason must hold. */
static PetscErrorCode CheckRefused(TestCount *tc, const char *dir, const char *path, const char *what, const char *want)
{
  SpamCkFile ck;
  Caught     got;
  long       printed;
  char       head[PETSC_MAX_PATH_LEN + 16];

  PetscFunctionBeginUser;
  PetscCall(Try(TRY_READ, dir, path, &ck, NULL, 0, &got, &printed));
  (void)snprintf(head, sizeof head, "checkpoint %s: ", path);
  TestCheck(tc, got.code == PETSC_ERR_USER_INPUT && !strncmp(got.msg, head, strlen(head)) && !strchr(got.msg, '\n') && printed == 0 && ck.n == 0 && (!want || strstr(got.msg, want)),
            "%s refused: code %d (bad input %d), stderr %ld bytes, entries kept %d, message: %s", what, (int)got.code, PETSC_ERR_USER_INPUT, printed, ck.n, got.msg);
  PetscCall(SpamCkFileDestroy(&ck));
  PetscFunctionReturn(0);
}

/* dir/name (a function: the length is the caller's, not a truncation warning's). */
static void PathIn(char *out, size_t len, const char *dir, const char *name) { (void)PetscSNPrintf(out, len, "%s/%s", dir, name); }

static uint64_t Bits(double x)
{
  uint64_t u;
  memcpy(&u, &x, 8);
  return u;
}

static double FromBits(uint64_t u)
{
  double x;
  memcpy(&x, &u, 8);
  return x;
}

/* splitmix64: random bit patterns, every kind of double among them (NaNs, subnormals). */
static uint64_t NextBits(uint64_t *s)
{
  uint64_t z = (*s += 0x9E3779B97F4A7C15ULL);
  z          = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z          = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

static const char TEXT[] = "line one\nline \"two\" 'quoted' <b>&amp;\0after a NUL \xc3\xa9t\xc3\xa9 \xff\x01\x7f end\n";

/* What every round trip checks: the specials, integer limits, text with every awkward
 * byte, empty entries, scalars and NBIG reals of random bits. */
static PetscErrorCode FillSample(SpamCkFile *ck, double *big)
{
  const double  special[8] = {FromBits(0x7ff8000000012345ULL), FromBits(0xfff0000000000001ULL), -0.0, 4.9e-324, 1e308, -INFINITY, 1.0 / 3.0, FromBits(0x000fffffffffffffULL)};
  const int64_t ints[5]    = {INT64_MIN, INT64_MAX, -1, 0, 1};
  uint64_t      seed       = 17;

  PetscFunctionBeginUser;
  for (int i = 0; i < NBIG; i++) big[i] = FromBits(NextBits(&seed));
  PetscCall(SpamCkPutReal(ck, "special", 8, special));
  PetscCall(SpamCkPutInt(ck, "ints", 5, ints));
  PetscCall(SpamCkPutText(ck, "options", TEXT, sizeof TEXT - 1));
  PetscCall(SpamCkPutText(ck, "empty_text", "", 0));
  PetscCall(SpamCkPutReal(ck, "empty_real", 0, NULL));
  PetscCall(SpamCkPutInt(ck, "empty_int", 0, NULL));
  PetscCall(SpamCkPutScalar(ck, "t", 0.1 + 0.2));
  PetscCall(SpamCkPutLong(ck, "step", -123456789L));
  PetscCall(SpamCkPutReal(ck, "big", NBIG, big));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckSample(TestCount *tc, const SpamCkFile *ck, const double *big, const char *label)
{
  const double  *sp, *b, *er;
  const int64_t *in, *ei;
  const char    *txt, *et;
  size_t         len, elen, nbad = 0;
  double         t;
  long           step;

  PetscFunctionBeginUser;
  PetscCall(SpamCkGetReal(ck, "special", 8, &sp));
  TestCheck(tc, Bits(sp[0]) == 0x7ff8000000012345ULL && Bits(sp[1]) == 0xfff0000000000001ULL && Bits(sp[2]) == 0x8000000000000000ULL && sp[3] == 4.9e-324 && sp[4] == 1e308 && sp[5] == -INFINITY && sp[6] == 1.0 / 3.0 && Bits(sp[7]) == 0x000fffffffffffffULL,
            "%s: special reals bitwise: quiet NaN payload %016llx, signalling -NaN %016llx, -0.0 %016llx, %.17g, %.17g, %g, %.17g, largest subnormal %016llx", label, (unsigned long long)Bits(sp[0]), (unsigned long long)Bits(sp[1]), (unsigned long long)Bits(sp[2]), sp[3], sp[4], sp[5], sp[6], (unsigned long long)Bits(sp[7]));
  PetscCall(SpamCkGetInt(ck, "ints", 5, &in));
  TestCheck(tc, in[0] == INT64_MIN && in[1] == INT64_MAX && in[2] == -1 && in[3] == 0 && in[4] == 1, "%s: integers %lld %lld %lld %lld %lld", label, (long long)in[0], (long long)in[1], (long long)in[2], (long long)in[3], (long long)in[4]);
  PetscCall(SpamCkGetText(ck, "options", &txt, &len));
  TestCheck(tc, len == sizeof TEXT - 1 && !memcmp(txt, TEXT, len) && txt[len] == 0, "%s: text with newlines, quotes, a NUL and non-ASCII bytes: %zu bytes (put %zu), equal, NUL-terminated", label, len, sizeof TEXT - 1);
  PetscCall(SpamCkGetText(ck, "empty_text", &et, &elen));
  PetscCall(SpamCkGetReal(ck, "empty_real", 0, &er));
  PetscCall(SpamCkGetInt(ck, "empty_int", 0, &ei));
  {
    size_t nr, ni;
    PetscCall(SpamCkGetLength(ck, "empty_real", &nr));
    PetscCall(SpamCkGetLength(ck, "empty_int", &ni));
    TestCheck(tc, elen == 0 && et[0] == 0 && nr == 0 && ni == 0, "%s: empty text (%zu bytes), empty reals (%zu), empty integers (%zu)", label, elen, nr, ni);
  }
  PetscCall(SpamCkGetScalar(ck, "t", &t));
  PetscCall(SpamCkGetLong(ck, "step", &step));
  TestCheck(tc, Bits(t) == Bits(0.1 + 0.2) && step == -123456789L, "%s: scalar t = %.17g (0.1 + 0.2 bitwise), step = %ld", label, t, step);
  PetscCall(SpamCkGetReal(ck, "big", NBIG, &b));
  for (int i = 0; i < NBIG; i++) nbad += Bits(b[i]) != Bits(big[i]);
  TestCheck(tc, nbad == 0, "%s: %d reals of random bits (NaNs, infinities, subnormals among them): %zu differ", label, NBIG, nbad);
  TestCheck(tc, ck->n == 9, "%s: %d entries (put 9)", label, ck->n);
  PetscFunctionReturn(0);
}

/* Names in dir, and how many of them end in ".tmp". */
static int ListDir(const char *dir, int *ntmp, char *names, size_t len)
{
  DIR           *d = opendir(dir);
  struct dirent *e;
  int            n = 0;

  *ntmp    = 0;
  names[0] = 0;
  if (!d) return -1;
  while ((e = readdir(d))) {
    const size_t l = strlen(e->d_name);
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") || !strcmp(e->d_name, "stderr.txt")) continue;
    n++;
    if (l > 4 && !strcmp(e->d_name + l - 4, ".tmp")) (*ntmp)++;
    (void)snprintf(names + strlen(names), len - strlen(names), "%s%s", names[0] ? " " : "", e->d_name);
  }
  (void)closedir(d);
  return n;
}

static PetscErrorCode ReadAll(const char *path, char **buf, size_t *len)
{
  FILE *f = fopen(path, "rb");
  long  n;

  PetscFunctionBeginUser;
  PetscCheck(f, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", path);
  (void)fseek(f, 0, SEEK_END);
  n = ftell(f);
  (void)fseek(f, 0, SEEK_SET);
  PetscCall(PetscMalloc1(n + 1, buf));
  *len = fread(*buf, 1, (size_t)n, f);
  (void)fclose(f);
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteAll(const char *path, const char *buf, size_t len)
{
  FILE *f = fopen(path, "wb");

  PetscFunctionBeginUser;
  PetscCheck(f && fwrite(buf, 1, len, f) == len && !fclose(f), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s", path);
  PetscFunctionReturn(0);
}

/* HDF5's automatic error printer as it is now (NULL: off). */
static H5E_auto2_t AutoPrint(void)
{
  H5E_auto2_t func = NULL;
  void       *data;

  if (H5Eget_auto2(H5E_DEFAULT, &func, &data) < 0) return NULL;
  return func;
}

/* Round trip, replacement, and writing over a checkpoint. */
static PetscErrorCode TestRoundTrip(TestCount *tc, const char *dir, double *big)
{
  char       path[PETSC_MAX_PATH_LEN], names[1024];
  SpamCkFile ck, back;
  size_t     bytes, n;
  int        ntmp, nfiles;

  PetscFunctionBeginUser;
  PathIn(path, sizeof path, dir, "ck.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(FillSample(&ck, big));
  PetscCall(CheckSample(tc, &ck, big, "in memory"));
  {
    const H5E_auto2_t before = AutoPrint();
    H5E_auto2_t       after_write, after_read;
    PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, &bytes));
    after_write = AutoPrint();
    TestCheck(tc, bytes >= 8 * (size_t)NBIG, "written: %zu bytes for %zu bytes of data in the large entry", bytes, 8 * (size_t)NBIG);
    PetscCall(SpamCkFileRead(PETSC_COMM_WORLD, path, &back));
    after_read = AutoPrint();
    TestCheck(tc, before && after_write == before && after_read == before, "HDF5's automatic error printing (on at the start: %s) put back after the write (%s) and the read (%s)", before ? "yes" : "no", after_write == before ? "yes" : "no", after_read == before ? "yes" : "no");
  }
  PetscCall(CheckSample(tc, &back, big, "read back"));
  PetscCall(SpamCkFileDestroy(&back));

  /* A name put twice replaces the entry, whatever its kind. */
  {
    const int64_t two[2] = {7, -7};
    const int64_t *got;
    PetscCall(SpamCkPutInt(&ck, "special", 2, two));
    PetscCall(SpamCkGetInt(&ck, "special", 2, &got));
    TestCheck(tc, ck.n == 9 && got[0] == 7 && got[1] == -7, "replaced 'special' (8 reals) by 2 integers: %d entries, values %lld %lld", ck.n, (long long)got[0], (long long)got[1]);
  }
  /* Writing over the checkpoint: one file, no temporaries, the new contents. */
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, &bytes));
  nfiles = ListDir(dir, &ntmp, names, sizeof names);
  PetscCall(SpamCkFileRead(PETSC_COMM_WORLD, path, &back));
  {
    const int64_t *got;
    PetscCall(SpamCkGetInt(&back, "special", 2, &got));
    PetscCall(SpamCkGetLength(&back, "special", &n));
    TestCheck(tc, nfiles == 1 && ntmp == 0 && n == 2 && got[0] == 7 && got[1] == -7, "written over: the directory holds %d file(s) [%s], %d temporaries; 'special' read back as %zu integers %lld %lld", nfiles, names, ntmp, n, (long long)got[0], (long long)got[1]);
  }
  PetscCall(SpamCkFileDestroy(&back));
  PetscCall(SpamCkFileDestroy(&ck));
  PetscFunctionReturn(0);
}

/* h5dump shows a text entry as text (skipped, and said so, without h5dump). */
static PetscErrorCode TestH5dump(TestCount *tc, const char *dir)
{
  char       path[PETSC_MAX_PATH_LEN], cmd[2 * PETSC_MAX_PATH_LEN], out[4096] = "";
  SpamCkFile ck;
  FILE      *p;
  size_t     got;

  PetscFunctionBeginUser;
  if (system("command -v h5dump >/dev/null 2>&1")) {
    printf("note: h5dump not found, its view of a text entry not checked\n");
    PetscFunctionReturn(0);
  }
  PathIn(path, sizeof path, dir, "dump.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(SpamCkPutText(&ck, "options", "-scene expansion -ts_type arkode", 32));
  PetscCall(SpamCkPutText(&ck, "empty", "", 0));
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, NULL));
  PetscCall(SpamCkFileDestroy(&ck));
  (void)snprintf(cmd, sizeof cmd, "h5dump -d /checkpoint/options -d /checkpoint/empty -a /format %s 2>&1", path);
  p   = popen(cmd, "r");
  got = p ? fread(out, 1, sizeof out - 1, p) : 0;
  out[got] = 0;
  if (p) (void)pclose(p);
  TestCheck(tc, strstr(out, "\"-scene expansion -ts_type arkode\"") && strstr(out, "\"\"") && strstr(out, "\"spam-ark checkpoint 1\""), "h5dump shows the text entries and the format:\n%s", out);
  (void)unlink(path);
  PetscFunctionReturn(0);
}

/* Damaged and foreign files are refused. */
static PetscErrorCode TestRefusals(TestCount *tc, const char *dir, const double *big)
{
  char       path[PETSC_MAX_PATH_LEN], bad[PETSC_MAX_PATH_LEN], *bytes;
  SpamCkFile ck;
  size_t     len;
  haddr_t    offset = HADDR_UNDEF;

  PetscFunctionBeginUser;
  PathIn(path, sizeof path, dir, "ref.h5");
  PathIn(bad, sizeof bad, dir, "bad.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(SpamCkPutReal(&ck, "big", NBIG, big));
  PetscCall(SpamCkPutText(&ck, "options", "-a 1", 4));
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, NULL));
  PetscCall(SpamCkFileDestroy(&ck));
  PetscCall(ReadAll(path, &bytes, &len));

  PathIn(bad, sizeof bad, dir, "missing.h5");
  PetscCall(CheckRefused(tc, dir, bad, "a missing file", "No such file"));
  PathIn(bad, sizeof bad, dir, "bad.h5");
  PetscCall(WriteAll(bad, "", 0));
  PetscCall(CheckRefused(tc, dir, bad, "an empty file", "not an HDF5 file (0 bytes)"));
  PetscCall(WriteAll(bad, "t,x,y\n0,1,2\n", 12));
  PetscCall(CheckRefused(tc, dir, bad, "a text file", "not an HDF5 file"));
  PetscCall(WriteAll(bad, bytes, len / 2));
  PetscCall(CheckRefused(tc, dir, bad, "the checkpoint truncated to half", "truncated"));
  /* Left off after a refusal: HDF5 1.10.8 would otherwise print at exit (checkpoint_read.c). */
  TestCheck(tc, AutoPrint() == NULL, "HDF5's automatic error printing left off after a refused read (%s)", AutoPrint() ? "on" : "off");
  PetscCall(CheckRefused(tc, dir, dir, "a directory", "is a directory"));

  { /* One byte in the middle of the large real dataset, found where HDF5 stored it. */
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT), d = f >= 0 ? H5Dopen2(f, "/checkpoint/big", H5P_DEFAULT) : -1;
    if (d >= 0) offset = H5Dget_offset(d);
    if (d >= 0) (void)H5Dclose(d);
    if (f >= 0) (void)H5Fclose(f);
  }
  TestCheck(tc, offset != HADDR_UNDEF && offset + 8 * (size_t)NBIG <= len, "/checkpoint/big is stored contiguously at byte %llu of %zu", (unsigned long long)offset, len);
  if (offset != HADDR_UNDEF && offset + 8 * (size_t)NBIG <= len) {
    const size_t at = (size_t)offset + 8 * 500000 + 3;
    bytes[at] ^= 0x10;
    PetscCall(WriteAll(bad, bytes, len));
    bytes[at] ^= 0x10;
    printf("flipped bit 4 of byte %zu (value 500000 of /checkpoint/big)\n", at);
    PetscCall(CheckRefused(tc, dir, bad, "one flipped bit in the large real dataset", "checksum disagrees"));
  }
  PetscCall(PetscFree(bytes));

  { /* Another format version, and an HDF5 file that is no checkpoint. */
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT), t = H5Tcopy(H5T_C_S1), s = H5Screate(H5S_SCALAR), a;
    (void)H5Adelete(f, "format");
    (void)H5Tset_size(t, 22);
    a = H5Acreate2(f, "format", t, s, H5P_DEFAULT, H5P_DEFAULT);
    (void)H5Awrite(a, t, "spam-ark checkpoint 2");
    (void)H5Aclose(a);
    (void)H5Fclose(f);
    PetscCall(CheckRefused(tc, dir, path, "a checkpoint of format 2", "format 'spam-ark checkpoint 2', this spam-ark reads 'spam-ark checkpoint 1'"));
    f = H5Fcreate(bad, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    a = H5Acreate2(f, "units", t, s, H5P_DEFAULT, H5P_DEFAULT);
    {
      const char units[22] = "reduced"; /* as long as the type */
      (void)H5Awrite(a, t, units);
    }
    (void)H5Aclose(a);
    (void)H5Fclose(f);
    (void)H5Sclose(s);
    (void)H5Tclose(t);
    PetscCall(CheckRefused(tc, dir, bad, "an HDF5 file that is not a checkpoint", "without the root attribute format"));
  }
  (void)unlink(path);
  (void)unlink(bad);
  PetscFunctionReturn(0);
}

/* Getters: a missing entry, another length, another kind. */
static PetscErrorCode TestGetters(TestCount *tc, const char *dir)
{
  char       path[PETSC_MAX_PATH_LEN];
  SpamCkFile ck, back;
  Caught     got;
  long       printed;
  const double x[3] = {1, 2, 3};
  const char *cases[3][2] = {{"absent", "no entry 'absent'"}, {"x", "entry 'x' has 3 values, expected 4"}, {"note", "entry 'note' is text, expected real"}};

  PetscFunctionBeginUser;
  PathIn(path, sizeof path, dir, "get.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(SpamCkPutReal(&ck, "x", 3, x));
  PetscCall(SpamCkPutText(&ck, "note", "hello", 5));
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, NULL));
  PetscCall(SpamCkFileDestroy(&ck));
  PetscCall(SpamCkFileRead(PETSC_COMM_WORLD, path, &back));
  for (int k = 0; k < 3; k++) {
    char want[PETSC_MAX_PATH_LEN + 128];
    PetscCall(Try(TRY_GET, dir, path, &back, cases[k][0], 4, &got, &printed));
    (void)snprintf(want, sizeof want, "checkpoint %s: %s", path, cases[k][1]);
    TestCheck(tc, got.code == PETSC_ERR_USER_INPUT && !strcmp(got.msg, want), "get '%s' (4 reals): code %d, message: %s", cases[k][0], (int)got.code, got.msg);
  }
  PetscCall(SpamCkFileDestroy(&back));
  { /* A name HDF5 would take as a path is a program error. */
    PetscErrorCode ierr;
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    ierr = SpamCkPutReal(&ck, "a/b", 3, x);
    PetscCall(PetscPopErrorHandler());
    TestCheck(tc, ierr == PETSC_ERR_ARG_WRONG && ck.n == 0, "the name 'a/b' refused: code %d (PETSC_ERR_ARG_WRONG %d)", (int)ierr, PETSC_ERR_ARG_WRONG);
  }
  (void)unlink(path);
  PetscFunctionReturn(0);
}

/* A failed write removes its temporary and keeps the previous checkpoint byte for byte;
 * a directory that is missing or not writable gets nothing. */
static PetscErrorCode TestWriteFailures(TestCount *tc, const char *dir)
{
  char        path[PETSC_MAX_PATH_LEN], sub[PETSC_MAX_PATH_LEN], names[1024], *before, *after;
  SpamCkFile  ck;
  Caught      got;
  long        printed;
  size_t      nb, na;
  int         ntmp, nfiles;
  const double x[4] = {1, 2, 3, 4};

  PetscFunctionBeginUser;
  PathIn(sub, sizeof sub, dir, "fail");
  (void)mkdir(sub, 0755);
  PathIn(path, sizeof path, sub, "ck.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(SpamCkPutReal(&ck, "a", 4, x));
  PetscCall(SpamCkPutReal(&ck, "b", 4, x));
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, NULL));
  PetscCall(ReadAll(path, &before, &nb));
  PetscCall(SpamCkPutReal(&ck, "a", 2, x));
  /* The second dataset write fails as on a full disk. */
  setenv("SPAM_TEST_FAIL_WRITE", "ck.h5:2", 1);
  PetscCall(Try(TRY_WRITE, dir, path, &ck, NULL, 0, &got, &printed));
  unsetenv("SPAM_TEST_FAIL_WRITE");
  nfiles = ListDir(sub, &ntmp, names, sizeof names);
  PetscCall(ReadAll(path, &after, &na));
  TestCheck(tc, got.code == PETSC_ERR_FILE_WRITE && strstr(got.msg, path) && strstr(got.msg, "No space left") && printed == 0, "a write failing at its second dataset: code %d (file write %d), stderr %ld bytes, message: %s", (int)got.code, PETSC_ERR_FILE_WRITE, printed, got.msg);
  TestCheck(tc, nfiles == 1 && ntmp == 0 && na == nb && !memcmp(before, after, nb), "after the failed write: %d file(s) [%s], %d temporaries, the previous checkpoint unchanged (%zu bytes, %s)", nfiles, names, ntmp, na, na == nb && !memcmp(before, after, nb) ? "equal" : "differs");
  PetscCall(PetscFree(before));
  PetscCall(PetscFree(after));
  (void)unlink(path);

  PathIn(path, sizeof path, dir, "no_such_dir/ck.h5");
  PetscCall(Try(TRY_WRITE, dir, path, &ck, NULL, 0, &got, &printed));
  TestCheck(tc, got.code == PETSC_ERR_FILE_WRITE && strstr(got.msg, path) && strstr(got.msg, "No such file or directory") && printed == 0, "a write into a missing directory: code %d, message: %s", (int)got.code, got.msg);

  /* Root writes anywhere: the attempt then runs as nobody, for whom 0555 means no. */
  (void)chmod(sub, 0555);
  PathIn(path, sizeof path, sub, "ck.h5");
  {
    const uid_t euid = geteuid();
    const int   as_nobody = euid == 0 && seteuid(65534) == 0;
    PetscCall(Try(TRY_WRITE, dir, path, &ck, NULL, 0, &got, &printed));
    if (as_nobody) PetscCheck(seteuid(euid) == 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "cannot return to uid %d", (int)euid);
    nfiles = ListDir(sub, &ntmp, names, sizeof names);
    TestCheck(tc, got.code == PETSC_ERR_FILE_WRITE && strstr(got.msg, path) && strstr(got.msg, "Permission denied") && nfiles == 0, "a write into a directory without write permission%s: code %d, %d file(s) left, message: %s", as_nobody ? " (as nobody)" : "", (int)got.code, nfiles, got.msg);
  }
  (void)chmod(sub, 0755);
  (void)rmdir(sub);
  PetscCall(SpamCkFileDestroy(&ck));
  PetscFunctionReturn(0);
}

/* Every byte of a small checkpoint flipped in turn: the read refuses it (bad input, naming
 * the file, silent) or returns exactly the entries written. */
static PetscErrorCode TestEveryByte(TestCount *tc, const char *dir)
{
  char          path[PETSC_MAX_PATH_LEN], bad[PETSC_MAX_PATH_LEN], *bytes;
  SpamCkFile    ck, ref;
  size_t        len, refused = 0, same = 0, wrong = 0, loud = 0, first_wrong = 0;
  const double  x[16]  = {1, -2, 3.5, 1e-300, -0.0, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  const int64_t id[4]  = {4, 3, 2, 1};

  PetscFunctionBeginUser;
  PathIn(path, sizeof path, dir, "small.h5");
  PathIn(bad, sizeof bad, dir, "flip.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(SpamCkPutReal(&ck, "x", 16, x));
  PetscCall(SpamCkPutInt(&ck, "id", 4, id));
  PetscCall(SpamCkPutText(&ck, "options", "-scene expansion", 16));
  PetscCall(SpamCkPutScalar(&ck, "t", 0.5));
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, NULL));
  PetscCall(SpamCkFileDestroy(&ck));
  PetscCall(SpamCkFileRead(PETSC_COMM_WORLD, path, &ref));
  PetscCall(ReadAll(path, &bytes, &len));
  for (size_t at = 0; at < len; at++) {
    Caught got;
    long   printed;
    bytes[at] ^= 0x01;
    PetscCall(WriteAll(bad, bytes, len));
    bytes[at] ^= 0x01;
    PetscCall(Try(TRY_READ, dir, bad, &ck, NULL, 0, &got, &printed));
    loud += printed != 0;
    if (got.code == PETSC_ERR_USER_INPUT && strstr(got.msg, bad)) refused++;
    else if (!got.code) {
      PetscBool eq = (PetscBool)(ck.n == ref.n);
      for (int i = 0; eq && i < ck.n; i++)
        eq = (PetscBool)(!strcmp(ck.e[i].name, ref.e[i].name) && ck.e[i].kind == ref.e[i].kind && ck.e[i].n == ref.e[i].n && !memcmp(ck.e[i].data, ref.e[i].data, ck.e[i].n * (ck.e[i].kind == SPAM_CK_TEXT ? 1 : 8)));
      if (eq) same++;
      else if (!wrong++) first_wrong = at;
    } else if (!wrong++) first_wrong = at;
    PetscCall(SpamCkFileDestroy(&ck));
  }
  TestCheck(tc, wrong == 0 && loud == 0 && refused + same == len, "every byte of a %zu-byte checkpoint flipped (bit 0): %zu refused, %zu read unchanged (unused bytes), %zu otherwise (first at byte %zu), %zu printed to stderr", len, refused, same, wrong, first_wrong, loud);
  PetscCall(PetscFree(bytes));
  PetscCall(SpamCkFileDestroy(&ref));
  (void)unlink(path);
  (void)unlink(bad);
  PetscFunctionReturn(0);
}

/* Size and write time of 65536 x 8 reals (4 MiB): printed for the report, not asserted. */
static PetscErrorCode MeasureOverhead(const char *dir, const double *big)
{
  char          path[PETSC_MAX_PATH_LEN];
  SpamCkFile    ck;
  size_t        bytes;
  const size_t  n = 65536 * 8;
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PathIn(path, sizeof path, dir, "size.h5");
  PetscCall(SpamCkFileInit(&ck));
  PetscCall(SpamCkPutReal(&ck, "state", n, big));
  PetscCall(PetscTime(&t0));
  PetscCall(SpamCkFileWrite(PETSC_COMM_WORLD, &ck, path, &bytes));
  PetscCall(PetscTime(&t1));
  printf("measured: 65536 x 8 reals (%zu bytes raw) make a %zu-byte checkpoint: %zu bytes (%.3f%%) more; written (with fsync) in %.4f s\n", 8 * n, bytes, bytes - 8 * n, 100.0 * (double)(bytes - 8 * n) / (double)(8 * n), t1 - t0);
  PetscCall(SpamCkFileDestroy(&ck));
  (void)unlink(path);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  TestCount   tc = {0, 0};
  char        dir[PETSC_MAX_PATH_LEN];
  const char *tmp = getenv("TMPDIR");
  double     *big;

  PetscCall(TestInitialize(&argc, &argv));
  (void)snprintf(dir, sizeof dir, "%s/ckfile.XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
  PetscCheck(mkdtemp(dir), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create %s: %s", dir, strerror(errno));
  (void)chmod(dir, 0755); /* nobody (TestWriteFailures) must reach the subdirectory */
  PetscCall(PetscMalloc1(NBIG, &big));
  PetscCall(TestRoundTrip(&tc, dir, big));
  PetscCall(TestH5dump(&tc, dir));
  PetscCall(TestRefusals(&tc, dir, big));
  PetscCall(TestGetters(&tc, dir));
  PetscCall(TestWriteFailures(&tc, dir));
  PetscCall(TestEveryByte(&tc, dir));
  PetscCall(MeasureOverhead(dir, big));
  PetscCall(PetscFree(big));
  {
    char f[PETSC_MAX_PATH_LEN + 16];
    PathIn(f, sizeof f, dir, "stderr.txt");
    (void)unlink(f);
    PathIn(f, sizeof f, dir, "ck.h5");
    (void)unlink(f);
    (void)rmdir(dir);
  }
  PetscCall(TestFinalize());
  return TestFinish(&tc);
}
