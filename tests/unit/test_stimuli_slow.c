/* Not only Gabors: the model on ModelFest's classes of stimuli (Watson &
 * Ahumada 2005) — Gabors, edges, lines, discs, noise patches and a natural
 * image — synthesised here on a 30 cd/m² grey at 60 pixels a degree. Each
 * class must have a finite, sensible threshold; visibility must grow with
 * contrast; and thresholds must fall with size until the summation limit. */
#include "test.h"
#include "core/core.h"
#include "jnd.h"

#define PPD 60.0
#define SIDE 256
#define BG 30.0

typedef enum { GABOR, EDGE, LINE, DISC, NOISE, NATURAL, NCLASS } stim_class;
static const char *NAMES[NCLASS] = {"gabor", "edge", "line", "disc", "noise", "natural"};

/* the class's luminance modulation in [-1, 1] at (x, y) degrees from the centre */
static void profile(stim_class k, double size_deg, float *m) {
  jnd_rng rng;
  jnd_rng_seed(&rng, 11);
  /* noise: white noise; natural: 1/f noise (the amplitude spectrum of natural
   * images) made by summing octave bands of blurred noise */
  float *noise = NULL;
  if (k == NOISE || k == NATURAL) {
    noise = calloc(SIDE * SIDE, sizeof(float));
    for (int i = 0; i < SIDE * SIDE; i++) noise[i] = (float)jnd_rng_normal(&rng);
    if (k == NATURAL) {
      float *acc = calloc(SIDE * SIDE, sizeof(float)), *tmp = malloc(sizeof(float) * SIDE * SIDE);
      for (int oct = 0; oct < 6; oct++) {
        int r = 1 << oct; /* box blur of radius r: a band about 1/(2r) cycles/pixel */
        for (int y = 0; y < SIDE; y++)
          for (int x = 0; x < SIDE; x++) {
            double s = 0;
            for (int d = -r; d <= r; d++) s += noise[y * SIDE + jnd_clampi(x + d, 0, SIDE - 1)];
            tmp[y * SIDE + x] = (float)(s / (2 * r + 1));
          }
        for (int y = 0; y < SIDE; y++)
          for (int x = 0; x < SIDE; x++) {
            double s = 0;
            for (int d = -r; d <= r; d++) s += tmp[jnd_clampi(y + d, 0, SIDE - 1) * SIDE + x];
            acc[y * SIDE + x] += (float)(s / (2 * r + 1) * sqrt((double)r)); /* equal energy per octave */
          }
      }
      free(noise);
      free(tmp);
      noise = acc;
    }
    double mx = 0;
    for (int i = 0; i < SIDE * SIDE; i++) mx = fmax(mx, fabs(noise[i]));
    for (int i = 0; i < SIDE * SIDE; i++) noise[i] /= (float)mx;
  }
  for (int y = 0; y < SIDE; y++)
    for (int x = 0; x < SIDE; x++) {
      double u = (x + 0.5 - SIDE / 2.0) / PPD, v = (y + 0.5 - SIDE / 2.0) / PPD, r2 = u * u + v * v;
      double win = exp(-r2 / (2 * size_deg * size_deg)); /* ModelFest's Gaussian window */
      double g;
      switch (k) {
        case GABOR: g = cos(2 * M_PI * 4.0 * u) * win; break;                 /* 4 cpd */
        case EDGE: g = (u > 0 ? 1 : -1) * win; break;                        /* a windowed step */
        case LINE: g = (x == SIDE / 2 ? 1 : 0) * win; break;                  /* one pixel wide */
        case DISC: g = sqrt(r2) <= size_deg ? 1 : 0; break;                   /* a hard-edged disc */
        default: g = noise[y * SIDE + x] * win; break;
      }
      m[y * SIDE + x] = (float)g;
    }
  free(noise);
}

static jnd_image grey_plus(const float *m, double c) {
  jnd_image img;
  jnd_image_alloc(&img, SIDE, SIDE, 3);
  for (int ch = 0; ch < 3; ch++)
    for (int i = 0; i < SIDE * SIDE; i++) jnd_image_plane(&img, ch)[i] = (float)(BG * (1 + c * m[i]));
  return img;
}

