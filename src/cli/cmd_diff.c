/* jnd diff REF TEST — how likely a viewer notices the difference. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd diff REF TEST [options]\n"
      "\n"
      "Predicts, per pixel, how many just-noticeable differences (JND) separate TEST\n"
      "from REF as a viewer sees them on a display, and the probability that a viewer\n"
      "notices (000 eq. 4), pooled over the image (default: 93rd percentile, 000 §6).\n"
      "Inputs: PNG (8/16-bit, sRGB), JPEG, Radiance HDR, OpenEXR (linear, cd/m2 x\n"
      "--exr-scale). Alpha is composited over the display's black.\n"
      "\n"
      "%s"
      "\n"
      "model inputs:\n"
      "  --motion FILE.exr   per-pixel screen displacement, pixels per frame (2 channels)\n"
      "  --fps N             frames per second for --motion (default 60)\n"
      "  --weights FILE      per-pixel weights (first channel) multiplying the difference map\n"
      "  --gaze X,Y          fixation point in pixels, inside the image: sensitivity falls\n"
      "                      with eccentricity (default: every pixel is seen foveally)\n"
      "\n"
      "outputs:\n"
      "  --map FILE.exr      float JND per pixel\n"
      "  --heatmap FILE.png  JND over a dimmed grey copy of REF on a log scale from 0.1\n"
      "                      JND, with a colour bar (small images are magnified)\n"
      "  --heatmap-max J     JND at the top of the heatmap's scale (default: the 99.9th\n"
      "                      percentile rounded up to 1, 2 or 5 x 10^k, at least 2)\n"
      "  --pool P            pooling for p_detect: p93 (default), pNN, max, mean, minkowski\n"
      "  --calibration FILE  a `jnd calibrate` file: its JND transform, slope and percentile\n"
      "  --fail-above P      exit 1 when the pooled probability exceeds P (render gating)\n"
      "%s"
      "\n"
      "Paper numbers: 000 is Wolski et al. 2019 (pooling, psychometric function); the\n"
      "model is Schwarz & Stamminger 2009 (004); include/jnd.h lists them all.\n"
      "Exit status: 0, 1 when above --fail-above, 2 for bad input.\n",
      cli_display_help, cli_common_help);
}

static int load(const char *path, jnd_image *img, jnd_image_info *info) {
  if (jnd_image_read(path, img, info) != JND_OK) {
    cli_error("%s", jnd_last_error());
    return 0;
  }
  return 1;
}

/* the reference as a display signal for the heatmap's grey backdrop: a
 * linear file as the display shows it (scaled to its peak, sRGB-encoded) */
