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
      "cd/m2 x --exr-scale). Maps (displacement, depth): OpenEXR. A switch is a change\n"
      "in place, so pop judges it in the flicker task whatever --task says.\n"
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

static int run(int argc, char **argv) {
  cli_common common = {0};
  pop_progress prog = {&common, {0}, NULL, ""};
  jnd_pop_run_params rp;
  jnd_pop_run_defaults(&rp);
  jnd_model_params *mp = &rp.model;
  jnd_pop_paths *f = &rp.frames;
  jnd_pop_asset_params *ap = &rp.asset;
  cli_views views;
  cli_views_init(&views, 512, 512);
  const char *paths[2] = {0}, *dir = NULL, *levels[64];
  double errors[64], speeds[64];
  int npaths = 0, asset_opts = 0, nlevels = 0, nspeeds = 0, nmotion = 0;
  cli_display disp;
  cli_display_init(&disp);
  cli_args args = cli_args_start(argc, argv, "pop"), *ca = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    int was = args.i;
    if (cli_help(ca)) {
      help();
      return EXIT_OK;
    } else if (cli_display_opt(ca, &disp)) {
    } else if (cli_views_opt(ca, &views)) {
      asset_opts++;
    } else if (cli_opt(ca, "--displacement-expected", &v)) {
      f->displacement_expected = v;
    } else if (cli_opt(ca, "--displacement", &v)) {
      f->displacement = v;
    } else if (cli_opt(ca, "--fps", &v)) {
      mp->fps = cli_double(ca, "--fps", v, 1, 1000);
    } else if (cli_opt(ca, "--weights", &v)) {
      f->weights = v;
    } else if (cli_opt(ca, "--depth-expected", &v)) {
      f->depth_expected = v;
    } else if (cli_opt(ca, "--depth", &v)) {
      f->depth = v;
    } else if (cli_opt(ca, "--prev-depth-expected", &v)) {
      f->prev_depth_expected = v;
    } else if (cli_opt(ca, "--prev-depth", &v)) {
      f->prev_depth = v;
    } else if (cli_opt(ca, "--prev-frame", &v)) {
      f->prev_color = v;
    } else if (cli_opt(ca, "--prev-shading", &v)) {
      f->prev_shading = v;
    } else if (cli_opt(ca, "--mask", &v)) {
      f->mask = v;
    } else if (cli_opt(ca, "--frames", &v)) {
      int fr[2] = {0, 0};
      int n = cli_int_list(ca, "--frames", v, 0, 1 << 30, fr, 2);
      if (!args.bad && (n != 2 || fr[1] < fr[0]))
        return cli_bad("pop: --frames: '%s' is not FIRST,LAST with 0 <= FIRST <= LAST", v);
      rp.seq.first = fr[0];
      rp.seq.last = fr[1];
      rp.sequence = 1;
    } else if (cli_opt(ca, "--switch", &v)) {
      ap->level = cli_int(ca, "--switch", v, 0, 62);
      asset_opts++;
    } else if (cli_opt(ca, "--frame", &v)) {
      ap->frame = cli_int(ca, "--frame", v, -100000, 100000);
      asset_opts++;
    } else if (cli_opt(ca, "--orbit", &v) || cli_opt(ca, "--spin", &v) || cli_opt(ca, "--translate", &v) ||
               cli_opt(ca, "--pan", &v)) {
      const char *o = argv[was];
      ap->motion.kind = strncmp(o, "--translate", 11) == 0 ? JND_POP_TRANSLATE
                       : strncmp(o, "--spin", 6) == 0   ? JND_POP_OBJECT
                       : strncmp(o, "--pan", 5) == 0    ? JND_POP_PAN
                                                        : JND_POP_ORBIT;
      ap->motion.speed = cli_double(ca, (const char *[]){"--orbit", "--translate", "--spin", "--pan"}[ap->motion.kind], v, -100000, 100000);
      nmotion++;
      asset_opts++;
    } else if (cli_opt(ca, "--direction", &v)) {
      int n = cli_double_list(ca, "--direction", v, -1e6, 1e6, ap->motion.direction, 3);
      if (!ca->bad && (n != 3 || !(fabs(ap->motion.direction[0]) + fabs(ap->motion.direction[1]) +
                                       fabs(ap->motion.direction[2]) > 0)))
        return cli_bad("pop: --direction: '%s' is not X,Y,Z (not all 0)", v);
      asset_opts++;
    } else if (cli_opt(ca, "--unit-m", &v)) {
      ap->motion.unit_m = cli_double(ca, "--unit-m", v, 1e-9, 1e9);
      asset_opts++;
    } else if (cli_opt(ca, "--level", &v)) {
      if (nlevels >= 63) return cli_bad("pop: at most 63 --level files");
      levels[nlevels++] = v;
      asset_opts++;
    } else if (cli_opt(ca, "--errors", &v)) {
      int n = cli_errors(ca, v, errors, 63);
      ap->chain.errors = errors;
      ap->chain.nerrors = n;
      asset_opts++;
    } else if (cli_flag(ca, "--rebuild")) {
      ap->rebuild = 1;
      asset_opts++;
    } else if (cli_flag(ca, "--decide")) {
      ap->decide = 1;
      asset_opts++;
    } else if (cli_opt(ca, "--speeds", &v)) {
      nspeeds = cli_double_list(ca, "--speeds", v, -100000, 100000, speeds, 64);
      ap->decide = 1;
      asset_opts++;
    } else if (cli_opt(ca, "--tolerance", &v)) {
      ap->search.tolerance = cli_double(ca, "--tolerance", v, 1e-4, 10);
      asset_opts++;
    } else if (cli_opt(ca, "--coverage-range", &v)) {
      cli_pair(ca, "--coverage-range", v, &ap->search.coverage_near, &ap->search.coverage_far);
      if (!args.bad && !(ap->search.coverage_near <= 10 && ap->search.coverage_near > ap->search.coverage_far &&
                         ap->search.coverage_far >= 0.001))
        return cli_bad("pop: --coverage-range: '%s' is not N,F with 10 >= N > F >= 0.001", v);
      asset_opts++;
    } else if (cli_opt(ca, "-o", &v) || cli_opt(ca, "--output", &v)) {
      dir = v;
    } else if (cli_flag(ca, "--maps")) {
      rp.maps = 1;
    } else if (cli_opt(ca, "--max-regions", &v)) {
      rp.max_regions = cli_int(ca, "--max-regions", v, 0, 1 << 30);
    } else if (cli_opt(ca, "--fail-above", &v)) {
      rp.fail_above = cli_double(ca, "--fail-above", v, -100, 100);
    } else if (cli_common_opt(ca, &common)) {
    } else if (!cli_operand(ca, paths, &npaths, 2)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  mp->display = cli_display_get(&disp);
  if (disp.task_given && disp.task != JND_TASK_FLICKER)
    cli_info(&common, "jnd pop: a level switch is a change in place: judged in the flicker task, not --task %s\n",
             jnd_viewing_task_name(disp.task));
  mp->threads = rp.pop.threads = common.threads;
  int asset = npaths == 1;
  if (npaths != 1 && npaths != 2) return cli_bad("pop: needs two frames, NEW and EXPECTED, or a MODEL (jnd pop --help)");
  if (!dir) return cli_bad("pop: give an output folder with -o OUT (jnd pop --help)");
  if (asset && rp.sequence) return cli_bad("pop: --frames is for frames you bring, jnd pop NEW EXPECTED");
  if (!asset && asset_opts) return cli_bad("pop: views, motion, chain and --decide options are for the asset form, jnd pop MODEL");
  if (asset && (f->displacement || f->displacement_expected || f->weights || f->depth || f->depth_expected ||
                f->prev_depth || f->prev_depth_expected || f->prev_color || f->prev_shading || f->mask))
    return cli_bad("pop: frame maps (--displacement, --depth, --weights, ...) are for the frame form; jnd pop MODEL "
                   "renders its own");
  if (nmotion > 1) return cli_bad("pop: give one of --orbit, --translate and --spin");
  if (ap->chain.errors && nlevels) return cli_bad("pop: give --errors or --level files, not both");
  if (asset) {
    ap->views = views.set;
    ap->cameras = views.cameras;
    ap->builtin_map_size = views.map_size;
    ap->level_paths = levels;
    ap->nlevel_paths = nlevels;
    if (nspeeds) {
      ap->speeds = speeds;
      ap->nspeeds = nspeeds;
    }
    ap->chain.threads = common.threads;
  } else {
    f->actual = paths[0];
    f->expected = paths[1];
  }
  rp.progress = on_progress;
  rp.progress_user = &prog;
  cli_run_options(&rp.run, &common, views.map_size);
  jnd_pop_run_result *R = NULL;
  if (jnd_pop_run(asset ? paths[0] : NULL, &rp, dir, &R) != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  const jnd_pop_result *pair = R->pair;
  const jnd_pop_sequence_result *Q = &R->sequence;
  const jnd_pop_asset_report *A = &R->asset;
  if (rp.sequence)
    cli_info(&common, "%d frames; frames.csv has each; the worst, frame %d:\n", Q->nrows, Q->rows[Q->worst].frame);
  if (pair->nregions)
    cli_info(&common, "%d popping region%s, max R %.2f; coverage %s, rating %s: detection score %d of 5; "
                      "max dE94 %.2f   %dx%d, %.2f s\n",
             pair->nregions, pair->nregions == 1 ? "" : "s", pair->max_rating,
             jnd_pop_coverage_name(pair->coverage_score), jnd_pop_rating_name(pair->rating_score),
             pair->detection_score, pair->max_delta_e94, pair->w, pair->h, R->total_s);
  else
    cli_info(&common, "no popping region (detection score 1 of 5); max dE94 %.2f   %dx%d, %.2f s\n",
             pair->max_delta_e94, pair->w, pair->h, R->total_s);
  for (int i = 0; i < A->nrows; i++) {
    /* max R is -inf where the switch shows no popping region at all (JSON: null) */
    char rating[32];
    if (isfinite(A->rows[i].sw.max_rating)) snprintf(rating, sizeof rating, "max R %.2f", A->rows[i].sw.max_rating);
    else snprintf(rating, sizeof rating, "no popping region");
    cli_info(&common, "  level %d at %g deg/s: switch from %.3g %s (%s); 1-pixel rule %.3g %s\n", A->rows[i].level,
             A->rows[i].speed_dps, A->rows[i].distance_m, A->distance_unit, rating, A->rows[i].distance_m_pixel_rule,
             A->distance_unit);
  }
  if (R->above) cli_info(&common, "above --fail-above %g\n", rp.fail_above);
  if (rc == EXIT_OK && R->above) rc = EXIT_ABOVE;
  jnd_pop_run_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_pop = {"pop", "will a level switch pop? popping regions, ratings and scores (004)", run};
