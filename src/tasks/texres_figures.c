/* Pictures of a texres result that a person reads (drawn with io/draw.h):
 *   - the worst view: the object as rendered beside where the model predicts
 *     a visible difference, magnified to a readable size, with the JND scale
 *   - the two-map matrices of 000 Fig. 13: the criterion statistic per pair
 *     of sizes, large, with axis labels, the sizes and a colour legend, the
 *     chosen pair outlined; then the same per view, small */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"
#include "tasks/tasks.h"

jnd_status texres_worst_view_figure(const jnd_image *ref_srgb, const jnd_image *map, int view, int nviews, double p,
                                    jnd_image *out) {
  char title[160];
  snprintf(title, sizeof title, "worst of %d views (view %d): P(detect) = %.3f at the chosen sizes", nviews, view, p);
  jnd_heatmap_params hp;
  jnd_heatmap_defaults(&hp);
  hp.min_side = 320;
  hp.beside = 1;
  hp.title = title;
  return jnd_heatmap_draw(&hp, ref_srgb, map, out);
}

static int longer(const int s[2]) { return s[0] > s[1] ? s[0] : s[1]; }

/* one panel: rows the second map's sizes, columns the first's */
static jnd_status panel(const jnd_texres_matrix *mx, const double *values, const char *title, const char *row_title,
                        const char *col_title, int cell, int bar, int marked, jnd_image *out) {
  char *text = jnd_calloc((size_t)mx->na * mx->nb, 8);
  char rl[JND_TEXRES_MAX_CAND][16], cl[JND_TEXRES_MAX_CAND][16];
  const char *rows[JND_TEXRES_MAX_CAND], *cols[JND_TEXRES_MAX_CAND];
  const char **cells = jnd_calloc((size_t)mx->na * mx->nb, sizeof *cells);
  double *v = jnd_calloc((size_t)mx->na * mx->nb, sizeof *v);
  if (!text || !cells || !v) {
    free(text), free(cells), free(v);
    return JND_ERR_NOMEM;
  }
  for (int b = 0; b < mx->nb; b++) {
    snprintf(rl[b], sizeof rl[b], "%d", mx->size_b[b]);
    rows[b] = rl[b];
  }
  for (int a = 0; a < mx->na; a++) {
    snprintf(cl[a], sizeof cl[a], "%d", mx->size_a[a]);
    cols[a] = cl[a];
  }
  /* values are [a][b]; the grid is row-major over (b, a) */
  for (int b = 0; b < mx->nb; b++)
    for (int a = 0; a < mx->na; a++) {
      double x = values[a * mx->nb + b];
      int i = b * mx->na + a;
      v[i] = x;
      if (isfinite(x)) snprintf(text + 8 * i, 8, "%.2f", x);
      else text[8 * i] = 0;
      cells[i] = text + 8 * i;
    }
  jnd_plot_grid_spec g = {.rows = mx->nb, .cols = mx->na, .value = v, .cell_text = cells, .row_labels = rows,
                          .col_labels = cols, .title = title, .row_title = row_title, .col_title = col_title,
                          .scale_title = bar ? "P(detect)" : NULL, .vmin = 0, .vmax = 1, .cell_px = cell,
                          .no_colour_bar = !bar, .marked = marked};
  jnd_status s = jnd_plot_grid(&g, out);
  free(text), free(cells), free(v);
  return s;
}

jnd_status jnd_texres_matrix_figure(const jnd_texres_result *r, int t, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (t < 0 || t >= r->nmatrix) return jnd_fail(JND_ERR_ARG, "texres: no matrix %d", t);
  const jnd_texres_matrix *mx = &r->matrix[t];
  const jnd_texres_map *A = &r->maps[mx->map_a], *B = &r->maps[mx->map_b];
  int ca = -1, cb = -1;
  for (int a = 0; a < mx->na; a++)
    if (mx->size_a[a] == longer(A->chosen)) ca = a;
  for (int b = 0; b < mx->nb; b++)
    if (mx->size_b[b] == longer(B->chosen)) cb = b;
  int marked = ca >= 0 && cb >= 0 ? 1 + cb * mx->na + ca : 0;
  char row_title[160], col_title[160], title[160];
  snprintf(row_title, sizeof row_title, "%s (px)", B->name);
  snprintf(col_title, sizeof col_title, "%s (longer side, px)", A->name);
  snprintf(title, sizeof title, "criterion statistic over %d views", mx->nviews);
  /* the large panel, then the views four to a row */
  int np = mx->nviews + 1;
  jnd_image *pics = jnd_calloc((size_t)np, sizeof *pics);
  double *pv = jnd_calloc((size_t)mx->na * mx->nb, sizeof *pv);
  jnd_status s = pics && pv ? JND_OK : JND_ERR_NOMEM;
  if (s == JND_OK) s = panel(mx, mx->stat, title, row_title, col_title, 56, 1, marked, &pics[0]);
  for (int v = 0; v < mx->nviews && s == JND_OK; v++) {
    for (int i = 0; i < mx->na * mx->nb; i++) pv[i] = mx->p[(size_t)v * mx->na * mx->nb + i];
    snprintf(title, sizeof title, "view %d", v);
    s = panel(mx, pv, title, NULL, NULL, 36, 0, marked, &pics[v + 1]);
  }
  if (s == JND_OK) {
    enum { PER_ROW = 4, GAP = 8 };
    int W = pics[0].w, H = pics[0].h + GAP, row_w = 0, row_h = 0;
    for (int i = 1; i < np; i++) {
      if ((i - 1) % PER_ROW == 0) {
        H += row_h;
        row_w = row_h = 0;
      }
      row_w += pics[i].w;
      row_h = pics[i].h > row_h ? pics[i].h : row_h;
      W = row_w > W ? row_w : W;
    }
    H += row_h + 30;
    static const char note[] = "Outlined in red: the chosen pair. Each cell: pooled P(detect) of the view at that pair of "
                               "sizes (000 Fig. 13).";
    int nw = (int)jnd_text_width(note, 12) + 20;
    W = nw > W ? nw : W;
    s = jnd_canvas_new(out, W, H, (jnd_rgb){1, 1, 1});
    if (s == JND_OK) {
      jnd_draw_image(out, 0, 0, &pics[0], 1);
      int x = 0, y = pics[0].h + GAP;
      row_h = 0;
      for (int i = 1; i < np; i++) {
        if (i > 1 && (i - 1) % PER_ROW == 0) {
          x = 0;
          y += row_h;
          row_h = 0;
        }
        jnd_draw_image(out, x, y, &pics[i], 1);
        x += pics[i].w;
        row_h = pics[i].h > row_h ? pics[i].h : row_h;
      }
      jnd_draw_text(out, 10, H - 10, note, 12, (jnd_rgb){0.13f, 0.13f, 0.13f}, JND_ALIGN_LEFT, 0);
    }
  }
  for (int i = 0; pics && i < np; i++) jnd_image_free(&pics[i]);
  free(pics);
  free(pv);
  return s;
}
