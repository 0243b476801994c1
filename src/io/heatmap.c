/* Heatmaps: where a viewer would notice, over a dimmed grey copy of the
 * reference, with a legend strip. Colours run from transparent (0 JND)
 * through blue, cyan, green and yellow to red at the top of the scale
 * (1 JND by default: a 50% chance of detection). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <stb_easy_font.h>

#include "core/core.h"

#define LEGEND_H 30

static void ramp(double t, float rgb[3]) {
  static const float stops[5][3] = {{0.10f, 0.20f, 0.90f}, {0.00f, 0.75f, 0.95f}, {0.10f, 0.85f, 0.20f},
                                    {1.00f, 0.90f, 0.00f}, {0.95f, 0.05f, 0.05f}};
  t = jnd_clampd(t, 0, 1) * 4.0;
  int i = (int)t;
  if (i >= 4) {
    memcpy(rgb, stops[4], sizeof(float) * 3);
    return;
  }
  float f = (float)(t - i);
  for (int c = 0; c < 3; c++) rgb[c] = stops[i][c] + f * (stops[i + 1][c] - stops[i][c]);
}

/* draws text with stb_easy_font's quads, scale 1, colour v */
static void draw_text(jnd_image *img, int x0, int y0, const char *text, float v) {
  char buf[16384];
  char t[128];
  snprintf(t, sizeof t, "%s", text);
  int quads = stb_easy_font_print((float)x0, (float)y0, t, NULL, buf, sizeof buf);
  for (int q = 0; q < quads; q++) {
    const float *v0 = (const float *)(buf + (size_t)q * 64);
    const float *v2 = (const float *)(buf + (size_t)q * 64 + 32);
    int xa = (int)v0[0], ya = (int)v0[1], xb = (int)v2[0], yb = (int)v2[1];
    for (int y = ya; y < yb; y++)
      for (int x = xa; x < xb; x++)
        if (x >= 0 && y >= 0 && x < img->w && y < img->h)
          for (int c = 0; c < 3; c++) jnd_image_plane(img, c)[(size_t)y * img->w + x] = v;
  }
}

jnd_status jnd_heatmap(const jnd_image *ref, const jnd_image *map, double max_jnd, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (ref->w != map->w || ref->h != map->h)
    return jnd_fail(JND_ERR_ARG, "heatmap: reference %d × %d and map %d × %d differ", ref->w, ref->h, map->w, map->h);
  if (!(max_jnd > 0)) max_jnd = 1.0;
  int w = ref->w, h = ref->h, legend = w >= 160 ? LEGEND_H : 0;
  jnd_status s = jnd_image_alloc(out, w, h + legend, 3);
  if (s != JND_OK) return s;
  size_t n = (size_t)w * h;
  for (size_t i = 0; i < n; i++) {
    /* dimmed grey of the reference (its sRGB signal's luma) */
    double g;
    if (ref->c >= 3)
      g = 0.2126 * jnd_image_plane(ref, 0)[i] + 0.7152 * jnd_image_plane(ref, 1)[i] + 0.0722 * jnd_image_plane(ref, 2)[i];
    else
      g = jnd_image_plane(ref, 0)[i];
    g = 0.15 + 0.45 * jnd_clampd(g, 0, 1);
    double t = map->data[i] / max_jnd;
    float col[3];
    ramp(t, col);
    double a = t <= 0 ? 0 : fmin(0.9, 0.25 + 0.65 * sqrt(fmin(t, 1.0)));
    if (map->data[i] < 0.02 * max_jnd) a = 0; /* invisible differences leave the picture alone */
    for (int c = 0; c < 3; c++) jnd_image_plane(out, c)[i] = (float)(g * (1 - a) + col[c] * a);
  }
  if (legend) {
    int bx0 = 10, bx1 = w - 110, by0 = h + 4, by1 = h + 14;
    for (int y = h; y < h + legend; y++)
      for (int x = 0; x < w; x++)
        for (int c = 0; c < 3; c++) jnd_image_plane(out, c)[(size_t)y * w + x] = 0.08f;
    for (int x = bx0; x < bx1; x++) {
      float col[3];
      ramp((double)(x - bx0) / (bx1 - bx0 - 1), col);
      for (int y = by0; y < by1; y++)
        for (int c = 0; c < 3; c++) jnd_image_plane(out, c)[(size_t)y * w + x] = col[c];
    }
    char lab[64];
    draw_text(out, bx0, h + 17, "0", 0.9f);
    snprintf(lab, sizeof lab, "%.2g", max_jnd / 2);
    draw_text(out, (bx0 + bx1) / 2 - 6, h + 17, lab, 0.9f);
    snprintf(lab, sizeof lab, ">=%.2g", max_jnd);
    draw_text(out, bx1 - 20, h + 17, lab, 0.9f);
    draw_text(out, bx1 + 8, h + 4, "JND", 0.9f);
    draw_text(out, bx1 + 8, h + 16, "1 JND: P=0.5", 0.7f);
  }
  return JND_OK;
}
