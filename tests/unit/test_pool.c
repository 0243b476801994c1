/* The pool layer: sorting, order statistics, percentiles and pooling. */
#include "test.h"
#include "core/core.h"
#include "jnd.h"
#include "pool/pool.h"

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* values like a JND map's: many exact zeros, ties, a long tail; and optionally
 * negatives (order statistics must hold for any finite floats) */
static void fill(float *v, size_t n, uint64_t seed, int negatives) {
  jnd_rng r;
  jnd_rng_seed(&r, seed);
  for (size_t i = 0; i < n; i++) {
    double u = jnd_rng_uniform(&r);
    float x = u < 0.3 ? 0.0f : u < 0.4 ? 1.5f : (float)(exp(8 * jnd_rng_uniform(&r) - 4));
    if (negatives && jnd_rng_uniform(&r) < 0.4) x = -x;
    v[i] = x;
  }
}

TEST(order_statistics_equal_the_sorted_values) {
  const size_t sizes[] = {1, 2, 7, 100, 5000, 200000};
  for (int neg = 0; neg < 2; neg++)
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
      size_t n = sizes[si];
      float *v = malloc(n * sizeof *v), *s = malloc(n * sizeof *s);
      fill(v, n, 17 + n, neg);
      memcpy(s, v, n * sizeof *s);
      qsort(s, n, sizeof *s, cmp_float);
      size_t ks[8] = {0, n / 3, n / 2, n / 2, (size_t)(0.93 * (n - 1)), (size_t)(0.99 * (n - 1)), n - 1, n - 1};
      for (int i = 1; i < 8; i++) /* ascending, as the function wants */
        for (int j = i; j > 0 && ks[j - 1] > ks[j]; j--) {
          size_t t = ks[j];
          ks[j] = ks[j - 1];
          ks[j - 1] = t;
        }
      float out[8];
      float *before = malloc(n * sizeof *before);
      memcpy(before, v, n * sizeof *v);
      CHECK_OK(jnd_order_stats(v, n, ks, 8, out));
      for (int i = 0; i < 8; i++) CHECK(out[i] == s[ks[i]]);
      CHECK(memcmp(before, v, n * sizeof *v) == 0); /* the input is left alone */
      free(before);
      free(v);
      free(s);
    }
}

/* Most values in one bin of the top 12 key bits (as in a smooth map): the
 * ranks are found one level finer (pool.c, order_stats_level), and must
 * still be the sorted values, ties and neighbours in one fine bin included. */
TEST(order_statistics_of_values_crowded_in_one_bin_equal_the_sorted_values) {
  const size_t n = 300000;
  float *v = malloc(n * sizeof *v), *s = malloc(n * sizeof *s);
  jnd_rng r;
  jnd_rng_seed(&r, 99);
  for (size_t i = 0; i < n; i++) {
    double u = jnd_rng_uniform(&r);
    /* [1, 1.125): one coarse bin; a few values outside it and many ties */
    v[i] = u < 0.05 ? (float)(4 * u) : u < 0.2 ? 1.0625f : (float)(1 + jnd_rng_uniform(&r) / 8);
  }
  memcpy(s, v, n * sizeof *s);
  qsort(s, n, sizeof *s, cmp_float);
  size_t ks[9] = {0, n / 20, n / 7, n / 2, n / 2 + 1, (size_t)(0.93 * (n - 1)), (size_t)(0.93 * (n - 1)) + 1,
                  n - 2, n - 1};
  float out[9];
  CHECK_OK(jnd_order_stats(v, n, ks, 9, out));
  for (int i = 0; i < 9; i++) CHECK(out[i] == s[ks[i]]);
  free(v);
  free(s);
}

/* Counting apart from selecting (jnd_diff_summarise counts as it sums):
 * whatever the ranges the values are cut into, empty ones included, the
 * ranks are the sorted values; ranges that do not cover the values are
 * refused. */
