/* Popping of rendered switches (004 §3, issue 12 items 5–6): jnd renders
 * the switching frame itself and decides switch distances.
 *
 *   1. a motion (camera orbit or translation, or the object spinning) gives
 *      the view at every frame; frame f is at f / fps
 *   2. the pair: the frame rendered with level + 1 (004: "the actually
 *      rendered frame") and with level (004: "rendering the frame again but
 *      utilizing the previous LOD"), with motion vectors from the previous
 *      frame's pose and depth
 *   3. disocclusion inputs (004 §4): the previous frame's depth for both
 *      levels, and each pixel's depth as the previous camera saw it
 *      (reprojected from this frame's depth, not approximated by it)
 *   3b. flicker inputs (004 §4): the previous frame as shown (the previous
 *      level, the previous pose) and this frame's pixels of the previous
 *      level shaded with the previous pose's setup (jnd_view.shade_prev)
 *   4. jnd_pop_predict on the pair
 *   5. decisions: per level and speed, the nearest camera distance at which
 *      the largest R over the views stays below 1, by bisection on log
 *      distance (switch_search, the search jnd lod uses on its grid), beside
 *      meshoptimizer's 1-pixel rule
 *
 * docs/pop.md sets each step next to 004's text. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"
#include "render/render.h"
#include "tasks/tasks.h"

/* ---- 1. motion ---- */

void jnd_pop_motion_defaults(jnd_pop_motion *m) {
  memset(m, 0, sizeof *m);
  m->kind = JND_POP_ORBIT;
  m->direction[0] = 1;
  m->unit_m = 1;
}

/* p rotated by deg about +Y through c (counter-clockwise seen from above) */
static void rotate_y(const double p[3], const double c[3], double deg, double out[3]) {
  double a = deg * M_PI / 180, cs = cos(a), sn = sin(a), x = p[0] - c[0], z = p[2] - c[2];
  out[0] = c[0] + x * cs + z * sn;
  out[1] = p[1];
  out[2] = c[2] - x * sn + z * cs;
}

/* the camera's axes as the renderer's look-at makes them: right, up, forward */
static void camera_axes(const jnd_camera *c, double s[3], double u[3], double f[3]) {
  double v[16];
  jnd_mat4_look_at(c->eye, c->target, c->up, v);
  for (int k = 0; k < 3; k++) {
    s[k] = v[k * 4 + 0];
    u[k] = v[k * 4 + 1];
    f[k] = -v[k * 4 + 2];
  }
}

void jnd_pop_motion_pose(const jnd_view *view, const jnd_pop_motion *m, double t, jnd_view *out) {
  *out = *view;
  if (m->speed == 0 || t == 0) return;
  const jnd_camera *c = &view->camera;
  if (m->kind == JND_POP_ORBIT) {
    rotate_y(c->eye, c->target, m->speed * t, out->camera.eye);
  } else if (m->kind == JND_POP_PAN) {
    rotate_y(c->target, c->eye, m->speed * t, out->camera.target);
  } else if (m->kind == JND_POP_TRANSLATE) {
    double s[3], u[3], f[3], d[3], len = 0;
    camera_axes(c, s, u, f);
    for (int k = 0; k < 3; k++) {
      d[k] = m->direction[0] * s[k] + m->direction[1] * u[k] - m->direction[2] * f[k];
      len += d[k] * d[k];
    }
    double step = len > 0 ? m->speed * t / (m->unit_m > 0 ? m->unit_m : 1) / sqrt(len) : 0;
    for (int k = 0; k < 3; k++) {
      out->camera.eye[k] += step * d[k];
      out->camera.target[k] += step * d[k];
    }
  } else {
    /* model' = T(c) R_y T(−c) model: the columns of model as points and directions */
    double r[16], o[3] = {0, 0, 0};
    for (int col = 0; col < 4; col++) {
      const double *src = view->model + col * 4;
      double p[3] = {src[0], src[1], src[2]};
      if (col < 3) {
        rotate_y(p, o, m->speed * t, r + col * 4);
      } else {
        /* translation: (p − c) rotated + c, with p = the column (w = 1) */
        rotate_y(p, c->target, m->speed * t, r + col * 4);
      }
      r[col * 4 + 3] = src[3];
    }
    memcpy(out->model, r, sizeof r);
  }
}

/* ---- 2–4. the pair ---- */

/* 3. each pixel's surface point (depth along cur's view axis) as prev's camera
 * sees it: unprojected through cur's camera, carried by the object's motion
 * (prev model × cur model⁻¹), depth along prev's view axis; 0 stays 0 */
