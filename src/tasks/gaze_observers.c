/* Synthetic observers for 002's models: answers drawn from jnd's own vision
 * model, to fit the default parameters without a study (docs/gaze.md
 * "Defaults").
 *
 * Procedure, per scene (its chain), object size and orientation:
 *  1. The object at the distance where its bounding sphere subtends the
 *     size; every level rendered once in the window the table uses
 *     (gaze_frame_for, gaze_render_levels).
 *  2. Per eccentricity e (fixation point e degrees left of the object's
 *     centre, as the table) and level k ≥ 1, three comparisons:
 *     - the spatial model's terms: xor_deg (eq. 1 with w ≡ 1) and v_jnd
 *       (jnd_gaze_spatial's shading term, the XOR grey);
 *     - what the observer sees: level 0 against level k, nothing greyed, at
 *       each pixel's eccentricity, pooled as the terms are (the silhouette
 *       change and the shading change as the vision model sees them, not as
 *       the gaze model's formula weighs them: otherwise the fit would only
 *       find the formula back);
 *     - the switch k − 1 → k through the model's temporal sensitivity
 *       (jnd_gaze_switch's t_jnd).
 *  3. Probabilities in the 2AFC range from 000 eq. 4's psychometric
 *     function: P = ½ + ½ · (1 − exp(ln ½ · J^β)), 0.75 at 1 JND.
 *  4. answers Bernoulli draws per stimulus and model, from one generator
 *     seeded with seed, in the stimuli's order (thread-independent).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "jnd.h"
#include "tasks/tasks.h"

void jnd_gaze_observers_defaults(jnd_gaze_observers_params *p) {
  memset(p, 0, sizeof *p);
  p->orientations = 2;
  p->answers = 40;
  p->seed = 1;
  p->min_px = 64;
  p->max_px = 192;
  jnd_gaze_measure_defaults(&p->measure);
  jnd_renderer_defaults(&p->render);
}

void jnd_gaze_observers_free(jnd_gaze_observers *o) {
  if (!o) return;
  free(o->stimuli);
  memset(o, 0, sizeof *o);
}

/* step 3: 000 eq. 4 in the 2AFC range */
static double two_afc_of_jnd(double jnd, double beta) { return 0.5 + 0.5 * jnd_probability(jnd, beta); }

/* One (scene, size): renders the chain and judges every (orientation,
 * eccentricity, level) into s[(o · ne + e) · (L − 1) + k − 1]. */
