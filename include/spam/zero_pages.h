/* Zeros that take no memory (zero_pages.c). */
#ifndef SPAM_ZERO_PAGES_H
#define SPAM_ZERO_PAGES_H
#include <stddef.h>

/* Sets [a, a + bytes) of a heap array to zero, giving the whole pages inside it back to
 * the kernel instead of writing them (Linux madvise MADV_DONTNEED: a private anonymous
 * page given back reads as zeros, and a read maps the shared zero page, not memory of
 * its own). The partial pages at the ends, and every page where the kernel refuses, are
 * written. For an array that must read as zeros and is never written. */
void SpamZeroPages(void *a, size_t bytes);
/* Gives the heap's free pages back to the kernel (glibc: malloc_trim), so that arrays
 * allocated after it start from pages nobody has written: before the run loop. */
void SpamReleaseFreedMemory(void);
#endif
