/* jnd lod's 003 metric: the Point of Imperceptibility (PoI) of a chain of
 * levels of detail per target screen, as Wu, Agu & Lindsay (2007, 003)
 * define it. docs/lod.md gives each term's equation beside the function
 * that computes it and says how what 003 leaves open was decided.
 *
 * Procedure, with 003's sections:
 *  1. Chain (003 §2, §5): the scene's levels, F_k triangles each (made by
 *     jnd_scene_lod_build, or imported); level 0 is S1, level k is S2.
 *  2. Object-space term (003 §4.1, eq. 1): (1 − F2/F1) times the
 *     area-weighted L2 distance from S1 to S2 (points sampled on S1 by area,
 *     nearest point on S2: jnd_scene_points_distance), over the scene's
 *     extent so that it has no unit, like E_p.  object_term()
 *  3. Views (003 §6 proposes several): p->views cameras around the object
 *     (jnd_views_sample), each seeing the bounding sphere fill p->coverage of
 *     the screen's height.
 *  4. Virtual screen M1 (003 §4.1 step 2): every level rendered, unlit and
 *     lit, into one large square image that holds the sphere — the central
 *     part of the viewer's field of view, so that M1 and each screen's M2
 *     share one perspective — 8-bit codes as a display shows them.
 *  5. Screen-space term E_p (003 §4.1, eq. 2, p = 2): M1 minified by blocks
 *     to each screen's M2 (area-weighted where blocks are not whole
 *     pixels), each M2 pixel of level k against the M1 pixels of level 0 it
 *     covers, RMS over the screen's W2 × H2 pixels.  ep_sum()
 *  6. Perceptual term M_p (003 §4.2, eqs. 3–4): the lit M2 images of levels
 *     0 and k, their Haar bands weighted by C_m, the Mannos–Sakrison CSF's
 *     mean over each band at the screen's pixels per degree, the squared
 *     differences summed over the screen's pixels.  mp_sum()
 *  7. Curves and knees (003 §3, Hypothesis 1): error = object + E_p (eq. 1,
 *     unlit) and error_lit = error × M_p (eq. 3) against log2 of the
 *     triangles; the PoI is the knee, the point farthest below the chord
 *     (jnd_knee).  knee_of()
 *  8. Rules of thumb beside it: meshoptimizer's error in pixels at most
 *     p->meshopt_pixels, and the measured largest deviation at most
 *     p->pixel_error pixels.
 *  9. Textures (003 §4.3): each map over its mip chain, M1 the map itself,
 *     E_p and M_p only.  texture_curves()
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"
#include "jnd.h"
#include "scene/scene.h"
#include "tasks/tasks.h"
#include "vision/vision.h"

enum { MAX_BANDS = 24 };

void jnd_poi_defaults(jnd_poi_params *p) {
  memset(p, 0, sizeof *p);
  p->views = 2;
  p->seed = 1;
  p->coverage = 0.5;
  p->fov_y_deg = 45;
  p->lights = 1;
  p->virtual_scale = 1.5;
  p->max_virtual_px = 4096;
  p->anisotropy = 4;
  p->surface_samples = 65536;
  p->meshopt_pixels = 1;
  p->pixel_error = 0.5;
  p->textures = 1;
  p->min_texture_px = 8;
}

static const char *const default_screens[] = {"standard-fhd", "standard-4k", "phone", "laptop"};

jnd_status jnd_poi_screen_parse(const char *spec, jnd_poi_screen *s) {
  memset(s, 0, sizeof *s);
  int w = 0, h = 0, n = 0;
  double ppd = 0;
  if (sscanf(spec, "%dx%d%n", &w, &h, &n) == 2 && (spec[n] == 0 || spec[n] == '@')) {
    if (spec[n] == '@') {
      char *end;
      ppd = strtod(spec + n + 1, &end);
      if (*end || !(ppd > 0 && ppd < 1000)) return jnd_fail(JND_ERR_ARG, "screen '%s': PPD must be in (0, 1000)", spec);
    } else {
      jnd_display d;
      jnd_display_defaults(&d);   /* standard-fhd's pixels per degree (docs/lod.md) */
      ppd = d.ppd;
    }
    if (w < 16 || h < 16 || w > 32768 || h > 32768)
      return jnd_fail(JND_ERR_ARG, "screen '%s': W and H must be 16..32768 pixels", spec);
    snprintf(s->name, sizeof s->name, "%dx%d", w, h);
  } else {
    jnd_display d;
    if (jnd_display_preset(spec, &d) != JND_OK)
      return jnd_fail(JND_ERR_ARG, "screen '%s': not a display preset (standard-fhd, standard-4k, phone, laptop) "
                      "nor WxH[@PPD]", spec);
    if (d.width_px <= 0)
      return jnd_fail(JND_ERR_ARG, "screen '%s' has no size in pixels: give it as WxH@PPD", spec);
    w = d.width_px;
    h = d.height_px;
    ppd = d.ppd;
    snprintf(s->name, sizeof s->name, "%s", spec);
  }
  s->width_px = w;
  s->height_px = h;
  s->ppd = ppd;
  return JND_OK;
}

