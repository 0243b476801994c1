/* jnd pop NEW EXPECTED -o OUT — will this level switch pop? (004 §3.2, §4, §5.2) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd pop NEW EXPECTED -o OUT [options]      frames you bring\n"
      "       jnd pop NEW_%%04d.png EXPECTED_%%04d.png --frames FIRST,LAST -o OUT [options]\n"
      "                                                  a sequence of them\n"
      "       jnd pop MODEL -o OUT [options]             frames jnd renders\n"
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
      "sequences (frame form):\n"
      "  --frames FIRST,LAST    every frame FIRST..LAST: NEW, EXPECTED and any map path\n"
      "                         holding %%d or %%0Nd get the frame's number (a path\n"
      "                         without one serves every frame). pop.json gets\n"
      "                         .result.frames[] and OUT/frames.csv one row per frame;\n"
      "                         the rest of the report and regions.png are the worst\n"
      "                         frame's (highest max R), .result.worst_frame\n"
      "\n"
      "asset form (MODEL: glTF/GLB/OBJ, builtin, builtin:sphere):\n"
      "  the chain is the file's MSFT_lod levels (as jnd lod writes them), the --level\n"
      "  files, or one made with meshoptimizer (--errors). The switch from level K to\n"
      "  K + 1 is rendered at frame F of the motion, seen from the first view: NEW is\n"
      "  level K + 1, EXPECTED level K, with motion vectors and depth (this frame and\n"
      "  the previous one, for the disocclusion weight).\n"
      "  --switch K             the switch from level K to K + 1 (0)\n"
      "  --frame F              the switch frame along the motion (0: the view's pose)\n"
      "  --orbit DPS            the camera circles the target, degrees/s (0: static)\n"
      "  --translate MPS        the camera travels at MPS metres/s along --direction\n"
      "  --direction X,Y,Z      in the camera's frame: x right, y up, z back (1,0,0)\n"
      "  --spin DPS             the object spins about +Y instead, degrees/s\n"
      "  --pan DPS              the camera turns in place about +Y, degrees/s\n"
      "  --unit-m U             metres per object unit (1)\n"
      "  --level FILE           a level from another file, finest first (repeatable)\n"
      "  --errors LIST          error targets of a chain made here: rising, in [1e-6, 1] of\n"
      "                         the model's extent, e.g. 1/1024,1/256 (docs/lod.md)\n"
      "  --rebuild              make a chain even when the file has levels\n"
      "decisions (asset form):\n"
      "  --decide               the popping-free switch distance of every level and\n"
      "                         speed (largest R over the views < 1), beside the\n"
      "                         1-pixel geometric-error rule: pop.json .result.switch[]\n"
      "                         and switch.png\n"
      "  --speeds LIST          degrees/s of the orbit (or --spin, --pan) (0,30,120)\n"
      "  --tolerance T          relative tolerance of the distance bisection (0.05)\n"
      "  --coverage-range N,F   distances searched, as the fraction of the image\n"
      "                         height the object fills (1,0.02)\n"
      "%s"
      "\n"
      "outputs:\n"
      "  -o, --output DIR       pop.json and regions.png (the folder is created)\n"
      "  --maps                 also jnd.exr (weighted JND map) and weights.exr\n"
      "  --max-regions N        regions listed in pop.json, best first (default 100;\n"
      "                         all are counted)\n"
      "  --fail-above R         exit 1 when the largest rating exceeds R\n"
      "%s"
      "\n"
      "Exit status: 0; 1 when above --fail-above; 2 for bad input (one line:\n"
      "jnd: FILE: problem, and nothing written).\n",
      cli_display_help, cli_views_help, cli_common_help);
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

/* a comma-separated list of numbers in lo..hi; its count, or −1 */
/* the pair's result: regions, scores, weights (the same fields in both forms) */
static void result_json(cJSON *res, const jnd_pop_result *r, int max_regions) {
  cJSON_AddNumberToObject(res, "width", r->w);
  cJSON_AddNumberToObject(res, "height", r->h);
  cJSON_AddNumberToObject(res, "region_count", r->nregions);
  cJSON *regs = cJSON_AddArrayToObject(res, "regions");
  for (int k = 0; k < r->nregions && k < max_regions; k++) {
    const jnd_pop_region *g = &r->regions[k];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "pixels", (double)g->pixels);
    cJSON_AddNumberToObject(o, "sigma", g->sigma);
    cJSON_AddNumberToObject(o, "rating", g->rating);
    cJSON_AddItemToObject(o, "bbox", int4(g->bbox));
    cJSON_AddNumberToObject(o, "jnd_max", g->jnd_max);
    cJSON_AddItemToArray(regs, o);
  }
  add_num(res, "max_rating", r->max_rating);
  cJSON_AddNumberToObject(res, "coverage", r->coverage);
  cJSON_AddStringToObject(res, "coverage_score", jnd_pop_coverage_name(r->coverage_score));
  add_num(res, "rating_top", r->rating_top);
  cJSON_AddStringToObject(res, "rating_score", jnd_pop_rating_name(r->rating_score));
  cJSON_AddNumberToObject(res, "detection_score", r->detection_score);
  cJSON_AddNumberToObject(res, "max_delta_e94", r->max_delta_e94);
  cJSON_AddNumberToObject(res, "jnd_max", r->jnd_max);
  cJSON_AddNumberToObject(res, "object_pixels", (double)r->object_pixels);
  cJSON_AddNumberToObject(res, "covered_pixels", (double)r->covered_pixels);
  cJSON *wj = cJSON_AddObjectToObject(res, "weights");
  cJSON_AddItemToObject(wj, "disocclusion", weight_json(&r->disocclusion));
  cJSON_AddItemToObject(wj, "flicker", weight_json(&r->flicker));
  cJSON_AddItemToObject(wj, "user", weight_json(&r->user));
}

