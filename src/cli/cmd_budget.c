/* jnd budget MODEL -o OUTDIR — texture sizes and the LOD chain chosen
 * together under one cost (issue 27, docs/budget.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd budget MODEL -o OUTDIR [options]\n"
      "\n"
      "Chooses the texture sizes and the levels of detail of MODEL (glTF 2.0 .gltf/.glb,\n"
      "OBJ, or `builtin`) together, on one cost: the textures' GPU memory (each unique\n"
      "image once, with its mip chain, in the block format its slots need, or BC1\n"
      "where its block artefacts go unnoticed) plus the finest level's triangles\n"
      "times an exchange rate in bytes. The chain and its\n"
      "popping-free switch distances are jnd lod's; the texture sizes are jnd texres's\n"
      "search run with each mesh level drawn (levels up to lod's perceptual one), so\n"
      "that geometry and textures share one criterion (at most a fraction Q of the\n"
      "views above P). A ladder of uniform halvings per level gives the Pareto front\n"
      "of (memory, triangles, statistic). Each coarser level is checked on held-out\n"
      "views at its switch distance with its maps capped at the mips that distance\n"
      "samples (000 section 4). See docs/budget.md.\n"
      "\n"
      "modes:\n"
      "  (default)           cheapest unnoticed: the cheapest candidate that passes\n"
      "                      with texres's margin and on held-out views; or texres +\n"
      "                      pca + lod chosen separately where that is cheaper and\n"
      "                      unnoticed at P on the judge's and held-out views\n"
      "  --memory SIZE       budget mode: texture memory at most SIZE (B, KiB, MiB,\n"
      "                      GiB, kB, MB, GB; e.g. 8MiB) ...\n"
      "  --triangles N       ... and at most N triangles at the finest level (either or\n"
      "                      both): the candidate within it with the lowest statistic\n"
      "  --bytes-per-triangle F  the exchange rate (default: level 0's own vertex and\n"
      "                      index bytes per triangle as written, so that the cost is the\n"
      "                      GPU bytes of textures and mesh)\n"
      "  --verify-views N    held-out views at each level's switch distance (4)\n"
      "\n"
      "%s"
      "                      (--coverage is the viewing condition of both searches, 0.5)\n"
      "\n"
      "%s"
      "  --margin F          texres: choose with P x (1 - F) (0.5)\n"
      "  --confirm R         texres: fresh sets of views the choice must hold on (2)\n"
      "  --min-size N        the smallest map side of any candidate (32)\n"
      "\n"
      "%s"
      "\n"
      "chain and switch distances (jnd lod):\n"
      "  --screens LIST      target screens (presets or WxH[@PPD]; default standard-fhd,\n"
      "                      standard-4k, phone, laptop); the model's MSFT_screencoverage\n"
      "                      is the first screen's\n"
      "  --errors LIST       the chain's error targets (relative to the extent)\n"
      "  --judge-views N     views per distance of the switch search (4)\n"
      "  --far-coverage F    the farthest switch searched: the sphere fills F (0.02)\n"
      "  --tolerance F       switch distances within a factor 1 + F (0.1)\n"
      "  --max-px N          largest rendering side of the switch search (512)\n"
      "  --no-pop            switch distances by the criterion only (no popping check)\n"
      "\n"
      "outputs:\n"
      "  -o, --output DIR    the folder (created): budget.json, model/NAME.glb (the chosen\n"
      "                      levels with MSFT_lod and MSFT_screencoverage, maps at the\n"
      "                      chosen sizes), pareto.png\n"
      "%s"
      "\n"
      "The report gives each level's switch per screen as Unreal ScreenSize and Unity\n"
      "LODGroup screenRelativeTransitionHeight: both the bounding sphere's projected\n"
      "diameter over the screen's height at the switch distance d for the vertical\n"
      "field of view: tan(asin(r / d)) / tan(fov / 2).\n"
      "Exit status: 0; 1 when the choice fails the criterion (on the views or at a\n"
      "switch distance); 2 for bad input or a budget nothing meets (one line: jnd:\n"
      "FILE: problem, naming the smallest memory and triangles possible).\n",
      cli_views_help, cli_criterion_help, cli_display_help, cli_common_help);
}

/* "8MiB", "8 MiB", "512KB", "1048576" (bytes): > 0 */
static int parse_size(const char *v, double *out) {
  char *end;
  double x = strtod(v, &end);
  if (end == v || !isfinite(x)) return 0;
  while (*end == ' ') end++;
  static const struct {
    const char *unit;
    double bytes;
  } units[] = {{"", 1}, {"B", 1}, {"KiB", 1024}, {"MiB", 1048576}, {"GiB", 1073741824}, {"kB", 1e3}, {"KB", 1e3},
               {"MB", 1e6}, {"GB", 1e9}};
  for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
    if (strcmp(end, units[i].unit) == 0) {
      *out = x * units[i].bytes;
      return x > 0;
    }
  return 0;
}