/* ---- images as a display shows them: 8-bit codes, planar (the judge's
 * judge_level_codes shows renderings so) ---- */

typedef display_codes codes;

static void codes_free(codes *c) {
  free(c->px);
  c->px = NULL;
}

/* Area weights of a minification (or magnification) along one axis: output
 * pixel o covers input [o·n/m, (o+1)·n/m); each input pixel it overlaps
 * counts by the overlap over the block's width (003 §4.1 step 3: a block of
 * M1 pixels per M2 pixel, whole or not). */
typedef struct {
  int *first, *count;
  float *w;        /* per output, count weights from first */
  int stride;      /* weights per output (the largest count) */
} axis_weights;

static void axis_free(axis_weights *a) {
  free(a->first);
  free(a->count);
  free(a->w);
}

static jnd_status axis_make(int n, int m, axis_weights *a) {
  memset(a, 0, sizeof *a);
  a->stride = (int)ceil((double)n / m) + 2;
  a->first = jnd_alloc((size_t)m, sizeof *a->first);
  a->count = jnd_alloc((size_t)m, sizeof *a->count);
  a->w = jnd_alloc((size_t)m * a->stride, sizeof *a->w);
  if (!a->first || !a->count || !a->w) {
    axis_free(a);
    return JND_ERR_NOMEM;
  }
  double scale = (double)n / m;
  for (int o = 0; o < m; o++) {
    double lo = o * scale, hi = (o + 1) * scale;
    int j0 = (int)floor(lo), j1 = (int)ceil(hi);
    if (j1 > n) j1 = n;
    a->first[o] = j0;
    a->count[o] = 0;
    for (int j = j0; j < j1 && a->count[o] < a->stride; j++) {
      double ov = fmin(hi, j + 1.0) - fmax(lo, (double)j);
      if (ov <= 0) continue;
      if (a->count[o] == 0) a->first[o] = j;
      a->w[(size_t)o * a->stride + a->count[o]++] = (float)(ov / scale);
    }
  }
  return JND_OK;
}

/* in (w × h codes) resampled to mw × mh by the area weights, rounded to
 * codes; out's pixels are reused when it has the size already */
static jnd_status resample_codes(const codes *in, const axis_weights *ax, int mw, const axis_weights *ay, int mh,
                                 codes *out) {
  if (!out->px || out->w != mw || out->h != mh || out->c != in->c) {
    codes_free(out);
    if (!(out->px = jnd_alloc((size_t)mw * mh * in->c, 1))) return JND_ERR_NOMEM;
  }
  out->w = mw, out->h = mh, out->c = in->c;
  float *row = jnd_alloc((size_t)mw * in->h * in->c, sizeof *row);
  if (!row) return JND_ERR_NOMEM;
  int C = in->c;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (int y = 0; y < C * in->h; y++) {
      const uint8_t *src = in->px + (size_t)y * in->w;   /* channel-major rows */
      float *dst = row + (size_t)y * mw;
      for (int o = 0; o < mw; o++) {
        const float *w = ax->w + (size_t)o * ax->stride;
        const uint8_t *sp = src + ax->first[o];
        float acc = 0;
        for (int k = 0; k < ax->count[o]; k++) acc += w[k] * sp[k];
        dst[o] = acc;
      }
    }
#pragma omp for schedule(static)
    for (int oy = 0; oy < C * mh; oy++) {
      int c = oy / mh, o = oy % mh;
      const float *w = ay->w + (size_t)o * ay->stride;
      const float *base = row + ((size_t)c * in->h + ay->first[o]) * mw;
      uint8_t *dst = out->px + ((size_t)c * mh + o) * mw;
      for (int x = 0; x < mw; x++) {
        float acc = 0;
        for (int k = 0; k < ay->count[o]; k++) acc += w[k] * base[(size_t)k * mw + x];
        dst[x] = (uint8_t)jnd_clampi((int)lrintf(acc), 0, 255);
      }
    }
  }
  free(row);
  return JND_OK;
}