TEST(ranks_selected_from_counts_of_any_ranges_equal_the_sorted_values) {
  const size_t n = 100003;
  float *v = malloc(n * sizeof *v), *s = malloc(n * sizeof *s);
  fill(v, n, 23, 1);
  /* a run of values in one bin far from the rest: the gather's groups of 8
   * without a wanted value are skipped, those with one are not */
  for (size_t i = 40000; i < 40100; i++) v[i] = 1000.0f + (float)(i % 7);
  memcpy(s, v, n * sizeof *s);
  qsort(s, n, sizeof *s, cmp_float);
  const size_t cuts[][5] = {{0, n, 0, 0, 0}, {0, 4096, n, 0, 0}, {0, 0, 50001, n, 0}, {0, 17, 17, 99999, n}};
  const int nts[] = {1, 2, 3, 4};
  size_t *h4 = malloc(4 * JND_ORDER_BINS * sizeof *h4), *hist = malloc(4 * JND_ORDER_BINS * sizeof *hist);
  for (int c = 0; c < 4; c++) {
    const int nt = nts[c];
    for (int t = 0; t < nt; t++) {
      memset(h4, 0, 4 * JND_ORDER_BINS * sizeof *h4);
      jnd_order_count(v + cuts[c][t], cuts[c][t + 1] - cuts[c][t], h4);
      jnd_order_fold(h4, hist + (size_t)t * JND_ORDER_BINS);
    }
    jnd_ranks r;
    jnd_ranks_init(&r, n);
    const double p[] = {0, 50, 93, 99, 99.99, 100};
    for (int i = 0; i < 6; i++) CHECK_OK(jnd_ranks_want(&r, p[i]));
    CHECK_OK(jnd_ranks_select_counted(&r, v, nt, cuts[c], hist));
    for (int i = 0; i < r.nk; i++) CHECK(r.v[i] == s[r.k[i]]);
    CHECK(jnd_ranks_percentile(&r, 100, NULL, NULL) == s[n - 1]);
  }
  jnd_ranks r;
  jnd_ranks_init(&r, n);
  CHECK_OK(jnd_ranks_want(&r, 50));
  const size_t short_of_n[2] = {0, n - 1}, not_from_0[2] = {1, n};
  CHECK_STATUS(jnd_ranks_select_counted(&r, v, 1, short_of_n, hist), JND_ERR_INTERNAL);
  CHECK_STATUS(jnd_ranks_select_counted(&r, v, 1, not_from_0, hist), JND_ERR_INTERNAL);
  free(h4);
  free(hist);
  free(v);
  free(s);
}

TEST(order_statistics_of_a_constant_map) {
  size_t n = 10000, ks[3] = {0, 9299, 9999};
  float *v = malloc(n * sizeof *v), out[3];
  for (size_t i = 0; i < n; i++) v[i] = 0.25f;
  CHECK_OK(jnd_order_stats(v, n, ks, 3, out));
  CHECK(out[0] == 0.25f && out[1] == 0.25f && out[2] == 0.25f);
  free(v);
}

TEST(order_statistics_refuse_bad_indices) {
  float v[4] = {1, 2, 3, 4}, out[2];
  size_t past[1] = {4}, descending[2] = {3, 1};
  CHECK_STATUS(jnd_order_stats(v, 4, past, 1, out), JND_ERR_INTERNAL);
  CHECK_STATUS(jnd_order_stats(v, 4, descending, 2, out), JND_ERR_INTERNAL);
}

TEST(sort_matches_qsort_for_both_paths) {
  /* small or signed arrays go through qsort, large non-negative ones through radix */
  const size_t n = 50000;
  for (int neg = 0; neg < 2; neg++) {
    float *v = malloc(n * sizeof *v), *s = malloc(n * sizeof *s);
    fill(v, n, 5, neg);
    memcpy(s, v, n * sizeof *s);
    qsort(s, n, sizeof *s, cmp_float);
    CHECK_OK(jnd_sort_floats(v, n));
    CHECK(memcmp(v, s, n * sizeof *v) == 0);
    free(v);
    free(s);
  }
}

/* the reference: the p-th percentile of sorted values, linear interpolation */
static double sorted_percentile(const float *s, size_t n, double p) {
  double pos = (p < 0 ? 0 : p > 100 ? 100 : p) / 100.0 * (double)(n - 1);
  size_t k = (size_t)floor(pos);
  if (k >= n - 1) return s[n - 1];
  return s[k] + (pos - (double)k) * ((double)s[k + 1] - s[k]);
}

TEST(percentiles_interpolate_linearly) {
  float s[5] = {10, 2, 0, 3, 1}; /* unsorted: 0, 1, 2, 3, 10 */
  CHECK_NEAR(jnd_percentile(s, 5, 0), 0, 0);
  CHECK_NEAR(jnd_percentile(s, 5, 50), 2, 0);
  CHECK_NEAR(jnd_percentile(s, 5, 87.5), 6.5, 1e-12);
  CHECK_NEAR(jnd_percentile(s, 5, 100), 10, 0);
  CHECK_NEAR(jnd_percentile(s, 5, 250), 10, 0); /* clamped */
  CHECK(s[0] == 10 && s[4] == 1);               /* the values are left as they were */
  const double p[3] = {0, 87.5, 100};
  double out[3];
  CHECK_OK(jnd_percentiles(s, 5, p, 3, out));
  CHECK(out[0] == 0 && fabs(out[1] - 6.5) < 1e-12 && out[2] == 10);
  CHECK(isnan(jnd_percentile(s, 0, 50)));
}

