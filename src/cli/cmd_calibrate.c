/* jnd calibrate THRESHOLDS.csv -o CAL.json — retunes pooling and the JND
 * transform to measured texture thresholds (000 §6–§7). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd calibrate THRESHOLDS.csv -o CAL.json [options]\n"
      "\n"
      "Fits, to thresholds measured in your own experiment, the pooling percentile\n"
      "(90th-99th, 000 §6) and a linear transform of the model's JND map before the\n"
      "psychometric function (scale and bias, 000 §7.1) that minimise the mean absolute\n"
      "error between predicted and measured threshold resolution; k-fold\n"
      "cross-validation by scene (000 §7.3). CAL.json is accepted by `jnd diff`,\n"
      "`jnd texres` and later tasks with --calibration. See docs/calibrate.md.\n"
      "\n"
      "THRESHOLDS.csv (header row; one row per scene, or per scene and resolution):\n"
      "  scene               scene name (folds never split a scene)\n"
      "  mu, sigma           the measured threshold distribution, pixels (000 eq. 1), or\n"
      "  resolution, rate    per-resolution detection rates (0..1), fitted with eq. 1\n"
      "  model, map          (optional) a glTF/GLB/OBJ asset (path relative to the CSV)\n"
      "                      and its map MATERIAL/SLOT: the series is rendered as in\n"
      "                      `jnd texres`, at the rows' resolutions (or --sizes)\n"
      "\n"
      "image series (instead of model/map):\n"
      "  --pairs FILE.csv    columns scene, resolution, reference, test: prepared image\n"
      "                      pairs (paths relative to that CSV), one per resolution\n"
      "  --sizes LIST        resolutions rendered for model/map scenes given as mu, sigma\n"
      "                      (default: 11 steps from the original down to 1/6 of it)\n"
      "\n"
      "%s"
      "  (calibrate renders 4 views at 256x256 unless told otherwise)\n"
      "\n"
      "%s"
      "\n"
      "fit:\n"
      "  --folds K           cross-validation folds (5; at most the number of scenes)\n"
      "  --p P               probability at which thresholds are read (0.2, 000 §6)\n"
      "  --bias-range A,B    exhaustive bias search range in JND (-2,2)\n"
      "\n"
      "outputs:\n"
      "  -o, --output FILE   the calibration (a JSON report with result.calibration)\n"
      "  --histogram FILE    PNG histogram of held-out signed errors (000 Fig. 9/11)\n"
      "%s"
      "\n"
      "Paper numbers: 000 is Wolski et al. 2019 (include/jnd.h lists them all).\n"
      "Exit status: 0, 2 for bad input (one line: jnd: FILE: problem).\n",
      cli_views_help, cli_display_help, cli_common_help);
}

typedef struct {
  char name[128];
  char model[1024], map[160];
  double mu, sigma;
  int has_mu;
  int nres;
  double res[64], rate[64];
  double pct[64 * JND_CALIB_NPCT];
  int npct;                 /* resolutions whose percentiles are known */
  double pct_res[64];
} scene_rec;

static void rel_path(const char *csv, const char *p, char *out, size_t n) {
  if (p[0] == '/') {
    snprintf(out, n, "%s", p);
    return;
  }
  const char *slash = strrchr(csv, '/');
  if (!slash) snprintf(out, n, "%s", p);
  else snprintf(out, n, "%.*s/%s", (int)(slash - csv), csv, p);
}

static int col(const jnd_csv *c, const char *name) { return jnd_csv_column(c, name); }

static int number(const char *file, int row, const char *colname, const char *cell, double *v) {
  if (!jnd_csv_number(cell, v) || !isfinite(*v)) {
    cli_error("%s: row %d: %s '%s' is not a number", file, row + 2, colname, cell);
    return 0;
  }
  return 1;
}

static int find_scene(scene_rec *s, int n, const char *name, const char *map) {
  for (int i = 0; i < n; i++)
    if (strcmp(s[i].name, name) == 0 && strcmp(s[i].map, map) == 0) return i;
  return -1;
}

/* 000 Fig. 9/11: counts of held-out signed errors in 32-pixel bins */
static int write_histogram(const char *path, const jnd_calibrate_result *R) {
  jnd_image img;
  if (jnd_calibrate_histogram(R, &img) != JND_OK) {
    cli_error("%s", jnd_last_error());
    return 0;
  }
  int ok = jnd_image_write_png(path, &img, 8) == JND_OK;
  if (!ok) cli_error("%s", jnd_last_error());
  jnd_image_free(&img);
  return ok;
}

