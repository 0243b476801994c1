/* Calibration of the model to a task (000 §6–§7). A general visibility
 * metric is too conservative for texture resolution in a game (000 §6:
 * observers do not scrutinise every pixel), so 000 retunes it to measured
 * thresholds: (1) pooling by a percentile (90th–99th tested, §6) instead of
 * the maximum, (2) a linear transform of the metric's contrast before the
 * psychometric function (§7.1: scale and bias, exhaustive search over the
 * bias), both chosen to minimise the error between the predicted threshold
 * resolution (000 eq. 1 fitted to the pooled P of a resolution series, read
 * at P = 0.2) and the measured one; k-fold cross-validation by scene (§7.3).
 *
 * In jnd the quantity before the psychometric function is the JND map, so a
 * calibration maps JND → max(0, a·JND + b) before P = 1 − exp(ln 0.5 · x^β)
 * (000 eq. 4) and pools P with its percentile. Both transforms are monotone,
 * so the pooled P of a map is ψ(max(0, a·J_p + b)) with J_p the JND map's
 * own percentile: a series of maps reduces to ten numbers per resolution and
 * the search is cheap. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "pool/pool.h"

void jnd_calibration_defaults(jnd_calibration *c) {
  memset(c, 0, sizeof *c);
  jnd_criterion cr;
  jnd_criterion_defaults(&cr);
  c->percentile = 93; /* 000 §6: P93 pools best */
  c->scale = 1;
  c->bias = 0;
  c->beta = 3.5;      /* 000 eq. 4 */
  c->threshold_p = cr.p;   /* 000 §6 reads thresholds where the criterion does */
}

static int json_number(const cJSON *o, const char *key, double *v) {
  const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!x) return 0;
  if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) return -1;
  *v = x->valuedouble;
  return 1;
}

jnd_status jnd_calibration_load(const char *path, jnd_calibration *c) {
  jnd_calibration_defaults(c);
  unsigned char *text = NULL;
  size_t n = 0;
  jnd_status st = jnd_read_file(path, (size_t)16 << 20, &text, &n);
  if (st != JND_OK) return st;
  cJSON *root = cJSON_ParseWithLength((const char *)text, n);
  free(text);
  if (!root) return jnd_fail(JND_ERR_FORMAT, "%s: not JSON", path);
  const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "calibration");
  if (!o) {
    /* a `jnd calibrate` report keeps it under result */
    const cJSON *res = cJSON_GetObjectItemCaseSensitive(root, "result");
    o = cJSON_GetObjectItemCaseSensitive(res, "calibration");
  }
  if (!cJSON_IsObject(o)) {
    cJSON_Delete(root);
    return jnd_fail(JND_ERR_FORMAT, "%s: no \"calibration\" object (write one with jnd calibrate)", path);
  }
  static const char *const need[3] = {"percentile", "scale", "bias"};
  double *dst[3] = {&c->percentile, &c->scale, &c->bias};
  for (int k = 0; k < 3; k++) {
    if (json_number(o, need[k], dst[k]) != 1) {
      cJSON_Delete(root);
      return jnd_fail(JND_ERR_FORMAT, "%s: calibration.%s is missing or not a number", path, need[k]);
    }
  }
  if (json_number(o, "beta", &c->beta) < 0 || json_number(o, "threshold_p", &c->threshold_p) < 0 ||
      json_number(o, "mae_px", &c->mae_px) < 0) {
    cJSON_Delete(root);
    return jnd_fail(JND_ERR_FORMAT, "%s: calibration.beta, threshold_p and mae_px must be numbers", path);
  }
  cJSON_Delete(root);
  if (!(c->percentile >= 0 && c->percentile <= 100) || !(c->scale > 0) || !(c->beta > 0) ||
      !(c->threshold_p > 0 && c->threshold_p < 1))
    return jnd_fail(JND_ERR_FORMAT, "%s: calibration values out of range (percentile 0..100, scale > 0, beta > 0)",
                    path);
  c->path = path;
  return JND_OK;
}

