/* jnd texres MODEL -o OUTDIR — the smallest texture maps nobody notices (000 §4–§9). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd texres MODEL -o OUTDIR [options]\n"
      "\n"
      "Chooses, for every texture map of MODEL (glTF 2.0 .gltf/.glb, OBJ, or `builtin`),\n"
      "the smallest resolution a viewer does not notice (Wolski et al. 2019: paper 000,\n"
      "sections 4-9): candidates are the original and its power-of-two reductions, each\n"
      "rendered from N sampled views and compared with the full-resolution rendering by\n"
      "the vision model; a combination passes when at most a fraction Q of the views\n"
      "have a pooled probability of detection above P. Each map's candidates are searched\n"
      "by bisection; the choice is made with P x (1 - margin) so that it holds on views\n"
      "it was not chosen on. Sizes never exceed the mip-usage bound (the finest mip level\n"
      "any pixel samples). Writes OUTDIR/texres.json, the resized maps and a copy of the\n"
      "model pointing at them (inputs are never touched) and the worst view's heatmap.\n"
      "See docs/texres.md.\n"
      "\n"
      "%s"
      "  --verify-views M    then check the choice on M other views (held out; 0)\n"
      "\n"
      "%s"
      "  --margin F          choose with P x (1 - F) on the views (0.5; 0 = P itself)\n"
      "  --confirm R         the choice must then hold on up to R fresh sets of views;\n"
      "                      a set where it fails joins the views and the choice grows (2)\n"
      "\n"
      "%s"
      "\n"
      "search:\n"
      "  --sizes LIST        candidate sizes (longer side, pixels), e.g. 1024,768,512\n"
      "                      (default: the original and its halvings down to --min-size)\n"
      "  --min-size N        floor of the halvings (32)\n"
      "  --maps LIST         maps to search: MATERIAL/SLOT or slot names (default all)\n"
      "  --matrix            also render the baseColor x normal matrix of each material\n"
      "                      (000 Fig. 13; every pair of candidates: slow)\n"
      "  --quick-matrix      the matrix down to each map's first size that fails on its own\n"
      "\n"
      "outputs:\n"
      "  -o, --output DIR    the folder (created): texres.json, worst_view.png,\n"
      "                      matrix_N.png, model/ (a glTF/GLB copy with resized maps) or\n"
      "                      maps/ (OBJ, builtin: the resized maps as PNG)\n"
      "%s"
      "\n"
      "Paper numbers: 000 is Wolski et al. 2019, texture resolution (include/jnd.h lists\n"
      "them all).\n"
      "Exit status: 0; 1 when the choice fails the criterion on the views (or the\n"
      "held-out views); 2 for bad input (one line: jnd: FILE: problem).\n",
      cli_views_help, cli_criterion_help, cli_display_help, cli_common_help);
}

/* the human summary: per map, per unique image, memory and the criterion */
static void summary(const cli_common *common, const jnd_texres_params *p, const jnd_texres_result *R, double t0) {
  cli_info(common, "%-40s %11s %11s %11s %11s %9s\n", "map", "original", "chosen", "mip bound", "eye bound",
           "fit P=p");
  for (int i = 0; i < R->nmaps; i++) {
    const jnd_texres_map *m = &R->maps[i];
    char o[4][24], f[24] = "-";
    snprintf(o[0], 24, "%dx%d", m->orig[0], m->orig[1]);
    snprintf(o[1], 24, "%dx%d", m->chosen[0], m->chosen[1]);
    snprintf(o[2], 24, "%dx%d", m->mip_bound[0], m->mip_bound[1]);
    snprintf(o[3], 24, "%dx%d", m->eye_bound[0], m->eye_bound[1]);
    if (m->fit_ok) snprintf(f, sizeof f, "%.0f", m->fit_res);
    cli_info(common, "%-40.40s %11s %11s %11s %11s %9s%s\n", m->name, o[0], o[1], o[2], o[3], f,
             m->searched ? "" : "  (kept)");
  }
  cli_info(common, "\n%-52s %11s %11s %21s\n", "image (the maps that sample it)", "original", "chosen",
           "RGBA8 + mips, MiB");
  for (int t = 0; t < R->nimages; t++) {
    const jnd_texres_image *im = &R->images[t];
    char users[256] = "", o[2][24];
    size_t n = 0;
    for (int i = 0; i < R->nmaps && n < sizeof users; i++)
      if (R->maps[i].image == t)
        n += (size_t)snprintf(users + n, sizeof users - n, "%s%s", n ? ", " : "", R->maps[i].name);
    snprintf(o[0], 24, "%dx%d", im->orig[0], im->orig[1]);
    snprintf(o[1], 24, "%dx%d", im->chosen[0], im->chosen[1]);
    cli_info(common, "%-52.52s %11s %11s %9.3f -> %8.3f\n", users, o[0], o[1],
             im->bytes_before[JND_TEX_RGBA8] / 1048576.0, im->bytes_after[JND_TEX_RGBA8] / 1048576.0);
  }
  size_t bb = R->before_bytes[JND_TEX_RGBA8], ba = R->after_bytes[JND_TEX_RGBA8];
  cli_info(common,
           "memory (%d unique image%s, RGBA8 + mips): %.2f MiB -> %.2f MiB (%+.0f%%); block-compressed %.2f MiB -> "
           "%.2f MiB\n",
           R->nimages, R->nimages == 1 ? "" : "s", bb / 1048576.0, ba / 1048576.0,
           bb ? 100.0 * ((double)ba / bb - 1.0) : 0.0, R->block_before_bytes / 1048576.0,
           R->block_after_bytes / 1048576.0);
  cli_info(common, "views above P=%.2f: %.0f%% of %d (criterion <= %.0f%%; sizes chosen against P <= %.3f, p less the margin)%s",
           p->judge.criterion.p, 100 * R->views.fraction_above, R->nviews, 100 * p->judge.criterion.q, R->choice_p,
           R->views.pass ? "" : "  FAILS");
  if (R->verify_views)
    cli_info(common, "; held out: %.0f%% of %d%s", 100 * R->verify.fraction_above, R->verify_views,
             R->verify.pass ? "" : "  FAILS the criterion");
  cli_info(common, "\n%d evaluations, %d renderings, %.1f s on %s\n", R->evaluations, R->renderings,
           jnd_seconds() - t0, R->renderer);
}

