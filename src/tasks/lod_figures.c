/* pareto_SCREEN.png of jnd lod (docs/lod.md): 003's two curves of one
 * screen, each over its largest value, against the triangles of each level
 * (log axis), with 003's knees, the rules of thumb and the perceptual
 * choice marked. The figure is built once (pareto_figure) and either drawn
 * or laid out, so that a test reads the same ticks, labels and marks the
 * picture holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"
#include "jnd.h"
#include "tasks/tasks.h"

#define PARETO_MAX_LEVELS 64

typedef struct {
  double x[PARETO_MAX_LEVELS], yu[PARETO_MAX_LEVELS], yl[PARETO_MAX_LEVELS];
  char lu[96], ll[96], title[160], mark_text[5][96];
  jnd_plot_series ser[2];
  jnd_plot_mark marks[5];
  jnd_plot_axes ax;
} pareto_figure;

static jnd_status pareto_build(const jnd_poi_result *r, int screen, int perceptual, pareto_figure *f) {
  if (screen < 0 || screen >= r->nscreens) return jnd_fail(JND_ERR_ARG, "pareto plot: screen %d out of range", screen);
  const jnd_poi_screen_result *R = &r->screens[screen];
  int n = R->nlevels;
  if (n < 1 || n > PARETO_MAX_LEVELS)
    return jnd_fail(JND_ERR_ARG, "pareto plot: %d levels (1 to %d)", n, PARETO_MAX_LEVELS);
  memset(f, 0, sizeof *f);
  double mu = 0, ml = 0;
  for (int k = 0; k < n; k++) {
    mu = fmax(mu, R->curve[k].error);
    ml = fmax(ml, R->curve[k].error_lit);
  }
  for (int k = 0; k < n; k++) {
    f->x[k] = (double)r->levels[k].triangles;
    f->yu[k] = mu > 0 ? R->curve[k].error / mu : 0;
    f->yl[k] = ml > 0 ? R->curve[k].error_lit / ml : 0;
  }
  char largest[2][32];
  /* the two scales of the y axis, in one format (not %g's 5.02e-05) */
  jnd_plot_number_labels((const double[2]){mu, ml}, 2, 3, largest);
  snprintf(f->lu, sizeof f->lu, "unlit, eq. 1 (largest %s)", largest[0]);
  snprintf(f->ll, sizeof f->ll, "lit, eq. 3 (largest %s)", largest[1]);
  f->ser[0] = (jnd_plot_series){
      .x = f->x, .y = f->yu, .n = n, .label = f->lu, .colour = jnd_palette(0), .line = 1, .markers = 1, .width = 2};
  f->ser[1] = (jnd_plot_series){
      .x = f->x, .y = f->yl, .n = n, .label = f->ll, .colour = jnd_palette(1), .line = 1, .markers = 1, .width = 2};
  snprintf(f->title, sizeof f->title, "003 Pareto curves: %s (%d x %d, %.0f px/deg)", R->screen.name,
           R->screen.width_px, R->screen.height_px, R->screen.ppd);
  const int level[4] = {R->poi_level, R->poi_level_unlit, R->meshopt_level, R->pixel_level};
  const char *name[4] = {"003 lit", "003 unlit", "meshopt", "px rule"};
  const int colour[4] = {1, 0, 2, 3};
  int nmarks = 0;
  for (int i = 0; i < 4; i++) {
    if (level[i] < 0 || level[i] >= n) continue;
    snprintf(f->mark_text[nmarks], sizeof f->mark_text[0], "%s %zu", name[i], r->levels[level[i]].triangles);
    f->marks[nmarks] = (jnd_plot_mark){f->x[level[i]], f->mark_text[nmarks], jnd_palette(colour[i])};
    nmarks++;
  }
  if (perceptual >= 0 && perceptual < n) {
    snprintf(f->mark_text[nmarks], sizeof f->mark_text[0], "perceptual %zu", r->levels[perceptual].triangles);
    f->marks[nmarks] = (jnd_plot_mark){f->x[perceptual], f->mark_text[nmarks], jnd_palette(4)};
    nmarks++;
  }
  f->ax.title = f->title;
  f->ax.xlabel = "triangles (level of detail)";
  f->ax.ylabel = "error / its largest value";
  f->ax.log_x = 1;
  f->ax.xmin = f->ax.xmax = NAN;
  f->ax.ymin = 0;
  f->ax.ymax = 1;
  f->ax.marks = f->marks;
  f->ax.nmarks = nmarks;
  return JND_OK;
}

jnd_status jnd_poi_pareto_plot(const jnd_poi_result *r, int screen, int perceptual, jnd_image *out) {
  return lod_pareto_plot(r, screen, perceptual, out, NULL);
}

jnd_status lod_pareto_plot(const jnd_poi_result *r, int screen, int perceptual, jnd_image *out,
                           jnd_plot_layout *layout) {
  pareto_figure *f = jnd_calloc(1, sizeof *f);
  if (!f) return jnd_fail(JND_ERR_NOMEM, "pareto plot: out of memory");
  jnd_status s = pareto_build(r, screen, perceptual, f);
  if (s == JND_OK && layout) s = jnd_plot_lines_layout(&f->ax, f->ser, 2, layout);
  if (s == JND_OK && out) s = jnd_plot_lines(&f->ax, f->ser, 2, out);
  free(f);
  return s;
}
