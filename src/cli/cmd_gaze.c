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

/* the shared view options gaze has a use for, into its renderer's parameters */
static void views_into(const cli_views *vo, uint64_t *seed, jnd_renderer_params *r) {
  *seed = vo->set.sampling.seed;
  r->env_path = vo->set.render.env_path;
  r->samples = vo->set.render.samples;
  r->anisotropy = vo->set.render.anisotropy;
  r->platform = vo->set.render.platform;
}

/* the run with a progress bar; *progress, *user the mode's progress fields */
static int call(const char *input, const char *dir, jnd_gaze_run_params *rp, const cli_common *c, const char *label,
                void (**progress)(void *, int, int), void **user, jnd_gaze_run_result **R) {
  cli_progress bar;
  cli_progress_start(&bar, c, label, 1);
  *progress = on_progress;
  *user = &bar;
  jnd_status st = jnd_gaze_run(input, rp, dir, R);
  cli_progress_end(&bar);
  *progress = NULL;
  *user = NULL;
  return st == JND_OK ? EXIT_OK : cli_lib_error();
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
  jnd_gaze_run_params p;
  jnd_gaze_run_defaults(&p);
  jnd_gaze_fit_params *fp = &p.fit;
  cli_args args = cli_args_start(argc, argv, "gaze fit"), *ap = &args;
  args.i = 2;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      fit_help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--folds", &v)) {
      fp->folds = cli_int(ap, "--folds", v, 2, JND_GAZE_MAX_FOLDS);
    } else if (cli_opt(ap, "--seed", &v)) {
      fp->seed = (uint64_t)cli_double(ap, "--seed", v, 0, 9007199254740992.0);
    } else if (cli_opt(ap, "--confidence", &v)) {
      fp->confidence = cli_double(ap, "--confidence", v, 0.5, 0.9999);
    } else if (cli_opt(ap, "--b", &v)) {
      fp->start.b = cli_double(ap, "--b", v, 1e-6, 1e6);
    } else if (cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &data, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!data) return cli_bad("gaze fit: give a DATA.csv of trials; jnd gaze fit --help");
  p.mode = JND_GAZE_RUN_FIT;
  cli_run_options(&p.run, &common, 512);
  jnd_gaze_run_result *R = NULL;
  if (jnd_gaze_run(data, &p, dir, &R) != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  const jnd_gaze_fit_result *r = &R->fit;
  cli_info(&common, "jnd gaze fit: %s, %s model, %d trials of %d stimuli\n", data, r->temporal ? "temporal" : "spatial",
           r->trials, r->stimuli);
  for (int i = 0; i < r->nparams; i++)
    cli_info(&common, "  %-8s %10.4g  [%.4g, %.4g]\n", r->names[i], r->value[i], r->ci_lo[i], r->ci_hi[i]);
  cli_info(&common, "  all data: r = %.3f, MAE = %.3f; %d-fold: r = %.3f ± %.3f, MAE = %.3f ± %.3f\n", r->r_all,
           r->mae_all, r->folds, r->r_mean, r->r_sd, r->mae_mean, r->mae_sd);
  jnd_gaze_run_result_free(R);
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
  jnd_gaze_run_params rp;
  jnd_gaze_run_defaults(&rp);
  rp.mode = JND_GAZE_RUN_OBSERVERS;
  jnd_gaze_observers_params *p = &rp.observers;
  jnd_lod_params chain;
  jnd_lod_defaults(&chain);
  double sizes[64], ecc[64], errors[64];
  cli_views vo;   /* the observers' defaults, read back after parsing */
  cli_views_init(&vo, 0, 0);
  vo.set.sampling.seed = p->seed;
  vo.set.render = p->render;
  vo.map_size = 512;
  cli_args args = cli_args_start(argc, argv, "gaze observers"), *ap = &args;
  args.i = 2;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      observers_help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--sizes", &v)) {
      p->nsizes = cli_double_list(ap, "--sizes", v, 1e-3, 60, sizes, 64);
      p->sizes_deg = sizes;
    } else if (cli_opt(ap, "--eccentricities", &v)) {
      p->neccentricities = cli_double_list(ap, "--eccentricities", v, 0, 90, ecc, 64);
      p->eccentricities_deg = ecc;
    } else if (cli_opt(ap, "--orientations", &v)) {
      p->orientations = cli_int(ap, "--orientations", v, 1, 64);
    } else if (cli_opt(ap, "--answers", &v)) {
      p->answers = cli_int(ap, "--answers", v, 1, 10000);
    } else if (cli_opt(ap, "--errors", &v)) {
      chain.nerrors = cli_errors(ap, v, errors, 63);
      chain.errors = errors;
      p->chain = &chain;
    } else if (cli_opt(ap, "--min-px", &v)) {
      p->min_px = cli_int(ap, "--min-px", v, 16, 4096);
    } else if (cli_opt(ap, "--max-px", &v)) {
      p->max_px = cli_int(ap, "--max-px", v, 16, 4096);
    } else if (cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, models, &nmodels, 64)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (cli_views_only(&vo, CLI_SEED | CLI_ENV | CLI_SAMPLES | CLI_ANISOTROPY | CLI_PLATFORM | CLI_MAP_SIZE,
                     "gaze observers", "its views are --sizes x --orientations; see jnd gaze observers --help"))
    return EXIT_BAD;
  views_into(&vo, &p->seed, &p->render);
  if (!nmodels) return cli_bad("gaze observers: give at least one MODEL; jnd gaze observers --help");
  if (!dir) return cli_bad("gaze observers: give an output folder with -o OUTDIR");
  rp.models = models;
  rp.nmodels = nmodels;
  cli_run_options(&rp.run, &common, vo.map_size);
  jnd_gaze_run_result *R = NULL;
  if (call(NULL, dir, &rp, &common, "gaze observers", &p->progress, &p->progress_user, &R) != EXIT_OK) return EXIT_BAD;
  int rc = cli_report_print(R->report, common.json_path);
  cli_info(&common, "jnd gaze observers: %d stimuli x %d answers; mean P spatial %.3f, switch %.3f; wrote %s\n",
           R->observers.n, R->observers.answers, R->mean_p_spatial, R->mean_p_switch, dir);
  jnd_gaze_run_result_free(R);
  return rc;
}

