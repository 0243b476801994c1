/* pareto.png of a budget (docs/budget.md): every candidate's texture memory
 * against its criterion statistic, one series per mesh level, the Pareto
 * front of (memory, triangles, statistic), the choice and the separately
 * chosen pair marked (and, where step 7 took the separate one, the joint
 * search's own choice; the choices dropped on held-out views, step 6), the
 * criterion's p as a line; drawn with the shared
 * line plot (io/draw.h). The figure is built once (budget_build) and either
 * drawn or laid out, so that a test reads the ticks, labels and points the
 * picture holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/core.h"
#include "io/draw.h"
#include "jnd.h"
#include "tasks/tasks.h"

#define MAX_SERIES 14
#define MAX_LEVEL_GROUPS 8

typedef struct {
  double *x, *y; /* MAX_SERIES blocks of n values (owned) */
  char labels[MAX_SERIES][96];
  jnd_plot_series s[MAX_SERIES];
  int ns;
  jnd_plot_hline h;
  jnd_plot_axes ax;
} budget_figure;

static void budget_figure_free(budget_figure *f) {
  free(f->x);
  free(f->y);
}

static jnd_status budget_build(const jnd_budget_result *r, const jnd_criterion *c, budget_figure *f) {
  int n = r->ncandidates;
  if (n < 1) return jnd_fail(JND_ERR_ARG, "budget: no candidates to draw");
  if (r->chosen < 0 || r->chosen >= n || r->separate < 0 || r->separate >= n ||
      (r->separate_taken && (r->joint < 0 || r->joint >= n)))
    return jnd_fail(JND_ERR_ARG, "budget: the chosen, separate or joint candidate is out of range");
  f->x = jnd_calloc((size_t)n * MAX_SERIES, sizeof *f->x);
  f->y = jnd_calloc((size_t)n * MAX_SERIES, sizeof *f->y);
  if (!f->x || !f->y) return jnd_fail(JND_ERR_NOMEM, "budget: out of memory");
  static const jnd_rgb level_colour[MAX_LEVEL_GROUPS] = {
      {0.55f, 0.55f, 0.55f}, {0.45f, 0.62f, 0.80f}, {0.60f, 0.78f, 0.55f}, {0.85f, 0.70f, 0.45f},
      {0.75f, 0.55f, 0.80f}, {0.50f, 0.75f, 0.75f}, {0.80f, 0.60f, 0.60f}, {0.70f, 0.70f, 0.40f}};
  double *x = f->x, *y = f->y;
  int ns = 0, nlev = 0;
  /* the levels the candidates use (the chain's coarser levels, never a
   * candidate, are not in the picture) */
  for (int i = 0; i < n; i++)
    if (r->candidates[i].level + 1 > nlev) nlev = r->candidates[i].level + 1;
  /* the ladder's points per level (at most 8 levels drawn apart, the rest together) */
  int groups = nlev < MAX_LEVEL_GROUPS ? nlev : MAX_LEVEL_GROUPS;
  for (int g = 0; g < groups; g++) {
    int m = 0;
    size_t tris = 0;
    for (int i = 0; i < n; i++) {
      const jnd_budget_candidate *q = &r->candidates[i];
      int grp = q->level < groups - 1 ? q->level : groups - 1;
      if (q->level == g) tris = q->triangles;
      if (grp != g || !isfinite(q->statistic)) continue;
      x[ns * n + m] = q->memory_bytes / 1048576.0;
      y[ns * n + m] = q->statistic;
      m++;
    }
    if (m == 0) continue;
    snprintf(f->labels[ns], sizeof f->labels[ns],
             g == groups - 1 && nlev > groups ? "levels %d.. (%zu triangles and fewer)" : "level %d (%zu triangles)", g, tris);
    f->s[ns] = (jnd_plot_series){.x = x + ns * n, .y = y + ns * n, .n = m, .label = f->labels[ns],
                                 .colour = level_colour[g], .markers = 2};
    ns++;
  }
  /* the front (in memory order; drawn as points: its third axis, triangles, is the series) */
  int m = 0;
  for (int i = 0; i < n; i++)
    if (r->candidates[i].pareto && isfinite(r->candidates[i].statistic)) {
      double mx = r->candidates[i].memory_bytes / 1048576.0, my = r->candidates[i].statistic;
      int j = m++;
      for (; j > 0 && x[ns * n + j - 1] > mx; j--) {
        x[ns * n + j] = x[ns * n + j - 1];
        y[ns * n + j] = y[ns * n + j - 1];
      }
      x[ns * n + j] = mx;
      y[ns * n + j] = my;
    }
  if (m > 0) {
    f->s[ns] = (jnd_plot_series){.x = x + ns * n, .y = y + ns * n, .n = m,
                                 .label = "Pareto front (memory, triangles, statistic)",
                                 .colour = {0.13f, 0.13f, 0.13f}, .markers = 1};
    ns++;
  }
  const jnd_budget_candidate *sep = &r->candidates[r->separate], *ch = &r->candidates[r->chosen];
  double *px = x + ns * n, *py = y + ns * n;
  px[0] = sep->memory_bytes / 1048576.0;
  py[0] = sep->statistic;
  px[1] = ch->memory_bytes / 1048576.0;
  py[1] = ch->statistic;
  snprintf(f->labels[ns], sizeof f->labels[ns], "texres + pca + lod separately (level %d)", sep->level);
  snprintf(f->labels[ns + 1], sizeof f->labels[ns + 1],
           r->separate_taken ? "chosen: the separate one (level %d)" : "chosen (level %d)", ch->level);
  /* the two are often a few bytes apart: the separate choice's marker is
   * drawn larger, beneath, so that it rings the chosen one where they meet */
  f->s[ns] = (jnd_plot_series){.x = px, .y = py, .n = 1, .label = f->labels[ns], .colour = {0.15f, 0.35f, 0.85f},
                               .markers = 1, .width = 12};
  f->s[ns + 1] = (jnd_plot_series){.x = px + 1, .y = py + 1, .n = 1, .label = f->labels[ns + 1],
                                   .colour = {0.85f, 0.15f, 0.15f}, .markers = 1, .width = 6};
  ns += 2;
  /* the choices seen on their held-out views and dropped (step 6) */
  int nd = 0;
  for (int i = 0; i < n; i++)
    if (r->candidates[i].held_out_fail && isfinite(r->candidates[i].statistic)) {
      x[ns * n + nd] = r->candidates[i].memory_bytes / 1048576.0;
      y[ns * n + nd] = r->candidates[i].statistic;
      nd++;
    }
  if (nd > 0) {
    f->s[ns] = (jnd_plot_series){.x = x + ns * n, .y = y + ns * n, .n = nd,
                                 .label = "seen on its held-out views: dropped", .colour = {0.55f, 0.20f, 0.60f},
                                 .markers = 2, .width = 10};
    ns++;
  }
  /* the joint search's own choice, where the separate one was taken instead (step 7) */
  if (r->separate_taken) {
    const jnd_budget_candidate *jo = &r->candidates[r->joint];
    x[ns * n] = jo->memory_bytes / 1048576.0;
    y[ns * n] = jo->statistic;
    /* taken where it is cheaper, or where the joint one is seen (budget_take_separate) */
    snprintf(f->labels[ns], sizeof f->labels[ns], "the joint search's own, %s (level %d)",
             jo->cost > ch->cost ? "dearer" : "seen on its held-out views", jo->level);
    f->s[ns] = (jnd_plot_series){.x = x + ns * n, .y = y + ns * n, .n = 1, .label = f->labels[ns],
                                 .colour = {0.90f, 0.55f, 0.10f}, .markers = 1, .width = 8};
    ns++;
  }
  f->ns = ns;
  f->h = (jnd_plot_hline){.y = c->p, .label = "criterion p", .colour = {0.85f, 0.15f, 0.15f}};
  f->ax = (jnd_plot_axes){.title = "Budget: texture memory against visibility, per mesh level",
                          .xlabel = "texture memory (MiB: unique images, mip chains, block formats)",
                          .ylabel = "criterion statistic (view quantile of pooled P)",
                          .log_x = 1, .xmin = NAN, .xmax = NAN, .ymin = 0, .ymax = NAN, .hlines = &f->h,
                          .nhlines = 1, .width = 900, .height = 560};
  return JND_OK;
}

jnd_status budget_pareto_plot(const jnd_budget_result *r, const jnd_criterion *c, jnd_image *out,
                              jnd_plot_layout *layout) {
  budget_figure *f = jnd_calloc(1, sizeof *f);
  if (!f) return jnd_fail(JND_ERR_NOMEM, "budget: out of memory");
  jnd_status st = budget_build(r, c, f);
  if (st == JND_OK && layout) st = jnd_plot_lines_layout(&f->ax, f->s, f->ns, layout);
  if (st == JND_OK && out) st = jnd_plot_lines(&f->ax, f->s, f->ns, out);
  budget_figure_free(f);
  free(f);
  return st;
}

jnd_status jnd_budget_pareto_plot(const jnd_budget_result *r, const jnd_criterion *c, jnd_image *out) {
  return budget_pareto_plot(r, c, out, NULL);
}