static double max_jnd(jnd_model *mod, const float *m, double c) {
  jnd_image a = grey_plus(m, 0), b = grey_plus(m, c), map;
  double mx = -1;
  if (jnd_model_diff(mod, &a, &b, NULL, &map) == JND_OK) {
    mx = 0;
    for (int i = 0; i < SIDE * SIDE; i++) mx = fmax(mx, map.data[i]);
    jnd_image_free(&map);
  }
  jnd_image_free(&a);
  jnd_image_free(&b);
  return mx;
}

/* the peak contrast where max JND = 1 */
static double threshold(jnd_model *mod, const float *m) {
  double c = 1e-3;
  for (int it = 0; it < 3; it++) {
    double j = max_jnd(mod, m, c);
    if (!(j > 0)) return INFINITY;
    double next = c / j; /* JND is nearly proportional to contrast on a uniform background */
    if (fabs(log(next / c)) < 0.01) return next;
    c = next;
  }
  return c;
}

static jnd_model *model(void) {
  jnd_model_params p;
  jnd_model_defaults(&p);
  p.display.ppd = PPD;
  jnd_model *m = NULL;
  jnd_model_create(&p, &m);
  return m;
}

TEST(every_modelfest_class_has_a_finite_sensible_threshold) {
  jnd_model *mod = model();
  float *m = malloc(sizeof(float) * SIDE * SIDE);
  for (int k = 0; k < NCLASS; k++) {
    profile((stim_class)k, k == DISC ? 0.25 : 0.5, m);
    double t = threshold(mod, m);
    fprintf(stderr, "  %-8s threshold %.4f (%.1f dB sensitivity)\n", NAMES[k], t, -20 * log10(t));
    /* ModelFest's thresholds lie between about 0.1% and 30% contrast */
    CHECK(t > 1e-3 && t < 0.3);
  }
  free(m);
  jnd_model_free(mod);
}

TEST(visibility_grows_with_contrast_for_every_class) {
  jnd_model *mod = model();
  float *m = malloc(sizeof(float) * SIDE * SIDE);
  for (int k = 0; k < NCLASS; k++) {
    profile((stim_class)k, k == DISC ? 0.25 : 0.5, m);
    double prev = 0;
    for (double c = 0.004; c <= 0.2; c *= 3) {
      double j = max_jnd(mod, m, c);
      CHECK_LT(prev, j);
      prev = j;
    }
  }
  free(m);
  jnd_model_free(mod);
}

TEST(thresholds_fall_with_size_until_the_summation_limit) {
  jnd_model *mod = model();
  float *m = malloc(sizeof(float) * SIDE * SIDE);
  /* Gabors of 4 cpd and discs, growing in octaves: each larger one is easier
   * to see */
  const stim_class classes[2] = {GABOR, DISC};
  for (int q = 0; q < 2; q++) {
    double t[5];
    for (int i = 0; i < 5; i++) {
      profile(classes[q], 0.0625 * (1 << i) * (classes[q] == DISC ? 0.5 : 1), m);
      t[i] = threshold(mod, m);
    }
    fprintf(stderr, "  %s thresholds by size: %.4f %.4f %.4f %.4f %.4f\n", NAMES[classes[q]], t[0], t[1], t[2], t[3],
            t[4]);
    for (int i = 0; i < 4; i++) CHECK(t[i + 1] < t[i] * 1.01);
    CHECK_LT(t[0] / t[1], t[0] / t[4]); /* it keeps falling */
    /* a disc reaches the critical area within the range (a 4 cpd Gabor's,
     * about 50 deg², lies beyond it): the gain of its last octave is small */
    if (classes[q] == DISC) CHECK_LT(t[3] / t[4], 0.5 * (t[0] / t[1] - 1) + 1);
  }
  free(m);
  jnd_model_free(mod);
}

RUN_TESTS(every_modelfest_class_has_a_finite_sensible_threshold, visibility_grows_with_contrast_for_every_class,
          thresholds_fall_with_size_until_the_summation_limit)
