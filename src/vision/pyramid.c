/* Gaussian and contrast pyramids (004 §3.1; Burt & Adelson 1983): REDUCE
 * blurs with the 5×5 binomial kernel [1 4 6 4 1]/16 (separable) and keeps the
 * even samples; EXPAND inserts zeros and interpolates with twice the kernel.
 * Borders are mirrored (whole-sample symmetric). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "vision/vision.h"

static const float K[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};

/* REDUCE's horizontal pass on one row: the kept (even) columns */
JND_HOT static void reduce_row(const float *r, int w, float *o, int dw) {
  int x = 0;
  for (; x < dw && 2 * x < 2; x++) { /* the left border, mirrored */
    float s = 0;
    for (int k = -2; k <= 2; k++) s += K[k + 2] * r[jnd_mirror(2 * x + k, w)];
    o[x] = s;
  }
  /* inside: 2x + 2 < w; one bound, so that the loop vectorises */
  const int xe = dw < (w - 1) / 2 ? dw : (w - 1) / 2;
  for (; x < xe; x++) {
    int c = 2 * x;
    o[x] = K[0] * r[c - 2] + K[1] * r[c - 1] + K[2] * r[c] + K[3] * r[c + 1] + K[4] * r[c + 2];
  }
  for (; x < dw; x++) {
    float s = 0;
    for (int k = -2; k <= 2; k++) s += K[k + 2] * r[jnd_mirror(2 * x + k, w)];
    o[x] = s;
  }
}

/* REDUCE's vertical pass for one output row from five input rows */
JND_HOT static void reduce_col(const float *r0, const float *r1, const float *r2, const float *r3, const float *r4,
                               float *o, int dw) {
  for (int x = 0; x < dw; x++) o[x] = K[0] * r0[x] + K[1] * r1[x] + K[2] * r2[x] + K[3] * r3[x] + K[4] * r4[x];
}

int jnd_pyr_reduce(const float *src, int w, int h, float *dst, int dw, int dh, int threads) {
  /* each output row blurs five input rows, each first reduced horizontally;
   * a thread keeps its last five reduced rows (neighbouring output rows share
   * three), so no intermediate image is needed */
  int ok = 1;
#pragma omp parallel num_threads(threads)
  {
    float *ring = malloc(sizeof(float) * (size_t)dw * 5);
    if (!ring) {
#pragma omp atomic write
      ok = 0;
    }
    int held[5] = {-1, -1, -1, -1, -1};
#pragma omp for schedule(static)
    for (int y = 0; y < dh; y++) {
      if (!ring) continue;
      const float *r[5];
      for (int k = 0; k < 5; k++) {
        int row = jnd_mirror(2 * y + k - 2, h), slot = row % 5;
        float *buf = ring + (size_t)slot * dw;
        if (held[slot] != row) {
          reduce_row(src + (size_t)row * w, w, buf, dw);
          held[slot] = row;
        }
        r[k] = buf;
      }
      reduce_col(r[0], r[1], r[2], r[3], r[4], dst + (size_t)y * dw, dw);
    }
    free(ring);
  }
  return ok;
}