static void summary(const cli_common *common, const jnd_budget_result *R) {
  const jnd_budget_candidate *ch = &R->candidates[R->chosen], *se = &R->candidates[R->separate];
  cli_info(common, "%-30s %6s %14s %10s %14s %10s\n", "", "level", "textures MiB", "triangles", "cost MiB",
           "statistic");
  const jnd_budget_candidate *rows[2] = {ch, se};
  const char *names[2] = {R->mode                ? "chosen (within the budget)"
                          : R->separate_taken ? "chosen: the separate one"
                                              : "chosen (cheapest unnoticed)",
                          "texres + pca + lod separately"};
  for (int i = 0; i < 2; i++)
    cli_info(common, "%-30s %6d %14.3f %10zu %14.3f %10.3f%s\n", names[i], rows[i]->level,
             rows[i]->memory_bytes / 1048576.0, rows[i]->triangles, rows[i]->cost / 1048576.0, rows[i]->statistic,
             i == 1 && !rows[i]->searched_pass ? "  (fails with the margin)" : "");
  if (R->separate_taken) {   /* step 7 takes the separate one where it is cheaper, or where the joint one is seen */
    const jnd_budget_candidate *jo = &R->candidates[R->joint];
    cli_info(common,
             "the joint search's own choice (level %d, %.3f MiB) %s: the separate one is unnoticed at p on the "
             "judge's and held-out views, so it is taken\n",
             jo->level, jo->cost / 1048576.0, jo->cost > ch->cost ? "costs more" : "is seen on its held-out views");
  }
  int front = 0;
  for (int i = 0; i < R->ncandidates; i++) front += R->candidates[i].pareto;
  cli_info(common, "exchange rate %.1f bytes per triangle; %d candidates, %d on the Pareto front\n",
           R->bytes_per_triangle, R->ncandidates, front);
  for (int j = 0; j < R->nlevels; j++) {
    const jnd_budget_level *L = &R->levels[j];
    cli_info(common, "level %d: from %.4g (ScreenSize %.4f on %s), %zu triangles, textures %.3f MiB, held out %s",
             L->level, L->switch_distance, L->switch_coverage, R->lod.nsw ? R->lod.sw[0].screen.name : "-",
             L->triangles, L->texture_bytes / 1048576.0, L->views ? (L->pass ? "pass" : "FAIL") : "-");
    if (L->views) cli_info(common, " (%.3f on %d)", L->statistic, L->views);
    cli_info(common, "\n");
  }
  cli_info(common, "%s written; %.1f s search, %.1f s verification\n", R->model_path, R->search_s, R->verify_s);
}