static void params_json(cJSON *params, const jnd_model_params *mp, const jnd_pop_params *pp, double fail_above) {
  cJSON_AddItemToObject(params, "display", cli_display_json(&mp->display));
  cJSON_AddNumberToObject(params, "fps", mp->fps);
  cJSON_AddNumberToObject(params, "threshold_jnd", pp->threshold_jnd);
  cJSON_AddNumberToObject(params, "minkowski", pp->minkowski);
  cJSON_AddNumberToObject(params, "depth_tolerance", pp->depth_tolerance);
  cJSON *fl = cJSON_AddObjectToObject(params, "flicker");
  cJSON_AddNumberToObject(fl, "ratio_lo", pp->flicker_ratio_lo);
  cJSON_AddNumberToObject(fl, "ratio_hi", pp->flicker_ratio_hi);
  cJSON_AddNumberToObject(fl, "motion_lo_px", pp->flicker_motion_lo_px);
  cJSON_AddNumberToObject(fl, "motion_hi_px", pp->flicker_motion_hi_px);
  cJSON_AddNumberToObject(params, "top_regions", pp->top_regions);
  cJSON *ct = cJSON_AddArrayToObject(params, "coverage_thresholds");
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp->coverage_small));
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp->coverage_large));
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp->coverage_huge));
  cJSON *rt = cJSON_AddArrayToObject(params, "rating_thresholds");
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp->rating_low));
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp->rating_high));
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp->rating_very_high));
  cJSON_AddNumberToObject(params, "sensitivity", mp->sensitivity);
  cJSON_AddNumberToObject(params, "sens_rg", mp->sens_rg);
  cJSON_AddNumberToObject(params, "sens_yv", mp->sens_yv);
  if (isfinite(fail_above)) cJSON_AddNumberToObject(params, "fail_above", fail_above);
}

