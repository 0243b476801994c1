#include <float.h>
#include <malloc.h>
#include <math.h>
#include <omp.h>
#include <pthread.h>
#include <sched.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include "test.h"
#include "core/core.h"
#include "jnd.h"
#include "core/fastmath.h"
#include "tasks/tasks.h"

TEST(image_alloc_is_zeroed_and_planar) {
  jnd_image img;
  CHECK_OK(jnd_image_alloc(&img, 5, 4, 3));
  CHECK(img.w == 5 && img.h == 4 && img.c == 3);
  CHECK(jnd_image_plane(&img, 2) == img.data + 2 * 20);
  double s = 0;
  for (int i = 0; i < 60; i++) s += img.data[i];
  CHECK(s == 0);
  jnd_image_free(&img);
  CHECK(img.data == NULL);
}

/* the whole pages of [p, p + n) that are not mapped in yet */
static size_t pages_not_resident(const void *p, size_t n) {
  const uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE);
  const uintptr_t a = ((uintptr_t)p + page - 1) & ~(page - 1), e = ((uintptr_t)p + n) & ~(page - 1);
  if (e <= a) return 0;
  size_t np = (e - a) / page, missing = 0;
  unsigned char *v = malloc(np);
  if (!v || mincore((void *)a, e - a, v) != 0) {
    free(v);
    return (size_t)-1;
  }
  for (size_t i = 0; i < np; i++) missing += !(v[i] & 1);
  free(v);
  return missing;
}

/* jnd_alloc populates a block of 16 pages or more before handing it out
 * (src/core/alloc.c); between parallel loops the team populates it, a slice
 * each: no page may fall between two slices, whatever the block's length
 * and alignment, the thread count, or whether the caller is in a parallel
 * region. Where the kernel has no MADV_POPULATE_WRITE (before 5.14) there
 * is nothing to check. */
TEST(large_blocks_are_mapped_in_whole_whoever_populates_them) {
#ifdef MADV_POPULATE_WRITE
  void *probe = mmap(NULL, 4096, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  CHECK(probe != MAP_FAILED);
  const int works = madvise(probe, 4096, MADV_POPULATE_WRITE) == 0;
  munmap(probe, 4096);
  if (!works) return;
  /* every block a fresh mapping: glibc would otherwise raise its mmap
   * threshold after the first free and hand out heap memory already mapped
   * in (under ASan, whose allocator maps large blocks by themselves, the
   * call does nothing) */
  (void)mallopt(M_MMAP_THRESHOLD, 64 * 1024);
  const size_t sizes[] = {16 * 4096 + 100, 256 * 4096, 257 * 4096 + 1, (4u << 20) + 3 * 4096 + 8, (9u << 20) + 12345,
                          (16u << 20) + 5 * 4096};
  const int previous = omp_get_max_threads();
  for (int nt = 1; nt <= 3; nt++) {
    omp_set_num_threads(nt);
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
      unsigned char *p = jnd_alloc(sizes[i], 1), *q = jnd_calloc(sizes[i], 1);
      CHECK(p && q);
      CHECK(pages_not_resident(p, sizes[i]) == 0);
      CHECK(pages_not_resident(q, sizes[i]) == 0);
      CHECK(q[0] == 0 && q[sizes[i] / 2] == 0 && q[sizes[i] - 1] == 0);
      free(p);
      free(q);
    }
    size_t missing = 0;
#pragma omp parallel num_threads(2) reduction(+ : missing)
    {
      unsigned char *p = jnd_alloc(sizes[4], 1);
      missing += p ? pages_not_resident(p, sizes[4]) : 1;
      free(p);
    }
    CHECK(missing == 0);
  }
  omp_set_num_threads(previous);
#endif
}

TEST(image_alloc_refuses_zero_and_oversized) {
  jnd_image img;
  CHECK_STATUS(jnd_image_alloc(&img, 0, 10, 3), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_image_alloc(&img, JND_MAX_SIDE + 1, 1, 1), JND_ERR_LIMIT);
  CHECK_STATUS(jnd_image_alloc(&img, 20000, 20000, 1), JND_ERR_LIMIT);
  CHECK(strstr(jnd_last_error(), "limit") != NULL);
}

TEST(error_messages_are_one_line) {
  jnd_fail(JND_ERR_IO, "a\nb\rc");
  CHECK(strchr(jnd_last_error(), '\n') == NULL);
  CHECK(strcmp(jnd_last_error(), "a b c") == 0);
}

TEST(rng_is_deterministic_and_uniform) {
  jnd_rng a, b;
  jnd_rng_seed(&a, 42);
  jnd_rng_seed(&b, 42);
  double mean = 0;
  for (int i = 0; i < 10000; i++) {
    double u = jnd_rng_uniform(&a);
    CHECK(u == jnd_rng_uniform(&b));
    mean += u;
  }
  CHECK_NEAR(mean / 10000, 0.5, 0.02);
  double s2 = 0;
  for (int i = 0; i < 10000; i++) {
    double z = jnd_rng_normal(&a);
    s2 += z * z;
  }
  CHECK_NEAR(s2 / 10000, 1.0, 0.05);
}

