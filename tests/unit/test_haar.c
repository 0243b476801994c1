/* Properties of the CSF-weighted Haar bands of 003 §4.2 (src/vision/haar.c). */
#include <math.h>
#include <stdlib.h>

#include "jnd.h"
#include "test.h"
#include "vision/vision.h"

TEST(haar_energies_add_up_to_the_plane_parseval) {
  int w = 37, h = 23;
  float *p = malloc(sizeof(float) * w * h);
  double total = 0;
  unsigned x = 12345;
  for (int i = 0; i < w * h; i++) {
    x = x * 1103515245u + 12345u;
    p[i] = (float)((x >> 8) % 1000) / 1000.0f;
    total += (double)p[i] * p[i];
  }
  double e[32], rest = 0, sum = 0;
  int n = jnd_haar_band_energy(p, w, h, e, 32, &rest);
  CHECK(n == 6);   /* 37 → 19 → 10 → 5 → 3 → 2 → 1 */
  for (int m = 0; m < n; m++) sum += e[m];
  CHECK_NEAR(sum + rest, total, 1e-6 * total);
  free(p);
}

TEST(haar_puts_a_pattern_in_the_band_of_its_period) {
  enum { W = 64 };
  static float p[W * W];
  double e[32], rest;
  /* a checkerboard: all detail at level 1 */
  for (int y = 0; y < W; y++)
    for (int x = 0; x < W; x++) p[y * W + x] = (float)((x + y) % 2);
  int n = jnd_haar_band_energy(p, W, W, e, 32, &rest);
  CHECK(n == 6);
  CHECK(e[0] > 0);
  for (int m = 1; m < n; m++) CHECK(e[m] < 1e-9 * e[0]);
  /* bars two pixels wide (period 4): nothing at level 1, all at level 2 */
  for (int y = 0; y < W; y++)
    for (int x = 0; x < W; x++) p[y * W + x] = (float)((x / 2) % 2);
  jnd_haar_band_energy(p, W, W, e, 32, &rest);
  CHECK(e[0] < 1e-9 && e[1] > 0);
  for (int m = 2; m < n; m++) CHECK(e[m] < 1e-9 * e[1]);
  /* a constant: no detail at all */
  for (int i = 0; i < W * W; i++) p[i] = 0.5f;
  jnd_haar_band_energy(p, W, W, e, 32, &rest);
  for (int m = 0; m < n; m++) CHECK(e[m] < 1e-9);
  CHECK_NEAR(rest, 0.25 * W * W, 1e-6);
}

TEST(mannos_sakrison_csf_peaks_near_eight_cycles_per_degree) {
  double best = 0, at = 0;
  for (double f = 0.25; f < 60; f += 0.01) {
    double c = jnd_csf_mannos_sakrison(f);
    if (c > best) best = c, at = f;
  }
  CHECK_NEAR(at, 8.0, 0.5);
  CHECK_NEAR(best, 0.981, 0.01);
  /* 003's form: (0.0499 + 0.2964 f) exp(−(0.114 f)^1.1) */
  CHECK_NEAR(jnd_csf_mannos_sakrison(20), (0.0499 + 0.2964 * 20) * exp(-pow(0.114 * 20, 1.1)), 1e-12);
  CHECK(jnd_csf_mannos_sakrison(50) < 0.05);
}

TEST(band_weight_is_the_csf_mean_over_the_band) {
  /* level m of a 40 ppd display spans [40 / 2^(m+1), 40 / 2^m] cpd */
  for (int m = 1; m <= 5; m++) {
    double hi = 40.0 / (1 << m), lo = hi / 2, mean = 0;
    int n = 100000;
    for (int i = 0; i < n; i++) mean += jnd_csf_mannos_sakrison(lo + (i + 0.5) * (hi - lo) / n) / n;
    CHECK_NEAR(jnd_haar_band_weight(m, 40), mean, 1e-6);
  }
  /* a finer display (a phone) weighs its finest band less: it is beyond the eye */
  CHECK(jnd_haar_band_weight(1, 94) < 0.5 * jnd_haar_band_weight(1, 38));
  CHECK(jnd_haar_band_weight(0, 40) == 0);
}

RUN_TESTS(haar_energies_add_up_to_the_plane_parseval, haar_puts_a_pattern_in_the_band_of_its_period,
          mannos_sakrison_csf_peaks_near_eight_cycles_per_degree, band_weight_is_the_csf_mean_over_the_band)