static jnd_status reproject_depth(const jnd_image *depth, const jnd_view *cur, const jnd_view *prev, jnd_image *out) {
  int w = depth->w, h = depth->h;
  jnd_status st = jnd_image_alloc(out, w, h, 1);
  if (st) return st;
  double s[3], u[3], f[3], ps[3], pu[3], pf[3], inv[16], carry[16];
  camera_axes(&cur->camera, s, u, f);
  camera_axes(&prev->camera, ps, pu, pf);
  if (!jnd_mat4_invert(cur->model, inv)) return jnd_fail(JND_ERR_ARG, "pop: the view's model matrix is singular");
  jnd_mat4_mul(prev->model, inv, carry);
  double ty = tan((cur->camera.fov_y_deg > 0 ? cur->camera.fov_y_deg : 45) * M_PI / 360), tx = ty * w / h;
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      float z = depth->data[(size_t)y * w + x];
      float *o = out->data + (size_t)y * w + x;
      if (!(z > 0)) {
        *o = 0;
        continue;
      }
      double nx = (2.0 * (x + 0.5) / w - 1) * tx * z, ny = (1 - 2.0 * (y + 0.5) / h) * ty * z, p[3], q[3];
      for (int k = 0; k < 3; k++) p[k] = cur->camera.eye[k] + s[k] * nx + u[k] * ny + f[k] * z;
      for (int k = 0; k < 3; k++)
        q[k] = carry[k] * p[0] + carry[4 + k] * p[1] + carry[8 + k] * p[2] + carry[12 + k];
      double d = 0;
      for (int k = 0; k < 3; k++) d += (q[k] - prev->camera.eye[k]) * pf[k];
      *o = d > 0 ? (float)d : 0;
    }
  return JND_OK;
}

/* A frame rendered in a window of the view's frame (pop_window): every
 * image of it placed at the window's spot in a W × H image whose other
 * pixels are the background's (0 in colour, coverage, depth and motion),
 * so that the predictor sees the frame's own pixels. */
typedef struct {
  int side;      /* the window's side, centred in the frame; 0: the whole frame is rendered */
  int W, H;      /* the frame */
  double fov;    /* the frame's field of view (the view's is the window's) */
} pop_frame_window;

static jnd_status unwindow(const pop_frame_window *win, jnd_frame *f) {
  if (!win || win->side <= 0) return JND_OK;
  jnd_image *im[] = {&f->color, &f->depth, &f->mask, &f->motion};
  int ox = (win->W - win->side) / 2, oy = (win->H - win->side) / 2;
  for (size_t k = 0; k < sizeof im / sizeof *im; k++) {
    if (!im[k]->data) continue;
    jnd_image big = {0};
    jnd_status st = jnd_image_alloc(&big, win->W, win->H, im[k]->c);   /* zeroed */
    if (st) return st;
    for (int c = 0; c < im[k]->c; c++)
      for (int y = 0; y < im[k]->h; y++)
        memcpy(big.data + ((size_t)c * win->H + oy + y) * win->W + ox,
               im[k]->data + ((size_t)c * im[k]->h + y) * im[k]->w, (size_t)im[k]->w * sizeof(float));
    jnd_image_free(im[k]);
    *im[k] = big;
  }
  return JND_OK;
}

