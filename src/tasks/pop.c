/* Will a level switch pop? The popping predictor of Schwarz & Stamminger
 * (004), on the frame where the switch happens, rendered with the new level
 * (actual) and with the previous one (expected, 004 §3: "what the user
 * might expect for this frame"):
 *
 *   1. seeds' first condition: the pixels where the two colour images
 *      differ (004 §3.2)
 *   2. the simple baseline: ΔE*94 of the two frames, its maximum (004 §5.1)
 *   3. weights (004 §3.2 "scale down … by weights provided as additional
 *      input", 004 §4): previous-frame visibility by percentage-closer
 *      filtering, the larger of the two levels' (disocclusion); the ΔE*94
 *      flicker heuristic; the caller's own weights; multiplied
 *   4. the JND map of expected against actual, each frame with its own
 *      displacement → retinal velocity (Daly's eye tracking, 004 §3.1),
 *      combined across bands and channels by Minkowski 2.4 and multiplied
 *      by the weights (004 §3.1–3.2; src/vision/model.c)
 *   5. popping regions: seeds (step 1 and >= 2 JND) grown over the eight
 *      neighbours while >= 2 JND (004 §3.2; src/pool/regions.c)
 *   6. per region its pixels, bounding box, Minkowski sum Σ (exponent 2.4)
 *      of its JND values and rating R = ln(0.375 Σ) / ln 2.25 (004 §3.2)
 *   7. coverage score, rating score and detection score (004 §5.2; the
 *      thresholds and the completed rule table are ours, docs/pop.md)
 *   8. the picture of 004 Fig. 4: the regions coloured by R, with a legend
 *
 * 004 ignores temporal integration and attention (§3): one frame, every
 * region assumed attended. So does this file. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "pool/pool.h"
#include "tasks/tasks.h"
#include "vision/vision.h"

void jnd_pop_defaults(jnd_pop_params *p) {
  memset(p, 0, sizeof *p);
  p->threshold_jnd = 2.0; /* 004 §3.2 */
  p->minkowski = 2.4;     /* 004 §3.2 */
  p->depth_tolerance = 0.01;
  p->flicker_ratio_lo = 0.5;
  p->flicker_ratio_hi = 1.0;
  p->flicker_motion_lo_px = 2.0;
  p->flicker_motion_hi_px = 4.0;
  p->top_regions = 3;
  p->coverage_small = 0.01;
  p->coverage_large = 0.05;
  p->coverage_huge = 0.25;
  p->rating_low = 1.0;       /* 004 §3.2: R < 1 rarely visible */
  p->rating_high = 2.0;
  p->rating_very_high = 3.0; /* 004 §3.2: R > 3 easily detectable */
  p->picture = 1;
}

/* A level switch is a change at the same place on the screen, from one frame
 * to the next: the flicker task by nature (docs/model.md "Viewing task"),
 * whatever task the caller's display names. Side by side, a change of the
 * mean colour would be capped at its CIEDE2000 difference, which is what a
 * viewer comparing two places sees, not one watching a switch in place. */
jnd_status pop_model_create(const jnd_model_params *mp, jnd_model **m) {
  jnd_model_params q = *mp;
  q.display.task = JND_TASK_FLICKER;
  return jnd_model_create(&q, m);
}

/* 004 §3.2: "the empirically derived mapping R(Σ) = ln(0.375 Σ) / ln(2.25)" */
double jnd_pop_rating_of(double sigma) { return log(0.375 * sigma) / log(2.25); }

jnd_pop_coverage jnd_pop_coverage_level(const jnd_pop_params *p, double c) {
  if (c >= p->coverage_huge) return JND_COVERAGE_HUGE;
  if (c >= p->coverage_large) return JND_COVERAGE_LARGE;
  if (c >= p->coverage_small) return JND_COVERAGE_SMALL;
  return JND_COVERAGE_TINY;
}

jnd_pop_rating jnd_pop_rating_level(const jnd_pop_params *p, double r) {
  if (!(r >= p->rating_low)) return JND_RATING_VERY_LOW; /* NaN (no region) too */
  if (r >= p->rating_very_high) return JND_RATING_VERY_HIGH;
  if (r >= p->rating_high) return JND_RATING_HIGH;
  return JND_RATING_LOW;
}