jnd_status jnd_calibration_save(const char *path, const jnd_calibration *c) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "jnd_version", jnd_version());
  cJSON_AddStringToObject(root, "kind", "jnd calibration (000 §6-§7): JND -> max(0, scale*JND + bias) -> "
                                        "P = 1 - exp(ln 0.5 x^beta) -> percentile pooling");
  cJSON *o = cJSON_AddObjectToObject(root, "calibration");
  cJSON_AddNumberToObject(o, "percentile", c->percentile);
  cJSON_AddNumberToObject(o, "scale", c->scale);
  cJSON_AddNumberToObject(o, "bias", c->bias);
  cJSON_AddNumberToObject(o, "beta", c->beta);
  cJSON_AddNumberToObject(o, "threshold_p", c->threshold_p);
  cJSON_AddNumberToObject(o, "mae_px", c->mae_px);
  char *text = cJSON_Print(root);
  cJSON_Delete(root);
  if (!text) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  size_t n = strlen(text);
  char *t2 = malloc(n + 2);
  if (!t2) {
    free(text);
    return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  }
  memcpy(t2, text, n);
  t2[n] = '\n';
  jnd_status s = jnd_write_file_atomic(path, t2, n + 1);
  free(t2);
  free(text);
  return s;
}

static double calibrated_p(const jnd_calibration *c, double jnd) {
  double x = c->scale * jnd + c->bias;
  return jnd_probability(x > 0 ? x : 0, c->beta);
}

double jnd_calibration_pool(const jnd_calibration *c, const jnd_image *map, const jnd_image *mask) {
  size_t n = (size_t)map->w * map->h, k = 0;
  float *v = jnd_alloc(n ? n : 1, sizeof *v);
  if (!v) return NAN;
  for (size_t i = 0; i < n; i++)
    if (!mask || mask->data[i] > 0.5f) v[k++] = map->data[i];
  /* monotone transforms commute with order statistics */
  double r = k > 0 ? calibrated_p(c, jnd_percentile(v, k, c->percentile)) : NAN;
  free(v);
  return r;
}

jnd_status jnd_diff_summarise_calibrated(const jnd_image *map, const jnd_calibration *c, jnd_diff_stats *st) {
  jnd_image t = {0};
  jnd_status s = jnd_image_alloc(&t, map->w, map->h, 1);
  if (s != JND_OK) return s;
  size_t n = (size_t)map->w * map->h;
  for (size_t i = 0; i < n; i++) {
    double x = c->scale * map->data[i] + c->bias;
    t.data[i] = (float)(x > 0 ? x : 0);
  }
  jnd_pooling pool = {JND_POOL_PERCENTILE, c->percentile};
  s = jnd_diff_summarise(&t, c->beta, &pool, st);
  jnd_image_free(&t);
  return s;
}

jnd_status jnd_calib_percentiles(const jnd_image *map, const jnd_image *mask, double *out) {
  size_t n = (size_t)map->w * map->h, k = 0;
  float *v = jnd_alloc(n ? n : 1, sizeof *v);
  if (!v) return JND_ERR_NOMEM;
  for (size_t i = 0; i < n; i++)
    if (!mask || mask->data[i] > 0.5f) v[k++] = map->data[i];
  double pct[JND_CALIB_NPCT];
  for (int j = 0; j < JND_CALIB_NPCT; j++) pct[j] = JND_CALIB_PCT_LO + j;
  jnd_status s = k ? jnd_percentiles(v, k, pct, JND_CALIB_NPCT, out)
                   : jnd_fail(JND_ERR_ARG, "calibration: no pixel under the mask");
  free(v);
  return s;
}

/* The rendered series of one map for calibration (000 §6–§7): the judge's
 * JND maps (its views, display and model; before any calibration, which is
 * what is being fitted) of the map at each size against the file's map,
 * the object's pixels of every view pooled together. */
