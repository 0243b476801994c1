/* jnd_calibrate_run: `jnd calibrate` as one library call (000 §6–§7) — the
 * thresholds table grouped into scenes, each scene's series measured (an
 * asset rendered by the judge, or image pairs diffed), the fit, and the
 * calibration file (which is the report) and its histogram written through
 * one output writer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"
#include "tasks/tasks.h"

#define SERIES_MAX 64   /* resolutions per scene */

/* one scene of the table: its measurement and its series */
typedef struct {
  char name[128];
  char model[1024], map[160];
  double mu, sigma;
  int has_mu;
  int nres;
  double res[SERIES_MAX], rate[SERIES_MAX];
  double pct[SERIES_MAX * JND_CALIB_NPCT];
  int npct;                 /* resolutions whose percentiles are known */
  double pct_res[SERIES_MAX];
} scene_rec;

void jnd_calibrate_run_defaults(jnd_calibrate_run_params *p) {
  memset(p, 0, sizeof *p);
  jnd_calibrate_defaults(&p->fit);
  jnd_judge_defaults(&p->judge);
  p->judge.views.render.width = p->judge.views.render.height = 256;
  p->judge.views.sampling.count = 4;
  jnd_run_options_defaults(&p->run);
}

/* a path in a table, relative to the table's folder */
static void rel_path(const char *table, const char *p, char *out, size_t n) {
  if (p[0] == '/') {
    snprintf(out, n, "%s", p);
    return;
  }
  const char *slash = strrchr(table, '/');
  if (!slash) snprintf(out, n, "%s", p);
  else snprintf(out, n, "%.*s/%s", (int)(slash - table), table, p);
}

static jnd_status number(const char *file, int row, const char *colname, const char *cell, double *v) {
  if (!jnd_csv_number(cell, v) || !isfinite(*v))
    return jnd_fail(JND_ERR_FORMAT, "%s: row %d: %s '%s' is not a number", file, row + 2, colname, cell);
  return JND_OK;
}

static int find_scene(const scene_rec *s, int n, const char *name, const char *map) {
  for (int i = 0; i < n; i++)
    if (strcmp(s[i].name, name) == 0 && strcmp(s[i].map, map) == 0) return i;
  return -1;
}

