/* The perceptual choice and the switch distances of a level-of-detail
 * chain on one screen, asked of the judge (docs/lod.md "The perceptual
 * choice"; the judge is docs/judge.md). Beyond 003: where 003 takes the knee
 * of an error curve, this asks jnd's own vision model whether a viewer
 * notices each level against level 0, with 000 §9's criterion.
 *
 * Procedure:
 *  1. The screen: its display preset (or the standard-fhd display with the
 *     screen's pixels per degree) is the judge's display; the game's field
 *     of view spans its height. A view is rendered at the screen's own
 *     pixel scale: the central window_px × window_px part of the screen,
 *     the field of view narrowed to it, window_px the sphere's diameter at
 *     the nearest distance plus the judge's crop margins. Where that
 *     exceeds max_px, the screen is scaled down (pixels and pixels per
 *     degree alike) until the object fits: whole, the same angular size.
 *  2. Distances: a geometric grid from the viewing condition's distance d0
 *     (the sphere filling `coverage` of the height, or `distance`) out to
 *     where it fills far_coverage, ratio 1 + tolerance. Views at a grid
 *     distance are sampled (same seed, so the same directions at every
 *     distance) and added to the judge the first time they are needed,
 *     their references level 0.
 *  3. A test: level k selected (jnd_scene_lod_select), judged on the views
 *     of one distance with JND_JUDGE_DECIDE: passes when at most
 *     floor(q·n) views have P > p. Each (level, distance) is asked once.
 *  4. The perceptual level: the coarsest level passing at d0.
 *     lod_switch_search()
 *  5. Switch distances: level k's search starts at level k − 1's distance
 *     (monotone by construction), takes it when k passes there, gives up
 *     (INFINITY, and for every coarser level) when k fails at the far end,
 *     and bisects the grid otherwise: P falls with distance, so the
 *     nearest passing grid distance is within a factor 1 + tolerance of
 *     where the criterion starts to hold. A step asks a distance already
 *     judged near its bracket's middle first.  lod_switch_search()
 *  6. Popping (pop on; 004 §3.2 through jnd_pop_switch_distance): for each
 *     level k shown somewhere by step 5, the nearest distance at which the
 *     switch from level k − 1 to k, rendered on the same views (same seed
 *     and display; the window and pixel scale of step 1 where the search
 *     starts) with the chosen motion, has its largest
 *     rating R below pop_rating_limit — a continuous bisection on log
 *     distance to the same tolerance, assuming, as pop does, that popping
 *     fades with distance. It starts where step 5 and the finer level
 *     allow level k (nearer, popping cannot decide), so a switch that does
 *     not pop there costs one evaluation.
 *  7. A level's switch distance is the farthest of step 5's, step 6's and
 *     the finer level's (monotone): lod_switch_combine().
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "jnd.h"
#include "tasks/tasks.h"

void jnd_lod_switch_defaults(jnd_lod_switch_params *p) {
  memset(p, 0, sizeof *p);
  jnd_judge_defaults(&p->judge);
  p->judge.views.sampling.count = 4;
  p->coverage = 0.5;
  p->far_coverage = 0.02;
  p->tolerance = 0.1;
  p->max_px = 512;
  p->pop = 1;
  p->pop_motion = JND_POP_ORBIT;
  p->pop_speed = 0;          /* static: the switch seen by a viewer standing still */
  p->pop_rating_limit = 1;   /* 004 §3.2: R < 1 "rarely visible" */
}

const char *jnd_lod_switch_by_name(jnd_lod_switch_by b) {
  switch (b) {
  case JND_LOD_SWITCH_REFERENCE: return "reference";
  case JND_LOD_SWITCH_CRITERION: return "criterion";
  case JND_LOD_SWITCH_POP: return "popping";
  case JND_LOD_SWITCH_FINER: return "finer level";
  }
  return "?";
}

void jnd_lod_switch_result_free(jnd_lod_switch_result *r) {
  if (!r) return;
  free(r->statistic);
  free(r->p_max);
  free(r->switch_distance);
  free(r->switch_coverage);
  free(r->switch_distance_criterion);
  free(r->switch_scale);
  free(r->switch_distance_pop);
  free(r->pop_max_rating);
  free(r->switch_by);
  memset(r, 0, sizeof *r);
}