TEST(percentiles_of_a_large_map_match_a_full_sort) {
  const size_t n = 100000;
  float *v = malloc(n * sizeof *v), *s = malloc(n * sizeof *s);
  fill(v, n, 3, 1);
  memcpy(s, v, n * sizeof *s);
  qsort(s, n, sizeof *s, cmp_float);
  const double p[6] = {0, 12.5, 50, 93, 99.9, 100};
  double out[6];
  CHECK_OK(jnd_percentiles(v, n, p, 6, out));
  for (int i = 0; i < 6; i++) CHECK(out[i] == sorted_percentile(s, n, p[i]));
  free(v);
  free(s);
}

TEST(diff_summary_percentiles_match_a_full_sort) {
  /* the summary reads percentiles by selection; a sort gives the same */
  jnd_image map;
  CHECK_OK(jnd_image_alloc(&map, 301, 203, 1));
  size_t n = (size_t)map.w * map.h;
  fill(map.data, n, 99, 0);
  jnd_diff_stats st;
  jnd_pooling p80 = {JND_POOL_PERCENTILE, 80.0};
  CHECK_OK(jnd_diff_summarise(&map, 3.5, &p80, &st));
  float *s = malloc(n * sizeof *s);
  memcpy(s, map.data, n * sizeof *s);
  qsort(s, n, sizeof *s, cmp_float);
  CHECK_NEAR(st.jnd_p93, sorted_percentile(s, n, 93), 0);
  CHECK_NEAR(st.jnd_max, s[n - 1], 0);
  CHECK_NEAR(st.p_max, jnd_probability(s[n - 1], 3.5), 1e-5);
  /* P is monotonic in JND: P's percentile lies between P of the neighbours */
  double pos = 0.8 * (double)(n - 1);
  size_t k = (size_t)pos;
  CHECK(st.p_detect >= jnd_probability(s[k], 3.5) - 1e-5 && st.p_detect <= jnd_probability(s[k + 1], 3.5) + 1e-5);
  CHECK(st.p_p50 <= st.p_p93 && st.p_p93 <= st.p_p99 && st.p_p99 <= st.p_max);
  free(s);
  jnd_image_free(&map);
}

TEST(pooling_names_parse_and_print) {
  jnd_pooling p;
  char buf[32];
  CHECK_OK(jnd_pooling_parse("p93", &p));
  CHECK(p.kind == JND_POOL_PERCENTILE && p.percentile == 93);
  CHECK(strcmp(jnd_pooling_name(&p, buf, sizeof buf), "p93") == 0);
  CHECK_OK(jnd_pooling_parse("max", &p));
  CHECK(p.kind == JND_POOL_MAX);
  CHECK_STATUS(jnd_pooling_parse("p101", &p), JND_ERR_ARG);
  CHECK_STATUS(jnd_pooling_parse("median", &p), JND_ERR_ARG);
}

/* 000 §9 on hand-made lists: the statistic is the (floor(q·n) + 1)-th largest P */
TEST(criterion_allows_floor_q_n_views_above_p) {
  jnd_criterion_result r;
  /* n = 10, q = 0.1: one view may be above 0.2 */
  double one_above[10] = {0.05, 0.9, 0.1, 0.0, 0.2, 0.15, 0.01, 0.02, 0.03, 0.04};
  CHECK_OK(jnd_criterion_eval(one_above, 10, 0.2, 0.1, 0.9, &r));
  CHECK(r.allowed == 1 && r.above == 1 && r.pass == 1);
  CHECK_NEAR(r.statistic, 0.2, 0); /* second largest; P = p exactly is not above */
  CHECK(r.worst_view == 1);
  double two_above[10] = {0.05, 0.9, 0.1, 0.0, 0.21, 0.15, 0.01, 0.02, 0.03, 0.04};
  CHECK_OK(jnd_criterion_eval(two_above, 10, 0.2, 0.1, 0.9, &r));
  CHECK(r.above == 2 && r.pass == 0);
  CHECK_NEAR(r.statistic, 0.21, 0);
  CHECK_NEAR(r.fraction_above, 0.2, 1e-15);
  /* n = 8, q = 0.1: q·n = 0.8, no view may be above */
  double eight[8] = {0.1, 0.1, 0.1, 0.25, 0.1, 0.1, 0.1, 0.1};
  CHECK_OK(jnd_criterion_eval(eight, 8, 0.2, 0.1, 0.9, &r));
  CHECK(r.allowed == 0 && r.above == 1 && r.pass == 0);
  CHECK_NEAR(r.statistic, 0.25, 0);
  /* n = 20, q = 0.1: two may be above; ties at the statistic */
  double twenty[20];
  for (int i = 0; i < 20; i++) twenty[i] = 0.05;
  twenty[3] = twenty[7] = twenty[11] = 0.5;
  CHECK_OK(jnd_criterion_eval(twenty, 20, 0.2, 0.1, 0.9, &r));
  CHECK(r.allowed == 2 && r.above == 3 && r.pass == 0 && r.worst_view == 3);
  CHECK_NEAR(r.statistic, 0.5, 0);
  twenty[11] = 0.2;
  CHECK_OK(jnd_criterion_eval(twenty, 20, 0.2, 0.1, 0.9, &r));
  CHECK(r.above == 2 && r.pass == 1);
  CHECK_NEAR(r.statistic, 0.2, 0);
  /* n = 1: the one view decides */
  double single = 0.3;
  CHECK_OK(jnd_criterion_eval(&single, 1, 0.2, 0.1, 0.9, &r));
  CHECK(r.allowed == 0 && r.pass == 0);
  CHECK_OK(jnd_criterion_eval(&single, 1, 0.3, 0.1, 0.9, &r));
  CHECK(r.pass == 1);
}

