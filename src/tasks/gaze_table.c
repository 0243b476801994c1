/* 002's lookup table L(distance, eccentricity) and the engine's lookup.
 *
 * Procedure (002 "Gaze-contingent LOD prediction", eqs. 9–10):
 *  1. Per distance d: the object's bounding sphere (radius r) subtends
 *     2 asin(r/d); the rendering is a square window a little larger, at the
 *     display's pixels per degree within [min_px, max_px] pixels.  gaze_frame_for()
 *  1b. Where that window would need more than max_px (a near object), the
 *     object is judged instead on windows of max_px at the display's ppd:
 *     centred on the fixation point where it falls on the object, else on
 *     the silhouette facing the gaze (the leftmost covered pixel of level
 *     0's whole-object rendering, nearest the centre row); the fixation
 *     points are projected onto their windows.  near_windows()
 *  2. Per orientation (jnd_views_sample at distance d, seeded): every level
 *     of the chain rendered once, colour and coverage.
 *  3. Per eccentricity e: the fixation point e degrees left of the object's
 *     centre; each level k's spatial P against level 0 (jnd_gaze_spatial) and
 *     the switch k − 1 → k (jnd_gaze_switch); the worst orientation decides.
 *  4. The level: the coarsest k whose two probabilities are both below the
 *     threshold (eqs. 9, 10); level 0 when none is.  choose_levels()
 *  5. Monotone: L(d, e) = min over d' ≥ d, e' ≥ e of step 4's level, so the
 *     level never gets finer as the object moves away or out of the gaze —
 *     the safe direction: it can only make a choice finer.
 * Away from near objects the renderings do not depend on e: only the
 * vision model's fixation point moves, so the renderings cost distances ×
 * orientations × levels (a near object's windows on the fixation point add
 * a level set per such e).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"
#include "jnd.h"
#include "tasks/tasks.h"

#define GAZE_MAX_AXIS 256
#define GAZE_WINDOW_MARGIN 1.2   /* the window is this times the sphere's angular diameter */

void jnd_gaze_table_defaults(jnd_gaze_table_params *p) {
  memset(p, 0, sizeof *p);
  p->build_chain = 1;
  p->orientations = 8;
  p->seed = 1;
  p->threshold = 0.75;   /* 002: the 2AFC midpoint */
  p->min_px = 64;
  p->max_px = 192;
  p->near_window = 1;
  jnd_gaze_model_defaults(&p->model);
  jnd_gaze_measure_defaults(&p->measure);
  jnd_renderer_defaults(&p->render);
}

void jnd_gaze_table_free(jnd_gaze_table *t) {
  if (!t) return;
  free(t->distances_m);
  free(t->eccentricities_deg);
  free(t->level);
  free(t->level_raw);
  free(t->p_spatial);
  free(t->p_switch);
  free(t->ppd);
  free(t->side_px);
  free(t->windowed);
  free(t->triangles);
  memset(t, 0, sizeof *t);
}

jnd_status gaze_check_axis(const double *v, int n, const char *flag, double lo, int lo_open, double hi) {
  if (!v || n < 1 || n > GAZE_MAX_AXIS) return jnd_fail(JND_ERR_ARG, "%s: give 1 to %d values", flag, GAZE_MAX_AXIS);
  for (int i = 0; i < n; i++) {
    if (!isfinite(v[i]) || (lo_open ? v[i] <= lo : v[i] < lo) || v[i] > hi)
      return jnd_fail(JND_ERR_ARG, "%s: %g is outside %s%g, %g]", flag, v[i], lo_open ? "(" : "[", lo, hi);
    if (i && v[i] <= v[i - 1]) return jnd_fail(JND_ERR_ARG, "%s: values must ascend (%g after %g)", flag, v[i], v[i - 1]);
  }
  return JND_OK;
}

/* Step 1: the window (vertical field of view, degrees), its side in pixels
 * and the pixels per degree at its centre. */
void gaze_frame_for(double ppd_display, int min_px, int max_px, double radius, double d, double *fov_deg, int *side,
                    double *ppd) {
  double object_deg = 2.0 * asin(radius / d) * 180.0 / M_PI * GAZE_WINDOW_MARGIN;
  double fov = fmax(object_deg, min_px / ppd_display);
  /* its side: the object window's (a larger object keeps fov on max_px) */
  int n;
  double scale;
  object_window(fov * ppd_display, 1, 0, min_px, max_px, 0, &n, &scale);
  /* focal length in pixels, and a pixel's angle at the centre */
  double f = 0.5 * n / tan(0.5 * fov * M_PI / 180.0);
  *fov_deg = fov;
  *side = n;
  *ppd = 1.0 / (atan(1.0 / f) * 180.0 / M_PI);
}