double jnd_coverage_at_distance(double radius, double distance, double fov_y_deg) {
  if (!isfinite(distance)) return 0;
  if (!(distance > radius)) return INFINITY;
  /* jnd_camera_distance_for_coverage: d = r / sin(atan(c·tan(fov/2))) */
  return tan(asin(radius / distance)) / tan(fov_y_deg * M_PI / 360);
}

/* A bisection step's distance in the bracket (lo, hi): its middle, or the
 * ready distance nearest to it (the nearer one on a tie) within the
 * bracket's middle half — a judge already made costs no references, and
 * the bracket still shrinks by at least a quarter. */
static int bisection_point(lod_ready_fn ready, void *user, int lo, int hi) {
  int mid = lo + (hi - lo) / 2;
  if (!ready || ready(user, mid)) return mid;
  for (int off = 1; off <= (hi - lo) / 4; off++) {
    if (ready(user, mid - off)) return mid - off;
    if (ready(user, mid + off)) return mid + off;
  }
  return mid;
}

/* step 5's search, and pop's (tasks.h) */
jnd_status switch_search(double lo, double hi, switch_test_fn test, switch_between_fn between, void *user,
                         switch_found *found, double *at, double *fail_at) {
  int r;
  *at = *fail_at = NAN;
  if ((r = test(user, lo)) < 0) return JND_ERR_INTERNAL;
  if (r) {
    *found = SWITCH_AT_START;
    *at = lo;
    return JND_OK;
  }
  *fail_at = lo;
  if (!(hi > lo) || (r = test(user, hi)) == 0) {   /* not even at the far end */
    *found = SWITCH_NEVER;
    *fail_at = hi > lo ? hi : lo;
    return JND_OK;
  }
  if (r < 0) return JND_ERR_INTERNAL;
  /* invariant: fails at lo, passes at hi */
  for (double mid; !isnan(mid = between(user, lo, hi));) {
    if ((r = test(user, mid)) < 0) return JND_ERR_INTERNAL;
    if (r) hi = mid;
    else lo = mid;
  }
  *found = SWITCH_FOUND;
  *at = hi;
  *fail_at = lo;
  return JND_OK;
}

/* lod_switch_search's grid as switch_search sees it: level k at grid index x */
typedef struct {
  lod_passes_fn passes;
  lod_ready_fn ready;
  void *user;
  int k;
} grid_search;

static int grid_test(void *user, double x) {
  grid_search *g = user;
  return g->passes(g->user, g->k, (int)x);
}

static double grid_between(void *user, double lo, double hi) {
  grid_search *g = user;
  return hi - lo > 1 ? bisection_point(g->ready, g->user, (int)lo, (int)hi) : NAN;
}

/* steps 4 and 5 on any pass/fail oracle (tasks.h) */
jnd_status lod_switch_search(int nlevels, int ngrid, lod_passes_fn passes, lod_ready_fn ready, void *user,
                             int *perceptual, int *switch_idx) {
  int r;
  *perceptual = 0;
  for (int k = nlevels - 1; k >= 1; k--) {
    if ((r = passes(user, k, 0)) < 0) return JND_ERR_INTERNAL;
    if (r) {
      *perceptual = k;
      break;
    }
  }
  switch_idx[0] = 0;
  int lo = 0;   /* level k − 1's grid index: no coarser level is shown nearer */
  for (int k = 1; k < nlevels; k++) {
    if (lo < 0) {
      switch_idx[k] = -1;
      continue;
    }
    grid_search g = {passes, ready, user, k};
    switch_found f;
    double at, fail_at;
    jnd_status st = switch_search(lo, ngrid - 1, grid_test, grid_between, &g, &f, &at, &fail_at);
    if (st != JND_OK) return st;
    /* never: not even at the far end, nor any coarser level */
    switch_idx[k] = lo = f == SWITCH_NEVER ? -1 : (int)at;
  }
  return JND_OK;
}

