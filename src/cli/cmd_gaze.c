/* jnd gaze MODEL -o OUTDIR — 002's gaze-contingent level of detail: the
 * table L(distance, eccentricity) of the coarsest level nobody notices. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd gaze MODEL -o OUTDIR [options]\n"
      "       jnd gaze fit DATA.csv [options]   (jnd gaze fit --help)\n"
      "       jnd gaze observers MODEL... -o OUTDIR [options]   (jnd gaze observers --help)\n"
      "\n"
      "For MODEL's chain of levels of detail (glTF MSFT_lod as `jnd lod` writes it, or\n"
      "made now from a plain mesh), finds per distance and eccentricity the coarsest level\n"
      "an observer looking elsewhere does not notice (Surace et al. 2023, 002): every level\n"
      "is rendered from sampled orientations, and at each eccentricity the spatial model\n"
      "(silhouette change weighted by eccentricity + shading change through jnd's vision\n"
      "model at the fixation point) and the temporal model (the switch from the next finer\n"
      "level) must both stay below the threshold; the worst orientation decides, and the\n"
      "level never gets finer farther away or farther from the gaze. Writes OUTDIR/gaze.json,\n"
      "OUTDIR/gaze.csv (what an engine loads: jnd_gaze_lookup_load) and OUTDIR/gaze.png.\n"
      "Model units are metres. See docs/gaze.md.\n"
      "\n"
      "table:\n"
      "  --distances LIST    metres from the eye, ascending (default 4..96 bounding radii)\n"
      "  --eccentricities LIST degrees from the gaze, ascending, 0..90 (default\n"
      "                      0,5,10,15,20,30,40,60)\n"
      "  --orientations N    object orientations per distance (8; the worst decides)\n"
      "  --seed S            seed of the orientations and lights (1)\n"
      "  --threshold P       2AFC probability both models must stay below (0.75, 002)\n"
      "  --errors LIST       a plain mesh's chain: error targets, rising, in [1e-6, 1] of its\n"
      "                      extent (default 1/1024,1/256,1/64)\n"
      "  --min-px N, --max-px N  rendering side: the object's window at the display's\n"
      "                      ppd, within these (64, 192)\n"
      "  --whole-near        judge a near object whole at reduced ppd (default: windows of\n"
      "                      --max-px at the display's ppd, on the fixation point where it falls\n"
      "                      on the object, else on the silhouette facing it)\n"
      "  --params FIT.json   the models' parameters from `jnd gaze fit -o` (its gaze_fit.json;\n"
      "                      give the spatial and the temporal fit) or scripts/gaze-defaults.json\n"
      "                      (default: jnd's, fitted to its own vision model; docs/gaze.md)\n"
      "  --env FILE, --samples N, --anisotropy N, --platform P, --map-size N   as in jnd render\n"
      "\n"
      "%s"
      "\n"
      "outputs:\n"
      "  -o, --output DIR    the folder (created)\n"
      "%s"
      "\n"
      "Exit status: 0; 2 for bad input (one line: jnd: FILE or --flag: problem), nothing written.\n",
      cli_display_help, cli_common_help);
}

static void on_progress(void *user, int done, int total) {
  cli_progress *p = user;
  p->total = total;
  cli_progress_step(p, done);
}

static cJSON *matrix_int(const int *v, int rows, int cols) {
  cJSON *a = cJSON_CreateArray();
  for (int r = 0; r < rows; r++) cJSON_AddItemToArray(a, cJSON_CreateIntArray(v + (size_t)r * cols, cols));
  return a;
}

/* [d][e][k] */
static cJSON *cube(const double *v, int nd, int ne, int nk) {
  cJSON *a = cJSON_CreateArray();
  for (int d = 0; d < nd; d++) {
    cJSON *row = cJSON_CreateArray();
    for (int e = 0; e < ne; e++) cJSON_AddItemToArray(row, cJSON_CreateDoubleArray(v + ((size_t)d * ne + e) * nk, nk));
    cJSON_AddItemToArray(a, row);
  }
  return a;
}