/* 004 §5.2 gives three cells: tiny + low → 1, small + high → 3, huge +
 * high → 5. Completed as coverage level + rating level (each 0..3),
 * clamped to 1..5, which holds all three; but a very low rating (every
 * region R < 1, rarely visible even when looked at) stays at most 2 however
 * much of the object it covers. Non-decreasing along rows and columns. */
static const int DETECTION[4][4] = {
    /*            very low  low  high  very high */
    /* tiny  */ {1, 1, 2, 3},
    /* small */ {1, 2, 3, 4},
    /* large */ {2, 3, 4, 5},
    /* huge  */ {2, 4, 5, 5},
};

int jnd_pop_detection_score(jnd_pop_coverage c, jnd_pop_rating r) {
  return DETECTION[jnd_clampi((int)c, 0, 3)][jnd_clampi((int)r, 0, 3)];
}

const char *jnd_pop_coverage_name(jnd_pop_coverage c) {
  static const char *const n[] = {"tiny", "small", "large", "huge"};
  return n[jnd_clampi((int)c, 0, 3)];
}

const char *jnd_pop_rating_name(jnd_pop_rating r) {
  static const char *const n[] = {"very low", "low", "high", "very high"};
  return n[jnd_clampi((int)r, 0, 3)];
}

void jnd_pop_result_free(jnd_pop_result *r) {
  if (!r) return;
  free(r->regions);
  free(r->labels);
  jnd_image_free(&r->jnd);
  jnd_image_free(&r->weights);
  jnd_image_free(&r->picture);
  memset(r, 0, sizeof *r);
}

/* ---- inputs ---- */

/* the inputs in one list, for checking and for reading files */
enum {
  IN_ACTUAL, IN_EXPECTED, IN_DISP_A, IN_DISP_E, IN_DEPTH_A, IN_DEPTH_E, IN_PREV_DEPTH_A, IN_PREV_DEPTH_E,
  IN_WEIGHTS, IN_PREV_COLOR, IN_PREV_SHADING, IN_MASK, NIN
};
typedef enum { K_COLOUR, K_DISPLACEMENT, K_DEPTH, K_UNIT } in_kind;
static const in_kind KIND[NIN] = {K_COLOUR, K_COLOUR, K_DISPLACEMENT, K_DISPLACEMENT, K_DEPTH, K_DEPTH,
                                  K_DEPTH, K_DEPTH, K_UNIT, K_COLOUR, K_COLOUR, K_UNIT};
static const char *const IN_NAME[NIN] = {
    "actual colour", "expected colour", "actual displacement", "expected displacement",
    "actual depth", "expected depth", "actual previous-frame depth", "expected previous-frame depth",
    "weights", "previous frame", "previous shading", "mask"};

static void inputs_list(const jnd_pop_inputs *in, const jnd_image *im[NIN]) {
  im[IN_ACTUAL] = in->actual.color;
  im[IN_EXPECTED] = in->expected.color;
  im[IN_DISP_A] = in->actual.displacement;
  im[IN_DISP_E] = in->expected.displacement;
  im[IN_DEPTH_A] = in->actual.depth;
  im[IN_DEPTH_E] = in->expected.depth;
  im[IN_PREV_DEPTH_A] = in->actual.prev_depth;
  im[IN_PREV_DEPTH_E] = in->expected.prev_depth;
  im[IN_WEIGHTS] = in->weights;
  im[IN_PREV_COLOR] = in->prev_color;
  im[IN_PREV_SHADING] = in->prev_shading;
  im[IN_MASK] = in->mask;
}