/* step 7 */
void lod_switch_combine(int nlevels, const double *criterion, const double *pop, double *out, jnd_lod_switch_by *by) {
  if (nlevels < 1) return;
  out[0] = 0;
  by[0] = JND_LOD_SWITCH_REFERENCE;
  for (int k = 1; k < nlevels; k++) {
    double d = criterion[k];
    by[k] = JND_LOD_SWITCH_CRITERION;
    if (out[k - 1] > d) {
      d = out[k - 1];
      by[k] = JND_LOD_SWITCH_FINER;
    }
    /* popping decides only beyond both: its search starts at the farther of
     * them, and a switch that does not pop there gets that very distance */
    if (pop[k] > d) {   /* NaN: no constraint */
      d = pop[k];
      by[k] = JND_LOD_SWITCH_POP;
    }
    out[k] = d;
  }
}

/* ---- the rendered oracle ---- */

typedef struct {
  jnd_scene *scene;
  const jnd_lod_switch_params *p;
  jnd_judge_params jp;       /* the judges' parameters but for the window, scale and distance */
  double screen_h, ppd, fov; /* the screen's height and pixels per degree, the game's field of view */
  double radius;             /* the bounding sphere's */
  int nviews, nlevels, ngrid;
  double *grid;              /* distances */
  jnd_judge **judge;         /* per grid point: its judge (NULL: not made yet) */
  jnd_view *views;           /* ngrid × nviews: each grid point's views, added to its judge as first asked */
  double *scale;             /* per grid point: the screen's scale its judge renders at */
  signed char *known;        /* nlevels × ngrid: −1 not asked, 0 fails, 1 passes */
  double *P, *z;             /* nviews: each view's P; for the criterion, 0 where not judged */
  jnd_lod_switch_result *out;
  jnd_status st;
} oracle;

/* Step 1 at one distance: the window (side R) and the screen's scale. The
 * object is rendered at the screen's own pixel scale wherever its diameter
 * plus the crop margins fits in max_px, in a window just that large; a
 * larger object is rendered whole, smaller, on a display with as many fewer
 * pixels per degree: it keeps its angular size and its silhouette (where a
 * coarser level shows first), at the price of the finest detail. */
static void window_at(double object_px, int max_px, int *R, double *scale) {
  object_window(object_px, 1, JUDGE_CROP_MARGIN, 0, max_px, 1, R, scale);
}

/* the object's diameter in the screen's pixels at distance d */
static double object_px_at(const oracle *o, double d) {
  return fmin(jnd_coverage_at_distance(o->radius, d, o->fov), 1.0) * o->screen_h;
}

/* The judges' parameters for views at distance d: step 1's window (side
 * *R) and screen scale (*scale) there, the window's field of view, its
 * pixels and the scaled display's pixels per degree. */
static jnd_judge_params params_at(const oracle *o, double d, int *Rp, double *scalep) {
  int R;
  double scale;
  window_at(object_px_at(o, d), o->p->max_px, &R, &scale);
  *Rp = R;
  *scalep = scale;
  jnd_judge_params jp = o->jp;
  jp.views.sampling.distance = d;
  jp.views.sampling.fov_y_deg = 2 * atan((double)R / (scale * o->screen_h) * tan(o->fov * M_PI / 360)) * 180 / M_PI;
  jp.views.sampling.aspect = 1;
  jp.views.render.width = jp.views.render.height = R;
  jp.model.display.ppd = o->ppd * scale;
  return jp;
}

/* The judge of grid point g: its window and scale from the object's size
 * there, its views sampled at that distance (the same seed, so the same
 * directions and lights at every distance), their references level 0. The
 * judge is made with the first view only; decide() adds the others when it
 * first asks them (a reference is a rendering of level 0, the finest and
 * dearest level, and most distances are decided by a view or two). */