/* a float plane resampled by the area weights (the lit luma, 003 §4.2) */
static jnd_status resample_plane(const float *in, int w, int h, const axis_weights *ax, int mw,
                                 const axis_weights *ay, int mh, float *out) {
  float *row = jnd_alloc((size_t)mw * h, sizeof *row);
  if (!row) return JND_ERR_NOMEM;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (int y = 0; y < h; y++)
      for (int o = 0; o < mw; o++) {
        const float *wt = ax->w + (size_t)o * ax->stride;
        const float *sp = in + (size_t)y * w + ax->first[o];
        float acc = 0;
        for (int k = 0; k < ax->count[o]; k++) acc += wt[k] * sp[k];
        row[(size_t)y * mw + o] = acc;
      }
#pragma omp for schedule(static)
    for (int o = 0; o < mh; o++) {
      const float *wt = ay->w + (size_t)o * ay->stride;
      for (int x = 0; x < mw; x++) {
        float acc = 0;
        for (int k = 0; k < ay->count[o]; k++) acc += wt[k] * row[(size_t)(ay->first[o] + k) * mw + x];
        out[(size_t)o * mw + x] = acc;
      }
    }
  }
  free(row);
  return JND_OK;
}

/* 003 eq. 2 (p = 2) before its normalisation: Σ_i (Σ_j w_ij √S_ij)² over the
 * M2 pixels i, S_ij = ⅓ Σ_c ((R_i2 − R_j1) / 256)² for the M1 pixels j of
 * i's block, weighted by how much of j the block covers (w_ij sums to 1;
 * for whole blocks w_ij = W2H2 / W1H1, as 003 writes it). ref is M1 (level
 * 0), test is M2 (level k). Rows are summed in order: thread-independent. */
static double ep_sum(const codes *ref, const codes *test, const axis_weights *ax, const axis_weights *ay) {
  int mw = test->w, mh = test->h, C = ref->c;
  double *rows = jnd_calloc((size_t)mh, sizeof *rows);
  if (!rows) return NAN;
  /* ((a − b)/256)² / C for every code difference */
  float sq[511];
  for (int d = -255; d <= 255; d++) sq[d + 255] = (float)((d / 256.0) * (d / 256.0) / C);
  size_t P1 = (size_t)ref->w * ref->h, P2 = (size_t)mw * mh;
#pragma omp parallel for schedule(dynamic, 4)
  for (int oy = 0; oy < mh; oy++) {
    double acc = 0;
    const float *wy = ay->w + (size_t)oy * ay->stride;
    for (int ox = 0; ox < mw; ox++) {
      const float *wx = ax->w + (size_t)ox * ax->stride;
      int r2[3] = {0, 0, 0};
      for (int c = 0; c < C; c++) r2[c] = test->px[c * P2 + (size_t)oy * mw + ox] + 255;
      float block = 0;
      for (int ky = 0; ky < ay->count[oy]; ky++) {
        size_t y = (size_t)(ay->first[oy] + ky);
        const uint8_t *p0 = ref->px + y * ref->w + ax->first[ox];
        float rowsum = 0;
        for (int kx = 0; kx < ax->count[ox]; kx++) {
          float sp = 0;
          for (int c = 0; c < C; c++) sp += sq[r2[c] - p0[c * P1 + kx]];
          rowsum += wx[kx] * sqrtf(sp);
        }
        block += wy[ky] * rowsum;
      }
      acc += (double)block * block;
    }
    rows[oy] = acc;
  }
  double sum = 0;
  for (int y = 0; y < mh; y++) sum += rows[y];
  free(rows);
  return sum;
}

/* Rec. 709 luma of the codes over 256, the signal the Mannos–Sakrison CSF
 * weighs (003 §4.2 is achromatic) */
static jnd_status luma_of(const codes *in, float **out) {
  size_t P = (size_t)in->w * in->h;
  float *y = jnd_alloc(P ? P : 1, sizeof *y);
  if (!y) return JND_ERR_NOMEM;
  for (size_t i = 0; i < P; i++)
    y[i] = in->c >= 3 ? (float)((0.2126 * in->px[i] + 0.7152 * in->px[P + i] + 0.0722 * in->px[2 * P + i]) / 256.0)
                      : (float)(in->px[i] / 256.0);
  *out = y;
  return JND_OK;
}

/* 003 eq. 4 before its normalisation: Σ_{m,i,j} |D1 − D2|² with D = C_m·W,
 * i.e. Σ_m C_m² ‖W_m(Y1) − W_m(Y2)‖² (the Haar transform is linear: the
 * bands of the difference). */
