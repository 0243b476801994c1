/* Plots from the canvas primitives of draw.c: line plots on labelled axes,
 * colour bars and labelled grids (see draw.h). Axis ranges widen to round
 * ticks (1, 2 or 5 × 10^k on linear axes, decades on logarithmic ones) so
 * that a reader can read values off the picture. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"

static const jnd_rgb INK = {0.13f, 0.13f, 0.13f}, GRID = {0.88f, 0.88f, 0.88f}, WHITE = {1, 1, 1},
                     NODATA = {0.75f, 0.75f, 0.75f};
#define TITLE_PX 18
#define LABEL_PX 15
#define TICK_PX 13

#define MAX_TICKS 40

/* a round step near range / target: 1, 2 or 5 × 10^k */
static double nice_step(double range, int target) {
  double raw = range / target, mag = pow(10, floor(log10(raw))), f = raw / mag;
  return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
}

/* ticks of an axis over [lo, hi]; log axes in decades (with 2 and 5 where
 * the range is short) */
static int axis_ticks(double lo, double hi, int log_axis, double *t) {
  int n = 0;
  if (log_axis) {
    int d0 = (int)floor(log10(lo) + 1e-9), d1 = (int)ceil(log10(hi) - 1e-9);
    int fine = d1 - d0 <= 2;
    for (int d = d0; d <= d1 && n < MAX_TICKS - 3; d++) {
      double m[3] = {1, 2, 5};
      for (int k = 0; k < (fine ? 3 : 1); k++) {
        double v = m[k] * pow(10, d);
        if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t[n++] = v;
      }
    }
    return n;
  }
  double step = nice_step(hi - lo, 5);
  for (double k = ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step && n < MAX_TICKS; k++) {
    double v = k * step;
    t[n++] = fabs(v) < 1e-12 * step ? 0 : v;
  }
  return n;
}

/* widens [lo, hi] to round values; a degenerate range gets a width */
static void axis_range(double *lo, double *hi, int log_axis) {
  if (!(*hi > *lo)) {
    if (log_axis) {
      *lo /= 2;
      *hi *= 2;
    } else {
      double d = *lo == 0 ? 1 : fabs(*lo) * 0.1;
      *lo -= d;
      *hi += d;
    }
  }
  if (log_axis) {
    *lo = pow(10, floor(log10(*lo) + 1e-9));
    *hi = pow(10, ceil(log10(*hi) - 1e-9));
  } else {
    double step = nice_step(*hi - *lo, 5);
    *lo = floor(*lo / step + 1e-9) * step;
    *hi = ceil(*hi / step - 1e-9) * step;
  }
}

static void tick_label(double v, char *buf, size_t n) {
  snprintf(buf, n, "%.6g", v);
}

typedef struct {
  double x0, y0, x1, y1; /* plot area, pixels */
  double lo[2], hi[2];
  int log[2];
} frame;

static double map_axis(const frame *f, int axis, double v) {
  double a = f->lo[axis], b = f->hi[axis];
  double t = f->log[axis] ? (log10(v) - log10(a)) / (log10(b) - log10(a)) : (v - a) / (b - a);
  return axis == 0 ? f->x0 + t * (f->x1 - f->x0) : f->y1 - t * (f->y1 - f->y0);
}