static jnd_status judge_at(oracle *o, int g) {
  int R;
  jnd_judge_params jp = params_at(o, o->grid[g], &R, &o->scale[g]);
  jnd_view *v = o->views + (size_t)g * o->nviews;
  /* as jnd_view_set_make samples them for a judge of all the views */
  jnd_view_sampling vs = jp.views.sampling;
  vs.count = o->nviews;
  vs.aspect = 1;
  jnd_status st = jnd_views_sample(o->scene, &vs, v);
  jp.views.cameras = v;
  jp.views.ncameras = 1;
  if (!st) st = jnd_scene_lod_select(o->scene, 0);
  if (!st) st = jnd_judge_create(o->scene, &jp, &o->judge[g]);
  if (!st) o->out->distances++;
  return st;
}

/* jnd_judge_eval(JND_JUDGE_DECIDE) on grid point g's views, each view's
 * reference rendered when the view is first asked: the views in their own
 * order (DECIDE's order by the changed materials' pixels is the views' own
 * when only the level changes: a level changes no material's maps),
 * stopping once more than floor(q·n) have P > p; views not judged count as
 * P = 0 and the state fails. The same views judged, the same judgement. */
static jnd_status decide(oracle *o, int g, jnd_judgement *r) {
  jnd_judge *j = o->judge[g];
  const jnd_criterion *c = &o->jp.criterion;
  int n = o->nviews, allowed = (int)floor(c->q * n + 1e-9), above = 0, judged = 0;
  jnd_status st = JND_OK;
  for (int v = 0; v < n; v++) o->P[v] = NAN;
  for (int v = 0; v < n && above <= allowed && !st; v++) {
    if (v >= jnd_judge_view_count(j)) {
      st = jnd_judge_add_views(j, o->views + (size_t)g * n + v, 1, NULL);
      if (st) break;
    }
    if ((st = jnd_judge_eval(j, v, 1, 0, &o->P[v], NULL))) break;
    judged++;
    above += o->P[v] > c->p;
  }
  if (st) return st;
  for (int v = 0; v < n; v++) o->z[v] = isnan(o->P[v]) ? 0 : o->P[v];
  r->views = n;
  r->judged = judged;
  st = jnd_criterion_eval(o->z, n, c->p, c->q, c->confidence, &r->criterion);
  if (judged < n) r->criterion.pass = 0;
  return st;
}

static int rendered_ready(void *user, int g) {
  return ((oracle *)user)->judge[g] != NULL;
}

static int rendered_passes(void *user, int k, int g) {
  oracle *o = user;
  signed char *kn = &o->known[(size_t)k * o->ngrid + g];
  if (*kn >= 0) return *kn;
  jnd_status st = o->judge[g] ? JND_OK : judge_at(o, g);
  jnd_judgement r;
  if (!st) st = jnd_scene_lod_select(o->scene, k);
  if (!st) st = decide(o, g, &r);
  if (st) {
    o->st = st;
    return -1;
  }
  o->out->judgements++;
  *kn = (signed char)(r.criterion.pass != 0);
  if (g == 0) {
    double m = NAN;
    for (int v = 0; v < o->nviews; v++)
      if (!isnan(o->P[v]) && !(o->P[v] <= m)) m = o->P[v];
    o->out->statistic[k] = r.criterion.statistic;
    o->out->p_max[k] = m;
  }
  return *kn;
}

/* the judge's display for a screen: its preset, or standard-fhd's with the
 * screen's pixels and pixels per degree */
static void screen_display(const jnd_poi_screen *s, jnd_display *d) {
  const jnd_viewing_task task = d->task; /* the judge's, not the preset's */
  if (jnd_display_preset(s->name, d) == JND_OK && d->width_px == s->width_px && d->height_px == s->height_px &&
      fabs(d->ppd - s->ppd) < 1e-9) {
    d->task = task;
    return;
  }
  jnd_display_defaults(d);
  d->task = task;
  snprintf(d->name, sizeof d->name, "%s", s->name);
  d->ppd = s->ppd;
  d->width_px = s->width_px;
  d->height_px = s->height_px;
  d->diagonal_in = d->distance_m = 0;
}

/* step 6: where each switch stops popping, on the judges' renderer
 * (o->jp.renderer), display and view sampling. Each level's search is
 * rendered in the window and at the screen's scale of the distance where
 * it starts (step 1's rule: the object is largest there, so it fits at
 * every distance the search tries), the views sampled there; pop's
 * coverages are the window's: window_cov fractions of its height per
 * fraction of the screen's. */