static int run(int argc, char **argv) {
  if (argc >= 2 && strcmp(argv[1], "fit") == 0) return run_fit(argc, argv);
  if (argc >= 2 && strcmp(argv[1], "observers") == 0) return run_observers(argc, argv);
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  cli_display disp;
  cli_display_init(&disp);
  jnd_gaze_run_params rp;
  jnd_gaze_run_defaults(&rp);
  jnd_gaze_table_params *p = &rp.table;
  jnd_lod_params chain;
  jnd_lod_defaults(&chain);
  double dist[256], ecc[256], errors[64];
  cli_views vo;   /* gaze's defaults, read back after parsing */
  cli_views_init(&vo, 0, 0);
  vo.set.sampling.seed = p->seed;
  vo.set.render = p->render;
  vo.map_size = 512;
  int nparams = 0;
  const char *params_files[8];
  cli_args args = cli_args_start(argc, argv, "gaze"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--distances", &v)) {
      p->ndistances = cli_double_list(ap, "--distances", v, 0, 1e6, dist, 256);
      p->distances_m = dist;
    } else if (cli_opt(ap, "--eccentricities", &v)) {
      p->neccentricities = cli_double_list(ap, "--eccentricities", v, 0, 90, ecc, 256);
      p->eccentricities_deg = ecc;
    } else if (cli_opt(ap, "--orientations", &v)) {
      p->orientations = cli_int(ap, "--orientations", v, 1, 256);
    } else if (cli_opt(ap, "--threshold", &v)) {
      p->threshold = cli_double(ap, "--threshold", v, 0.501, 0.999);
    } else if (cli_opt(ap, "--errors", &v)) {
      chain.nerrors = cli_errors(ap, v, errors, 63);
      chain.errors = errors;
      p->chain = &chain;
    } else if (cli_opt(ap, "--min-px", &v)) {
      p->min_px = cli_int(ap, "--min-px", v, 16, 4096);
    } else if (cli_opt(ap, "--max-px", &v)) {
      p->max_px = cli_int(ap, "--max-px", v, 16, 4096);
    } else if (cli_flag(ap, "--whole-near")) {
      p->near_window = 0;
    } else if (cli_opt(ap, "--params", &v)) {
      if (nparams == 8) return cli_bad("--params: at most 8 files");
      params_files[nparams++] = v;
    } else if (cli_display_opt(ap, &disp) || cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &model, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  /* the shared view options, where gaze has a use for them */
  if (cli_views_only(&vo, CLI_SEED | CLI_ENV | CLI_SAMPLES | CLI_ANISOTROPY | CLI_PLATFORM | CLI_MAP_SIZE, "gaze",
                     "its views are --distances x --orientations, each at its own size; see jnd gaze --help"))
    return EXIT_BAD;
  views_into(&vo, &p->seed, &p->render);
  if (!model) return cli_bad("gaze: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd gaze --help");
  if (!dir) return cli_bad("gaze: give an output folder with -o OUTDIR; jnd gaze --help");
  p->measure.model.display = cli_display_get(&disp);
  rp.model_files = params_files;
  rp.nmodel_files = nparams;
  cli_run_options(&rp.run, &common, vo.map_size);
  jnd_gaze_run_result *R = NULL;
  if (call(model, dir, &rp, &common, "gaze", &p->progress, &p->progress_user, &R) != EXIT_OK) return EXIT_BAD;
  int rc = cli_report_print(R->report, common.json_path);

  /* the human summary: the table */
  const jnd_gaze_table *T = &R->table;
  cli_info(&common, "jnd gaze: %s, %d levels (", model, T->nlevels);
  for (int k = 0; k < T->nlevels; k++) cli_info(&common, "%s%zu", k ? " " : "", T->triangles[k]);
  cli_info(&common, " triangles), level below P = %.2f:\n%10s", p->threshold, "d \\ ecc");
  for (int e = 0; e < T->ne; e++) cli_info(&common, " %5.3g", T->eccentricities_deg[e]);
  cli_info(&common, "\n");
  for (int d = 0; d < T->nd; d++) {
    cli_info(&common, "%8.3g m", T->distances_m[d]);
    for (int e = 0; e < T->ne; e++) cli_info(&common, " %5d", T->level[d * T->ne + e]);
    cli_info(&common, "\n");
  }
  if (R->nreduced)
    cli_info(&common, "note: %d of %d distances judged below the display's %.3g ppd (the window is capped at --max-px %d): "
                      ".result.reduced_ppd\n", R->nreduced, T->nd, p->measure.model.display.ppd, p->max_px);
  if (R->nwindowed)
    cli_info(&common, "note: %d of %d distances judged on %d-pixel windows at the display's ppd around the fixation "
                      "point or the silhouette facing it: .result.windowed\n", R->nwindowed, T->nd, p->max_px);
  int made = R->input_levels < 2;
  cli_info(&common, "wrote %s/gaze.json, gaze.csv, gaze.png%s%s (%.1f s)\n", dir, made ? ", " : "",
           made ? R->chain_model : "", R->table_s);
  jnd_gaze_run_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_gaze = {"gaze", "002's gaze-contingent LOD table L(distance, eccentricity)", run};
