/* Resident bytes by allocation, for run_bench.py --memory (bench_memory.py): preloaded into
 * spam-ark (LD_PRELOAD), it records every heap block of at least SPAM_MEM_THRESHOLD bytes
 * (default 64 KiB) with the call stack that made it, and counts its resident pages
 * (mincore) whenever one such block is freed and at exit. The live blocks' resident bytes
 * at the largest of those sums are the peak's owners: between two frees or reallocations
 * a live block's residency can only grow, so the largest sum is found at one of them.
 * Massif counts what is allocated; this counts what is written (a page becomes resident at
 * its first write; a read of an untouched page maps the shared zero page, left out).
 *
 * At exit it writes SPAM_MEM_OUT.PID (a text file): a line "peak TOTAL" and then, per block
 * live at the peak, "block SIZE RESIDENT" followed by its frames "frame MODULE OFFSET",
 * which the Python side names with addr2line. Small blocks, the stack, libraries' own
 * mappings and the executable's pages are not counted here: they are the difference to
 * the process's peak RSS.
 *
 * Build: cc -O2 -shared -fPIC -o memory_owners.so memory_owners.c -ldl -lpthread
 * (bench_memory.py builds it into bench/results/). Linux and glibc only. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <execinfo.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void  __libc_free(void *);
extern void *__libc_memalign(size_t, size_t);

#define MAX_BLOCKS 32768
#define DEPTH      28
#define VEC_PAGES  (1u << 21) /* mincore's answer for up to 8 GiB in one block */

typedef struct {
  void  *p;
  size_t size, resident; /* resident: at the peak snapshot */
  void  *stack[DEPTH];
  int    depth, live, at_peak;
} Block;

static Block           blocks[MAX_BLOCKS];
static int             nblocks, overflow;
static size_t          threshold = 64 << 10, page;
static size_t          peak_total;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static __thread int    busy; /* inside the hook: backtrace's own allocations pass */
static unsigned char   vec[VEC_PAGES];

/* A page that was only read maps the kernel's shared zero page (or its huge zero page):
 * present, yet not the process's memory (RSS leaves it out). /proc/self/pagemap names the
 * frame (readable by root), so those pages are left out here too; without the frame
 * numbers (not root) every present page counts, as mincore would. */
static int      pagemap = -1;
static uint64_t zero_pfn, huge_zero_pfn; /* 0: unknown */
static uint64_t pm[1 << 16];

static uint64_t FrameOf(const volatile char *a)
{
  uint64_t e = 0;
  (void)a[0]; /* read: maps the zero page */
  if (pread(pagemap, &e, sizeof e, (off_t)((uintptr_t)a / page * sizeof e)) != (ssize_t)sizeof e) return 0;
  return (e >> 63) & 1 ? e & ((1ULL << 55) - 1) : 0;
}