static jnd_status pop_render_in(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *view,
                                const jnd_pop_motion *mo, int level, int frame, const jnd_pop_params *p,
                                const pop_frame_window *win, jnd_pop_result *out) {
  memset(out, 0, sizeof *out);
  int n = jnd_scene_lod_count(scene), keep = jnd_scene_lod_selected(scene);
  if (level < 0 || level + 1 >= n)
    return jnd_fail(JND_ERR_ARG, "pop: level %d: the switch needs levels %d and %d; the chain has %d", level, level,
                    level + 1, n);
  if (!(mo->speed == mo->speed) || !isfinite(mo->speed)) return jnd_fail(JND_ERR_ARG, "pop: the speed is not finite");
  double fps = jnd_model_get_params(m)->fps;
  int moving = mo->speed != 0;
  jnd_view cur, prev;
  jnd_pop_motion_pose(view, mo, frame / fps, &cur);
  jnd_pop_motion_pose(view, mo, (frame - 1) / fps, &prev);
  cur.has_prev = moving;
  cur.prev_camera = prev.camera;
  memcpy(cur.prev_model, prev.model, sizeof cur.prev_model);
  /* depth only for the disocclusion inputs of a moving view (3): for a
   * static one it would be a second drawing of each level for nothing */
  cur.outputs = JND_OUT_COLOR | JND_OUT_MASK | (moving ? JND_OUT_DEPTH | JND_OUT_MOTION : 0);
  prev.has_prev = 0;
  prev.outputs = JND_OUT_DEPTH;
  /* 3b: the previous frame is the expected level's: it also needs its colour;
   * and the expected level at this pose, shaded as in the previous one */
  jnd_view prev_e = prev, shade = cur;
  prev_e.outputs = JND_OUT_DEPTH | JND_OUT_COLOR;
  shade.shade_prev = 1;
  shade.outputs = JND_OUT_COLOR;

  jnd_frame fa = {0}, fe = {0}, pa = {0}, pe = {0}, fs = {0};
  jnd_image ca = {0}, ce = {0}, za = {0}, ze = {0}, mask = {0}, cp = {0}, cs = {0};
  /* the new level's frames first, then the old level's: two level changes per pair */
  jnd_status st = judge_render_level(r, scene, level + 1, &cur, &fa);
  if (!st && moving) st = judge_render_level(r, scene, level + 1, &prev, &pa);
  if (!st) st = judge_render_level(r, scene, level, &cur, &fe);
  if (!st && moving) st = judge_render_level(r, scene, level, &prev_e, &pe);
  if (!st && moving) st = judge_render_level(r, scene, level, &shade, &fs);
  jnd_status sel = jnd_scene_lod_select(scene, keep);
  if (!st) st = sel;
  jnd_frame *rendered[] = {&fa, &fe, &pa, &pe, &fs};
  for (size_t k = 0; k < sizeof rendered / sizeof *rendered && !st; k++) st = unwindow(win, rendered[k]);
  /* 4: each frame as the viewer sees it, as the judge shows frames */
  const jnd_display *d = &jnd_model_get_params(m)->display;
  if (!st) st = jnd_judge_show(d, &fa.color, NULL, 0, NULL, &ca, NULL);
  if (!st) st = jnd_judge_show(d, &fe.color, NULL, 0, NULL, &ce, NULL);
  if (!st && moving) st = jnd_judge_show(d, &pe.color, NULL, 0, NULL, &cp, NULL);
  if (!st && moving) st = jnd_judge_show(d, &fs.color, NULL, 0, NULL, &cs, NULL);
  /* the depth is the frame's again: so is the field of view it unprojects with */
  jnd_view cur_f = cur, prev_f = prev;
  if (win && win->side > 0) cur_f.camera.fov_y_deg = prev_f.camera.fov_y_deg = win->fov;
  if (!st && moving) st = reproject_depth(&fa.depth, &cur_f, &prev_f, &za);
  if (!st && moving) st = reproject_depth(&fe.depth, &cur_f, &prev_f, &ze);
  if (!st) st = jnd_image_alloc(&mask, fa.mask.w, fa.mask.h, 1);
  if (!st) {
    size_t np = (size_t)mask.w * mask.h;
    for (size_t i = 0; i < np; i++) mask.data[i] = fmaxf(fa.mask.data[i], fe.mask.data[i]) > 0.5f ? 1.0f : 0.0f;
    jnd_pop_inputs in;
    memset(&in, 0, sizeof in);
    in.actual = (jnd_pop_frame){&ca, moving ? &fa.motion : NULL, moving ? &za : NULL, moving ? &pa.depth : NULL};
    in.expected = (jnd_pop_frame){&ce, moving ? &fe.motion : NULL, moving ? &ze : NULL, moving ? &pe.depth : NULL};
    in.mask = &mask;
    in.prev_color = moving ? &cp : NULL;
    in.prev_shading = moving ? &cs : NULL;
    st = jnd_pop_predict(m, &in, p, out);
  }
  jnd_frame_free(&fa);
  jnd_frame_free(&fe);
  jnd_frame_free(&pa);
  jnd_frame_free(&pe);
  jnd_frame_free(&fs);
  jnd_image_free(&cp);
  jnd_image_free(&cs);
  jnd_image_free(&ca);
  jnd_image_free(&ce);
  jnd_image_free(&za);
  jnd_image_free(&ze);
  jnd_image_free(&mask);
  return st;
}

jnd_status jnd_pop_render(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *view,
                          const jnd_pop_motion *mo, int level, int frame, const jnd_pop_params *p,
                          jnd_pop_result *out) {
  return pop_render_in(m, r, scene, view, mo, level, frame, p, NULL, out);
}

/* the field of view of a centred window of side pixels in a frame H high seen with fov */
static double window_fov(double fov, int side, int H) {
  return 2 * atan((double)side / H * tan(fov * M_PI / 360)) * 180 / M_PI;
}

jnd_status pop_render_window(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *view,
                             const jnd_pop_motion *mo, int level, int frame, const jnd_pop_params *p, int side,
                             jnd_pop_result *out) {
  int W, H;
  jnd_renderer_size(r, &W, &H);
  if (side <= 0) return pop_render_in(m, r, scene, view, mo, level, frame, p, NULL, out);
  memset(out, 0, sizeof *out);
  if (side > W || side > H || (W - side) % 2 || (H - side) % 2)
    return jnd_fail(JND_ERR_ARG, "pop: a window of %d pixels is not centred in a %d × %d frame", side, W, H);
  double fov = view->camera.fov_y_deg > 0 ? view->camera.fov_y_deg : 45;
  pop_frame_window win = {side, W, H, fov};
  jnd_view at = *view;
  at.camera.fov_y_deg = window_fov(fov, side, H);
  jnd_status st = jnd_renderer_resize(r, side, side);
  if (!st) st = pop_render_in(m, r, scene, &at, mo, level, frame, p, &win, out);
  jnd_status back = jnd_renderer_resize(r, W, H);
  if (!st) st = back;
  if (st) jnd_pop_result_free(out);
  return st;
}

/* ---- 5. decisions ---- */

void jnd_pop_switch_defaults(jnd_pop_switch_params *p) {
  memset(p, 0, sizeof *p);
  p->rating_limit = 1.0; /* 004 §3.2: R < 1 "rarely visible" */
  p->tolerance = 0.05;
  p->coverage_near = 1.0;
  p->coverage_far = 0.02;
}