/* one input: its size, channels and values; name is what messages call it */
static jnd_status check_input(const jnd_image *img, in_kind k, const char *name, const char *actual_name, int w,
                              int h) {
  if (!img->data) return jnd_fail(JND_ERR_ARG, "%s: no pixels", name);
  if (img->w != w || img->h != h)
    return jnd_fail(JND_ERR_ARG, "%s: size %d × %d differs from %s (%d × %d)", name, img->w, img->h, actual_name, w, h);
  int need = k == K_COLOUR ? 3 : k == K_DISPLACEMENT ? 2 : 1;
  if (img->c < need || (k == K_COLOUR && img->c != 3))
    return jnd_fail(JND_ERR_ARG, "%s: needs %s, has %d channel%s", name,
                    k == K_COLOUR ? "3 channels (RGB)" : k == K_DISPLACEMENT ? "2 channels (x, y displacement)" : "1 channel",
                    img->c, img->c == 1 ? "" : "s");
  const size_t n = (size_t)w * h;
  const int nch = k == K_COLOUR ? 3 : need; /* the channels that are used */
  /* the values allowed: finite, and for depths ≥ 0, for unit maps in 0–1 */
  const float lo = k == K_DEPTH || k == K_UNIT ? 0.0f : -FLT_MAX, hi = k == K_UNIT ? 1.0f : FLT_MAX;
  for (int c = 0; c < nch; c++) {
    const float *v = jnd_image_plane(img, c);
    const size_t i = jnd_first_outside(v, n, lo, hi);
    if (i == n) continue;
    const float x = v[i];
    const char *what = !isfinite(x) ? (isnan(x) ? "is NaN" : "is infinite")
                       : k == K_DEPTH ? "is a negative depth"
                                      : "is outside 0–1";
    return jnd_fail(JND_ERR_ARG, "%s: value %g at pixel (%zu, %zu) %s", name, (double)x, i % (size_t)w, i / (size_t)w,
                    what);
  }
  return JND_OK;
}

static jnd_status check_inputs(const jnd_pop_inputs *in, const char *const *names) {
  const jnd_image *im[NIN];
  inputs_list(in, im);
  if (!im[IN_ACTUAL] || !im[IN_EXPECTED]) return jnd_fail(JND_ERR_ARG, "pop: both colour frames are needed");
  const int w = im[IN_ACTUAL]->w, h = im[IN_ACTUAL]->h;
  jnd_status s = jnd_check_size(w, h, 3, names[IN_ACTUAL]);
  if (s != JND_OK) return s;
  for (int k = 0; k < NIN; k++)
    if (im[k] && (s = check_input(im[k], KIND[k], names[k], names[IN_ACTUAL], w, h)) != JND_OK) return s;
  /* inputs that only work in pairs */
  static const int pairs[][2] = {{IN_DEPTH_A, IN_PREV_DEPTH_A}, {IN_DEPTH_E, IN_PREV_DEPTH_E},
                                 {IN_PREV_COLOR, IN_PREV_SHADING}};
  for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
    int a = pairs[k][0], b = pairs[k][1];
    if (!im[a] != !im[b])
      return jnd_fail(JND_ERR_ARG, "%s: needs the %s too", names[im[a] ? a : b], IN_NAME[im[a] ? b : a]);
  }
  return JND_OK;
}

static jnd_status check_params(const jnd_pop_params *p) {
  if (!(p->threshold_jnd > 0) || !(p->minkowski >= 1))
    return jnd_fail(JND_ERR_ARG, "pop: the threshold must be > 0 JND and the Minkowski exponent >= 1");
  if (!(p->depth_tolerance >= 0) || !(p->flicker_ratio_lo >= 0) || !(p->flicker_ratio_hi >= p->flicker_ratio_lo) ||
      !(p->flicker_motion_lo_px >= 0) || !(p->flicker_motion_hi_px >= p->flicker_motion_lo_px))
    return jnd_fail(JND_ERR_ARG, "pop: tolerances must be >= 0 and each range low <= high");
  if (p->top_regions < 1) return jnd_fail(JND_ERR_ARG, "pop: top_regions must be at least 1");
  if (!(p->coverage_small > 0 && p->coverage_small <= p->coverage_large && p->coverage_large <= p->coverage_huge &&
        p->coverage_huge <= 1))
    return jnd_fail(JND_ERR_ARG, "pop: coverage thresholds must rise within (0, 1]");
  if (!(p->rating_low <= p->rating_high && p->rating_high <= p->rating_very_high))
    return jnd_fail(JND_ERR_ARG, "pop: rating thresholds must rise");
  return JND_OK;
}

/* ---- steps ---- */

