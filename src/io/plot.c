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

#define MAX_TICKS JND_PLOT_MAX_TICKS

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
    int fine = log10(hi / lo) <= 2.5 + 1e-9;
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
    /* to 1, 2 or 5 × 10^k: 32..1024 reads on 20..2000, not 10..10000 */
    static const double m[3] = {1, 2, 5};
    double d = pow(10, floor(log10(*lo) + 1e-9)), l = d, u = pow(10, ceil(log10(*hi) - 1e-9));
    for (int k = 0; k < 3; k++)
      if (m[k] * d <= *lo * (1 + 1e-9)) l = m[k] * d;
    double e = u / 10, h = u;
    for (int k = 2; k >= 0; k--)
      if (m[k] * e >= *hi * (1 - 1e-9)) h = m[k] * e;
    *lo = l;
    *hi = h;
  } else {
    double step = nice_step(*hi - *lo, 5);
    *lo = floor(*lo / step + 1e-9) * step;
    *hi = ceil(*hi / step - 1e-9) * step;
  }
}

/* the decimals that print v exactly to 1e-9 of its magnitude (0..9) */
static int decimals_of(double v) {
  double a = fabs(v);
  for (int d = 0; d < 9; d++) {
    double s = pow(10, d), r = round(a * s) / s;
    if (fabs(r - a) <= 1e-9 * fmax(a, 1e-300) + 1e-12) return d;
  }
  return 9;
}

/* UTF-8 superscript digits and minus, for m×10ⁿ */
static void superscript(int e, char *buf, size_t n) {
  static const char *const digit[10] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                        "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  char d[16];
  snprintf(d, sizeof d, "%d", e < 0 ? -e : e);
  size_t k = 0;
  buf[0] = 0;
  if (e < 0) k += (size_t)snprintf(buf + k, n - k, "\u207b");
  for (const char *c = d; *c && k < n; c++) k += (size_t)snprintf(buf + k, n - k, "%s", digit[*c - '0']);
}

void jnd_plot_tick_labels(const double *t, int n, int log_axis, char (*label)[32]) {
  /* plain decimals while every tick prints in at most 7 digits and
   * 4 decimals; else m×10ⁿ for every tick */
  double big = 0, small = INFINITY;
  int dec = 0;
  for (int i = 0; i < n; i++) {
    double a = fabs(t[i]);
    if (!(a > 0)) continue;
    big = fmax(big, a);
    small = fmin(small, a);
    int d = decimals_of(t[i]);
    if (d > dec) dec = d;
  }
  int sci = big >= 1e7 || (isfinite(small) && small < 1e-4) || dec > 4;
  if (sci) {
    /* the same mantissa decimals for every tick */
    int mdec = 0;
    for (int i = 0; i < n; i++) {
      if (!(fabs(t[i]) > 0)) continue;
      int e = (int)floor(log10(fabs(t[i])) + 1e-9);
      int d = decimals_of(t[i] / pow(10, e));
      if (d > mdec) mdec = d;
    }
    if (mdec > 3) mdec = 3;
    for (int i = 0; i < n; i++) {
      if (!(fabs(t[i]) > 0)) {
        snprintf(label[i], 32, "0");
        continue;
      }
      int e = (int)floor(log10(fabs(t[i])) + 1e-9);
      double m = t[i] / pow(10, e);
      char sup[24];
      superscript(e, sup, sizeof sup);
      if (log_axis && fabs(m - 1) < 1e-9) snprintf(label[i], 32, "10%s", sup);
      else snprintf(label[i], 32, "%.*f\u00d710%s", mdec, m, sup);
    }
    return;
  }
  /* a linear axis: the same decimals for every tick; a logarithmic one:
   * each tick's own (0.01, 0.1, 1 read better than 0.01, 0.10, 1.00) */
  for (int i = 0; i < n; i++) snprintf(label[i], 32, "%.*f", log_axis ? decimals_of(t[i]) : dec, t[i] == 0 ? 0.0 : t[i]);
}

/* v ≠ 0 as m × 10^e, m rounded to `digits` significant digits (1 <= |m| < 10;
 * rounding can carry: 9.996 -> 1.00 × 10¹) */
static void significant(double v, int digits, double *m, int *e) {
  *e = (int)floor(log10(fabs(v)) + 1e-12);
  *m = round(v / pow(10, *e - digits + 1)) * pow(10, -digits + 1);
  if (fabs(*m) >= 10) *m /= 10, ++*e;
}