/* the view at camera distance d from its target, along its own direction */
static void at_distance(const jnd_view *v, double d, jnd_view *out) {
  *out = *v;
  double dir[3], len = 0;
  for (int k = 0; k < 3; k++) {
    dir[k] = v->camera.eye[k] - v->camera.target[k];
    len += dir[k] * dir[k];
  }
  len = sqrt(len);
  for (int k = 0; k < 3; k++) out->camera.eye[k] = v->camera.target[k] + (len > 0 ? dir[k] / len : k == 2) * d;
  /* clip distances set for the view's own distance move with the camera */
  if (v->camera.znear > 0 && v->camera.zfar > v->camera.znear) {
    out->camera.znear = fmax(v->camera.znear + d - len, d * 1e-3);
    out->camera.zfar = v->camera.zfar + d - len;
  }
}

/* the largest R over the views at distance d (−inf: no region); stops at the
 * first view at or above the limit, which decides already. The views are
 * asked from *first on (then in order, wrapping): the caller passes the
 * view that failed last, which at a popping distance usually fails again. */
static jnd_status max_rating_at(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *views, int nviews,
                                const jnd_pop_motion *mo, int level, const jnd_pop_params *p,
                                const jnd_pop_switch_params *sp, double d, double fov_y_deg,
                                const pop_frame_window *win, int *first, double *worst) {
  jnd_pop_params q = *p;
  q.picture = 0;
  *worst = -INFINITY;
  for (int i = 0; i < nviews; i++) {
    int v = (*first + i) % nviews;
    jnd_view at;
    jnd_pop_result res;
    at_distance(&views[v], d, &at);
    if (fov_y_deg > 0) at.camera.fov_y_deg = fov_y_deg;
    jnd_status st = pop_render_in(m, r, scene, &at, mo, level - 1, sp->frame, &q, win, &res);
    if (st) return st;
    if (res.nregions && res.max_rating > *worst) *worst = res.max_rating;
    jnd_pop_result_free(&res);
    if (*worst >= sp->rating_limit) {
      *first = v;
      break;
    }
  }
  return JND_OK;
}

/* The search on the grid of distances lo (1 + tolerance)^i, i < n (the
 * last one hi): each grid distance is asked once, its result and largest
 * R kept. */
typedef struct {
  jnd_model *m;
  jnd_renderer *r;
  jnd_scene *scene;
  const jnd_view *views;
  int nviews;
  const jnd_pop_motion *mo;
  int level;
  const jnd_pop_params *p;
  const jnd_pop_switch_params *sp;
  double lo, hi;
  int n;
  int frame_w, frame_h;  /* the views' frame (the renderer's size when the search began) */
  int windowed;          /* 1: a distance renders only the object's window (pop_window) */
  double radius, fov;    /* the object's bounding sphere, the views' field of view */
  signed char *known;   /* n: −1 not asked, 0 pops, 1 popping-free */
  double *rating;       /* n: the largest R measured there */
  int first;            /* the view asked first (the last to fail) */
  int evaluations;
  jnd_status st;
} pop_search;

static double grid_distance(const pop_search *s, int i) {
  return i == 0 ? s->lo : i >= s->n - 1 ? s->hi : s->lo * pow(1 + s->sp->tolerance, i);
}

/* The pixels a distance renders (docs/pop.md "Switch decisions"): at a far
 * distance the object fills a few percent of the frame, yet every
 * rendering, read-back and model pass would be of the whole frame. When
 * the object stays centred through the motion (the views look at its
 * centre, and the camera orbits it or it spins about it), only the judge's
 * object window is rendered: a square of the frame's own pixels around the
 * object's bounding sphere with the pyramid's margin (object_window, as
 * jnd lod's judges frame it), centred as the frame is, so that its pixels
 * are the frame's pixels (the frame's and the window's sides differ by an
 * even count) and the field of view shrinks with it. Outside the window
 * the frame is background in both levels. *side: the window's side (the
 * frame's own size where no smaller window holds the object); *fov: the
 * window's field of view (0: the views' own). */
static void pop_window(const pop_search *s, double d, int *side, double *fov) {
  *side = 0;
  *fov = 0;
  if (!s->windowed || s->frame_w != s->frame_h) return;
  double scale, object_px = fmin(jnd_coverage_at_distance(s->radius, d, s->fov), 1.0) * s->frame_h;
  int R;
  object_window(object_px, 1, JUDGE_CROP_MARGIN, 0, s->frame_h, 1, &R, &scale);
  R += (s->frame_h - R) & 1;
  if (scale != 1 || R >= s->frame_h) return;
  *side = R;
  *fov = window_fov(s->fov, R, s->frame_h);
}