/* Step 4: the coarsest level with both probabilities below the threshold. */
static int coarsest_below(const double *p_spatial, const double *p_switch, int nlevels, double threshold) {
  int best = 0;
  for (int k = 1; k < nlevels; k++)
    if (p_spatial[k] < threshold && p_switch[k] < threshold) best = k;
  return best;
}

/* Step 5: L(d, e) = min over d' ≥ d, e' ≥ e of the raw level. */
static void make_monotone(const int *raw, int nd, int ne, int *level) {
  for (int d = nd - 1; d >= 0; d--)
    for (int e = ne - 1; e >= 0; e--) {
      int l = raw[d * ne + e];
      if (d + 1 < nd && level[(d + 1) * ne + e] < l) l = level[(d + 1) * ne + e];
      if (e + 1 < ne && level[d * ne + e + 1] < l) l = level[d * ne + e + 1];
      level[d * ne + e] = l;
    }
}

static void choose_levels(jnd_gaze_table *t, double threshold) {
  int L = t->nlevels;
  for (int i = 0; i < t->nd * t->ne; i++)
    t->level_raw[i] = coarsest_below(t->p_spatial + (size_t)i * L, t->p_switch + (size_t)i * L, L, threshold);
  make_monotone(t->level_raw, t->nd, t->ne, t->level);
}

jnd_status gaze_render_levels(jnd_scene *scene, jnd_renderer *r, const jnd_view *views, int no, int L,
                              gaze_renders *R, int *count) {
  jnd_status st = JND_OK;
  for (int k = 0; k < L && st == JND_OK; k++) {
    for (int o = 0; o < no && st == JND_OK; o++) {
      jnd_view v = views[o];
      v.outputs = JND_OUT_COLOR | JND_OUT_MASK;
      v.background_env = 0;
      jnd_frame f;
      memset(&f, 0, sizeof f);
      if ((st = judge_render_level(r, scene, k, &v, &f)) != JND_OK) break;
      R->color[o * L + k] = f.color;
      R->mask[o * L + k] = f.mask;
      f.color.data = f.mask.data = NULL;
      jnd_frame_free(&f);
      (*count)++;
    }
  }
  jnd_scene_lod_select(scene, 0);
  return st;
}

/* ---- step 1b: a near object's window at the display's ppd ---- */

static void vsub(const double *a, const double *b, double *o) { o[0] = a[0] - b[0], o[1] = a[1] - b[1], o[2] = a[2] - b[2]; }
static double vdot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void vcross(const double *a, const double *b, double *o) {
  o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}
static void vnorm(double *a) {
  double n = sqrt(vdot(a, a));
  if (n > 0) a[0] /= n, a[1] /= n, a[2] /= n;
}

/* a camera's forward, right and up unit vectors (image x right, y down) */
static void camera_basis(const jnd_camera *c, double *fwd, double *right, double *up) {
  vsub(c->target, c->eye, fwd);
  vnorm(fwd);
  vcross(fwd, c->up, right);
  vnorm(right);
  vcross(right, fwd, up);
}

/* The silhouette pixel the gaze meets first when it lies off the object:
 * gaze points lie left of the object's centre, so the leftmost covered
 * pixel of the row nearest the centre that has one. 0 when nothing is
 * covered. */
static int edge_facing_gaze(const jnd_image *mask, double *x, double *y) {
  const int w = mask->w, h = mask->h, cy = h / 2;
  for (int dy = 0; dy <= h / 2; dy++)
    for (int sgn = 0; sgn < 2; sgn++) {
      int row = sgn ? cy - dy : cy + dy;
      if (row < 0 || row >= h || (sgn && dy == 0)) continue;
      for (int c = 0; c < w; c++)
        if (mask->data[(size_t)row * w + c] > 0.5f) {
          *x = c, *y = row;
          return 1;
        }
    }
  return 0;
}

/* The windows of one orientation of a near object (step 1b). base: the
 * whole-object view (fov degrees over side pixels) whose level-0 coverage
 * is mask. Per eccentricity e the fixation point lies ecc[e] degrees left of
 * the object's centre; its window is centred on the fixation point where
 * that falls on the object (the object around the fovea is what is judged
 * there), else on the silhouette facing the gaze (one window serves every
 * such e). Fills win[0..*nwin) (at most ne + 1), which[e] and the fixation
 * point gaze[2e], gaze[2e + 1] in window which[e]'s pixels. */