int jnd_pyr_reduce3_rows(jnd_rows3_fn row, void *ctx, int w, int h, float *const dst[3], int dw, int dh,
                         int threads) {
  /* jnd_pyr_reduce on three planes at once, each input row made once for
   * all three (row), then reduced by the same reduce_row and reduce_col */
  int ok = 1;
#pragma omp parallel num_threads(threads)
  {
    float *mem = malloc(sizeof(float) * ((size_t)dw * 15 + (size_t)w * 3));
    if (!mem) {
#pragma omp atomic write
      ok = 0;
    }
    int held[5] = {-1, -1, -1, -1, -1};
#pragma omp for schedule(static)
    for (int y = 0; y < dh; y++) {
      if (!mem) continue;
      float *in[3] = {mem + (size_t)dw * 15, mem + (size_t)dw * 15 + w, mem + (size_t)dw * 15 + 2 * (size_t)w};
      const float *r[3][5];
      for (int k = 0; k < 5; k++) {
        int at = jnd_mirror(2 * y + k - 2, h), slot = at % 5;
        float *buf = mem + (size_t)slot * 3 * dw;
        if (held[slot] != at) {
          row(ctx, at, in);
          for (int c = 0; c < 3; c++) reduce_row(in[c], w, buf + (size_t)c * dw, dw);
          held[slot] = at;
        }
        for (int c = 0; c < 3; c++) r[c][k] = buf + (size_t)c * dw;
      }
      for (int c = 0; c < 3; c++) reduce_col(r[c][0], r[c][1], r[c][2], r[c][3], r[c][4], dst[c] + (size_t)y * dw, dw);
    }
    free(mem);
  }
  return ok;
}

/* fine sample x of EXPAND near the borders (mirrored coarse indices) */
static float expand_at(const float *src, int cw, int x) {
  if ((x & 1) == 0) {
    int c = x / 2;
    return 0.125f * src[jnd_mirror(c - 1, cw)] + 0.75f * src[jnd_mirror(c, cw)] + 0.125f * src[jnd_mirror(c + 1, cw)];
  }
  int c = (x - 1) / 2;
  return 0.5f * (src[jnd_mirror(c, cw)] + src[jnd_mirror(c + 1, cw)]);
}

JND_HOT void jnd_pyr_expand_row(const float *src, int cw, float *dst, int fw) {
  /* fine sample x gets 2·Σ K[m] src[(x−m)/2] over m with x−m even:
   * even x: K0, K2, K4 on coarse x/2+1, x/2, x/2−1 → 1/8, 3/4, 1/8
   * odd x:  K1, K3 on coarse (x±1)/2 → 1/2, 1/2 */
  int c1 = cw - 1; /* coarse c in [1, c1) has both neighbours inside */
  if (2 * c1 > fw) c1 = fw / 2;
  if (c1 < 1) c1 = 1;
  for (int x = 0; x < 2 && x < fw; x++) dst[x] = expand_at(src, cw, x);
  for (int c = 1; c < c1; c++) {
    float a = src[c - 1], b = src[c], n = src[c + 1];
    dst[2 * c] = 0.125f * a + 0.75f * b + 0.125f * n;
    dst[2 * c + 1] = 0.5f * (b + n);
  }
  for (int x = 2 * c1; x < fw; x++) dst[x] = expand_at(src, cw, x);
}

int jnd_pyr_expand_rows(int y, int ch, int rows[3], float wts[3]) {
  if ((y & 1) == 0) {
    int c = y / 2;
    rows[0] = jnd_mirror(c - 1, ch);
    rows[1] = jnd_mirror(c, ch);
    rows[2] = jnd_mirror(c + 1, ch);
    wts[0] = 0.125f;
    wts[1] = 0.75f;
    wts[2] = 0.125f;
    return 3;
  }
  int c = (y - 1) / 2;
  rows[0] = jnd_mirror(c, ch);
  rows[1] = jnd_mirror(c + 1, ch);
  wts[0] = wts[1] = 0.5f;
  return 2;
}

/* EXPAND's vertical step for one output row: the weighted sum of two or three
 * horizontally expanded rows */
JND_HOT static void expand_col(const float *const rb[3], const float wts[3], int n, float *o, int dw) {
  const float w0 = wts[0], w1 = wts[1];
  const float *r0 = rb[0], *r1 = rb[1];
  if (n == 2) {
    for (int x = 0; x < dw; x++) o[x] = w0 * r0[x] + w1 * r1[x];
    return;
  }
  const float w2 = wts[2], *r2 = rb[2];
  for (int x = 0; x < dw; x++) o[x] = w0 * r0[x] + w1 * r1[x] + w2 * r2[x];
}