/* the thresholds table into scenes; the assets it names join the inputs */
static jnd_status read_thresholds(const char *path, const jnd_csv *csv, int has_pairs, report_output *o, scene_rec *sc,
                                  int *nsc) {
  int c_scene = jnd_csv_column(csv, "scene"), c_mu = jnd_csv_column(csv, "mu"), c_sigma = jnd_csv_column(csv, "sigma"),
      c_res = jnd_csv_column(csv, "resolution"), c_rate = jnd_csv_column(csv, "rate"),
      c_model = jnd_csv_column(csv, "model"), c_map = jnd_csv_column(csv, "map");
  int by_mu = c_mu >= 0 && c_sigma >= 0, by_rate = c_res >= 0 && c_rate >= 0;
  if (c_scene < 0 || (!by_mu && !by_rate))
    return jnd_fail(JND_ERR_FORMAT, "%s: missing column%s (need scene, and mu and sigma, or resolution and rate)",
                    path, c_scene < 0 ? " 'scene'" : "s");
  if ((c_model >= 0) != (c_map >= 0))
    return jnd_fail(JND_ERR_FORMAT, "%s: missing column '%s' (model and map go together)", path,
                    c_model >= 0 ? "map" : "model");
  if (c_model < 0 && !has_pairs)
    return jnd_fail(JND_ERR_ARG, "%s: no image series: give model and map columns, or --pairs FILE.csv", path);
  if (csv->nrows < 1) return jnd_fail(JND_ERR_FORMAT, "%s: no rows", path);
  *nsc = 0;
  for (int r = 0; r < csv->nrows; r++) {
    const char *name = csv->cells[r][c_scene], *map = c_map >= 0 ? csv->cells[r][c_map] : "";
    if (!*name) return jnd_fail(JND_ERR_FORMAT, "%s: row %d: empty scene", path, r + 2);
    int k = find_scene(sc, *nsc, name, map);
    if (k < 0) {
      scene_rec *n = &sc[k = (*nsc)++];
      snprintf(n->name, sizeof n->name, "%s", name);
      snprintf(n->map, sizeof n->map, "%s", map);
      if (c_model >= 0) {
        const char *m = csv->cells[r][c_model];
        jnd_builtin_params bp;
        jnd_builtin_defaults(&bp);
        if (jnd_builtin_parse(m, &bp) != 0) snprintf(n->model, sizeof n->model, "%s", m);
        else rel_path(path, m, n->model, sizeof n->model);
        const char *one[] = {n->model};
        jnd_status s = report_output_add_inputs(o, one, 1);
        if (s != JND_OK) return s;
      }
    }
    scene_rec *S = &sc[k];
    jnd_status s = JND_OK;
    if (by_mu && *csv->cells[r][c_mu]) {
      if ((s = number(path, r, "mu", csv->cells[r][c_mu], &S->mu)) != JND_OK ||
          (s = number(path, r, "sigma", csv->cells[r][c_sigma], &S->sigma)) != JND_OK)
        return s;
      if (!(S->mu > 0) || S->sigma < 0)
        return jnd_fail(JND_ERR_FORMAT, "%s: row %d: mu must be > 0 and sigma >= 0 (pixels)", path, r + 2);
      S->has_mu = 1;
    }
    if (by_rate && *csv->cells[r][c_res] && *csv->cells[r][c_rate]) {
      double res, rate;
      if ((s = number(path, r, "resolution", csv->cells[r][c_res], &res)) != JND_OK ||
          (s = number(path, r, "rate", csv->cells[r][c_rate], &rate)) != JND_OK)
        return s;
      if (!(res >= 1) || rate < 0 || rate > 1 || S->nres >= SERIES_MAX)
        return jnd_fail(JND_ERR_FORMAT,
                        "%s: row %d: resolution must be >= 1 pixel and rate 0..1 (at most %d per scene)", path,
                        r + 2, SERIES_MAX);
      S->res[S->nres] = res;
      S->rate[S->nres++] = rate;
    }
  }
  /* 000 eq. 1 fitted to the rates where mu and sigma are not given */
  for (int k = 0; k < *nsc; k++) {
    if (sc[k].has_mu) continue;
    jnd_psychometric f;
    if (sc[k].nres < 2 || jnd_psychometric_fit(sc[k].res, sc[k].rate, sc[k].nres, 0, &f) != JND_OK)
      return jnd_fail(JND_ERR_FORMAT, "%s: scene %s: needs mu and sigma, or detection rates at 2 or more resolutions",
                      path, sc[k].name);
    sc[k].mu = f.mu;
    sc[k].sigma = f.sigma;
  }
  return JND_OK;
}

/* the image pairs table: each pair's JND percentiles, for the scenes without
 * a model; its images join the inputs before any is read */