jnd_status jnd_calib_series_percentiles(jnd_scene *scene, const char *map, const int *sizes, int nres,
                                        const jnd_judge_params *p, double *out) {
  int mi_idx = jnd_scene_map_find(scene, map);
  if (mi_idx < 0) return jnd_fail(JND_ERR_ARG, "%s: no map %s", jnd_scene_path(scene), map);
  if (nres < 1 || !sizes) return jnd_fail(JND_ERR_ARG, "%s: no sizes", map);
  jnd_map_info mi;
  jnd_scene_map_info(scene, mi_idx, &mi);
  jnd_scene_map_restore(scene, mi_idx);
  jnd_judge *j = NULL;
  jnd_status s = jnd_judge_create(scene, p, &j);
  if (s != JND_OK) return s;
  int nv = jnd_judge_view_count(j), L = mi.orig_width > mi.orig_height ? mi.orig_width : mi.orig_height;
  float *all = NULL;
  size_t cap = 0;
  for (int r = 0; r < nres && s == JND_OK; r++) {
    int w = (int)lround((double)sizes[r] * mi.orig_width / L), h = (int)lround((double)sizes[r] * mi.orig_height / L);
    if ((s = jnd_scene_map_resize(scene, mi_idx, w < 1 ? 1 : w, h < 1 ? 1 : h)) != JND_OK) break;
    size_t n = 0;
    for (int v = 0; v < nv && s == JND_OK; v++) {
      jnd_image jm = {0}, mask = {0};
      s = jnd_judge_view_images(j, v, &jm, NULL, &mask, NULL, NULL);
      size_t px = (size_t)jm.w * jm.h;
      if (s == JND_OK && n + px > cap) {
        cap = 2 * (n + px);
        float *a = realloc(all, cap * sizeof *a);
        if (!a) s = jnd_fail(JND_ERR_NOMEM, "calibration: out of memory");
        else all = a;
      }
      for (size_t q = 0; s == JND_OK && q < px; q++)
        if (mask.data[q] > 0.5f) all[n++] = jm.data[q];
      jnd_image_free(&jm);
      jnd_image_free(&mask);
    }
    if (s != JND_OK) break;
    /* percentiles over the object's pixels of every view together */
    float zero = 0;
    jnd_image pooled = {(int)(n ? n : 1), 1, 1, n ? all : &zero};
    s = jnd_calib_percentiles(&pooled, NULL, out + (size_t)r * JND_CALIB_NPCT);
  }
  jnd_scene_map_restore(scene, mi_idx);
  free(all);
  jnd_judge_free(j);
  return s;
}

void jnd_calibrate_defaults(jnd_calibrate_params *p) {
  memset(p, 0, sizeof *p);
  jnd_calibration cal;
  jnd_calibration_defaults(&cal);
  p->folds = 5;
  p->beta = cal.beta;
  p->threshold_p = cal.threshold_p;
  p->bias_min = -2;
  p->bias_max = 2;
  p->bias_steps = 21;
  p->scale_min = 0.05;
  p->scale_max = 20;
}

void jnd_calibrate_result_clear(jnd_calibrate_result *r) {
  free(r->errors_px);
  free(r->predicted_px);
  free(r->report);
  r->errors_px = r->predicted_px = NULL;
  r->report = NULL;
}

void jnd_calibrate_result_free(jnd_calibrate_result *r) {
  if (!r) return;
  jnd_calibrate_result_clear(r);
  free(r);
}

/* ---- the fit ---- */

#define CAL_MAX_RES 256
/* P levels at which the predicted and measured functions are also compared
 * (weight CURVE_WEIGHT): thresholds alone fix only where a·J + b crosses
 * ψ⁻¹(0.2), not a and b apart, so the slope of the measured function
 * (its σ) is what separates scale from bias. */
static const double curve_levels[3] = {0.1, 0.5, 0.8};
#define CURVE_WEIGHT 0.5

typedef struct {
  const jnd_calib_scene *sc;
  int n;
  const int *use;   /* scenes in the set (1) or held out (0); NULL all */
  double beta, pthr;
} cal_set;

/* The predicted function of scene s under (pct k, a, b): eq. 1 fitted (in
 * pixels, as 000) to the calibrated pooled P of its series. */
static int predict(const cal_set *S, int s, int k, double a, double b, jnd_psychometric *f) {
  const jnd_calib_scene *c = &S->sc[s];
  double p[CAL_MAX_RES];
  jnd_calibration cal = {.percentile = 0, .scale = a, .bias = b, .beta = S->beta, .threshold_p = S->pthr};
  for (int i = 0; i < c->nres; i++) p[i] = calibrated_p(&cal, c->jnd_pct[i * JND_CALIB_NPCT + k]);
  return jnd_psychometric_fit(c->res, p, c->nres, 0, f) == JND_OK;
}

static double measured_at(const jnd_calib_scene *c, double level) {
  jnd_psychometric m = {c->mu, c->sigma > 1e-9 ? c->sigma : 1e-9, 0, 0};
  return jnd_psychometric_resolution(&m, level);
}

/* objective: mean absolute threshold error (pixels) + CURVE_WEIGHT × the
 * mean absolute error at the other levels; *mae gets the threshold part */
static double objective(const cal_set *S, int k, double a, double b, double *mae) {
  double e = 0, ec = 0;
  int m = 0;
  for (int s = 0; s < S->n; s++) {
    if (S->use && !S->use[s]) continue;
    jnd_psychometric f;
    if (!predict(S, s, k, a, b, &f)) return INFINITY;
    e += fabs(jnd_psychometric_resolution(&f, S->pthr) - measured_at(&S->sc[s], S->pthr));
    for (int l = 0; l < 3; l++)
      ec += fabs(jnd_psychometric_resolution(&f, curve_levels[l]) - measured_at(&S->sc[s], curve_levels[l])) / 3;
    m++;
  }
  if (!m) return INFINITY;
  if (mae) *mae = e / m;
  return (e + CURVE_WEIGHT * ec) / m;
}

