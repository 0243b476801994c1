/* jnd lod MODEL -o OUTDIR — a level-of-detail chain and the Point of
 * Imperceptibility of each target screen (Wu, Agu & Lindsay 2007, 003). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"

/* JND_VIEWS_MAX as text, for the help */
#define TEXT_OF(x) #x
#define TEXT(x) TEXT_OF(x)
#define MAX_VIEWS_TEXT TEXT(JND_VIEWS_MAX)

static void help(void) {
  printf(
      "usage: jnd lod MODEL -o OUTDIR [options]\n"
      "\n"
      "Makes a chain of levels of detail of MODEL (glTF 2.0 .gltf/.glb, OBJ, or `builtin`)\n"
      "with meshoptimizer, to a list of error targets, keeping uv seams; or takes the chain\n"
      "the file has (glTF MSFT_lod) or the files given with --level. Then, for every target\n"
      "screen, finds the Point of Imperceptibility of Wu, Agu & Lindsay (2007, 003): every\n"
      "level is rendered unlit and lit on a large virtual screen, minified to the screen, and\n"
      "its error (object-space distance + screen-space E_p, eq. 1; times the CSF-weighted\n"
      "wavelet term M_p when lit, eq. 3) is plotted against its triangles; the knee of each\n"
      "curve is the PoI. Beside it: meshoptimizer's error-to-pixels rule and a fixed\n"
      "pixel-error rule. The same for each texture map over its mip chain (003 §4.3).\n"
      "Writes OUTDIR/lod.json, OUTDIR/model/NAME.glb (every level, MSFT_lod with\n"
      "MSFT_screencoverage) and OUTDIR/pareto_SCREEN.png; the input is never touched.\n"
      "Beyond 003, per screen: the perceptual choice, the coarsest level jnd's vision model\n"
      "finds no more visible than 000's criterion allows (at most a fraction q of the views\n"
      "with P > p) against level 0 at the viewing condition (--coverage or --distance), and\n"
      "each level's switch distance (from which camera distance it may be shown), found by\n"
      "bisection on a log scale; the model's MSFT_screencoverage then comes from the first\n"
      "screen's switch distances; screens are judged in parallel, one per --threads.\n"
      "See docs/lod.md.\n"
      "\n"
      "chain:\n"
      "  --errors LIST       error targets relative to the model's extent, rising, each in\n"
      "                      [1e-6, 1], numbers or fractions (default 1/4096,1/2048,...,1/16)\n"
      "  --ratios LIST       triangle ratios instead, descending, e.g. 0.5,0.25,0.1\n"
      "  --level FILE        a level from another file, finest first (repeatable): the chain\n"
      "                      is MODEL and these, matched by material name\n"
      "  --rebuild           make a chain even when MODEL has MSFT_lod levels\n"
      "  --lock-border       never move open borders (default: when there are several meshes)\n"
      "  --no-lock-border    move them where the topology allows\n"
      "  --no-sloppy         never fall back to meshopt_simplifySloppy\n"
      "  --chain-only        the chain and the model only, no analysis\n"
      "\n"
      "screens and views (003):\n"
      "  --screens LIST      target screens: display presets (standard-fhd, standard-4k,\n"
      "                      phone, laptop) or WxH or WxH@PPD (default the four presets)\n"
      "  --coverage F        fraction of each screen's height the object fills (0.5)\n"
      "  --views N           views around the object, averaged (2; 1.." MAX_VIEWS_TEXT ")\n"
      "  --seed S            view and light sampling seed (1)\n"
      "  --fov DEG           vertical field of view (45)\n"
      "  --lights N          directional lights of the lit renderings (1)\n"
      "  --env FILE          environment of the lit renderings (.hdr/.exr; default the studio)\n"
      "  --virtual-scale F   the virtual screen shows the object F times larger than the\n"
      "                      largest target screen (1.5)\n"
      "  --max-virtual N     ... and has at most N pixels a side (4096)\n"
      "  --surface-samples N points on the surface for the object-space term (65536)\n"
      "  --meshopt-pixels PX meshoptimizer's rule: error at most PX pixels (1)\n"
      "  --pixel-error PX    the fixed pixel-error rule: measured deviation at most PX (0.5)\n"
      "  --no-textures       skip the texture maps' mip chains\n"
      "  --anisotropy N      renderer anisotropy of the virtual screen (4)\n"
      "  --platform P        EGL platform: auto, device, surfaceless\n"
      "  --map-size N        side of the builtin asset's maps (512)\n"
      "\n"
      "the perceptual choice and switch distances (through the judge, docs/judge.md):\n"
      "  --distance D        the viewing condition as a camera distance (object units, metres in\n"
      "                      glTF) instead of --coverage\n"
      "  --judge-views N     views per distance (4; 1.." MAX_VIEWS_TEXT "), sampled with --seed, --fov, --lights\n"
      "  --p P, --q Q        the criterion: at most a fraction Q of the views with P > P (0.2, 0.1)\n"
      "  --far-coverage F    the farthest distance searched: the sphere fills F of the screen's\n"
      "                      height (0.02)\n"
      "  --tolerance T       ratio between neighbouring distances of the search, minus 1 (0.1)\n"
      "  --max-px N          largest rendering side (512): a larger object is judged on the\n"
      "                      screen scaled down until it fits (fewer pixels per degree)\n"
      "  --samples N         MSAA samples of the judge's renderings (4)\n"
      "  --no-pop            switch distances from the criterion only; by default level K is\n"
      "                      also not shown nearer than where the switch from level K - 1 stops\n"
      "                      popping (004: largest rating R over the views < 1, jnd pop), a\n"
      "                      switch in place, so always judged in the flicker task\n"
      "  --pop-speed DPS     the motion under which that switch is seen: an orbit at DPS\n"
      "                      degrees per second (0: a static viewer, the default)\n"
      "  --pop-motion M      orbit (default), spin (the object turns) or pan (the camera turns)\n"
      "  --no-perceptual     003's analysis and the rules only\n"
      CLI_TASK_HELP
      "\n"
      "outputs:\n"
      "  -o, --output DIR    the folder (created): lod.json, model/, pareto_*.png\n"
      "%s"
      "\n"
      "Exit status: 0; 2 for bad input (one line: jnd: FILE: problem), nothing written.\n",
      cli_common_help);
}