static void fit_help(void) {
  printf(
      "usage: jnd gaze fit DATA.csv [-o OUTDIR] [options]\n"
      "\n"
      "Fits 002's spatial model (columns xor_deg, v_jnd, eccentricity_deg, seen) or its\n"
      "temporal model (columns t_jnd, seen) to observers' answers by maximum likelihood\n"
      "over the Bernoulli outcomes, with intervals from the observed information and\n"
      "k-fold cross-validation over stimuli (Pearson r and mean absolute error between\n"
      "predicted P and the proportion seen, per fold and on all data). An optional\n"
      "column stimulus (0..rows-1) groups rows; else rows with equal terms are one.\n"
      "See docs/gaze.md \"Fitting\".\n"
      "\n"
      "  --folds K           cross-validation folds (4, as 002; 2..%d)\n"
      "  --seed S            seed of the assignment of stimuli to folds (1)\n"
      "  --confidence C      of the parameters' intervals (0.95)\n"
      "  --b B               the weight's floor, kept fixed (2)\n"
      "  -o, --output DIR    write DIR/gaze_fit.json\n"
      "%s"
      "\n"
      "Exit status: 0; 2 for bad input (one line: jnd: FILE: row R: problem).\n",
      JND_GAZE_MAX_FOLDS, cli_common_help);
}