/* golden-section minimum of the objective along one coordinate (log
 * scale or bias) in [x0, x1], the other fixed; returns the best x and its
 * objective in *fbest (never worse than at x_start) */
static double golden(const cal_set *S, int k, int along_scale, double fixed, double x0, double x1, double x_start,
                     double *fbest) {
#define CAL_F(x) (along_scale ? objective(S, k, exp(x), fixed, NULL) : objective(S, k, exp(fixed), (x), NULL))
  const double g = 0.6180339887498949;
  double c = x1 - g * (x1 - x0), d = x0 + g * (x1 - x0);
  double fc = CAL_F(c), fd = CAL_F(d);
  for (int it = 0; it < 10; it++) {
    if (fc < fd) {
      x1 = d, d = c, fd = fc;
      c = x1 - g * (x1 - x0);
      fc = CAL_F(c);
    } else {
      x0 = c, c = d, fc = fd;
      d = x0 + g * (x1 - x0);
      fd = CAL_F(d);
    }
  }
  double xs = fc < fd ? c : d, fs = fc < fd ? fc : fd;
  if (!(fs < *fbest)) return x_start;
  *fbest = fs;
  return xs;
#undef CAL_F
}

typedef struct {
  int k;
  double a, b, obj, mae;
} cal_fit;

/* the best log scale for bias b: a scan of nscan + 1 points over [l0, l1],
 * then golden section between the best point's neighbours */
static double best_log_scale(const cal_set *S, int k, double b, double l0, double l1, int nscan, double *f) {
  double best = INFINITY, lb = l0, step = (l1 - l0) / nscan;
  for (int i = 0; i <= nscan; i++) {
    double o = objective(S, k, exp(l0 + step * i), b, NULL);
    if (o < best) best = o, lb = l0 + step * i;
  }
  *f = best;
  return golden(S, k, 1, b, lb - step, lb + step, lb, f);
}

/* per percentile: an exhaustive search over bias (000 §7.1), each bias with
 * its best scale (the valley of equal thresholds runs diagonally in
 * (log a, b), so the scale is followed along it), then a golden-section
 * search over bias between the best grid point's neighbours */
static void fit_set(const cal_set *S, const jnd_calibrate_params *p, cal_fit *best, double *pct_mae) {
  best->obj = INFINITY;
  int steps = p->bias_steps > 1 ? p->bias_steps : 2, nscan = 6;
  double db = (p->bias_max - p->bias_min) / (steps - 1);
  double l0 = log(p->scale_min), l1 = log(p->scale_max), ds = (l1 - l0) / nscan;
  cal_fit per[JND_CALIB_NPCT];
  /* the percentiles are independent searches; the best is picked in order
   * afterwards, so the result does not depend on the threads */
#pragma omp parallel for schedule(dynamic, 1)
  for (int k = 0; k < JND_CALIB_NPCT; k++) {
    double la = 0, b = 0, f = INFINITY;
    for (int i = 0; i < steps; i++) {
      double bi = p->bias_min + db * i, fi;
      double li = best_log_scale(S, k, bi, l0, l1, nscan, &fi);
      if (fi < f) f = fi, la = li, b = bi;
    }
    const double g = 0.6180339887498949;
    double x0 = b - db, x1 = b + db, lc, ld, fc, fd;
    double c = x1 - g * (x1 - x0), d = x0 + g * (x1 - x0);
    lc = best_log_scale(S, k, c, la - ds, la + ds, 4, &fc);
    ld = best_log_scale(S, k, d, la - ds, la + ds, 4, &fd);
    for (int it = 0; it < 14; it++) {
      if (fc < fd) {
        x1 = d, d = c, fd = fc, ld = lc;
        c = x1 - g * (x1 - x0);
        lc = best_log_scale(S, k, c, la - ds, la + ds, 4, &fc);
      } else {
        x0 = c, c = d, fc = fd, lc = ld;
        d = x0 + g * (x1 - x0);
        ld = best_log_scale(S, k, d, la - ds, la + ds, 4, &fd);
      }
    }
    if (fc < f) f = fc, b = c, la = lc;
    if (fd < f) f = fd, b = d, la = ld;
    cal_fit cf = {k, exp(la), b, f, INFINITY};
    objective(S, k, cf.a, cf.b, &cf.mae);
    per[k] = cf;
  }
  for (int k = 0; k < JND_CALIB_NPCT; k++) {
    if (pct_mae) pct_mae[k] = per[k].mae;
    if (per[k].obj < best->obj - 1e-9) *best = per[k];
  }
}

