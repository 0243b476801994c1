/* Resampling of texture maps with a separable Lanczos-3 filter (000 §4:
 * lower-resolution candidates are made by Lanczos filtering), in the space
 * where averaging is meaningful for the map's kind. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "scene/scene.h"

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

/* The taps of out outputs over in inputs, output o sitting at input
 * coordinate (o + 0.5)·ratio − 0.5 (ratio: input samples per output
 * sample; in/out for a whole image, 2^s for the coarse level of a box
 * reduction, whose samples sit at the centres of their boxes). */
static jnd_status taps_make(int in, int out, int wrap, double ratio, taps1d *t) {
  double scale = 1.0 / ratio;
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

jnd_status jnd_resample_plane(const float *src, int sw, int sh, float *dst, int dw, int dh, double rx, double ry,
                              int wrap, int threads) {
  taps1d tx = {0}, ty = {0};
  threads = jnd_threads(threads);
  jnd_status st;
  if ((st = taps_make(sw, dw, wrap, rx, &tx)) || (st = taps_make(sh, dh, wrap, ry, &ty))) {
    taps_free(&tx);
    return jnd_fail(st, "out of memory");
  }
  float *mid = jnd_alloc((size_t)dw * sh, sizeof(float));   /* horizontal pass */
  if (!mid) {
    taps_free(&tx);
    taps_free(&ty);
    return JND_ERR_NOMEM;
  }
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int row = 0; row < sh; row++) {
    const float *s = src + (size_t)row * sw;
    float *d = mid + (size_t)row * dw;
    for (int x = 0; x < dw; x++) {
      const int *ix = tx.idx + (size_t)x * tx.taps;
      const float *wt = tx.w + (size_t)x * tx.taps;
      double acc = 0;
      for (int k = 0; k < tx.count[x]; k++) acc += wt[k] * s[ix[k]];
      d[x] = (float)acc;
    }
  }
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int y = 0; y < dh; y++) {
    const int *iy = ty.idx + (size_t)y * ty.taps;
    const float *wt = ty.w + (size_t)y * ty.taps;
    float *d = dst + (size_t)y * dw;
    for (int x = 0; x < dw; x++) {
      double acc = 0;
      for (int k = 0; k < ty.count[y]; k++) acc += wt[k] * mid[(size_t)iy[k] * dw + x];
      d[x] = (float)acc;
    }
  }
  free(mid);
  taps_free(&tx);
  taps_free(&ty);
  return JND_OK;
}

static int coarse_side(int n, int s) { return (n + (1 << s) - 1) >> s; }

void jnd_box_down_plane(const float *src, int w, int h, int s, float *dst) {
  int d = 1 << s, cw = coarse_side(w, s), ch = coarse_side(h, s);
#pragma omp parallel for schedule(static)
  for (int cy = 0; cy < ch; cy++) {
    for (int cx = 0; cx < cw; cx++) {
      double acc = 0;
      int n = 0;
      for (int y = cy * d; y < cy * d + d && y < h; y++)
        for (int x = cx * d; x < cx * d + d && x < w; x++) {
          acc += src[(size_t)y * w + x];
          n++;
        }
      dst[(size_t)cy * cw + cx] = (float)(acc / n);
    }
  }
}

jnd_status jnd_box_reduce_map(const jnd_image *orig, int lev, jnd_map_kind kind, jnd_image *out) {
  int w = coarse_side(orig->w, lev), h = coarse_side(orig->h, lev);
  jnd_status s = jnd_image_alloc(out, w, h, orig->c);
  if (s != JND_OK) return s;
  size_t n = (size_t)orig->w * orig->h;
  float *tmp = jnd_alloc(n, sizeof *tmp);
  if (!tmp) {
    jnd_image_free(out);
    return JND_ERR_NOMEM;
  }
  for (int ch = 0; ch < orig->c; ch++) {
    /* sRGB colour is averaged in linear light, as GL does for sRGB textures */
    int colour = kind == JND_MAP_KIND_COLOR && ch < 3;
    const float *src = orig->data + (size_t)ch * n;
    for (size_t i = 0; i < n; i++) tmp[i] = colour ? jnd_srgb_decode(src[i]) : src[i];
    float *dst = out->data + (size_t)ch * w * h;
    jnd_box_down_plane(tmp, orig->w, orig->h, lev, dst);
    if (colour)
      for (size_t i = 0; i < (size_t)w * h; i++) dst[i] = jnd_srgb_encode(dst[i]);
  }
  free(tmp);
  return JND_OK;
}

jnd_status jnd_resample_map(const jnd_image *in, int w, int h, jnd_map_kind kind, int wrap,
                            jnd_image *out) {
  return jnd_resample_map_threads(in, w, h, kind, wrap, 0, out);
}

jnd_status jnd_resample_map_threads(const jnd_image *in, int w, int h, jnd_map_kind kind, int wrap, int threads,
                                    jnd_image *out) {
  threads = jnd_threads(threads);
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
      if (ch < ncol) v = kind == JND_MAP_KIND_COLOR ? jnd_srgb_decode(v) : 2 * v - 1;
      q[i] = v;
    }
  }
  if ((st = jnd_image_alloc(out, w, h, c))) {
    free(src);
    return st;
  }
  for (int ch = 0; ch < c && st == JND_OK; ch++)
    st = jnd_resample_plane(src + ch * inpix, in->w, in->h, out->data + (size_t)ch * w * h, w, h,
                            (double)in->w / w, (double)in->h / h, wrap, threads);
  free(src);
  if (st) {
    jnd_image_free(out);
    return st;
  }
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int y = 0; y < h; y++) {
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
          if (ch < ncol) v = kind == JND_MAP_KIND_COLOR ? jnd_srgb_encode(v) : 0.5f * v + 0.5f;
          out->data[ch * plane + i] = (float)jnd_clampd(v, 0, 1);
        }
      }
    }
  }
  return JND_OK;
}