static int run(int argc, char **argv) {
  const char *csv_path = NULL, *out_path = NULL, *pairs_path = NULL, *hist_path = NULL, *v;
  cli_common common = {0};
  jnd_calibrate_params cp;
  jnd_calibrate_defaults(&cp);
  jnd_judge_params jp;
  jnd_judge_defaults(&jp);
  cli_views vo;
  cli_views_init(&vo, 256, 256);
  vo.set.sampling.count = 4;
  cli_display disp;
  cli_display_init(&disp);
  int sizes[64], nsizes = 0;
  cli_args args = cli_args_start(argc, argv, "calibrate"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_views_opt(ap, &vo) || cli_display_opt(ap, &disp) || cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      out_path = v;
    } else if (cli_opt(ap, "--pairs", &v)) {
      pairs_path = v;
    } else if (cli_opt(ap, "--sizes", &v)) {
      nsizes = cli_int_list(ap, "--sizes", v, 1, 32768, sizes, 64);
    } else if (cli_opt(ap, "--folds", &v)) {
      cp.folds = cli_int(ap, "--folds", v, 1, 32);
    } else if (cli_opt(ap, "--p", &v)) {
      cp.threshold_p = cli_double(ap, "--p", v, 0.01, 0.99);
    } else if (cli_opt(ap, "--bias-range", &v)) {
      cli_pair(ap, "--bias-range", v, &cp.bias_min, &cp.bias_max);
      if (!args.bad && !(cp.bias_max > cp.bias_min)) {
        cli_error("calibrate: --bias-range: '%s' needs A < B", v);
        return EXIT_BAD;
      }
    } else if (cli_opt(ap, "--histogram", &v)) {
      hist_path = v;
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (!csv_path) {
      csv_path = a;
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!csv_path) {
    cli_error("calibrate: give a THRESHOLDS.csv (jnd calibrate --help)");
    return EXIT_BAD;
  }
  if (!out_path) {
    cli_error("calibrate: give the calibration file to write with -o CAL.json");
    return EXIT_BAD;
  }
  jp.model.display = cli_display_get(&disp);
  jp.model.threads = common.threads;
  jp.model.beta = cp.beta;
  jp.views = vo.set;

  int rc = EXIT_BAD, nsc = 0;
  jnd_csv csv = {0}, pairs = {0};
  scene_rec *sc = NULL;
  jnd_calib_scene *cs = NULL;
  jnd_calibrate_result R = {0};
  jnd_model *model = NULL;
  cJSON *report = NULL;
  /* the outputs checked before any work, written staged, published at the
   * end; the files the tables name join the inputs as they are read */
  jnd_output *outw = NULL;
  const char *ins[] = {csv_path, pairs_path, vo.set.render.env_path, vo.cameras}, *final_out = out_path,
             *final_hist = hist_path, *json_out = common.json_path;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 4) != EXIT_OK ||
      cli_out_file(outw, final_out, &out_path) != EXIT_OK || cli_out_file(outw, final_hist, &hist_path) != EXIT_OK ||
      cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    goto out;
  if (jnd_csv_read(csv_path, &csv) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  int c_scene = col(&csv, "scene"), c_mu = col(&csv, "mu"), c_sigma = col(&csv, "sigma"),
      c_res = col(&csv, "resolution"), c_rate = col(&csv, "rate"), c_model = col(&csv, "model"),
      c_map = col(&csv, "map");
  int by_mu = c_mu >= 0 && c_sigma >= 0, by_rate = c_res >= 0 && c_rate >= 0;
  if (c_scene < 0 || (!by_mu && !by_rate)) {
    cli_error("%s: missing column%s (need scene, and mu and sigma, or resolution and rate)", csv_path,
              c_scene < 0 ? " 'scene'" : "s");
    goto out;
  }
  if ((c_model >= 0) != (c_map >= 0)) {
    cli_error("%s: missing column '%s' (model and map go together)", csv_path, c_model >= 0 ? "map" : "model");
    goto out;
  }
  if (c_model < 0 && !pairs_path) {
    cli_error("%s: no image series: give model and map columns, or --pairs FILE.csv", csv_path);
    goto out;
  }
  if (csv.nrows < 1) {
    cli_error("%s: no rows", csv_path);
    goto out;
  }
  sc = calloc((size_t)csv.nrows, sizeof *sc);
  if (!sc) goto out;
  for (int r = 0; r < csv.nrows; r++) {
    const char *name = csv.cells[r][c_scene], *map = c_map >= 0 ? csv.cells[r][c_map] : "";
    if (!*name) {
      cli_error("%s: row %d: empty scene", csv_path, r + 2);
      goto out;
    }
    int k = find_scene(sc, nsc, name, map);
    if (k < 0) {
      k = nsc++;
      snprintf(sc[k].name, sizeof sc[k].name, "%s", name);
      snprintf(sc[k].map, sizeof sc[k].map, "%s", map);
      if (c_model >= 0) {
        const char *m = csv.cells[r][c_model];
        jnd_builtin_params bp;
        jnd_builtin_defaults(&bp);
        if (jnd_builtin_parse(m, &bp) != 0) snprintf(sc[k].model, sizeof sc[k].model, "%s", m);
        else rel_path(csv_path, m, sc[k].model, sizeof sc[k].model);
        const char *one[] = {sc[k].model};
        if (cli_out_inputs(outw, one, 1) != EXIT_OK) goto out;
      }
    }
    if (by_mu && *csv.cells[r][c_mu]) {
      if (!number(csv_path, r, "mu", csv.cells[r][c_mu], &sc[k].mu) ||
          !number(csv_path, r, "sigma", csv.cells[r][c_sigma], &sc[k].sigma))
        goto out;
      if (!(sc[k].mu > 0) || sc[k].sigma < 0) {
        cli_error("%s: row %d: mu must be > 0 and sigma >= 0 (pixels)", csv_path, r + 2);
        goto out;
      }
      sc[k].has_mu = 1;
    }
    if (by_rate && *csv.cells[r][c_res] && *csv.cells[r][c_rate]) {
      double res, rate;
      if (!number(csv_path, r, "resolution", csv.cells[r][c_res], &res) ||
          !number(csv_path, r, "rate", csv.cells[r][c_rate], &rate))
        goto out;
      if (!(res >= 1) || rate < 0 || rate > 1 || sc[k].nres >= 64) {
        cli_error("%s: row %d: resolution must be >= 1 pixel and rate 0..1 (at most 64 per scene)", csv_path, r + 2);
        goto out;
      }
      sc[k].res[sc[k].nres] = res;
      sc[k].rate[sc[k].nres++] = rate;
    }
  }
  for (int k = 0; k < nsc; k++) {
    if (sc[k].has_mu) continue;
    jnd_psychometric f;
    if (sc[k].nres < 2 || jnd_psychometric_fit(sc[k].res, sc[k].rate, sc[k].nres, 0, &f) != JND_OK) {
      cli_error("%s: scene %s: needs mu and sigma, or detection rates at 2 or more resolutions", csv_path,
                sc[k].name);
      goto out;
    }
    sc[k].mu = f.mu;
    sc[k].sigma = f.sigma;
  }

  /* the model's JND percentiles over each scene's series */
  cli_progress prog;
  cli_progress_start(&prog, &common, "calibrate", nsc);
  if (pairs_path) {
    if (jnd_csv_read(pairs_path, &pairs) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
    int p_scene = col(&pairs, "scene"), p_res = col(&pairs, "resolution"), p_ref = col(&pairs, "reference"),
        p_test = col(&pairs, "test");
    if (p_scene < 0 || p_res < 0 || p_ref < 0 || p_test < 0) {
      cli_error("%s: missing column (need scene, resolution, reference, test)", pairs_path);
      goto out;
    }
    for (int r = 0; r < pairs.nrows; r++) {
      char rp[4200], tpth[4200];
      rel_path(pairs_path, pairs.cells[r][p_ref], rp, sizeof rp);
      rel_path(pairs_path, pairs.cells[r][p_test], tpth, sizeof tpth);
      const char *two[] = {rp, tpth};
      if (cli_out_inputs(outw, two, 2) != EXIT_OK) goto out;
    }
    jnd_model_params mp = jp.model;
    mp.threads = 1;
    if (jnd_model_create(&mp, &model) != JND_OK) {
      cli_error("calibrate: %s", jnd_last_error());
      goto out;
    }
    for (int r = 0; r < pairs.nrows; r++) {
      int k = -1;
      for (int j = 0; j < nsc; j++)
        if (strcmp(sc[j].name, pairs.cells[r][p_scene]) == 0 && !sc[j].model[0]) k = j;
      if (k < 0) continue;
      double res;
      if (!number(pairs_path, r, "resolution", pairs.cells[r][p_res], &res)) goto out;
      if (sc[k].npct >= 64) continue;
      char rp[4200], tpth[4200];
      rel_path(pairs_path, pairs.cells[r][p_ref], rp, sizeof rp);
      rel_path(pairs_path, pairs.cells[r][p_test], tpth, sizeof tpth);
      jnd_image ref = {0}, test = {0}, map = {0};
      jnd_image_info ri, ti;
      if (jnd_image_read(rp, &ref, &ri) != JND_OK || jnd_image_read(tpth, &test, &ti) != JND_OK) {
        cli_error("%s", jnd_last_error());
        jnd_image_free(&ref);
        goto out;
      }
      jnd_status st = jnd_diff_files(model, &ref, &ri, &test, &ti, NULL, NULL, &map, NULL);
      if (st == JND_OK) st = jnd_calib_percentiles(&map, NULL, sc[k].pct + (size_t)sc[k].npct * JND_CALIB_NPCT);
      jnd_image_free(&map);
      if (st != JND_OK) {
        cli_error("%s: %s", tpth, jnd_last_error());
        goto out;
      }
      sc[k].pct_res[sc[k].npct++] = res;
    }
  }
  for (int k = 0; k < nsc; k++) {
    if (!sc[k].model[0]) continue;
    jnd_scene *scene = NULL;
    if (jnd_scene_open(sc[k].model, vo.map_size, &scene) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
    int idx = jnd_scene_map_find(scene, sc[k].map);
    if (idx < 0) {
      cli_error("%s: no map '%s' (jnd render %s --list-maps)", sc[k].model, sc[k].map, sc[k].model);
      jnd_scene_free(scene);
      goto out;
    }
    jnd_map_info mi;
    jnd_scene_map_info(scene, idx, &mi);
    int L = mi.orig_width > mi.orig_height ? mi.orig_width : mi.orig_height;
    int ss[64], n = 0;
    if (sc[k].nres >= 2 && !nsizes) {
      for (int i = 0; i < sc[k].nres && n < 64; i++) ss[n++] = (int)lround(sc[k].res[i]);
    } else if (nsizes) {
      for (int i = 0; i < nsizes; i++) ss[n++] = sizes[i];
    } else {
      for (int i = 1; i <= 11; i++) ss[n++] = (int)lround(L * (1.0 - i * (5.0 / 6.0) / 11.0));
    }
    jnd_status st = jnd_calib_series_percentiles(scene, sc[k].map, ss, n, &jp, sc[k].pct);
    jnd_scene_free(scene);
    if (st != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
    for (int i = 0; i < n; i++) sc[k].pct_res[i] = ss[i];
    sc[k].npct = n;
    cli_progress_step(&prog, k + 1);
    char line[512];
    snprintf(line, sizeof line, "scene %d/%d %s: %s at %d resolutions", k + 1, nsc, sc[k].name, sc[k].map, n);
    cli_progress_line(&prog, line);
  }
  cli_progress_end(&prog);
  cs = calloc((size_t)nsc, sizeof *cs);
  if (!cs) goto out;
  for (int k = 0; k < nsc; k++) {
    if (sc[k].npct < 2) {
      cli_error("%s: scene %s has %d image pairs (needs 2 or more resolutions)", pairs_path ? pairs_path : csv_path,
                sc[k].name, sc[k].npct);
      goto out;
    }
    snprintf(cs[k].name, sizeof cs[k].name, "%s", sc[k].name);
    cs[k].nres = sc[k].npct;
    cs[k].res = sc[k].pct_res;
    cs[k].jnd_pct = sc[k].pct;
    cs[k].mu = sc[k].mu;
    cs[k].sigma = sc[k].sigma;
  }
  if (jnd_calibrate_fit(cs, nsc, &cp, &R) != JND_OK) {
    cli_error("%s: %s", csv_path, jnd_last_error());
    goto out;
  }

  report = cli_report_new("calibrate");
  cJSON *in = cli_report_section(report, "inputs"), *par = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(in, "thresholds", csv_path);
  if (pairs_path) cJSON_AddStringToObject(in, "pairs", pairs_path);
  cJSON_AddNumberToObject(par, "folds", cp.folds);
  cJSON_AddNumberToObject(par, "threshold_p", cp.threshold_p);
  cJSON_AddNumberToObject(par, "beta", cp.beta);
  cJSON_AddNumberToObject(par, "bias_min", cp.bias_min);
  cJSON_AddNumberToObject(par, "bias_max", cp.bias_max);
  cJSON_AddItemToObject(par, "display", cli_display_json(&jp.model.display));
  cJSON_AddItemToObject(par, "views", cli_views_json(&vo));
  cJSON *cal = cJSON_AddObjectToObject(res, "calibration");
  cJSON_AddNumberToObject(cal, "percentile", R.cal.percentile);
  cJSON_AddNumberToObject(cal, "scale", R.cal.scale);
  cJSON_AddNumberToObject(cal, "bias", R.cal.bias);
  cJSON_AddNumberToObject(cal, "beta", R.cal.beta);
  cJSON_AddNumberToObject(cal, "threshold_p", R.cal.threshold_p);
  cJSON_AddNumberToObject(cal, "mae_px", R.cal.mae_px);
  cJSON_AddNumberToObject(res, "train_mae_px", R.mae_px);
  cJSON_AddNumberToObject(res, "cv_mae_px", R.cv_mae_px);
  cJSON *fm = cJSON_AddArrayToObject(res, "fold_mae_px");
  for (int k = 0; k < R.folds; k++) cJSON_AddItemToArray(fm, cJSON_CreateNumber(R.fold_mae_px[k]));
  cJSON *pm = cJSON_AddObjectToObject(res, "percentile_train_mae_px");
  for (int k = 0; k < JND_CALIB_NPCT; k++) {
    char key[8];
    snprintf(key, sizeof key, "p%d", JND_CALIB_PCT_LO + k);
    cJSON_AddNumberToObject(pm, key, R.pct_mae_px[k]);
  }
  cJSON *js = cJSON_AddArrayToObject(res, "scenes");
  for (int k = 0; k < nsc; k++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "scene", sc[k].name);
    if (sc[k].map[0]) cJSON_AddStringToObject(o, "map", sc[k].map);
    cJSON_AddNumberToObject(o, "mu", sc[k].mu);
    cJSON_AddNumberToObject(o, "sigma", sc[k].sigma);
    jnd_psychometric m = {sc[k].mu, sc[k].sigma > 1e-9 ? sc[k].sigma : 1e-9, 0, 0};
    cJSON_AddNumberToObject(o, "measured_px", jnd_psychometric_resolution(&m, cp.threshold_p));
    cJSON_AddNumberToObject(o, "predicted_px", R.predicted_px[k]);
    cJSON_AddNumberToObject(o, "heldout_error_px", R.errors_px[k]);
    cJSON_AddItemToArray(js, o);
  }
  if (hist_path) {
    if (!write_histogram(hist_path, &R)) goto out;
    cJSON_AddStringToObject(res, "histogram", final_hist);
  }
  if (cli_report_write(report, out_path) != EXIT_OK) goto out;
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto out;
  cli_info(&common, "calibration: p%g, JND -> max(0, %.4f JND %+.4f), beta %.2f\n", R.cal.percentile, R.cal.scale,
           R.cal.bias, R.cal.beta);
  cli_info(&common, "threshold error at P = %.2f: train MAE %.1f px; held out (%d folds) MAE %.1f px [", cp.threshold_p,
           R.mae_px, R.folds, R.cv_mae_px);
  for (int k = 0; k < R.folds; k++) cli_info(&common, "%s%.1f", k ? " " : "", R.fold_mae_px[k]);
  cli_info(&common, "]\n%d scenes -> %s\n", nsc, final_out);
  rc = EXIT_OK;
out:
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  jnd_calibrate_result_free(&R);
  jnd_model_free(model);
  free(cs);
  free(sc);
  jnd_csv_free(&csv);
  jnd_csv_free(&pairs);
  return rc;
}

const jnd_command jnd_cmd_calibrate = {"calibrate", "fit pooling and a JND transform to measured thresholds (000)",
                                       run};
