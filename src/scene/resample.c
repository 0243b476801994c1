/* Resampling of texture maps with a separable Lanczos-3 filter (000 §4:
 * lower-resolution candidates are made by Lanczos filtering), in the space
 * where averaging is meaningful for the map's kind. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"

#define LANCZOS_A 3.0   /* 000 §4: Lanczos-3 */

static double lanczos(double x) {
  x = fabs(x);
  if (x < 1e-9) return 1.0;
  if (x >= LANCZOS_A) return 0.0;
  double px = M_PI * x;
  return LANCZOS_A * sin(px) * sin(px / LANCZOS_A) / (px * px);
}

/* The taps of one output coordinate: first input index, count, weights. */
typedef struct {
  int *first, *count;
  int *idx;          /* per output: taps indices (resolved for the edge mode) */
  float *w;
  int taps;          /* maximum taps per output */
} taps1d;

static void taps_free(taps1d *t) {
  free(t->first);
  free(t->count);
  free(t->idx);
  free(t->w);
}

static jnd_status taps_make(int in, int out, int wrap, taps1d *t) {
  double scale = (double)out / in;
  double support = scale < 1 ? LANCZOS_A / scale : LANCZOS_A;   /* widened when shrinking */
  double fscale = scale < 1 ? scale : 1.0;
  t->taps = (int)ceil(2 * support) + 2;
  t->first = jnd_alloc((size_t)out, sizeof(int));
  t->count = jnd_alloc((size_t)out, sizeof(int));
  t->idx = jnd_alloc((size_t)out * t->taps, sizeof(int));
  t->w = jnd_alloc((size_t)out * t->taps, sizeof(float));
  if (!t->first || !t->count || !t->idx || !t->w) {
    taps_free(t);
    return JND_ERR_NOMEM;
  }
  for (int o = 0; o < out; o++) {
    double centre = (o + 0.5) / scale - 0.5;
    int lo = (int)floor(centre - support) + 1, hi = (int)floor(centre + support);
    int n = 0;
    double sum = 0;
    int *ix = t->idx + (size_t)o * t->taps;
    float *wt = t->w + (size_t)o * t->taps;
    for (int i = lo; i <= hi && n < t->taps; i++) {
      double w = lanczos((i - centre) * fscale);
      if (w == 0) continue;
      ix[n] = wrap ? ((i % in) + in) % in : jnd_clampi(i, 0, in - 1);
      wt[n] = (float)w;
      sum += w;
      n++;
    }
    if (n == 0 || fabs(sum) < 1e-12) {
      n = 1;
      ix[0] = jnd_clampi((int)floor(centre + 0.5), 0, in - 1);
      wt[0] = 1;
      sum = 1;
    }
    t->count[o] = n;
    for (int k = 0; k < n; k++) wt[k] = (float)(wt[k] / sum);
  }
  return JND_OK;
}

static float srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}
static float linear_to_srgb(float v) {
  if (v <= 0) return 0;
  if (v >= 1) return 1;
  return v <= 0.0031308f ? v * 12.92f : 1.055f * powf(v, 1 / 2.4f) - 0.055f;
}

jnd_status jnd_resample_map(const jnd_image *in, int w, int h, jnd_map_kind kind, int wrap,
                            jnd_image *out) {
  if (!in || !in->data || in->c < 1 || in->c > 4) return jnd_fail(JND_ERR_ARG, "resample: bad input map");
  if (w < 1 || h < 1) return jnd_fail(JND_ERR_ARG, "resample: size %dx%d is not positive", w, h);
  jnd_status st = jnd_check_size(w, h, in->c, "resample");
  if (st) return st;
  int c = in->c;
  /* channels that carry colour (sRGB) or vector components */
  int ncol = kind == JND_MAP_KIND_DATA ? 0 : (c >= 3 ? 3 : 1);
  size_t inpix = (size_t)in->w * in->h;
  float *src = jnd_alloc(inpix * c, sizeof(float));
  if (!src) return JND_ERR_NOMEM;
  for (int ch = 0; ch < c; ch++) {
    const float *p = in->data + ch * inpix;
    float *q = src + ch * inpix;
    for (size_t i = 0; i < inpix; i++) {
      float v = p[i];
      if (ch < ncol) v = kind == JND_MAP_KIND_COLOR ? srgb_to_linear(v) : 2 * v - 1;
      q[i] = v;
    }
  }
  taps1d tx = {0}, ty = {0};
  if ((st = taps_make(in->w, w, wrap, &tx)) || (st = taps_make(in->h, h, wrap, &ty))) {
    free(src);
    taps_free(&tx);
    return jnd_fail(st, "out of memory");
  }
  float *mid = jnd_alloc((size_t)w * in->h * c, sizeof(float));   /* horizontal pass */
  if (!mid || (st = jnd_image_alloc(out, w, h, c))) {
    free(src);
    free(mid);
    taps_free(&tx);
    taps_free(&ty);
    return st ? st : JND_ERR_NOMEM;
  }
  int ih = in->h, iw = in->w;
#pragma omp parallel for schedule(static)
  for (int row = 0; row < c * ih; row++) {
    const float *s = src + (size_t)row * iw;
    float *d = mid + (size_t)row * w;
    for (int x = 0; x < w; x++) {
      const int *ix = tx.idx + (size_t)x * tx.taps;
      const float *wt = tx.w + (size_t)x * tx.taps;
      double acc = 0;
      for (int k = 0; k < tx.count[x]; k++) acc += wt[k] * s[ix[k]];
      d[x] = (float)acc;
    }
  }
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++) {
    const int *iy = ty.idx + (size_t)y * ty.taps;
    const float *wt = ty.w + (size_t)y * ty.taps;
    for (int ch = 0; ch < c; ch++) {
      float *d = out->data + ((size_t)ch * h + y) * w;
      const float *m = mid + (size_t)ch * ih * w;
      for (int x = 0; x < w; x++) {
        double acc = 0;
        for (int k = 0; k < ty.count[y]; k++) acc += wt[k] * m[(size_t)iy[k] * w + x];
        d[x] = (float)acc;
      }
    }
    /* back to the map's encoding */
    size_t plane = (size_t)w * h;
    for (int x = 0; x < w; x++) {
      size_t i = (size_t)y * w + x;
      if (kind == JND_MAP_KIND_NORMAL && ncol == 3) {
        float v[3], l = 0;
        for (int ch = 0; ch < 3; ch++) {
          v[ch] = out->data[ch * plane + i];
          l += v[ch] * v[ch];
        }
        l = sqrtf(l);
        for (int ch = 0; ch < 3; ch++) {
          float n = l > 1e-8f ? v[ch] / l : (ch == 2 ? 1.0f : 0.0f);
          out->data[ch * plane + i] = jnd_clampd(0.5 * n + 0.5, 0, 1);
        }
      } else {
        for (int ch = 0; ch < c; ch++) {
          float v = out->data[ch * plane + i];
          if (ch < ncol) v = kind == JND_MAP_KIND_COLOR ? linear_to_srgb(v) : 0.5f * v + 0.5f;
          out->data[ch * plane + i] = (float)jnd_clampd(v, 0, 1);
        }
      }
    }
  }
  free(src);
  free(mid);
  taps_free(&tx);
  taps_free(&ty);
  return JND_OK;
}