static double mp_sum(const float *y1, const float *y2, int w, int h, double ppd) {
  size_t P = (size_t)w * h;
  float *d = jnd_alloc(P ? P : 1, sizeof *d);
  if (!d) return NAN;
  for (size_t i = 0; i < P; i++) d[i] = y1[i] - y2[i];
  double e[MAX_BANDS];
  int n = jnd_haar_band_energy(d, w, h, e, MAX_BANDS, NULL);
  free(d);
  if (n < 0) return NAN;
  double sum = 0;
  for (int m = 1; m <= n; m++) {
    double cm = jnd_haar_band_weight(m, ppd);
    sum += cm * cm * e[m - 1];
  }
  return sum;
}

double poi_ep_sum_codes(const uint8_t *ref, int w, int h, const uint8_t *test, int mw, int mh, int c) {
  codes r = {w, h, c, (uint8_t *)ref}, t = {mw, mh, c, (uint8_t *)test};
  axis_weights ax, ay;
  if (axis_make(w, mw, &ax)) return NAN;
  if (axis_make(h, mh, &ay)) {
    axis_free(&ax);
    return NAN;
  }
  double e = ep_sum(&r, &t, &ax, &ay);
  axis_free(&ax);
  axis_free(&ay);
  return e;
}

double poi_mp_sum(const float *y1, const float *y2, int w, int h, double ppd) { return mp_sum(y1, y2, w, h, ppd); }

jnd_status poi_luma_codes(const uint8_t *px, int w, int h, int c, float **out) {
  codes in = {w, h, c, (uint8_t *)px};
  return luma_of(&in, out);
}

/* 003 §3: the PoI is the knee of the curve against the level of detail,
 * log2 of the triangles (or texels) — 003's wavelet levels are each a
 * factor 4 — farthest below the chord; levels within 2% of the farthest are
 * a tie, settled for the finer one (docs/lod.md: a 0.3% difference flipped
 * the teapot's unlit knee on the 4K screen). */
#define KNEE_TIE 0.02
static int knee_of(const double *cost, const double *err, int n) {
  double x[64], y[64];
  if (n > 64) n = 64;
  for (int k = 0; k < n; k++) {
    x[k] = log2(cost[k] > 1 ? cost[k] : 1);
    y[k] = err[k];
  }
  int k = jnd_knee(x, y, n, JND_KNEE_BELOW, KNEE_TIE);
  return k < 0 ? 0 : k;
}

/* ---- 003 §4.3: textures over their mip chains ---- */

/* a map as codes: colour channels as stored (sRGB-encoded), 1–2 channels as grey */
static jnd_status map_codes(const jnd_image *im, codes *out) {
  int C = im->c >= 3 ? 3 : 1;
  size_t P = (size_t)im->w * im->h;
  out->w = im->w, out->h = im->h, out->c = C;
  out->px = jnd_alloc(P * C, 1);
  if (!out->px) return JND_ERR_NOMEM;
  for (int c = 0; c < C; c++)
    for (size_t i = 0; i < P; i++) out->px[c * P + i] = (uint8_t)jnd_clampi((int)lrintf(255.0f * im->data[c * P + i]), 0, 255);
  return JND_OK;
}

/* the next mip level: 2 × 2 boxes (a partial box averages what it covers) */
static jnd_status mip_down(const codes *in, codes *out) {
  int w = (in->w + 1) / 2, h = (in->h + 1) / 2;
  out->w = w, out->h = h, out->c = in->c;
  out->px = jnd_alloc((size_t)w * h * in->c, 1);
  if (!out->px) return JND_ERR_NOMEM;
  for (int c = 0; c < in->c; c++) {
    const uint8_t *s = in->px + (size_t)c * in->w * in->h;
    uint8_t *d = out->px + (size_t)c * w * h;
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++) {
        int sum = 0, n = 0;
        for (int dy = 0; dy < 2; dy++)
          for (int dx = 0; dx < 2; dx++) {
            int sx = 2 * x + dx, sy = 2 * y + dy;
            if (sx < in->w && sy < in->h) sum += s[(size_t)sy * in->w + sx], n++;
          }
        d[(size_t)y * w + x] = (uint8_t)((sum + n / 2) / n);
      }
  }
  return JND_OK;
}

/* the M2 size of a w × h image whose longer side fills `side` pixels */
static void fit(int w, int h, int side, int *mw, int *mh) {
  if (w >= h) {
    *mw = side;
    *mh = (int)lrint((double)side * h / w);
  } else {
    *mh = side;
    *mw = (int)lrint((double)side * w / h);
  }
  if (*mw < 1) *mw = 1;
  if (*mh < 1) *mh = 1;
}