static void near_windows(const jnd_view *base, const jnd_image *mask, double fov, int side, double win_fov,
                         const double *ecc, int ne, jnd_view *win, int *nwin, int *which, double *gaze) {
  double fwd[3], right[3], up[3], to_target[3];
  camera_basis(&base->camera, fwd, right, up);
  vsub(base->camera.target, base->camera.eye, to_target);
  const double dist = sqrt(vdot(to_target, to_target));
  const double f = 0.5 * side / tan(0.5 * fov * M_PI / 180.0), c = 0.5 * side - 0.5;
  const double fw = 0.5 * side / tan(0.5 * win_fov * M_PI / 180.0);
  int edge = -1;
  *nwin = 0;
  for (int e = 0; e < ne; e++) {
    double t = tan(ecc[e] * M_PI / 180.0), g[3], d[3];
    for (int i = 0; i < 3; i++) g[i] = fwd[i] - right[i] * t;
    /* where the fixation point falls in the whole-object rendering */
    int gx = (int)lround(c - f * t), gy = (int)lround(c);
    int on = gx >= 0 && gx < side && mask->data[(size_t)gy * side + gx] > 0.5f;
    if (!on && edge >= 0) {
      which[e] = edge;
    } else {
      double ex = c, ey = c;
      if (on) {
        memcpy(d, g, sizeof d);
      } else {
        edge_facing_gaze(mask, &ex, &ey);
        for (int i = 0; i < 3; i++) d[i] = fwd[i] + right[i] * (ex - c) / f - up[i] * (ey - c) / f;
      }
      vnorm(d);
      jnd_view *v = &win[*nwin];
      *v = *base;
      for (int i = 0; i < 3; i++) v->camera.target[i] = v->camera.eye[i] + dist * d[i];
      v->camera.fov_y_deg = win_fov;
      which[e] = (*nwin)++;
      if (!on) edge = which[e];
    }
    /* the fixation point projected onto its window's image plane */
    double wf[3], wr[3], wu[3];
    camera_basis(&win[which[e]].camera, wf, wr, wu);
    double z = vdot(g, wf);
    gaze[2 * e] = c + fw * vdot(g, wr) / z;
    gaze[2 * e + 1] = c - fw * vdot(g, wu) / z;
  }
}