jnd_status jnd_plot_lines(const jnd_plot_axes *ax, const jnd_plot_series *series, int nseries, jnd_image *out) {
  memset(out, 0, sizeof *out);
  int W = ax->width > 0 ? ax->width : 800, H = ax->height > 0 ? ax->height : 500;
  if (W < 200 || H < 150 || W > 8192 || H > 8192) return jnd_fail(JND_ERR_ARG, "plot: size %d × %d is outside 200..8192", W, H);
  frame f;
  f.log[0] = ax->log_x;
  f.log[1] = ax->log_y;
  double lim[2][2] = {{ax->xmin, ax->xmax}, {ax->ymin, ax->ymax}};
  for (int a = 0; a < 2; a++) {
    double lo = INFINITY, hi = -INFINITY;
    for (int s = 0; s < nseries; s++)
      for (int i = 0; i < series[s].n; i++) {
        double v = a == 0 ? series[s].x[i] : series[s].y[i];
        if (!isfinite(v) || (f.log[a] && v <= 0)) continue;
        lo = fmin(lo, v);
        hi = fmax(hi, v);
      }
    if (a == 0)
      for (int m = 0; m < ax->nmarks; m++)
        if (isfinite(ax->marks[m].x) && (!f.log[0] || ax->marks[m].x > 0)) {
          lo = fmin(lo, ax->marks[m].x);
          hi = fmax(hi, ax->marks[m].x);
        }
    if (!isfinite(lo)) {
      lo = f.log[a] ? 1 : 0;
      hi = f.log[a] ? 10 : 1;
    }
    int fixed_lo = isfinite(lim[a][0]) && (!f.log[a] || lim[a][0] > 0), fixed_hi = isfinite(lim[a][1]) && (!f.log[a] || lim[a][1] > 0);
    if (fixed_lo) lo = lim[a][0];
    if (fixed_hi) hi = lim[a][1];
    double l = lo, h = hi;
    axis_range(&l, &h, f.log[a]);
    f.lo[a] = fixed_lo ? lo : l;
    f.hi[a] = fixed_hi ? hi : h;
    if (!(f.hi[a] > f.lo[a])) f.hi[a] = f.lo[a] + 1;
  }
  f.x0 = 84;
  f.x1 = W - 24;
  f.y0 = ax->title ? 44 : 20;
  f.y1 = H - 62;
  jnd_status s = jnd_canvas_new(out, W, H, WHITE);
  if (s != JND_OK) return s;

  /* grid and ticks */
  double t[MAX_TICKS];
  char buf[64];
  for (int a = 0; a < 2; a++) {
    int n = axis_ticks(f.lo[a], f.hi[a], f.log[a], t);
    for (int i = 0; i < n; i++) {
      double p = map_axis(&f, a, t[i]);
      tick_label(t[i], buf, sizeof buf);
      if (a == 0) {
        jnd_draw_line(out, p, f.y0, p, f.y1, 1, GRID);
        jnd_draw_line(out, p, f.y1, p, f.y1 + 5, 1, INK);
        jnd_draw_text(out, p, f.y1 + 20, buf, TICK_PX, INK, JND_ALIGN_CENTRE, 0);
      } else {
        jnd_draw_line(out, f.x0, p, f.x1, p, 1, GRID);
        jnd_draw_line(out, f.x0 - 5, p, f.x0, p, 1, INK);
        jnd_draw_text(out, f.x0 - 8, p + 0.35 * TICK_PX, buf, TICK_PX, INK, JND_ALIGN_RIGHT, 0);
      }
    }
  }
  jnd_draw_frame(out, f.x0, f.y0, f.x1 + 1, f.y1 + 1, 1, INK);
  if (ax->title) jnd_draw_text(out, 0.5 * (f.x0 + f.x1), 28, ax->title, TITLE_PX, INK, JND_ALIGN_CENTRE, 0);
  if (ax->xlabel) jnd_draw_text(out, 0.5 * (f.x0 + f.x1), H - 16, ax->xlabel, LABEL_PX, INK, JND_ALIGN_CENTRE, 0);
  if (ax->ylabel) jnd_draw_text(out, 22, 0.5 * (f.y0 + f.y1), ax->ylabel, LABEL_PX, INK, JND_ALIGN_CENTRE, 1);

  /* vertical markers, dashed, labelled at the top */
  for (int m = 0; m < ax->nmarks; m++) {
    double x = ax->marks[m].x;
    if (!isfinite(x) || (f.log[0] && x <= 0) || x < f.lo[0] || x > f.hi[0]) continue;
    double p = map_axis(&f, 0, x);
    for (double y = f.y0; y < f.y1; y += 10) jnd_draw_line(out, p, y, p, fmin(y + 6, f.y1), 2, ax->marks[m].colour);
    if (ax->marks[m].label)
      jnd_draw_text(out, p + 4, f.y0 + 16 + 16 * m, ax->marks[m].label, TICK_PX, ax->marks[m].colour, JND_ALIGN_LEFT, 0);
  }

  /* series, clipped to the plot area by skipping points outside it */
  for (int k = 0; k < nseries; k++) {
    const jnd_plot_series *ps = &series[k];
    double w = ps->width > 0 ? ps->width : 2;
    double px = NAN, py = NAN;
    for (int i = 0; i < ps->n; i++) {
      double x = ps->x[i], y = ps->y[i];
      int ok = isfinite(x) && isfinite(y) && (!f.log[0] || x > 0) && (!f.log[1] || y > 0);
      double cx = ok ? map_axis(&f, 0, x) : NAN, cy = ok ? map_axis(&f, 1, y) : NAN;
      if (ok && (cx < f.x0 - 0.5 || cx > f.x1 + 0.5 || cy < f.y0 - 0.5 || cy > f.y1 + 0.5)) ok = 0;
      if (ok && ps->line && isfinite(px)) jnd_draw_line(out, px, py, cx, cy, w, ps->colour);
      if (ok && ps->markers) jnd_draw_circle(out, cx, cy, w + 2, ps->markers == 1, ps->colour);
      px = ok ? cx : NAN;
      py = ok ? cy : NAN;
    }
  }

  /* legend, top right inside the plot */
  int nl = 0;
  double lw = 0;
  for (int k = 0; k < nseries; k++)
    if (series[k].label) {
      nl++;
      lw = fmax(lw, jnd_text_width(series[k].label, TICK_PX));
    }
  if (nl) {
    double bx1 = f.x1 - 8, bx0 = bx1 - lw - 52, by0 = f.y0 + 8, by1 = by0 + 8 + 20 * nl;
    jnd_draw_rect(out, bx0, by0, bx1, by1, WHITE, 0.9);
    jnd_draw_frame(out, bx0, by0, bx1, by1, 1, GRID);
    int row = 0;
    for (int k = 0; k < nseries; k++) {
      if (!series[k].label) continue;
      double y = by0 + 14 + 20 * row++;
      if (series[k].line) jnd_draw_line(out, bx0 + 8, y, bx0 + 36, y, series[k].width > 0 ? series[k].width : 2, series[k].colour);
      if (series[k].markers) jnd_draw_circle(out, bx0 + 22, y, 4, series[k].markers == 1, series[k].colour);
      jnd_draw_text(out, bx0 + 44, y + 0.35 * TICK_PX, series[k].label, TICK_PX, INK, JND_ALIGN_LEFT, 0);
    }
  }
  return JND_OK;
}