static int run_fit(int argc, char **argv) {
  const char *data = NULL, *dir = NULL, *v;
  cli_common common = {0};
  jnd_gaze_fit_params fp;
  jnd_gaze_fit_defaults(&fp);
  cli_args args = cli_args_start(argc, argv, "gaze fit"), *ap = &args;
  args.i = 2;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      fit_help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--folds", &v)) {
      fp.folds = cli_int(ap, "--folds", v, 2, JND_GAZE_MAX_FOLDS);
    } else if (cli_opt(ap, "--seed", &v)) {
      fp.seed = (uint64_t)cli_double(ap, "--seed", v, 0, 9007199254740992.0);
    } else if (cli_opt(ap, "--confidence", &v)) {
      fp.confidence = cli_double(ap, "--confidence", v, 0.5, 0.9999);
    } else if (cli_opt(ap, "--b", &v)) {
      fp.start.b = cli_double(ap, "--b", v, 1e-6, 1e6);
    } else if (cli_common_opt(ap, &common)) {
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (!data) {
      data = a;
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!data) return cli_bad("gaze fit: give a DATA.csv of trials; jnd gaze fit --help");
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *json_out = NULL;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, &data, 1) != EXIT_OK ||
      cli_out_dir(outw, dir, &dir) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    return cli_out_end(outw, EXIT_BAD);
  jnd_gaze_data d;
  if (jnd_gaze_data_read(data, &d) != JND_OK) return cli_out_end(outw, cli_lib_error());
  jnd_gaze_fit_result r;
  jnd_status st = jnd_gaze_fit(&d, &fp, &r);
  jnd_gaze_data_free(&d);
  if (st != JND_OK) return cli_out_end(outw, cli_lib_error());

  cJSON *report = cli_report_new("gaze fit");
  cJSON *in = cli_report_section(report, "inputs"), *par = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(in, "data", data);
  cJSON_AddNumberToObject(par, "folds", fp.folds);
  cJSON_AddNumberToObject(par, "seed", (double)fp.seed);
  cJSON_AddNumberToObject(par, "confidence", fp.confidence);
  if (!r.temporal) cJSON_AddNumberToObject(par, "b", fp.start.b);
  cJSON_AddStringToObject(res, "model", r.temporal ? "temporal" : "spatial");
  cJSON_AddNumberToObject(res, "trials", r.trials);
  cJSON_AddNumberToObject(res, "stimuli", r.stimuli);
  cJSON_AddNumberToObject(res, "neg_log_likelihood", r.neg_loglik);
  cJSON *jp = cJSON_AddObjectToObject(res, "parameters");
  for (int i = 0; i < r.nparams; i++) {
    cJSON *o = cJSON_AddObjectToObject(jp, r.names[i]);
    cJSON_AddNumberToObject(o, "value", r.value[i]);
    if (isfinite(r.ci_lo[i])) {
      cJSON_AddNumberToObject(o, "ci_lo", r.ci_lo[i]);
      cJSON_AddNumberToObject(o, "ci_hi", r.ci_hi[i]);
    } else {
      cJSON_AddNullToObject(o, "ci_lo");
      cJSON_AddNullToObject(o, "ci_hi");
    }
  }
  cJSON *all = cJSON_AddObjectToObject(res, "all_data");
  cJSON_AddNumberToObject(all, "pearson_r", r.r_all);
  cJSON_AddNumberToObject(all, "mae", r.mae_all);
  cJSON *cv = cJSON_AddObjectToObject(res, "cross_validation");
  cJSON_AddItemToObject(cv, "pearson_r", cJSON_CreateDoubleArray(r.fold_r, r.folds));
  cJSON_AddItemToObject(cv, "mae", cJSON_CreateDoubleArray(r.fold_mae, r.folds));
  cJSON_AddNumberToObject(cv, "pearson_r_mean", r.r_mean);
  cJSON_AddNumberToObject(cv, "pearson_r_sd", r.r_sd);
  cJSON_AddNumberToObject(cv, "mae_mean", r.mae_mean);
  cJSON_AddNumberToObject(cv, "mae_sd", r.mae_sd);
  int rc = EXIT_OK;
  if (dir) {
    char path[4400];
    snprintf(path, sizeof path, "%s/gaze_fit.json", dir);
    if (jnd_make_dirs(dir) != JND_OK) rc = cli_lib_error();
    if (rc == EXIT_OK) rc = cli_report_write(report, path);
  }
  if (rc == EXIT_OK && json_out) rc = cli_report_write(report, json_out);
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  cli_info(&common, "jnd gaze fit: %s, %s model, %d trials of %d stimuli\n", data, r.temporal ? "temporal" : "spatial",
           r.trials, r.stimuli);
  for (int i = 0; i < r.nparams; i++)
    cli_info(&common, "  %-8s %10.4g  [%.4g, %.4g]\n", r.names[i], r.value[i], r.ci_lo[i], r.ci_hi[i]);
  cli_info(&common, "  all data: r = %.3f, MAE = %.3f; %d-fold: r = %.3f ± %.3f, MAE = %.3f ± %.3f\n", r.r_all,
           r.mae_all, r.folds, r.r_mean, r.r_sd, r.mae_mean, r.mae_sd);
  return rc;
}

static void observers_help(void) {
  printf(
      "usage: jnd gaze observers MODEL... -o OUTDIR [options]\n"
      "\n"
      "Synthetic observers for `jnd gaze fit`: for each MODEL's chain (MSFT_lod, or made\n"
      "now), object sizes, orientations, eccentricities and levels, the spatial model's\n"
      "terms and the switch's, and answers drawn (seeded) from the probability jnd's own\n"
      "vision model gives: the level against the reference seen whole (silhouette and\n"
      "shading, nothing greyed) at each pixel's eccentricity, and the switch through its\n"
      "temporal sensitivity. Writes OUTDIR/spatial.csv and OUTDIR/temporal.csv (one row\n"
      "per answer) and OUTDIR/observers.json. scripts/fit-gaze-defaults.sh fits jnd's\n"
      "default parameters to them. See docs/gaze.md \"Defaults\".\n"
      "\n"
      "  --sizes LIST        the object's angular diameter, degrees (1.5,4,12; 002: 1.22-12.22)\n"
      "  --eccentricities LIST degrees from the gaze, ascending, 0..90 (0,5,10,20,30,45,60)\n"
      "  --orientations N    per size (2)\n"
      "  --answers N         Bernoulli answers per stimulus (40)\n"
      "  --seed S            of the orientations, lights and answers (1)\n"
      "  --errors LIST       a plain mesh's chain: error targets, rising, in [1e-6, 1] of its\n"
      "                      extent (default 1/1024,1/256,1/64)\n"
      "  --min-px N, --max-px N  rendering side (64, 192)\n"
      "  --map-size N        texture size of built-in models (512)\n"
      "  -o, --output DIR    the folder (created)\n"
      "%s"
      "\n"
      "Exit status: 0; 2 for bad input (one line: jnd: FILE or --flag: problem), nothing written.\n",
      cli_common_help);
}