jnd_status jnd_gaze_table_run(jnd_scene *scene, const jnd_gaze_table_params *p, jnd_gaze_table *out) {
  memset(out, 0, sizeof *out);
  jnd_status st;
  static const double default_ecc[] = {0, 5, 10, 15, 20, 30, 40, 60};
  static const double default_radii[] = {4, 6, 9, 14, 22, 34, 54, 96};
  static const double default_errors[] = {1.0 / 1024, 1.0 / 256, 1.0 / 64};
  jnd_gaze_table_params q = *p;
  double centre[3], radius, dist[8];
  jnd_scene_subject_bounds(scene, centre, &radius, NULL);
  if (!(radius > 0)) return jnd_fail(JND_ERR_FORMAT, "%s: the model has no extent", jnd_scene_path(scene));
  if (!q.distances_m) {
    for (int i = 0; i < 8; i++) dist[i] = default_radii[i] * radius;
    q.distances_m = dist, q.ndistances = 8;
  }
  if (!q.eccentricities_deg) q.eccentricities_deg = default_ecc, q.neccentricities = 8;
  p = &q;
  if ((st = gaze_check_axis(p->distances_m, p->ndistances, "--distances", 0, 1, 1e6)) != JND_OK) return st;
  if ((st = gaze_check_axis(p->eccentricities_deg, p->neccentricities, "--eccentricities", 0, 0, 90)) != JND_OK) return st;
  if (p->orientations < 1 || p->orientations > 256) return jnd_fail(JND_ERR_ARG, "--orientations: give 1 to 256");
  if (!(p->threshold > 0.5 && p->threshold < 1))
    return jnd_fail(JND_ERR_ARG, "--threshold: %g is outside (0.5, 1) (a 2AFC proportion)", p->threshold);
  if (p->min_px < 16 || p->max_px < p->min_px || p->max_px > 4096)
    return jnd_fail(JND_ERR_ARG, "gaze: rendering sides must satisfy 16 <= min <= max <= 4096");
  for (int d = 0; d < p->ndistances; d++)
    if (p->distances_m[d] <= radius * 1.01)
      return jnd_fail(JND_ERR_ARG, "--distances: %g m is inside the object's bounding sphere (radius %.4g m)",
                      p->distances_m[d], radius);
  if (jnd_scene_lod_count(scene) < 2 && p->build_chain) {
    jnd_lod_params lp;
    jnd_lod_defaults(&lp);
    lp.errors = default_errors, lp.nerrors = 3;
    if ((st = jnd_scene_lod_build(scene, p->chain ? p->chain : &lp)) != JND_OK) return st;
  }
  const int L = jnd_scene_lod_count(scene), nd = p->ndistances, ne = p->neccentricities, no = p->orientations;
  if (L < 2)
    return jnd_fail(JND_ERR_ARG, "%s: the chain has one level (nothing simpler could be made); a table needs two",
                    jnd_scene_path(scene) ? jnd_scene_path(scene) : "MODEL");
  out->nd = nd, out->ne = ne, out->nlevels = L, out->orientations = no;
  out->distances_m = jnd_alloc((size_t)nd, sizeof(double));
  out->eccentricities_deg = jnd_alloc((size_t)ne, sizeof(double));
  out->level = jnd_calloc((size_t)nd * ne, sizeof(int));
  out->level_raw = jnd_calloc((size_t)nd * ne, sizeof(int));
  out->p_spatial = jnd_calloc((size_t)nd * ne * L, sizeof(double));
  out->p_switch = jnd_calloc((size_t)nd * ne * L, sizeof(double));
  out->ppd = jnd_calloc((size_t)nd, sizeof(double));
  out->side_px = jnd_calloc((size_t)nd, sizeof(int));
  out->windowed = jnd_calloc((size_t)nd, sizeof(int));
  out->triangles = jnd_calloc((size_t)L, sizeof(size_t));
  /* the renderings: per view (an orientation's whole object, or one of its
   * near windows: at most ne + 1 per orientation) × level */
  const size_t maxviews = (size_t)no * (ne + 1);
  gaze_renders R = {jnd_calloc(maxviews * L, sizeof(jnd_image)), jnd_calloc(maxviews * L, sizeof(jnd_image))};
  jnd_view *views = jnd_calloc((size_t)no, sizeof *views), *wviews = jnd_calloc(maxviews, sizeof *wviews);
  double *gaze = jnd_calloc((size_t)no * ne * 2, sizeof(double));   /* per orientation and eccentricity: x, y */
  int *which = jnd_calloc((size_t)no * ne, sizeof(int));           /* ... and the view it is judged on */
  if (!out->distances_m || !out->eccentricities_deg || !out->level || !out->level_raw || !out->p_spatial ||
      !out->p_switch || !out->ppd || !out->side_px || !out->windowed || !out->triangles || !R.color || !R.mask || !views ||
      !wviews || !gaze || !which) {
    free(R.color), free(R.mask), free(views), free(wviews), free(gaze), free(which);
    jnd_gaze_table_free(out);
    return JND_ERR_NOMEM;
  }
  memcpy(out->distances_m, p->distances_m, (size_t)nd * sizeof(double));
  memcpy(out->eccentricities_deg, p->eccentricities_deg, (size_t)ne * sizeof(double));
  for (int k = 0; k < L; k++) {
    jnd_lod_level_info li;
    if (jnd_scene_lod_info(scene, k, &li) == JND_OK) out->triangles[k] = li.triangles;
  }

  jnd_renderer *r = NULL;
  st = judge_renderer(&p->render, p->min_px, &r);
  /* one judge of pairs for the run: a model per distance's ppd and per
   * thread, not one per pair */
  jnd_gaze_measure_params mp = p->measure;
  mp.model.threads = 1;   /* the tasks run in parallel instead: small images scale poorly by rows */
  jnd_pair_judge *judge = NULL;
  if (st == JND_OK && !mp.judge) st = jnd_pair_judge_create(&mp.model, &judge), mp.judge = judge;
  if (st == JND_OK) snprintf(out->renderer, sizeof out->renderer, "%s", jnd_renderer_description(r));
  /* every (orientation, eccentricity, level, spatial|switch) of a distance is one task */
  const int ntask = no * ne * (L - 1) * 2, total = nd * (no * L + ntask);
  double *task_p = jnd_alloc((size_t)(ntask ? ntask : 1), sizeof(double));
  if (!task_p) st = JND_ERR_NOMEM;
  int done = 0;
  for (int d = 0; d < nd && st == JND_OK; d++) {
    double fov, ppd;
    int side;
    gaze_frame_for(p->measure.model.display.ppd, p->min_px, p->max_px, radius, p->distances_m[d], &fov, &side, &ppd);
    out->ppd[d] = ppd;
    out->side_px[d] = side;
    jnd_view_sampling vs;
    jnd_view_sampling_defaults(&vs);
    vs.count = no;
    vs.seed = p->seed;
    vs.distance = p->distances_m[d];
    vs.fov_y_deg = fov;
    vs.aspect = 1;
    if ((st = jnd_views_sample(scene, &vs, views)) != JND_OK) break;
    if ((st = jnd_renderer_resize(r, side, side)) != JND_OK) break;
    const double ppd_display = p->measure.model.display.ppd, cx = 0.5 * side - 0.5;
    int nviews = 0;
    if (p->near_window && ppd < 0.99 * ppd_display) {
      /* step 1b: the whole object would need more than max_px: judge
       * windows of max_px at the display's ppd (level 0's coverage of the
       * whole-object rendering places them) */
      gaze_renders O = {jnd_calloc((size_t)no, sizeof(jnd_image)), jnd_calloc((size_t)no, sizeof(jnd_image))};
      if (!O.color || !O.mask) st = JND_ERR_NOMEM;
      if (st == JND_OK) st = gaze_render_levels(scene, r, views, no, 1, &O, &out->renderings);
      const double win_fov = side / ppd_display;
      for (int o = 0; o < no && st == JND_OK; o++) {
        int nw = 0;
        near_windows(&views[o], &O.mask[o], fov, side, win_fov, p->eccentricities_deg, ne, wviews + nviews, &nw,
                     which + (size_t)o * ne, gaze + (size_t)o * ne * 2);
        for (int e = 0; e < ne; e++) which[(size_t)o * ne + e] += nviews;
        nviews += nw;
      }
      for (int o = 0; O.color && O.mask && o < no; o++) jnd_image_free(&O.color[o]), jnd_image_free(&O.mask[o]);
      free(O.color), free(O.mask);
      if (st != JND_OK) break;
      ppd = 1.0 / (atan(tan(0.5 * win_fov * M_PI / 180.0) / (0.5 * side)) * 180.0 / M_PI);
      out->ppd[d] = ppd;
      out->windowed[d] = 1;
    } else {
      const double dist_px = 1.0 / tan(M_PI / 180.0 / ppd);
      memcpy(wviews, views, (size_t)no * sizeof *views);
      nviews = no;
      for (int o = 0; o < no; o++)
        for (int e = 0; e < ne; e++) {
          which[(size_t)o * ne + e] = o;
          gaze[((size_t)o * ne + e) * 2] = cx - dist_px * tan(p->eccentricities_deg[e] * M_PI / 180.0);
          gaze[((size_t)o * ne + e) * 2 + 1] = cx;
        }
    }
    if ((st = gaze_render_levels(scene, r, wviews, nviews, L, &R, &out->renderings)) != JND_OK) break;
    done += no * L;
    if (p->progress) p->progress(p->progress_user, done, total);
    jnd_status tst = JND_OK;
#pragma omp parallel for schedule(dynamic, 1)
    for (int t = 0; t < ntask; t++) {
      int kind = t % 2, k = 1 + (t / 2) % (L - 1), e = (t / 2 / (L - 1)) % ne, o = t / 2 / (L - 1) / ne;
      const double gx = gaze[((size_t)o * ne + e) * 2], gy = gaze[((size_t)o * ne + e) * 2 + 1];
      const size_t view = (size_t)which[(size_t)o * ne + e];
      const jnd_image *c = R.color + view * L, *m = R.mask + view * L;
      jnd_gaze_terms terms;
      jnd_status s = kind == 0 ? jnd_gaze_spatial(&p->model, &mp, ppd, gx, gy, &c[0], &m[0], &c[k], &m[k], &terms)
                               : jnd_gaze_switch(&p->model, &mp, ppd, gx, gy, &c[k - 1], &m[k - 1], &c[k], &m[k], &terms);
      task_p[t] = terms.p;
      if (s != JND_OK) {
#pragma omp critical(gaze_status)
        tst = tst == JND_OK ? s : tst;
      }
    }
    if ((st = tst) != JND_OK) break;
    /* the worst orientation, in a fixed order */
    for (int e = 0; e < ne; e++) {
      double *ps = out->p_spatial + ((size_t)d * ne + e) * L, *pw = out->p_switch + ((size_t)d * ne + e) * L;
      ps[0] = pw[0] = 0.5;
      for (int k = 1; k < L; k++) {
        ps[k] = pw[k] = 0.5;
        for (int o = 0; o < no; o++) {
          int t = 2 * (((o * ne) + e) * (L - 1) + (k - 1));
          ps[k] = fmax(ps[k], task_p[t]);
          pw[k] = fmax(pw[k], task_p[t + 1]);
        }
      }
    }
    for (size_t i = 0; i < maxviews * L; i++) jnd_image_free(&R.color[i]), jnd_image_free(&R.mask[i]);
    done += ntask;
    if (p->progress) p->progress(p->progress_user, done, total);
  }
  for (size_t i = 0; i < maxviews * L; i++) jnd_image_free(&R.color[i]), jnd_image_free(&R.mask[i]);
  free(R.color), free(R.mask), free(views), free(wviews), free(task_p), free(gaze), free(which);
  jnd_renderer_free(r);
  jnd_pair_judge_free(judge);
  if (st != JND_OK) {
    jnd_gaze_table_free(out);
    return st;
  }
  choose_levels(out, p->threshold);
  return JND_OK;
}