static jnd_status judge_size(jnd_scene *scene, jnd_renderer *r, jnd_pair_judge *judge, const jnd_gaze_observers_params *p,
                             const double *ecc, int ne, double size_deg, int L, jnd_gaze_stimulus *s) {
  const int no = p->orientations;
  double centre[3], radius;
  jnd_scene_subject_bounds(scene, centre, &radius, NULL);
  double dist = radius / sin(0.5 * size_deg * M_PI / 180.0), fov, ppd;
  int side;
  gaze_frame_for(p->measure.model.display.ppd, p->min_px, p->max_px, radius, dist, &fov, &side, &ppd);
  jnd_view *views = jnd_calloc((size_t)no, sizeof *views);
  gaze_renders R = {jnd_calloc((size_t)no * L, sizeof(jnd_image)), jnd_calloc((size_t)no * L, sizeof(jnd_image))};
  jnd_status st = views && R.color && R.mask ? JND_OK : JND_ERR_NOMEM;
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = no;
  vs.seed = p->seed;
  vs.distance = dist;
  vs.fov_y_deg = fov;
  vs.aspect = 1;
  int count = 0;
  if (st == JND_OK) st = jnd_views_sample(scene, &vs, views);
  if (st == JND_OK) st = jnd_renderer_resize(r, side, side);
  if (st == JND_OK) st = gaze_render_levels(scene, r, views, no, L, &R, &count);
  /* xor_deg: eq. 1 with the weight 1 everywhere (α = 0, b = 1) */
  jnd_gaze_model unit;
  jnd_gaze_model_defaults(&unit);
  unit.alpha = 0, unit.b = 1;
  const double cx = 0.5 * side - 0.5;
  jnd_gaze_measure_params mp = p->measure;
  mp.judge = judge;
  const int ntask = no * ne * (L - 1);
  jnd_status tst = JND_OK;
  if (st == JND_OK) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int t = 0; t < ntask; t++) {
      int k = 1 + t % (L - 1), e = t / (L - 1) % ne, o = t / (L - 1) / ne;
      const jnd_image *c = R.color + (size_t)o * L, *m = R.mask + (size_t)o * L;
      double gx = judge_fixation_left_of(cx, ecc[e], ppd);
      jnd_gaze_stimulus *x = &s[t];
      jnd_gaze_terms sp, sw;
      jnd_status q = jnd_gaze_spatial(&unit, &mp, ppd, gx, cx, &c[0], &m[0], &c[k], &m[k], &sp);
      if (q == JND_OK) q = gaze_pooled_jnd(&mp, ppd, gx, cx, &c[0], &m[0], &c[k], &m[k], 0, 0, &x->jnd_whole);
      if (q == JND_OK) q = jnd_gaze_switch(&unit, &mp, ppd, gx, cx, &c[k - 1], &m[k - 1], &c[k], &m[k], &sw);
      x->orientation = o, x->level = k, x->size_deg = size_deg, x->ecc_deg = ecc[e];
      x->xor_deg = sp.g_deg, x->v_jnd = sp.v_jnd, x->t_jnd = sw.t_jnd;
      x->p_spatial = two_afc_of_jnd(x->jnd_whole, mp.model.beta);
      x->p_switch = two_afc_of_jnd(x->t_jnd, mp.model.beta);
      if (q != JND_OK) {
#pragma omp critical(gaze_observers_status)
        tst = tst == JND_OK ? q : tst;
      }
    }
    st = tst;
  }
  for (int i = 0; R.color && R.mask && i < no * L; i++) jnd_image_free(&R.color[i]), jnd_image_free(&R.mask[i]);
  free(R.color), free(R.mask), free(views);
  return st;
}

