/* The report's own plots: drawn from the numbers of a command's JSON report
 * with the shared plot code (io/draw.h), so they look like every other
 * picture jnd draws. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "batch/batch.h"
#include "batch/plots.h"
#include "io/draw.h"

#define MAX_MAPS 16 /* series a plot tells apart: 8 colours (jnd_palette) × discs or rings */
#define MAX_POINTS 64

static int write_image(jnd_image *img, const char *path) {
  int ok = jnd_image_write_png(path, img, 8) == JND_OK;
  jnd_image_free(img);
  return ok ? 1 : -1;
}

static int draw(const jnd_plot_axes *ax, const jnd_plot_series *s, int n, jnd_image *img, jnd_plot_layout *layout) {
  if (layout && jnd_plot_lines_layout(ax, s, n, layout) != JND_OK) return -1;
  return jnd_plot_lines(ax, s, n, img) == JND_OK ? 1 : -1;
}

int jnd_plot_texres_series_image(const cJSON *report, jnd_image *img, jnd_plot_layout *layout) {
  memset(img, 0, sizeof *img);
  const cJSON *maps[MAX_MAPS];
  int all = jnd_json_select(report, RS_TEXRES_MAPS, maps, MAX_MAPS), nm = all < MAX_MAPS ? all : MAX_MAPS;
  double x[MAX_MAPS][MAX_POINTS], y[MAX_MAPS][MAX_POINTS];
  signed char bound[MAX_MAPS][MAX_POINTS];
  jnd_plot_series s[MAX_MAPS];
  int ns = 0;
  for (int m = 0; m < nm; m++) {
    const cJSON *cand = cJSON_GetObjectItemCaseSensitive(maps[m], RS_TEXRES_MAPS_CANDIDATES);
    const cJSON *ser = cJSON_GetObjectItemCaseSensitive(maps[m], RS_TEXRES_MAPS_SERIES);
    const cJSON *early = cJSON_GetObjectItemCaseSensitive(maps[m], RS_TEXRES_MAPS_SERIES_EARLY);
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(maps[m], RS_TEXRES_MAPS_NAME);
    const cJSON *searched = cJSON_GetObjectItemCaseSensitive(maps[m], RS_TEXRES_MAPS_SEARCHED);
    if (!cJSON_IsArray(cand) || !cJSON_IsArray(ser) || cJSON_IsFalse(searched)) continue;
    /* the candidates judged (bisection leaves the others out): a value
     * judged on every view is measured; one whose judging stopped once it
     * failed (series_decided_early) is only a lower bound */
    int n = 0;
    for (int k = 0; k < cJSON_GetArraySize(cand) && n < MAX_POINTS; k++) {
      const cJSON *c = cJSON_GetArrayItem(cand, k), *v = cJSON_GetArrayItem(ser, k);
      const cJSON *w = cJSON_GetArrayItem(c, 0), *h = cJSON_GetArrayItem(c, 1);
      if (!cJSON_IsNumber(w) || !cJSON_IsNumber(h) || !cJSON_IsNumber(v)) continue;
      x[ns][n] = fmax(w->valuedouble, h->valuedouble);
      y[ns][n] = v->valuedouble;
      bound[ns][n] = cJSON_IsTrue(cJSON_GetArrayItem(early, k)) ? 1 : 0;
      n++;
    }
    if (!n) continue;
    s[ns] = (jnd_plot_series){.x = x[ns], .y = y[ns], .n = n, .label = cJSON_IsString(name) ? name->valuestring : NULL,
                              .colour = jnd_palette(ns), .line = 1, .markers = 1 + ns / 8, .bound = bound[ns]};
    ns++;
  }
  if (!ns) return 0;
  /* texres chooses against the choice line p·(1 − margin) (000 §6 with
   * --margin; texres.c's choice_p), not against p itself: with the default
   * margin 0.5 a size whose statistic lies between the two failed, and
   * without the choice line it would look as if it had passed (issue 25) */
  double p = jnd_json_number(report, RS_TEXRES_CRITERION_P), cp = jnd_json_number(report, RS_TEXRES_CHOICE_P);
  char plabel[64], clabel[96];
  snprintf(plabel, sizeof plabel, "criterion p = %g", p);
  snprintf(clabel, sizeof clabel, "choice line p(1 - margin) = %g: a size passes below it", cp);
  jnd_plot_hline lines[2] = {{.y = p, .label = plabel, .colour = {0.45f, 0.45f, 0.45f}},
                             {.y = cp, .label = clabel, .colour = {0.85f, 0.15f, 0.15f}}};
  int nlines = isfinite(p) ? 1 : 0;
  if (isfinite(cp) && cp > 0 && (!nlines || cp < p)) lines[nlines++] = lines[1];
  /* more maps than the plot tells apart: the title says which it shows
   * rather than leaving the rest out unsaid (the 6-material bench asset
   * has 24; issue 25) */
  char title[128] = "Each map alone: visibility against size";
  if (all > nm)
    snprintf(title, sizeof title, "Each map alone: visibility against size (the first %d of %d maps)", nm, all);
  jnd_plot_axes ax = {.title = title,
                      .xlabel = "longer side of the map (pixels)",
                      .ylabel = "criterion statistic (P)",
                      .log_x = 1,
                      .xmin = NAN, .xmax = NAN, .ymin = 0, .ymax = 1,
                      .width = 760, .height = 460,
                      .hlines = lines, .nhlines = nlines,
                      .bound_label = "judged until it failed: a lower bound"};
  return draw(&ax, s, ns, img, layout);
}

