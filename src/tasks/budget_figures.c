/* pareto.png of a budget (docs/budget.md): every candidate's texture memory
 * against its criterion statistic, one series per mesh level, the Pareto
 * front of (memory, triangles, statistic), the choice and the separately
 * chosen pair marked, the criterion's p as a line; drawn with the shared
 * line plot (io/draw.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/core.h"
#include "io/draw.h"

#define MAX_SERIES 12

jnd_status jnd_budget_pareto_plot(const jnd_budget_result *r, const jnd_criterion *c, jnd_image *out) {
  int n = r->ncandidates;
  if (n < 1) return jnd_fail(JND_ERR_ARG, "budget: no candidates to draw");
  double *x = jnd_calloc((size_t)n * (MAX_SERIES + 1), sizeof *x), *y = jnd_calloc((size_t)n * (MAX_SERIES + 1), sizeof *y);
  if (!x || !y) {
    free(x);
    free(y);
    return jnd_fail(JND_ERR_NOMEM, "budget: out of memory");
  }
  static const jnd_rgb level_colour[8] = {{0.55f, 0.55f, 0.55f}, {0.45f, 0.62f, 0.80f}, {0.60f, 0.78f, 0.55f},
                                          {0.85f, 0.70f, 0.45f}, {0.75f, 0.55f, 0.80f}, {0.50f, 0.75f, 0.75f},
                                          {0.80f, 0.60f, 0.60f}, {0.70f, 0.70f, 0.40f}};
  jnd_plot_series s[MAX_SERIES];
  char labels[MAX_SERIES][96];
  int ns = 0, nlev = jnd_scene_lod_count(r->lod.scene);
  /* the ladder's points per level (at most 8 levels drawn apart, the rest together) */
  int groups = nlev < 8 ? nlev : 8;
  for (int g = 0; g < groups; g++) {
    int m = 0;
    for (int i = 0; i < n; i++) {
      const jnd_budget_candidate *q = &r->candidates[i];
      int grp = q->level < groups - 1 ? q->level : groups - 1;
      if (grp != g || !isfinite(q->statistic)) continue;
      x[ns * n + m] = q->memory_bytes / 1048576.0;
      y[ns * n + m] = q->statistic;
      m++;
    }
    if (m == 0) continue;
    size_t tris = 0;
    for (int i = 0; i < n; i++)
      if (r->candidates[i].level == g) tris = r->candidates[i].triangles;
    snprintf(labels[ns], sizeof labels[ns], g == groups - 1 && nlev > groups ? "levels %d.. (%zu triangles and fewer)" : "level %d (%zu triangles)",
             g, tris);
    s[ns] = (jnd_plot_series){.x = x + ns * n, .y = y + ns * n, .n = m, .label = labels[ns],
                              .colour = level_colour[g % 8], .markers = 2};
    ns++;
  }
  /* the front (in memory order; drawn as points: its third axis, triangles, is the series) */
  int m = 0;
  for (int i = 0; i < n; i++)
    if (r->candidates[i].pareto) {
      double mx = r->candidates[i].memory_bytes / 1048576.0, my = r->candidates[i].statistic;
      int j = m++;
      for (; j > 0 && x[ns * n + j - 1] > mx; j--) {
        x[ns * n + j] = x[ns * n + j - 1];
        y[ns * n + j] = y[ns * n + j - 1];
      }
      x[ns * n + j] = mx;
      y[ns * n + j] = my;
    }
  s[ns] = (jnd_plot_series){.x = x + ns * n, .y = y + ns * n, .n = m, .label = "Pareto front (memory, triangles, statistic)",
                            .colour = {0.13f, 0.13f, 0.13f}, .markers = 1};
  ns++;
  const jnd_budget_candidate *sep = &r->candidates[r->separate], *ch = &r->candidates[r->chosen];
  double *px = x + ns * n, *py = y + ns * n;
  px[0] = sep->memory_bytes / 1048576.0;
  py[0] = sep->statistic;
  px[1] = ch->memory_bytes / 1048576.0;
  py[1] = ch->statistic;
  char lsep[96], lch[96];
  snprintf(lsep, sizeof lsep, "texres + lod separately (level %d)", sep->level);
  snprintf(lch, sizeof lch, "chosen (level %d)", ch->level);
  /* the two are often a few bytes apart: the separate choice's marker is
   * drawn larger, beneath, so that it rings the chosen one where they meet */
  s[ns++] = (jnd_plot_series){.x = px, .y = py, .n = 1, .label = lsep, .colour = {0.15f, 0.35f, 0.85f}, .markers = 1,
                              .width = 12};
  s[ns++] = (jnd_plot_series){.x = px + 1, .y = py + 1, .n = 1, .label = lch, .colour = {0.85f, 0.15f, 0.15f},
                              .markers = 1, .width = 6};
  jnd_plot_hline h = {.y = c->p, .label = "criterion p", .colour = {0.85f, 0.15f, 0.15f}};
  jnd_plot_axes ax = {.title = "Budget: texture memory against visibility, per mesh level",
                      .xlabel = "texture memory (MiB: unique images, mip chains, block formats)",
                      .ylabel = "criterion statistic (view quantile of pooled P)",
                      .log_x = 1, .xmin = NAN, .xmax = NAN, .ymin = 0, .ymax = NAN, .hlines = &h, .nhlines = 1,
                      .width = 900, .height = 560};
  jnd_status st = jnd_plot_lines(&ax, s, ns, out);
  free(x);
  free(y);
  return st;
}