/* The fast log2 / exp2 / pow against libm (in double) over the model's
 * ranges. Measured worst relative errors (x86-64, with and without FMA):
 * log2 2.7e-7 over x in 1e-30 … 1e30 and every float in [√½, √2), exp2
 * 2.4e-7 over -126 … 127, pow 5.0e-6 over x in 1e-6 … 1e6 with the model's
 * exponents (the rounding of y·log2 x to float, 70 at most here). */
TEST(fast_log2_exp2_pow_match_libm_over_the_models_ranges) {
  double wl = 0, we = 0, wp = 0;
  for (float x = 1e-30f; x < 1e30f; x *= 1.0007f) {
    if (fabsf(x - 1.0f) < 1e-3f) continue;
    const double want = log2((double)x), rel = fabs(jnd_fast_log2(x) - want) / fabs(want);
    if (rel > wl) wl = rel;
  }
  for (float m = 0.70710677f; m < 1.4142135f; m = nextafterf(m, 2.0f)) { /* every mantissa */
    if (m == 1.0f) continue;
    const double want = log2((double)m), rel = fabs(jnd_fast_log2(m) - want) / fabs(want);
    if (rel > wl) wl = rel;
  }
  for (float y = -126.0f; y <= 127.0f; y += 0.00037f) {
    const double want = exp2((double)y), rel = fabs(jnd_fast_exp2(y) - want) / want;
    if (rel > we) we = rel;
  }
  const float ys[] = {2.4f, 1.0f / 2.4f, -0.1f, 3.5f, 0.3f, 1.458f, 2.0f, 0.5f};
  for (float x = 1e-6f; x < 1e6f; x *= 1.0013f)
    for (int k = 0; k < 8; k++) {
      const double want = pow(x, ys[k]), rel = fabs(jnd_fast_pow(x, ys[k]) - want) / want;
      if (rel > wp) wp = rel;
    }
  CHECK_LT(wl, 3e-7);
  CHECK_LT(we, 3e-7);
  CHECK_LT(wp, 6e-6);
  CHECK(jnd_fast_log2(1.0f) == 0.0f);
  CHECK(jnd_fast_pow(0.0f, 2.4f) == 0.0f);
  CHECK_NEAR(jnd_fast_log2(8.0f), 3.0, 1e-6);
  CHECK_NEAR(jnd_fast_exp2(-3.0f), 0.125, 1e-9);
}

TEST(first_outside_finds_the_first_bad_value_in_any_block) {
  enum { N = 3 * 4096 + 17 };
  static float v[N];
  for (size_t i = 0; i < N; i++) v[i] = (float)(i % 11) / 10; /* 0 .. 1, both ends included */
  CHECK(jnd_first_outside(v, N, 0, 1) == N);
  CHECK(jnd_first_outside(v, 0, 0, 1) == 0);
  CHECK(jnd_first_outside(v, N, 0.05f, 1) == 0); /* v[0] = 0 is below */
  CHECK(jnd_first_outside(v, N, 0, 0.95f) == 10);
  /* one bad value at a time, either side of the block edges */
  const size_t at[] = {0, 4095, 4096, 4097, 2 * 4096 - 1, N - 1};
  const float bad[] = {NAN, INFINITY, -INFINITY, -0.001f, 1.001f};
  for (size_t a = 0; a < sizeof at / sizeof at[0]; a++)
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
      float keep = v[at[a]];
      v[at[a]] = bad[b];
      CHECK(jnd_first_outside(v, N, 0, 1) == at[a]);
      if (b < 3) CHECK(jnd_first_outside(v, N, -FLT_MAX, FLT_MAX) == at[a]); /* not finite */
      else CHECK(jnd_first_outside(v, N, -FLT_MAX, FLT_MAX) == N);
      v[at[a]] = keep;
    }
  /* two: the earlier */
  v[9000] = NAN;
  v[5000] = 2;
  CHECK(jnd_first_outside(v, N, 0, 1) == 5000);
}

TEST(clocks_advance_with_work_and_never_go_back) {
  double w0 = jnd_seconds(), c0 = jnd_cpu_seconds(), prev = w0;
  volatile double x = 0;
  int backwards = 0;
  for (int i = 0; i < 2000000; i++) {
    x += sqrt((double)i);
    if (i % 100000 == 0) {
      double t = jnd_seconds();
      backwards += t < prev;
      prev = t;
    }
  }
  double w1 = jnd_seconds(), c1 = jnd_cpu_seconds();
  CHECK(backwards == 0);
  CHECK_LT(w0, w1); /* 2 M square roots take more than a nanosecond */
  CHECK_LT(c0, c1);
  CHECK_LT(w1 - w0, 60); /* seconds, not milliseconds or nanoseconds */
  CHECK(x > 0);
}

/* A library opened on first use (core.h, jnd_lazy_symbol): its functions
 * are the library's own; a library or symbol that cannot be had is NULL
 * with a message naming it, and the shims built for assimp and LAPACKE call
 * through. */