TEST(criterion_refuses_bad_arguments) {
  double v[2] = {0.1, 0.2}, bad[2] = {0.1, NAN};
  jnd_criterion_result r;
  CHECK_STATUS(jnd_criterion_eval(v, 0, 0.2, 0.1, 0.9, &r), JND_ERR_ARG);
  CHECK_STATUS(jnd_criterion_eval(v, 2, 1.5, 0.1, 0.9, &r), JND_ERR_ARG);
  CHECK_STATUS(jnd_criterion_eval(v, 2, 0.2, 1.0, 0.9, &r), JND_ERR_ARG);
  CHECK_STATUS(jnd_criterion_eval(v, 2, 0.2, 0.1, 1.0, &r), JND_ERR_ARG);
  CHECK_STATUS(jnd_criterion_eval(bad, 2, 0.2, 0.1, 0.9, &r), JND_ERR_ARG);
}

/* Clopper–Pearson: with k = 0 the bound solves (1 − u)^n = 1 − c, u = 1 − (1 − c)^(1/n) */
TEST(binomial_upper_bound_matches_closed_forms) {
  CHECK_NEAR(jnd_binomial_upper(0, 8, 0.9), 1 - pow(0.1, 1.0 / 8), 1e-9);
  CHECK_NEAR(jnd_binomial_upper(0, 20, 0.95), 1 - pow(0.05, 1.0 / 20), 1e-9);
  /* k = n − 1: P(X <= n − 1) = 1 − u^n = 1 − c, u = c^(1/n) */
  CHECK_NEAR(jnd_binomial_upper(7, 8, 0.9), pow(0.9, 1.0 / 8), 1e-9);
  CHECK_NEAR(jnd_binomial_upper(8, 8, 0.9), 1, 0);
  /* k = 1, n = 10, c = 0.9: (1−u)^10 + 10u(1−u)^9 = 0.1 at u = 0.33684 (solved by hand, Newton) */
  CHECK_NEAR(jnd_binomial_upper(1, 10, 0.9), 0.33684, 5e-5);
  CHECK(jnd_binomial_upper(1, 10, 0.9) < jnd_binomial_upper(2, 10, 0.9));
  CHECK(jnd_binomial_upper(1, 20, 0.9) < jnd_binomial_upper(1, 10, 0.9));
}

/* The upper bound is the Clopper–Pearson bound of what was observed: the
 * views above p (not those allowed, not the views at or below p), out of
 * the views judged. Recomputed here by another route: the binomial CDF as
 * a sum of products (no log-gamma), bisected for CDF(u) = 1 − confidence. */
static double cdf_by_products(int k, int n, double u) {
  double sum = 0;
  for (int i = 0; i <= k; i++) {
    double term = 1;
    for (int j = 0; j < i; j++) term *= (double)(n - j) / (j + 1) * u;
    for (int j = 0; j < n - i; j++) term *= 1 - u;
    sum += term;
  }
  return sum;
}

