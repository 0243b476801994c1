/* Pictures a person reads: a raster canvas with anti-aliased shapes and text,
 * and the plots built from them (line plots with labelled axes, colour bars,
 * labelled grids). Every report picture of jnd — heatmap legends, Pareto
 * curves, popping regions, gaze tables, texres matrices — is drawn with these,
 * so that they look alike and none carries its own drawing code.
 *
 * A canvas is a jnd_image of 3 planes holding the display signal (sRGB-encoded
 * 0..1), ready for jnd_image_write_png. Coordinates are pixels, x to the
 * right, y down, pixel centres at +0.5. Text is DejaVu Sans (from Debian's
 * fonts-dejavu-core, embedded at build time, so pictures do not depend on the
 * fonts of the machine that draws them). */
#ifndef JND_DRAW_H
#define JND_DRAW_H

#include "jnd.h"

typedef struct {
  float r, g, b; /* display signal, 0..1 */
} jnd_rgb;

/* Categorical colours for series (Okabe & Ito's colour-blind-safe set): i wraps. */
jnd_rgb jnd_palette(int i);
/* A sequential colour scale for t in 0..1 (dark blue → teal → yellow), monotone
 * in lightness so that it reads in grey too; t is clamped. */
jnd_rgb jnd_colour_scale(double t);
/* The colour at t (clamped to 0..1) of a scale of five evenly spaced stops,
 * linearly between them. */
jnd_rgb jnd_ramp5(const float stops[5][3], double t);

/* A new canvas w × h filled with bg. */
jnd_status jnd_canvas_new(jnd_image *img, int w, int h, jnd_rgb bg);

/* Filled axis-aligned rectangle [x0, x1) × [y0, y1), blended with opacity alpha. */
void jnd_draw_rect(jnd_image *img, double x0, double y0, double x1, double y1, jnd_rgb c, double alpha);
/* Rectangle outline of the given line width. */
void jnd_draw_frame(jnd_image *img, double x0, double y0, double x1, double y1, double width, jnd_rgb c);
/* Anti-aliased segment of the given width (pixels). */
void jnd_draw_line(jnd_image *img, double x0, double y0, double x1, double y1, double width, jnd_rgb c);
/* Anti-aliased disc (filled) or ring of radius r. */
void jnd_draw_circle(jnd_image *img, double cx, double cy, double r, int filled, jnd_rgb c);

typedef enum { JND_ALIGN_LEFT = 0, JND_ALIGN_CENTRE, JND_ALIGN_RIGHT } jnd_align;
/* Text (UTF-8; characters the font lacks show as '?') of height size_px
 * (the font's em), its baseline's anchor at (x, y), aligned left, centred or
 * right of x; rotated by 90° counter-clockwise when vertical (for y-axis
 * labels: it then runs upwards from the anchor). */
void jnd_draw_text(jnd_image *img, double x, double y, const char *text, double size_px, jnd_rgb c, jnd_align align,
                   int vertical);
/* The advance width of text at size_px. */
double jnd_text_width(const char *text, double size_px);

/* Copies src (3 planes of display signal, or 1 grey plane) into img with its
 * top-left corner at (x, y), scaled by an integer factor (nearest pixel),
 * clipped to img. */
void jnd_draw_image(jnd_image *img, int x, int y, const jnd_image *src, int scale);

/* The box a text drawn with jnd_draw_text(x, y, text, size_px, align,
 * vertical) covers: [x0, x1) × [y0, y1) in pixels, from the font's ascent
 * and descent and the text's advance width (the ink lies inside it). */
typedef struct {
  double x0, y0, x1, y1;
} jnd_box;
jnd_box jnd_text_box(double x, double y, const char *text, double size_px, jnd_align align, int vertical);

/* ---- plots ---- */

typedef struct {
  const double *x, *y; /* n points; NaN y values break the line */
  int n;
  const char *label;   /* legend entry (NULL: none) */
  jnd_rgb colour;
  int line;            /* draw the polyline (through the measured points only) */
  int markers;         /* 0 none, 1 discs, 2 rings */
  double width;        /* line width in pixels (0: 2) */
  const signed char *bound; /* per point, or NULL (all measured): 0 a measured value; +1 a lower
                          bound (the value is y or more: an open triangle with an arrow up, off
                          the line); −1 an upper bound (arrow down) */
  double bar_width;    /* > 0: a bar per point, this wide in x units, from the axis' bottom to y */
} jnd_plot_series;

typedef struct {
  double x;            /* a vertical marker at this x (NaN: none), labelled above the plot area */
  const char *label;
  jnd_rgb colour;
} jnd_plot_mark;

typedef struct {
  double y;            /* a horizontal reference line at this y (a threshold), dashed across the
                          plot area, its label in the legend (NaN: none) */
  const char *label;
  jnd_rgb colour;
} jnd_plot_hline;

