/* Zeros without resident pages. An array that is read but never written (the error
 * weights of a fixed-step run, which ERKStep reads once a step for a check it cannot
 * fail at zero weight) still needs defined contents; written zeros would cost a resident
 * page each, pages given back cost none. */
#define _DEFAULT_SOURCE /* madvise: not C11 */
#include <spam/zero_pages.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>
#include <sys/mman.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

void SpamZeroPages(void *a, size_t bytes)
{
  const long page = sysconf(_SC_PAGESIZE);
  uintptr_t  lo, hi;

  if (!a || !bytes) return;
  if (page <= 0) {
    memset(a, 0, bytes);
    return;
  }
  lo = ((uintptr_t)a + (uintptr_t)page - 1) & ~((uintptr_t)page - 1);
  hi = ((uintptr_t)a + bytes) & ~((uintptr_t)page - 1);
  if (hi <= lo) {
    memset(a, 0, bytes);
    return;
  }
  memset(a, 0, lo - (uintptr_t)a);
  memset((void *)hi, 0, (uintptr_t)a + bytes - hi);
#if defined(MADV_DONTNEED)
  if (madvise((void *)lo, hi - lo, MADV_DONTNEED) == 0) return;
#endif
  memset((void *)lo, 0, hi - lo);
}

/* The set-up frees large buffers (the input particles, sort keys, the first list's
 * scratch) into the C library's heap, which keeps their pages resident; and an array the
 * run allocates later may land on them, so that memory it never writes is resident all
 * the same (the list's reference positions kept over outputs, 24 bytes a particle at
 * N = 262144). glibc's malloc_trim gives the free pages back (elsewhere: nothing). */
void SpamReleaseFreedMemory(void)
{
#if defined(__GLIBC__)
  (void)malloc_trim(0);
#endif
}
