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

static cJSON *pair(const int *wh) {
  cJSON *a = cJSON_CreateArray();
  cJSON_AddItemToArray(a, cJSON_CreateNumber(wh[0]));
  cJSON_AddItemToArray(a, cJSON_CreateNumber(wh[1]));
  return a;
}

static cJSON *bytes_json(const size_t *b) {
  cJSON *o = cJSON_CreateObject();
  for (int f = 0; f < JND_TEX_FORMATS; f++) cJSON_AddNumberToObject(o, jnd_tex_format_name(f), (double)b[f]);
  return o;
}

/* 000 Fig. 13, drawn by the library (jnd_texres_matrix_figure) */
static int write_matrix_png(const char *path, const jnd_texres_result *r, int t) {
  jnd_image img;
  int ok = jnd_texres_matrix_figure(r, t, &img) == JND_OK && jnd_image_write_png(path, &img, 8) == JND_OK;
  if (!ok) cli_error("%s", jnd_last_error());
  jnd_image_free(&img);
  return ok;
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
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
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
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (!model) {
      model = a;
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!model) return cli_bad("texres: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd texres --help");
  if (!dir) return cli_bad("texres: give an output folder with -o OUTDIR; jnd texres --help");
  if (!cli_calibration_get(&cal, &p.judge.calibration)) return EXIT_BAD;
  p.judge.model.display = cli_display_get(&disp);
  p.judge.model.threads = common.threads;

  double t0 = jnd_seconds();
  jnd_scene *scene = NULL;
  jnd_view *views = NULL;
  int nviews = 0;
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *ins[] = {model, vo.set.render.env_path, vo.cameras, cal.path}, *final_dir = dir;
  const char *json_out = common.json_path;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 4) != EXIT_OK ||
      cli_out_dir(outw, final_dir, &dir) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    return cli_out_end(outw, EXIT_BAD);
  if (jnd_scene_open(model, vo.map_size, &scene) != JND_OK) return cli_out_end(outw, cli_lib_error());
  for (int i = 0; i < jnd_scene_warning_count(scene); i++) cli_info(&common, "jnd: warning: %s\n", jnd_scene_warning(scene, i));
  int rc = EXIT_BAD;
  cJSON *report = NULL, *written = NULL;
  jnd_texres_result R = {0};
  cli_progress prog;
  if (jnd_scene_map_count(scene) == 0) {
    cli_error("%s: the asset has no texture maps (nothing to choose)", model);
    goto out;
  }
  if (cli_views_make(&vo, scene, &views, &nviews) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  p.judge.views = vo.set;
  if (vo.cameras) {
    p.judge.views.cameras = views;
    p.judge.views.ncameras = nviews;
  }
  cli_progress_start(&prog, &common, "texres", 1);
  p.progress = cli_progress_callback;
  p.progress_user = &prog;
  if (jnd_make_dirs(dir) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  jnd_status st = jnd_texres_run(scene, &p, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  double t_search = jnd_seconds() - t0;

  char path[4400], model_out[4400] = "";
  const char *ext = strrchr(model, '.');
  int gltf = ext && (strcasecmp(ext, ".gltf") == 0 || strcasecmp(ext, ".glb") == 0);
  if (gltf) {
    char mdir[4200];
    snprintf(mdir, sizeof mdir, "%s/model", dir);
    if (jnd_make_dirs(mdir) != JND_OK || jnd_texres_write_model(scene, model, mdir, model_out, sizeof model_out) != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  written = cJSON_CreateArray();
  if (!gltf) {
    /* OBJ and the builtin asset: the resized maps as PNG files (no model copy) */
    char mdir[4200];
    snprintf(mdir, sizeof mdir, "%s/maps", dir);
    for (int i = 0; i < R.nmaps; i++) {
      const jnd_texres_map *m = &R.maps[i];
      if (m->chosen[0] == m->orig[0] && m->chosen[1] == m->orig[1]) continue;
      char name[200];
      snprintf(name, sizeof name, "%s_%dx%d.png", m->name, m->chosen[0], m->chosen[1]);
      for (char *q = name; *q; q++)
        if (*q == '/' || *q == ' ' || *q == '#') *q = '_';
      snprintf(path, sizeof path, "%s/%s", mdir, name);
      jnd_image im = {0};
      int ok = jnd_make_dirs(mdir) == JND_OK && jnd_scene_map_get(scene, m->map, 0, &im) == JND_OK &&
               jnd_image_write_png(path, &im, 8) == JND_OK;
      jnd_image_free(&im);
      if (!ok) {
        cli_error("%s: %s", path, jnd_last_error());
        goto out;
      }
      char rel[260];
      snprintf(rel, sizeof rel, "maps/%s", name);
      cJSON_AddItemToArray(written, cJSON_CreateString(rel));
    }
  }
  snprintf(path, sizeof path, "%s/worst_view.png", dir);
  if (jnd_image_write_png(path, &R.worst_heatmap, 8) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }

  report = cli_report_new("texres");
  cJSON *in = cli_report_section(report, "inputs"), *par = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  if (cal.path) cJSON_AddStringToObject(in, "calibration", cal.path);
  cJSON_AddItemToObject(par, "views", cli_views_json(&vo));
  cJSON_AddNumberToObject(par, "verify_views", p.verify_views);
  cJSON_AddItemToObject(par, "criterion", cli_criterion_json(&p.judge.criterion, NULL));
  cJSON_AddNumberToObject(par, "margin", p.margin);
  cJSON_AddNumberToObject(par, "confirm_rounds", p.confirm_rounds);
  cJSON_AddNumberToObject(par, "choice_p", R.choice_p);
  cJSON_AddNumberToObject(par, "min_size", p.min_size);
  cJSON *calj = cJSON_AddObjectToObject(par, "calibration");
  cJSON_AddNumberToObject(calj, "percentile", p.judge.calibration.percentile);
  cJSON_AddNumberToObject(calj, "scale", p.judge.calibration.scale);
  cJSON_AddNumberToObject(calj, "bias", p.judge.calibration.bias);
  cJSON_AddNumberToObject(calj, "beta", p.judge.calibration.beta);
  cJSON_AddItemToObject(par, "display", cli_display_json(&p.judge.model.display));
  cJSON_AddBoolToObject(par, "matrix", p.matrix != 0);

  cJSON_AddStringToObject(res, "renderer", R.renderer);
  cJSON *jm = cJSON_AddArrayToObject(res, "maps");
  for (int i = 0; i < R.nmaps; i++) {
    const jnd_texres_map *m = &R.maps[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", m->name);
    cJSON_AddStringToObject(o, "slot", jnd_map_slot_name(m->slot));
    cJSON_AddStringToObject(o, "material", jnd_scene_material_name(scene, m->material));
    cJSON_AddBoolToObject(o, "searched", m->searched);
    cJSON_AddItemToObject(o, "original", pair(m->orig));
    cJSON_AddItemToObject(o, "chosen", pair(m->chosen));
    cJSON_AddItemToObject(o, "mip_bound", pair(m->mip_bound));
    cJSON_AddNumberToObject(o, "mip_min", m->mip_min);
    cJSON_AddItemToObject(o, "eye_bound", pair(m->eye_bound));
    cJSON *cand = cJSON_AddArrayToObject(o, "candidates"), *ser = cJSON_AddArrayToObject(o, "series"),
          *part = cJSON_AddArrayToObject(o, "series_decided_early");
    for (int j = 0; j < m->ncand; j++) {
      cJSON_AddItemToArray(cand, pair(m->cand[j]));
      cJSON_AddItemToArray(ser, isfinite(m->series[j]) ? cJSON_CreateNumber(m->series[j]) : cJSON_CreateNull());
      cJSON_AddItemToArray(part, cJSON_CreateBool(m->series_partial[j]));
    }
    if (m->fit_ok) {
      cJSON *f = cJSON_AddObjectToObject(o, "psychometric");
      cJSON_AddNumberToObject(f, "mu_log2", m->fit.mu);
      cJSON_AddNumberToObject(f, "sigma_log2", m->fit.sigma);
      cJSON_AddNumberToObject(f, "rmse", m->fit.rmse);
      cJSON_AddNumberToObject(f, "resolution_at_p", m->fit_res);
      cJSON_AddItemToObject(f, "rounded_up", pair(m->fit_cand));
    }
    cJSON_AddStringToObject(o, "block_format", jnd_tex_format_name(jnd_slot_block_format(m->slot, m->channels)));
    cJSON_AddNumberToObject(o, "image", m->image);
    cJSON_AddItemToArray(jm, o);
  }
  /* memory as a GPU holds it: each unique image once, with its mip chain;
   * RGBA8 is the headline, block formats beside it */
  cJSON *mem = cJSON_AddObjectToObject(res, "memory");
  size_t bb = R.before_bytes[JND_TEX_RGBA8], ba = R.after_bytes[JND_TEX_RGBA8];
  cJSON_AddNumberToObject(mem, "before_bytes", (double)bb);
  cJSON_AddNumberToObject(mem, "after_bytes", (double)ba);
  cJSON_AddNumberToObject(mem, "reduction", bb ? 1.0 - (double)ba / bb : 0);
  cJSON_AddNumberToObject(mem, "block_before_bytes", (double)R.block_before_bytes);
  cJSON_AddNumberToObject(mem, "block_after_bytes", (double)R.block_after_bytes);
  cJSON_AddItemToObject(mem, "formats_before", bytes_json(R.before_bytes));
  cJSON_AddItemToObject(mem, "formats_after", bytes_json(R.after_bytes));
  cJSON *jimg = cJSON_AddArrayToObject(mem, "images");
  for (int t = 0; t < R.nimages; t++) {
    const jnd_texres_image *im = &R.images[t];
    cJSON *o = cJSON_CreateObject(), *users = cJSON_AddArrayToObject(o, "maps");
    for (int i = 0; i < R.nmaps; i++)
      if (R.maps[i].image == t) cJSON_AddItemToArray(users, cJSON_CreateString(R.maps[i].name));
    cJSON_AddItemToObject(o, "original", pair(im->orig));
    cJSON_AddItemToObject(o, "chosen", pair(im->chosen));
    cJSON_AddStringToObject(o, "block_format", jnd_tex_format_name(im->block_format));
    cJSON_AddItemToObject(o, "bytes_before", bytes_json(im->bytes_before));
    cJSON_AddItemToObject(o, "bytes_after", bytes_json(im->bytes_after));
    cJSON_AddItemToArray(jimg, o);
  }
  cJSON *jv = cJSON_AddObjectToObject(res, "views");
  cJSON_AddNumberToObject(jv, "count", R.nviews);
  cJSON *pv = cJSON_AddArrayToObject(jv, "p");
  for (int i = 0; i < R.nviews; i++) cJSON_AddItemToArray(pv, cJSON_CreateNumber(R.view_p[i]));
  cJSON_AddNumberToObject(jv, "fraction_above", R.views.fraction_above);
  cJSON_AddBoolToObject(jv, "passes", R.views.pass);
  cJSON_AddNumberToObject(jv, "worst_view", R.worst_view);
  cJSON_AddStringToObject(jv, "heatmap", "worst_view.png");
  cJSON_AddItemToObject(jv, "criterion", cli_criterion_json(&p.judge.criterion, &R.views));
  if (R.verify_views > 0) {
    cJSON *vv = cJSON_AddObjectToObject(res, "verify");
    cJSON_AddNumberToObject(vv, "views", R.verify_views);
    cJSON_AddNumberToObject(vv, "fraction_above", R.verify.fraction_above);
    cJSON_AddBoolToObject(vv, "passes", R.verify.pass);
    cJSON *vp = cJSON_AddArrayToObject(vv, "p");
    for (int i = 0; i < R.verify_views; i++) cJSON_AddItemToArray(vp, cJSON_CreateNumber(R.verify_p[i]));
    cJSON_AddItemToObject(vv, "criterion", cli_criterion_json(&p.judge.criterion, &R.verify));
  }
  cJSON *jmx = cJSON_AddArrayToObject(res, "matrices");
  for (int t = 0; t < R.nmatrix; t++) {
    const jnd_texres_matrix *mx = &R.matrix[t];
    const jnd_texres_map *A = &R.maps[mx->map_a], *B = &R.maps[mx->map_b];
    char name[64];
    snprintf(name, sizeof name, "matrix_%d.png", t);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (!write_matrix_png(path, &R, t)) goto out;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "columns", A->name);
    cJSON_AddStringToObject(o, "rows", B->name);
    cJSON *sa = cJSON_AddArrayToObject(o, "column_sizes"), *sb = cJSON_AddArrayToObject(o, "row_sizes");
    for (int a = 0; a < mx->na; a++) cJSON_AddItemToArray(sa, cJSON_CreateNumber(mx->size_a[a]));
    for (int b = 0; b < mx->nb; b++) cJSON_AddItemToArray(sb, cJSON_CreateNumber(mx->size_b[b]));
    cJSON *pv2 = cJSON_AddArrayToObject(o, "p");   /* [view][row][column] */
    for (int v2 = 0; v2 < mx->nviews; v2++) {
      cJSON *tab = cJSON_CreateArray();
      for (int b = 0; b < mx->nb; b++) {
        cJSON *row = cJSON_CreateArray();
        for (int a = 0; a < mx->na; a++)
          cJSON_AddItemToArray(row, cJSON_CreateNumber(mx->p[((size_t)v2 * mx->na + a) * mx->nb + b]));
        cJSON_AddItemToArray(tab, row);
      }
      cJSON_AddItemToArray(pv2, tab);
    }
    cJSON *stt = cJSON_AddArrayToObject(o, "stat");
    for (int b = 0; b < mx->nb; b++) {
      cJSON *row = cJSON_CreateArray();
      for (int a = 0; a < mx->na; a++) cJSON_AddItemToArray(row, cJSON_CreateNumber(mx->stat[a * mx->nb + b]));
      cJSON_AddItemToArray(stt, row);
    }
    if (mx->best_a >= 0) {
      int best[2] = {mx->size_a[mx->best_a], mx->size_b[mx->best_b]};
      cJSON_AddItemToObject(o, "best", pair(best));
    }
    cJSON_AddBoolToObject(o, "complete", mx->complete);
    cJSON_AddStringToObject(o, "png", name);
    cJSON_AddItemToArray(jmx, o);
  }
  if (model_out[0]) {   /* where it will be: the final folder, not the staging */
    char final_model[4600];
    snprintf(final_model, sizeof final_model, "%s%s", final_dir, model_out + strlen(dir));
    cJSON_AddStringToObject(res, "model", final_model);
  }
  cJSON_AddItemToObject(res, "map_files", written);
  written = NULL;
  cJSON_AddNumberToObject(res, "ppd", R.ppd);
  cJSON_AddNumberToObject(res, "evaluations", R.evaluations);
  cJSON_AddNumberToObject(res, "renderings", R.renderings);
  cJSON *rc2 = cJSON_AddObjectToObject(res, "rendering_counts");
  cJSON_AddNumberToObject(rc2, "references", R.counts.references);
  cJSON_AddNumberToObject(rc2, "whole", R.counts.renderings);
  cJSON_AddNumberToObject(rc2, "partial", R.counts.partial_renderings);
  cJSON_AddNumberToObject(rc2, "view_judgements", R.counts.view_judgements);
  cJSON_AddNumberToObject(rc2, "reused", R.counts.reused);
  if (common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "search_s", t_search);
    cJSON_AddNumberToObject(t, "total_s", jnd_seconds() - t0);
  }
  snprintf(path, sizeof path, "%s/texres.json", dir);
  if (cli_report_write(report, path) != EXIT_OK) goto out;
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto out;

  cli_info(&common, "%-40s %11s %11s %11s %11s %9s\n", "map", "original", "chosen", "mip bound", "eye bound",
           "fit P=p");
  for (int i = 0; i < R.nmaps; i++) {
    const jnd_texres_map *m = &R.maps[i];
    char o[4][24], f[24] = "-";
    snprintf(o[0], 24, "%dx%d", m->orig[0], m->orig[1]);
    snprintf(o[1], 24, "%dx%d", m->chosen[0], m->chosen[1]);
    snprintf(o[2], 24, "%dx%d", m->mip_bound[0], m->mip_bound[1]);
    snprintf(o[3], 24, "%dx%d", m->eye_bound[0], m->eye_bound[1]);
    if (m->fit_ok) snprintf(f, sizeof f, "%.0f", m->fit_res);
    cli_info(&common, "%-40.40s %11s %11s %11s %11s %9s%s\n", m->name, o[0], o[1], o[2], o[3], f,
             m->searched ? "" : "  (kept)");
  }
  cli_info(&common, "\n%-52s %11s %11s %21s\n", "image (the maps that sample it)", "original", "chosen",
           "RGBA8 + mips, MiB");
  for (int t = 0; t < R.nimages; t++) {
    const jnd_texres_image *im = &R.images[t];
    char users[256] = "", o[2][24];
    size_t n = 0;
    for (int i = 0; i < R.nmaps && n < sizeof users; i++)
      if (R.maps[i].image == t)
        n += (size_t)snprintf(users + n, sizeof users - n, "%s%s", n ? ", " : "", R.maps[i].name);
    snprintf(o[0], 24, "%dx%d", im->orig[0], im->orig[1]);
    snprintf(o[1], 24, "%dx%d", im->chosen[0], im->chosen[1]);
    cli_info(&common, "%-52.52s %11s %11s %9.3f -> %8.3f\n", users, o[0], o[1],
             im->bytes_before[JND_TEX_RGBA8] / 1048576.0, im->bytes_after[JND_TEX_RGBA8] / 1048576.0);
  }
  cli_info(&common,
           "memory (%d unique image%s, RGBA8 + mips): %.2f MiB -> %.2f MiB (-%.0f%%); block-compressed %.2f MiB -> "
           "%.2f MiB\n",
           R.nimages, R.nimages == 1 ? "" : "s", bb / 1048576.0, ba / 1048576.0,
           bb ? 100.0 * (1.0 - (double)ba / bb) : 0, R.block_before_bytes / 1048576.0,
           R.block_after_bytes / 1048576.0);
  cli_info(&common, "views above P=%.2f: %.0f%% of %d (criterion <= %.0f%%; chosen with P=%.3f)%s", p.judge.criterion.p,
           100 * R.views.fraction_above, R.nviews, 100 * p.judge.criterion.q, R.choice_p, R.views.pass ? "" : "  FAILS");
  if (R.verify_views)
    cli_info(&common, "; held out: %.0f%% of %d%s", 100 * R.verify.fraction_above, R.verify_views,
             R.verify.pass ? "" : "  FAILS the criterion");
  cli_info(&common, "\n%d evaluations, %d renderings, %.1f s on %s\n", R.evaluations, R.renderings,
           jnd_seconds() - t0, R.renderer);
  rc = (R.views.pass && (R.verify_views == 0 || R.verify.pass)) ? EXIT_OK : EXIT_ABOVE;
out:
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  cJSON_Delete(written);
  jnd_texres_result_free(&R);
  free(views);
  jnd_scene_free(scene);
  return rc;
}

const jnd_command jnd_cmd_texres = {"texres", "the smallest texture resolution nobody notices (000)", run};