/* popping-free at grid distance i: the largest R below the limit (−1: error) */
static int pop_test(pop_search *s, int i) {
  if (s->known[i] >= 0) return s->known[i];
  double worst, fov;
  int side;
  pop_window(s, grid_distance(s, i), &side, &fov);
  s->st = side > 0 ? jnd_renderer_resize(s->r, side, side) : jnd_renderer_resize(s->r, s->frame_w, s->frame_h);
  if (s->st) return -1;
  pop_frame_window win = {side, s->frame_w, s->frame_h, s->fov};
  s->st = max_rating_at(s->m, s->r, s->scene, s->views, s->nviews, s->mo, s->level, s->p, s->sp, grid_distance(s, i),
                        fov, &win, &s->first, &worst);
  if (s->st) return -1;
  s->evaluations++;
  s->rating[i] = worst;
  return s->known[i] = worst < s->sp->rating_limit;
}

/* The nearest grid index popping-free with the one before it popping
 * (*at; *fail_at the one before), 0 when popping-free at the nearest
 * distance (SWITCH_AT_START), −1 when popping at the farthest
 * (SWITCH_NEVER). From a start index: doubling steps away from it until
 * the bracket [popping, popping-free] holds, then bisection; without one
 * (start < 0) the whole grid's ends first, as switch_search does. */
static jnd_status grid_search(pop_search *s, int start, switch_found *found, int *at, int *fail_at) {
  int lo = -1, hi = -1, r;   /* the nearest index known to pass, the farthest known to fail below it */
  if (start < 0) {
    if ((r = pop_test(s, 0)) < 0) return s->st;
    if (r) lo = -1, hi = 0;
    else if ((r = pop_test(s, s->n - 1)) < 0) return s->st;
    else if (!r) lo = s->n - 1;
    else lo = 0, hi = s->n - 1;
  } else {
    if ((r = pop_test(s, start)) < 0) return s->st;
    if (r) {   /* popping-free at start: nearer, in doubling steps */
      hi = start;
      for (int step = 1;; step *= 2) {
        int j = start - step > 0 ? start - step : 0;
        if ((r = pop_test(s, j)) < 0) return s->st;
        if (r) hi = j;
        else lo = j;
        if (!r || j == 0) break;
      }
    } else {   /* popping at start: farther */
      lo = start;
      for (int step = 1;; step *= 2) {
        int j = start + step < s->n - 1 ? start + step : s->n - 1;
        if ((r = pop_test(s, j)) < 0) return s->st;
        if (r) hi = j;
        else lo = j;
        if (r || j == s->n - 1) break;
      }
    }
  }
  if (hi < 0) {
    *found = SWITCH_NEVER;
    *at = -1;
    *fail_at = s->n - 1;
    return JND_OK;
  }
  if (hi == 0) {
    *found = SWITCH_AT_START;
    *at = 0;
    *fail_at = -1;
    return JND_OK;
  }
  while (hi - lo > 1) {   /* fails at lo, passes at hi */
    int mid = lo + (hi - lo) / 2;
    if ((r = pop_test(s, mid)) < 0) return s->st;
    if (r) hi = mid;
    else lo = mid;
  }
  *found = SWITCH_FOUND;
  *at = hi;
  *fail_at = lo;
  return JND_OK;
}

/* Whether the object stays centred in every view through the motion, so
 * that pop_window may frame it: no ground plane (it would reach past the
 * window), a black background, every view looking at the object's centre
 * with the same field of view and no model transform, and a motion that
 * keeps the centre where it is (an orbit about it, a spin about it; a pan
 * or a travel moves it across the frame). */
static int centred_views(const jnd_view *views, int nviews, const jnd_pop_motion *mo, const double centre[3],
                         int ground, double fov) {
  static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (ground >= 0 || (mo->speed != 0 && mo->kind != JND_POP_ORBIT && mo->kind != JND_POP_OBJECT)) return 0;
  for (int v = 0; v < nviews; v++) {
    const jnd_camera *c = &views[v].camera;
    double off = 0, len = 0;
    for (int k = 0; k < 3; k++) {
      off += (c->target[k] - centre[k]) * (c->target[k] - centre[k]);
      len += (c->eye[k] - c->target[k]) * (c->eye[k] - c->target[k]);
    }
    if (views[v].background_env || (c->fov_y_deg > 0 ? c->fov_y_deg : 45) != fov || off > 1e-12 * len ||
        memcmp(views[v].model, identity, sizeof identity) != 0)
      return 0;
  }
  return 1;
}