void jnd_draw_colour_bar(jnd_image *img, int x, int y, int w, int h, double vmin, double vmax,
                         jnd_rgb (*map)(double t), const double *ticks, const char *const *tick_labels, int nticks,
                         const char *title) {
  if (!map) map = jnd_colour_scale;
  for (int r = 0; r < h; r++) {
    double t = h > 1 ? 1.0 - (double)r / (h - 1) : 0;
    jnd_draw_rect(img, x, y + r, x + w, y + r + 1, map(t), 1);
  }
  jnd_draw_frame(img, x, y, x + w, y + h, 1, INK);
  char buf[64];
  for (int i = 0; i < nticks; i++) {
    if (!(vmax > vmin)) break;
    double t = (ticks[i] - vmin) / (vmax - vmin);
    if (t < -1e-9 || t > 1 + 1e-9) continue;
    double py = y + (1 - t) * (h - 1) + 0.5;
    jnd_draw_line(img, x + w, py, x + w + 5, py, 1, INK);
    const char *label = tick_labels ? tick_labels[i] : (tick_label(ticks[i], buf, sizeof buf), buf);
    jnd_draw_text(img, x + w + 8, py + 0.35 * TICK_PX, label, TICK_PX, INK, JND_ALIGN_LEFT, 0);
  }
  if (title) jnd_draw_text(img, x, y - 10, title, TICK_PX, INK, JND_ALIGN_LEFT, 0);
}