static jnd_status texture_curves(const jnd_scene *scene, int map, const jnd_poi_screen *scr, int nscr,
                                 const jnd_poi_params *p, jnd_poi_texture *t) {
  jnd_map_info mi;
  jnd_status st = jnd_scene_map_info(scene, map, &mi);
  if (st) return st;
  memset(t, 0, sizeof *t);
  t->map = map;
  snprintf(t->name, sizeof t->name, "%s", mi.name);
  jnd_image im = {0};
  if ((st = jnd_scene_map_get(scene, map, 1, &im))) return st;
  codes lv[32];
  int n = 0;
  st = map_codes(&im, &lv[0]);
  jnd_image_free(&im);
  if (st) return st;
  n = 1;
  while (!st && n < 32 && (lv[n - 1].w > 1 || lv[n - 1].h > 1) &&
         (lv[n - 1].w > lv[n - 1].h ? lv[n - 1].w : lv[n - 1].h) / 2 >= p->min_texture_px) {
    st = mip_down(&lv[n - 1], &lv[n]);
    if (!st) n++;
  }
  t->nlevels = n;
  t->nscreens = nscr;
  t->size = jnd_calloc((size_t)n, sizeof *t->size);
  size_t sn = (size_t)n * nscr;
  t->e_p = jnd_calloc(sn, sizeof *t->e_p);
  t->m_p = jnd_calloc(sn, sizeof *t->m_p);
  t->error = jnd_calloc(sn, sizeof *t->error);
  t->poi_level = jnd_calloc((size_t)nscr, sizeof *t->poi_level);
  t->poi_level_ep = jnd_calloc((size_t)nscr, sizeof *t->poi_level_ep);
  if (!st && (!t->size || !t->e_p || !t->m_p || !t->error || !t->poi_level || !t->poi_level_ep)) st = JND_ERR_NOMEM;
  for (int k = 0; k < n && !st; k++) t->size[k][0] = lv[k].w, t->size[k][1] = lv[k].h;
  for (int s = 0; s < nscr && !st; s++) {
    int side = (int)lrint(p->coverage * scr[s].height_px), mw, mh;
    fit(lv[0].w, lv[0].h, side < 1 ? 1 : side, &mw, &mh);
    double norm = (double)scr[s].width_px * scr[s].height_px;
    float *yref = NULL;
    for (int k = 0; k < n && !st; k++) {
      axis_weights ax, ay, bx, by;
      /* level k shown on M2, and level 0's M1 blocks it covers */
      st = axis_make(lv[k].w, mw, &ax);
      if (!st && (st = axis_make(lv[k].h, mh, &ay))) axis_free(&ax);
      if (st) break;
      codes m2 = {0};
      st = resample_codes(&lv[k], &ax, mw, &ay, mh, &m2);
      axis_free(&ax);
      axis_free(&ay);
      if (!st && !(st = axis_make(lv[0].w, mw, &bx))) {
        if (!(st = axis_make(lv[0].h, mh, &by))) {
          double e = ep_sum(&lv[0], &m2, &bx, &by);
          t->e_p[(size_t)s * n + k] = sqrt(e / norm);
          axis_free(&by);
        }
        axis_free(&bx);
      }
      float *y2 = NULL;
      if (!st) st = luma_of(&m2, &y2);
      if (!st && k == 0) {
        yref = y2;
        y2 = NULL;
        t->m_p[(size_t)s * n] = 0;
      } else if (!st) {
        t->m_p[(size_t)s * n + k] = mp_sum(yref, y2, mw, mh, scr[s].ppd) / norm;
      }
      free(y2);
      codes_free(&m2);
    }
    free(yref);
    if (st) break;
    double cost[32];
    for (int k = 0; k < n; k++) {
      cost[k] = (double)lv[k].w * lv[k].h;
      t->error[(size_t)s * n + k] = t->e_p[(size_t)s * n + k] * t->m_p[(size_t)s * n + k];
    }
    t->poi_level[s] = knee_of(cost, t->error + (size_t)s * n, n);
    t->poi_level_ep[s] = knee_of(cost, t->e_p + (size_t)s * n, n);
  }
  for (int k = 0; k < n; k++) codes_free(&lv[k]);
  return st;
}

/* ---- the analysis ---- */