typedef struct {
  const char *title, *xlabel, *ylabel;
  int log_x, log_y;            /* logarithmic axes (values <= 0 are not drawn) */
  double xmin, xmax, ymin, ymax; /* NaN: from the data, widened to round ticks */
  int width, height;           /* pixels (0: 800 × 500) */
  const jnd_plot_mark *marks;  /* vertical markers, e.g. a chosen level */
  int nmarks;
  const jnd_plot_hline *hlines; /* horizontal reference lines, e.g. a threshold */
  int nhlines;
  const char *bound_label;     /* the legend's entry for bound markers ("lower bound"), shown when a
                                  series has bounds */
  int integer_x, integer_y;    /* 1: ticks only at whole numbers (levels, components, counts) */
} jnd_plot_axes;

/* Where jnd_plot_lines puts things, so that tests can check that nothing
 * overlaps and nothing is clipped: the plot (data) area, the legend (below
 * the axes, outside the data), the tick labels of each axis (one number
 * format per axis: plain decimals with the same decimals on a linear axis,
 * or m×10ⁿ for all when a tick needs more than 7 digits), the markers'
 * labels (above the plot area, in rows that do not overlap) and every text's
 * box. */
#define JND_PLOT_MAX_TICKS 40
#define JND_PLOT_MAX_TEXTS 160
#define JND_PLOT_TEXT_MAX 256
typedef struct {
  int width, height;
  jnd_box plot;                /* the data area */
  double lo[2], hi[2];         /* the axes' ranges (x, y) */
  int log[2];
  jnd_box legend;              /* the legend's entries (x1 <= x0 when there is none) */
  int nticks[2];               /* x, y */
  double tick[2][JND_PLOT_MAX_TICKS];
  char tick_label[2][JND_PLOT_MAX_TICKS][32];
  int ntexts;                  /* every text the picture holds, with its box */
  jnd_box text_box[JND_PLOT_MAX_TEXTS];
  char text[JND_PLOT_MAX_TEXTS][JND_PLOT_TEXT_MAX]; /* copies: the layout outlives the caller's strings */
  char text_kind[JND_PLOT_MAX_TEXTS]; /* 't' title, 'x'/'y' axis label, 'X'/'Y' tick, 'm' marker, 'l' legend */
} jnd_plot_layout;

/* The pixel coordinate of value v on axis 0 (x) or 1 (y) of a layout. */
double jnd_plot_layout_map(const jnd_plot_layout *L, int axis, double v);

/* The layout of jnd_plot_lines(axes, series) without drawing it. */
jnd_status jnd_plot_lines_layout(const jnd_plot_axes *axes, const jnd_plot_series *series, int nseries,
                                 jnd_plot_layout *out);

/* Line plot of series on labelled axes with ticks, grid and a legend. */
jnd_status jnd_plot_lines(const jnd_plot_axes *axes, const jnd_plot_series *series, int nseries, jnd_image *out);

/* Labels for the ticks t[0..n) of an axis in one format (see
 * jnd_plot_layout): label[i] for t[i]. */
void jnd_plot_tick_labels(const double *t, int n, int log_axis, char (*label)[32]);

/* Numbers that a figure prints beside an axis's values (legend entries,
 * captions) in that axis's one format: plain decimals, or m×10ⁿ for all of
 * them when one needs it (as jnd_plot_tick_labels), each to `digits`
 * significant digits; label[i] for v[i]. */
void jnd_plot_number_labels(const double *v, int n, int digits, char (*label)[32]);

/* A vertical colour bar into img at (x, y), w × h, mapping vmin (bottom) to
 * vmax (top) through map (NULL: jnd_colour_scale), with ticks at the given
 * values and their labels (NULL: printed with %g), and a title above it. */
void jnd_draw_colour_bar(jnd_image *img, int x, int y, int w, int h, double vmin, double vmax,
                         jnd_rgb (*map)(double t), const double *ticks, const char *const *tick_labels, int nticks,
                         const char *title);

/* A labelled grid: rows × cols cells coloured by value through the colour
 * scale over [vmin, vmax] (NaN cells grey), each cell's text (NULL: the values,
 * one format for the grid: jnd_plot_number_labels, 3 digits), row and column labels, axis titles and a colour bar. For
 * texres's size matrices, gaze's L(distance, eccentricity) and similar. */
typedef struct {
  int rows, cols;
  const double *value;            /* rows × cols, row-major */
  const char *const *cell_text;   /* rows × cols or NULL */
  const char *const *row_labels, *const *col_labels;
  const char *title, *row_title, *col_title, *scale_title;
  double vmin, vmax;              /* NaN: the values' range */
  int cell_px;                    /* 0: 56 */
  int no_colour_bar;              /* 1: leave the bar out (small multiples sharing one) */
  int marked;                     /* 1 + row * cols + col of a cell to outline (a choice); 0: none */
  int integer_scale;              /* 1: the values are counts or indices: the colour bar's ticks at whole numbers */
} jnd_plot_grid_spec;
jnd_status jnd_plot_grid(const jnd_plot_grid_spec *g, jnd_image *out);

#endif
