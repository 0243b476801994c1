/* A minimal test harness: a test file is a list of TEST(property_name) blocks,
 * each a statement of a property; main() is RUN_TESTS(name, name, ...).
 * CHECK* report file:line and the values and keep going; the process exits 1
 * if any check failed, so CTest sees it. */
#ifndef JND_TEST_H
#define JND_TEST_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int test_failures_;
static int test_checks_;
static int test_skips_;

/* A test that cannot run here (no shared data, no renderer, a package not
 * installed) calls TEST_SKIP("why") and returns. The binary then exits 77,
 * which CTest reports as skipped, not passed. Where JND_NO_SKIP is set (CI,
 * which has all of them) a skip is a failure. */
#define TEST_SKIP(...) do { test_skips_++; fprintf(stderr, "skip: " __VA_ARGS__); fputc('\n', stderr); \
  if (getenv("JND_NO_SKIP") && *getenv("JND_NO_SKIP")) { test_failures_++; \
  fprintf(stderr, "%s:%d: skipped, but JND_NO_SKIP is set\n", __FILE__, __LINE__); } } while (0)

/* A skip of the file's remaining tests (each needs what is missing): exits
 * as RUN_TESTS would, 77 or, where JND_NO_SKIP is set, 1. */
#define TEST_SKIP_REST(...) do { TEST_SKIP(__VA_ARGS__); \
  fprintf(stderr, "%d checks, %d failed, %d skipped\n", test_checks_, test_failures_, test_skips_); \
  exit(test_failures_ ? 1 : 77); } while (0)

#define TEST(name) static void name(void)

#define CHECK(cond) do { test_checks_++; if (!(cond)) { test_failures_++; \
  fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #cond); } } while (0)

#define CHECK_NEAR(a, b, tol) do { double a_ = (a), b_ = (b); test_checks_++; \
  if (!(fabs(a_ - b_) <= (tol))) { test_failures_++; \
  fprintf(stderr, "%s:%d: CHECK_NEAR(%s, %s, %s): %.9g vs %.9g\n", __FILE__, __LINE__, #a, #b, #tol, a_, b_); } } while (0)

#define CHECK_LT(a, b) do { double a_ = (a), b_ = (b); test_checks_++; if (!(a_ < b_)) { test_failures_++; \
  fprintf(stderr, "%s:%d: CHECK_LT(%s, %s): %.9g vs %.9g\n", __FILE__, __LINE__, #a, #b, a_, b_); } } while (0)

#define CHECK_OK(expr) do { jnd_status s_ = (expr); test_checks_++; if (s_ != JND_OK) { test_failures_++; \
  fprintf(stderr, "%s:%d: %s returned %d: %s\n", __FILE__, __LINE__, #expr, (int)s_, jnd_last_error()); } } while (0)

#define CHECK_STATUS(expr, want) do { jnd_status s_ = (expr); test_checks_++; if (s_ != (want)) { test_failures_++; \
  fprintf(stderr, "%s:%d: %s returned %d, wanted %d (%s)\n", __FILE__, __LINE__, #expr, (int)s_, (int)(want), jnd_last_error()); } } while (0)

typedef void (*test_fn_)(void);
static inline int run_tests_(const char *names, test_fn_ *fns, int n) {
  char buf[4096]; snprintf(buf, sizeof buf, "%s", names);
  char *save = NULL, *tok = strtok_r(buf, ", ", &save);
  for (int i = 0; i < n; i++) {
    int before = test_failures_, skipped = test_skips_;
    fns[i]();
    fprintf(stderr, "%s %s\n", test_failures_ != before ? "FAIL" : test_skips_ != skipped ? "SKIP" : "ok  ",
            tok ? tok : "?");
    tok = strtok_r(NULL, ", ", &save);
  }
  fprintf(stderr, "%d checks, %d failed, %d skipped\n", test_checks_, test_failures_, test_skips_);
  return test_failures_ ? 1 : test_skips_ ? 77 : 0;
}
#define RUN_TESTS(...) int main(void) { test_fn_ fns_[] = {__VA_ARGS__}; \
  return run_tests_(#__VA_ARGS__, fns_, (int)(sizeof fns_ / sizeof fns_[0])); }

/* The shared data folder (../shared/data) or NULL when absent: tests that need it skip. */
static inline const char *test_shared_data(void) {
  static char path[1024];
  const char *s = getenv("JND_SHARED");
  if (!s) return NULL;
  snprintf(path, sizeof path, "%s/data", s);
  FILE *f; char probe[1100]; snprintf(probe, sizeof probe, "%s/README.md", path);
  if (!(f = fopen(probe, "r"))) return NULL;
  fclose(f);
  return path;
}

/* Whether an OpenGL context can be had here (tests that render skip without). */
#ifdef JND_H
static inline int test_renderer_available(void) {
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = rp.height = 16;
  jnd_renderer *r;
  if (jnd_renderer_create(&rp, &r) != JND_OK) return 0;
  jnd_renderer_free(r);
  return 1;
}
#endif

/* A scratch directory for this test binary (created on demand). */
static inline const char *test_tmp_dir(void) {
  static char path[1024];
  const char *t = getenv("JND_TMP");
  snprintf(path, sizeof path, "%s", t ? t : "/tmp/jnd-test");
  char cmd[1100]; snprintf(cmd, sizeof cmd, "mkdir -p '%s'", path);
  if (system(cmd) != 0) return "/tmp";
  return path;
}
#endif
