/* jnd pop NEW EXPECTED -o OUT — will this level switch pop? (004 §3.2, §4, §5.2) */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd pop NEW EXPECTED -o OUT [options]\n"
      "\n"
      "Will this level switch pop? NEW is the frame where the switch happens,\n"
      "rendered with the new level; EXPECTED is the same frame rendered with the\n"
      "previous level (what the viewer expects). Both go through the vision model\n"
      "with each pixel's retinal velocity; where they differ by at least 2 JND,\n"
      "popping regions grow and are rated by R (R < 1 rarely visible, R > 3 easily;\n"
      "Schwarz & Stamminger 2009). Frames: PNG/JPEG (sRGB) or EXR/HDR (linear,\n"
      "cd/m2 x --exr-scale). Maps (displacement, depth): OpenEXR.\n"
      "\n"
      "%s"
      "\n"
      "motion:\n"
      "  --displacement D.exr   NEW's screen displacement from the previous frame,\n"
      "                         pixels (2 channels: x right, y down); also EXPECTED's\n"
      "                         unless --displacement-expected. Without: static\n"
      "  --displacement-expected E.exr   EXPECTED's own displacement\n"
      "  --fps F                frames per second (default 60)\n"
      "\n"
      "weights (optional; multiplied into the difference map, 004 §3.2, §4):\n"
      "  --weights W            per-pixel weights 0..1 (first channel)\n"
      "  --depth D.exr          disocclusion: depth of NEW's pixels as the previous\n"
      "                         frame's camera saw them (0 = nothing there)\n"
      "  --prev-depth P.exr     the previous frame's depth map, rendered with NEW's level\n"
      "  --depth-expected, --prev-depth-expected   the same for EXPECTED's level\n"
      "  --prev-frame F         flicker: the previous frame as shown\n"
      "  --prev-shading S       flicker: EXPECTED's pixels shaded with the previous\n"
      "                         frame's camera and lights\n"
      "  --mask M               object pixels (> 0.5) that coverage counts (default all)\n"
      "\n"
      "outputs:\n"
      "  -o, --output DIR       pop.json and regions.png (the folder is created)\n"
      "  --maps                 also jnd.exr (weighted JND map) and weights.exr\n"
      "  --max-regions N        regions listed in pop.json, best first (default 100;\n"
      "                         all are counted)\n"
      "  --fail-above R         exit 1 when the largest rating exceeds R\n"
      "  --timings              add wall-clock timings to the report (they differ run to run)\n"
      "  --json FILE|-          also write the report there\n"
      "  --threads N            worker threads (results do not depend on it)\n"
      "  --quiet                nothing on stderr but errors\n"
      "\n"
      "Exit status: 0; 1 when above --fail-above; 2 for bad input (one line:\n"
      "jnd: FILE: problem, and nothing written).\n",
      cli_display_help);
}

static cJSON *int4(const int *v) {
  cJSON *a = cJSON_CreateArray();
  for (int k = 0; k < 4; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
  return a;
}

/* a number, or null where it is undefined (no region) */
static void add_num(cJSON *o, const char *key, double v) {
  if (isfinite(v))
    cJSON_AddNumberToObject(o, key, v);
  else
    cJSON_AddNullToObject(o, key);
}

static cJSON *weight_json(const jnd_pop_weight_stats *w) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddBoolToObject(o, "present", w->present);
  if (w->present) {
    cJSON_AddNumberToObject(o, "mean", w->mean);
    cJSON_AddNumberToObject(o, "min", w->min);
    cJSON_AddNumberToObject(o, "pixels_below_half", (double)w->below_half);
  }
  return o;
}

