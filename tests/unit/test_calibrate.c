/* Calibration to measured thresholds (000 §6–§7): a synthetic observer with
 * a known percentile and transform is recovered. */
#include "jnd.h"
#include "test.h"

#define NS 8
#define NR 10
#define NPX (64 * 64)

static double res[NR];
static double pct[NS][NR * JND_CALIB_NPCT];  /* the library's percentiles: the calibration's input */
static double own96[NS][NR];                 /* the observer's own 96th percentile of each map */
static jnd_calib_scene scenes[NS];

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* the p-th percentile by its definition: sort, rank p/100 · (n − 1), linear between ranks */
static double own_percentile(const float *v, int n, double p) {
  float *s = malloc(sizeof *s * (size_t)n);
  memcpy(s, v, sizeof *s * (size_t)n);
  qsort(s, (size_t)n, sizeof *s, cmp_float);
  double pos = p / 100 * (n - 1);
  int k = (int)floor(pos);
  double r = k >= n - 1 ? s[n - 1] : s[k] + (pos - k) * (s[k + 1] - s[k]);
  free(s);
  return r;
}

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
      for (int k = 0; k < NPX; k++) {
        seed = seed * 1664525u + 1013904223u;
        double u = ((seed >> 8) + 1.0) / 16777218.0;
        double tail = pow(u, -1 / alpha) - 1;
        m.data[k] = (float)(amp * d * (w * tail + (1 - w) * u));
      }
      CHECK_OK(jnd_calib_percentiles(&m, NULL, &pct[s][i * JND_CALIB_NPCT]));
      /* the library's percentiles 90..99 are the definition's */
      for (int k = 0; k < JND_CALIB_NPCT; k++)
        CHECK_NEAR(pct[s][i * JND_CALIB_NPCT + k], own_percentile(m.data, NPX, JND_CALIB_PCT_LO + k),
                   1e-6 * (1 + fabs(pct[s][i * JND_CALIB_NPCT + k])));
      own96[s][i] = own_percentile(m.data, NPX, 96);
      jnd_image_free(&m);
    }
  }
}

