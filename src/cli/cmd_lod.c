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
      "                      popping (004: largest rating R over the views < 1, jnd pop)\n"
      "  --pop-speed DPS     the motion under which that switch is seen: an orbit at DPS\n"
      "                      degrees per second (0: a static viewer, the default)\n"
      "  --pop-motion M      orbit (default), spin (the object turns) or pan (the camera turns)\n"
      "  --no-perceptual     003's analysis and the rules only\n"
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

static const char *method_name(jnd_lod_method m) {
  switch (m) {
  case JND_LOD_INPUT: return "input";
  case JND_LOD_SIMPLIFIED: return "simplified";
  case JND_LOD_SLOPPY: return "sloppy";
  default: return "imported";
  }
}

static cJSON *num_or_null(double v) { return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull(); }

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
  vo.map_size = p.builtin_map_size;
  cli_args args = cli_args_start(argc, argv, "lod"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
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
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (!model) {
      model = a;
    } else {
      return cli_unknown(ap);
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
  p.builtin_map_size = vo.map_size;
  p.chain.threads = common.threads;
  p.threads = common.threads;
  if (!model) return cli_bad("lod: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd lod --help");
  if (!dir) return cli_bad("lod: give an output folder with -o OUTDIR; jnd lod --help");
  if (p.chain.errors && p.chain.ratios) return cli_bad("lod: give --errors or --ratios, not both");
  p.level_paths = levels;
  p.nlevel_paths = nlevels;
  /* the outputs checked before the analysis, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *ins[64 + 2] = {model, p.poi.env_path}, *final_dir = dir, *json_out = common.json_path;
  for (int i = 0; i < nlevels; i++) ins[2 + i] = levels[i];
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 2 + nlevels) != EXIT_OK ||
      cli_out_dir(outw, final_dir, &dir) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    return cli_out_end(outw, EXIT_BAD);
  p.out_dir = dir;
  progress_state ps = {&common, {0}, NULL, jnd_seconds()};
  p.progress = on_progress;
  p.progress_user = &ps;

  jnd_lod_report R;
  jnd_status st = jnd_lod_run(model, &p, &R);
  if (ps.stage) cli_progress_end(&ps.bar);
  if (st != JND_OK) return cli_out_end(outw, cli_bad("%s", jnd_last_error()));
  jnd_scene *scene = R.scene;
  for (int i = 0; i < jnd_scene_warning_count(scene); i++) cli_info(&common, "jnd: warning: %s\n", jnd_scene_warning(scene, i));
  /* memory before and after: level 0 and the first screen's perceptual choice */
  size_t mem_before = 0, mem_after = 0;
  if (R.nsw > 0 && (jnd_scene_lod_bytes(scene, 0, &mem_before) != JND_OK ||
                    jnd_scene_lod_bytes(scene, R.sw[0].perceptual_level, &mem_after) != JND_OK)) {
    cli_error("%s", jnd_last_error());
    jnd_lod_report_free(&R);
    return cli_out_end(outw, EXIT_BAD);
  }

  cJSON *report = cli_report_new("lod");
  cJSON *in = cli_report_section(report, "inputs"), *par = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  cJSON *jl = cJSON_AddArrayToObject(in, "levels");
  for (int i = 0; i < nlevels; i++) cJSON_AddItemToArray(jl, cJSON_CreateString(levels[i]));
  cJSON *jc = cJSON_AddObjectToObject(par, "chain");
  cJSON *je = cJSON_AddArrayToObject(jc, p.chain.ratios ? "ratios" : "errors");
  for (int k = 0; k < (p.chain.ratios ? p.chain.nratios : p.chain.errors ? p.chain.nerrors : 9); k++)
    cJSON_AddItemToArray(je, cJSON_CreateNumber(p.chain.ratios ? ratios[k] : p.chain.errors ? errors[k] : ldexp(1, k - 12)));
  cJSON_AddNumberToObject(jc, "lock_border", p.chain.lock_border);
  cJSON_AddBoolToObject(jc, "allow_sloppy", p.chain.allow_sloppy);
  cJSON_AddBoolToObject(jc, "rebuild", p.rebuild);
  cJSON_AddBoolToObject(par, "analyse", p.analyse);
  cJSON_AddNumberToObject(par, "views", p.poi.views);
  cJSON_AddNumberToObject(par, "seed", (double)p.poi.seed);
  cJSON_AddNumberToObject(par, "coverage", p.poi.coverage);
  cJSON_AddNumberToObject(par, "fov_y_deg", p.poi.fov_y_deg);
  cJSON_AddNumberToObject(par, "lights", p.poi.lights);
  cJSON_AddNumberToObject(par, "virtual_scale", p.poi.virtual_scale);
  cJSON_AddNumberToObject(par, "max_virtual_px", p.poi.max_virtual_px);
  cJSON_AddNumberToObject(par, "surface_samples", p.poi.surface_samples);
  cJSON_AddNumberToObject(par, "meshopt_pixels", p.poi.meshopt_pixels);
  cJSON_AddNumberToObject(par, "pixel_error", p.poi.pixel_error);
  cJSON_AddBoolToObject(par, "textures", p.poi.textures);
  cJSON *jpc = cJSON_AddObjectToObject(par, "perceptual");
  cJSON_AddBoolToObject(jpc, "enabled", p.perceptual && p.analyse);
  cJSON_AddItemToObject(jpc, "distance", p.sw.distance > 0 ? cJSON_CreateNumber(p.sw.distance) : cJSON_CreateNull());
  cJSON_AddNumberToObject(jpc, "views", p.sw.judge.views.sampling.count);
  cJSON_AddItemToObject(jpc, "criterion", cli_criterion_json(&p.sw.judge.criterion, NULL));
  cJSON_AddNumberToObject(jpc, "far_coverage", p.sw.far_coverage);
  cJSON_AddNumberToObject(jpc, "tolerance", p.sw.tolerance);
  cJSON_AddNumberToObject(jpc, "max_px", p.sw.max_px);
  cJSON_AddNumberToObject(jpc, "samples", p.sw.judge.views.render.samples);
  cJSON *jpop = cJSON_AddObjectToObject(jpc, "pop");
  cJSON_AddBoolToObject(jpop, "enabled", p.sw.pop);
  cJSON_AddStringToObject(jpop, "motion", p.sw.pop_motion == JND_POP_OBJECT ? "spin" : p.sw.pop_motion == JND_POP_PAN ? "pan" : "orbit");
  cJSON_AddNumberToObject(jpop, "speed_dps", p.sw.pop_speed);
  cJSON_AddNumberToObject(jpop, "rating_limit", p.sw.pop_rating_limit);

  cJSON_AddStringToObject(res, "chain_source", R.chain_source);
  int n = jnd_scene_lod_count(scene);
  const jnd_poi_result *P = R.analysed ? &R.poi : NULL;
  cJSON *jlev = cJSON_AddArrayToObject(res, "levels");
  for (int k = 0; k < n; k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(scene, k, &li);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", k);
    cJSON_AddNumberToObject(o, "triangles", (double)li.triangles);
    cJSON_AddItemToObject(o, "error", num_or_null(li.error));
    cJSON_AddNumberToObject(o, "vertices", (double)li.vertices);
    cJSON_AddItemToObject(o, "error_abs", num_or_null(li.error_abs));
    cJSON_AddItemToObject(o, "target_error", num_or_null(k ? li.target_error : NAN));
    cJSON_AddItemToObject(o, "target_ratio", num_or_null(li.target_ratio));
    cJSON_AddStringToObject(o, "method", method_name(li.method));
    cJSON_AddNumberToObject(o, "sloppy_meshes", li.sloppy_meshes);
    if (li.source[0]) cJSON_AddStringToObject(o, "source", li.source);
    if (P) {
      cJSON_AddNumberToObject(o, "distance_rms", P->distance[k].rms / P->extent);
      cJSON_AddNumberToObject(o, "distance_max", P->distance[k].max / P->extent);
    }
    cJSON_AddItemToArray(jlev, o);
  }
  if (P) {
    cJSON_AddNumberToObject(res, "extent", P->extent);
    cJSON_AddNumberToObject(res, "radius", P->radius);
    cJSON_AddNumberToObject(res, "virtual_px", P->virtual_px);
    cJSON_AddNumberToObject(res, "renderings", P->renderings);
    cJSON_AddStringToObject(res, "renderer", P->renderer);
    cJSON *js = cJSON_AddArrayToObject(res, "screens");
    for (int i = 0; i < P->nscreens; i++) {
      const jnd_poi_screen_result *S = &P->screens[i];
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "name", S->screen.name);
      cJSON_AddNumberToObject(o, "width_px", S->screen.width_px);
      cJSON_AddNumberToObject(o, "height_px", S->screen.height_px);
      cJSON_AddNumberToObject(o, "ppd", S->screen.ppd);
      cJSON_AddNumberToObject(o, "object_px", S->object_px);
      cJSON_AddNumberToObject(o, "m2_px", S->m2_px);
      cJSON *cv = cJSON_AddArrayToObject(o, "curve");
      for (int k = 0; k < S->nlevels; k++) {
        const jnd_poi_point *q = &S->curve[k];
        cJSON *c = cJSON_CreateObject();
        cJSON_AddNumberToObject(c, "level", k);
        cJSON_AddNumberToObject(c, "error", q->error);
        cJSON_AddNumberToObject(c, "error_lit", q->error_lit);
        cJSON_AddNumberToObject(c, "object", q->object);
        cJSON_AddNumberToObject(c, "e_p", q->e_p);
        cJSON_AddNumberToObject(c, "m_p", q->m_p);
        cJSON_AddNumberToObject(c, "meshopt_px", q->meshopt_px);
        cJSON_AddNumberToObject(c, "deviation_px", q->deviation_px);
        cJSON_AddItemToArray(cv, c);
      }
      cJSON_AddNumberToObject(o, "poi_level", S->poi_level);
      cJSON_AddNumberToObject(o, "poi_triangles", (double)P->levels[S->poi_level].triangles);
      cJSON_AddNumberToObject(o, "poi_level_unlit", S->poi_level_unlit);
      cJSON_AddNumberToObject(o, "poi_triangles_unlit", (double)P->levels[S->poi_level_unlit].triangles);
      cJSON *rules = cJSON_AddObjectToObject(o, "rules");
      cJSON *rm = cJSON_AddObjectToObject(rules, "meshopt"), *rp = cJSON_AddObjectToObject(rules, "pixel_error");
      cJSON_AddNumberToObject(rm, "pixels", p.poi.meshopt_pixels);
      cJSON_AddNumberToObject(rm, "level", S->meshopt_level);
      cJSON_AddNumberToObject(rm, "triangles", (double)P->levels[S->meshopt_level].triangles);
      cJSON_AddNumberToObject(rp, "pixels", p.poi.pixel_error);
      cJSON_AddNumberToObject(rp, "level", S->pixel_level);
      cJSON_AddNumberToObject(rp, "triangles", (double)P->levels[S->pixel_level].triangles);
      if (i < R.nsw) {
        const jnd_lod_switch_result *W = &R.sw[i];
        cJSON_AddNumberToObject(o, "perceptual_level", W->perceptual_level);
        cJSON_AddNumberToObject(o, "perceptual_triangles", (double)P->levels[W->perceptual_level].triangles);
        cJSON_AddNumberToObject(o, "perceptual_statistic", W->statistic[W->perceptual_level]);
        /* never (INFINITY) is null */
        cJSON *sd = cJSON_AddArrayToObject(o, "switch_distance_m"), *sc = cJSON_AddArrayToObject(o, "switch_coverage");
        cJSON *jst = cJSON_AddArrayToObject(o, "statistic"), *pm = cJSON_AddArrayToObject(o, "p_max");
        /* its components: the criterion (a), popping (b; null where never or not searched) and what decided */
        cJSON *sda = cJSON_AddArrayToObject(o, "switch_distance_criterion_m"),
              *sdb = cJSON_AddArrayToObject(o, "switch_distance_pop_m"), *sby = cJSON_AddArrayToObject(o, "switch_by"),
              *jpr = cJSON_AddArrayToObject(o, "pop");
        /* the screen's scale each level was judged at at its criterion distance (1: the screen's own) */
        cJSON *ssc = cJSON_AddArrayToObject(o, "switch_scale");
        for (int k = 0; k < W->nlevels; k++) {
          cJSON_AddItemToArray(sda, num_or_null(W->switch_distance_criterion[k]));
          cJSON_AddItemToArray(ssc, num_or_null(W->switch_scale[k]));
          cJSON_AddItemToArray(sdb, num_or_null(W->switch_distance_pop[k]));
          cJSON_AddItemToArray(sby, cJSON_CreateString(jnd_lod_switch_by_name(W->switch_by[k])));
          if (k == 0) continue;
          int searched = !isnan(W->switch_distance_pop[k]);
          cJSON *r = cJSON_CreateObject();
          cJSON_AddNumberToObject(r, "level", k);
          cJSON_AddBoolToObject(r, "searched", searched);
          cJSON_AddBoolToObject(r, "never", searched && isinf(W->switch_distance_pop[k]));
          cJSON_AddItemToObject(r, "distance_m", num_or_null(W->switch_distance_pop[k]));
          /* the largest R there; null: not searched or no popping region */
          cJSON_AddItemToObject(r, "max_rating", num_or_null(W->pop_max_rating[k]));
          cJSON_AddItemToArray(jpr, r);
        }
        cJSON_AddNumberToObject(o, "pop_evaluations", W->pop_evaluations);
        for (int k = 0; k < W->nlevels; k++) {
          cJSON_AddItemToArray(sd, num_or_null(W->switch_distance[k]));
          cJSON_AddItemToArray(sc, cJSON_CreateNumber(W->switch_coverage[k]));
          cJSON_AddItemToArray(jst, num_or_null(W->statistic[k]));
          cJSON_AddItemToArray(pm, num_or_null(W->p_max[k]));
        }
        cJSON *vc = cJSON_AddObjectToObject(o, "viewing_condition");
        cJSON_AddNumberToObject(vc, "distance", W->view_distance);
        cJSON_AddNumberToObject(vc, "coverage", W->view_coverage);
        cJSON_AddNumberToObject(vc, "window_px", W->window_px);
        cJSON_AddNumberToObject(vc, "scale", W->scale);
        cJSON *jw = cJSON_AddObjectToObject(o, "judge");
        cJSON_AddNumberToObject(jw, "distances", W->distances);
        cJSON_AddNumberToObject(jw, "judgements", W->judgements);
        cJSON_AddNumberToObject(jw, "references", W->counts.references);
        cJSON_AddNumberToObject(jw, "renderings", W->counts.renderings);
        cJSON_AddNumberToObject(jw, "view_judgements", W->counts.view_judgements);
      } else {
        cJSON_AddNullToObject(o, "perceptual_level");
        cJSON_AddNullToObject(o, "switch_distance_m");
      }
      if (i < R.nplots) cJSON_AddStringToObject(o, "pareto_png", R.plots[i]);
      cJSON_AddItemToArray(js, o);
    }
    if (R.nsw == 0) cJSON_AddStringToObject(res, "perceptual", "not asked (--no-perceptual)");
    /* before and after: level 0 and the first screen's perceptual choice, as
     * the written model stores a level and a GPU holds it (jnd_scene_lod_bytes:
     * the attributes each mesh's material uses, 32-bit indices) */
    if (R.nsw > 0) {
      const jnd_lod_level_info *l0 = &P->levels[0], *l1 = &P->levels[R.sw[0].perceptual_level];
      cJSON *mem = cJSON_AddObjectToObject(res, "memory"), *tri = cJSON_AddObjectToObject(res, "triangles");
      cJSON_AddStringToObject(mem, "screen", R.sw[0].screen.name);
      cJSON_AddNumberToObject(mem, "level", R.sw[0].perceptual_level);
      cJSON_AddNumberToObject(mem, "before_bytes", (double)mem_before);
      cJSON_AddNumberToObject(mem, "after_bytes", (double)mem_after);
      cJSON_AddNumberToObject(tri, "before", (double)l0->triangles);
      cJSON_AddNumberToObject(tri, "after", (double)l1->triangles);
    }
    cJSON *jt = cJSON_AddArrayToObject(res, "textures");
    for (int t = 0; t < P->ntextures; t++) {
      const jnd_poi_texture *T = &P->textures[t];
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "name", T->name);
      cJSON *lv = cJSON_AddArrayToObject(o, "levels");
      for (int k = 0; k < T->nlevels; k++) {
        cJSON *a = cJSON_CreateArray();
        cJSON_AddItemToArray(a, cJSON_CreateNumber(T->size[k][0]));
        cJSON_AddItemToArray(a, cJSON_CreateNumber(T->size[k][1]));
        cJSON_AddItemToArray(lv, a);
      }
      cJSON *sc = cJSON_AddArrayToObject(o, "screens");
      for (int i = 0; i < T->nscreens; i++) {
        cJSON *so = cJSON_CreateObject();
        cJSON_AddStringToObject(so, "name", P->screens[i].screen.name);
        cJSON *cv = cJSON_AddArrayToObject(so, "curve");
        for (int k = 0; k < T->nlevels; k++) {
          cJSON *c = cJSON_CreateObject();
          size_t x = (size_t)i * T->nlevels + k;
          cJSON_AddNumberToObject(c, "level", k);
          cJSON_AddNumberToObject(c, "e_p", T->e_p[x]);
          cJSON_AddNumberToObject(c, "m_p", T->m_p[x]);
          cJSON_AddNumberToObject(c, "error", T->error[x]);
          cJSON_AddItemToArray(cv, c);
        }
        cJSON_AddNumberToObject(so, "poi_level", T->poi_level[i]);
        cJSON *sz = cJSON_AddArrayToObject(so, "poi_size");
        cJSON_AddItemToArray(sz, cJSON_CreateNumber(T->size[T->poi_level[i]][0]));
        cJSON_AddItemToArray(sz, cJSON_CreateNumber(T->size[T->poi_level[i]][1]));
        cJSON_AddNumberToObject(so, "poi_level_ep", T->poi_level_ep[i]);
        cJSON_AddItemToArray(sc, so);
      }
      cJSON_AddItemToArray(jt, o);
    }
  }
  cJSON *jm = cJSON_AddObjectToObject(res, "model");
  const char *rel = strstr(R.model_path, "/model/");
  cJSON_AddStringToObject(jm, "path", rel ? rel + 1 : R.model_path);
  cJSON *cov = cJSON_AddArrayToObject(jm, "screen_coverage");
  for (int k = 0; k < n; k++) cJSON_AddItemToArray(cov, cJSON_CreateNumber(R.coverage[k]));
  cJSON_AddStringToObject(jm, "screen_coverage_rule", R.coverage_rule);
  if (common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "load_s", R.load_s);
    cJSON_AddNumberToObject(t, "load_cpu_s", R.load_cpu_s);
    cJSON_AddNumberToObject(t, "chain_s", R.chain_s);
    cJSON_AddNumberToObject(t, "chain_cpu_s", R.chain_cpu_s);
    cJSON_AddNumberToObject(t, "analysis_s", R.analysis_s);
    cJSON_AddNumberToObject(t, "analysis_cpu_s", R.analysis_cpu_s);
    cJSON_AddNumberToObject(t, "write_s", R.write_s);
  }
  char path[4400];
  snprintf(path, sizeof path, "%s/lod.json", dir);
  int rc = cli_report_write(report, path);
  if (rc == EXIT_OK && json_out) rc = cli_report_write(report, json_out);
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);

  /* the human summary */
  cli_info(&common, "jnd lod: %s, %d levels (%s):", model, n, R.chain_source);
  for (int k = 0; k < n; k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(scene, k, &li);
    cli_info(&common, " %zu%s", li.triangles, li.method == JND_LOD_SLOPPY ? "*" : "");
  }
  cli_info(&common, " triangles\n");
  for (int k = 1; k < n; k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(scene, k, &li);
    if (li.method == JND_LOD_SLOPPY)
      cli_info(&common, "jnd lod: level %d: %d mesh(es) made by meshopt_simplifySloppy (seams not kept)\n", k,
               li.sloppy_meshes);
  }
  if (P) {
    cli_info(&common, "%-16s %12s %12s %12s %12s %12s\n", "screen", "perceptual", "003 PoI lit", "PoI unlit",
             "meshopt rule", "pixel rule");
    for (int i = 0; i < P->nscreens; i++) {
      const jnd_poi_screen_result *S = &P->screens[i];
      char perc[32] = "-";
      if (i < R.nsw) snprintf(perc, sizeof perc, "%zu", P->levels[R.sw[i].perceptual_level].triangles);
      cli_info(&common, "%-16s %12s %12zu %12zu %12zu %12zu\n", S->screen.name, perc, P->levels[S->poi_level].triangles,
               P->levels[S->poi_level_unlit].triangles, P->levels[S->meshopt_level].triangles,
               P->levels[S->pixel_level].triangles);
    }
    /* per level: the switch distance, and its criterion and popping components */
    for (int i = 0; i < R.nsw; i++) {
      const jnd_lod_switch_result *W = &R.sw[i];
      cli_info(&common, "%-16s switch distances (criterion, popping):", W->screen.name);
      for (int k = 1; k < W->nlevels; k++) {
        char a[3][24];
        const double d[3] = {W->switch_distance[k], W->switch_distance_criterion[k], W->switch_distance_pop[k]};
        for (int c = 0; c < 3; c++) {
          if (isnan(d[c])) snprintf(a[c], sizeof a[c], "-");
          else if (isinf(d[c])) snprintf(a[c], sizeof a[c], "never");
          else snprintf(a[c], sizeof a[c], "%.3g", d[c]);
        }
        cli_info(&common, " %d: %s (%s, %s)", k, a[0], a[1], a[2]);
      }
      cli_info(&common, "\n");
    }
  }
  if (R.nsw > 0)
    cli_info(&common, "memory (vertices and indices as written): level 0 %.3f MiB, level %d (%s) %.3f MiB\n",
             mem_before / 1048576.0, R.sw[0].perceptual_level, R.sw[0].screen.name, mem_after / 1048576.0);
  const char *model_rel = strstr(R.model_path, "/model/");
  if (rc == EXIT_OK) cli_info(&common, "wrote %s/lod.json and %s%s\n", final_dir, final_dir, model_rel ? model_rel : "");
  jnd_lod_report_free(&R);
  return rc;
}

const jnd_command jnd_cmd_lod = {"lod", "LOD chain and 003's Point of Imperceptibility per screen", run};