void jnd_poi_result_free(jnd_poi_result *r) {
  if (!r) return;
  free(r->levels);
  free(r->distance);
  for (int s = 0; s < r->nscreens && r->screens; s++) free(r->screens[s].curve);
  free(r->screens);
  for (int t = 0; t < r->ntextures && r->textures; t++) {
    jnd_poi_texture *x = &r->textures[t];
    free(x->size);
    free(x->e_p);
    free(x->m_p);
    free(x->error);
    free(x->poi_level);
    free(x->poi_level_ep);
  }
  free(r->textures);
  memset(r, 0, sizeof *r);
}

static void progress(const jnd_poi_params *p, const char *stage, int done, int total) {
  if (p->progress) p->progress(p->progress_user, stage, done, total);
}

/* step 2 */
static double object_term(size_t f1, size_t f2, double l2, double extent) {
  /* 003: "If F1 < F2, we can rewrite 1 − F2/F1 as 1 − F1/F2" */
  double a = (double)f1, b = (double)f2, frac = a >= b ? 1 - b / a : 1 - a / b;
  return frac * l2 / extent;
}

jnd_status poi_check(const jnd_scene *scene, const jnd_poi_params *p, jnd_poi_screen scr[LOD_MAX_SCREENS],
                     int *nscr) {
  int n = jnd_scene_lod_count(scene);
  if (n < 2) return jnd_fail(JND_ERR_ARG, "%s: no levels of detail to compare (build or add a chain)", jnd_scene_path(scene));
  if (n > 64) return jnd_fail(JND_ERR_LIMIT, "%s: %d levels (at most 64)", jnd_scene_path(scene), n);
  return poi_params_check(p, scr, nscr);
}

jnd_status poi_params_check(const jnd_poi_params *p, jnd_poi_screen scr[LOD_MAX_SCREENS], int *nscr) {
  if (p->views < 1 || p->views > JND_VIEWS_MAX)
    return jnd_fail(JND_ERR_ARG, "poi: %d views (1..%d)", p->views, JND_VIEWS_MAX);
  if (!(p->coverage > 0 && p->coverage <= 1)) return jnd_fail(JND_ERR_ARG, "lod: coverage %g outside (0, 1]: the object must fit on the screen", p->coverage);
  if (!(p->virtual_scale >= 1)) return jnd_fail(JND_ERR_ARG, "poi: virtual scale %g is below 1", p->virtual_scale);
  if (p->surface_samples < 16) return jnd_fail(JND_ERR_ARG, "poi: %d surface samples (at least 16)", p->surface_samples);
  /* the screens */
  *nscr = p->screens ? p->nscreens : 4;
  if (*nscr < 1 || *nscr > LOD_MAX_SCREENS) return jnd_fail(JND_ERR_ARG, "poi: %d screens (1..%d)", *nscr, LOD_MAX_SCREENS);
  for (int s = 0; s < *nscr; s++) {
    if (p->screens) scr[s] = p->screens[s];
    else if (jnd_poi_screen_parse(default_screens[s], &scr[s])) return JND_ERR_INTERNAL;
    if (scr[s].width_px < 1 || scr[s].height_px < 1 || !(scr[s].ppd > 0))
      return jnd_fail(JND_ERR_ARG, "poi: screen '%s' needs pixels and pixels per degree", scr[s].name);
  }
  return JND_OK;
}