static int run(int argc, char **argv) {
  const char *model = NULL, *dir = NULL, *v;
  cli_common common = {0};
  cli_views vo;
  cli_display disp;
  cli_calibration cal = {0};
  jnd_texres_params p;
  jnd_texres_defaults(&p);
  cli_views_init(&vo, p.judge.views.render.width, p.judge.views.render.height);
  cli_display_init(&disp);
  int sizes[64];
  cli_args args = cli_args_start(argc, argv, "texres"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_views_opt(ap, &vo) || cli_display_opt(ap, &disp) || cli_criterion_opt(ap, &p.judge.criterion) ||
               cli_calibration_opt(ap, &cal) || cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--verify-views", &v)) {
      p.verify_views = cli_int(ap, "--verify-views", v, 0, 4096);
    } else if (cli_opt(ap, "--margin", &v)) {
      p.margin = cli_double(ap, "--margin", v, 0, 0.99);
    } else if (cli_opt(ap, "--confirm", &v)) {
      p.confirm_rounds = cli_int(ap, "--confirm", v, 0, 16);
    } else if (cli_opt(ap, "--sizes", &v)) {
      p.nsizes = cli_int_list(ap, "--sizes", v, 1, 32768, sizes, 64);
      p.sizes = sizes;
    } else if (cli_opt(ap, "--min-size", &v)) {
      p.min_size = cli_int(ap, "--min-size", v, 1, 32768);
    } else if (cli_opt(ap, "--maps", &v)) {
      p.maps = v;
    } else if (cli_flag(ap, "--matrix")) {
      p.matrix = 2;
    } else if (cli_flag(ap, "--quick-matrix")) {
      p.matrix = 1;
    } else if (cli_flag(ap, "--no-matrix")) {
      p.matrix = 0;   /* the default; kept so that older command lines work */
    } else if (!cli_operand(ap, &model, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!model) return cli_bad("texres: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd texres --help");
  if (!dir) return cli_bad("texres: give an output folder with -o OUTDIR; jnd texres --help");
  if (!cli_calibration_get(&cal, &p.judge.calibration)) return EXIT_BAD;
  p.judge.model.display = cli_display_get(&disp);
  p.judge.model.threads = common.threads;

  p.judge.views = vo.set;
  cli_run_options(&p.run, &common, vo.map_size);
  double t0 = jnd_seconds();
  cli_progress prog;
  cli_progress_start(&prog, &common, "texres", 1);
  p.progress = cli_progress_callback;
  p.progress_user = &prog;
  jnd_texres_result *R = NULL;
  jnd_status st = jnd_texres_run(model, &p, dir, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  if (rc == EXIT_OK) {
    summary(&common, &p, R, t0);
    rc = R->passes ? EXIT_OK : EXIT_ABOVE;
  }
  jnd_texres_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_texres = {"texres", "the smallest texture resolution nobody notices (000)", run};
