/* CIELAB and the CIE ΔE*94 colour difference (Fairchild 2004): 004 §5.1's
 * simple baseline beside the popping rating ("the maximum CIELAB ΔE*94
 * difference value"), and the colour comparisons of 004 §4's flicker
 * heuristic. Not part of the vision model: a colorimetric yardstick.
 *
 * Colours are absolute linear RGB in cd/m² (jnd_display_apply), Rec.709
 * primaries; L*a*b* is taken relative to the display's white, the colour
 * full-scale RGB (1, 1, 1) produces: peak luminance plus the ambient light
 * the screen reflects, with D65 chromaticity. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "vision/vision.h"

enum { LAB_ROWS = 16 }; /* rows converted at a time into a thread's scratch */

/* cube root of t > 0: an exponent-thirding first guess on the float's bits,
 * then three Newton steps (relative error below 1e-6 over the float range);
 * plain arithmetic, so that the loop calling it vectorises */
static inline float cube_root(float t) {
  uint32_t b;
  memcpy(&b, &t, 4);
  b = b / 3u + 709921077u;
  float y;
  memcpy(&y, &b, 4);
  for (int k = 0; k < 3; k++) y = (2.0f * y + t / (y * y)) * (1.0f / 3.0f);
  return y;
}

/* CIE 1976 f(t): the cube root above (6/29)^3, the linear segment below */
static inline float lab_f(float t) {
  const float e = 216.0f / 24389.0f; /* (6/29)^3 */
  float c = cube_root(t > e ? t : e), l = t * (841.0f / 108.0f) + 4.0f / 29.0f;
  return t > e ? c : l;
}

/* ΔE*94 in float, for the vectorised map loop and jnd_delta_e94 alike */
static inline float de94(float l1, float a1, float b1, float l2, float a2, float b2) {
  float dl = l1 - l2, da = a1 - a2, db = b1 - b2;
  float c1 = sqrtf(a1 * a1 + b1 * b1), c2 = sqrtf(a2 * a2 + b2 * b2);
  float dc = c1 - c2;
  float dh2 = jnd_maxf(da * da + db * db - dc * dc, 0.0f); /* ΔH², may round below 0 */
  float sc = 1.0f + 0.045f * c1, sh = 1.0f + 0.015f * c1;
  return sqrtf(dl * dl + (dc / sc) * (dc / sc) + dh2 / (sh * sh));
}

/* the display white in XYZ, cd/m², through the same RGB → XYZ matrix as images */
static void white_xyz(const jnd_display *d, float w[3]) {
  float px[3];
  jnd_image one = {1, 1, 3, px};
  float yw = (float)(d->peak_cdm2 + d->reflectivity * d->ambient_lux / M_PI);
  px[0] = px[1] = px[2] = yw;
  jnd_rgb_to_xyz(&one);
  for (int c = 0; c < 3; c++) w[c] = px[c];
}

/* XYZ planes of n pixels → L*, a*, b* in place */
JND_HOT static void xyz_to_lab(float *x, float *y, float *z, size_t n, const float w[3]) {
  const float ix = 1.0f / w[0], iy = 1.0f / w[1], iz = 1.0f / w[2];
#pragma omp simd
  for (size_t i = 0; i < n; i++) {
    float fx = lab_f(jnd_maxf(x[i], 0.0f) * ix), fy = lab_f(jnd_maxf(y[i], 0.0f) * iy),
          fz = lab_f(jnd_maxf(z[i], 0.0f) * iz);
    x[i] = 116.0f * fy - 16.0f;
    y[i] = 500.0f * (fx - fy);
    z[i] = 200.0f * (fy - fz);
  }
}

/* rows [y0, y0 + n) of a linear RGB image as L*a*b* into buf (3 planes of n·w) */
static void rows_to_lab(const jnd_image *rgb, int y0, int n, const float w[3], float *buf) {
  const size_t span = (size_t)n * rgb->w;
  for (int c = 0; c < 3; c++) memcpy(buf + c * span, jnd_image_plane(rgb, c) + (size_t)y0 * rgb->w, span * sizeof(float));
  jnd_image part = {rgb->w, n, 3, buf};
  jnd_rgb_to_xyz(&part); /* inside the caller's parallel loop this runs on its thread */
  xyz_to_lab(buf, buf + span, buf + 2 * span, span, w);
}