/* the sequence's table: .result.frames[] */
static void frames_json(cJSON *res, const jnd_pop_sequence_result *q) {
  cJSON_AddNumberToObject(res, "worst_frame", q->rows[q->worst].frame);
  cJSON *fr = cJSON_AddArrayToObject(res, "frames");
  for (int i = 0; i < q->nrows; i++) {
    const jnd_pop_frame_row *w = &q->rows[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "frame", w->frame);
    add_num(o, "max_rating", w->max_rating);
    cJSON_AddNumberToObject(o, "detection_score", w->detection_score);
    cJSON_AddNumberToObject(o, "regions", w->nregions);
    cJSON_AddNumberToObject(o, "max_delta_e94", w->max_delta_e94);
    cJSON_AddNumberToObject(o, "coverage", w->coverage);
    cJSON_AddStringToObject(o, "coverage_score", jnd_pop_coverage_name(w->coverage_score));
    add_num(o, "rating_top", w->rating_top);
    cJSON_AddStringToObject(o, "rating_score", jnd_pop_rating_name(w->rating_score));
    cJSON_AddNumberToObject(o, "jnd_max", w->jnd_max);
    cJSON_AddItemToArray(fr, o);
  }
}

/* the same table as OUT/frames.csv (an empty max_rating: no region) */
static int frames_csv(const char *dir, const jnd_pop_sequence_result *q) {
  size_t cap = 128 + (size_t)q->nrows * 160, n = 0;
  char *t = malloc(cap);
  if (!t) {
    cli_error("pop: out of memory");
    return 0;
  }
  n += (size_t)snprintf(t + n, cap - n, "frame,max_rating,detection_score,regions,max_delta_e94,coverage\n");
  for (int i = 0; i < q->nrows; i++) {
    const jnd_pop_frame_row *w = &q->rows[i];
    char r[40] = "";
    if (isfinite(w->max_rating)) snprintf(r, sizeof r, "%.6f", w->max_rating);
    n += (size_t)snprintf(t + n, cap - n, "%d,%s,%d,%d,%.6f,%.6f\n", w->frame, r, w->detection_score, w->nregions,
                          w->max_delta_e94, w->coverage);
  }
  char path[4400];
  snprintf(path, sizeof path, "%s/frames.csv", dir);
  int ok = jnd_write_file_atomic(path, t, n) == JND_OK;
  if (!ok) cli_error("%s", jnd_last_error());
  free(t);
  return ok;
}

static const char *motion_name(jnd_pop_motion_kind k) {
  return k == JND_POP_ORBIT ? "orbit" : k == JND_POP_TRANSLATE ? "translate" : k == JND_POP_PAN ? "pan" : "spin";
}

static const char *switch_status_name(jnd_pop_switch_status s) {
  return s == JND_POP_SWITCH_FOUND ? "found" : s == JND_POP_SWITCH_NEAREST ? "nearest" : "none";
}

typedef struct {
  const cli_common *common;
  cli_progress count;
  const char *stage;
  char label[64];
} pop_progress;

/* a line per stage and, where it has several steps (the switch table's
 * searches, minutes each; a sequence's frames), per step with the time left */
static void on_progress(void *user, const char *stage, int done, int total) {
  pop_progress *p = user;
  if (!p->stage || strcmp(p->stage, stage) != 0) {
    p->stage = stage;
    snprintf(p->label, sizeof p->label, "pop: %s", stage);
    cli_progress_start(&p->count, p->common, p->label, total);
    if (total <= 1) cli_info(p->common, "jnd pop: %s\n", stage);
  }
  if (total > 1) cli_progress_count(&p->count, done);
}