static jnd_status measure_pairs(const char *path, const jnd_judge_params *jp, report_output *o, scene_rec *sc,
                                int nsc) {
  jnd_csv pairs = {0};
  jnd_model *model = NULL;
  jnd_status s = jnd_csv_read(path, &pairs);
  if (s != JND_OK) return s;
  int p_scene = jnd_csv_column(&pairs, "scene"), p_res = jnd_csv_column(&pairs, "resolution"),
      p_ref = jnd_csv_column(&pairs, "reference"), p_test = jnd_csv_column(&pairs, "test");
  if (p_scene < 0 || p_res < 0 || p_ref < 0 || p_test < 0)
    s = jnd_fail(JND_ERR_FORMAT, "%s: missing column (need scene, resolution, reference, test)", path);
  char rp[4200], tp[4200];
  for (int r = 0; r < pairs.nrows && s == JND_OK; r++) {
    rel_path(path, pairs.cells[r][p_ref], rp, sizeof rp);
    rel_path(path, pairs.cells[r][p_test], tp, sizeof tp);
    const char *two[] = {rp, tp};
    s = report_output_add_inputs(o, two, 2);
  }
  if (s == JND_OK) {
    jnd_model_params mp = jp->model;
    mp.threads = 1;
    if (jnd_model_create(&mp, &model) != JND_OK) s = jnd_fail(JND_ERR_ARG, "calibrate: %s", jnd_last_error());
  }
  for (int r = 0; r < pairs.nrows && s == JND_OK; r++) {
    int k = -1;
    for (int j = 0; j < nsc; j++)
      if (strcmp(sc[j].name, pairs.cells[r][p_scene]) == 0 && !sc[j].model[0]) k = j;
    if (k < 0) continue;
    double res;
    if ((s = number(path, r, "resolution", pairs.cells[r][p_res], &res)) != JND_OK) break;
    if (sc[k].npct >= SERIES_MAX) continue;
    rel_path(path, pairs.cells[r][p_ref], rp, sizeof rp);
    rel_path(path, pairs.cells[r][p_test], tp, sizeof tp);
    jnd_image ref = {0}, test = {0}, map = {0};
    jnd_image_info ri, ti;
    s = jnd_image_read(rp, &ref, &ri);
    if (s == JND_OK) s = jnd_image_read(tp, &test, &ti);
    if (s == JND_OK) {
      s = jnd_diff_files(model, &ref, &ri, &test, &ti, NULL, NULL, &map, NULL);
      if (s == JND_OK) s = jnd_calib_percentiles(&map, NULL, sc[k].pct + (size_t)sc[k].npct * JND_CALIB_NPCT);
      if (s != JND_OK) s = jnd_fail(s, "%s: %s", tp, jnd_last_error());
    }
    jnd_image_free(&ref);
    jnd_image_free(&test);
    jnd_image_free(&map);
    if (s == JND_OK) sc[k].pct_res[sc[k].npct++] = res;
  }
  jnd_model_free(model);
  jnd_csv_free(&pairs);
  return s;
}

/* an asset's series: the map at each size, rendered and judged */
static jnd_status measure_asset(scene_rec *S, const jnd_calibrate_run_params *p) {
  jnd_scene *scene = NULL;
  jnd_status s = jnd_scene_open(S->model, p->run.map_size, &scene);
  if (s != JND_OK) return s;
  int idx = jnd_scene_map_find(scene, S->map);
  if (idx < 0) {
    jnd_scene_free(scene);
    return jnd_fail(JND_ERR_ARG, "%s: no map '%s' (jnd render %s --list-maps)", S->model, S->map, S->model);
  }
  jnd_map_info mi;
  jnd_scene_map_info(scene, idx, &mi);
  int L = mi.orig_width > mi.orig_height ? mi.orig_width : mi.orig_height;
  int ss[SERIES_MAX], n = 0;
  if (S->nres >= 2 && !p->nsizes) {
    for (int i = 0; i < S->nres && n < SERIES_MAX; i++) ss[n++] = (int)lround(S->res[i]);
  } else if (p->nsizes) {
    for (int i = 0; i < p->nsizes && n < SERIES_MAX; i++) ss[n++] = p->sizes[i];
  } else {
    for (int i = 1; i <= 11; i++) ss[n++] = (int)lround(L * (1.0 - i * (5.0 / 6.0) / 11.0));
  }
  s = jnd_calib_series_percentiles(scene, S->map, ss, n, &p->judge, S->pct);
  jnd_scene_free(scene);
  if (s != JND_OK) return s;
  for (int i = 0; i < n; i++) S->pct_res[i] = ss[i];
  S->npct = n;
  return JND_OK;
}

/* 000 Fig. 9/11: counts of held-out signed errors in 32-pixel bins */
static jnd_status write_histogram(const char *path, const jnd_calibrate_result *R) {
  jnd_image img = {0};
  jnd_status s = jnd_calibrate_histogram(R, &img);
  if (s == JND_OK) s = jnd_image_write_png(path, &img, 8);
  jnd_image_free(&img);
  return s;
}