jnd_status jnd_pop_switch_distance(jnd_model *m, jnd_renderer *r, jnd_scene *scene, const jnd_view *views,
                                   int nviews, const jnd_pop_motion *mo, int level, const jnd_pop_params *p,
                                   const jnd_pop_switch_params *sp, jnd_pop_switch *out) {
  memset(out, 0, sizeof *out);
  out->distance_popping = NAN;
  int n = jnd_scene_lod_count(scene);
  if (level < 1 || level >= n) return jnd_fail(JND_ERR_ARG, "pop: level %d is not in 1..%d", level, n - 1);
  if (nviews < 1) return jnd_fail(JND_ERR_ARG, "pop: no views");
  if (!(sp->tolerance > 0) || !(sp->coverage_near > sp->coverage_far) || !(sp->coverage_far > 0))
    return jnd_fail(JND_ERR_ARG, "pop: the search needs tolerance > 0 and near coverage > far coverage > 0");
  double centre[3], radius;
  int ground;
  jnd_scene_subject_bounds(scene, centre, &radius, &ground);
  double fov = views[0].camera.fov_y_deg > 0 ? views[0].camera.fov_y_deg : 45;
  jnd_lod_level_info li;
  jnd_status st = jnd_scene_lod_info(scene, level, &li);
  if (st) return st;
  int wpx, hpx;
  jnd_renderer_size(r, &wpx, &hpx); /* the images the views are rendered at */
  /* the level's geometric error in object units: meshoptimizer's where it
   * made the level, else (levels read from a file, jnd lod's GLB among
   * them) measured from level 0's surface as lod does (docs/lod.md) */
  double err = li.error_abs;
  if (!isfinite(err)) {
    jnd_surface_distance dist;
    if ((st = jnd_scene_lod_distance(scene, level, 16384, 1, &dist))) return st;
    err = dist.max;
  }
  out->distance_pixel_rule = isfinite(err) && err > 0 ? err * hpx / (2 * tan(fov * M_PI / 360)) : NAN;

  pop_search ps = {.m = m, .r = r, .scene = scene, .views = views, .nviews = nviews, .mo = mo, .level = level,
                   .p = p, .sp = sp, .n = 1, .frame_w = wpx, .frame_h = hpx, .radius = radius, .fov = fov};
  ps.windowed = !sp->whole_frame && centred_views(views, nviews, mo, centre, ground, fov);
  ps.lo = jnd_camera_distance_for_coverage(radius, sp->coverage_near, fov);
  ps.hi = jnd_camera_distance_for_coverage(radius, sp->coverage_far, fov);
  if (ps.hi > ps.lo * (1 + sp->tolerance)) ps.n = (int)ceil(log(ps.hi / ps.lo) / log1p(sp->tolerance)) + 1;
  if (ps.n > 4096) return jnd_fail(JND_ERR_ARG, "pop: %d distances to search (tolerance too small)", ps.n);
  ps.known = jnd_alloc((size_t)ps.n, 1);
  ps.rating = jnd_alloc((size_t)ps.n, sizeof *ps.rating);
  if (!ps.known || !ps.rating) {
    free(ps.known);
    free(ps.rating);
    return jnd_fail(JND_ERR_NOMEM, "pop: out of memory");
  }
  memset(ps.known, -1, (size_t)ps.n);
  int start = -1;   /* the grid distance nearest to sp->start (on a log scale) */
  if (sp->start > 0 && isfinite(sp->start) && ps.n > 1)
    start = jnd_clampi((int)lround(log(sp->start / ps.lo) / log1p(sp->tolerance)), 0, ps.n - 1);
  else if (isinf(sp->start) && sp->start > 0)
    start = ps.n - 1;
  switch_found f = SWITCH_NEVER;
  int at = -1, fail_at = 0;
  st = grid_search(&ps, start, &f, &at, &fail_at);
  jnd_status back = jnd_renderer_resize(r, wpx, hpx);   /* the caller's frame again */
  if (!st) st = back;
  out->evaluations = ps.evaluations;
  if (!st) {
    if (f == SWITCH_AT_START) {
      out->status = JND_POP_SWITCH_NEAREST;
      out->distance = ps.lo;
      out->max_rating = ps.rating[0];
    } else if (f == SWITCH_NEVER) {
      out->status = JND_POP_SWITCH_NONE;
      out->distance = INFINITY;
      out->max_rating = ps.rating[fail_at];
    } else {
      out->status = JND_POP_SWITCH_FOUND;
      out->distance = grid_distance(&ps, at);
      out->distance_popping = grid_distance(&ps, fail_at);
      out->max_rating = ps.rating[at];
    }
  }
  free(ps.known);
  free(ps.rating);
  return st;
}

/* ---- jnd pop MODEL as one call ---- */

void jnd_pop_asset_defaults(jnd_pop_asset_params *p) {
  memset(p, 0, sizeof *p);
  jnd_view_set_defaults(&p->views);
  p->builtin_map_size = 512;
  jnd_lod_defaults(&p->chain);
  jnd_pop_motion_defaults(&p->motion);
  jnd_pop_defaults(&p->pop);
  jnd_pop_switch_defaults(&p->search);
}

void jnd_pop_asset_report_free(jnd_pop_asset_report *r) {
  if (!r) return;
  jnd_pop_result_free(&r->pair);
  free(r->rows);
  jnd_image_free(&r->plot);
  memset(r, 0, sizeof *r);
}

/* the unit of distances × motion.unit_m: glTF is in metres by its
 * specification; OBJ and the built-in assets carry no unit */
static const char *distance_unit(const char *path, const jnd_pop_motion *mo) {
  return mo->unit_m > 0 && mo->unit_m != 1 ? "m" : jnd_asset_length_unit(path);
}

/* switch.png: each level's popping-free distance per speed and where its
 * geometric error covers a pixel. Each point is measured on its own (the
 * switch from level k − 1 to k), so a level can pop less than the one
 * before and come out nearer: the plot shows it as measured and says so. */