/* step 1: where the two colour images differ (any channel); their number */
static size_t colours_differ(const jnd_image *a, const jnd_image *b, uint8_t *out) {
  const ptrdiff_t n = (ptrdiff_t)a->w * a->h;
  const float *a0 = jnd_image_plane(a, 0), *a1 = jnd_image_plane(a, 1), *a2 = jnd_image_plane(a, 2);
  const float *b0 = jnd_image_plane(b, 0), *b1 = jnd_image_plane(b, 1), *b2 = jnd_image_plane(b, 2);
  size_t count = 0; /* an integer sum: the same in any order */
#pragma omp parallel for reduction(+ : count) schedule(static)
  for (ptrdiff_t i = 0; i < n; i++) {
    out[i] = a0[i] != b0[i] || a1[i] != b1[i] || a2[i] != b2[i];
    count += out[i];
  }
  return count;
}

/* the statistics of one weight map, in raster order */
static void weight_stats(const float *w, size_t n, jnd_pop_weight_stats *st) {
  double sum = 0, mn = 1;
  size_t below = 0;
  for (size_t i = 0; i < n; i++) {
    sum += w[i];
    if (w[i] < mn) mn = w[i];
    below += w[i] < 0.5f;
  }
  st->present = 1;
  st->mean = sum / (double)n;
  st->min = mn;
  st->below_half = below;
}

/* step 3: the combined weight map (NULL in *out when there is none) */
static jnd_status make_weights(const jnd_display *d, const jnd_pop_inputs *in, const jnd_image *de_levels,
                               const jnd_pop_params *p, jnd_pop_result *out) {
  const int w = in->actual.color->w, h = in->actual.color->h;
  const size_t n = (size_t)w * h;
  const jnd_pop_frame *fr[2] = {&in->actual, &in->expected};
  const int occ = fr[0]->depth || fr[1]->depth, flick = in->prev_color != NULL, user = in->weights != NULL;
  if (!occ && !flick && !user) return JND_OK;
  jnd_status s = jnd_image_alloc(&out->weights, w, h, 1);
  if (s != JND_OK) return s;
  float *W = out->weights.data;
  for (size_t i = 0; i < n; i++) W[i] = 1.0f;
  float *tmp = jnd_alloc(n, sizeof(float));
  if (!tmp) return JND_ERR_NOMEM;
  if (occ) {
    /* 004 §4: each level's previous-frame visibility; the pixel-wise maximum */
    float *vis = jnd_alloc(n, sizeof(float));
    if (!vis) {
      free(tmp);
      return JND_ERR_NOMEM;
    }
    int first = 1;
    for (int k = 0; k < 2 && s == JND_OK; k++) {
      if (!fr[k]->depth) continue;
      s = pop_visibility(fr[k]->depth, fr[k]->prev_depth, fr[k]->displacement, p->depth_tolerance, first ? vis : tmp);
      if (s == JND_OK && !first)
        for (size_t i = 0; i < n; i++) vis[i] = vis[i] > tmp[i] ? vis[i] : tmp[i];
      first = 0;
    }
    if (s == JND_OK) {
      weight_stats(vis, n, &out->disocclusion);
      for (size_t i = 0; i < n; i++) W[i] *= vis[i];
    }
    free(vis);
  }
  if (s == JND_OK && flick) {
    /* 004 §4: flicker, judged on the expected level (the previous frame's) */
    const jnd_pop_frame *e = &in->expected;
    s = pop_flicker_weight(d, in->prev_shading, in->prev_color, e->displacement, e->depth, e->prev_depth,
                           de_levels, p, tmp);
    if (s == JND_OK) {
      weight_stats(tmp, n, &out->flicker);
      for (size_t i = 0; i < n; i++) W[i] *= tmp[i];
    }
  }
  if (s == JND_OK && user) {
    weight_stats(in->weights->data, n, &out->user);
    for (size_t i = 0; i < n; i++) W[i] *= in->weights->data[i];
  }
  free(tmp);
  return s;
}

static int region_order(const void *a, const void *b) {
  const jnd_region *x = a, *y = b;
  if (x->sum_pow != y->sum_pow) return x->sum_pow > y->sum_pow ? -1 : 1;
  return x->first < y->first ? -1 : x->first > y->first;
}

