/* Transparent huge pages for the large per-particle arrays that the right-hand side and
 * the integrator stream through at every evaluation (huge_pages.c). */
#ifndef SPAM_HUGE_PAGES_H
#define SPAM_HUGE_PAGES_H
#include <stddef.h>

/* Asks the kernel to back the whole 2 MiB pages inside [a, a + bytes) with huge pages when
 * they are first written (Linux madvise MADV_HUGEPAGE): call it before the first write.
 * Nothing for arrays below 4 MiB, on other systems, or when the kernel refuses (the array
 * keeps its small pages). Contents and results are unchanged. */
void SpamAdviseHugePages(void *a, size_t bytes);
/* The same for an array already written: its small pages are gathered into huge ones
 * now (MADV_COLLAPSE, Linux 6.1 and later; a copy of the array, once), else advised as
 * above for the pages not yet written. */
void SpamCollapseHugePages(void *a, size_t bytes);
#endif