jnd_status pop_switch_plot(const jnd_pop_asset_report *r, const double *speeds, int nspeeds, jnd_image *out,
                           jnd_plot_layout *layout) {
  memset(out, 0, sizeof *out);
  int nl = r->nlevels - 1;
  if (nl < 1 || nspeeds < 1) return jnd_fail(JND_ERR_ARG, "pop: no switch to draw");
  double *x = malloc((sizeof(double) + 1) * (size_t)nl * (nspeeds + 2));
  jnd_plot_series *ser = calloc((size_t)nspeeds + 1, sizeof *ser);
  char(*labels)[64] = calloc((size_t)nspeeds + 1, sizeof *labels);
  if (!x || !ser || !labels) {
    free(x);
    free(ser);
    free(labels);
    return jnd_fail(JND_ERR_NOMEM, "pop: out of memory");
  }
  double *ys = x + nl;
  signed char *bound = (signed char *)(ys + (size_t)nl * (nspeeds + 1));
  for (int k = 0; k < nl; k++) x[k] = k + 1;
  int nearer = 0, bounds = 0; /* a level found nearer than the one before; a bound drawn */
  for (int s = 0; s <= nspeeds; s++) {
    double *y = ys + (size_t)s * nl;
    signed char *b = bound + (size_t)s * nl;
    for (int k = 0; k < nl; k++) {
      const jnd_pop_switch_row *row = &r->rows[(size_t)k * nspeeds + (s < nspeeds ? s : 0)];
      double v = s < nspeeds ? row->distance_m : row->distance_m_pixel_rule;
      y[k] = isfinite(v) && v > 0 ? v : NAN;
      /* popping-free already at the nearest distance searched: the switch
       * could come nearer still, so the distance is an upper bound */
      b[k] = s < nspeeds && row->sw.status == JND_POP_SWITCH_NEAREST ? -1 : 0;
      bounds |= b[k] != 0 && isfinite(y[k]);
      const jnd_pop_switch_row *prev = k > 0 ? row - nspeeds : NULL;
      if (s < nspeeds && prev && row->sw.status == JND_POP_SWITCH_FOUND && prev->sw.status == JND_POP_SWITCH_FOUND &&
          y[k] < y[k - 1])
        nearer = 1;
    }
    if (s < nspeeds)
      snprintf(labels[s], sizeof labels[s], "max R < 1 at %g deg/s", speeds[s]);
    else
      snprintf(labels[s], sizeof labels[s], "1-pixel geometric error");
    ser[s] = (jnd_plot_series){.x = x, .y = y, .n = nl, .label = labels[s],
                               .colour = s < nspeeds ? jnd_palette(s) : (jnd_rgb){0.4f, 0.4f, 0.4f}, .line = 1,
                               .markers = s < nspeeds ? 1 : 2, .bound = b,
                               /* speeds that pop alike give one line: each slower speed is drawn
                                  wider beneath the next, so that every one shows */
                               .width = s < nspeeds ? 2.0 + 2.0 * (nspeeds - 1 - s) : 1.5};
  }
  char ylabel[64];
  snprintf(ylabel, sizeof ylabel, "camera distance (%s)", r->distance_unit ? r->distance_unit : "object units");
  jnd_plot_axes ax;
  memset(&ax, 0, sizeof ax);
  ax.title = nearer ? "popping-free switch distance per level (004: largest R < 1); a level below the one before "
                      "pops less than it, as measured"
                    : "popping-free switch distance per level (004: largest R < 1)";
  ax.xlabel = "level that takes over (the switch from the level before)";
  ax.ylabel = ylabel;
  ax.log_y = 1;
  ax.xmin = 0.5;
  ax.xmax = nl + 0.5;
  ax.ymin = ax.ymax = NAN;
  ax.integer_x = 1;
  ax.bound_label = bounds ? "at most: popping-free already at the nearest distance searched" : NULL;
  jnd_status st = layout ? jnd_plot_lines_layout(&ax, ser, nspeeds + 1, layout) : JND_OK;
  if (!st) st = jnd_plot_lines(&ax, ser, nspeeds + 1, out);
  free(x);
  free(ser);
  free(labels);
  return st;
}

static const double DEFAULT_SPEEDS[3] = {0, 30, 120}; /* static, slow, fast (°/s) */