/* steps 5–6: regions, sorted by rating, and their labels */
static jnd_status find_regions(const uint8_t *seed, const jnd_pop_params *p, jnd_pop_result *out) {
  const int w = out->w, h = out->h;
  const size_t n = (size_t)w * h;
  out->labels = jnd_alloc(n, sizeof *out->labels);
  if (!out->labels) return JND_ERR_NOMEM;
  jnd_region *reg = NULL;
  int nr = 0;
  jnd_status s = jnd_regions_find(out->jnd.data, seed, w, h, (float)p->threshold_jnd, p->minkowski, p->threads,
                                  out->labels, &reg, &nr);
  if (s != JND_OK) return s;
  if (nr == 0) return JND_OK;
  /* sort by Σ (so by R), ties by first pixel; labels follow: a region's old
   * index is the label at its first pixel */
  int *order = jnd_alloc((size_t)nr, sizeof *order);
  out->regions = jnd_calloc((size_t)nr, sizeof *out->regions);
  if (!order || !out->regions) {
    free(order);
    free(reg);
    return JND_ERR_NOMEM;
  }
  qsort(reg, (size_t)nr, sizeof *reg, region_order);
  for (int k = 0; k < nr; k++) order[out->labels[reg[k].first]] = k;
  const ptrdiff_t nn = (ptrdiff_t)n;
  int32_t *lab = out->labels;
#pragma omp parallel for schedule(static)
  for (ptrdiff_t i = 0; i < nn; i++)
    if (lab[i] >= 0) lab[i] = order[lab[i]];
  for (int k = 0; k < nr; k++) {
    const jnd_region *g = &reg[k];
    jnd_pop_region *r = &out->regions[k];
    r->pixels = g->pixels;
    r->sigma = pow(g->sum_pow, 1.0 / p->minkowski); /* 004 §3.2: Minkowski sum, exponent 2.4 */
    r->rating = jnd_pop_rating_of(r->sigma);
    r->jnd_max = g->max;
    r->bbox[0] = g->x0;
    r->bbox[1] = g->y0;
    r->bbox[2] = g->x1;
    r->bbox[3] = g->y1;
    r->first[0] = (int)(g->first % (size_t)w);
    r->first[1] = (int)(g->first / (size_t)w);
  }
  out->nregions = nr;
  free(order);
  free(reg);
  return JND_OK;
}

/* step 7: coverage of the object, mean R of the best regions, the scores */
static void scores(const jnd_pop_inputs *in, const jnd_pop_params *p, jnd_pop_result *out) {
  const size_t n = (size_t)out->w * out->h;
  const float *mask = in->mask ? in->mask->data : NULL;
  size_t obj = 0, cov = 0; /* integer sums: the same in any order */
  const int32_t *lab = out->labels;
  const ptrdiff_t nn = (ptrdiff_t)n;
#pragma omp parallel for reduction(+ : obj, cov) schedule(static)
  for (ptrdiff_t i = 0; i < nn; i++) {
    int on = !mask || mask[i] > 0.5f;
    obj += (size_t)on;
    cov += (size_t)(on && lab[i] >= 0);
  }
  out->object_pixels = obj;
  out->covered_pixels = cov;
  out->coverage = obj ? (double)cov / (double)obj : 0.0;
  out->coverage_score = jnd_pop_coverage_level(p, out->coverage);
  out->max_rating = out->nregions ? out->regions[0].rating : NAN;
  int k = out->nregions < p->top_regions ? out->nregions : p->top_regions;
  double sum = 0;
  for (int i = 0; i < k; i++) sum += out->regions[i].rating;
  out->rating_top = k ? sum / k : NAN;
  out->rating_score = jnd_pop_rating_level(p, out->rating_top);
  /* no region at all: nothing to see */
  out->detection_score = out->nregions ? jnd_pop_detection_score(out->coverage_score, out->rating_score) : 1;
}

/* The procedure. own_exp and own_act (may be NULL) are the frames' images when
 * the caller gives them up: the model then works in them instead of copies. */