static int run(int argc, char **argv) {
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  cli_views vo;
  cli_display disp;
  cli_calibration cal = {0};
  jnd_budget_params p;
  jnd_budget_defaults(&p);
  cli_views_init(&vo, p.texres.judge.views.render.width, p.texres.judge.views.render.height);
  vo.set.sampling.coverage = p.lod.poi.coverage;
  vo.map_size = p.run.map_size;
  cli_display_init(&disp);
  double errors[64];
  jnd_poi_screen screens[16];
  cli_args args = cli_args_start(argc, argv, "budget"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_views_opt(ap, &vo) || cli_display_opt(ap, &disp) ||
               cli_criterion_opt(ap, &p.texres.judge.criterion) || cli_calibration_opt(ap, &cal) ||
               cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--memory", &v)) {
      if (!parse_size(v, &p.memory_bytes))
        return cli_bad("budget: --memory: '%s' is not a size above 0 (e.g. 8MiB; units B, KiB, MiB, GiB, kB, MB, GB)", v);
    } else if (cli_opt(ap, "--triangles", &v)) {
      p.triangles = cli_int(ap, "--triangles", v, 1, 2000000000);
    } else if (cli_opt(ap, "--bytes-per-triangle", &v)) {
      p.bytes_per_triangle = cli_double(ap, "--bytes-per-triangle", v, 1e-6, 1e6);
    } else if (cli_opt(ap, "--verify-views", &v)) {
      p.verify_views = cli_int(ap, "--verify-views", v, 0, JND_VIEWS_MAX);
    } else if (cli_opt(ap, "--margin", &v)) {
      p.texres.margin = cli_double(ap, "--margin", v, 0, 0.99);
    } else if (cli_opt(ap, "--confirm", &v)) {
      p.texres.confirm_rounds = cli_int(ap, "--confirm", v, 0, 16);
    } else if (cli_opt(ap, "--min-size", &v)) {
      p.texres.min_size = cli_int(ap, "--min-size", v, 1, 32768);
    } else if (cli_opt(ap, "--screens", &v)) {
      char buf[1024];
      snprintf(buf, sizeof buf, "%s", v);
      p.lod.poi.nscreens = 0;
      for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (p.lod.poi.nscreens >= 16) return cli_bad("budget: --screens: at most 16 screens");
        if (jnd_poi_screen_parse(tok, &screens[p.lod.poi.nscreens]) != JND_OK)
          return cli_bad("budget: --screens: %s", jnd_last_error());
        p.lod.poi.nscreens++;
      }
      if (p.lod.poi.nscreens == 0) return cli_bad("budget: --screens: '%s' names no screen", v);
      p.lod.poi.screens = screens;
    } else if (cli_opt(ap, "--errors", &v)) {
      p.lod.chain.nerrors = cli_errors(ap, v, errors, 63);
      p.lod.chain.errors = errors;
    } else if (cli_opt(ap, "--judge-views", &v)) {
      p.lod.sw.judge.views.sampling.count = cli_int(ap, "--judge-views", v, 1, JND_VIEWS_MAX);
    } else if (cli_opt(ap, "--far-coverage", &v)) {
      p.lod.sw.far_coverage = cli_double(ap, "--far-coverage", v, 1e-4, 1);
    } else if (cli_opt(ap, "--tolerance", &v)) {
      p.lod.sw.tolerance = cli_double(ap, "--tolerance", v, 0.001, 10);
    } else if (cli_opt(ap, "--max-px", &v)) {
      p.lod.sw.max_px = cli_int(ap, "--max-px", v, 32, 8192);
    } else if (cli_flag(ap, "--no-pop")) {
      p.lod.sw.pop = 0;
    } else if (!cli_operand(ap, &model, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!model) return cli_bad("budget: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd budget --help");
  if (!dir) return cli_bad("budget: give an output folder with -o OUTDIR; jnd budget --help");
  if (!cli_calibration_get(&cal, &p.texres.judge.calibration)) return EXIT_BAD;
  p.texres.judge.model.display = cli_display_get(&disp);
  p.texres.judge.model.threads = common.threads;
  p.texres.judge.views = vo.set;
  /* one viewing condition and view sampling for both searches */
  p.lod.poi.coverage = vo.set.sampling.coverage;
  p.lod.poi.seed = vo.set.sampling.seed;
  p.lod.poi.fov_y_deg = vo.set.sampling.fov_y_deg;
  p.lod.poi.lights = vo.set.sampling.lights;
  p.lod.poi.env_path = vo.set.render.env_path;
  p.lod.poi.platform = vo.set.render.platform;
  p.lod.sw.judge.criterion = p.texres.judge.criterion;
  p.lod.sw.judge.calibration = p.texres.judge.calibration;
  p.lod.threads = common.threads;
  cli_run_options(&p.run, &common, vo.map_size);
  cli_progress prog;
  cli_progress_start(&prog, &common, "budget", 1);
  p.progress = cli_progress_callback;
  p.progress_user = &prog;
  jnd_budget_result *R = NULL;
  jnd_status st = jnd_budget_run(model, &p, dir, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  if (rc == EXIT_OK) {
    summary(&common, R);
    rc = R->passes ? EXIT_OK : EXIT_ABOVE;
  }
  jnd_budget_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_budget = {"budget", "texture sizes and LOD chain together under one cost", run};