static int heatmap_backdrop(const char *path, const jnd_display *d, jnd_image *out) {
  jnd_image_info info;
  if (!load(path, out, &info)) return 0;
  if (info.encoding == JND_ENCODING_LINEAR) {
    size_t n = (size_t)out->w * out->h * out->c;
    for (size_t i = 0; i < n; i++) out->data[i] = (float)(out->data[i] * d->exr_scale / d->peak_cdm2);
    jnd_image enc = {0};
    if (jnd_render_to_srgb(out, &enc) != JND_OK) {
      cli_error("%s", jnd_last_error());
      return 0;
    }
    jnd_image_free(out);
    *out = enc;
  }
  return 1;
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  jnd_model_params mp;
  jnd_model_defaults(&mp);
  const char *paths[2] = {0}, *motion_path = NULL, *weights_path = NULL, *map_path = NULL, *heat_path = NULL;
  const char *pool_name = "p93", *cal_path = NULL;
  jnd_calibration cal;
  double fail_above = -1, heat_max = 0;
  int npaths = 0;
  cli_display disp;
  cli_display_init(&disp);
  cli_args args = cli_args_start(argc, argv, "diff"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_display_opt(ap, &disp)) {
    } else if (cli_opt(ap, "--motion", &v)) {
      motion_path = v;
    } else if (cli_opt(ap, "--fps", &v)) {
      mp.fps = cli_double(ap, "--fps", v, 1, 1000);
    } else if (cli_opt(ap, "--weights", &v)) {
      weights_path = v;
    } else if (cli_opt(ap, "--gaze", &v)) {
      cli_pair(ap, "--gaze", v, &mp.gaze_x, &mp.gaze_y);
      mp.has_gaze = 1;
    } else if (cli_opt(ap, "--pool", &v)) {
      pool_name = v;
    } else if (cli_opt(ap, "--calibration", &v)) {
      cal_path = v;
    } else if (cli_opt(ap, "--map", &v)) {
      map_path = v;
    } else if (cli_opt(ap, "--heatmap", &v)) {
      heat_path = v;
    } else if (cli_opt(ap, "--heatmap-max", &v)) {
      heat_max = cli_double(ap, "--heatmap-max", v, 0.2, 1e4);
    } else if (cli_opt(ap, "--fail-above", &v)) {
      fail_above = cli_double(ap, "--fail-above", v, 0, 1);
    } else if (cli_common_opt(ap, &common)) {
    } else if (argv[args.i][0] == '-' && argv[args.i][1]) {
      return cli_unknown(ap);
    } else if (npaths < 2) {
      paths[npaths++] = argv[args.i];
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (npaths != 2) {
    cli_error("diff: needs two images, REF and TEST (jnd diff --help)");
    return EXIT_BAD;
  }
  mp.display = cli_display_get(&disp);
  mp.threads = common.threads;
  jnd_pooling pool;
  if (jnd_pooling_parse(pool_name, &pool) != JND_OK) {
    cli_error("diff: --pool: %s", jnd_last_error());
    return EXIT_BAD;
  }
  if (cal_path) { /* 000 §7: the calibration's transform, slope and percentile */
    if (jnd_calibration_load(cal_path, &cal) != JND_OK) {
      cli_error("%s", jnd_last_error());
      return EXIT_BAD;
    }
    mp.beta = cal.beta;
    pool.kind = JND_POOL_PERCENTILE;
    pool.percentile = cal.percentile;
  }
  double t0 = jnd_seconds();
  jnd_image ref = {0}, test = {0}, motion = {0}, weights = {0}, map = {0};
  jnd_image_info ri, ti;
  int rc = EXIT_BAD;
  jnd_model *model = NULL;
  cJSON *report = NULL;
  /* outputs checked before any work, written staged, published together */
  jnd_output *outw = NULL;
  const char *ins[] = {paths[0], paths[1], motion_path, weights_path, cal_path};
  const char *map_out = NULL, *heat_out = NULL, *json_out = NULL;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 5) != EXIT_OK ||
      cli_out_file(outw, map_path, &map_out) != EXIT_OK || cli_out_file(outw, heat_path, &heat_out) != EXIT_OK ||
      cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    goto out;
  /* the two files decode at the same time */
  int ok[2];
  char msg[2][1024] = {"", ""};
#pragma omp parallel sections num_threads(common.threads == 1 ? 1 : 2)
  {
#pragma omp section
    {
      ok[0] = jnd_image_read(paths[0], &ref, &ri) == JND_OK;
      /* the message lives on the thread that failed: take it along */
      if (!ok[0]) snprintf(msg[0], sizeof msg[0], "%s", jnd_last_error());
    }
#pragma omp section
    {
      ok[1] = jnd_image_read(paths[1], &test, &ti) == JND_OK;
      if (!ok[1]) snprintf(msg[1], sizeof msg[1], "%s", jnd_last_error());
    }
  }
  if (!ok[0] || !ok[1]) {
    cli_error("%s", msg[ok[0] ? 1 : 0]);
    goto out;
  }
  cli_exr_scale_warn(&common, &disp, paths[0], &ref, &ri);
  cli_exr_scale_warn(&common, &disp, paths[1], &test, &ti);
  if (ref.w != test.w || ref.h != test.h) {
    cli_error("%s: size %d x %d differs from %s (%d x %d)", paths[1], test.w, test.h, paths[0], ref.w, ref.h);
    goto out;
  }
  if (mp.has_gaze && !(mp.gaze_x >= 0 && mp.gaze_x < ref.w && mp.gaze_y >= 0 && mp.gaze_y < ref.h)) {
    cli_error("diff: --gaze: %g,%g is outside the %d x %d image", mp.gaze_x, mp.gaze_y, ref.w, ref.h);
    goto out;
  }
  jnd_diff_inputs in = {0};
  if (motion_path) {
    if (!load(motion_path, &motion, NULL)) goto out;
    if (motion.w != ref.w || motion.h != ref.h || motion.c < 2) {
      cli_error("%s: motion map must be %d x %d with 2 channels (is %d x %d x %d)", motion_path, ref.w, ref.h,
                motion.w, motion.h, motion.c);
      goto out;
    }
    in.motion = &motion;
  }
  if (weights_path) {
    if (!load(weights_path, &weights, NULL)) goto out;
    if (weights.w != ref.w || weights.h != ref.h) {
      cli_error("%s: weight map must be %d x %d (is %d x %d)", weights_path, ref.w, ref.h, weights.w, weights.h);
      goto out;
    }
    weights.c = 1; /* the first channel */
    in.weights = &weights;
  }
  int w = ref.w, h = ref.h;
  double t_load = jnd_seconds() - t0;
  if (jnd_model_create(&mp, &model) != JND_OK) {
    cli_error("diff: %s", jnd_last_error());
    goto out;
  }
  jnd_diff_stats st;
  if (jnd_diff_files(model, &ref, &ri, &test, &ti, &in, &pool, &map, &st) != JND_OK ||
      (cal_path && jnd_diff_summarise_calibrated(&map, &cal, &st) != JND_OK)) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  double t_model = jnd_seconds() - t0 - t_load;
  if (map_path) {
    const char *name[1] = {"JND"};
    if (jnd_image_write_exr(map_out, &map, name, 0) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  if (heat_path) {
    jnd_image back = {0}, heat = {0};
    if (!heatmap_backdrop(paths[0], &mp.display, &back)) goto out;
    jnd_status s = jnd_heatmap(&back, &map, heat_max, &heat);
    if (s == JND_OK) s = jnd_image_write_png(heat_out, &heat, 8);
    jnd_image_free(&back);
    jnd_image_free(&heat);
    if (s != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  double t_total = jnd_seconds() - t0;
  int above = fail_above >= 0 && st.p_detect > fail_above;

  char pname[32];
  jnd_pooling_name(&pool, pname, sizeof pname);
  report = cli_report_new("diff");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(inputs, "reference", paths[0]);
  cJSON_AddStringToObject(inputs, "test", paths[1]);
  cJSON_AddStringToObject(inputs, "reference_format", ri.format);
  cJSON_AddStringToObject(inputs, "test_format", ti.format);
  if (motion_path) cJSON_AddStringToObject(inputs, "motion", motion_path);
  if (weights_path) cJSON_AddStringToObject(inputs, "weights", weights_path);
  if (cal_path) cJSON_AddStringToObject(inputs, "calibration", cal_path);
  cJSON_AddItemToObject(params, "display", cli_display_json(&mp.display));
  cJSON_AddStringToObject(params, "pooling", pname);
  cJSON_AddNumberToObject(params, "beta", mp.beta);
  cJSON_AddNumberToObject(params, "minkowski", mp.minkowski);
  cJSON_AddNumberToObject(params, "sensitivity", mp.sensitivity);
  cJSON_AddNumberToObject(params, "sens_rg", mp.sens_rg);
  cJSON_AddNumberToObject(params, "sens_yv", mp.sens_yv);
  if (motion_path) cJSON_AddNumberToObject(params, "fps", mp.fps);
  if (mp.has_gaze) {
    cJSON *g = cJSON_AddArrayToObject(params, "gaze");
    cJSON_AddItemToArray(g, cJSON_CreateNumber(mp.gaze_x));
    cJSON_AddItemToArray(g, cJSON_CreateNumber(mp.gaze_y));
  }
  if (fail_above >= 0) cJSON_AddNumberToObject(params, "fail_above", fail_above);
  cJSON_AddNumberToObject(res, "p_detect", st.p_detect);
  cJSON_AddStringToObject(res, "pooling", pname);
  cJSON_AddNumberToObject(res, "p_p50", st.p_p50);
  cJSON_AddNumberToObject(res, "p_p93", st.p_p93);
  cJSON_AddNumberToObject(res, "p_p99", st.p_p99);
  cJSON_AddNumberToObject(res, "p_max", st.p_max);
  cJSON_AddNumberToObject(res, "p_mean", st.p_mean);
  cJSON_AddNumberToObject(res, "jnd_mean", st.jnd_mean);
  cJSON_AddNumberToObject(res, "jnd_p93", st.jnd_p93);
  cJSON_AddNumberToObject(res, "jnd_max", st.jnd_max);
  cJSON_AddNumberToObject(res, "jnd_minkowski", st.jnd_minkowski);
  cJSON_AddNumberToObject(res, "width", w);
  cJSON_AddNumberToObject(res, "height", h);
  double bands[16];
  int nb = jnd_model_band_peaks(model, bands, 16);
  cJSON *ba = cJSON_AddArrayToObject(res, "bands_cpd");
  for (int b = 0; b < nb && b < 16; b++) cJSON_AddItemToArray(ba, cJSON_CreateNumber(round(bands[b] * 1e4) / 1e4));
  if (fail_above >= 0) cJSON_AddBoolToObject(res, "above_threshold", above);
  if (common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "load_s", t_load);
    cJSON_AddNumberToObject(t, "model_s", t_model);
    cJSON_AddNumberToObject(t, "total_s", t_total);
    cJSON_AddNumberToObject(t, "megapixels_per_s", (double)w * h / 1e6 / t_total);
  }
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto out;
  cli_info(&common, "P(detect) %s = %.3f   (p50 %.3f, p99 %.3f, max %.3f)   JND p93 %.2f, max %.2f   %dx%d, %.2f s\n",
           pname, st.p_detect, st.p_p50, st.p_p99, st.p_max, st.jnd_p93, st.jnd_max, w, h, t_total);
  if (above) cli_info(&common, "above --fail-above %.3f\n", fail_above);
  rc = above ? EXIT_ABOVE : EXIT_OK;
out:
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  jnd_model_free(model);
  jnd_image_free(&ref);
  jnd_image_free(&test);
  jnd_image_free(&motion);
  jnd_image_free(&weights);
  jnd_image_free(&map);
  return rc;
}

const jnd_command jnd_cmd_diff = {"diff", "how likely a viewer notices the difference between two images", run};