static jnd_status predict(jnd_model *m, const jnd_pop_inputs *in, const char *const *names,
                          const jnd_pop_params *p, jnd_image *own_exp, jnd_image *own_act, jnd_pop_result *out) {
  memset(out, 0, sizeof *out);
  out->max_rating = out->rating_top = NAN;
  jnd_status s = check_params(p);
  if (s == JND_OK) s = check_inputs(in, names);
  if (s != JND_OK) return s;
  const jnd_model_params *mp = jnd_model_get_params(m);
  const jnd_image *act = in->actual.color, *exp = in->expected.color;
  const int w = act->w, h = act->h;
  const size_t n = (size_t)w * h;
  out->w = w;
  out->h = h;
  uint8_t *seed = jnd_alloc(n, 1);
  jnd_image de = {0}, grey = {0}, still = {0};
  if (!seed) return JND_ERR_NOMEM;
  double t = jnd_seconds();
  const size_t ndiff = colours_differ(act, exp, seed); /* 1 */
  /* 2: only where the colours differ (ΔE is 0 elsewhere) */
  if ((s = jnd_delta_e94_map_where(&mp->display, exp, act, seed, &de, &out->max_delta_e94)) != JND_OK) goto fail;
  if ((s = make_weights(&mp->display, in, &de, p, out)) != JND_OK) goto fail; /* 3 */
  jnd_image_free(&de);
  /* the picture's backdrop now, before the model may use up the frames */
  if (p->picture && (s = pop_backdrop(&mp->display, act, &grey)) != JND_OK) goto fail;
  out->timings.weights_s = jnd_seconds() - t;
  t = jnd_seconds();
  /* 4: expected is the reference, actual the test, each with its own motion */
  jnd_diff_inputs di = {0};
  di.motion = in->expected.displacement; /* NULL with motion_test set: a static reference */
  di.motion_test = in->actual.displacement;
  if (di.motion && !di.motion_test) {
    /* the model would let the reference's motion serve both: a static actual frame needs zeros */
    if ((s = jnd_image_alloc(&still, w, h, 2)) != JND_OK) goto fail;
    di.motion_test = &still;
  }
  di.weights = out->weights.data ? &out->weights : NULL;
  if (!ndiff && in->expected.displacement == in->actual.displacement) {
    /* the same colours with the same motion: every band's responses are
     * equal, the model's map is exactly 0 (and there is no seed); a
     * sequence's unchanged frames cost nothing */
    s = jnd_image_alloc(&out->jnd, w, h, 1); /* zeroed */
  } else if (own_exp && own_act && own_exp != own_act)
    s = jnd_model_diff_consume(m, own_exp, own_act, &di, &out->jnd);
  else
    s = jnd_model_diff(m, exp, act, &di, &out->jnd);
  jnd_image_free(&still);
  if (s != JND_OK) goto fail;
  float jmax = 0;
  const float *J = out->jnd.data;
  const ptrdiff_t nn = (ptrdiff_t)n;
#pragma omp parallel for reduction(max : jmax) schedule(static)
  for (ptrdiff_t i = 0; i < nn; i++) jmax = J[i] > jmax ? J[i] : jmax;
  out->jnd_max = jmax;
  out->timings.model_s = jnd_seconds() - t;
  t = jnd_seconds();
  if ((s = find_regions(seed, p, out)) != JND_OK) goto fail; /* 5, 6 */
  free(seed);
  seed = NULL;
  scores(in, p, out); /* 7 */
  out->timings.regions_s = jnd_seconds() - t;
  t = jnd_seconds();
  if (p->picture && (s = pop_picture(&grey, out, &out->picture)) != JND_OK) goto fail; /* 8 */
  jnd_image_free(&grey);
  out->timings.picture_s = jnd_seconds() - t;
  return JND_OK;
fail:
  free(seed);
  jnd_image_free(&de);
  jnd_image_free(&grey);
  jnd_pop_result_free(out);
  return s;
}

jnd_status jnd_pop_predict(jnd_model *m, const jnd_pop_inputs *in, const jnd_pop_params *p, jnd_pop_result *out) {
  return predict(m, in, IN_NAME, p, NULL, NULL, out);
}

/* ---- files ---- */