void jnd_pyr_expanded_row(jnd_row_cache *c, const float *src, int cw, int ch, int y, float *out, int fw) {
  int rows[3];
  float wts[3];
  int n = jnd_pyr_expand_rows(y, ch, rows, wts);
  const float *rb[3];
  for (int k = 0; k < n; k++) rb[k] = jnd_pyr_cached_row(c, src, cw, rows[k], fw);
  expand_col(rb, wts, n, out, fw);
}

/* dst += max(o, 0) along a row */
JND_HOT static void add_positive(const float *o, float *dst, int n) {
  for (int x = 0; x < n; x++) dst[x] += jnd_maxf(o[x], 0.0f);
}

const float *jnd_pyr_cached_row(jnd_row_cache *c, const float *src, int cw, int crow, int fw) {
  int slot = crow % 3;
  float *dst = c->buf + (size_t)slot * fw;
  if (c->row[slot] != crow) {
    jnd_pyr_expand_row(src + (size_t)crow * cw, cw, dst, fw);
    c->row[slot] = crow;
  }
  return dst;
}

/* a row raised to p in place (jnd_fast_pow) */
JND_HOT static void pow_row(float *d, int n, float p) {
#pragma omp simd
  for (int x = 0; x < n; x++) d[x] = jnd_fast_pow(d[x], p);
}

/* EXPAND into dst, or, with add, max(EXPAND, 0) added to dst a row at a
 * time (no expanded image is stored), and with topow each row of the sum
 * then raised to p while it is in cache */
static int expand(const float *src, int w, int h, float *dst, int dw, int dh, int threads, int add, int topow,
                  float p) {
  int ok = 1;
#pragma omp parallel num_threads(threads)
  {
    /* three cached rows, and with add one for the expanded row */
    jnd_row_cache cache = {malloc(sizeof(float) * (size_t)dw * (add ? 4 : 3)), {-1, -1, -1}};
    if (!cache.buf) {
#pragma omp atomic write
      ok = 0;
    }
#pragma omp for schedule(static)
    for (int y = 0; y < dh; y++) {
      if (!cache.buf) continue;
      int rows[3];
      float wts[3];
      int n = jnd_pyr_expand_rows(y, h, rows, wts);
      const float *rb[3];
      for (int k = 0; k < n; k++) rb[k] = jnd_pyr_cached_row(&cache, src, w, rows[k], dw);
      float *d = dst + (size_t)y * dw;
      if (!add) {
        expand_col(rb, wts, n, d, dw);
        continue;
      }
      float *o = cache.buf + (size_t)3 * dw;
      expand_col(rb, wts, n, o, dw);
      add_positive(o, d, dw);
      if (topow) pow_row(d, dw, p);
    }
    free(cache.buf);
  }
  return ok;
}

int jnd_pyr_expand(const float *src, int w, int h, float *dst, int dw, int dh, int threads) {
  return expand(src, w, h, dst, dw, dh, threads, 0, 0, 0);
}

int jnd_pyr_expand_add(const float *src, int w, int h, float *dst, int dw, int dh, int threads) {
  return expand(src, w, h, dst, dw, dh, threads, 1, 0, 0);
}

int jnd_pyr_expand_add_pow(const float *src, int w, int h, float *dst, int dw, int dh, float p, int threads) {
  return expand(src, w, h, dst, dw, dh, threads, 1, 1, p);
}

/* the levels' sizes; each from the one above, halved and rounded up */
static jnd_status gauss_sizes(jnd_gauss *g, int w, int h, int levels) {
  memset(g, 0, sizeof *g);
  if (levels < 1 || levels > 24) return jnd_fail(JND_ERR_INTERNAL, "pyramid: %d levels", levels);
  g->levels = levels;
  g->w[0] = w;
  g->h[0] = h;
  for (int i = 1; i < levels; i++) {
    g->w[i] = (g->w[i - 1] + 1) / 2;
    g->h[i] = (g->h[i - 1] + 1) / 2;
  }
  return JND_OK;
}

