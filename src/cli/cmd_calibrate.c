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

static int run(int argc, char **argv) {
  const char *csv_path = NULL, *out_path = NULL, *v;
  cli_common common = {0};
  jnd_calibrate_run_params p;
  jnd_calibrate_run_defaults(&p);
  jnd_calibrate_params *cp = &p.fit;
  cli_views vo;
  cli_views_init(&vo, p.judge.views.render.width, p.judge.views.render.height);
  vo.set.sampling.count = p.judge.views.sampling.count;
  cli_display disp;
  cli_display_init(&disp);
  int sizes[64], nsizes = 0;
  cli_args args = cli_args_start(argc, argv, "calibrate"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_views_opt(ap, &vo) || cli_display_opt(ap, &disp) || cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      out_path = v;
    } else if (cli_opt(ap, "--pairs", &v)) {
      p.pairs = v;
    } else if (cli_opt(ap, "--sizes", &v)) {
      nsizes = cli_int_list(ap, "--sizes", v, 1, 32768, sizes, 64);
    } else if (cli_opt(ap, "--folds", &v)) {
      cp->folds = cli_int(ap, "--folds", v, 1, 32);
    } else if (cli_opt(ap, "--p", &v)) {
      cp->threshold_p = cli_double(ap, "--p", v, 0.01, 0.99);
    } else if (cli_opt(ap, "--bias-range", &v)) {
      cli_pair(ap, "--bias-range", v, &cp->bias_min, &cp->bias_max);
      if (!args.bad && !(cp->bias_max > cp->bias_min)) {
        cli_error("calibrate: --bias-range: '%s' needs A < B", v);
        return EXIT_BAD;
      }
    } else if (cli_opt(ap, "--histogram", &v)) {
      p.histogram = v;
    } else if (!cli_operand(ap, &csv_path, NULL, 1)) {
      return EXIT_BAD;
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
  p.judge.model.display = cli_display_get(&disp);
  p.judge.model.threads = common.threads;
  p.judge.views = vo.set;
  p.sizes = sizes;
  p.nsizes = nsizes;
  p.run.map_size = vo.map_size;
  p.run.report_path = common.json_path;
  cli_progress prog;
  cli_progress_start(&prog, &common, "calibrate", 1);
  p.progress = cli_progress_callback;
  p.progress_user = &prog;
  jnd_calibrate_result *R = NULL;
  jnd_status st = jnd_calibrate_run(csv_path, &p, out_path, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  cli_info(&common, "calibration: p%g, JND -> max(0, %.4f JND %+.4f), beta %.2f\n", R->cal.percentile, R->cal.scale,
           R->cal.bias, R->cal.beta);
  cli_info(&common, "threshold error at P = %.2f: train MAE %.1f px; held out (%d folds) MAE %.1f px [",
           cp->threshold_p, R->mae_px, R->folds, R->cv_mae_px);
  for (int k = 0; k < R->folds; k++) cli_info(&common, "%s%.1f", k ? " " : "", R->fold_mae_px[k]);
  cli_info(&common, "]\n%d scenes -> %s\n", R->nscenes, out_path);
  jnd_calibrate_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_calibrate = {"calibrate", "fit pooling and a JND transform to measured thresholds (000)",
                                       run};