jnd_status jnd_pop_files(jnd_model *m, const jnd_pop_paths *f, const jnd_pop_params *p, jnd_pop_result *out) {
  memset(out, 0, sizeof *out);
  const char *path[NIN] = {f->actual, f->expected, f->displacement,
                           f->displacement_expected ? f->displacement_expected : f->displacement,
                           f->depth, f->depth_expected, f->prev_depth, f->prev_depth_expected,
                           f->weights, f->prev_color, f->prev_shading, f->mask};
  if (!path[IN_ACTUAL] || !path[IN_EXPECTED]) return jnd_fail(JND_ERR_ARG, "pop: two frames are needed");
  /* each file is read once: a slot naming the same path as an earlier slot
   * of the same kind shares its image (a colour frame is converted to cd/m²,
   * so it cannot double as a weight map) */
  int src[NIN], todo[NIN], ntodo = 0;
  for (int k = 0; k < NIN; k++) {
    src[k] = k;
    if (!path[k]) continue;
    for (int j = 0; j < k; j++)
      if (path[j] && KIND[j] == KIND[k] && strcmp(path[j], path[k]) == 0 && src[j] == j) {
        src[k] = j;
        break;
      }
    if (src[k] == k) todo[ntodo++] = k;
  }
  const double t0 = jnd_seconds();
  jnd_image img[NIN];
  jnd_image_info info[NIN];
  jnd_status st[NIN];
  char msg[NIN][600];
  memset(img, 0, sizeof img);
  /* one task a file; a decoder that splits its own work (OpenEXR's chunks)
   * hands the pieces to the same threads */
#pragma omp parallel
#pragma omp single
  for (int t = 0; t < ntodo; t++) {
#pragma omp task firstprivate(t) shared(st, img, info, msg)
    {
      int k = todo[t];
      st[k] = jnd_image_read(path[k], &img[k], &info[k]);
      /* the message is thread-local: keep it for the calling thread. Tasks
       * are tied to their thread, and a read records its message after its
       * last scheduling point (the EXR decoder's taskloop), so another task
       * run meanwhile on this thread cannot have overwritten it */
      if (st[k] != JND_OK) snprintf(msg[k], sizeof msg[k], "%s", jnd_last_error());
    }
  }
  jnd_status s = JND_OK;
  const jnd_display *d = &jnd_model_get_params(m)->display;
  for (int t = 0; t < ntodo && s == JND_OK; t++) {
    int k = todo[t];
    if (st[k] != JND_OK) {
      s = jnd_fail(st[k], "%s", msg[k]);
    } else if ((KIND[k] == K_DISPLACEMENT || KIND[k] == K_DEPTH) && strcmp(info[k].format, "exr") != 0) {
      s = jnd_fail(JND_ERR_FORMAT, "%s: %s maps must be OpenEXR (float pixels), not %s", path[k],
                   KIND[k] == K_DEPTH ? "depth" : "displacement", info[k].format);
    } else if (k != IN_ACTUAL && (img[k].w != img[IN_ACTUAL].w || img[k].h != img[IN_ACTUAL].h)) {
      s = jnd_fail(JND_ERR_ARG, "%s: size %d × %d differs from %s (%d × %d)", path[k], img[k].w, img[k].h,
                   path[IN_ACTUAL], img[IN_ACTUAL].w, img[IN_ACTUAL].h);
    } else if (KIND[k] == K_COLOUR) {
      /* colour frames as the viewer sees them (alpha over the display's black) */
      s = jnd_display_apply(d, &img[k], info[k].encoding, info[k].has_alpha, &img[k]);
      if (s != JND_OK) s = jnd_fail(s, "%s: %s", path[k], jnd_last_error());
    } else if (KIND[k] == K_UNIT || KIND[k] == K_DEPTH) {
      img[k].c = 1; /* the first channel (its plane comes first) */
    }
  }
  if (s == JND_OK) {
    const jnd_image *I[NIN];
    for (int k = 0; k < NIN; k++) I[k] = path[k] ? &img[src[k]] : NULL;
    jnd_pop_inputs in = {0};
    in.actual = (jnd_pop_frame){I[IN_ACTUAL], I[IN_DISP_A], I[IN_DEPTH_A], I[IN_PREV_DEPTH_A]};
    in.expected = (jnd_pop_frame){I[IN_EXPECTED], I[IN_DISP_E], I[IN_DEPTH_E], I[IN_PREV_DEPTH_E]};
    in.weights = I[IN_WEIGHTS];
    in.prev_color = I[IN_PREV_COLOR];
    in.prev_shading = I[IN_PREV_SHADING];
    in.mask = I[IN_MASK];
    const double t_read = jnd_seconds() - t0;
    /* the frames were read for this call: the model may work in them */
    s = predict(m, &in, path, p, &img[src[IN_EXPECTED]], &img[src[IN_ACTUAL]], out);
    out->timings.read_s = t_read;
  }
  for (int k = 0; k < NIN; k++) jnd_image_free(&img[k]);
  return s;
}