jnd_status jnd_gaze_table_write_csv(const jnd_gaze_table *t, const char *path) {
  size_t cap = 128 + (size_t)t->nd * t->ne * 96, n = 0;
  char *buf = malloc(cap);
  if (!buf) return JND_ERR_NOMEM;
  n += (size_t)snprintf(buf + n, cap - n, "distance_m,eccentricity_deg,level,level_raw,p_spatial,p_switch\n");
  for (int d = 0; d < t->nd; d++)
    for (int e = 0; e < t->ne; e++) {
      size_t i = (size_t)d * t->ne + e;
      int l = t->level[i];
      n += (size_t)snprintf(buf + n, cap - n, "%.9g,%.9g,%d,%d,%.6f,%.6f\n", t->distances_m[d],
                            t->eccentricities_deg[e], l, t->level_raw[i], t->p_spatial[i * t->nlevels + l],
                            t->p_switch[i * t->nlevels + l]);
    }
  jnd_status st = jnd_write_file_atomic(path, buf, n);
  free(buf);
  return st;
}

jnd_status jnd_gaze_table_figure(const jnd_gaze_table *t, double threshold, const char *length_unit,
                                 jnd_image *out) {
  size_t cells = (size_t)t->nd * t->ne;
  double *v = jnd_calloc(cells, sizeof *v);
  char *text = jnd_calloc(cells, 8), (*rl)[32] = jnd_calloc((size_t)t->nd, 32), (*cl)[32] = jnd_calloc((size_t)t->ne, 32);
  const char **ct = jnd_calloc(cells, sizeof *ct), **rows = jnd_calloc((size_t)t->nd, sizeof *rows),
             **cols = jnd_calloc((size_t)t->ne, sizeof *cols);
  jnd_status st = JND_ERR_NOMEM;
  if (v && text && rl && cl && ct && rows && cols) {
    /* one number format per axis, the unit in the axis's title */
    jnd_plot_number_labels(t->distances_m, t->nd, 3, rl);
    jnd_plot_number_labels(t->eccentricities_deg, t->ne, 3, cl);
    for (int d = 0; d < t->nd; d++) rows[d] = rl[d];
    for (int e = 0; e < t->ne; e++) cols[e] = cl[e];
    for (size_t i = 0; i < cells; i++) {
      v[i] = t->level[i];
      snprintf(text + 8 * i, 8, "%d", t->level[i]);
      ct[i] = text + 8 * i;
    }
    char title[128], row_title[64];
    snprintf(title, sizeof title, "L(d, ecc): coarsest level with P below %.3g (0 = finest of %d)", threshold,
             t->nlevels);
    snprintf(row_title, sizeof row_title, "distance from the eye (%s)", length_unit ? length_unit : "object units");
    jnd_plot_grid_spec g = {.rows = t->nd, .cols = t->ne, .value = v, .cell_text = ct, .row_labels = rows,
                            .col_labels = cols, .title = title, .row_title = row_title,
                            .col_title = "eccentricity from the gaze (\u00b0)", .scale_title = "level",
                            .vmin = 0, .vmax = t->nlevels - 1, .integer_scale = 1};
    st = jnd_plot_grid(&g, out);
  }
  free(v), free(text), free(rl), free(cl), free(ct), free(rows), free(cols);
  return st;
}
