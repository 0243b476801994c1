/* Calibration to measured thresholds (000 §6–§7): a synthetic observer with
 * a known percentile and transform is recovered. */
#include "jnd.h"
#include "test.h"

#define NS 8
#define NR 10

static double res[NR];
static double pct[NS][NR * JND_CALIB_NPCT];
static jnd_calib_scene scenes[NS];

/* A scene's JND maps: amplitude growing as the resolution falls, a heavy
 * tail whose shape differs per scene and per resolution (so that one
 * percentile cannot stand in for another). */
static void make_scenes(void) {
  unsigned seed = 7;
  for (int i = 0; i < NR; i++) res[i] = 1024 - 96 * i;
  for (int s = 0; s < NS; s++) {
    double alpha = 1.5 + 0.3 * s, amp = 0.4 + 0.12 * s, gamma = 0.8 + 0.05 * (s % 4);
    for (int i = 0; i < NR; i++) {
      jnd_image m;
      jnd_image_alloc(&m, 64, 64, 1);
      double d = pow(1024.0 / res[i] - 1, gamma), w = 0.3 + 0.5 * i / (NR - 1.0);
      for (int k = 0; k < 64 * 64; k++) {
        seed = seed * 1664525u + 1013904223u;
        double u = ((seed >> 8) + 1.0) / 16777218.0;
        double tail = pow(u, -1 / alpha) - 1;
        m.data[k] = (float)(amp * d * (w * tail + (1 - w) * u));
      }
      CHECK_OK(jnd_calib_percentiles(&m, NULL, &pct[s][i * JND_CALIB_NPCT]));
      jnd_image_free(&m);
    }
  }
}

/* the synthetic observer: the calibrated pooled P over the series, and the
 * measured µ, σ as 000 eq. 1 fitted to it */
static void observe(double percentile, double a, double b) {
  for (int s = 0; s < NS; s++) {
    double p[NR];
    jnd_calibration c;
    jnd_calibration_defaults(&c);
    c.scale = a;
    c.bias = b;
    int k = (int)percentile - JND_CALIB_PCT_LO;
    for (int i = 0; i < NR; i++) {
      double x = a * pct[s][i * JND_CALIB_NPCT + k] + b;
      p[i] = jnd_probability(x > 0 ? x : 0, c.beta);
    }
    jnd_psychometric f;
    CHECK_OK(jnd_psychometric_fit(res, p, NR, 0, &f));
    snprintf(scenes[s].name, sizeof scenes[s].name, "scene%d", s);
    scenes[s].nres = NR;
    scenes[s].res = res;
    scenes[s].jnd_pct = pct[s];
    scenes[s].mu = f.mu;
    scenes[s].sigma = f.sigma;
  }
}

TEST(calibration_recovers_a_synthetic_observer) {
  make_scenes();
  const double true_pct = 96, true_a = 0.6, true_b = 0.3;
  observe(true_pct, true_a, true_b);
  jnd_calibrate_params p;
  jnd_calibrate_defaults(&p);
  p.folds = 4;
  jnd_calibrate_result r;
  CHECK_OK(jnd_calibrate_fit(scenes, NS, &p, &r));
  fprintf(stderr, "recovered p%g, scale %.4f, bias %.4f (true p%g, %g, %g); train MAE %.2f px, held out %.2f px\n",
          r.cal.percentile, r.cal.scale, r.cal.bias, true_pct, true_a, true_b, r.mae_px, r.cv_mae_px);
  CHECK_NEAR(r.cal.percentile, true_pct, 0);
  CHECK_NEAR(r.cal.scale, true_a, 0.1 * true_a);
  CHECK_NEAR(r.cal.bias, true_b, 0.1 * true_b);
  CHECK(r.mae_px < 5);
  CHECK(r.folds == 4);
  for (int k = 0; k < r.folds; k++) CHECK(r.fold_mae_px[k] < 40);
  for (int s = 0; s < NS; s++) CHECK(isfinite(r.errors_px[s]));
  jnd_calibrate_result_free(&r);
}

TEST(identity_calibration_pools_like_diff) {
  jnd_image m;
  jnd_image_alloc(&m, 32, 32, 1);
  for (int k = 0; k < 32 * 32; k++) m.data[k] = (float)(k % 97) / 40.0f;
  jnd_calibration c;
  jnd_calibration_defaults(&c);
  jnd_diff_stats a, b;
  CHECK_OK(jnd_diff_summarise(&m, 3.5, NULL, &a));
  CHECK_OK(jnd_diff_summarise_calibrated(&m, &c, &b));
  CHECK_NEAR(a.p_detect, b.p_detect, 1e-6);
  CHECK_NEAR(jnd_calibration_pool(&c, &m, NULL), a.p_detect, 1e-6);
  c.scale = 0.5;
  CHECK(jnd_calibration_pool(&c, &m, NULL) < a.p_detect);
  jnd_image_free(&m);
}

TEST(calibration_file_round_trips_and_bad_files_are_refused) {
  char path[1200], bad[1200];
  snprintf(path, sizeof path, "%s/cal.json", test_tmp_dir());
  snprintf(bad, sizeof bad, "%s/bad.json", test_tmp_dir());
  jnd_calibration c, d;
  jnd_calibration_defaults(&c);
  c.percentile = 95;
  c.scale = 0.7;
  c.bias = -0.2;
  CHECK_OK(jnd_calibration_save(path, &c));
  CHECK_OK(jnd_calibration_load(path, &d));
  CHECK_NEAR(d.percentile, 95, 0);
  CHECK_NEAR(d.scale, 0.7, 1e-12);
  CHECK_NEAR(d.bias, -0.2, 1e-12);
  FILE *f = fopen(bad, "w");
  fputs("{\"calibration\": {\"percentile\": 95}}", f);
  fclose(f);
  CHECK_STATUS(jnd_calibration_load(bad, &d), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "scale") != NULL);
  CHECK_STATUS(jnd_calibration_load("/nonexistent/cal.json", &d), JND_ERR_IO);
}

RUN_TESTS(calibration_recovers_a_synthetic_observer, identity_calibration_pools_like_diff,
          calibration_file_round_trips_and_bad_files_are_refused)