jnd_status jnd_plot_grid(const jnd_plot_grid_spec *g, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (g->rows < 1 || g->cols < 1 || g->rows > 256 || g->cols > 256 || !g->value)
    return jnd_fail(JND_ERR_ARG, "plot: a grid of %d × %d cells is outside 1..256", g->rows, g->cols);
  int cell = g->cell_px > 0 ? g->cell_px : 56;
  double vmin = g->vmin, vmax = g->vmax, lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < g->rows * g->cols; i++)
    if (isfinite(g->value[i])) {
      lo = fmin(lo, g->value[i]);
      hi = fmax(hi, g->value[i]);
    }
  if (!isfinite(vmin)) vmin = isfinite(lo) ? lo : 0;
  if (!isfinite(vmax)) vmax = isfinite(hi) ? hi : 1;
  if (!(vmax > vmin)) vmax = vmin + 1;
  double rl = 0, cl = 0;
  for (int r = 0; g->row_labels && r < g->rows; r++) rl = fmax(rl, jnd_text_width(g->row_labels[r], TICK_PX));
  for (int c = 0; g->col_labels && c < g->cols; c++) cl = fmax(cl, jnd_text_width(g->col_labels[c], TICK_PX));
  int left = (int)rl + 16 + (g->row_title ? 28 : 0), top = g->title ? 44 : 16;
  int gw = cell * g->cols, gh = cell * g->rows;
  int bottom = 28 + (g->col_title ? 26 : 0), right = g->no_colour_bar ? 12 : 110;
  /* titles centred over the grid get room on both sides where they are wider */
  double tw = fmax(g->title ? jnd_text_width(g->title, TITLE_PX) : 0, g->col_title ? jnd_text_width(g->col_title, LABEL_PX) : 0);
  int spill = tw > gw ? (int)ceil((tw - gw) / 2) + 8 : 0;
  if (left < spill) left = spill;
  if (right < spill) right = spill;
  int W = left + gw + right, H = top + gh + bottom;
  if (W > 16384 || H > 16384) return jnd_fail(JND_ERR_LIMIT, "plot: grid picture %d × %d is too large", W, H);
  (void)cl;
  jnd_status s = jnd_canvas_new(out, W, H, WHITE);
  if (s != JND_OK) return s;
  char buf[64];
  for (int r = 0; r < g->rows; r++)
    for (int c = 0; c < g->cols; c++) {
      double v = g->value[r * g->cols + c];
      double x0 = left + c * cell, y0 = top + r * cell;
      int ok = isfinite(v);
      double t = ok ? (v - vmin) / (vmax - vmin) : 0;
      jnd_rgb bg = ok ? jnd_colour_scale(t) : NODATA;
      jnd_draw_rect(out, x0, y0, x0 + cell, y0 + cell, bg, 1);
      const char *text = g->cell_text ? g->cell_text[r * g->cols + c] : NULL;
      if (!text && ok) {
        snprintf(buf, sizeof buf, "%.3g", v);
        text = buf;
      }
      /* dark text on the light end of the scale, white on the dark end */
      jnd_rgb ink = ok && t > 0.55 ? INK : WHITE;
      if (text) jnd_draw_text(out, x0 + 0.5 * cell, y0 + 0.5 * cell + 0.35 * TICK_PX, text, TICK_PX, ink, JND_ALIGN_CENTRE, 0);
    }
  for (int c = 0; c <= g->cols; c++) jnd_draw_line(out, left + c * cell, top, left + c * cell, top + gh, 1, WHITE);
  for (int r = 0; r <= g->rows; r++) jnd_draw_line(out, left, top + r * cell, left + gw, top + r * cell, 1, WHITE);
  if (g->marked > 0 && g->marked <= g->rows * g->cols) {
    int mr = (g->marked - 1) / g->cols, mc = (g->marked - 1) % g->cols;
    /* red reads on both ends of the scale (navy and yellow) */
    jnd_draw_frame(out, left + mc * cell + 1, top + mr * cell + 1, left + (mc + 1) * cell - 1, top + (mr + 1) * cell - 1, 3,
                   (jnd_rgb){0.89f, 0.10f, 0.11f});
  }
  for (int r = 0; g->row_labels && r < g->rows; r++)
    jnd_draw_text(out, left - 8, top + (r + 0.5) * cell + 0.35 * TICK_PX, g->row_labels[r], TICK_PX, INK, JND_ALIGN_RIGHT, 0);
  for (int c = 0; g->col_labels && c < g->cols; c++)
    jnd_draw_text(out, left + (c + 0.5) * cell, top + gh + 18, g->col_labels[c], TICK_PX, INK, JND_ALIGN_CENTRE, 0);
  if (g->title) jnd_draw_text(out, left + 0.5 * gw, 28, g->title, TITLE_PX, INK, JND_ALIGN_CENTRE, 0);
  if (g->col_title) jnd_draw_text(out, left + 0.5 * gw, H - 10, g->col_title, LABEL_PX, INK, JND_ALIGN_CENTRE, 0);
  if (g->row_title) jnd_draw_text(out, 20, top + 0.5 * gh, g->row_title, LABEL_PX, INK, JND_ALIGN_CENTRE, 1);
  if (g->no_colour_bar) return JND_OK;
  double ticks[MAX_TICKS];
  int nt = axis_ticks(vmin, vmax, 0, ticks);
  int bh = gh < 120 ? gh : gh - 20;
  jnd_draw_colour_bar(out, left + gw + 24, top + (gh - bh) / 2 + (g->scale_title ? 8 : 0), 18,
                      bh - (g->scale_title ? 8 : 0), vmin, vmax, NULL, ticks, NULL, nt, g->scale_title);
  return JND_OK;
}