static jnd_status pop_step(oracle *o, jnd_lod_switch_result *out) {
  const jnd_lod_switch_params *p = o->p;
  int n = out->nlevels;
  for (int k = 0; k < n; k++) out->switch_distance_pop[k] = out->pop_max_rating[k] = NAN;
  lod_switch_combine(n, out->switch_distance_criterion, out->switch_distance_pop, out->switch_distance, out->switch_by);
  if (!p->pop) return JND_OK;
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  mo.kind = (jnd_pop_motion_kind)p->pop_motion;
  mo.speed = p->pop_speed;
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  pp.picture = 0;
  jnd_pop_switch_params sp;
  jnd_pop_switch_defaults(&sp);
  sp.rating_limit = p->pop_rating_limit;
  sp.tolerance = p->tolerance;
  jnd_model *m = NULL;
  double m_scale = NAN;   /* the scale m's display was made for */
  jnd_view *views = jnd_calloc((size_t)o->nviews, sizeof *views);
  if (!views) return jnd_fail(JND_ERR_NOMEM, "lod: out of memory");
  jnd_status st = JND_OK;
  /* a level never shown (by (a), or after a level never shown) needs no search */
  for (int k = 1; k < n && !st && isfinite(out->switch_distance[k]); k++) {
    /* nearer than (a) and the finer level's distance, popping cannot
     * decide: the search starts there (one evaluation when the switch does
     * not pop there), out to far_coverage (a little beyond where that is
     * nearer than the start) */
    double from = fmax(out->switch_distance_criterion[k], out->switch_distance[k - 1]);
    int R;
    double scale;
    jnd_judge_params jp = params_at(o, from, &R, &scale);
    if (!(scale == m_scale)) {   /* the model's display has the scaled pixels per degree */
      jnd_model_free(m);
      m = NULL;
      if ((st = pop_model_create(&jp.model, &m))) break;   /* a switch in place: flicker */
      m_scale = scale;
    }
    if ((st = jnd_views_sample(o->scene, &jp.views.sampling, views))) break;
    if ((st = jnd_renderer_resize(o->jp.renderer, R, R))) break;
    double window_cov = scale * o->screen_h / R;
    double cfrom = jnd_coverage_at_distance(o->radius, from, o->fov);
    sp.coverage_near = cfrom * window_cov;
    sp.coverage_far = fmin(p->far_coverage, cfrom / (1 + p->tolerance)) * window_cov;
    jnd_pop_switch sw;
    /* the judge's window already frames the object: rendered whole, as the
     * judges' renderings are (the popping distance reproducible exactly) */
    sp.whole_frame = 1;
    if ((st = jnd_pop_switch_distance(m, o->jp.renderer, o->scene, views, o->nviews, &mo, k, &pp, &sp, &sw))) break;
    /* popping-free where the search started: that distance exactly (pop's is
     * the same up to the rounding of its coverage-to-distance conversion,
     * which must not make popping look decisive) */
    out->switch_distance_pop[k] = sw.status == JND_POP_SWITCH_NEAREST ? from : sw.distance;
    out->pop_max_rating[k] = sw.max_rating;
    out->pop_evaluations += sw.evaluations;
    lod_switch_combine(n, out->switch_distance_criterion, out->switch_distance_pop, out->switch_distance, out->switch_by);
  }
  jnd_model_free(m);
  free(views);
  return st;
}