/* the asset form's own report parts: chain, motion, views, switch table */
static void asset_json(cJSON *inputs, cJSON *params, cJSON *res, const char *model, const jnd_pop_asset_params *ap,
                       const jnd_pop_asset_report *R, const cli_views *views, const double *speeds, int nspeeds) {
  cJSON_AddStringToObject(inputs, "model", model);
  cJSON *jl = cJSON_AddArrayToObject(inputs, "levels");
  for (int i = 0; i < ap->nlevel_paths; i++) cJSON_AddItemToArray(jl, cJSON_CreateString(ap->level_paths[i]));
  cJSON_AddItemToObject(params, "views", cli_views_json(views));
  cJSON *mo = cJSON_AddObjectToObject(params, "motion");
  cJSON_AddStringToObject(mo, "kind", motion_name(ap->motion.kind));
  cJSON_AddNumberToObject(mo, "speed", ap->motion.speed);
  cJSON_AddStringToObject(mo, "unit", ap->motion.kind == JND_POP_TRANSLATE ? "m/s" : "deg/s");
  if (ap->motion.kind == JND_POP_TRANSLATE) {
    cJSON *d = cJSON_AddArrayToObject(mo, "direction");
    for (int k = 0; k < 3; k++) cJSON_AddItemToArray(d, cJSON_CreateNumber(ap->motion.direction[k]));
  }
  cJSON_AddNumberToObject(mo, "unit_m", ap->motion.unit_m);
  cJSON_AddNumberToObject(params, "switch_level", ap->level);
  cJSON_AddNumberToObject(params, "frame", ap->frame);
  if (ap->decide) {
    cJSON *se = cJSON_AddObjectToObject(params, "search");
    cJSON *sj = cJSON_AddArrayToObject(se, "speeds_dps");
    for (int s = 0; s < nspeeds; s++) cJSON_AddItemToArray(sj, cJSON_CreateNumber(speeds[s]));
    cJSON_AddNumberToObject(se, "rating_limit", ap->search.rating_limit);
    cJSON_AddNumberToObject(se, "tolerance", ap->search.tolerance);
    cJSON_AddNumberToObject(se, "coverage_near", ap->search.coverage_near);
    cJSON_AddNumberToObject(se, "coverage_far", ap->search.coverage_far);
    cJSON_AddStringToObject(se, "pixel_rule", "level's error_abs covers 1 pixel of the image height at the distance");
  }
  cJSON_AddStringToObject(res, "renderer", R->renderer);
  cJSON_AddStringToObject(res, "chain_source", R->chain_source);
  cJSON *lv = cJSON_AddArrayToObject(res, "levels");
  for (int k = 0; k < R->nlevels; k++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", k);
    cJSON_AddNumberToObject(o, "triangles", (double)R->levels[k].triangles);
    add_num(o, "error_abs", R->levels[k].error_abs);
    cJSON_AddItemToArray(lv, o);
  }
  cJSON_AddNumberToObject(res, "views", R->nviews);
  cJSON_AddNumberToObject(res, "distance_m", R->pair_distance * ap->motion.unit_m);
  cJSON_AddStringToObject(res, "distance_unit", R->distance_unit); /* of every distance_m */
  if (!ap->decide) return;
  cJSON *sw = cJSON_AddArrayToObject(res, "switch");
  for (int i = 0; i < R->nrows; i++) {
    const jnd_pop_switch_row *w = &R->rows[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", w->level);
    cJSON_AddNumberToObject(o, "speed_dps", w->speed_dps);
    add_num(o, "distance_m", w->distance_m);
    add_num(o, "distance_m_pixel_rule", w->distance_m_pixel_rule);
    cJSON_AddStringToObject(o, "status", switch_status_name(w->sw.status));
    add_num(o, "max_rating", w->sw.max_rating);
    cJSON_AddNumberToObject(o, "evaluations", w->sw.evaluations);
    cJSON_AddItemToArray(sw, o);
  }
  cJSON_AddStringToObject(cJSON_GetObjectItem(res, "outputs"), "switch", "switch.png");
}

/* frame i's name from a --frames pattern (one %d or %0Nd field, %% a
 * percent sign); 0 for a pattern jnd_pop_sequence refuses anyway */
static int frame_name(const char *pattern, int i, char *out, size_t n) {
  size_t k = 0;
  int fields = 0;
  for (const char *c = pattern; *c && k + 16 < n; c++) {
    if (*c != '%') {
      out[k++] = *c;
      continue;
    }
    if (c[1] == '%') {
      out[k++] = '%';
      c++;
      continue;
    }
    int width = 0;
    const char *d = c + 1;
    if (*d == '0')
      while (*d >= '0' && *d <= '9') width = width * 10 + (*d++ - '0');
    if (*d != 'd' || width > 12 || fields++) return 0;
    k += (size_t)snprintf(out + k, n - k, "%0*d", width, i);
    c = d;
  }
  out[k] = 0;
  return fields == 1;
}

/* every file the frame form reads, frame by frame for a sequence */
static int pop_inputs(jnd_output *w, const jnd_pop_paths *f, int sequence, int first, int last) {
  const char *const pat[] = {f->actual, f->expected, f->displacement, f->displacement_expected, f->depth,
                             f->depth_expected, f->prev_depth, f->prev_depth_expected, f->weights, f->prev_color,
                             f->prev_shading, f->mask};
  int np = (int)(sizeof pat / sizeof pat[0]);
  if (!sequence) return cli_out_inputs(w, pat, np);
  for (int i = first; i <= last; i++)
    for (int k = 0; k < np; k++) {
      char name[4200];
      if (!pat[k] || !frame_name(pat[k], i, name, sizeof name)) continue;
      const char *one[] = {name};
      if (cli_out_inputs(w, one, 1) != EXIT_OK) return EXIT_BAD;
    }
  return EXIT_OK;
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  pop_progress prog = {&common, {0}, NULL, ""};
  jnd_model_params mp;
  jnd_model_defaults(&mp);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_paths f = {0};
  jnd_pop_sequence_params seq;
  jnd_pop_sequence_defaults(&seq);
  int sequence = 0;
  jnd_pop_asset_params ap;
  jnd_pop_asset_defaults(&ap);
  cli_views views;
  cli_views_init(&views, 512, 512);
  const char *paths[2] = {0}, *dir = NULL, *levels[64];
  double errors[64], speeds[64];
  int npaths = 0, maps = 0, max_regions = 100, asset_opts = 0, nlevels = 0, nspeeds = 0, nmotion = 0;
  double fail_above = NAN;
  cli_display disp;
  cli_display_init(&disp);
  cli_args args = cli_args_start(argc, argv, "pop"), *ca = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v, *a = argv[args.i];
    int was = args.i;
    if (cli_flag(ca, "--help") || cli_flag(ca, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_display_opt(ca, &disp)) {
    } else if (cli_views_opt(ca, &views)) {
      asset_opts++;
    } else if (cli_opt(ca, "--displacement-expected", &v)) {
      f.displacement_expected = v;
    } else if (cli_opt(ca, "--displacement", &v)) {
      f.displacement = v;
    } else if (cli_opt(ca, "--fps", &v)) {
      mp.fps = cli_double(ca, "--fps", v, 1, 1000);
    } else if (cli_opt(ca, "--weights", &v)) {
      f.weights = v;
    } else if (cli_opt(ca, "--depth-expected", &v)) {
      f.depth_expected = v;
    } else if (cli_opt(ca, "--depth", &v)) {
      f.depth = v;
    } else if (cli_opt(ca, "--prev-depth-expected", &v)) {
      f.prev_depth_expected = v;
    } else if (cli_opt(ca, "--prev-depth", &v)) {
      f.prev_depth = v;
    } else if (cli_opt(ca, "--prev-frame", &v)) {
      f.prev_color = v;
    } else if (cli_opt(ca, "--prev-shading", &v)) {
      f.prev_shading = v;
    } else if (cli_opt(ca, "--mask", &v)) {
      f.mask = v;
    } else if (cli_opt(ca, "--frames", &v)) {
      int fr[2] = {0, 0};
      int n = cli_int_list(ca, "--frames", v, 0, 1 << 30, fr, 2);
      if (!args.bad && (n != 2 || fr[1] < fr[0]))
        return cli_bad("pop: --frames: '%s' is not FIRST,LAST with 0 <= FIRST <= LAST", v);
      seq.first = fr[0];
      seq.last = fr[1];
      sequence = 1;
    } else if (cli_opt(ca, "--switch", &v)) {
      ap.level = cli_int(ca, "--switch", v, 0, 62);
      asset_opts++;
    } else if (cli_opt(ca, "--frame", &v)) {
      ap.frame = cli_int(ca, "--frame", v, -100000, 100000);
      asset_opts++;
    } else if (cli_opt(ca, "--orbit", &v) || cli_opt(ca, "--spin", &v) || cli_opt(ca, "--translate", &v) ||
               cli_opt(ca, "--pan", &v)) {
      const char *o = argv[was];
      ap.motion.kind = strncmp(o, "--translate", 11) == 0 ? JND_POP_TRANSLATE
                       : strncmp(o, "--spin", 6) == 0   ? JND_POP_OBJECT
                       : strncmp(o, "--pan", 5) == 0    ? JND_POP_PAN
                                                        : JND_POP_ORBIT;
      ap.motion.speed = cli_double(ca, (const char *[]){"--orbit", "--translate", "--spin", "--pan"}[ap.motion.kind], v, -100000, 100000);
      nmotion++;
      asset_opts++;
    } else if (cli_opt(ca, "--direction", &v)) {
      int n = cli_double_list(ca, "--direction", v, -1e6, 1e6, ap.motion.direction, 3);
      if (!ca->bad && (n != 3 || !(fabs(ap.motion.direction[0]) + fabs(ap.motion.direction[1]) +
                                       fabs(ap.motion.direction[2]) > 0)))
        return cli_bad("pop: --direction: '%s' is not X,Y,Z (not all 0)", v);
      asset_opts++;
    } else if (cli_opt(ca, "--unit-m", &v)) {
      ap.motion.unit_m = cli_double(ca, "--unit-m", v, 1e-9, 1e9);
      asset_opts++;
    } else if (cli_opt(ca, "--level", &v)) {
      if (nlevels >= 63) return cli_bad("pop: at most 63 --level files");
      levels[nlevels++] = v;
      asset_opts++;
    } else if (cli_opt(ca, "--errors", &v)) {
      int n = cli_errors(ca, v, errors, 63);
      ap.chain.errors = errors;
      ap.chain.nerrors = n;
      asset_opts++;
    } else if (cli_flag(ca, "--rebuild")) {
      ap.rebuild = 1;
      asset_opts++;
    } else if (cli_flag(ca, "--decide")) {
      ap.decide = 1;
      asset_opts++;
    } else if (cli_opt(ca, "--speeds", &v)) {
      nspeeds = cli_double_list(ca, "--speeds", v, -100000, 100000, speeds, 64);
      ap.decide = 1;
      asset_opts++;
    } else if (cli_opt(ca, "--tolerance", &v)) {
      ap.search.tolerance = cli_double(ca, "--tolerance", v, 1e-4, 10);
      asset_opts++;
    } else if (cli_opt(ca, "--coverage-range", &v)) {
      cli_pair(ca, "--coverage-range", v, &ap.search.coverage_near, &ap.search.coverage_far);
      if (!args.bad && !(ap.search.coverage_near <= 10 && ap.search.coverage_near > ap.search.coverage_far &&
                         ap.search.coverage_far >= 0.001))
        return cli_bad("pop: --coverage-range: '%s' is not N,F with 10 >= N > F >= 0.001", v);
      asset_opts++;
    } else if (cli_opt(ca, "-o", &v) || cli_opt(ca, "--output", &v)) {
      dir = v;
    } else if (cli_flag(ca, "--maps")) {
      maps = 1;
    } else if (cli_opt(ca, "--max-regions", &v)) {
      max_regions = cli_int(ca, "--max-regions", v, 0, 1 << 30);
    } else if (cli_opt(ca, "--fail-above", &v)) {
      fail_above = cli_double(ca, "--fail-above", v, -100, 100);
    } else if (cli_common_opt(ca, &common)) {
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ca);
    } else if (npaths < 2) {
      paths[npaths++] = a;
    } else {
      return cli_unknown(ca);
    }
  }
  if (args.bad) return EXIT_BAD;
  mp.display = cli_display_get(&disp);
  mp.threads = pp.threads = common.threads;
  int asset = npaths == 1;
  if (npaths != 1 && npaths != 2) return cli_bad("pop: needs two frames, NEW and EXPECTED, or a MODEL (jnd pop --help)");
  if (!dir) return cli_bad("pop: give an output folder with -o OUT (jnd pop --help)");
  if (asset && sequence) return cli_bad("pop: --frames is for frames you bring, jnd pop NEW EXPECTED");
  if (!asset && asset_opts) return cli_bad("pop: views, motion, chain and --decide options are for the asset form, jnd pop MODEL");
  if (asset && (f.displacement || f.displacement_expected || f.weights || f.depth || f.depth_expected ||
                f.prev_depth || f.prev_depth_expected || f.prev_color || f.prev_shading || f.mask))
    return cli_bad("pop: frame maps (--displacement, --depth, --weights, ...) are for the frame form; jnd pop MODEL "
                   "renders its own");
  if (nmotion > 1) return cli_bad("pop: give one of --orbit, --translate and --spin");
  if (ap.chain.errors && nlevels) return cli_bad("pop: give --errors or --level files, not both");
  double t0 = jnd_seconds();
  int rc = EXIT_BAD;
  jnd_model *model = NULL;
  cJSON *report = NULL;
  jnd_pop_result r = {0};
  jnd_pop_sequence_result Q;
  memset(&Q, 0, sizeof Q);
  jnd_pop_asset_report R;
  memset(&R, 0, sizeof R);
  const jnd_pop_result *res_pair = &r;
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *json_out = NULL, *final_dir = dir;
  if (!asset) {
    f.actual = paths[0];
    f.expected = paths[1];
  }
  const char *ains[66] = {asset ? paths[0] : NULL, views.set.render.env_path, views.cameras};
  for (int i = 0; i < nlevels; i++) ains[3 + i] = levels[i];
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ains, 3 + nlevels) != EXIT_OK ||
      (!asset && pop_inputs(outw, &f, sequence, seq.first, seq.last) != EXIT_OK) ||
      cli_out_dir(outw, final_dir, &dir) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    goto out;
  if (jnd_model_create(&mp, &model) != JND_OK) {
    cli_error("pop: %s", jnd_last_error());
    goto out;
  }
  if (asset) {
    ap.views = views.set;
    ap.cameras = views.cameras;
    ap.builtin_map_size = views.map_size;
    ap.level_paths = levels;
    ap.nlevel_paths = nlevels;
    ap.pop = pp;
    if (nspeeds) {
      ap.speeds = speeds;
      ap.nspeeds = nspeeds;
    }
    ap.chain.threads = common.threads;
    ap.progress = on_progress;
    ap.progress_user = &prog;
    if (jnd_pop_asset_run(model, paths[0], &ap, &R) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
    res_pair = &R.pair;
  } else if (sequence) {
    f.actual = paths[0];
    f.expected = paths[1];
    seq.progress = on_progress;
    seq.progress_user = &prog;
    if (jnd_pop_sequence(model, &f, &seq, &pp, &Q) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
    res_pair = &Q.worst_result;
  } else {
    f.actual = paths[0];
    f.expected = paths[1];
    if (jnd_pop_files(model, &f, &pp, &r) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  /* only now, with a result, is anything created */
  if (jnd_make_dirs(dir) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  double t_write = jnd_seconds();
  if (!write_image(dir, "regions.png", &res_pair->picture, 0)) goto out;
  if (maps && (!write_image(dir, "jnd.exr", &res_pair->jnd, 1) ||
               (res_pair->weights.data && !write_image(dir, "weights.exr", &res_pair->weights, 2))))
    goto out;
  if (asset && ap.decide && !write_image(dir, "switch.png", &R.plot, 0)) goto out;
  if (sequence && !frames_csv(dir, &Q)) goto out;
  int above = isfinite(fail_above) && res_pair->nregions && res_pair->max_rating > fail_above;

  report = cli_report_new("pop");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  if (!asset) {
    const char *in_keys[] = {"new", "expected", "displacement", "displacement_expected", "depth", "depth_expected",
                             "prev_depth", "prev_depth_expected", "weights", "prev_frame", "prev_shading", "mask"};
    const char *in_vals[] = {f.actual, f.expected, f.displacement, f.displacement_expected, f.depth,
                             f.depth_expected, f.prev_depth, f.prev_depth_expected, f.weights, f.prev_color,
                             f.prev_shading, f.mask};
    for (size_t k = 0; k < sizeof in_keys / sizeof in_keys[0]; k++)
      if (in_vals[k]) cJSON_AddStringToObject(inputs, in_keys[k], in_vals[k]);
    if (sequence) {
      cJSON *fr = cJSON_AddArrayToObject(inputs, "frames");
      cJSON_AddItemToArray(fr, cJSON_CreateNumber(seq.first));
      cJSON_AddItemToArray(fr, cJSON_CreateNumber(seq.last));
    }
  }
  params_json(params, &mp, &pp, fail_above);
  result_json(res, res_pair, max_regions);
  cJSON *outs = cJSON_AddObjectToObject(res, "outputs");
  cJSON_AddStringToObject(outs, "regions", "regions.png");
  if (sequence) {
    cJSON_AddStringToObject(outs, "frames", "frames.csv");
    frames_json(res, &Q);
  }
  if (maps) {
    cJSON_AddStringToObject(outs, "jnd", "jnd.exr");
    if (res_pair->weights.data) cJSON_AddStringToObject(outs, "weights", "weights.exr");
  }
  if (asset)
    asset_json(inputs, params, res, paths[0], &ap, &R, &views, ap.speeds ? ap.speeds : (const double[]){0, 30, 120},
               ap.speeds ? ap.nspeeds : 3);
  if (isfinite(fail_above)) cJSON_AddBoolToObject(res, "above_threshold", above);
  if (common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "read_s", res_pair->timings.read_s);
    cJSON_AddNumberToObject(t, "weights_s", res_pair->timings.weights_s);
    cJSON_AddNumberToObject(t, "model_s", res_pair->timings.model_s);
    cJSON_AddNumberToObject(t, "regions_s", res_pair->timings.regions_s);
    cJSON_AddNumberToObject(t, "picture_s", res_pair->timings.picture_s);
    if (asset) {
      cJSON_AddNumberToObject(t, "load_s", R.load_s);
      cJSON_AddNumberToObject(t, "render_s", R.render_s);
      cJSON_AddNumberToObject(t, "decide_s", R.decide_s);
    }
    cJSON_AddNumberToObject(t, "write_s", jnd_seconds() - t_write);
    cJSON_AddNumberToObject(t, "total_s", jnd_seconds() - t0);
  }
  char jpath[4400];
  snprintf(jpath, sizeof jpath, "%s/pop.json", dir);
  if (cli_report_write(report, jpath) != EXIT_OK) goto out;
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto out;
  if (sequence)
    cli_info(&common, "%d frames; frames.csv has each; the worst, frame %d:\n", Q.nrows, Q.rows[Q.worst].frame);
  if (res_pair->nregions)
    cli_info(&common, "%d popping region%s, max R %.2f; coverage %s, rating %s: detection score %d of 5; "
                      "max dE94 %.2f   %dx%d, %.2f s\n",
             res_pair->nregions, res_pair->nregions == 1 ? "" : "s", res_pair->max_rating,
             jnd_pop_coverage_name(res_pair->coverage_score), jnd_pop_rating_name(res_pair->rating_score),
             res_pair->detection_score, res_pair->max_delta_e94, res_pair->w, res_pair->h, jnd_seconds() - t0);
  else
    cli_info(&common, "no popping region (detection score 1 of 5); max dE94 %.2f   %dx%d, %.2f s\n",
             res_pair->max_delta_e94, res_pair->w, res_pair->h, jnd_seconds() - t0);
  for (int i = 0; i < R.nrows; i++)
    cli_info(&common, "  level %d at %g deg/s: switch from %.3g %s (max R %.2f); 1-pixel rule %.3g %s\n", R.rows[i].level,
             R.rows[i].speed_dps, R.rows[i].distance_m, R.distance_unit, R.rows[i].sw.max_rating,
             R.rows[i].distance_m_pixel_rule, R.distance_unit);
  if (above) cli_info(&common, "above --fail-above %g\n", fail_above);
  rc = above ? EXIT_ABOVE : EXIT_OK;
out:
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  jnd_pop_result_free(&r);
  jnd_pop_sequence_free(&Q);
  jnd_pop_asset_report_free(&R);
  jnd_model_free(model);
  return rc;
}

const jnd_command jnd_cmd_pop = {"pop", "will a level switch pop? popping regions, ratings and scores (004)", run};