static double clopper_pearson_upper(int k, int n, double confidence) {
  if (k >= n) return 1;
  double lo = 0, hi = 1;
  for (int it = 0; it < 200; it++) {
    double mid = 0.5 * (lo + hi);
    if (cdf_by_products(k, n, mid) > 1 - confidence) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(criterion_upper_bound_is_clopper_pearson_of_the_views_observed_above) {
  /* n views, `above` of them above p = 0.2; allowed = floor(q n) differs
   * from above in every case, and above differs from n − above */
  static const struct {
    int n, above;
    double q, confidence;
  } cases[] = {{10, 3, 0.1, 0.9}, {10, 0, 0.1, 0.9}, {8, 1, 0.1, 0.95}, {20, 5, 0.1, 0.9},
               {12, 2, 0.25, 0.8}, {5, 4, 0.1, 0.9}, {30, 7, 0.1, 0.99}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    double P[64];
    int n = cases[c].n, above = cases[c].above;
    /* the views above p at the end, so that their count is not their index */
    for (int i = 0; i < n; i++) P[i] = i >= n - above ? 0.2 + 0.7 * (i + 1) / n : 0.19 * i / n;
    jnd_criterion_result r;
    CHECK_OK(jnd_criterion_eval(P, n, 0.2, cases[c].q, cases[c].confidence, &r));
    CHECK(r.above == above && r.views == n);
    double want = clopper_pearson_upper(above, n, cases[c].confidence);
    CHECK_NEAR(r.fraction_upper, want, 1e-7);
    CHECK(r.fraction_upper >= r.fraction_above);
    CHECK_NEAR(r.fraction_above, (double)above / n, 1e-15);
    /* a higher confidence asks for a larger bound */
    jnd_criterion_result hi;
    CHECK_OK(jnd_criterion_eval(P, n, 0.2, cases[c].q, 1 - (1 - cases[c].confidence) / 2, &hi));
    if (above < n) CHECK(hi.fraction_upper > r.fraction_upper);
  }
  /* the route itself at hand values: 0 of 10 at 90 %: 1 − 0.1^(1/10);
   * 9 of 10: 0.9^(1/10); 3 of 10 at 90 %: 0.55173 (Python's math.comb
   * sum, bisected) */
  CHECK_NEAR(clopper_pearson_upper(0, 10, 0.9), 1 - pow(0.1, 0.1), 1e-9);
  CHECK_NEAR(clopper_pearson_upper(3, 10, 0.9), 0.5517308, 1e-6);
  /* docs/texres.md: with the default confidence (90 %), 8 views none above
   * bound the fraction of all views above p at 25 % */
  jnd_criterion def;
  jnd_criterion_defaults(&def);
  double eight[8] = {0};
  jnd_criterion_result r8;
  CHECK_OK(jnd_criterion_eval(eight, 8, def.p, def.q, def.confidence, &r8));
  CHECK_NEAR(r8.fraction_upper, 0.25, 0.0005);
  CHECK_NEAR(clopper_pearson_upper(9, 10, 0.9), pow(0.9, 0.1), 1e-9);
}

/* 000 §9 with q·N integral and not: ⌊q·N⌋ views may lie above p and the
 * statistic is the (⌊q·N⌋ + 1)-th largest P. On P = (j + 0.5)/N, j = 0..N−1
 * (distinct, stored shuffled) the (k + 1)-th largest is (N − k − 0.5)/N. A
 * threshold equal to the statistic passes (P = p is not above); one just
 * below it fails with one view too many above. */
TEST(criterion_counts_floor_q_n_views_whether_q_n_is_integral_or_not) {
  static const struct {
    int n;
    double q;
    int allowed; /* ⌊q·N⌋ by hand */
  } cases[] = {
      {10, 0.1, 1},  {10, 0.15, 1}, {10, 0.2, 2},  {10, 0.25, 2},  {10, 0.3, 3},   {10, 0.05, 0},
      {8, 0.1, 0},   {8, 0.125, 1}, {8, 0.25, 2},  {20, 0.05, 1},  {20, 0.04, 0},  {20, 0.1, 2},
      {20, 0.15, 3}, {3, 0.34, 1},  {3, 0.33, 0},  {1, 0.5, 0},    {100, 0.29, 29}, /* 0.29·100 = 28.999999999999996 in binary */
      {100, 0.57, 57}, {100, 0.07, 7},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    int n = cases[c].n, k = cases[c].allowed;
    double P[100];
    for (int j = 0; j < n; j++) P[(j * 7) % n] = (j + 0.5) / n;
    double stat = (n - k - 0.5) / n;
    jnd_criterion_result r;
    CHECK_OK(jnd_criterion_eval(P, n, stat, cases[c].q, 0.9, &r));
    if (r.allowed != k || r.statistic != stat || !r.pass || r.above != k)
      fprintf(stderr, "case n = %d, q = %g: allowed %d (want %d), statistic %g (want %g), above %d, pass %d\n", n,
              cases[c].q, r.allowed, k, r.statistic, stat, r.above, r.pass);
    CHECK(r.allowed == k && r.above == k && r.pass == 1);
    CHECK(r.statistic == stat);
    CHECK_NEAR(r.fraction_above, (double)k / n, 1e-15);
    CHECK(r.worst_view == (((n - 1) * 7) % n));
    CHECK_OK(jnd_criterion_eval(P, n, stat - 1e-9, cases[c].q, 0.9, &r));
    CHECK(r.above == k + 1 && r.pass == 0 && r.statistic == stat);
  }
}

/* 000 eq. 4 makes one JND P = 0.5 whatever the slope β, and pins β elsewhere:
 * a map at 1.2 JND everywhere is P = 1 − 0.5^(1.2^3.5) = 0.73074018 with β = 3.5,
 * a map at 2 JND is 1 − 0.5^(2²) = 0.9375 with β = 2. */
TEST(summary_of_constant_maps_follows_000_eq4) {
  jnd_image map;
  CHECK_OK(jnd_image_alloc(&map, 37, 23, 1));
  size_t n = (size_t)map.w * map.h;
  const double betas[3] = {3.5, 2, 0.8};
  for (int b = 0; b < 3; b++) {
    for (size_t i = 0; i < n; i++) map.data[i] = 1.0f;
    jnd_diff_stats st;
    CHECK_OK(jnd_diff_summarise(&map, betas[b], NULL, &st));
    CHECK_NEAR(st.p_detect, 0.5, 1e-6);
    CHECK_NEAR(st.p_mean, 0.5, 1e-6);
    CHECK_NEAR(st.p_max, 0.5, 1e-6);
    CHECK_NEAR(st.p_p50, 0.5, 1e-6);
    CHECK_NEAR(st.jnd_minkowski, 1, 1e-6);
    CHECK_NEAR(st.jnd_mean, 1, 1e-12);
  }
  for (size_t i = 0; i < n; i++) map.data[i] = 1.2f;
  jnd_diff_stats st;
  CHECK_OK(jnd_diff_summarise(&map, 3.5, NULL, &st));
  CHECK_NEAR(st.p_detect, 0.73074018, 2e-5);
  CHECK_NEAR(st.p_mean, 0.73074018, 2e-5);
  for (size_t i = 0; i < n; i++) map.data[i] = 2.0f;
  CHECK_OK(jnd_diff_summarise(&map, 2, NULL, &st));
  CHECK_NEAR(st.p_detect, 0.9375, 2e-5);
  jnd_image_free(&map);
}

/* Every number jnd diff reports, on ten hand-made JND values (β = 3.5):
 * JND 1.5, 0, 1, 0.25, 0.8, 0.5, 1.2, 0.1, 1, 0.5 give P = 1 − 0.5^(JND^3.5):
 * sorted 0, 0.00021917, 0.00540058, 0.05942711, 0.05942711, 0.27197834, 0.5,
 * 0.5, 0.73074018, 0.94302448. Percentile p lies at rank p/100 · 9:
 * p50 (4.5) = (0.05942711 + 0.27197834)/2 = 0.16570273;
 * p93 (8.37) = 0.73074018 + 0.37 · 0.21228430 = 0.80928537;
 * p99 (8.91) = 0.73074018 + 0.91 · 0.21228430 = 0.92391889;
 * mean 0.30702170; max 0.94302448; Minkowski (mean P^2.4)^(1/2.4) = 0.48543071.
 * JND: mean 0.685, p93 (8.37) = 1.2 + 0.37 · 0.3 = 1.311, max 1.5,
 * Minkowski (mean JND^2.4)^(1/2.4) = 0.87204125. */
TEST(summary_of_a_hand_made_map_gives_every_pooling_by_hand) {
  const float v[10] = {1.5f, 0, 1, 0.25f, 0.8f, 0.5f, 1.2f, 0.1f, 1, 0.5f};
  jnd_image map;
  CHECK_OK(jnd_image_alloc(&map, 5, 2, 1));
  memcpy(map.data, v, sizeof v);
  static const struct {
    const char *name;
    double p_detect;
  } want[] = {{"p93", 0.80928537}, {"p50", 0.16570273}, {"p99", 0.92391889},
              {"max", 0.94302448}, {"mean", 0.30702170}, {"minkowski", 0.48543071}};
  for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
    jnd_pooling pool;
    jnd_diff_stats st;
    CHECK_OK(jnd_pooling_parse(want[i].name, &pool));
    CHECK_OK(jnd_diff_summarise(&map, 3.5, &pool, &st));
    if (fabs(st.p_detect - want[i].p_detect) > 2e-5) fprintf(stderr, "pooling %s:\n", want[i].name);
    CHECK_NEAR(st.p_detect, want[i].p_detect, 2e-5);
    CHECK_NEAR(st.p_p50, 0.16570273, 2e-5);
    CHECK_NEAR(st.p_p93, 0.80928537, 2e-5);
    CHECK_NEAR(st.p_p99, 0.92391889, 2e-5);
    CHECK_NEAR(st.p_max, 0.94302448, 2e-5);
    CHECK_NEAR(st.p_mean, 0.30702170, 2e-5);
    CHECK_NEAR(st.jnd_mean, 0.685, 1e-6);
    CHECK_NEAR(st.jnd_p93, 1.311, 1e-6);
    CHECK_NEAR(st.jnd_max, 1.5, 0);
    CHECK_NEAR(st.jnd_minkowski, 0.87204125, 2e-5);
  }
  /* no pooling asked for is P93 (000 §6) */
  jnd_diff_stats st;
  CHECK_OK(jnd_diff_summarise(&map, 3.5, NULL, &st));
  CHECK_NEAR(st.p_detect, 0.80928537, 2e-5);
  jnd_image_free(&map);
}

/* jnd_pool on {4, 1, 3, 2}: max 4, mean 2.5, Minkowski with e = 2 √7.5 = 2.73861279,
 * with e = 2.4 (mean x^2.4)^(1/2.4) = 2.81866819; percentiles at rank p/100 · 3:
 * p50 = 2.5, p93 (2.79) = 3.79, p0 = 1, p100 = 4. */
TEST(pool_of_a_hand_made_map_gives_each_pooling_by_hand) {
  const float v[4] = {4, 1, 3, 2};
  jnd_pooling mx = {JND_POOL_MAX, 0}, mean = {JND_POOL_MEAN, 0}, mink = {JND_POOL_MINKOWSKI, 0};
  jnd_pooling p50 = {JND_POOL_PERCENTILE, 50}, p93 = {JND_POOL_PERCENTILE, 93}, p0 = {JND_POOL_PERCENTILE, 0},
              p100 = {JND_POOL_PERCENTILE, 100};
  CHECK_NEAR(jnd_pool(v, 4, &mx, 2.4), 4, 0);
  CHECK_NEAR(jnd_pool(v, 4, &mean, 2.4), 2.5, 1e-12);
  CHECK_NEAR(jnd_pool(v, 4, &mink, 2), 2.73861279, 1e-8);
  CHECK_NEAR(jnd_pool(v, 4, &mink, 2.4), 2.81866819, 1e-8);
  CHECK_NEAR(jnd_pool(v, 4, &p50, 2.4), 2.5, 1e-12);
  CHECK_NEAR(jnd_pool(v, 4, &p93, 2.4), 3.79, 1e-12);
  CHECK_NEAR(jnd_pool(v, 4, &p0, 2.4), 1, 0);
  CHECK_NEAR(jnd_pool(v, 4, &p100, 2.4), 4, 0);
  const float neg[3] = {-2, -5, -1}; /* the maximum of negative values is the largest, not 0 */
  CHECK_NEAR(jnd_pool(neg, 3, &mx, 2.4), -1, 0);
}

TEST(knee_of_a_flat_then_steep_curve_is_its_corner) {
  /* error stays 0.01 up to level 6, then climbs: the Point of Imperceptibility of 003 §3 */
  double x[10], y[10];
  for (int i = 0; i < 10; i++) {
    x[i] = i;
    y[i] = i <= 6 ? 0.01 + 0.001 * i : 0.016 + 0.3 * (i - 6);
  }
  CHECK(jnd_knee(x, y, 10, JND_KNEE_BELOW, 0) == 6);
  /* the same curve over a decreasing x (log triangles, finest first) */
  double xr[10];
  for (int i = 0; i < 10; i++) xr[i] = 20 - 1.5 * i;
  CHECK(jnd_knee(xr, y, 10, JND_KNEE_BELOW, 0) == 6);
  /* and a curve with different units on y has the same knee */
  double y2[10];
  for (int i = 0; i < 10; i++) y2[i] = 1000 * y[i] + 5;
  CHECK(jnd_knee(x, y2, 10, JND_KNEE_BELOW, 0) == 6);
  /* shifted x (units of x do not matter either), and the curve turned
   * upside down, which puts it above its chord: the same corner */
  double xs[10], yn[10];
  for (int i = 0; i < 10; i++) xs[i] = 3 * i + 1000, yn[i] = -y[i];
  CHECK(jnd_knee(xs, y, 10, JND_KNEE_BELOW, 0) == 6);
  CHECK(jnd_knee(x, yn, 10, JND_KNEE_ABOVE, 0) == 6);
  CHECK(jnd_knee(x, yn, 10, JND_KNEE_BELOW, 0) != 6);
}

TEST(knee_of_an_exponential_is_where_its_slope_equals_the_chord) {
  /* y = e^(a x) on [0, 1]: scaled, the gap to the chord peaks where
   * y'(x) = (e^a − 1), i.e. x* = ln((e^a − 1) / a) / a */
  enum { N = 1001 };
  static double x[N], y[N];
  for (double a = 2; a <= 8; a += 3) {
    for (int i = 0; i < N; i++) {
      x[i] = (double)i / (N - 1);
      y[i] = exp(a * x[i]);
    }
    double want = log((exp(a) - 1) / a) / a;
    int k = jnd_knee(x, y, N, JND_KNEE_BELOW, 0);
    CHECK_NEAR(x[k], want, 1.5 / (N - 1));
  }
  /* the cumulative curve 1 − e^(−b x) bends the other way: x* = ln(b / (1 − e^−b)) / b */
  for (int i = 0; i < N; i++) {
    x[i] = (double)i / (N - 1);
    y[i] = 1 - exp(-5 * x[i]);
  }
  CHECK_NEAR(x[jnd_knee(x, y, N, JND_KNEE_ABOVE, 0)], log(5 / (1 - exp(-5))) / 5, 1.5 / (N - 1));
  CHECK(jnd_knee(x, y, N, JND_KNEE_BELOW, 0) == 0);
}

TEST(knee_ties_within_the_tolerance_go_to_the_first_point) {
  /* two corners: gaps 0.295 at index 2 and 0.296 at index 3 (scaled axes) */
  double x[5] = {0, 0.25, 0.5, 0.75, 1}, y[5] = {0, 0.01, 0.205, 0.454, 1};
  CHECK(jnd_knee(x, y, 5, JND_KNEE_BELOW, 0) == 3);
  CHECK(jnd_knee(x, y, 5, JND_KNEE_BELOW, 0.02) == 2);
  /* but not beyond it */
  y[2] = 0.3;
  CHECK(jnd_knee(x, y, 5, JND_KNEE_BELOW, 0.02) == 3);
}

TEST(knee_of_a_line_or_a_short_curve_is_the_first_point) {
  double x[5] = {0, 1, 2, 3, 4}, y[5] = {1, 3, 5, 7, 9};
  CHECK(jnd_knee(x, y, 5, JND_KNEE_BELOW, 0) == 0);
  CHECK(jnd_knee(x, y, 5, JND_KNEE_ABOVE, 0) == 0);
  CHECK(jnd_knee(x, y, 2, JND_KNEE_BELOW, 0) == 0);
  CHECK(jnd_knee(x, y, 0, JND_KNEE_BELOW, 0) == -1);
  double flat[5] = {2, 2, 2, 2, 2};
  CHECK(jnd_knee(x, flat, 5, JND_KNEE_BELOW, 0) == 0);
  y[2] = NAN;
  CHECK(jnd_knee(x, y, 5, JND_KNEE_BELOW, 0) == -1);
}

RUN_TESTS(knee_of_a_flat_then_steep_curve_is_its_corner, knee_ties_within_the_tolerance_go_to_the_first_point, knee_of_an_exponential_is_where_its_slope_equals_the_chord,
          knee_of_a_line_or_a_short_curve_is_the_first_point, criterion_allows_floor_q_n_views_above_p, criterion_refuses_bad_arguments,
          binomial_upper_bound_matches_closed_forms, criterion_upper_bound_is_clopper_pearson_of_the_views_observed_above,
          order_statistics_equal_the_sorted_values,
          order_statistics_of_values_crowded_in_one_bin_equal_the_sorted_values, order_statistics_of_a_constant_map,
          ranks_selected_from_counts_of_any_ranges_equal_the_sorted_values,
          order_statistics_refuse_bad_indices, sort_matches_qsort_for_both_paths, percentiles_interpolate_linearly,
          percentiles_of_a_large_map_match_a_full_sort,
          diff_summary_percentiles_match_a_full_sort, pooling_names_parse_and_print,
          criterion_counts_floor_q_n_views_whether_q_n_is_integral_or_not, summary_of_constant_maps_follows_000_eq4,
          summary_of_a_hand_made_map_gives_every_pooling_by_hand, pool_of_a_hand_made_map_gives_each_pooling_by_hand)