typedef struct {
  const cli_common *common;
  cli_progress bar;
  const char *stage;
  double t0;
} progress_state;

/* a bar on a terminal; elsewhere one line per stage */
static void on_progress(void *user, const char *stage, int done, int total) {
  progress_state *p = user;
  if (p->common->quiet) return;
  if (!p->stage || strcmp(p->stage, stage) != 0) {
    if (p->stage) cli_progress_end(&p->bar);
    p->stage = stage;
    cli_progress_start(&p->bar, p->common, stage, total);
    if (!isatty(2)) fprintf(stderr, "jnd lod: %s (%d steps) at %.1f s\n", stage, total, jnd_seconds() - p->t0);
  }
  p->bar.total = total;
  cli_progress_step(&p->bar, done);
}

/* the human summary: the chain, per screen the choices, the switch distances and the memory */
static void summary(const cli_common *common, const char *model, const jnd_lod_result *R) {
  const jnd_scene *scene = R->scene;
  int n = jnd_scene_lod_count(scene);
  cli_info(common, "jnd lod: %s, %d levels (%s):", model, n, R->chain_source);
  for (int k = 0; k < n; k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(scene, k, &li);
    cli_info(common, " %zu%s", li.triangles, li.method == JND_LOD_SLOPPY ? "*" : "");
  }
  cli_info(common, " triangles\n");
  for (int k = 1; k < n; k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(scene, k, &li);
    if (li.method == JND_LOD_SLOPPY)
      cli_info(common, "jnd lod: level %d: %d mesh(es) made by meshopt_simplifySloppy (seams not kept)\n", k,
               li.sloppy_meshes);
  }
  const jnd_poi_result *P = R->analysed ? &R->poi : NULL;
  if (P) {
    cli_info(common, "%-16s %12s %12s %12s %12s %12s\n", "screen", "perceptual", "003 PoI lit", "PoI unlit",
             "meshopt rule", "pixel rule");
    for (int i = 0; i < P->nscreens; i++) {
      const jnd_poi_screen_result *S = &P->screens[i];
      char perc[32] = "-";
      if (i < R->nsw) snprintf(perc, sizeof perc, "%zu", P->levels[R->sw[i].perceptual_level].triangles);
      cli_info(common, "%-16s %12s %12zu %12zu %12zu %12zu\n", S->screen.name, perc, P->levels[S->poi_level].triangles,
               P->levels[S->poi_level_unlit].triangles, P->levels[S->meshopt_level].triangles,
               P->levels[S->pixel_level].triangles);
    }
    /* per level: the switch distance, and its criterion and popping components */
    for (int i = 0; i < R->nsw; i++) {
      const jnd_lod_switch_result *W = &R->sw[i];
      cli_info(common, "%-16s switch distances (criterion, popping):", W->screen.name);
      for (int k = 1; k < W->nlevels; k++) {
        char a[3][24];
        const double d[3] = {W->switch_distance[k], W->switch_distance_criterion[k], W->switch_distance_pop[k]};
        for (int c = 0; c < 3; c++) {
          if (isnan(d[c])) snprintf(a[c], sizeof a[c], "-");
          else if (isinf(d[c])) snprintf(a[c], sizeof a[c], "never");
          else snprintf(a[c], sizeof a[c], "%.3g", d[c]);
        }
        cli_info(common, " %d: %s (%s, %s)", k, a[0], a[1], a[2]);
      }
      cli_info(common, "\n");
    }
  }
  if (R->nsw > 0)
    cli_info(common, "memory (vertices and indices as written): level 0 %.3f MiB, level %d (%s) %.3f MiB\n",
             R->memory_before_bytes / 1048576.0, R->sw[0].perceptual_level, R->sw[0].screen.name,
             R->memory_after_bytes / 1048576.0);
}