/* levels from..levels−1 allocated and made from the one above each (or,
 * for a constant plane, set to its value) */
static jnd_status gauss_levels(jnd_gauss *g, int from, int constant, float value, int threads) {
  for (int i = from; i < g->levels; i++) {
    g->plane[i] = jnd_alloc((size_t)g->w[i] * g->h[i], sizeof(float));
    if (!g->plane[i]) return JND_ERR_NOMEM;
    if (constant) {
      for (size_t j = 0; j < (size_t)g->w[i] * g->h[i]; j++) g->plane[i][j] = value;
      continue;
    }
    if (!jnd_pyr_reduce(g->plane[i - 1], g->w[i - 1], g->h[i - 1], g->plane[i], g->w[i], g->h[i], threads))
      return jnd_fail(JND_ERR_NOMEM, "pyramid: out of memory");
  }
  return JND_OK;
}

jnd_status jnd_gauss_build(jnd_gauss *g, float *plane0, int w, int h, int levels, int threads) {
  jnd_status s = gauss_sizes(g, w, h, levels);
  if (s != JND_OK) return s;
  g->plane[0] = plane0;
  /* a constant plane (a psychophysical background) has constant levels */
  size_t n = (size_t)w * h, k = 1;
  while (k < n && plane0[k] == plane0[0]) k++;
  if ((s = gauss_levels(g, 1, k == n, plane0[0], threads)) != JND_OK) jnd_gauss_free(g);
  return s;
}

jnd_status jnd_gauss_build3_rows(jnd_gauss g[3], jnd_rows3_fn row, void *ctx, int w, int h, int levels,
                                 const int constant[3], const float value[3], int threads) {
  jnd_status s = JND_OK;
  for (int c = 0; c < 3 && s == JND_OK; c++) s = gauss_sizes(&g[c], w, h, levels);
  /* level 1 of all three from the rows (unless all are constant), then
   * each plane's own levels, a constant plane's set to its value as
   * jnd_gauss_build sets them */
  for (int c = 0; c < 3 && s == JND_OK && levels > 1; c++) {
    g[c].plane[1] = jnd_alloc((size_t)g[c].w[1] * g[c].h[1], sizeof(float));
    if (!g[c].plane[1]) s = JND_ERR_NOMEM;
  }
  if (s == JND_OK && levels > 1 && !(constant[0] && constant[1] && constant[2]) &&
      !jnd_pyr_reduce3_rows(row, ctx, w, h, (float *const[3]){g[0].plane[1], g[1].plane[1], g[2].plane[1]},
                            g[0].w[1], g[0].h[1], threads))
    s = jnd_fail(JND_ERR_NOMEM, "pyramid: out of memory");
  for (int c = 0; c < 3 && s == JND_OK && levels > 1; c++) {
    if (constant[c])
      for (size_t j = 0; j < (size_t)g[c].w[1] * g[c].h[1]; j++) g[c].plane[1][j] = value[c];
    s = gauss_levels(&g[c], 2, constant[c], value[c], threads);
  }
  if (s != JND_OK)
    for (int c = 0; c < 3; c++) jnd_gauss_free(&g[c]);
  return s;
}

void jnd_gauss_free(jnd_gauss *g) {
  for (int i = 1; i < g->levels; i++) free(g->plane[i]);
  if (g->own0) free(g->plane[0]);
  memset(g, 0, sizeof *g);
}

/* ---- band responses, measured through the filters themselves ---- */

/* Amplitude of band `band` for a unit cosine of frequency f (cycles per
 * full-resolution pixel): the 1-D signal goes through the same REDUCE and
 * EXPAND as images, and the band's RMS over the central half (×√2) is the
 * amplitude: the filters' gain losses and any aliased energy are included.
 * Frequencies stop just short of Nyquist (0.49 cycles/pixel), where a sampled
 * cosine is no longer a sinusoid and RMS·√2 would overstate it. */