static int run_observers(int argc, char **argv) {
  const char *dir = NULL, *v, *models[64];
  int nmodels = 0;
  cli_common common = {0};
  jnd_gaze_observers_params p;
  jnd_gaze_observers_defaults(&p);
  jnd_lod_params chain;
  jnd_lod_defaults(&chain);
  double sizes[64], ecc[64], errors[64];
  cli_views vo;   /* the observers' defaults, read back after parsing */
  cli_views_init(&vo, 0, 0);
  vo.set.sampling.seed = p.seed;
  vo.set.render = p.render;
  vo.map_size = 512;
  cli_args args = cli_args_start(argc, argv, "gaze observers"), *ap = &args;
  args.i = 2;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      observers_help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--sizes", &v)) {
      p.nsizes = cli_double_list(ap, "--sizes", v, 1e-3, 60, sizes, 64);
      p.sizes_deg = sizes;
    } else if (cli_opt(ap, "--eccentricities", &v)) {
      p.neccentricities = cli_double_list(ap, "--eccentricities", v, 0, 90, ecc, 64);
      p.eccentricities_deg = ecc;
    } else if (cli_opt(ap, "--orientations", &v)) {
      p.orientations = cli_int(ap, "--orientations", v, 1, 64);
    } else if (cli_opt(ap, "--answers", &v)) {
      p.answers = cli_int(ap, "--answers", v, 1, 10000);
    } else if (cli_opt(ap, "--errors", &v)) {
      chain.nerrors = cli_errors(ap, v, errors, 63);
      chain.errors = errors;
      p.chain = &chain;
    } else if (cli_opt(ap, "--min-px", &v)) {
      p.min_px = cli_int(ap, "--min-px", v, 16, 4096);
    } else if (cli_opt(ap, "--max-px", &v)) {
      p.max_px = cli_int(ap, "--max-px", v, 16, 4096);
    } else if (cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (nmodels < 64) {
      models[nmodels++] = a;
    } else {
      return cli_bad("gaze observers: at most 64 models");
    }
  }
  if (args.bad) return EXIT_BAD;
  if (cli_views_only(&vo, CLI_SEED | CLI_ENV | CLI_SAMPLES | CLI_ANISOTROPY | CLI_PLATFORM | CLI_MAP_SIZE,
                     "gaze observers", "its views are --sizes x --orientations; see jnd gaze observers --help"))
    return EXIT_BAD;
  p.seed = vo.set.sampling.seed;
  p.render.env_path = vo.set.render.env_path;
  p.render.samples = vo.set.render.samples;
  p.render.anisotropy = vo.set.render.anisotropy;
  p.render.platform = vo.set.render.platform;
  const int map_size = vo.map_size;
  if (!nmodels) return cli_bad("gaze observers: give at least one MODEL; jnd gaze observers --help");
  if (!dir) return cli_bad("gaze observers: give an output folder with -o OUTDIR");
  if (p.max_px < p.min_px) return cli_bad("--max-px: %d is below --min-px %d", p.max_px, p.min_px);
  jnd_scene *scenes[64] = {0};
  int rc = EXIT_OK;
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *json_out = NULL, *final_dir = dir;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, models, nmodels) != EXIT_OK ||
      cli_out_inputs(outw, &p.render.env_path, 1) != EXIT_OK || cli_out_dir(outw, final_dir, &dir) != EXIT_OK ||
      cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    return cli_out_end(outw, EXIT_BAD);
  for (int i = 0; i < nmodels && rc == EXIT_OK; i++)
    if (jnd_scene_open(models[i], map_size, &scenes[i]) != JND_OK) rc = cli_lib_error();
  jnd_gaze_observers O = {0};
  if (rc == EXIT_OK) {
    cli_progress bar;
    cli_progress_start(&bar, &common, "gaze observers", 1);
    p.progress = on_progress;
    p.progress_user = &bar;
    jnd_status st = jnd_gaze_observers_run(scenes, nmodels, &p, &O);
    cli_progress_end(&bar);
    if (st != JND_OK) rc = cli_lib_error();
  }
  char path[4400];
  if (rc == EXIT_OK && jnd_make_dirs(dir) != JND_OK) rc = cli_lib_error();
  snprintf(path, sizeof path, "%s/spatial.csv", dir);
  if (rc == EXIT_OK && jnd_gaze_observers_write_csv(&O, 0, path) != JND_OK) rc = cli_lib_error();
  snprintf(path, sizeof path, "%s/temporal.csv", dir);
  if (rc == EXIT_OK && jnd_gaze_observers_write_csv(&O, 1, path) != JND_OK) rc = cli_lib_error();
  if (rc == EXIT_OK) {
    cJSON *report = cli_report_new("gaze observers");
    cJSON *in = cli_report_section(report, "inputs"), *par = cli_report_section(report, "parameters"),
          *res = cli_report_section(report, "result");
    cJSON_AddItemToObject(in, "models", cJSON_CreateStringArray(models, nmodels));
    cJSON_AddNumberToObject(par, "orientations", p.orientations);
    cJSON_AddNumberToObject(par, "answers", p.answers);
    cJSON_AddNumberToObject(par, "seed", (double)p.seed);
    cJSON_AddNumberToObject(par, "switch_hz", p.measure.switch_hz);
    cJSON_AddNumberToObject(res, "stimuli", O.n);
    cJSON_AddNumberToObject(res, "trials_per_model", (double)O.n * O.answers);
    double ps = 0, pw = 0;
    for (int i = 0; i < O.n; i++) ps += O.stimuli[i].p_spatial, pw += O.stimuli[i].p_switch;
    cJSON_AddNumberToObject(res, "mean_p_spatial", O.n ? ps / O.n : 0);
    cJSON_AddNumberToObject(res, "mean_p_switch", O.n ? pw / O.n : 0);
    cJSON_AddStringToObject(res, "spatial_csv", "spatial.csv");
    cJSON_AddStringToObject(res, "temporal_csv", "temporal.csv");
    snprintf(path, sizeof path, "%s/observers.json", dir);
    rc = cli_report_write(report, path);
    if (rc == EXIT_OK && json_out) rc = cli_report_write(report, json_out);
    cJSON_Delete(report);
    cli_info(&common, "jnd gaze observers: %d stimuli x %d answers; mean P spatial %.3f, switch %.3f; wrote %s\n",
             O.n, O.answers, O.n ? ps / O.n : 0, O.n ? pw / O.n : 0, final_dir);
  }
  rc = cli_out_end(outw, rc);
  jnd_gaze_observers_free(&O);
  for (int i = 0; i < nmodels; i++) jnd_scene_free(scenes[i]);
  return rc;
}