static int run(int argc, char **argv) {
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  jnd_lod_run_params p;
  jnd_lod_run_defaults(&p);
  double errors[64], ratios[64];
  const char *levels[64];
  int nlevels = 0;
  jnd_poi_screen screens[16];
  cli_views vo;   /* lod's defaults, read back after parsing */
  cli_views_init(&vo, 0, 0);
  vo.set.sampling.count = p.poi.views;
  vo.set.sampling.seed = p.poi.seed;
  vo.set.sampling.coverage = p.poi.coverage;
  vo.set.sampling.distance = p.sw.distance;
  vo.set.sampling.fov_y_deg = p.poi.fov_y_deg;
  vo.set.sampling.lights = p.poi.lights;
  vo.set.render.env_path = p.poi.env_path;
  vo.set.render.anisotropy = p.poi.anisotropy;
  vo.set.render.platform = p.poi.platform;
  vo.set.render.samples = p.sw.judge.views.render.samples;
  vo.map_size = p.run.map_size;
  cli_args args = cli_args_start(argc, argv, "lod"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--errors", &v)) {
      p.chain.nerrors = cli_errors(ap, v, errors, 63);
      p.chain.errors = errors;
    } else if (cli_opt(ap, "--ratios", &v)) {
      p.chain.nratios = cli_double_list(ap, "--ratios", v, 0, 1, ratios, 63);   /* the library: falling in [0, 1) */
      p.chain.ratios = ratios;
    } else if (cli_opt(ap, "--level", &v)) {
      if (nlevels >= 63) return cli_bad("lod: at most 63 --level files");
      levels[nlevels++] = v;
    } else if (cli_flag(ap, "--rebuild")) {
      p.rebuild = 1;
    } else if (cli_flag(ap, "--lock-border")) {
      p.chain.lock_border = 1;
    } else if (cli_flag(ap, "--no-lock-border")) {
      p.chain.lock_border = 0;
    } else if (cli_flag(ap, "--no-sloppy")) {
      p.chain.allow_sloppy = 0;
    } else if (cli_flag(ap, "--chain-only")) {
      p.analyse = 0;
    } else if (cli_opt(ap, "--screens", &v)) {
      char buf[1024];
      snprintf(buf, sizeof buf, "%s", v);
      p.poi.nscreens = 0;
      for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (p.poi.nscreens >= 16) return cli_bad("lod: --screens: at most 16 screens");
        if (jnd_poi_screen_parse(tok, &screens[p.poi.nscreens]) != JND_OK) return cli_bad("lod: --screens: %s", jnd_last_error());
        p.poi.nscreens++;
      }
      if (p.poi.nscreens == 0) return cli_bad("lod: --screens: '%s' names no screen", v);
      p.poi.screens = screens;
    } else if (cli_opt(ap, "--virtual-scale", &v)) {
      p.poi.virtual_scale = cli_double(ap, "--virtual-scale", v, 1, 16);
    } else if (cli_opt(ap, "--max-virtual", &v)) {
      p.poi.max_virtual_px = cli_int(ap, "--max-virtual", v, 64, 16384);
    } else if (cli_opt(ap, "--surface-samples", &v)) {
      p.poi.surface_samples = cli_int(ap, "--surface-samples", v, 16, 1 << 24);
    } else if (cli_opt(ap, "--meshopt-pixels", &v)) {
      p.poi.meshopt_pixels = cli_double(ap, "--meshopt-pixels", v, 1e-3, 1e3);
    } else if (cli_opt(ap, "--pixel-error", &v)) {
      p.poi.pixel_error = cli_double(ap, "--pixel-error", v, 1e-3, 1e3);
    } else if (cli_flag(ap, "--no-textures")) {
      p.poi.textures = 0;
    } else if (cli_opt(ap, "--judge-views", &v)) {
      p.sw.judge.views.sampling.count = cli_int(ap, "--judge-views", v, 1, JND_VIEWS_MAX);
    } else if (cli_criterion_opt(ap, &p.sw.judge.criterion)) {
    } else if (cli_task_opt(ap, &p.sw.judge.model.display.task)) {   /* each screen's judge keeps it */
    } else if (cli_opt(ap, "--far-coverage", &v)) {
      p.sw.far_coverage = cli_double(ap, "--far-coverage", v, 1e-4, 1);
    } else if (cli_opt(ap, "--tolerance", &v)) {
      p.sw.tolerance = cli_double(ap, "--tolerance", v, 0.001, 10);
    } else if (cli_opt(ap, "--max-px", &v)) {
      p.sw.max_px = cli_int(ap, "--max-px", v, 32, 8192);
    } else if (cli_flag(ap, "--no-pop")) {
      p.sw.pop = 0;
    } else if (cli_opt(ap, "--pop-speed", &v)) {
      p.sw.pop_speed = cli_double(ap, "--pop-speed", v, -100000, 100000);
    } else if (cli_opt(ap, "--pop-motion", &v)) {
      if (strcmp(v, "orbit") == 0) p.sw.pop_motion = JND_POP_ORBIT;
      else if (strcmp(v, "spin") == 0) p.sw.pop_motion = JND_POP_OBJECT;
      else if (strcmp(v, "pan") == 0) p.sw.pop_motion = JND_POP_PAN;
      else return cli_bad("lod: --pop-motion: '%s' is not orbit, spin or pan", v);
    } else if (cli_flag(ap, "--no-perceptual")) {
      p.perceptual = 0;
    } else if (cli_views_opt(ap, &vo) || cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &model, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  /* the shared view options, where lod has a use for them */
  if (cli_views_only(&vo, CLI_VIEWS | CLI_SEED | CLI_COVERAGE | CLI_DISTANCE | CLI_FOV | CLI_LIGHTS | CLI_ENV |
                              CLI_SAMPLES | CLI_ANISOTROPY | CLI_PLATFORM | CLI_MAP_SIZE,
                     "lod", "its views are rendered at each screen's size around the object; see jnd lod --help"))
    return EXIT_BAD;
  p.poi.views = vo.set.sampling.count;
  p.poi.seed = vo.set.sampling.seed;
  p.poi.coverage = vo.set.sampling.coverage;
  p.poi.fov_y_deg = vo.set.sampling.fov_y_deg;
  p.poi.lights = vo.set.sampling.lights;
  p.poi.env_path = vo.set.render.env_path;
  p.poi.anisotropy = vo.set.render.anisotropy;
  p.poi.platform = vo.set.render.platform;
  p.sw.distance = vo.set.sampling.distance;
  p.sw.judge.views.render.samples = vo.set.render.samples;
  p.chain.threads = common.threads;
  p.threads = common.threads;
  if (!model) return cli_bad("lod: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd lod --help");
  if (!dir) return cli_bad("lod: give an output folder with -o OUTDIR; jnd lod --help");
  if (p.chain.errors && p.chain.ratios) return cli_bad("lod: give --errors or --ratios, not both");
  p.level_paths = levels;
  p.nlevel_paths = nlevels;
  cli_run_options(&p.run, &common, vo.map_size);
  progress_state ps = {&common, {0}, NULL, jnd_seconds()};
  p.progress = on_progress;
  p.progress_user = &ps;
  jnd_lod_result *R = NULL;
  jnd_status st = jnd_lod_run(model, &p, dir, &R);
  if (ps.stage) cli_progress_end(&ps.bar);
  if (st != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  if (rc == EXIT_OK) {
    summary(&common, model, R);
    cli_info(&common, "wrote %s/lod.json and %s\n", dir, R->model_path);
  }
  jnd_lod_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_lod = {"lod", "LOD chain and 003's Point of Imperceptibility per screen", run};
