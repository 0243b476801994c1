/* Checked allocation: sizes that overflow or memory that cannot be had become
 * JND_ERR_NOMEM messages instead of crashes. */
#include <omp.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include "core/core.h"

/* Image planes, pyramid levels and band planes are megabytes each, touched
 * once soon after they are allocated, and first touches are page faults: on
 * a 1920×1080 diff, 19 600 faults of 4 KiB took a third of the CPU time (most
 * of it in the kernel; on a virtual machine a fault is dear). Two things
 * make that 6 400 faults and most of them 2 MiB ones:
 * - transparent huge pages, asked for (MADV_HUGEPAGE, before first touch) on
 *   the whole 2 MiB pages inside a block malloc mapped by itself, and on the
 *   main heap as it grows (the planes below malloc's mmap threshold live
 *   there: a level-1 plane of 1920×1080 is 2 MB, never a whole huge page
 *   by itself) — what glibc's glibc.malloc.hugetlb=1 tunable does, which a
 *   program cannot set for itself;
 * - the block's pages populated in one call (MADV_POPULATE_WRITE, Linux 5.14)
 *   instead of a fault each: they are all written soon anyway.
 * Where the kernel has either off, the call fails and nothing changes. */
enum { HUGE = 2 << 20, PAGE = 4096, POPULATE_MIN = 16 * PAGE, POPULATE_SPLIT = 256 * PAGE, POPULATE_CHUNK = HUGE };

#ifdef MADV_HUGEPAGE
/* the end of the main heap already advised; the heap only grows upwards
 * from below the first large block seen */
static _Atomic uintptr_t heap_advised;

static void heap_pages(uintptr_t p) {
  uintptr_t top = (uintptr_t)sbrk(0);
  if (top == (uintptr_t)-1 || p >= top) return; /* mapped by itself, not on the heap */
  uintptr_t from = atomic_load(&heap_advised);
  if (from >= top) return;
  if (!from || from > p) from = p & ~(uintptr_t)(HUGE - 1);
  if (atomic_exchange(&heap_advised, top) >= top) return;
  (void)madvise((void *)from, top - from, MADV_HUGEPAGE);
}
#endif

#ifdef MADV_POPULATE_WRITE
/* Populating is the kernel zeroing and mapping pages, about 3 GB/s a thread
 * on this machine. A block asked for between parallel loops (the model's
 * levels and band planes: 72 MB of a 1920×1080 diff) was populated by one
 * thread while the others waited for the next loop — 20–35 ms of the run on
 * 2 threads with one idle (docs/speed.md, "Sixth pass: the process"). So a
 * block of POPULATE_SPLIT bytes or more asked for outside a parallel region
 * is populated by the team, a slice each, cut at huge-page boundaries where
 * the block has several per thread (a huge page is zeroed whole by
 * whichever thread touches it first). Inside a parallel region (the two
 * files decoding at once) the calling thread populates its block alone.
 * Only the process's first thread does so (below). Which thread populates a
 * page changes no value.
 *
 * A populating call holds the process's mmap lock (for reading) until it
 * returns, and mmap and MADV_HUGEPAGE wait for it (they write): the second
 * file's image, asked for while the first's 25 MB were being populated,
 * waited 3–4 ms for all of them. Populating a huge page a call lets them in
 * between: the second file's decoding now starts within a millisecond of the
 * first's, and both files are decoded about 5 ms sooner (docs/speed.md). */
static void populate_run(uintptr_t a, uintptr_t e) {
  for (uintptr_t c = a; c < e; c += POPULATE_CHUNK)
    (void)madvise((void *)c, e - c < POPULATE_CHUNK ? e - c : POPULATE_CHUNK, MADV_POPULATE_WRITE);
}

static void populate(uintptr_t a, uintptr_t e) {
  /* only the process's first thread starts a team: a thread of jnd's own
   * (lod's and pop's workers, pthreads) would start one more team each,
   * more threads than cores, for a block it fills itself anyway */
  const int nt = omp_in_parallel() || gettid() != getpid() ? 1 : omp_get_max_threads();
  if (nt <= 1 || e - a < POPULATE_SPLIT) {
    populate_run(a, e);
    return;
  }
  const uintptr_t grain = e - a >= 2 * (uintptr_t)HUGE * (uintptr_t)nt ? HUGE : PAGE;
#pragma omp parallel for num_threads(nt) schedule(static)
  for (int t = 0; t < nt; t++) {
    uintptr_t from = a + (e - a) / (uintptr_t)nt * (uintptr_t)t, to = a + (e - a) / (uintptr_t)nt * (uintptr_t)(t + 1);
    from = t == 0 ? a : (from + grain - 1) & ~(grain - 1);
    to = (to + grain - 1) & ~(grain - 1); /* the last slice's end rounds to e or past it */
    if (to > e) to = e;
    if (to > from) populate_run(from, to);
  }
}
#endif

static void *large_pages(void *p, size_t bytes) {
  if (!p || bytes < POPULATE_MIN) return p;
#ifdef MADV_HUGEPAGE
  heap_pages((uintptr_t)p);
  if (bytes >= 2 * (size_t)HUGE) {
    uintptr_t a = ((uintptr_t)p + HUGE - 1) & ~(uintptr_t)(HUGE - 1);
    uintptr_t e = ((uintptr_t)p + bytes) & ~(uintptr_t)(HUGE - 1);
    if (e > a) (void)madvise((void *)a, e - a, MADV_HUGEPAGE);
  }
#endif
#ifdef MADV_POPULATE_WRITE
  uintptr_t a = ((uintptr_t)p + PAGE - 1) & ~(uintptr_t)(PAGE - 1);
  uintptr_t e = ((uintptr_t)p + bytes) & ~(uintptr_t)(PAGE - 1);
  if (e > a) populate(a, e);
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