void jnd_plot_number_labels(const double *v, int n, int digits, char (*label)[32]) {
  /* the convention of the tick labels: plain decimals while every value
   * prints so (below 10⁷, from 10⁻⁴), each with its own decimals as on a
   * logarithmic axis (4, 22, 0.25 — not 4.00, 22.0); else m×10ⁿ for every
   * value, the mantissas with one number of decimals; `digits`
   * significant digits each */
  if (digits < 1) digits = 1;
  if (digits > 6) digits = 6;
  int sci = 0, mdec = 0, e;
  double m;
  for (int i = 0; i < n; i++) {
    if (!(fabs(v[i]) > 0) || !isfinite(v[i])) continue;
    sci |= fabs(v[i]) >= 1e7 || fabs(v[i]) < 1e-4;
    significant(v[i], digits, &m, &e);
    int d = decimals_of(m);
    if (d > mdec) mdec = d;
  }
  if (mdec > digits - 1) mdec = digits - 1;
  for (int i = 0; i < n; i++) {
    if (!isfinite(v[i])) {
      snprintf(label[i], 32, "%s", isnan(v[i]) ? "n/a" : v[i] > 0 ? "\u221e" : "\u2212\u221e");
      continue;
    }
    if (!(fabs(v[i]) > 0)) {
      snprintf(label[i], 32, "0");
      continue;
    }
    significant(v[i], digits, &m, &e);
    if (sci) {
      char sup[24];
      superscript(e, sup, sizeof sup);
      snprintf(label[i], 32, "%.*f\u00d710%s", mdec, m, sup);
    } else {
      double r = m * pow(10, e);
      int dec = decimals_of(r), most = digits - 1 - e;
      snprintf(label[i], 32, "%.*f", dec < most ? dec : most > 0 ? most : 0, r);
    }
  }
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

/* ---- the layout of a line plot ---- */

#define MAX_LEGEND 64
#define MAX_MARKS 32
enum { LEG_SERIES, LEG_HLINE, LEG_BOUND };

typedef struct {
  int kind, index;
  double x, y; /* the sample's left end, the sample's centre line */
} legend_entry;

typedef struct {
  jnd_plot_layout *L;
  frame f;
  double title_px;
  struct {
    double x, y, size;
    jnd_align align;
    int vertical;
  } at[JND_PLOT_MAX_TEXTS];
  int nleg;
  legend_entry leg[MAX_LEGEND];
  int mark_text[MAX_MARKS]; /* the text of each marker's label (−1: none) */
} plan;

static int add_text(plan *P, char kind, const char *text, double x, double y, double size, jnd_align align, int vertical) {
  jnd_plot_layout *L = P->L;
  if (!text || !*text || L->ntexts >= JND_PLOT_MAX_TEXTS) return -1;
  int i = L->ntexts++;
  snprintf(L->text[i], sizeof L->text[i], "%s", text);
  L->text_kind[i] = kind;
  L->text_box[i] = jnd_text_box(x, y, text, size, align, vertical);
  P->at[i].x = x;
  P->at[i].y = y;
  P->at[i].size = size;
  P->at[i].align = align;
  P->at[i].vertical = vertical;
  return i;
}

static int boxes_overlap(const jnd_box *a, const jnd_box *b, double gap) {
  return a->x0 < b->x1 + gap && b->x0 < a->x1 + gap && a->y0 < b->y1 + gap && b->y0 < a->y1 + gap;
}

/* whether a series has a bound pointing dir (+1 up, −1 down) */
static int series_has_bounds(const jnd_plot_series *s, int n, int dir) {
  for (int k = 0; k < n; k++)
    for (int i = 0; s[k].bound && i < s[k].n; i++)
      if (s[k].bound[i] == dir) return 1;
  return 0;
}

#define MARK_ROW 20 /* a row of markers' labels, pixels */
#define SAMPLE_W 30 /* a legend entry's line or marker sample */
static double legend_entry_width(const char *label) { return SAMPLE_W + 6 + jnd_text_width(label, TICK_PX) + 22; }

static const char *legend_label(const jnd_plot_axes *ax, const jnd_plot_series *s, int kind, int index) {
  return kind == LEG_SERIES ? s[index].label : kind == LEG_HLINE ? ax->hlines[index].label
                                                                  : ax->bound_label ? ax->bound_label
                                                                  : index < 0       ? "upper bound"
                                                                                    : "lower bound";
}

/* ticks of axis a and their labels; labels that would overlap are left out
 * (on a log axis first all but the decades, then every other one) */
static void layout_ticks(plan *P, const jnd_plot_axes *ax, int a) {
  jnd_plot_layout *L = P->L;
  frame *f = &P->f;
  int n = axis_ticks(f->lo[a], f->hi[a], f->log[a], L->tick[a]);
  if ((a == 0 ? ax->integer_x : ax->integer_y) && !f->log[a]) {
    int m = 0;
    double step = n > 1 ? L->tick[a][1] - L->tick[a][0] : 1;
    if (step < 1 || (a == 0 && f->hi[0] - f->lo[0] <= 16)) { /* every whole number while they are few */
      for (double v = ceil(f->lo[a] - 1e-9); v <= f->hi[a] + 1e-9 && m < MAX_TICKS; v++) L->tick[a][m++] = v;
    } else {
      for (int i = 0; i < n; i++)
        if (fabs(L->tick[a][i] - round(L->tick[a][i])) < 1e-9) L->tick[a][m++] = L->tick[a][i];
    }
    n = m;
  }
  L->nticks[a] = n;
  jnd_plot_tick_labels(L->tick[a], n, f->log[a], L->tick_label[a]);
}

static int tick_labels_overlap(const plan *P, int a, const int *keep) {
  const jnd_plot_layout *L = P->L;
  jnd_box prev = {0, 0, 0, 0};
  int have = 0;
  for (int i = 0; i < L->nticks[a]; i++) {
    if (!keep[i]) continue;
    double p = map_axis(&P->f, a, L->tick[a][i]);
    jnd_box b = a == 0 ? jnd_text_box(p, P->f.y1 + 24, L->tick_label[a][i], TICK_PX, JND_ALIGN_CENTRE, 0)
                       : jnd_text_box(P->f.x0 - 8, p + 0.35 * TICK_PX, L->tick_label[a][i], TICK_PX, JND_ALIGN_RIGHT, 0);
    if (have && boxes_overlap(&prev, &b, a == 0 ? 6 : 0)) return 1;
    prev = b;
    have = 1;
  }
  return 0;
}

static void thin_tick_labels(plan *P, int a) {
  jnd_plot_layout *L = P->L;
  int n = L->nticks[a], keep[MAX_TICKS] = {0};
  for (int i = 0; i < n; i++) keep[i] = 1;
  if (tick_labels_overlap(P, a, keep) && P->f.log[a]) {
    int decades = 0;
    for (int i = 0; i < n; i++) {
      double m = L->tick[a][i] / pow(10, floor(log10(L->tick[a][i]) + 1e-9));
      keep[i] = fabs(m - 1) < 1e-6;
      decades += keep[i];
    }
    if (decades < 2)
      for (int i = 0; i < n; i++) keep[i] = 1;
  }
  for (int every = 2; every < n && tick_labels_overlap(P, a, keep); every++) {
    int j = 0;
    for (int i = 0; i < n; i++)
      if (keep[i] || every > 2) keep[i] = (j++ % every) == 0;
  }
  for (int i = 0; i < n; i++)
    if (!keep[i]) L->tick_label[a][i][0] = 0;
}

static jnd_status plot_plan(const jnd_plot_axes *ax, const jnd_plot_series *series, int nseries, jnd_plot_layout *L,
                            plan *P) {
  memset(L, 0, sizeof *L);
  memset(P, 0, sizeof *P);
  P->L = L;
  int W = ax->width > 0 ? ax->width : 800, H = ax->height > 0 ? ax->height : 500;
  if (W < 200 || H < 150 || W > 8192 || H > 8192) return jnd_fail(JND_ERR_ARG, "plot: size %d × %d is outside 200..8192", W, H);
  if (ax->nmarks > MAX_MARKS) return jnd_fail(JND_ERR_ARG, "plot: %d markers (at most %d)", ax->nmarks, MAX_MARKS);
  L->width = W;
  L->height = H;
  frame *f = &P->f;
  f->log[0] = ax->log_x;
  f->log[1] = ax->log_y;
  double lim[2][2] = {{ax->xmin, ax->xmax}, {ax->ymin, ax->ymax}};
  for (int a = 0; a < 2; a++) {
    double lo = INFINITY, hi = -INFINITY;
    for (int s = 0; s < nseries; s++)
      for (int i = 0; i < series[s].n; i++) {
        double v = a == 0 ? series[s].x[i] : series[s].y[i];
        if (!isfinite(v) || (f->log[a] && v <= 0)) continue;
        lo = fmin(lo, v);
        hi = fmax(hi, v);
      }
    for (int m = 0; a == 0 && m < ax->nmarks; m++)
      if (isfinite(ax->marks[m].x) && (!f->log[0] || ax->marks[m].x > 0)) {
        lo = fmin(lo, ax->marks[m].x);
        hi = fmax(hi, ax->marks[m].x);
      }
    for (int m = 0; a == 1 && m < ax->nhlines; m++)
      if (isfinite(ax->hlines[m].y) && (!f->log[1] || ax->hlines[m].y > 0)) {
        lo = fmin(lo, ax->hlines[m].y);
        hi = fmax(hi, ax->hlines[m].y);
      }
    if (!isfinite(lo)) {
      lo = f->log[a] ? 1 : 0;
      hi = f->log[a] ? 10 : 1;
    }
    int fixed_lo = isfinite(lim[a][0]) && (!f->log[a] || lim[a][0] > 0);
    int fixed_hi = isfinite(lim[a][1]) && (!f->log[a] || lim[a][1] > 0);
    if (fixed_lo) lo = lim[a][0];
    if (fixed_hi) hi = lim[a][1];
    double l = lo, h = hi;
    axis_range(&l, &h, f->log[a]);
    f->lo[a] = fixed_lo ? lo : l;
    f->hi[a] = fixed_hi ? hi : h;
    if (!(f->hi[a] > f->lo[a])) f->hi[a] = f->lo[a] + 1;
  }

  /* margins from what they hold: the y ticks' widest label, half the last x
   * label, the title and the markers' label rows above, the x labels and the
   * legend's rows below */
  layout_ticks(P, ax, 0);
  layout_ticks(P, ax, 1);
  double yw = 0;
  for (int i = 0; i < L->nticks[1]; i++) yw = fmax(yw, jnd_text_width(L->tick_label[1][i], TICK_PX));
  f->x0 = fmax(56, (ax->ylabel ? 40 : 18) + yw);
  double last = L->nticks[0] ? jnd_text_width(L->tick_label[0][L->nticks[0] - 1], TICK_PX) : 0;
  f->x1 = W - fmax(20, 0.5 * last + 8);
  if (f->x1 - f->x0 < 80) return jnd_fail(JND_ERR_ARG, "plot: %d pixels are too narrow for its labels", W);

  P->title_px = TITLE_PX;
  double top = 10;
  if (ax->title) {
    while (P->title_px > 9 && jnd_text_width(ax->title, P->title_px) > W - 16) P->title_px -= 1;
    top = 14 + P->title_px * 1.45;
  }
  /* markers' labels: each centred on its marker (moved in to fit the
   * picture), in the first row where it overlaps no other */
  int rows = 0, mrow[MAX_MARKS];
  double mx[MAX_MARKS], mw[MAX_MARKS];
  for (int m = 0; m < ax->nmarks; m++) {
    mrow[m] = -1;
    double x = ax->marks[m].x;
    if (!ax->marks[m].label || !isfinite(x) || (f->log[0] && x <= 0) || x < f->lo[0] || x > f->hi[0]) continue;
    double p = map_axis(f, 0, x), w = jnd_text_width(ax->marks[m].label, TICK_PX);
    mx[m] = fmin(fmax(p, 6 + 0.5 * w), W - 6 - 0.5 * w);
    mw[m] = w;
    int r = 0, clash = 1;
    for (; clash; r += clash) {
      clash = 0;
      for (int j = 0; j < m && !clash; j++) clash = mrow[j] == r && fabs(mx[j] - mx[m]) < 0.5 * (w + mw[j]) + 10;
    }
    mrow[m] = r;
    if (r + 1 > rows) rows = r + 1;
  }
  double band = top;
  f->y0 = top + (rows ? (double)MARK_ROW * rows + 8 : 10);

  /* the legend: entries flowing left to right from the plot's left edge */
  int nleg = 0;
  for (int k = 0; k < nseries && nleg < MAX_LEGEND; k++)
    if (series[k].label) P->leg[nleg++] = (legend_entry){LEG_SERIES, k, 0, 0};
  for (int k = 0; k < ax->nhlines && nleg < MAX_LEGEND; k++)
    if (ax->hlines[k].label && isfinite(ax->hlines[k].y)) P->leg[nleg++] = (legend_entry){LEG_HLINE, k, 0, 0};
  for (int dir = 1; dir >= -1; dir -= 2)
    if (series_has_bounds(series, nseries, dir) && nleg < MAX_LEGEND) P->leg[nleg++] = (legend_entry){LEG_BOUND, dir, 0, 0};
  P->nleg = nleg;
  int lrows = 0;
  double lx = f->x0;
  for (int e = 0; e < nleg; e++) {
    double w = legend_entry_width(legend_label(ax, series, P->leg[e].kind, P->leg[e].index));
    if (e == 0 || (lx + w > W - 8 && lx > f->x0)) {
      lrows++;
      lx = fmin(f->x0, fmax(8, W - 8 - w));
    }
    P->leg[e].x = lx;
    P->leg[e].y = lrows; /* the row for now */
    lx += w;
  }
  double below = 34 + (ax->xlabel ? 24 : 0) + (lrows ? 20.0 * lrows + 10 : 0);
  f->y1 = H - below;
  if (f->y1 - f->y0 < 60) return jnd_fail(JND_ERR_ARG, "plot: %d pixels are too low for its labels", H);

  /* the texts, now that the frame is known */
  if (ax->title) add_text(P, 't', ax->title, 0.5 * W, 10 + P->title_px, P->title_px, JND_ALIGN_CENTRE, 0);
  for (int m = 0; m < ax->nmarks && m < MAX_MARKS; m++)
    P->mark_text[m] = mrow[m] < 0 ? -1
                                  : add_text(P, 'm', ax->marks[m].label, mx[m], band + 14 + (double)MARK_ROW * mrow[m],
                                             TICK_PX, JND_ALIGN_CENTRE, 0);
  thin_tick_labels(P, 0);
  thin_tick_labels(P, 1);
  for (int i = 0; i < L->nticks[0]; i++)
    add_text(P, 'X', L->tick_label[0][i], map_axis(f, 0, L->tick[0][i]), f->y1 + 24, TICK_PX, JND_ALIGN_CENTRE, 0);
  for (int i = 0; i < L->nticks[1]; i++)
    add_text(P, 'Y', L->tick_label[1][i], f->x0 - 8, map_axis(f, 1, L->tick[1][i]) + 0.35 * TICK_PX, TICK_PX,
             JND_ALIGN_RIGHT, 0);
  /* axis labels centred on the plot area, moved in and made smaller where
   * they would not fit the picture */
  if (ax->xlabel) {
    double px = LABEL_PX;
    while (px > 9 && jnd_text_width(ax->xlabel, px) > W - 12) px -= 1;
    double w = jnd_text_width(ax->xlabel, px), c = fmin(fmax(0.5 * (f->x0 + f->x1), 6 + 0.5 * w), W - 6 - 0.5 * w);
    add_text(P, 'x', ax->xlabel, c, f->y1 + 50, px, JND_ALIGN_CENTRE, 0);
  }
  if (ax->ylabel) {
    double px = LABEL_PX;
    while (px > 9 && jnd_text_width(ax->ylabel, px) > H - 12) px -= 1;
    double w = jnd_text_width(ax->ylabel, px), c = fmin(fmax(0.5 * (f->y0 + f->y1), 6 + 0.5 * w), H - 6 - 0.5 * w);
    add_text(P, 'y', ax->ylabel, 6 + 0.93 * LABEL_PX, c, px, JND_ALIGN_CENTRE, 1);
  }
  L->legend = (jnd_box){W, H, 0, 0};
  double ly0 = f->y1 + 34 + (ax->xlabel ? 24 : 0);
  for (int e = 0; e < nleg; e++) {
    P->leg[e].y = ly0 + 20 * (P->leg[e].y - 1) + 14;
    int t = add_text(P, 'l', legend_label(ax, series, P->leg[e].kind, P->leg[e].index), P->leg[e].x + SAMPLE_W + 6,
                     P->leg[e].y + 0.35 * TICK_PX, TICK_PX, JND_ALIGN_LEFT, 0);
    jnd_box b = {P->leg[e].x, P->leg[e].y - 9, P->leg[e].x + SAMPLE_W, P->leg[e].y + 9};
    if (t >= 0) b.x1 = L->text_box[t].x1, b.y0 = fmin(b.y0, L->text_box[t].y0), b.y1 = fmax(b.y1, L->text_box[t].y1);
    L->legend.x0 = fmin(L->legend.x0, b.x0);
    L->legend.y0 = fmin(L->legend.y0, b.y0);
    L->legend.x1 = fmax(L->legend.x1, b.x1);
    L->legend.y1 = fmax(L->legend.y1, b.y1);
  }
  if (!nleg) L->legend = (jnd_box){0, 0, 0, 0};
  L->plot = (jnd_box){f->x0, f->y0, f->x1, f->y1};
  for (int a = 0; a < 2; a++) {
    L->lo[a] = f->lo[a];
    L->hi[a] = f->hi[a];
    L->log[a] = f->log[a];
  }
  return JND_OK;
}

double jnd_plot_layout_map(const jnd_plot_layout *L, int axis, double v) {
  frame f = {L->plot.x0,           L->plot.y0,           L->plot.x1,           L->plot.y1,
             {L->lo[0], L->lo[1]}, {L->hi[0], L->hi[1]}, {L->log[0], L->log[1]}};
  return map_axis(&f, axis, v);
}

jnd_status jnd_plot_lines_layout(const jnd_plot_axes *ax, const jnd_plot_series *series, int nseries,
                                 jnd_plot_layout *out) {
  plan *P = malloc(sizeof *P);
  if (!P) return jnd_fail(JND_ERR_NOMEM, "plot: out of memory");
  jnd_status s = plot_plan(ax, series, nseries, out, P);
  free(P);
  return s;
}

/* an open triangle at (x, y) pointing the way of the bound, with an arrow
 * from it that way (up for a lower bound), stopped at the plot's edge; k
 * scales it: a series drawn wider beneath another (pop's speeds that pop
 * alike) draws its bound larger too, so that both show where they meet */
static void draw_bound(jnd_image *img, const frame *f, double x, double y, int dir, jnd_rgb c, double k) {
  double s = dir > 0 ? -1 : 1; /* screen y grows downwards */
  jnd_draw_line(img, x, y + 5 * k * s, x - 5 * k, y - 4 * k * s, 1.5 * k, c);
  jnd_draw_line(img, x - 5 * k, y - 4 * k * s, x + 5 * k, y - 4 * k * s, 1.5 * k, c);
  jnd_draw_line(img, x + 5 * k, y - 4 * k * s, x, y + 5 * k * s, 1.5 * k, c);
  double end = y + (17 + 5 * k) * s;
  end = s < 0 ? fmax(end, f->y0 + 1) : fmin(end, f->y1 - 1);
  if (fabs(end - (y + 6 * k * s)) < 4) return;
  jnd_draw_line(img, x, y + 6 * k * s, x, end, 2 * k, c);
  jnd_draw_line(img, x - 4 * k, end - 5 * k * s, x, end, 2 * k, c);
  jnd_draw_line(img, x + 4 * k, end - 5 * k * s, x, end, 2 * k, c);
}

/* dashes of 6 pixels every 10; phase j of n draws every n-th dash from the
 * j-th, so that n lines on one place alternate their colours */
static void dashed_phase(jnd_image *img, double x0, double y0, double x1, double y1, double width, jnd_rgb c, int j,
                         int n) {
  double len = hypot(x1 - x0, y1 - y0);
  for (double t = 10.0 * j; t < len; t += 10.0 * n) {
    double u = fmin(t + 6, len);
    jnd_draw_line(img, x0 + (x1 - x0) * t / len, y0 + (y1 - y0) * t / len, x0 + (x1 - x0) * u / len,
                  y0 + (y1 - y0) * u / len, width, c);
  }
}

static void dashed(jnd_image *img, double x0, double y0, double x1, double y1, double width, jnd_rgb c) {
  dashed_phase(img, x0, y0, x1, y1, width, c, 0, 1);
}

jnd_status jnd_plot_lines(const jnd_plot_axes *ax, const jnd_plot_series *series, int nseries, jnd_image *out) {
  memset(out, 0, sizeof *out);
  jnd_plot_layout *L = malloc(sizeof *L);
  plan *P = malloc(sizeof *P);
  jnd_status s = L && P ? plot_plan(ax, series, nseries, L, P) : jnd_fail(JND_ERR_NOMEM, "plot: out of memory");
  if (s == JND_OK) s = jnd_canvas_new(out, L->width, L->height, WHITE);
  if (s != JND_OK) {
    free(L);
    free(P);
    return s;
  }
  const frame *f = &P->f;

  /* grid and ticks */
  for (int a = 0; a < 2; a++)
    for (int i = 0; i < L->nticks[a]; i++) {
      double p = map_axis(f, a, L->tick[a][i]);
      if (a == 0) {
        jnd_draw_line(out, p, f->y0, p, f->y1, 1, GRID);
        jnd_draw_line(out, p, f->y1, p, f->y1 + 5, 1, INK);
      } else {
        jnd_draw_line(out, f->x0, p, f->x1, p, 1, GRID);
        jnd_draw_line(out, f->x0 - 5, p, f->x0, p, 1, INK);
      }
    }
  jnd_draw_frame(out, f->x0, f->y0, f->x1 + 1, f->y1 + 1, 1, INK);
  for (int i = 0; i < L->ntexts; i++) {
    char k = L->text_kind[i];
    if (k == 'm' || k == 'l') continue; /* in their colours, below */
    jnd_draw_text(out, P->at[i].x, P->at[i].y, L->text[i], P->at[i].size, INK, P->at[i].align, P->at[i].vertical);
  }

  /* horizontal reference lines, dashed */
  for (int m = 0; m < ax->nhlines; m++) {
    double y = ax->hlines[m].y;
    if (!isfinite(y) || (f->log[1] && y <= 0) || y < f->lo[1] || y > f->hi[1]) continue;
    double p = map_axis(f, 1, y);
    dashed(out, f->x0, p, f->x1, p, 2, ax->hlines[m].colour);
  }
  /* vertical markers, dashed, each joined to its label above the plot */
  for (int m = 0; m < ax->nmarks; m++) {
    double x = ax->marks[m].x;
    if (!isfinite(x) || (f->log[0] && x <= 0) || x < f->lo[0] || x > f->hi[0]) continue;
    double p = map_axis(f, 0, x);
    /* markers on one place (a rule choosing the same level as another) take turns */
    int j = 0, n = 0;
    for (int o = 0; o < ax->nmarks; o++) {
      double q = ax->marks[o].x;
      if (!isfinite(q) || (f->log[0] && q <= 0) || fabs(map_axis(f, 0, q) - p) > 1) continue;
      j += o < m;
      n++;
    }
    dashed_phase(out, p, f->y0, p, f->y1, 2, ax->marks[m].colour, j, n);
    int t = m < MAX_MARKS ? P->mark_text[m] : -1;
    if (t < 0) continue;
    jnd_draw_line(out, p, L->text_box[t].y1, p, f->y0, 1, ax->marks[m].colour);
  }
  /* their labels over the joins of the labels in the rows above (on white) */
  for (int m = 0; m < ax->nmarks && m < MAX_MARKS; m++) {
    int t = P->mark_text[m];
    if (t < 0) continue;
    const jnd_box *b = &L->text_box[t];
    jnd_draw_rect(out, b->x0, b->y0 + 2, b->x1, b->y1, WHITE, 1);
    jnd_draw_text(out, P->at[t].x, P->at[t].y, L->text[t], TICK_PX, ax->marks[m].colour, JND_ALIGN_CENTRE, 0);
  }

  /* series: bars, then lines through the measured points, then markers;
   * points outside the plot area are left out */
  for (int pass = 0; pass < 3; pass++)
    for (int k = 0; k < nseries; k++) {
      const jnd_plot_series *ps = &series[k];
      double w = ps->width > 0 ? ps->width : 2;
      double px = NAN, py = NAN;
      for (int i = 0; i < ps->n; i++) {
        double x = ps->x[i], y = ps->y[i];
        int b = ps->bound ? ps->bound[i] : 0;
        int ok = isfinite(x) && isfinite(y) && (!f->log[0] || x > 0) && (!f->log[1] || y > 0);
        double cx = ok ? map_axis(f, 0, x) : NAN, cy = ok ? map_axis(f, 1, y) : NAN;
        if (ok && (cx < f->x0 - 0.5 || cx > f->x1 + 0.5 || cy < f->y0 - 0.5 || cy > f->y1 + 0.5)) ok = 0;
        if (pass == 0 && ok && ps->bar_width > 0) {
          double a = map_axis(f, 0, f->log[0] ? x / pow(10, 0.5 * ps->bar_width) : x - 0.5 * ps->bar_width);
          double z = map_axis(f, 0, f->log[0] ? x * pow(10, 0.5 * ps->bar_width) : x + 0.5 * ps->bar_width);
          jnd_draw_rect(out, fmax(a, f->x0) + 1, cy, fmin(z, f->x1) - 1, f->y1, ps->colour, 1);
        }
        if (pass == 1 && ps->line) {
          if (b) continue; /* a bound is off the line: the line goes on to the next measured point */
          if (ok && isfinite(px)) jnd_draw_line(out, px, py, cx, cy, w, ps->colour);
          px = ok ? cx : NAN;
          py = ok ? cy : NAN;
        }
        if (pass == 2 && ok) {
          if (b) draw_bound(out, f, cx, cy, b, ps->colour, 0.5 + 0.25 * w);
          else if (ps->markers) jnd_draw_circle(out, cx, cy, w + 2, ps->markers == 1, ps->colour);
        }
      }
    }

  /* the legend, below the axes */
  for (int e = 0, t = 0; e < P->nleg; e++) {
    double x = P->leg[e].x, y = P->leg[e].y;
    const jnd_plot_series *ps = P->leg[e].kind == LEG_SERIES ? &series[P->leg[e].index] : NULL;
    if (ps) {
      if (ps->bar_width > 0) jnd_draw_rect(out, x + 6, y - 6, x + SAMPLE_W - 6, y + 6, ps->colour, 1);
      if (ps->line) jnd_draw_line(out, x, y, x + SAMPLE_W, y, ps->width > 0 ? ps->width : 2, ps->colour);
      if (ps->markers) jnd_draw_circle(out, x + 0.5 * SAMPLE_W, y, 4, ps->markers == 1, ps->colour);
    } else if (P->leg[e].kind == LEG_HLINE) {
      dashed(out, x, y, x + SAMPLE_W, y, 2, ax->hlines[P->leg[e].index].colour);
    } else {
      frame fr = {0, y - 12, 0, y + 12, {0, 0}, {1, 1}, {0, 0}};
      draw_bound(out, &fr, x + 0.5 * SAMPLE_W, y + 4 * P->leg[e].index, P->leg[e].index, INK, 1);
    }
    while (t < L->ntexts && L->text_kind[t] != 'l') t++;
    if (t < L->ntexts) {
      jnd_draw_text(out, P->at[t].x, P->at[t].y, L->text[t], TICK_PX, INK, JND_ALIGN_LEFT, 0);
      t++;
    }
  }
  free(L);
  free(P);
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
  char auto_labels[JND_PLOT_MAX_TICKS][32];
  if (nticks > JND_PLOT_MAX_TICKS) nticks = JND_PLOT_MAX_TICKS;
  if (!tick_labels) jnd_plot_tick_labels(ticks, nticks, 0, auto_labels);
  for (int i = 0; i < nticks; i++) {
    if (!(vmax > vmin)) break;
    double t = (ticks[i] - vmin) / (vmax - vmin);
    if (t < -1e-9 || t > 1 + 1e-9) continue;
    double py = y + (1 - t) * (h - 1) + 0.5;
    jnd_draw_line(img, x + w, py, x + w + 5, py, 1, INK);
    const char *label = tick_labels ? tick_labels[i] : auto_labels[i];
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
  /* the row title, drawn upright centred on the grid, gets room above and
   * below where it is longer than the grid is tall: otherwise it ran off
   * the picture and under the title (gaze.png of a 3 × 3 table, issue 25) */
  double rtw = g->row_title ? jnd_text_width(g->row_title, LABEL_PX) : 0;
  int vspill = rtw > gh ? (int)ceil((rtw - gh) / 2) : 0;
  top += vspill;
  bottom += vspill;
  int W = left + gw + right, H = top + gh + bottom;
  if (W > 16384 || H > 16384) return jnd_fail(JND_ERR_LIMIT, "plot: grid picture %d × %d is too large", W, H);
  (void)cl;
  jnd_status s = jnd_canvas_new(out, W, H, WHITE);
  if (s != JND_OK) return s;
  /* cells without their own text: the values, one number format for the
   * whole grid (jnd_plot_number_labels, 3 digits; never %g's 1e-05 beside 0.25) */
  char (*num)[32] = NULL;
  if (!g->cell_text) {
    num = jnd_alloc((size_t)g->rows * g->cols, sizeof *num);
    if (!num) {
      jnd_image_free(out);
      return JND_ERR_NOMEM;
    }
    jnd_plot_number_labels(g->value, g->rows * g->cols, 3, num);
  }
  for (int r = 0; r < g->rows; r++)
    for (int c = 0; c < g->cols; c++) {
      double v = g->value[r * g->cols + c];
      double x0 = left + c * cell, y0 = top + r * cell;
      int ok = isfinite(v);
      double t = ok ? (v - vmin) / (vmax - vmin) : 0;
      jnd_rgb bg = ok ? jnd_colour_scale(t) : NODATA;
      jnd_draw_rect(out, x0, y0, x0 + cell, y0 + cell, bg, 1);
      const char *text = g->cell_text ? g->cell_text[r * g->cols + c] : NULL;
      if (!text && ok) text = num[r * g->cols + c];
      /* dark text on the light end of the scale, white on the dark end */
      jnd_rgb ink = ok && t > 0.55 ? INK : WHITE;
      if (text) jnd_draw_text(out, x0 + 0.5 * cell, y0 + 0.5 * cell + 0.35 * TICK_PX, text, TICK_PX, ink, JND_ALIGN_CENTRE, 0);
    }
  free(num);
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
  if (g->integer_scale) {
    /* whole numbers only (a level 1.5 does not exist): every k-th of them */
    double step = fmax(1, ceil((vmax - vmin) / 8));
    nt = 0;
    for (double v = ceil(vmin); v <= vmax + 1e-9 && nt < MAX_TICKS; v += step) ticks[nt++] = v;
  }
  int bh = gh < 120 ? gh : gh - 20;
  jnd_draw_colour_bar(out, left + gw + 24, top + (gh - bh) / 2 + (g->scale_title ? 8 : 0), 18,
                      bh - (g->scale_title ? 8 : 0), vmin, vmax, NULL, ticks, NULL, nt, g->scale_title);
  return JND_OK;
}