jnd_status jnd_gaze_observers_run(jnd_scene *const *scenes, int nscenes, const jnd_gaze_observers_params *p,
                                  jnd_gaze_observers *out) {
  memset(out, 0, sizeof *out);
  static const double default_sizes[] = {1.5, 4, 12};
  static const double default_ecc[] = {0, 5, 10, 20, 30, 45, 60};
  static const double default_errors[] = {1.0 / 1024, 1.0 / 256, 1.0 / 64};
  const double *sizes = p->sizes_deg ? p->sizes_deg : default_sizes, *ecc = p->eccentricities_deg ? p->eccentricities_deg : default_ecc;
  const int ns = p->sizes_deg ? p->nsizes : 3, ne = p->eccentricities_deg ? p->neccentricities : 7;
  jnd_status st;
  if (nscenes < 1) return jnd_fail(JND_ERR_ARG, "gaze observers: give at least one model");
  if ((st = gaze_check_axis(sizes, ns, "--sizes", 0, 1, 60)) != JND_OK) return st;
  if ((st = gaze_check_axis(ecc, ne, "--eccentricities", 0, 0, 90)) != JND_OK) return st;
  if (p->orientations < 1 || p->orientations > 64) return jnd_fail(JND_ERR_ARG, "--orientations: give 1 to 64");
  if (p->answers < 1 || p->answers > 10000) return jnd_fail(JND_ERR_ARG, "--answers: give 1 to 10000");
  if (p->min_px < 16 || p->max_px < p->min_px || p->max_px > 4096)
    return jnd_fail(JND_ERR_ARG, "gaze: rendering sides must satisfy 16 <= min <= max <= 4096");
  int *levels = jnd_calloc((size_t)nscenes, sizeof *levels);
  if (!levels) return JND_ERR_NOMEM;
  int total = 0;
  for (int i = 0; i < nscenes; i++) {
    if (jnd_scene_lod_count(scenes[i]) < 2) {
      jnd_lod_params lp;
      jnd_lod_defaults(&lp);
      lp.errors = default_errors, lp.nerrors = 3;
      if ((st = jnd_scene_lod_build(scenes[i], p->chain ? p->chain : &lp)) != JND_OK) break;
    }
    levels[i] = jnd_scene_lod_count(scenes[i]);
    if (levels[i] < 2) {
      st = jnd_fail(JND_ERR_ARG, "%s: the chain has one level (nothing simpler could be made)", jnd_scene_path(scenes[i]));
      break;
    }
    total += ns * p->orientations * ne * (levels[i] - 1);
  }
  if (st != JND_OK) {
    free(levels);
    return st;
  }
  out->stimuli = jnd_calloc((size_t)total, sizeof *out->stimuli);
  out->answers = p->answers;
  jnd_renderer *r = NULL;
  st = out->stimuli ? judge_renderer(&p->render, p->min_px, &r) : JND_ERR_NOMEM;
  /* one judge of pairs for the run (a model per size's ppd and per thread) */
  jnd_model_params model = p->measure.model;
  model.threads = 1;   /* the stimuli run in parallel instead */
  jnd_pair_judge *judge = p->measure.judge, *own = NULL;
  if (st == JND_OK && !judge) st = jnd_pair_judge_create(&model, &own), judge = own;
  for (int i = 0; i < nscenes && st == JND_OK; i++)
    for (int z = 0; z < ns && st == JND_OK; z++) {
      jnd_gaze_stimulus *s = out->stimuli + out->n;
      st = judge_size(scenes[i], r, judge, p, ecc, ne, sizes[z], levels[i], s);
      int n = p->orientations * ne * (levels[i] - 1);
      for (int k = 0; k < n; k++) s[k].scene = i;
      out->n += n;
      if (p->progress) p->progress(p->progress_user, out->n, total);
    }
  jnd_renderer_free(r);
  jnd_pair_judge_free(own);
  free(levels);
  if (st != JND_OK) {
    jnd_gaze_observers_free(out);
    return st;
  }
  /* step 4: the answers, in the stimuli's order */
  jnd_rng g;
  jnd_rng_seed(&g, p->seed);
  for (int i = 0; i < out->n; i++) {
    jnd_gaze_stimulus *x = &out->stimuli[i];
    for (int a = 0; a < p->answers; a++) x->seen_spatial += jnd_rng_uniform(&g) < x->p_spatial;
    for (int a = 0; a < p->answers; a++) x->seen_switch += jnd_rng_uniform(&g) < x->p_switch;
  }
  return JND_OK;
}

jnd_status jnd_gaze_observers_write_csv(const jnd_gaze_observers *o, int temporal, const char *path) {
  size_t cap = 128 + (size_t)o->n * o->answers * 128, n = 0;
  char *buf = malloc(cap);
  if (!buf) return JND_ERR_NOMEM;
  n += (size_t)snprintf(buf + n, cap - n,
                        temporal ? "stimulus,scene,size_deg,at_deg,level,t_jnd,p_true,seen\n"
                                 : "stimulus,scene,size_deg,eccentricity_deg,level,xor_deg,v_jnd,jnd_whole,p_true,seen\n");
  for (int i = 0; i < o->n; i++) {
    const jnd_gaze_stimulus *x = &o->stimuli[i];
    int seen = temporal ? x->seen_switch : x->seen_spatial;
    /* the answers of a stimulus: its `seen` ones first (their order carries nothing) */
    for (int a = 0; a < o->answers; a++) {
      if (temporal)
        n += (size_t)snprintf(buf + n, cap - n, "%d,%d,%.6g,%.6g,%d,%.9g,%.6f,%d\n", i, x->scene, x->size_deg,
                              x->ecc_deg, x->level, x->t_jnd, x->p_switch, a < seen);
      else
        n += (size_t)snprintf(buf + n, cap - n, "%d,%d,%.6g,%.6g,%d,%.9g,%.9g,%.9g,%.6f,%d\n", i, x->scene,
                              x->size_deg, x->ecc_deg, x->level, x->xor_deg, x->v_jnd, x->jnd_whole, x->p_spatial,
                              a < seen);
    }
  }
  jnd_status st = jnd_write_file_atomic(path, buf, n);
  free(buf);
  return st;
}
