/* Heatmaps: where a viewer would notice, over a dimmed grey copy of the
 * reference, on a logarithmic scale of JND with a colour bar, so that
 * structure above 1 JND stays visible instead of saturating at the top of a
 * linear 0–1 scale. Small images are magnified by a whole factor (nearest
 * pixel: what the model saw, not a smoothed guess) to a size a person reads.
 *   1. the scale: from min_jnd (0.1 JND: below it nothing is drawn) to
 *      max_jnd, or when that is 0 to the map's 99.9th percentile rounded up
 *      to 1, 2 or 5 × 10^k (at least 2 JND, so 1 JND lies inside the scale)
 *   2. per pixel: a colour of a ramp monotone in lightness (dark violet →
 *      red → orange → pale yellow) at log(JND), blended over the backdrop
 *      with an opacity that grows with it
 *   3. the figure: a title, the reference itself beside the heatmap when
 *      asked, and the colour bar with ticks in JND and the 1 JND (P = 0.5)
 *      line marked */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"

#define LEGEND_W 150
#define TITLE_H 30
#define GAP 10
#define MIN_H 240
#define MAX_SIDE_PX 2048

static const jnd_rgb INK = {0.13f, 0.13f, 0.13f}, PAPER = {1, 1, 1};

void jnd_heatmap_defaults(jnd_heatmap_params *p) {
  memset(p, 0, sizeof *p);
  p->min_jnd = 0.1;
  p->min_side = 256;
}

/* step 2's ramp: five stops rising in lightness */
static jnd_rgb heat_ramp(double t) {
  static const float s[5][3] = {{0.16f, 0.04f, 0.38f}, {0.55f, 0.09f, 0.50f}, {0.90f, 0.22f, 0.22f},
                                {0.99f, 0.58f, 0.07f}, {1.00f, 0.95f, 0.55f}};
  return jnd_ramp5(s, t);
}

/* step 1: the 99.9th percentile from a histogram of log10(JND), 0.01–10^4 */
static double auto_top(const jnd_image *map) {
  enum { BINS = 1200 };
  static const double LO = -2, HI = 4;
  size_t hist[BINS] = {0}, n = (size_t)map->w * map->h, count = 0;
  for (size_t i = 0; i < n; i++) {
    float v = map->data[i];
    if (!(v > 0)) continue;
    double l = log10(v);
    int b = l <= LO ? 0 : l >= HI ? BINS - 1 : (int)((l - LO) / (HI - LO) * BINS);
    hist[b]++;
    count++;
  }
  double top = 0;
  if (count) {
    size_t want = (size_t)ceil(0.999 * (double)count), seen = 0;
    for (int b = 0; b < BINS; b++) {
      seen += hist[b];
      if (seen >= want) {
        top = pow(10, LO + (HI - LO) * (b + 1) / BINS);
        break;
      }
    }
  }
  /* round up to 1, 2 or 5 × 10^k, at least 2 */
  double r = 2;
  if (top > r) {
    double mag = pow(10, floor(log10(top))), f = top / mag;
    r = (f <= 1 + 1e-9 ? 1 : f <= 2 + 1e-9 ? 2 : f <= 5 + 1e-9 ? 5 : 10) * mag;
  }
  return fmin(r, 1e4);
}