jnd_status jnd_lab_from_linear(const jnd_display *d, jnd_image *img) {
  if (img->c != 3) return jnd_fail(JND_ERR_ARG, "CIELAB: images need 3 channels, not %d", img->c);
  if (!(d->peak_cdm2 > 0)) return jnd_fail(JND_ERR_ARG, "CIELAB: the display's peak must be positive");
  float w[3];
  white_xyz(d, w);
  jnd_rgb_to_xyz(img);
  size_t n = (size_t)img->w * img->h;
  const ptrdiff_t nb = (ptrdiff_t)((n + 4095) / 4096);
#pragma omp parallel for schedule(static)
  for (ptrdiff_t b = 0; b < nb; b++) {
    size_t i0 = (size_t)b * 4096, m = n - i0 < 4096 ? n - i0 : 4096;
    xyz_to_lab(jnd_image_plane(img, 0) + i0, jnd_image_plane(img, 1) + i0, jnd_image_plane(img, 2) + i0, m, w);
  }
  return JND_OK;
}

/* CIE ΔE*94, graphic-arts weights (kL = kC = kH = 1, K1 = 0.045, K2 = 0.015),
 * with the reference's chroma in S_C and S_H (Fairchild 2004) */
double jnd_delta_e94(const float ref[3], const float test[3]) {
  return de94(ref[0], ref[1], ref[2], test[0], test[1], test[2]);
}

/* ΔE*94 of n pixels of two L*a*b* blocks (planes m apart), and their maximum */
JND_HOT static float de94_span(const float *la, const float *lb, size_t m, float *o) {
  float mx = 0;
#pragma omp simd reduction(max : mx)
  for (size_t i = 0; i < m; i++) {
    float e = de94(la[i], la[m + i], la[2 * m + i], lb[i], lb[m + i], lb[2 * m + i]);
    o[i] = e;
    mx = jnd_maxf(mx, e);
  }
  return mx;
}

jnd_status jnd_delta_e94_map_where(const jnd_display *d, const jnd_image *ref, const jnd_image *test,
                                   const uint8_t *where, jnd_image *out, double *max_out) {
  memset(out, 0, sizeof *out);
  if (ref->c != 3 || test->c != 3) return jnd_fail(JND_ERR_ARG, "ΔE*94: images need 3 channels");
  if (ref->w != test->w || ref->h != test->h)
    return jnd_fail(JND_ERR_ARG, "ΔE*94: image sizes differ: %d × %d vs %d × %d", ref->w, ref->h, test->w, test->h);
  if (!(d->peak_cdm2 > 0)) return jnd_fail(JND_ERR_ARG, "ΔE*94: the display's peak must be positive");
  jnd_status s = jnd_image_alloc(out, ref->w, ref->h, 1);
  if (s != JND_OK) return s;
  float w[3];
  white_xyz(d, w);
  const int nblocks = (ref->h + LAB_ROWS - 1) / LAB_ROWS;
  float *bmax = jnd_calloc((size_t)nblocks, sizeof *bmax);
  int fail = 0;
  if (!bmax) {
    jnd_image_free(out);
    return JND_ERR_NOMEM;
  }
#pragma omp parallel
  {
    const size_t span = (size_t)LAB_ROWS * ref->w;
    float *a = NULL;
#pragma omp for schedule(static)
    for (int b = 0; b < nblocks; b++) {
      int y0 = b * LAB_ROWS, n = ref->h - y0 < LAB_ROWS ? ref->h - y0 : LAB_ROWS;
      size_t m = (size_t)n * ref->w, i0 = (size_t)y0 * ref->w;
      /* a block where the colours are the same everywhere has ΔE 0 (the
       * output is zeroed): skipping it changes no value */
      int any = !where;
      for (size_t i = 0; i < m && !any; i++) any = where[i0 + i] != 0;
      if (!any) continue;
      if (!a && !(a = malloc(sizeof(float) * 6 * span))) {
#pragma omp atomic write
        fail = 1;
      }
      if (!a) continue;
      float *la = a, *lb = a + 3 * span;
      rows_to_lab(ref, y0, n, w, la);
      rows_to_lab(test, y0, n, w, lb);
      bmax[b] = de94_span(la, lb, m, out->data + i0);
    }
    free(a);
  }
  float mx = 0;
  for (int b = 0; b < nblocks; b++) mx = bmax[b] > mx ? bmax[b] : mx;
  free(bmax);
  if (fail) {
    jnd_image_free(out);
    return jnd_fail(JND_ERR_NOMEM, "ΔE*94: out of memory");
  }
  if (max_out) *max_out = mx;
  return JND_OK;
}