jnd_status jnd_poi_analyse(jnd_scene *scene, const jnd_poi_params *pp, jnd_poi_result *out) {
  jnd_poi_params d;
  if (!pp) {
    jnd_poi_defaults(&d);
    pp = &d;
  }
  const jnd_poi_params *p = pp;
  memset(out, 0, sizeof *out);
  jnd_poi_screen scr[LOD_MAX_SCREENS];
  int nscr, n = jnd_scene_lod_count(scene);
  jnd_status st = poi_check(scene, p, scr, &nscr);
  if (st) return st;
  out->nlevels = n;
  out->nscreens = nscr;
  out->views = p->views;
  out->levels = jnd_calloc((size_t)n, sizeof *out->levels);
  out->distance = jnd_calloc((size_t)n, sizeof *out->distance);
  out->screens = jnd_calloc((size_t)nscr, sizeof *out->screens);
  if (!out->levels || !out->distance || !out->screens) goto nomem;
  for (int s = 0; s < nscr; s++) {
    out->screens[s].screen = scr[s];
    out->screens[s].nlevels = n;
    if (!(out->screens[s].curve = jnd_calloc((size_t)n, sizeof *out->screens[s].curve))) goto nomem;
  }
  for (int k = 0; k < n && !st; k++) st = jnd_scene_lod_info(scene, k, &out->levels[k]);
  if (st) goto fail;

  /* step 2: the object-space term */
  progress(p, "object-space term", 0, n);
  double centre[3];
  jnd_scene_bounds(scene, centre, &out->radius);
  double *pts = NULL;
  if ((st = jnd_scene_surface_samples(scene, p->surface_samples, p->seed, &pts))) goto fail;
  for (int k = 0; k < n && !st; k++) {
    st = jnd_scene_points_distance(scene, k, pts, p->surface_samples, &out->distance[k]);
    progress(p, "object-space term", k + 1, n);
  }
  free(pts);
  if (st) goto fail;
  out->extent = jnd_scene_extent(scene);
  if (!(out->extent > 0)) {
    st = jnd_fail(JND_ERR_FORMAT, "%s: the meshes have no extent", jnd_scene_path(scene));
    goto fail;
  }
  for (int s = 0; s < nscr; s++)
    for (int k = 0; k < n; k++)
      out->screens[s].curve[k].object = object_term(out->levels[0].triangles, out->levels[k].triangles,
                                                    out->distance[k].rms, out->extent);

  /* step 3: views; step 4: the virtual screen */
  double cov = p->coverage, fov = p->fov_y_deg > 0 ? p->fov_y_deg : 45;
  double largest = 0;
  for (int s = 0; s < nscr; s++) {
    jnd_poi_screen_result *R = &out->screens[s];
    R->object_px = cov * scr[s].height_px;
    R->m2_px = (int)lrint(R->object_px);
    if (R->m2_px < 1) R->m2_px = 1;
    if (R->object_px > largest) largest = R->object_px;
  }
  int S1 = (int)ceil(p->virtual_scale * largest);
  if (p->max_virtual_px > 0 && S1 > p->max_virtual_px) S1 = p->max_virtual_px;
  if (S1 < 16) S1 = 16;
  out->virtual_px = S1;
  jnd_view *views = jnd_calloc((size_t)p->views, sizeof *views);
  if (!views) goto nomem;
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = p->views;
  vs.seed = p->seed;
  vs.coverage = cov;
  vs.fov_y_deg = fov;
  vs.lights = p->lights;
  if ((st = jnd_views_sample(scene, &vs, views))) {
    free(views);
    goto fail;
  }
  /* M1 is the central part of the viewer's field that holds the sphere:
   * same eye, a field of view narrowed by the coverage */
  double fov1 = 2 * atan(cov * tan(fov * M_PI / 360)) * 180 / M_PI;
  for (int v = 0; v < p->views; v++) {
    views[v].camera.fov_y_deg = fov1;
    views[v].background_env = 0;
  }
  progress(p, "renderings", 0, p->views * n);
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.samples = 1;   /* M1 is the supersampled reference: minification antialiases */
  rp.anisotropy = p->anisotropy > 0 ? p->anisotropy : 1;
  rp.env_path = p->env_path;
  rp.platform = p->platform;
  jnd_renderer *r = NULL;
  if ((st = judge_renderer(&rp, S1, &r))) {
    free(views);
    goto fail;
  }
  snprintf(out->renderer, sizeof out->renderer, "%s", jnd_renderer_description(r));

  /* steps 5 and 6, view by view; buffers allocated once */
  axis_weights aw[LOD_MAX_SCREENS];
  memset(aw, 0, sizeof aw);
  for (int s = 0; s < nscr && !st; s++) st = axis_make(S1, out->screens[s].m2_px, &aw[s]);
  double *ep = jnd_calloc((size_t)nscr * n, sizeof *ep), *mp = jnd_calloc((size_t)nscr * n, sizeof *mp);
  float *ylit0[LOD_MAX_SCREENS] = {0}, *ylit = NULL, *ym1 = jnd_alloc((size_t)S1 * S1, sizeof *ym1);
  int biggest = 1;
  for (int s = 0; s < nscr; s++)
    if (out->screens[s].m2_px > biggest) biggest = out->screens[s].m2_px;
  ylit = jnd_alloc((size_t)biggest * biggest, sizeof *ylit);
  for (int s = 0; s < nscr && !st; s++)
    if (!(ylit0[s] = jnd_alloc((size_t)out->screens[s].m2_px * out->screens[s].m2_px, sizeof *ylit0[s]))) st = JND_ERR_NOMEM;
  if (!st && (!ep || !mp || !ym1 || !ylit)) st = JND_ERR_NOMEM;
  codes ref = {0}, u = {0}, l = {0}, u2 = {0};
  int total = p->views * n, done = 0;
  for (int v = 0; v < p->views && !st; v++) {
    for (int k = 0; k < n && !st; k++) {
      if (!(st = judge_level_codes(r, scene, k, &views[v], 1, k == 0 ? &ref : &u)))
        st = judge_level_codes(r, scene, k, &views[v], 0, &l);
      out->renderings += 2;
      if (st) break;
      /* the lit rendering's luma on M1 (003 §4.2 weighs luminance) */
      size_t P1 = (size_t)S1 * S1;
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < P1; i++)
        ym1[i] = (float)((0.2126 * l.px[i] + 0.7152 * l.px[P1 + i] + 0.0722 * l.px[2 * P1 + i]) / 256.0);
      for (int s = 0; s < nscr && !st; s++) {
        int m2 = out->screens[s].m2_px;
        double norm = (double)scr[s].width_px * scr[s].height_px;
        if ((st = resample_codes(k == 0 ? &ref : &u, &aw[s], m2, &aw[s], m2, &u2))) break;
        double e = ep_sum(&ref, &u2, &aw[s], &aw[s]);
        ep[(size_t)s * n + k] += e / norm;
        if ((st = resample_plane(ym1, S1, S1, &aw[s], m2, &aw[s], m2, k == 0 ? ylit0[s] : ylit))) break;
        if (k > 0) mp[(size_t)s * n + k] += mp_sum(ylit0[s], ylit, m2, m2, scr[s].ppd) / norm;
      }
      progress(p, "renderings", ++done, total);
    }
  }
  codes_free(&ref);
  codes_free(&u);
  codes_free(&l);
  codes_free(&u2);
  free(ym1);
  free(ylit);
  for (int s = 0; s < nscr; s++) {
    axis_free(&aw[s]);
    free(ylit0[s]);
  }
  jnd_renderer_free(r);
  free(views);
  jnd_scene_lod_select(scene, 0);
  if (!st) {
    for (size_t i = 0; i < (size_t)nscr * n; i++)
      if (!isfinite(ep[i]) || !isfinite(mp[i])) st = jnd_fail(JND_ERR_NOMEM, "%s: out of memory", jnd_scene_path(scene));
  }
  if (st) {
    free(ep);
    free(mp);
    goto fail;
  }

  /* steps 7 and 8 */
  double tris[64];
  for (int k = 0; k < n; k++) tris[k] = (double)out->levels[k].triangles;
  for (int s = 0; s < nscr; s++) {
    jnd_poi_screen_result *R = &out->screens[s];
    double d1 = jnd_camera_distance_for_coverage(out->radius, cov, fov);
    double px_per_unit = scr[s].height_px / (2 * d1 * tan(fov * M_PI / 360));
    double y0[64], y1[64];
    R->meshopt_level = R->pixel_level = 0;
    for (int k = 0; k < n; k++) {
      jnd_poi_point *q = &R->curve[k];
      q->e_p = sqrt(ep[(size_t)s * n + k] / p->views);       /* RMS over the views */
      q->m_p = mp[(size_t)s * n + k] / p->views;             /* mean over the views */
      q->error = q->object + q->e_p;                          /* eq. 1 */
      q->error_lit = q->error * q->m_p;                       /* eq. 3 */
      double merr = isfinite(out->levels[k].error_abs) ? out->levels[k].error_abs : out->distance[k].max;
      q->meshopt_px = merr * px_per_unit;
      q->deviation_px = out->distance[k].max * px_per_unit;
      if (q->meshopt_px <= p->meshopt_pixels) R->meshopt_level = k;
      if (q->deviation_px <= p->pixel_error) R->pixel_level = k;
      y0[k] = q->error;
      y1[k] = q->error_lit;
    }
    R->poi_level_unlit = knee_of(tris, y0, n);
    R->poi_level = knee_of(tris, y1, n);
  }
  free(ep);
  free(mp);

  /* step 9 */
  int nmaps = p->textures ? jnd_scene_map_count(scene) : 0;
  if (nmaps > 0) {
    if (!(out->textures = jnd_calloc((size_t)nmaps, sizeof *out->textures))) goto nomem;
    for (int i = 0; i < nmaps && !st; i++) {
      progress(p, "textures", i, nmaps);
      st = texture_curves(scene, i, scr, nscr, p, &out->textures[i]);
      out->ntextures = i + 1;
    }
    progress(p, "textures", nmaps, nmaps);
    if (st) goto fail;
  }
  return JND_OK;
nomem:
  st = jnd_fail(JND_ERR_NOMEM, "%s: out of memory", jnd_scene_path(scene));
fail:
  jnd_poi_result_free(out);
  jnd_scene_lod_select(scene, 0);
  return st;
}