jnd_status jnd_heatmap_draw(const jnd_heatmap_params *p, const jnd_image *ref, const jnd_image *map, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (ref->w != map->w || ref->h != map->h)
    return jnd_fail(JND_ERR_ARG, "heatmap: reference %d × %d and map %d × %d differ", ref->w, ref->h, map->w, map->h);
  int w = ref->w, h = ref->h;
  double lo = p->min_jnd > 0 ? p->min_jnd : 0.1;
  double hi = p->max_jnd > 0 ? p->max_jnd : auto_top(map);
  if (!(hi > lo * 1.01)) hi = lo * 10;
  double llo = log10(lo), lhi = log10(hi);
  /* step 2 at the image's own size */
  jnd_image heat;
  jnd_status s = jnd_image_alloc(&heat, w, h, 3);
  if (s != JND_OK) return s;
  size_t n = (size_t)w * h;
  for (size_t i = 0; i < n; i++) {
    double g;
    if (ref->c >= 3)
      g = 0.2126 * jnd_image_plane(ref, 0)[i] + 0.7152 * jnd_image_plane(ref, 1)[i] + 0.0722 * jnd_image_plane(ref, 2)[i];
    else
      g = jnd_image_plane(ref, 0)[i];
    g = 0.15 + 0.45 * jnd_clampd(g, 0, 1);
    double v = map->data[i], a = 0;
    jnd_rgb c = {0, 0, 0};
    if (v >= lo) {
      double t = jnd_clampd((log10(v) - llo) / (lhi - llo), 0, 1);
      c = heat_ramp(t);
      a = 0.35 + 0.55 * t;
    }
    jnd_image_plane(&heat, 0)[i] = (float)(g * (1 - a) + c.r * a);
    jnd_image_plane(&heat, 1)[i] = (float)(g * (1 - a) + c.g * a);
    jnd_image_plane(&heat, 2)[i] = (float)(g * (1 - a) + c.b * a);
  }
  /* step 3: magnify to a readable size, within MAX_SIDE_PX */
  int min_side = p->min_side > 0 ? p->min_side : 256;
  int k = (min_side + (w < h ? w : h) - 1) / (w < h ? w : h);
  int panels = p->beside ? 2 : 1;
  while (k > 1 && (panels * w * k > MAX_SIDE_PX || h * k > MAX_SIDE_PX)) k--;
  if (k < 1) k = 1;
  int top = p->title ? TITLE_H : GAP;
  int img_h = h * k, body_h = img_h > MIN_H ? img_h : MIN_H;
  int W = GAP + panels * (w * k + GAP) + LEGEND_W, H = top + body_h + GAP;
  s = jnd_canvas_new(out, W, H, PAPER);
  if (s != JND_OK) {
    jnd_image_free(&heat);
    return s;
  }
  int x = GAP;
  if (p->beside) {
    jnd_draw_image(out, x, top, ref, k);
    x += w * k + GAP;
  }
  jnd_draw_image(out, x, top, &heat, k);
  jnd_image_free(&heat);
  x += w * k + GAP;
  if (p->title) jnd_draw_text(out, GAP, 21, p->title, 15, INK, JND_ALIGN_LEFT, 0);
  /* the colour bar: ticks at 1, 2, 5 × 10^k on the log scale */
  double ticks[32];
  char text[32][16];
  const char *labels[32];
  int nt = 0;
  for (int d = (int)floor(llo) - 1; d <= (int)ceil(lhi) && nt < 32; d++)
    for (int m = 0; m < 3 && nt < 32; m++) {
      double v = (double[3]){1, 2, 5}[m] * pow(10, d);
      if (v < lo * 0.999 || v > hi * 1.001) continue;
      /* on a long scale only the decades and the ends are labelled */
      if (lhi - llo > 2.5 && m != 0 && fabs(v - hi) > 1e-9 * hi) continue;
      ticks[nt] = log10(v);
      snprintf(text[nt], sizeof text[nt], fabs(v - 1) < 1e-9 ? "1 (P=0.5)" : "%g", v);
      labels[nt] = text[nt];
      nt++;
    }
  int bar_y = top + 22, bar_h = body_h - 56;
  jnd_draw_colour_bar(out, x + 4, bar_y, 18, bar_h, llo, lhi, heat_ramp, ticks, labels, nt, "JND (log)");
  /* 1 JND: a viewer notices with probability 0.5 */
  if (lo < 1 && hi > 1) {
    double y1 = bar_y + (1 - (0 - llo) / (lhi - llo)) * (bar_h - 1) + 0.5;
    jnd_draw_line(out, x, y1, x + 26, y1, 2, INK);
  }
  char note[64];
  snprintf(note, sizeof note, "below %g: not drawn", lo);
  jnd_draw_text(out, x + 4, top + body_h - 14, note, 11, INK, JND_ALIGN_LEFT, 0);
  return JND_OK;
}

jnd_status jnd_heatmap(const jnd_image *ref, const jnd_image *map, double max_jnd, jnd_image *out) {
  jnd_heatmap_params p;
  jnd_heatmap_defaults(&p);
  p.max_jnd = max_jnd;
  return jnd_heatmap_draw(&p, ref, map, out);
}
