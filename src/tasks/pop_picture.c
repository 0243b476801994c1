/* The picture of 004 Fig. 4: "an in-context visualization of the popping
 * regions colored according to their rating values" — the actual frame in
 * dimmed grey, each region's pixels in the colour of its rating R, and a
 * legend column with the counts, the scores and a colour bar of R marked
 * where 004 §3.2 reads it (R < 1 rarely visible, R > 3 easily). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "io/draw.h"
#include "tasks/tasks.h"

#define LEGEND_W 210
#define MIN_H 370 /* the legend column: text lines, then the colour bar */
#define R_MIN 0.0 /* the colour scale's range of R */
#define R_MAX 4.0
#define SMALL_REGION_PX 12 /* a region at most this wide and tall is ringed */
#define RING_GAP 4         /* pixels between a region's box and its ring */

static const jnd_rgb INK = {0.13f, 0.13f, 0.13f};

/* a row of the frame in dimmed grey: its luminance back through the display
 * model to a signal */
JND_HOT static void grey_row(const float *r, const float *g, const float *b, float lo, float inv_range, float *out,
                             int w) {
#pragma omp simd
  for (int x = 0; x < w; x++) {
    float lum = 0.2126f * r[x] + 0.7152f * g[x] + 0.0722f * b[x];
    out[x] = 0.12f + 0.5f * jnd_srgb_encode((lum - lo) * inv_range);
  }
}

static jnd_rgb rating_colour(double r) { return jnd_colour_scale((r - R_MIN) / (R_MAX - R_MIN)); }

jnd_status pop_backdrop(const jnd_display *d, const jnd_image *frame, jnd_image *grey) {
  jnd_status s = jnd_image_alloc(grey, frame->w, frame->h, 1);
  if (s != JND_OK) return s;
  /* the frame as the display shows it, in grey: luminance back through the
   * display model to a signal, dimmed so that the regions stand out */
  const float lo = (float)(d->black_cdm2 + d->reflectivity * d->ambient_lux / M_PI);
  const float inv = (float)(1.0 / (d->peak_cdm2 - d->black_cdm2));
  const float *f0 = jnd_image_plane(frame, 0), *f1 = jnd_image_plane(frame, 1), *f2 = jnd_image_plane(frame, 2);
  const int w = frame->w, h = frame->h;
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++) {
    const size_t i0 = (size_t)y * w;
    grey_row(f0 + i0, f1 + i0, f2 + i0, lo, inv, grey->data + i0, w);
  }
  return JND_OK;
}