static void ZeroFrames(void)
{
  char *a;
  pagemap = open("/proc/self/pagemap", O_RDONLY);
  if (pagemap < 0) return;
  a = mmap(NULL, page, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (a != MAP_FAILED) {
    zero_pfn = FrameOf(a);
    munmap(a, page);
  }
  a = mmap(NULL, 8 << 20, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (a != MAP_FAILED) {
    char *h = (char *)(((uintptr_t)a + (2 << 20) - 1) & ~(uintptr_t)((2 << 20) - 1));
    (void)madvise(h, 2 << 20, MADV_HUGEPAGE);
    huge_zero_pfn = FrameOf(h);
    if (huge_zero_pfn == zero_pfn) huge_zero_pfn = 0;
    munmap(a, 8 << 20);
  }
}

static int IsZeroFrame(uint64_t pfn)
{
  if (!pfn) return 0; /* frame numbers hidden */
  return pfn == zero_pfn || (huge_zero_pfn && pfn >= huge_zero_pfn && pfn < huge_zero_pfn + 512);
}

static size_t Resident(const Block *b)
{
  const uintptr_t lo = (uintptr_t)b->p & ~(uintptr_t)(page - 1);
  const uintptr_t hi = ((uintptr_t)b->p + b->size + page - 1) & ~(uintptr_t)(page - 1);
  size_t          np = (hi - lo) / page, r = 0;

  if (pagemap >= 0) {
    for (size_t k0 = 0; k0 < np; k0 += sizeof pm / sizeof pm[0]) {
      const size_t m = np - k0 < sizeof pm / sizeof pm[0] ? np - k0 : sizeof pm / sizeof pm[0];
      if (pread(pagemap, pm, m * sizeof pm[0], (off_t)((lo / page + k0) * sizeof pm[0])) != (ssize_t)(m * sizeof pm[0])) break;
      for (size_t k = 0; k < m; k++)
        if ((pm[k] >> 63) & 1 && !IsZeroFrame(pm[k] & ((1ULL << 55) - 1))) r++;
    }
    return r * page;
  }
  if (np > VEC_PAGES) np = VEC_PAGES;
  if (mincore((void *)lo, np * page, vec)) return 0;
  for (size_t k = 0; k < np; k++) r += vec[k] & 1;
  return r * page;
}

/* The live blocks' residency now; kept as the peak when it is the largest so far. */
static void Snapshot(void)
{
  size_t total = 0;
  for (int i = 0; i < nblocks; i++)
    if (blocks[i].live) total += Resident(&blocks[i]);
  if (total < peak_total) return;
  peak_total = total;
  for (int i = 0; i < nblocks; i++) {
    blocks[i].at_peak  = blocks[i].live;
    blocks[i].resident = blocks[i].live ? Resident(&blocks[i]) : 0;
  }
}

static void Add(void *p, size_t size)
{
  Block *b;
  if (!p || size < threshold || busy) return;
  busy = 1;
  pthread_mutex_lock(&lock);
  if (nblocks < MAX_BLOCKS) {
    b       = &blocks[nblocks++];
    b->p    = p;
    b->size = size;
    b->live = 1;
    b->depth = backtrace(b->stack, DEPTH);
  } else overflow = 1;
  pthread_mutex_unlock(&lock);
  busy = 0;
}

static void Remove(void *p)
{
  if (!p || busy) return;
  busy = 1;
  pthread_mutex_lock(&lock);
  for (int i = nblocks - 1; i >= 0; i--)
    if (blocks[i].live && blocks[i].p == p) {
      Snapshot();
      blocks[i].live = 0;
      break;
    }
  pthread_mutex_unlock(&lock);
  busy = 0;
}

void *malloc(size_t n)
{
  void *p = __libc_malloc(n);
  Add(p, n);
  return p;
}

void *calloc(size_t k, size_t n)
{
  void *p = __libc_calloc(k, n);
  Add(p, k * n);
  return p;
}

void *realloc(void *q, size_t n)
{
  void *p;
  Remove(q);
  p = __libc_realloc(q, n);
  Add(p, n);
  return p;
}

void free(void *p)
{
  Remove(p);
  __libc_free(p);
}

int posix_memalign(void **r, size_t a, size_t n)
{
  void *p = __libc_memalign(a, n);
  if (!p) return 12; /* ENOMEM */
  Add(p, n);
  *r = p;
  return 0;
}

void *aligned_alloc(size_t a, size_t n)
{
  void *p = __libc_memalign(a, n);
  Add(p, n);
  return p;
}

void *memalign(size_t a, size_t n)
{
  void *p = __libc_memalign(a, n);
  Add(p, n);
  return p;
}

__attribute__((constructor)) static void Start(void)
{
  void       *warm[2];
  const char *t = getenv("SPAM_MEM_THRESHOLD");
  page          = (size_t)sysconf(_SC_PAGESIZE);
  if (t) threshold = (size_t)strtoull(t, NULL, 10);
  busy = 1;
  ZeroFrames();
  (void)backtrace(warm, 2); /* loads the unwinder now, outside any hook */
  busy = 0;
}

__attribute__((destructor)) static void Finish(void)
{
  const char *base = getenv("SPAM_MEM_OUT");
  char        path[4096];
  FILE       *f = NULL;

  busy = 1;
  pthread_mutex_lock(&lock);
  Snapshot();
  /* SPAM_MEM_OUT.PID: a launcher that the preload reaches too writes a file of its own */
  if (base && snprintf(path, sizeof path, "%s.%ld", base, (long)getpid()) < (int)sizeof path) f = fopen(path, "w");
  if (f) {
    fprintf(f, "peak %zu\nthreshold %zu\noverflow %d\nzero_frames %d\n", peak_total, threshold, overflow, zero_pfn != 0);
    for (int i = 0; i < nblocks; i++) {
      if (!blocks[i].at_peak) continue;
      fprintf(f, "block %zu %zu\n", blocks[i].size, blocks[i].resident);
      for (int k = 1; k < blocks[i].depth; k++) {
        Dl_info d;
        if (dladdr(blocks[i].stack[k], &d) && d.dli_fname) {
          /* addr2line takes a shared object's (ET_DYN) addresses from its base, an
           * executable's (ET_EXEC) as they are; minus 1: inside the call, not after it */
          const uint16_t  type = *(const uint16_t *)((const char *)d.dli_fbase + 16);
          const uintptr_t a    = (uintptr_t)blocks[i].stack[k] - 1 - (type == 3 ? (uintptr_t)d.dli_fbase : 0);
          fprintf(f, "frame %s %#lx\n", d.dli_fname, (unsigned long)a);
        }
      }
    }
    fclose(f);
  }
  pthread_mutex_unlock(&lock);
}