static int run(int argc, char **argv) {
  if (argc >= 2 && strcmp(argv[1], "fit") == 0) return run_fit(argc, argv);
  if (argc >= 2 && strcmp(argv[1], "observers") == 0) return run_observers(argc, argv);
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  cli_display disp;
  cli_display_init(&disp);
  jnd_gaze_table_params p;
  jnd_gaze_table_defaults(&p);
  jnd_lod_params chain;
  jnd_lod_defaults(&chain);
  double dist[256], ecc[256], errors[64];
  cli_views vo;   /* gaze's defaults, read back after parsing */
  cli_views_init(&vo, 0, 0);
  vo.set.sampling.seed = p.seed;
  vo.set.render = p.render;
  vo.map_size = 512;
  int nparams = 0;
  const char *params_files[8];
  cli_args args = cli_args_start(argc, argv, "gaze"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--distances", &v)) {
      p.ndistances = cli_double_list(ap, "--distances", v, 0, 1e6, dist, 256);
      p.distances_m = dist;
    } else if (cli_opt(ap, "--eccentricities", &v)) {
      p.neccentricities = cli_double_list(ap, "--eccentricities", v, 0, 90, ecc, 256);
      p.eccentricities_deg = ecc;
    } else if (cli_opt(ap, "--orientations", &v)) {
      p.orientations = cli_int(ap, "--orientations", v, 1, 256);
    } else if (cli_opt(ap, "--threshold", &v)) {
      p.threshold = cli_double(ap, "--threshold", v, 0.501, 0.999);
    } else if (cli_opt(ap, "--errors", &v)) {
      chain.nerrors = cli_errors(ap, v, errors, 63);
      chain.errors = errors;
      p.chain = &chain;
    } else if (cli_opt(ap, "--min-px", &v)) {
      p.min_px = cli_int(ap, "--min-px", v, 16, 4096);
    } else if (cli_opt(ap, "--max-px", &v)) {
      p.max_px = cli_int(ap, "--max-px", v, 16, 4096);
    } else if (cli_flag(ap, "--whole-near")) {
      p.near_window = 0;
    } else if (cli_opt(ap, "--params", &v)) {
      if (nparams == 8) return cli_bad("--params: at most 8 files");
      params_files[nparams++] = v;
    } else if (cli_display_opt(ap, &disp) || cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (!model) {
      model = a;
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  /* the shared view options, where gaze has a use for them */
  if (cli_views_only(&vo, CLI_SEED | CLI_ENV | CLI_SAMPLES | CLI_ANISOTROPY | CLI_PLATFORM | CLI_MAP_SIZE, "gaze",
                     "its views are --distances x --orientations, each at its own size; see jnd gaze --help"))
    return EXIT_BAD;
  p.seed = vo.set.sampling.seed;
  p.render.env_path = vo.set.render.env_path;
  p.render.samples = vo.set.render.samples;
  p.render.anisotropy = vo.set.render.anisotropy;
  p.render.platform = vo.set.render.platform;
  int map_size = vo.map_size;
  if (!model) return cli_bad("gaze: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd gaze --help");
  if (!dir) return cli_bad("gaze: give an output folder with -o OUTDIR; jnd gaze --help");
  if (p.max_px < p.min_px) return cli_bad("--max-px: %d is below --min-px %d", p.max_px, p.min_px);
  p.measure.model.display = cli_display_get(&disp);
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *json_out = NULL, *final_dir = dir, *ins[] = {model, p.render.env_path};
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 2) != EXIT_OK ||
      cli_out_inputs(outw, params_files, nparams) != EXIT_OK || cli_out_dir(outw, final_dir, &dir) != EXIT_OK ||
      cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    return cli_out_end(outw, EXIT_BAD);
  for (int i = 0; i < nparams; i++)
    if (jnd_gaze_model_read(params_files[i], &p.model) != JND_OK) return cli_out_end(outw, cli_lib_error());

  jnd_scene *scene = NULL;
  if (jnd_scene_open(model, map_size, &scene) != JND_OK) return cli_out_end(outw, cli_lib_error());
  int input_levels = jnd_scene_lod_count(scene);
  cli_progress bar;
  cli_progress_start(&bar, &common, "gaze", 1);
  p.progress = on_progress;
  p.progress_user = &bar;
  double t0 = jnd_seconds();
  jnd_gaze_table T;
  jnd_status st = jnd_gaze_table_run(scene, &p, &T);
  cli_progress_end(&bar);
  if (st != JND_OK) {
    jnd_scene_free(scene);
    return cli_out_end(outw, cli_lib_error());
  }
  double run_s = jnd_seconds() - t0;

  char path[4400];
  jnd_image fig = {0};
  int rc = EXIT_OK;
  if (jnd_make_dirs(dir) != JND_OK || jnd_gaze_table_figure(&T, &fig) != JND_OK) rc = cli_lib_error();
  snprintf(path, sizeof path, "%s/gaze.png", dir);
  if (rc == EXIT_OK && jnd_image_write_png(path, &fig, 8) != JND_OK) rc = cli_lib_error();
  snprintf(path, sizeof path, "%s/gaze.csv", dir);
  if (rc == EXIT_OK && jnd_gaze_table_write_csv(&T, path) != JND_OK) rc = cli_lib_error();
  jnd_image_free(&fig);
  /* the chain the table's levels index: the input's, or the one made here, written beside the table */
  char stem[256], chain_model[300];
  jnd_model_stem(model, stem, sizeof stem);
  snprintf(chain_model, sizeof chain_model, "model/%s.glb", stem);
  snprintf(path, sizeof path, "%s/model", dir);
  if (rc == EXIT_OK && input_levels < 2 && jnd_make_dirs(path) != JND_OK) rc = cli_lib_error();
  snprintf(path, sizeof path, "%s/%s", dir, chain_model);
  if (rc == EXIT_OK && input_levels < 2 && jnd_scene_write_lod_glb(scene, path, NULL) != JND_OK) rc = cli_lib_error();

  cJSON *report = cli_report_new("gaze");
  cJSON *in = cli_report_section(report, "inputs"), *par = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  cJSON_AddStringToObject(in, "chain", input_levels > 1 ? "input (MSFT_lod or levels of the file)" : "made by jnd gaze");
  cJSON_AddItemToObject(in, "params", cJSON_CreateStringArray(params_files, nparams));
  cJSON_AddNumberToObject(par, "threshold", p.threshold);
  cJSON_AddNumberToObject(par, "orientations", p.orientations);
  cJSON_AddNumberToObject(par, "seed", (double)p.seed);
  cJSON_AddNumberToObject(par, "min_px", p.min_px);
  cJSON_AddNumberToObject(par, "max_px", p.max_px);
  cJSON_AddBoolToObject(par, "near_window", p.near_window);
  cJSON_AddItemToObject(par, "display", cli_display_json(&p.measure.model.display));
  char pool[32];
  cJSON_AddStringToObject(par, "pooling", jnd_pooling_name(&p.measure.pool, pool, sizeof pool));
  cJSON_AddNumberToObject(par, "background", p.measure.background);
  cJSON *gm = cJSON_AddObjectToObject(par, "model");
  cJSON_AddNumberToObject(gm, "alpha", p.model.alpha);
  cJSON_AddNumberToObject(gm, "beta", p.model.beta);
  cJSON_AddNumberToObject(gm, "s_deg", p.model.s_deg);
  cJSON_AddNumberToObject(gm, "b", p.model.b);
  cJSON_AddNumberToObject(gm, "w_g", p.model.w_g);
  cJSON_AddNumberToObject(gm, "w_vdp", p.model.w_vdp);
  cJSON_AddNumberToObject(gm, "k_s", p.model.k_s);
  cJSON_AddNumberToObject(gm, "gamma", p.model.gamma);
  cJSON_AddNumberToObject(gm, "w_t", p.model.w_t);
  cJSON_AddNumberToObject(gm, "gamma_t", p.model.gamma_t);
  cJSON_AddItemToObject(res, "distances_m", cJSON_CreateDoubleArray(T.distances_m, T.nd));
  cJSON_AddItemToObject(res, "eccentricities_deg", cJSON_CreateDoubleArray(T.eccentricities_deg, T.ne));
  cJSON_AddItemToObject(res, "level", matrix_int(T.level, T.nd, T.ne));
  cJSON_AddItemToObject(res, "level_raw", matrix_int(T.level_raw, T.nd, T.ne));
  cJSON_AddItemToObject(res, "p_spatial", cube(T.p_spatial, T.nd, T.ne, T.nlevels));
  cJSON_AddItemToObject(res, "p_switch", cube(T.p_switch, T.nd, T.ne, T.nlevels));
  cJSON_AddItemToObject(res, "ppd", cJSON_CreateDoubleArray(T.ppd, T.nd));
  /* a near object's window is capped at --max-px: judged at fewer pixels per
   * degree than the display has (docs/gaze.md "The table", step 1) */
  const double display_ppd = p.measure.model.display.ppd;
  cJSON_AddNumberToObject(res, "display_ppd", display_ppd);
  cJSON_AddItemToObject(res, "windowed", cJSON_CreateIntArray(T.windowed, T.nd));
  cJSON *reduced = cJSON_AddArrayToObject(res, "reduced_ppd");
  int nreduced = 0;
  for (int d = 0; d < T.nd; d++) {
    int r = T.ppd[d] < 0.99 * display_ppd;
    nreduced += r;
    cJSON_AddItemToArray(reduced, cJSON_CreateBool(r));
  }
  cJSON_AddItemToObject(res, "side_px", cJSON_CreateIntArray(T.side_px, T.nd));
  cJSON *tri = cJSON_AddArrayToObject(res, "triangles");
  for (int k = 0; k < T.nlevels; k++) cJSON_AddItemToArray(tri, cJSON_CreateNumber((double)T.triangles[k]));
  cJSON_AddNumberToObject(res, "renderings", T.renderings);
  cJSON_AddStringToObject(res, "renderer", T.renderer);
  cJSON_AddStringToObject(res, "csv", "gaze.csv");
  cJSON_AddStringToObject(res, "png", "gaze.png");
  cJSON_AddStringToObject(res, "chain_model", input_levels < 2 ? chain_model : model);
  if (common.timings) cJSON_AddNumberToObject(res, "table_s", run_s);
  snprintf(path, sizeof path, "%s/gaze.json", dir);
  if (rc == EXIT_OK) rc = cli_report_write(report, path);
  if (rc == EXIT_OK && json_out) rc = cli_report_write(report, json_out);
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);

  /* the human summary: the table */
  cli_info(&common, "jnd gaze: %s, %d levels (", model, T.nlevels);
  for (int k = 0; k < T.nlevels; k++) cli_info(&common, "%s%zu", k ? " " : "", T.triangles[k]);
  cli_info(&common, " triangles), level below P = %.2f:\n%10s", p.threshold, "d \\ ecc");
  for (int e = 0; e < T.ne; e++) cli_info(&common, " %5.3g", T.eccentricities_deg[e]);
  cli_info(&common, "\n");
  for (int d = 0; d < T.nd; d++) {
    cli_info(&common, "%8.3g m", T.distances_m[d]);
    for (int e = 0; e < T.ne; e++) cli_info(&common, " %5d", T.level[d * T.ne + e]);
    cli_info(&common, "\n");
  }
  int nwindowed = 0;
  for (int d = 0; d < T.nd; d++) nwindowed += T.windowed[d];
  if (nreduced)
    cli_info(&common, "note: %d of %d distances judged below the display's %.3g ppd (the window is capped at --max-px %d): "
                      ".result.reduced_ppd\n", nreduced, T.nd, display_ppd, p.max_px);
  if (nwindowed)
    cli_info(&common, "note: %d of %d distances judged on %d-pixel windows at the display's ppd around the fixation "
                      "point or the silhouette facing it: .result.windowed\n", nwindowed, T.nd, p.max_px);
  if (rc == EXIT_OK)
    cli_info(&common, "wrote %s/gaze.json, gaze.csv, gaze.png%s%s (%.1f s)\n", final_dir, input_levels < 2 ? ", " : "",
             input_levels < 2 ? chain_model : "", run_s);
  jnd_gaze_table_free(&T);
  jnd_scene_free(scene);
  return rc;
}

const jnd_command jnd_cmd_gaze = {"gaze", "002's gaze-contingent LOD table L(distance, eccentricity)", run};