/* Θ⁻¹(q) by bisection on Θ(x) = ½ erfc(−x/√2) */
static double normal_quantile(double q) {
  double lo = -40, hi = 40;
  for (int i = 0; i < 200; i++) {
    double mid = 0.5 * (lo + hi);
    if (0.5 * erfc(-mid / M_SQRT2) < q) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

/* 000 eq. 1: P(r) = 1 − Θ((r − µ)/σ) */
static double eq1(double r, double mu, double sigma) { return 1 - 0.5 * erfc(-(r - mu) / (sigma * M_SQRT2)); }

static double sse(const double *p, double mu, double sigma) {
  double e = 0;
  for (int i = 0; i < NR; i++) e += (eq1(res[i], mu, sigma) - p[i]) * (eq1(res[i], mu, sigma) - p[i]);
  return e;
}

/* The synthetic observer, built from the equations alone (none of the
 * library's functions, so that it can catch an error they share): its
 * probability of detection at each resolution is 000 eq. 4 (β = 3.5) of the
 * transformed 96th percentile, P = 1 − 0.5^((a·J96 + b)^3.5); its measured
 * µ, σ are 000 eq. 1 fitted to those P by least squares on probability.
 * The fit starts from probit regression (Θ⁻¹(1 − P) = r/σ − µ/σ is a line in
 * r; least squares through the points with 0.01 < P < 0.99) and is refined by
 * a compass search on (µ, ln σ) with halving steps. */
static void observe(double a, double b) {
  for (int s = 0; s < NS; s++) {
    double p[NR], sx = 0, sy = 0, sxx = 0, sxy = 0;
    int m = 0;
    for (int i = 0; i < NR; i++) {
      double x = a * own96[s][i] + b;
      p[i] = x > 0 ? 1 - pow(0.5, pow(x, 3.5)) : 0;
      if (!(p[i] > 0.01 && p[i] < 0.99)) continue;
      double z = normal_quantile(1 - p[i]);
      sx += res[i], sy += z, sxx += res[i] * res[i], sxy += res[i] * z, m++;
    }
    CHECK(m >= 3);
    double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx), icpt = (sy - slope * sx) / m;
    double mu = -icpt / slope, ls = log(1 / slope), step[2] = {50, 0.5};
    double best = sse(p, mu, exp(ls));
    while (step[0] > 1e-7) {
      int moved = 0;
      for (int d = 0; d < 4; d++) {
        double m2 = mu + (d == 0 ? step[0] : d == 1 ? -step[0] : 0), l2 = ls + (d == 2 ? step[1] : d == 3 ? -step[1] : 0);
        double e = sse(p, m2, exp(l2));
        if (e < best) best = e, mu = m2, ls = l2, moved = 1;
      }
      if (!moved) step[0] /= 2, step[1] /= 2;
    }
    snprintf(scenes[s].name, sizeof scenes[s].name, "scene%d", s);
    scenes[s].nres = NR;
    scenes[s].res = res;
    scenes[s].jnd_pct = pct[s];
    scenes[s].mu = mu;
    scenes[s].sigma = exp(ls);
  }
}

TEST(calibration_recovers_a_synthetic_observer) {
  make_scenes();
  const double true_pct = 96, true_a = 0.6, true_b = 0.3;
  observe(true_a, true_b);
  jnd_calibrate_params p;
  jnd_calibrate_defaults(&p);
  p.folds = 4;
  jnd_calibrate_result r;
  CHECK_OK(jnd_calibrate_fit(scenes, NS, &p, &r));
  fprintf(stderr, "recovered p%g, scale %.4f, bias %.4f (true p%g, %g, %g); train MAE %.2f px, held out %.2f px\n",
          r.cal.percentile, r.cal.scale, r.cal.bias, true_pct, true_a, true_b, r.mae_px, r.cv_mae_px);
  CHECK_NEAR(r.cal.percentile, true_pct, 0);
  /* the observer is exactly of the calibration's family: recovered closely */
  CHECK_NEAR(r.cal.scale, true_a, 0.03 * true_a);
  CHECK_NEAR(r.cal.bias, true_b, 0.03 * true_b);
  CHECK_NEAR(r.cal.beta, 3.5, 0); /* 000 eq. 4, the observer's slope */
  CHECK(r.mae_px < 1);
  CHECK(r.folds == 4);
  for (int k = 0; k < r.folds; k++) CHECK(r.fold_mae_px[k] < 5);
  for (int s = 0; s < NS; s++) CHECK(isfinite(r.errors_px[s]));
  jnd_calibrate_result_clear(&r);
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

/* 000 §7 by hand: on a uniform map every percentile is its value x, so the
 * pooled P of a calibration is 1 − 0.5^(max(0, scale·x + bias)^β), from the
 * map (jnd_calibration_pool) and from the P map (jnd_diff_summarise_calibrated)
 * alike; a negative bias makes small differences invisible (P 0) */
TEST(a_calibration_is_max_of_0_and_scale_times_jnd_plus_bias_000_section_7) {
  jnd_calibration c;
  jnd_calibration_defaults(&c);
  c.scale = 1.5, c.bias = -0.4, c.beta = 3.5;
  const double xs[5] = {0.1, 0.26, 0.5, 1.0, 2.0};
  jnd_image m;
  CHECK_OK(jnd_image_alloc(&m, 16, 16, 1));
  for (int i = 0; i < 5; i++) {
    for (int k = 0; k < 16 * 16; k++) m.data[k] = (float)xs[i];
    double x = 1.5 * (double)(float)xs[i] - 0.4, want = x > 0 ? 1 - pow(0.5, pow(x, 3.5)) : 0;
    CHECK_NEAR(jnd_calibration_pool(&c, &m, NULL), want, 1e-6);
    jnd_diff_stats st;
    CHECK_OK(jnd_diff_summarise_calibrated(&m, &c, &st));
    CHECK_NEAR(st.p_detect, want, 1e-6);
  }
  jnd_image_free(&m);
}

/* the default calibration pools at P93 (000 §6): on a ramp of JND 0..1 the
 * pooled P is that of JND 0.93 (P95 would give that of 0.95: 0.440, not 0.416) */
TEST(the_default_calibration_pools_at_the_93rd_percentile) {
  jnd_calibration c;
  jnd_calibration_defaults(&c);
  jnd_image m;
  CHECK_OK(jnd_image_alloc(&m, 40, 25, 1));
  for (int k = 0; k < 1000; k++) m.data[k] = (float)(k / 999.0);
  double want = 1 - pow(0.5, pow(0.93, 3.5));
  CHECK_NEAR(jnd_calibration_pool(&c, &m, NULL), want, 0.003);
  jnd_diff_stats st;
  CHECK_OK(jnd_diff_summarise_calibrated(&m, &c, &st));
  CHECK_NEAR(st.p_detect, want, 0.003);
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
          a_calibration_is_max_of_0_and_scale_times_jnd_plus_bias_000_section_7,
          the_default_calibration_pools_at_the_93rd_percentile,
          calibration_file_round_trips_and_bad_files_are_refused)