static double band_amplitude(int band, double f) {
  int n = 256 << band; /* the band's level keeps 256 samples */
  if (n < 1024) n = 1024;
  float *lev[3];
  int len[3];
  float *sig = malloc(sizeof(float) * n);
  float *a = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
  if (!sig || !a || !b) {
    free(sig); free(a); free(b);
    return 0;
  }
  for (int x = 0; x < n; x++) sig[x] = (float)cos(2.0 * M_PI * f * x);
  /* reduce `band` times (1-D: a 1-row image) */
  int w = n;
  float *cur = sig;
  for (int i = 0; i < band; i++) {
    int dw = (w + 1) / 2;
    float *dst = cur == a ? b : a;
    jnd_pyr_reduce(cur, w, 1, dst, dw, 1, 1);
    cur = dst;
    w = dw;
  }
  len[0] = w;
  lev[0] = malloc(sizeof(float) * w);
  memcpy(lev[0], cur, sizeof(float) * w);
  len[1] = (w + 1) / 2;
  lev[1] = malloc(sizeof(float) * len[1]);
  jnd_pyr_reduce(lev[0], w, 1, lev[1], len[1], 1, 1);
  lev[2] = malloc(sizeof(float) * w);
  jnd_pyr_expand_row(lev[1], len[1], lev[2], w);
  double ss = 0;
  int cnt = 0;
  for (int x = w / 4; x < 3 * w / 4; x++) {
    double d = lev[0][x] - lev[2][x];
    ss += d * d;
    cnt++;
  }
  for (int i = 0; i < 3; i++) free(lev[i]);
  free(sig); free(a); free(b);
  return sqrt(2.0 * ss / cnt);
}

/* jnd_band_response's results for bands 0–5, kept so that models are cheap to
 * create; tests/unit/test_vision.c recomputes them from the filters. */
const double jnd_band_table[6][2] = {
    {0.4731243168, 1.0057773433}, {0.1254403726, 0.7137890529}, {0.0562395714, 0.6509001104},
    {0.0281187476, 0.6408069087}, {0.0140592362, 0.6383107060}, {0.0070296551, 0.6376883206},
};

void jnd_band_response(int band, double *peak_cpp, double *peak_amp) {
  /* coarse scan on a log grid below the full-resolution Nyquist, then golden section */
  const double fmax_cpp = 0.49;
  double best_f = fmax_cpp, best_a = -1;
  for (int k = 0; k <= 64; k++) {
    double f = fmax_cpp * pow(2.0, -(double)k / 8.0);
    if (f < 0.5 / pow(2.0, band + 4)) break;
    double amp = band_amplitude(band, f);
    if (amp > best_a) {
      best_a = amp;
      best_f = f;
    }
  }
  double lo = best_f * pow(2.0, -1.0 / 8), hi = fmin(fmax_cpp, best_f * pow(2.0, 1.0 / 8));
  const double gr = 0.6180339887498949;
  double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
  double f1 = band_amplitude(band, x1), f2 = band_amplitude(band, x2);
  for (int it = 0; it < 30 && hi - lo > 1e-6 * hi; it++) {
    if (f1 > f2) {
      hi = x2; x2 = x1; f2 = f1;
      x1 = hi - gr * (hi - lo); f1 = band_amplitude(band, x1);
    } else {
      lo = x1; x1 = x2; f1 = f2;
      x2 = lo + gr * (hi - lo); f2 = band_amplitude(band, x2);
    }
  }
  double fm = 0.5 * (lo + hi), am = band_amplitude(band, fm);
  if (am < best_a) {
    fm = best_f;
    am = best_a;
  }
  *peak_cpp = fm;
  *peak_amp = am;
}