jnd_status pop_picture(const jnd_image *grey, const jnd_pop_result *r, jnd_image *out) {
  memset(out, 0, sizeof *out);
  const int w = grey->w, h = grey->h, H = h > MIN_H ? h : MIN_H;
  jnd_status s = jnd_canvas_new(out, w + LEGEND_W, H, (jnd_rgb){0.97f, 0.97f, 0.97f});
  if (s != JND_OK) return s;
  jnd_rgb col[64];
  const int ncol = r->nregions < 64 ? r->nregions : 64;
  for (int k = 0; k < ncol; k++) col[k] = rating_colour(r->regions[k].rating);
  const int W = out->w;
  float *o0 = jnd_image_plane(out, 0), *o1 = jnd_image_plane(out, 1), *o2 = jnd_image_plane(out, 2);
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++) {
    const size_t i0 = (size_t)y * w, o0r = (size_t)y * W;
    float *g0 = o0 + o0r, *g1 = o1 + o0r, *g2 = o2 + o0r;
    memcpy(g0, grey->data + i0, sizeof(float) * (size_t)w);
    memcpy(g1, g0, sizeof(float) * (size_t)w);
    memcpy(g2, g0, sizeof(float) * (size_t)w);
    if (!r->labels) continue;
    const int32_t *lab = r->labels + i0;
    for (int x = 0; x < w; x++) {
      int k = lab[x];
      if (k < 0) continue;
      jnd_rgb c = k < ncol ? col[k] : rating_colour(r->regions[k].rating);
      const float a = 0.85f, g = g0[x];
      g0[x] = g * (1 - a) + c.r * a;
      g1[x] = g * (1 - a) + c.g * a;
      g2[x] = g * (1 - a) + c.b * a;
    }
  }
  /* a region a few pixels across is lost at the frame's own size (a
   * controller's 256² rendering: 8 regions, 0.1 % of the object): ring it,
   * in its colour, a few pixels outside its box (issue 25) */
  int ringed = 0;
  for (int k = 0; k < r->nregions; k++) {
    const int *b = r->regions[k].bbox;
    if (b[2] - b[0] + 1 > SMALL_REGION_PX || b[3] - b[1] + 1 > SMALL_REGION_PX) continue;
    jnd_draw_frame(out, fmax(b[0] - RING_GAP, 0), fmax(b[1] - RING_GAP, 0), fmin(b[2] + 1 + RING_GAP, w - 1),
                   fmin(b[3] + 1 + RING_GAP, h - 1), 1.5, rating_colour(r->regions[k].rating));
    ringed++;
  }
  /* the legend */
  const double x0 = w + 14;
  double y = 26;
  char line[128];
  jnd_draw_text(out, x0, y, "popping regions", 15, INK, JND_ALIGN_LEFT, 0);
  y += 24;
  snprintf(line, sizeof line, "regions: %d", r->nregions);
  jnd_draw_text(out, x0, y, line, 13, INK, JND_ALIGN_LEFT, 0);
  y += 19;
  if (ringed) {
    snprintf(line, sizeof line, "  (%d small one%s ringed)", ringed, ringed == 1 ? "" : "s");
    jnd_draw_text(out, x0, y, line, 11, INK, JND_ALIGN_LEFT, 0);
    y += 15;
  }
  if (r->nregions)
    snprintf(line, sizeof line, "max R: %.2f", r->max_rating);
  else
    snprintf(line, sizeof line, "max R: none");
  jnd_draw_text(out, x0, y, line, 13, INK, JND_ALIGN_LEFT, 0);
  y += 19;
  snprintf(line, sizeof line, "coverage: %s (%.1f%%)", jnd_pop_coverage_name(r->coverage_score), 100 * r->coverage);
  jnd_draw_text(out, x0, y, line, 13, INK, JND_ALIGN_LEFT, 0);
  y += 19;
  /* the rating is the best regions' mean R (004 §5.2), not max R: say which,
   * or "rating: high" under "max R: 4.28" reads as a contradiction */
  snprintf(line, sizeof line, "rating: %s", jnd_pop_rating_name(r->rating_score));
  jnd_draw_text(out, x0, y, line, 13, INK, JND_ALIGN_LEFT, 0);
  y += 17;
  if (r->nregions) {
    snprintf(line, sizeof line, "  (best regions' mean R %.2f)", r->rating_top);
    jnd_draw_text(out, x0, y, line, 11, INK, JND_ALIGN_LEFT, 0);
    y += 17;
  }
  y += 2;
  snprintf(line, sizeof line, "detection score: %d of 5", r->detection_score);
  jnd_draw_text(out, x0, y, line, 13, INK, JND_ALIGN_LEFT, 0);
  y += 19;
  snprintf(line, sizeof line, "max \u0394E*94: %.2f", r->max_delta_e94);
  jnd_draw_text(out, x0, y, line, 13, INK, JND_ALIGN_LEFT, 0);
  y += 40;
  static const double ticks[] = {0, 1, 2, 3, 4};
  static const char *const labels[] = {"0", "1  rarely visible", "2", "3  easily visible", "4+"};
  jnd_draw_colour_bar(out, (int)x0, (int)y, 18, 125, R_MIN, R_MAX, NULL, ticks, labels, 5, "rating R");
  return JND_OK;
}