jnd_status jnd_pop_asset_run(jnd_model *m, const char *model_path, const jnd_pop_asset_params *p,
                             jnd_pop_asset_report *out) {
  memset(out, 0, sizeof *out);
  const double *speeds = p->speeds ? p->speeds : DEFAULT_SPEEDS;
  int nspeeds = p->speeds ? p->nspeeds : 3;
  if (p->decide && p->motion.kind == JND_POP_TRANSLATE)
    return jnd_fail(JND_ERR_ARG, "pop: the switch table's speeds are in degrees per second: orbit, spin or pan");
  for (int s = 0; s < nspeeds; s++)
    if (!isfinite(speeds[s])) return jnd_fail(JND_ERR_ARG, "pop: a speed is not finite");
  if (p->decide && nspeeds < 1) return jnd_fail(JND_ERR_ARG, "pop: no speeds");
  double t0 = jnd_seconds();
  jnd_scene *scene = NULL;
  jnd_renderer *r = NULL;
  jnd_view *views = NULL, *cams = NULL;
  int nviews = 0;
  jnd_status st = jnd_scene_open(model_path, p->builtin_map_size > 0 ? p->builtin_map_size : 512, &scene);
  if (st) return st;
  jnd_lod_chain_params cp = {&p->chain, p->rebuild, p->level_paths, p->nlevel_paths};
  if ((st = jnd_scene_lod_chain(scene, model_path, &cp, &out->chain_source))) {
    jnd_scene_free(scene);
    return st;
  }
  out->distance_unit = distance_unit(model_path, &p->motion);
  out->nlevels = jnd_scene_lod_count(scene);
  if (out->nlevels > 64) out->nlevels = 64;
  for (int k = 0; k < out->nlevels && !st; k++) st = jnd_scene_lod_info(scene, k, &out->levels[k]);
  if (!st && (p->level < 0 || p->level + 1 >= out->nlevels))
    st = jnd_fail(JND_ERR_ARG, "pop: --switch %d: the chain has levels 0..%d, so the switch is from 0..%d", p->level,
                  out->nlevels - 1, out->nlevels - 2);
  jnd_view_set vs = p->views;
  if (!st && p->cameras) {
    int nc = 0;
    st = jnd_views_read(p->cameras, scene, vs.sampling.fov_y_deg, &cams, &nc);
    vs.cameras = cams;
    vs.ncameras = nc;
  }
  if (!st) st = jnd_view_set_make(scene, &vs, &views, &nviews);
  out->nviews = nviews;
  out->load_s = jnd_seconds() - t0;
  if (!st) st = judge_renderer(&vs.render, 0, &r);
  if (!st) snprintf(out->renderer, sizeof out->renderer, "%s", jnd_renderer_description(r));
  double t1 = jnd_seconds();
  if (!st) {
    if (p->progress) p->progress(p->progress_user, "the switch", 0, 1);
    const double *e = views[0].camera.eye, *c = views[0].camera.target;
    out->pair_distance = sqrt((e[0] - c[0]) * (e[0] - c[0]) + (e[1] - c[1]) * (e[1] - c[1]) + (e[2] - c[2]) * (e[2] - c[2]));
    st = jnd_pop_render(m, r, scene, &views[0], &p->motion, p->level, p->frame, &p->pop, &out->pair);
  }
  out->render_s = jnd_seconds() - t1;
  double t2 = jnd_seconds();
  if (!st && p->decide) {
    int nl = out->nlevels - 1;
    out->rows = calloc((size_t)nl * nspeeds, sizeof *out->rows);
    if (!out->rows) st = jnd_fail(JND_ERR_NOMEM, "pop: out of memory");
    for (int k = 1; k <= nl && !st; k++)
      for (int s = 0; s < nspeeds && !st; s++) {
        /* the first search bisects the whole grid, the others start at a
         * neighbour's answer and take a third of its evaluations or less:
         * the time left is estimated from those others only */
        int i = (k - 1) * nspeeds + s;
        if (p->progress && i == 0) p->progress(p->progress_user, "the first switch distance (a bisection)", 0, 1);
        if (p->progress && i > 0) p->progress(p->progress_user, "switch distances", i - 1, nl * nspeeds - 1);
        jnd_pop_switch_row *row = &out->rows[(size_t)(k - 1) * nspeeds + s];
        jnd_pop_motion mo = p->motion;
        mo.speed = speeds[s];
        row->level = k;
        row->speed_dps = speeds[s];
        /* the search starts where the previous speed's answer for this
         * level, or for the first speed the finer level's, was: motion
         * moves the distances little, and a coarser level's lies near */
        jnd_pop_switch_params sp = p->search;
        const jnd_pop_switch_row *near = s > 0 ? row - 1 : k > 1 ? row - nspeeds : NULL;
        if (near && sp.start == 0) sp.start = near->sw.distance;
        st = jnd_pop_switch_distance(m, r, scene, views, nviews, &mo, k, &p->pop, &sp, &row->sw);
        double u = p->motion.unit_m > 0 ? p->motion.unit_m : 1;
        row->distance_m = row->sw.distance * u;
        row->distance_m_pixel_rule = row->sw.distance_pixel_rule * u;
        out->nrows++;
      }
    if (!st && p->progress && nl * nspeeds > 1)
      p->progress(p->progress_user, "switch distances", nl * nspeeds - 1, nl * nspeeds - 1);
    if (!st) st = pop_switch_plot(out, speeds, nspeeds, &out->plot, NULL);
  }
  out->decide_s = jnd_seconds() - t2;
  free(views);
  free(cams);
  jnd_renderer_free(r);
  jnd_scene_free(scene);
  if (st) {
    jnd_pop_asset_report_free(out);
    return st;
  }
  return JND_OK;
}
