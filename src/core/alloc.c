/* Checked allocation: sizes that overflow or memory that cannot be had become
 * JND_ERR_NOMEM messages instead of crashes. */
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

#include "core/core.h"

/* Image planes and pyramid levels are tens of megabytes, touched once each
 * soon after they are allocated: with 4 KiB pages the page faults cost a
 * fifth of a run. Asking for transparent huge pages on the whole 2 MiB
 * pages inside a large block (before it is touched) makes that 512 times
 * fewer faults; where the kernel has them off this does nothing. */
static void *large_pages(void *p, size_t bytes) {
#ifdef MADV_HUGEPAGE
  enum { HUGE = 2 << 20 };
  if (p && bytes >= 2 * (size_t)HUGE) {
    uintptr_t a = ((uintptr_t)p + HUGE - 1) & ~(uintptr_t)(HUGE - 1);
    uintptr_t e = ((uintptr_t)p + bytes) & ~(uintptr_t)(HUGE - 1);
    if (e > a) (void)madvise((void *)a, e - a, MADV_HUGEPAGE);
  }
#else
  (void)bytes;
#endif
  return p;
}

void *jnd_alloc(size_t count, size_t size) {
  if (size && count > SIZE_MAX / size) {
    jnd_fail(JND_ERR_NOMEM, "allocation of %zu × %zu bytes overflows", count, size);
    return NULL;
  }
  size_t bytes = count * size;
  void *p = large_pages(malloc(bytes > 0 ? bytes : 1), bytes);
  if (!p) jnd_fail(JND_ERR_NOMEM, "out of memory allocating %zu bytes", count * size);
  return p;
}

void *jnd_calloc(size_t count, size_t size) {
  void *p = calloc(count ? count : 1, size ? size : 1);
  if (p && size && count <= SIZE_MAX / size) large_pages(p, count * size);
  if (!p) jnd_fail(JND_ERR_NOMEM, "out of memory allocating %zu × %zu bytes", count, size);
  return p;
}