jnd_status jnd_calibrate_fit(const jnd_calib_scene *scenes, int n, const jnd_calibrate_params *pp,
                             jnd_calibrate_result *out) {
  memset(out, 0, sizeof *out);
  jnd_calibrate_params p;
  if (pp) p = *pp;
  else jnd_calibrate_defaults(&p);
  if (n < 1) return jnd_fail(JND_ERR_ARG, "calibration: no scenes");
  for (int s = 0; s < n; s++) {
    if (scenes[s].nres < 2 || scenes[s].nres > CAL_MAX_RES)
      return jnd_fail(JND_ERR_ARG, "%s: a scene needs 2..%d resolutions (has %d)", scenes[s].name, CAL_MAX_RES,
                      scenes[s].nres);
    if (!(scenes[s].mu > 0) || !(scenes[s].sigma >= 0))
      return jnd_fail(JND_ERR_ARG, "%s: measured mu must be > 0 and sigma >= 0", scenes[s].name);
  }
  if (!(p.scale_min > 0 && p.scale_max > p.scale_min) || !(p.bias_max >= p.bias_min) || !(p.beta > 0))
    return jnd_fail(JND_ERR_ARG, "calibration: bad search ranges");
  /* folds by scene name: scenes sharing a name stay in one fold (000 §7.3) */
  int *fold = jnd_calloc((size_t)n, sizeof *fold), *use = jnd_calloc((size_t)n, sizeof *use);
  out->errors_px = jnd_calloc((size_t)n, sizeof *out->errors_px);
  out->predicted_px = jnd_calloc((size_t)n, sizeof *out->predicted_px);
  if (!fold || !use || !out->errors_px || !out->predicted_px) {
    free(fold);
    free(use);
    jnd_calibrate_result_clear(out);
    return JND_ERR_NOMEM;
  }
  int nnames = 0;
  for (int s = 0; s < n; s++) {
    int g = -1;
    for (int t = 0; t < s; t++)
      if (strcmp(scenes[t].name, scenes[s].name) == 0) g = fold[t];
    fold[s] = g >= 0 ? g : nnames++;
  }
  int K = p.folds < nnames ? p.folds : nnames;
  if (K > 32) K = 32;
  for (int s = 0; s < n; s++) fold[s] %= (K > 0 ? K : 1);
  out->nscenes = n;
  cal_set S = {scenes, n, NULL, p.beta, p.threshold_p};
  cal_fit all;
  fit_set(&S, &p, &all, out->pct_mae_px);
  out->cal.percentile = JND_CALIB_PCT_LO + all.k;
  out->cal.scale = all.a;
  out->cal.bias = all.b;
  out->cal.beta = p.beta;
  out->cal.threshold_p = p.threshold_p;
  out->mae_px = all.mae;
  for (int s = 0; s < n; s++) {
    jnd_psychometric f;
    out->predicted_px[s] = predict(&S, s, all.k, all.a, all.b, &f) ? jnd_psychometric_resolution(&f, p.threshold_p)
                                                                    : NAN;
  }
  /* k-fold cross-validation: fit without a fold, predict it */
  out->folds = K >= 2 ? K : 0;
  double cv = 0;
  for (int k = 0; k < out->folds; k++) {
    for (int s = 0; s < n; s++) use[s] = fold[s] != k;
    cal_set T = {scenes, n, use, p.beta, p.threshold_p};
    cal_fit f;
    fit_set(&T, &p, &f, NULL);
    double e = 0;
    int m = 0;
    for (int s = 0; s < n; s++) {
      if (fold[s] != k) continue;
      jnd_psychometric pf;
      double pred = predict(&T, s, f.k, f.a, f.b, &pf) ? jnd_psychometric_resolution(&pf, p.threshold_p) : NAN;
      out->errors_px[s] = pred - measured_at(&scenes[s], p.threshold_p);
      e += fabs(out->errors_px[s]);
      m++;
    }
    out->fold_mae_px[k] = m ? e / m : NAN;
    cv += e;
  }
  if (!out->folds)
    for (int s = 0; s < n; s++) out->errors_px[s] = out->predicted_px[s] - measured_at(&scenes[s], p.threshold_p);
  out->cv_mae_px = out->folds ? cv / n : out->mae_px;
  out->cal.mae_px = out->cv_mae_px;
  free(fold);
  free(use);
  return JND_OK;
}