jnd_status lod_switch_check(const jnd_lod_switch_params *p) {
  const jnd_view_sampling *s0 = &p->judge.views.sampling;
  if (s0->count < 1 || s0->count > JND_VIEWS_MAX)
    return jnd_fail(JND_ERR_ARG, "lod: %d views (1..%d)", s0->count, JND_VIEWS_MAX);
  if (!(p->distance > 0) && !(p->coverage > 0 && p->coverage <= 1))
    return jnd_fail(JND_ERR_ARG, "lod: coverage %g outside (0, 1]", p->coverage);
  if (!(p->far_coverage > 0 && p->far_coverage <= 1)) return jnd_fail(JND_ERR_ARG, "lod: far coverage %g outside (0, 1]", p->far_coverage);
  if (!(p->tolerance >= 0.001 && p->tolerance <= 10)) return jnd_fail(JND_ERR_ARG, "lod: tolerance %g outside [0.001, 10]", p->tolerance);
  if (p->max_px < 32 || p->max_px > 8192) return jnd_fail(JND_ERR_ARG, "lod: largest rendering %d px (32..8192)", p->max_px);
  if (p->pop && p->pop_motion != JND_POP_ORBIT && p->pop_motion != JND_POP_OBJECT && p->pop_motion != JND_POP_PAN)
    return jnd_fail(JND_ERR_ARG, "lod: the popping motion must be an orbit, a spin or a pan (degrees per second)");
  if (p->pop && (!isfinite(p->pop_speed) || !(p->pop_rating_limit > 0)))
    return jnd_fail(JND_ERR_ARG, "lod: popping speed %g or rating limit %g", p->pop_speed, p->pop_rating_limit);
  return JND_OK;
}