TEST(lazy_libraries_give_their_own_functions_or_name_what_is_missing) {
  jnd_lazy_lib m = {"libm.so.6", NULL};
  double (*cosine)(double) = (double (*)(double))jnd_lazy_symbol(&m, "cos");
  CHECK(cosine != NULL && cosine(0.5) == cos(0.5));
  CHECK(jnd_lazy_symbol(&m, "jnd_no_such_function") == NULL);
  CHECK(strstr(jnd_last_error(), "libm.so.6") && strstr(jnd_last_error(), "jnd_no_such_function"));
  jnd_lazy_lib none = {"libjnd-no-such-library.so.0", NULL};
  CHECK(jnd_lazy_symbol(&none, "cos") == NULL && none.handle == NULL);
  CHECK(strstr(jnd_last_error(), "libjnd-no-such-library.so.0") != NULL);
  /* through the LAPACKE shim (or LAPACKE itself): [[2, 1], [1, 2]] has
   * eigenvalues 1 and 3 */
  double a[4] = {2, 1, 1, 2}, val[2] = {0, 0}, vec[4];
  CHECK_OK(linalg_symmetric_eigen(a, 2, val, vec));
  CHECK(fabs(val[0] + val[1] - 4) < 1e-12 && fabs(val[0] * val[1] - 3) < 1e-12);
}

/* jnd_threads_pin (docs/speed.md "Twelfth pass"): with one thread per CPU
 * the process may use, each thread is held to a CPU of its own, no two to
 * the same; nothing is held for more or fewer threads than CPUs, nor when
 * the user asked for a binding of their own. Runs last: it holds this
 * process's threads. */
static int cpus_of_each_thread(int n, const cpu_set_t *allowed, int *one_each, int *distinct) {
  int cpu[CPU_SETSIZE], count[CPU_SETSIZE], inside = 1;
#pragma omp parallel num_threads(n)
  {
    cpu_set_t mine;
    const int t = omp_get_thread_num();
    count[t] = pthread_getaffinity_np(pthread_self(), sizeof mine, &mine) == 0 ? CPU_COUNT(&mine) : -1;
    cpu[t] = -1;
    for (int c = 0; c < CPU_SETSIZE; c++)
      if (count[t] >= 1 && CPU_ISSET(c, &mine)) {
        if (!CPU_ISSET(c, allowed)) {
#pragma omp atomic write
          inside = 0;
        }
        if (cpu[t] < 0) cpu[t] = c;
      }
  }
  *one_each = 1;
  *distinct = 1;
  int free_ = 1;
  for (int t = 0; t < n; t++) {
    *one_each &= count[t] == 1;
    free_ &= count[t] == CPU_COUNT(allowed);
    for (int u = 0; u < t; u++) *distinct &= cpu[t] != cpu[u];
  }
  return inside ? free_ : -1;
}

TEST(threads_are_held_one_to_a_cpu_only_when_every_cpu_has_one) {
  static const char *const asked[] = {"OMP_PROC_BIND", "OMP_PLACES", "GOMP_CPU_AFFINITY", "KMP_AFFINITY"};
  for (size_t i = 0; i < sizeof asked / sizeof asked[0]; i++) unsetenv(asked[i]);
  cpu_set_t allowed;
  CHECK(sched_getaffinity(0, sizeof allowed, &allowed) == 0);
  const int n = CPU_COUNT(&allowed);
  int one_each, distinct;
  CHECK(jnd_threads_pin(n + 1) == 0);
  if (n > 1) CHECK(jnd_threads_pin(n - 1) == 0);
  setenv("OMP_PLACES", "cores", 1);
  CHECK(jnd_threads_pin(n) == 0);
  unsetenv("OMP_PLACES");
  setenv("GOMP_CPU_AFFINITY", "0", 1);
  CHECK(jnd_threads_pin(n) == 0);
  unsetenv("GOMP_CPU_AFFINITY");
  /* so far every thread may run on every CPU */
  CHECK(cpus_of_each_thread(n, &allowed, &one_each, &distinct) == 1);
  const int held = jnd_threads_pin(n);
  if (n < 2) {
    CHECK(held == 0);
    return;
  }
  CHECK(held == n);
  CHECK(cpus_of_each_thread(n, &allowed, &one_each, &distinct) == 0);
  CHECK(one_each && distinct);
  /* a smaller team keeps the held threads it takes */
  CHECK(cpus_of_each_thread(2, &allowed, &one_each, &distinct) == 0);
  CHECK(one_each && distinct);
}

RUN_TESTS(large_blocks_are_mapped_in_whole_whoever_populates_them, lazy_libraries_give_their_own_functions_or_name_what_is_missing, clocks_advance_with_work_and_never_go_back, first_outside_finds_the_first_bad_value_in_any_block, fast_log2_exp2_pow_match_libm_over_the_models_ranges, image_alloc_is_zeroed_and_planar, image_alloc_refuses_zero_and_oversized,
          error_messages_are_one_line, rng_is_deterministic_and_uniform,
          threads_are_held_one_to_a_cpu_only_when_every_cpu_has_one)