jnd_status jnd_calibrate_run(const char *csv_path, const jnd_calibrate_run_params *pp, const char *out_path,
                             jnd_calibrate_result **out) {
  *out = NULL;
  if (!csv_path || !out_path) return jnd_fail(JND_ERR_ARG, "calibrate: give a thresholds table and an output file");
  jnd_calibrate_run_params p;
  if (pp) p = *pp;
  else jnd_calibrate_run_defaults(&p);
  p.judge.model.beta = p.fit.beta;
  /* the outputs checked before any work; the files the tables name join
   * the inputs as they are read */
  const char *ins[] = {csv_path, p.pairs, p.judge.views.render.env_path, p.judge.views.cameras_path};
  report_output o;
  jnd_status s = report_output_open(&o, ins, 4, NULL, NULL);
  if (s != JND_OK) return s;
  const char *staged_out = NULL, *staged_hist = NULL;
  s = jnd_output_add_file(o.w, out_path, &staged_out);
  if (s == JND_OK && p.histogram) s = jnd_output_add_file(o.w, p.histogram, &staged_hist);
  if (s == JND_OK) s = report_output_add_copy(&o, &p.run);
  jnd_csv csv = {0};
  scene_rec *sc = NULL;
  jnd_calib_scene *cs = NULL;
  const char **maps = NULL;
  int nsc = 0;
  cJSON *report = NULL;
  jnd_calibrate_result *R = jnd_calloc(1, sizeof *R);
  if (s == JND_OK && !R) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_csv_read(csv_path, &csv);
  if (s == JND_OK && !(sc = jnd_calloc((size_t)(csv.nrows > 0 ? csv.nrows : 1), sizeof *sc))) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = read_thresholds(csv_path, &csv, p.pairs != NULL, &o, sc, &nsc);
  /* the model's JND percentiles over each scene's series */
  if (s == JND_OK && p.pairs) s = measure_pairs(p.pairs, &p.judge, &o, sc, nsc);
  for (int k = 0; k < nsc && s == JND_OK; k++) {
    if (!sc[k].model[0]) continue;
    if ((s = measure_asset(&sc[k], &p)) != JND_OK) break;
    if (p.progress) {
      char line[512];
      snprintf(line, sizeof line, "scene %d/%d %s: %s at %d resolutions", k + 1, nsc, sc[k].name, sc[k].map,
               sc[k].npct);
      p.progress(p.progress_user, NULL, k + 1, nsc);
      p.progress(p.progress_user, line, k + 1, nsc);
    }
  }
  if (s == JND_OK && (!(cs = jnd_calloc((size_t)nsc, sizeof *cs)) || !(maps = jnd_calloc((size_t)nsc, sizeof *maps))))
    s = JND_ERR_NOMEM;
  for (int k = 0; k < nsc && s == JND_OK; k++) {
    if (sc[k].npct < 2) {
      s = jnd_fail(JND_ERR_FORMAT, "%s: scene %s has %d image pairs (needs 2 or more resolutions)",
                   p.pairs ? p.pairs : csv_path, sc[k].name, sc[k].npct);
      break;
    }
    snprintf(cs[k].name, sizeof cs[k].name, "%s", sc[k].name);
    cs[k].nres = sc[k].npct;
    cs[k].res = sc[k].pct_res;
    cs[k].jnd_pct = sc[k].pct;
    cs[k].mu = sc[k].mu;
    cs[k].sigma = sc[k].sigma;
    maps[k] = sc[k].map;
  }
  if (s == JND_OK && jnd_calibrate_fit(cs, nsc, &p.fit, R) != JND_OK)
    s = jnd_fail(JND_ERR_ARG, "%s: %s", csv_path, jnd_last_error());
  if (s == JND_OK && staged_hist) s = write_histogram(staged_hist, R);
  if (s == JND_OK) report = calibrate_report(csv_path, &p, R, cs, maps, p.histogram);
  s = REPORT_OUTPUT_FINISH(&o, s, report, staged_out, R);
  free(maps);
  free(cs);
  free(sc);
  jnd_csv_free(&csv);
  if (s != JND_OK) {
    jnd_calibrate_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
