/* Huge pages for large arrays. A gas of 2^20 particles in 2D streams about 300 bytes a
 * particle from memory per right-hand side (list rows, positions, state, stage vectors,
 * accelerations: callgrind's simulated misses), over some 90000 pages of 4 KiB, so
 * nearly every page of every stream costs a TLB miss, and on a virtual machine each miss
 * walks two page tables. ERKStep's clones are moreover written for the first time inside
 * the run loop (nvector_unwritten.c), a fault per page: 82000 faults in a run of four
 * Dormand-Prince steps at that size. With 2 MiB pages the same memory takes 512 times
 * fewer entries and faults. Kernels set to transparent huge pages "madvise" (the common
 * default) grant them only on request. Arrays of a few MiB, which fit the TLB's reach
 * anyway, are left alone. */
#define _DEFAULT_SOURCE /* madvise: not C11 */
#include <spam/huge_pages.h>
#include <stdint.h>
#include <sys/mman.h>

#if defined(__linux__) && !defined(MADV_COLLAPSE)
#define MADV_COLLAPSE 25 /* linux/mman.h of Linux 6.1; older C libraries lack the name */
#endif

#define SPAM_HUGE_PAGE ((uintptr_t)2 << 20)

/* The whole huge pages inside [a, a + bytes): 0 when there are none or the array is small. */
static size_t HugeRange(void *a, size_t bytes, void **lo)
{
  const uintptr_t l = ((uintptr_t)a + SPAM_HUGE_PAGE - 1) & ~(SPAM_HUGE_PAGE - 1);
  const uintptr_t h = ((uintptr_t)a + bytes) & ~(SPAM_HUGE_PAGE - 1);

  *lo = (void *)l;
  return a && bytes >= 2 * SPAM_HUGE_PAGE && h > l ? (size_t)(h - l) : 0;
}

/* Advice only: a refusal (EINVAL where the kernel lacks it, EAGAIN when no huge page is
 * free) leaves the small pages, so the return codes are not errors. */
void SpamAdviseHugePages(void *a, size_t bytes)
{
#if defined(MADV_HUGEPAGE)
  void        *lo;
  const size_t len = HugeRange(a, bytes, &lo);
  if (len) (void)madvise(lo, len, MADV_HUGEPAGE);
#else
  (void)a;
  (void)bytes;
#endif
}

void SpamCollapseHugePages(void *a, size_t bytes)
{
  SpamAdviseHugePages(a, bytes);
#if defined(MADV_COLLAPSE)
  {
    void        *lo;
    const size_t len = HugeRange(a, bytes, &lo);
    if (len) (void)madvise(lo, len, MADV_COLLAPSE);
  }
#endif
}
