/* The psychometric function of 000 eq. 1 and its fit. */
#include "jnd.h"
#include "test.h"

TEST(eval_is_one_half_at_mu_and_falls_with_resolution) {
  jnd_psychometric f = {500, 100, 0, 0};
  CHECK_NEAR(jnd_psychometric_eval(&f, 500), 0.5, 1e-12);
  CHECK(jnd_psychometric_eval(&f, 300) > jnd_psychometric_eval(&f, 400));
  CHECK(jnd_psychometric_eval(&f, 1000) < 1e-5);
  /* P = 0.2 at µ + 0.8416 σ (000 §6 reads thresholds there) */
  CHECK_NEAR(jnd_psychometric_resolution(&f, 0.2), 500 + 84.1621, 1e-3);
  CHECK_NEAR(jnd_psychometric_eval(&f, jnd_psychometric_resolution(&f, 0.2)), 0.2, 1e-9);
}

TEST(fit_recovers_mu_and_sigma_of_synthetic_data_in_pixels) {
  jnd_psychometric t = {412, 95, 0, 0}, f;
  double r[51], p[51];
  for (int i = 0; i < 51; i++) { /* 000 §4: 1024 down in 20-pixel steps */
    r[i] = 1024 - 20 * i;
    p[i] = jnd_psychometric_eval(&t, r[i]);
  }
  CHECK_OK(jnd_psychometric_fit(r, p, 51, 0, &f));
  CHECK_NEAR(f.mu, 412, 0.01);
  CHECK_NEAR(f.sigma, 95, 0.01);
  CHECK(f.rmse < 1e-6);
}

TEST(fit_recovers_parameters_in_log2_domain_from_six_powers_of_two) {
  jnd_psychometric t = {7.3, 0.8, 1, 0}, f;
  double r[6], p[6];
  for (int i = 0; i < 6; i++) {
    r[i] = 1024 >> i;
    p[i] = jnd_psychometric_eval(&t, r[i]);
  }
  CHECK_OK(jnd_psychometric_fit(r, p, 6, 1, &f));
  CHECK_NEAR(f.mu, 7.3, 1e-3);
  CHECK_NEAR(f.sigma, 0.8, 1e-3);
  CHECK_NEAR(jnd_psychometric_resolution(&f, 0.2), jnd_psychometric_resolution(&t, 0.2), 0.5);
}

TEST(fit_is_robust_to_noise) {
  jnd_psychometric t = {300, 60, 0, 0}, f;
  double r[40], p[40];
  unsigned s = 12345;
  for (int i = 0; i < 40; i++) {
    r[i] = 100 + 12 * i;
    s = s * 1103515245u + 12345u;
    double noise = ((s >> 16) & 0x7fff) / 32768.0 - 0.5;
    p[i] = jnd_psychometric_eval(&t, r[i]) + 0.04 * noise;
    if (p[i] < 0) p[i] = 0;
    if (p[i] > 1) p[i] = 1;
  }
  CHECK_OK(jnd_psychometric_fit(r, p, 40, 0, &f));
  CHECK_NEAR(f.mu, 300, 6);
  CHECK_NEAR(f.sigma, 60, 10);
  /* the reported rmse is the root of the mean squared residual of the
   * fitted curve, recomputed here from 000 eq. 1 at the fitted µ, σ */
  double ss = 0;
  for (int i = 0; i < 40; i++) {
    double e = 1 - 0.5 * erfc(-(r[i] - f.mu) / (f.sigma * sqrt(2.0))) - p[i];
    ss += e * e;
  }
  CHECK(f.rmse > 0.005);   /* noise of ±0.02: the residual is not zero */
  CHECK_NEAR(f.rmse, sqrt(ss / 40), 1e-9);
}

TEST(flat_data_gives_a_threshold_outside_the_range) {
  double r[4] = {1024, 512, 256, 128}, zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1};
  jnd_psychometric f;
  CHECK_OK(jnd_psychometric_fit(r, zero, 4, 1, &f));
  CHECK(jnd_psychometric_resolution(&f, 0.2) <= 128 * 1.01);
  CHECK_OK(jnd_psychometric_fit(r, one, 4, 1, &f));
  CHECK(jnd_psychometric_resolution(&f, 0.2) >= 1024 * 0.99);
}

TEST(bad_input_is_refused) {
  double r[2] = {100, 100}, p[2] = {0.1, 0.5}, rn[2] = {-1, 10};
  jnd_psychometric f;
  CHECK_STATUS(jnd_psychometric_fit(r, p, 1, 0, &f), JND_ERR_ARG);
  CHECK_STATUS(jnd_psychometric_fit(r, p, 2, 0, &f), JND_ERR_ARG);
  CHECK_STATUS(jnd_psychometric_fit(rn, p, 2, 1, &f), JND_ERR_ARG);
}

/* 000 eq. 1, P(r) = 1 − ½(1 + erf((r − µ)/(σ√2))), at hand values of the
 * normal distribution: 1 − Θ(1) = 0.15865525, 1 − Θ(−1) = 0.84134475,
 * 1 − Θ(2) = 0.02275013; in the log2 domain r = 512 is x = 9. */
TEST(eval_follows_000_eq1_at_hand_values) {
  jnd_psychometric f = {500, 100, 0, 0}, g = {8, 1, 1, 0};
  CHECK_NEAR(jnd_psychometric_eval(&f, 600), 0.15865525, 1e-8);
  CHECK_NEAR(jnd_psychometric_eval(&f, 400), 0.84134475, 1e-8);
  CHECK_NEAR(jnd_psychometric_eval(&f, 700), 0.02275013, 1e-8);
  CHECK_NEAR(jnd_psychometric_eval(&g, 512), 0.15865525, 1e-8);
  CHECK_NEAR(jnd_psychometric_resolution(&f, 0.15865525), 600, 1e-4);
  CHECK_NEAR(jnd_psychometric_resolution(&g, 0.84134475), 128, 1e-4);
}

RUN_TESTS(eval_is_one_half_at_mu_and_falls_with_resolution, eval_follows_000_eq1_at_hand_values, fit_recovers_mu_and_sigma_of_synthetic_data_in_pixels,
          fit_recovers_parameters_in_log2_domain_from_six_powers_of_two, fit_is_robust_to_noise,
          flat_data_gives_a_threshold_outside_the_range, bad_input_is_refused)
