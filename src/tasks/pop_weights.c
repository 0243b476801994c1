/* The weights of the popping predictor (004 §4): where the difference
 * between the actual frame and its prediction is less likely to be seen,
 * the difference map is scaled down (004 §3.2).
 *
 *   disocclusion  each pixel's surface point is looked up in the previous
 *                 frame's depth map at its previous position (pixel minus
 *                 displacement) with percentage-closer filtering: the
 *                 bilinear weights of the four nearest depth samples, each
 *                 counting when the point is not behind it. The fraction is
 *                 the previous-frame visibility; of the two levels' values
 *                 the larger is kept ("being conservative", 004 §4).
 *   flicker       the expected level's pixels shaded with the previous
 *                 frame's setup are compared (ΔE*94) with the previous frame
 *                 sampled at the previous position, over the samples whose
 *                 depth matches ("taking depth discontinuities into
 *                 account"). Where that difference is about as large as the
 *                 two levels' difference, flicker is assumed and the pixel
 *                 is weighted down, unless its displacement is large.
 *
 * 004 gives no filter size, tolerance or thresholds; docs/pop.md has ours. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"

/* the four depth samples around a pixel's previous position: index (−1 off
 * the image) and bilinear weight. Sample (i, j) sits at pixel centre
 * (i + 0.5, j + 0.5); the previous position of pixel (x, y)'s centre is
 * (x + 0.5 − dx, y + 0.5 − dy). */
typedef struct {
  ptrdiff_t idx[4];
  float wt[4];
} taps;

static void prev_taps(const jnd_image *disp, int x, int y, int w, int h, taps *t) {
  const ptrdiff_t i = (ptrdiff_t)y * w + x;
  const float dx = disp ? jnd_image_plane(disp, 0)[i] : 0.0f, dy = disp ? jnd_image_plane(disp, 1)[i] : 0.0f;
  /* far outside stays far outside without overflowing an int */
  double qx = jnd_clampd((double)x - dx, -4.0, w + 4.0), qy = jnd_clampd((double)y - dy, -4.0, h + 4.0);
  double fx = floor(qx), fy = floor(qy);
  int i0 = (int)fx, j0 = (int)fy;
  float tx = (float)(qx - fx), ty = (float)(qy - fy);
  for (int k = 0; k < 4; k++) {
    int ii = i0 + (k & 1), j = j0 + (k >> 1);
    t->wt[k] = ((k & 1) ? tx : 1 - tx) * ((k >> 1) ? ty : 1 - ty);
    t->idx[k] = ii >= 0 && ii < w && j >= 0 && j < h ? (ptrdiff_t)j * w + ii : -1;
  }
}

/* is a point at depth z not behind the previous frame's depth d? 0 is
 * "nothing there", infinitely far: an empty pixel was seen only where the
 * previous frame was empty too */
static inline int seen(float z, float d, float tol) {
  if (!(z > 0)) return !(d > 0);
  if (!(d > 0)) return 1;
  return z <= d * (1.0f + tol);
}

/* the previous-frame samples that show pixel (x, y)'s surface: the ones on
 * the image and, where depths are given, not in front of the point; t keeps
 * only those (idx −1 for the others) */
static void matching_taps(const jnd_image *disp, const jnd_image *depth, const jnd_image *prev_depth, float tol,
                          int x, int y, int w, int h, taps *t) {
  prev_taps(disp, x, y, w, h, t);
  if (!depth) return;
  const float z = depth->data[(ptrdiff_t)y * w + x];
  for (int k = 0; k < 4; k++)
    if (t->idx[k] >= 0 && !seen(z, prev_depth->data[t->idx[k]], tol)) t->idx[k] = -1;
}

jnd_status pop_visibility(const jnd_image *depth, const jnd_image *prev_depth, const jnd_image *disp, double tol,
                          float *vis) {
  const int w = depth->w, h = depth->h;
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      taps t;
      matching_taps(disp, depth, prev_depth, (float)tol, x, y, w, h, &t);
      float v = 0;
      for (int k = 0; k < 4; k++) v += t.idx[k] >= 0 ? t.wt[k] : 0.0f;
      vis[(ptrdiff_t)y * w + x] = v > 1.0f ? 1.0f : v;
    }
  return JND_OK;
}

jnd_status pop_flicker_weight(const jnd_display *disp_model, const jnd_image *prev_shading,
                              const jnd_image *prev_color, const jnd_image *disp, const jnd_image *depth,
                              const jnd_image *prev_depth, const jnd_image *de_levels, const jnd_pop_params *p,
                              float *wout) {
  const int w = prev_color->w, h = prev_color->h;
  const size_t n = (size_t)w * h;
  jnd_image sampled = {0}, de_prev = {0};
  uint8_t *valid = jnd_alloc(n, 1);
  jnd_status s = valid ? jnd_image_alloc(&sampled, w, h, 3) : JND_ERR_NOMEM;
  if (s != JND_OK) {
    free(valid);
    return s;
  }
  /* the previous frame at each pixel's previous position, from the samples
   * that show the same surface (where depths are given) */
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      const ptrdiff_t i = (ptrdiff_t)y * w + x;
      taps t;
      matching_taps(disp, depth, prev_depth, (float)p->depth_tolerance, x, y, w, h, &t);
      float acc[3] = {0, 0, 0}, sw = 0;
      for (int k = 0; k < 4; k++) {
        if (t.idx[k] < 0 || !(t.wt[k] > 0)) continue;
        for (int c = 0; c < 3; c++) acc[c] += t.wt[k] * jnd_image_plane(prev_color, c)[t.idx[k]];
        sw += t.wt[k];
      }
      valid[i] = sw > 1e-4f;
      for (int c = 0; c < 3; c++)
        jnd_image_plane(&sampled, c)[i] = valid[i] ? acc[c] / sw : jnd_image_plane(prev_shading, c)[i];
    }
  s = jnd_delta_e94_map(disp_model, prev_shading, &sampled, &de_prev, NULL);
  jnd_image_free(&sampled);
  if (s != JND_OK) {
    free(valid);
    return s;
  }
  const double lo = p->flicker_ratio_lo, hi = p->flicker_ratio_hi;
  const double mlo = p->flicker_motion_lo_px, mhi = p->flicker_motion_hi_px;
  const ptrdiff_t nn = (ptrdiff_t)n;
#pragma omp parallel for schedule(static)
  for (ptrdiff_t i = 0; i < nn; i++) {
    double f = de_prev.data[i], dl = de_levels->data[i];
    /* how flicker-like: the temporal difference against the levels' difference */
    double a;
    if (!valid[i] || !(f > 0))
      a = 0;
    else if (!(dl > 0))
      a = 1;
    else
      a = hi > lo ? jnd_clampd((f / dl - lo) / (hi - lo), 0, 1) : (f / dl >= hi);
    /* how far the heuristic is trusted: not where the displacement is large */
    double m = disp ? hypot(jnd_image_plane(disp, 0)[i], jnd_image_plane(disp, 1)[i]) : 0;
    double b = mhi > mlo ? jnd_clampd((mhi - m) / (mhi - mlo), 0, 1) : (m < mhi);
    wout[i] = (float)(1.0 - a * b);
  }
  jnd_image_free(&de_prev);
  free(valid);
  return JND_OK;
}