jnd_status jnd_lod_switch_analyse(jnd_scene *scene, const jnd_poi_screen *screen, const jnd_lod_switch_params *p,
                                  jnd_lod_switch_result *out) {
  memset(out, 0, sizeof *out);
  int n = jnd_scene_lod_count(scene);
  if (n < 2) return jnd_fail(JND_ERR_ARG, "%s: no levels of detail to compare (build or add a chain)", jnd_scene_path(scene));
  const jnd_view_sampling *s0 = &p->judge.views.sampling;
  double fov = s0->fov_y_deg > 0 ? s0->fov_y_deg : 45;
  jnd_status pst = lod_switch_check(p);
  if (pst != JND_OK) return pst;
  if (screen->height_px < 1 || !(screen->ppd > 0)) return jnd_fail(JND_ERR_ARG, "lod: screen '%s' needs pixels and pixels per degree", screen->name);

  /* steps 1 and 2 */
  double centre[3], radius;
  int ground;
  jnd_scene_subject_bounds(scene, centre, &radius, &ground);
  double d0 = p->distance > 0 ? p->distance : jnd_camera_distance_for_coverage(radius, p->coverage, fov);
  if (!(d0 > radius * 1.0001)) d0 = radius * 1.0001;
  double dfar = jnd_camera_distance_for_coverage(radius, p->far_coverage, fov);
  int ngrid = 1;
  if (dfar > d0 * (1 + p->tolerance)) ngrid = (int)ceil(log(dfar / d0) / log1p(p->tolerance)) + 1;
  if (ngrid > 4096) return jnd_fail(JND_ERR_ARG, "lod: %d distances to search (tolerance too small)", ngrid);
  out->screen = *screen;
  out->nlevels = n;
  out->view_distance = d0;
  out->view_coverage = jnd_coverage_at_distance(radius, d0, fov);

  oracle o;
  memset(&o, 0, sizeof o);
  o.scene = scene;
  o.p = p;
  o.nviews = s0->count;
  o.nlevels = n;
  o.ngrid = ngrid;
  o.out = out;
  o.screen_h = screen->height_px;
  o.ppd = screen->ppd;
  o.fov = fov;
  o.radius = radius;
  /* the judges: the screen's display, the views sampled as asked */
  o.jp = p->judge;
  o.jp.views.cameras = NULL;
  o.jp.views.cameras_path = NULL;
  o.jp.views.ncameras = 0;
  screen_display(screen, &o.jp.model.display);
  o.ppd = o.jp.model.display.ppd;
  o.grid = jnd_alloc((size_t)ngrid, sizeof *o.grid);
  o.judge = jnd_calloc((size_t)ngrid, sizeof *o.judge);
  o.views = jnd_calloc((size_t)ngrid * o.nviews, sizeof *o.views);
  o.scale = jnd_alloc((size_t)ngrid, sizeof *o.scale);
  o.known = jnd_alloc((size_t)n * ngrid, 1);
  o.P = jnd_alloc((size_t)o.nviews, sizeof *o.P);
  o.z = jnd_alloc((size_t)o.nviews, sizeof *o.z);
  int *idx = jnd_alloc((size_t)n, sizeof *idx);
  out->statistic = jnd_alloc((size_t)n, sizeof *out->statistic);
  out->p_max = jnd_alloc((size_t)n, sizeof *out->p_max);
  out->switch_distance = jnd_alloc((size_t)n, sizeof *out->switch_distance);
  out->switch_coverage = jnd_alloc((size_t)n, sizeof *out->switch_coverage);
  out->switch_distance_criterion = jnd_alloc((size_t)n, sizeof *out->switch_distance_criterion);
  out->switch_scale = jnd_alloc((size_t)n, sizeof *out->switch_scale);
  out->switch_distance_pop = jnd_alloc((size_t)n, sizeof *out->switch_distance_pop);
  out->pop_max_rating = jnd_alloc((size_t)n, sizeof *out->pop_max_rating);
  out->switch_by = jnd_alloc((size_t)n, sizeof *out->switch_by);
  jnd_status st = JND_OK;
  if (!o.grid || !o.judge || !o.views || !o.scale || !o.known || !o.P || !o.z || !idx || !out->statistic || !out->p_max || !out->switch_distance ||
      !out->switch_coverage || !out->switch_distance_criterion || !out->switch_scale || !out->switch_distance_pop ||
      !out->pop_max_rating || !out->switch_by)
    st = jnd_fail(JND_ERR_NOMEM, "lod: out of memory");
  if (!st) {
    for (int g = 0; g < ngrid; g++) o.grid[g] = g == ngrid - 1 && ngrid > 1 ? dfar : d0 * pow(1 + p->tolerance, g);
    memset(o.known, -1, (size_t)n * ngrid);
    for (int k = 0; k < n; k++) out->statistic[k] = out->p_max[k] = out->switch_scale[k] = NAN;
    out->statistic[0] = out->p_max[0] = 0;   /* the reference: P = 0 by definition */
    window_at(object_px_at(&o, d0), p->max_px, &out->window_px, &out->scale);
  }
  /* One renderer for every distance's judge and for popping, sized to each
   * window in turn: one context, environment and uploaded scene instead of
   * one per distance (made here unless the caller lends one, e.g. for all
   * screens). Made first: it tells a missing renderer early. */
  jnd_renderer *own = NULL;
  if (!st && !o.jp.renderer) {
    if (!(st = judge_renderer(&o.jp.views.render, out->window_px, &own))) o.jp.renderer = own;
  }
  if (!st) st = judge_at(&o, 0);
  if (!st) {
    st = lod_switch_search(n, ngrid, rendered_passes, rendered_ready, &o, &out->perceptual_level, idx);
    if (st) st = o.st ? o.st : st;
  }
  if (!st)
    for (int k = 0; k < n; k++) {
      out->switch_distance_criterion[k] = k == 0 ? 0 : idx[k] < 0 ? INFINITY : o.grid[idx[k]];
      if (k > 0 && idx[k] >= 0) out->switch_scale[k] = o.scale[idx[k]];
    }
  /* the judges' counts, summed; the judges freed (not the renderer, which popping uses next) */
  for (int g = 0; g < ngrid && o.judge; g++) {
    if (!o.judge[g]) continue;
    jnd_judge_counts c;
    jnd_judge_get_counts(o.judge[g], &c);
    out->counts.references += c.references;
    out->counts.renderings += c.renderings;
    out->counts.partial_renderings += c.partial_renderings;
    out->counts.view_judgements += c.view_judgements;
    out->counts.states += c.states;
    out->counts.reused += c.reused;
    jnd_judge_free(o.judge[g]);
  }
  if (!st) st = pop_step(&o, out);
  if (!st)
    for (int k = 0; k < n; k++)
      out->switch_coverage[k] = k == 0 ? 1 : jnd_coverage_at_distance(radius, out->switch_distance[k], fov);
  jnd_scene_lod_select(scene, 0);
  jnd_renderer_free(own);
  free(o.grid);
  free(o.judge);
  free(o.views);
  free(o.scale);
  free(o.known);
  free(o.P);
  free(o.z);
  free(idx);
  if (st) jnd_lod_switch_result_free(out);
  return st;
}