jnd_status jnd_delta_e94_map(const jnd_display *d, const jnd_image *ref, const jnd_image *test, jnd_image *out,
                             double *max_out) {
  return jnd_delta_e94_map_where(d, ref, test, NULL, out, max_out);
}

/* ---- CIEDE2000 and single colours ---- */

void jnd_lab_of_xyz(const jnd_display *d, const double xyz[3], double lab[3]) {
  float w[3];
  white_xyz(d, w);
  double f[3];
  for (int c = 0; c < 3; c++) {
    const double t = fmax(xyz[c], 0.0) / w[c], e = 216.0 / 24389.0; /* (6/29)^3 */
    f[c] = t > e ? cbrt(t) : t * (841.0 / 108.0) + 4.0 / 29.0;
  }
  lab[0] = 116.0 * f[1] - 16.0;
  lab[1] = 500.0 * (f[0] - f[1]);
  lab[2] = 200.0 * (f[1] - f[2]);
}

/* hue angle in degrees, [0, 360); 0 for a neutral colour (CIE 142-2001) */
static double hue_deg(double b, double a) {
  if (a == 0 && b == 0) return 0;
  double h = atan2(b, a) * 180.0 / M_PI;
  return h < 0 ? h + 360.0 : h;
}

/* Sharma, Wu & Dalal (2005), eqs. 1–22, with their notes on the hue
 * difference and mean where a chroma is zero */
double jnd_delta_e00(const double lab1[3], const double lab2[3]) {
  const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2], L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
  const double rad = M_PI / 180.0;
  const double cbar = 0.5 * (hypot(a1, b1) + hypot(a2, b2));
  const double c7 = pow(cbar, 7.0), g = 0.5 * (1.0 - sqrt(c7 / (c7 + 6103515625.0))); /* 25^7 */
  const double ap1 = (1.0 + g) * a1, ap2 = (1.0 + g) * a2;
  const double cp1 = hypot(ap1, b1), cp2 = hypot(ap2, b2);
  const double hp1 = hue_deg(b1, ap1), hp2 = hue_deg(b2, ap2);
  const double dL = L2 - L1, dC = cp2 - cp1;
  double dh = 0;
  if (cp1 * cp2 != 0) {
    dh = hp2 - hp1;
    if (dh > 180) dh -= 360;
    else if (dh < -180) dh += 360;
  }
  const double dH = 2.0 * sqrt(cp1 * cp2) * sin(0.5 * dh * rad);
  const double Lbar = 0.5 * (L1 + L2), Cbar = 0.5 * (cp1 + cp2);
  double hbar = hp1 + hp2;
  if (cp1 * cp2 != 0) {
    if (fabs(hp1 - hp2) <= 180) hbar *= 0.5;
    else hbar = hbar < 360 ? 0.5 * (hbar + 360) : 0.5 * (hbar - 360);
  }
  const double T = 1.0 - 0.17 * cos((hbar - 30) * rad) + 0.24 * cos(2 * hbar * rad) +
                   0.32 * cos((3 * hbar + 6) * rad) - 0.20 * cos((4 * hbar - 63) * rad);
  const double dtheta = 30.0 * exp(-pow((hbar - 275) / 25, 2));
  const double C7 = pow(Cbar, 7.0), RC = 2.0 * sqrt(C7 / (C7 + 6103515625.0));
  const double l50 = (Lbar - 50) * (Lbar - 50);
  const double SL = 1.0 + 0.015 * l50 / sqrt(20 + l50), SC = 1.0 + 0.045 * Cbar, SH = 1.0 + 0.015 * Cbar * T;
  const double RT = -sin(2 * dtheta * rad) * RC;
  const double tl = dL / SL, tc = dC / SC, th = dH / SH;
  return sqrt(tl * tl + tc * tc + th * th + RT * tc * th);
}