int jnd_plot_texres_series(const cJSON *report, const char *path) {
  jnd_image img;
  int r = jnd_plot_texres_series_image(report, &img, NULL);
  return r == 1 ? write_image(&img, path) : r;
}

int jnd_plot_pca_energy_image(const cJSON *report, jnd_image *img, jnd_plot_layout *layout) {
  memset(img, 0, sizeof *img);
  const cJSON *frac[MAX_POINTS], *cum[MAX_POINTS];
  int n = jnd_json_select(report, RS_PCA_ENERGY_FRACTION, frac, MAX_POINTS);
  int nc = jnd_json_select(report, RS_PCA_CUMULATIVE_ENERGY, cum, MAX_POINTS);
  if (n < 1 || n > MAX_POINTS || nc != n) return 0;
  double x[MAX_POINTS], f[MAX_POINTS], c[MAX_POINTS];
  for (int i = 0; i < n; i++) {
    x[i] = i + 1;
    f[i] = cJSON_IsNumber(frac[i]) ? frac[i]->valuedouble : NAN;
    c[i] = cJSON_IsNumber(cum[i]) ? cum[i]->valuedouble : NAN;
  }
  jnd_plot_series s[2] = {
      {.x = x, .y = f, .n = n, .label = "share of the energy", .colour = jnd_palette(0), .line = 1, .markers = 1},
      {.x = x, .y = c, .n = n, .label = "cumulative share", .colour = jnd_palette(1), .line = 1, .markers = 2}};
  double kept = jnd_json_number(report, RS_PCA_COMPONENTS_KEPT);
  int k = isfinite(kept) ? (int)kept : 0;
  char label[96];
  snprintf(label, sizeof label, "%d kept: %.1f %% of the energy", k, k >= 1 && k <= n ? 100 * c[k - 1] : 0.0);
  jnd_plot_mark mark = {.x = isfinite(kept) ? kept : NAN, .label = label, .colour = {0.8f, 0.1f, 0.1f}};
  jnd_plot_axes ax = {.title = "Energy of the principal components",
                      .xlabel = "component",
                      .ylabel = "fraction of the total variance",
                      .xmin = 1, .xmax = n > 1 ? n : 2, .ymin = 0, .ymax = 1,
                      .width = 760, .height = 440, .integer_x = 1,
                      .marks = &mark, .nmarks = isfinite(kept) ? 1 : 0};
  return draw(&ax, s, 2, img, layout);
}

int jnd_plot_pca_energy(const cJSON *report, const char *path) {
  jnd_image img;
  int r = jnd_plot_pca_energy_image(report, &img, NULL);
  return r == 1 ? write_image(&img, path) : r;
}
