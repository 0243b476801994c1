/* The built-in example: a synthetic image pair needing no files, for the
 * demo and the tests. The reference mixes what real renders have — smooth
 * gradients, gratings of several frequencies, sharp edges, saturated colour
 * and fine noise-like texture; the test carries four known distortions in
 * four quadrants: a 3×3 blur, 1% noise, a colour shift and a faint 1%
 * luminance step. */
#include <math.h>
#include <string.h>

#include "core/core.h"

static double texture(double x, double y, jnd_rng *r) {
  (void)r;
  /* a deterministic multi-octave value pattern */
  double v = 0, a = 0.5;
  for (int o = 0; o < 5; o++) {
    double f = 0.02 * pow(2.0, o);
    v += a * sin(x * f * 6.283 + 1.7 * o) * cos(y * f * 5.1 + 0.9 * o);
    a *= 0.55;
  }
  return v;
}

jnd_status jnd_example_pair(int w, int h, jnd_image *ref, jnd_image *test) {
  memset(ref, 0, sizeof *ref);
  memset(test, 0, sizeof *test);
  if (w < 64 || h < 64) return jnd_fail(JND_ERR_ARG, "example: the pair needs at least 64 × 64 pixels");
  jnd_status s = jnd_image_alloc(ref, w, h, 3);
  if (s != JND_OK) return s;
  if ((s = jnd_image_alloc(test, w, h, 3)) != JND_OK) {
    jnd_image_free(ref);
    return s;
  }
  jnd_rng rng;
  jnd_rng_seed(&rng, 20261121);
  float *R = jnd_image_plane(ref, 0), *G = jnd_image_plane(ref, 1), *B = jnd_image_plane(ref, 2);
  for (int y = 0; y < h; y++) {
    for (int x = 0; x < w; x++) {
      size_t i = (size_t)y * w + x;
      double u = (double)x / w, v = (double)y / h;
      double base = 0.25 + 0.5 * u;                            /* horizontal ramp */
      double tex = 0.12 * texture(x, y, &rng);                 /* material-like detail */
      double grating = 0.0;
      if (v > 0.42 && v < 0.58) grating = 0.15 * sin(6.283 * x / (4.0 + 28.0 * u)); /* chirp */
      double edge = ((x / 32 + y / 32) % 2) ? 0.06 : -0.06;    /* blocky edges */
      double lum = jnd_clampd(base + tex + grating + edge, 0.02, 0.98);
      double hue = 6.283 * (0.15 + 0.6 * v);
      double sat = 0.25 * (0.5 + 0.5 * sin(3.0 * u + 1.0));
      R[i] = (float)jnd_clampd(lum * (1 + sat * cos(hue)), 0, 1);
      G[i] = (float)jnd_clampd(lum * (1 + sat * cos(hue - 2.094)), 0, 1);
      B[i] = (float)jnd_clampd(lum * (1 + sat * cos(hue + 2.094)), 0, 1);
    }
  }
  memcpy(test->data, ref->data, sizeof(float) * (size_t)w * h * 3);
  int hw = w / 2, hh = h / 2;
  /* top left: a 3×3 box blur (a texture at a lower resolution) */
  for (int c = 0; c < 3; c++) {
    const float *src = jnd_image_plane(ref, c);
    float *dst = jnd_image_plane(test, c);
    for (int y = 8; y < hh - 8; y++)
      for (int x = 8; x < hw - 8; x++) {
        double sum = 0;
        for (int dy = -1; dy <= 1; dy++)
          for (int dx = -1; dx <= 1; dx++) sum += src[(size_t)(y + dy) * w + x + dx];
        dst[(size_t)y * w + x] = (float)(sum / 9);
      }
  }
  /* top right: Gaussian noise, sigma 1% of full scale */
  for (int y = 8; y < hh - 8; y++)
    for (int x = hw + 8; x < w - 8; x++) {
      double nz = 0.01 * jnd_rng_normal(&rng);
      for (int c = 0; c < 3; c++) {
        float *p = &jnd_image_plane(test, c)[(size_t)y * w + x];
        *p = (float)jnd_clampd(*p + nz, 0, 1);
      }
    }
  /* bottom left: a colour shift towards red in a disc */
  for (int y = hh + 8; y < h - 8; y++)
    for (int x = 8; x < hw - 8; x++) {
      double dx = x - hw / 2.0, dy = y - (hh + h) / 2.0, r = fmin(hw, hh) / 3.0;
      if (dx * dx + dy * dy > r * r) continue;
      size_t i = (size_t)y * w + x;
      jnd_image_plane(test, 0)[i] = (float)jnd_clampd(jnd_image_plane(test, 0)[i] * 1.06, 0, 1);
      jnd_image_plane(test, 2)[i] = (float)jnd_clampd(jnd_image_plane(test, 2)[i] * 0.95, 0, 1);
    }
  /* bottom right: a faint 1% luminance step (near threshold) */
  for (int y = hh + 8; y < h - 8; y++)
    for (int x = hw + hw / 2; x < w - 8; x++)
      for (int c = 0; c < 3; c++) {
        float *p = &jnd_image_plane(test, c)[(size_t)y * w + x];
        *p = (float)jnd_clampd(*p * 1.01, 0, 1);
      }
  return JND_OK;
}