static int write_image(const char *dir, const char *name, const jnd_image *img, int exr) {
  char path[4400];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  const char *ch[1] = {exr == 2 ? "W" : "JND"};
  jnd_status s = exr ? jnd_image_write_exr(path, img, ch, 0) : jnd_image_write_png(path, img, 8);
  if (s != JND_OK) {
    cli_error("%s", jnd_last_error());
    return 0;
  }
  return 1;
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  jnd_model_params mp;
  jnd_model_defaults(&mp);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_paths f = {0};
  const char *paths[2] = {0}, *dir = NULL;
  int npaths = 0, maps = 0, max_regions = 100;
  double fail_above = NAN;
  cli_display disp;
  cli_display_init(&disp);
  cli_args args = cli_args_start(argc, argv, "pop"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v, *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_display_opt(ap, &disp)) {
    } else if (cli_opt(ap, "--displacement-expected", &v)) {
      f.displacement_expected = v;
    } else if (cli_opt(ap, "--displacement", &v)) {
      f.displacement = v;
    } else if (cli_opt(ap, "--fps", &v)) {
      mp.fps = cli_double(ap, "--fps", v, 1, 1000);
    } else if (cli_opt(ap, "--weights", &v)) {
      f.weights = v;
    } else if (cli_opt(ap, "--depth-expected", &v)) {
      f.depth_expected = v;
    } else if (cli_opt(ap, "--depth", &v)) {
      f.depth = v;
    } else if (cli_opt(ap, "--prev-depth-expected", &v)) {
      f.prev_depth_expected = v;
    } else if (cli_opt(ap, "--prev-depth", &v)) {
      f.prev_depth = v;
    } else if (cli_opt(ap, "--prev-frame", &v)) {
      f.prev_color = v;
    } else if (cli_opt(ap, "--prev-shading", &v)) {
      f.prev_shading = v;
    } else if (cli_opt(ap, "--mask", &v)) {
      f.mask = v;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_flag(ap, "--maps")) {
      maps = 1;
    } else if (cli_opt(ap, "--max-regions", &v)) {
      max_regions = cli_int(ap, "--max-regions", v, 0, 1 << 30);
    } else if (cli_opt(ap, "--fail-above", &v)) {
      fail_above = cli_double(ap, "--fail-above", v, -100, 100);
    } else if (cli_common_opt(ap, &common)) {
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (npaths < 2) {
      paths[npaths++] = a;
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  mp.display = cli_display_get(&disp);
  mp.threads = pp.threads = common.threads;
  if (npaths == 1) {
    /* the asset form needs the judge's renders and the LOD chain (issue 12, items 5–6) */
    cli_error("pop: the asset form (jnd pop MODEL) is not available yet; give two frames, NEW EXPECTED "
              "(jnd pop --help)");
    return EXIT_BAD;
  }
  if (npaths != 2) {
    cli_error("pop: needs two frames, NEW and EXPECTED (jnd pop --help)");
    return EXIT_BAD;
  }
  if (!dir) {
    cli_error("pop: give an output folder with -o OUT (jnd pop --help)");
    return EXIT_BAD;
  }
  f.actual = paths[0];
  f.expected = paths[1];
  double t0 = cli_now();
  int rc = EXIT_BAD;
  jnd_model *model = NULL;
  cJSON *report = NULL;
  jnd_pop_result r = {0};
  if (jnd_model_create(&mp, &model) != JND_OK) {
    cli_error("pop: %s", jnd_last_error());
    goto out;
  }
  if (jnd_pop_files(model, &f, &pp, &r) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  /* only now, with a result, is anything created */
  if (jnd_make_dirs(dir) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  double t_write = cli_now();
  if (!write_image(dir, "regions.png", &r.picture, 0)) goto out;
  if (maps && (!write_image(dir, "jnd.exr", &r.jnd, 1) || (r.weights.data && !write_image(dir, "weights.exr", &r.weights, 2))))
    goto out;
  int above = isfinite(fail_above) && r.nregions && r.max_rating > fail_above;

  report = cli_report_new("pop");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  const char *in_keys[] = {"new", "expected", "displacement", "displacement_expected", "depth", "depth_expected",
                           "prev_depth", "prev_depth_expected", "weights", "prev_frame", "prev_shading", "mask"};
  const char *in_vals[] = {f.actual, f.expected, f.displacement, f.displacement_expected, f.depth,
                           f.depth_expected, f.prev_depth, f.prev_depth_expected, f.weights, f.prev_color,
                           f.prev_shading, f.mask};
  for (size_t k = 0; k < sizeof in_keys / sizeof in_keys[0]; k++)
    if (in_vals[k]) cJSON_AddStringToObject(inputs, in_keys[k], in_vals[k]);
  cJSON_AddItemToObject(params, "display", cli_display_json(&mp.display));
  cJSON_AddNumberToObject(params, "fps", mp.fps);
  cJSON_AddNumberToObject(params, "threshold_jnd", pp.threshold_jnd);
  cJSON_AddNumberToObject(params, "minkowski", pp.minkowski);
  cJSON_AddNumberToObject(params, "depth_tolerance", pp.depth_tolerance);
  cJSON *fl = cJSON_AddObjectToObject(params, "flicker");
  cJSON_AddNumberToObject(fl, "ratio_lo", pp.flicker_ratio_lo);
  cJSON_AddNumberToObject(fl, "ratio_hi", pp.flicker_ratio_hi);
  cJSON_AddNumberToObject(fl, "motion_lo_px", pp.flicker_motion_lo_px);
  cJSON_AddNumberToObject(fl, "motion_hi_px", pp.flicker_motion_hi_px);
  cJSON_AddNumberToObject(params, "top_regions", pp.top_regions);
  cJSON *ct = cJSON_AddArrayToObject(params, "coverage_thresholds");
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp.coverage_small));
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp.coverage_large));
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp.coverage_huge));
  cJSON *rt = cJSON_AddArrayToObject(params, "rating_thresholds");
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp.rating_low));
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp.rating_high));
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp.rating_very_high));
  cJSON_AddNumberToObject(params, "sensitivity", mp.sensitivity);
  cJSON_AddNumberToObject(params, "sens_rg", mp.sens_rg);
  cJSON_AddNumberToObject(params, "sens_yv", mp.sens_yv);
  if (isfinite(fail_above)) cJSON_AddNumberToObject(params, "fail_above", fail_above);

  cJSON_AddNumberToObject(res, "width", r.w);
  cJSON_AddNumberToObject(res, "height", r.h);
  cJSON_AddNumberToObject(res, "region_count", r.nregions);
  cJSON *regs = cJSON_AddArrayToObject(res, "regions");
  for (int k = 0; k < r.nregions && k < max_regions; k++) {
    const jnd_pop_region *g = &r.regions[k];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "pixels", (double)g->pixels);
    cJSON_AddNumberToObject(o, "sigma", g->sigma);
    cJSON_AddNumberToObject(o, "rating", g->rating);
    cJSON_AddItemToObject(o, "bbox", int4(g->bbox));
    cJSON_AddNumberToObject(o, "jnd_max", g->jnd_max);
    cJSON_AddItemToArray(regs, o);
  }
  add_num(res, "max_rating", r.max_rating);
  cJSON_AddNumberToObject(res, "coverage", r.coverage);
  cJSON_AddStringToObject(res, "coverage_score", jnd_pop_coverage_name(r.coverage_score));
  add_num(res, "rating_top", r.rating_top);
  cJSON_AddStringToObject(res, "rating_score", jnd_pop_rating_name(r.rating_score));
  cJSON_AddNumberToObject(res, "detection_score", r.detection_score);
  cJSON_AddNumberToObject(res, "max_delta_e94", r.max_delta_e94);
  cJSON_AddNumberToObject(res, "jnd_max", r.jnd_max);
  cJSON_AddNumberToObject(res, "object_pixels", (double)r.object_pixels);
  cJSON_AddNumberToObject(res, "covered_pixels", (double)r.covered_pixels);
  cJSON *wj = cJSON_AddObjectToObject(res, "weights");
  cJSON_AddItemToObject(wj, "disocclusion", weight_json(&r.disocclusion));
  cJSON_AddItemToObject(wj, "flicker", weight_json(&r.flicker));
  cJSON_AddItemToObject(wj, "user", weight_json(&r.user));
  cJSON *outs = cJSON_AddObjectToObject(res, "outputs");
  cJSON_AddStringToObject(outs, "regions", "regions.png");
  if (maps) {
    cJSON_AddStringToObject(outs, "jnd", "jnd.exr");
    if (r.weights.data) cJSON_AddStringToObject(outs, "weights", "weights.exr");
  }
  if (isfinite(fail_above)) cJSON_AddBoolToObject(res, "above_threshold", above);
  if (common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "read_s", r.timings.read_s);
    cJSON_AddNumberToObject(t, "weights_s", r.timings.weights_s);
    cJSON_AddNumberToObject(t, "model_s", r.timings.model_s);
    cJSON_AddNumberToObject(t, "regions_s", r.timings.regions_s);
    cJSON_AddNumberToObject(t, "picture_s", r.timings.picture_s);
    cJSON_AddNumberToObject(t, "write_s", cli_now() - t_write);
    cJSON_AddNumberToObject(t, "total_s", cli_now() - t0);
  }
  char jpath[4400];
  snprintf(jpath, sizeof jpath, "%s/pop.json", dir);
  if (cli_report_write(report, jpath) != EXIT_OK) goto out;
  if (common.json_path && cli_report_write(report, common.json_path) != EXIT_OK) goto out;
  if (r.nregions)
    cli_info(&common, "%d popping region%s, max R %.2f; coverage %s, rating %s: detection score %d of 5; "
                      "max dE94 %.2f   %dx%d, %.2f s\n",
             r.nregions, r.nregions == 1 ? "" : "s", r.max_rating, jnd_pop_coverage_name(r.coverage_score),
             jnd_pop_rating_name(r.rating_score), r.detection_score, r.max_delta_e94, r.w, r.h, cli_now() - t0);
  else
    cli_info(&common, "no popping region (detection score 1 of 5); max dE94 %.2f   %dx%d, %.2f s\n",
             r.max_delta_e94, r.w, r.h, cli_now() - t0);
  if (above) cli_info(&common, "above --fail-above %g\n", fail_above);
  rc = above ? EXIT_ABOVE : EXIT_OK;
out:
  cJSON_Delete(report);
  jnd_pop_result_free(&r);
  jnd_model_free(model);
  return rc;
}

const jnd_command jnd_cmd_pop = {"pop", "will a level switch pop? popping regions, ratings and scores (004)", run};
