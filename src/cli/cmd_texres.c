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
      "the smallest resolution a viewer does not notice (Wolski et al. 2019, 000 §4-§9):\n"
      "candidates are the original and its power-of-two reductions, each rendered from N\n"
      "sampled views and compared with the full-resolution rendering by the vision model;\n"
      "a combination passes when at most a fraction Q of the views have a pooled\n"
      "probability of detection above P. Sizes never exceed the mip-usage bound (the\n"
      "finest mip level any pixel samples, 000 §4). Writes OUTDIR/texres.json, the resized\n"
      "maps and a copy of the model pointing at them (inputs are never touched), the\n"
      "worst view's heatmap, and the baseColor x normal matrices (000 Fig. 13).\n"
      "See docs/texres.md.\n"
      "\n"
      "viewing condition:\n"
      "  --views N           sampled views for the choice (8)\n"
      "  --verify-views M    then check the choice on M other views (held out; 0)\n"
      "  --coverage F        fraction of the image height the object fills (0.8)\n"
      "  --distance D        camera distance in object units (instead of --coverage)\n"
      "  --size WxH          rendering size in pixels (384x384)\n"
      "  --fov DEG           vertical field of view (45)\n"
      "  --lights N          directional lights per view (1)\n"
      "  --seed S            view and light sampling seed (1)\n"
      "  --env FILE          environment map (.hdr/.exr; default the built-in studio)\n"
      "%s"
      "\n"
      "search:\n"
      "  --sizes LIST        candidate sizes (longer side, pixels), e.g. 1024,768,512\n"
      "                      (default: the original and its halvings down to --min-size)\n"
      "  --min-size N        floor of the halvings (32)\n"
      "  --maps LIST         maps to search: MATERIAL/SLOT or slot names (default all)\n"
      "  --p P               a view is above when its pooled P exceeds P (0.2, 000 §9)\n"
      "  --q Q               at most this fraction of views above P (0.1, 000 §9)\n"
      "  --pool pNN          pooling percentile (p93, 000 §6)\n"
      "  --calibration FILE  a `jnd calibrate` file: pooling and JND transform (000 §7)\n"
      "  --no-matrix         skip the baseColor x normal matrices\n"
      "  --quick-matrix      only candidates down to each map's first size that fails on\n"
      "                      its own (smaller ones fail anyway; default: every pair)\n"
      "  --anisotropy N      renderer anisotropic filtering (8)\n"
      "  --samples N         MSAA samples (4)\n"
      "  --platform P        EGL platform: auto, device, surfaceless\n"
      "  --map-size N        side of the builtin asset's maps (2048)\n"
      "\n"
      "outputs:\n"
      "  -o, --output DIR    the folder (created): texres.json, worst_view.png,\n"
      "                      matrix_N.png, model/ (a glTF/GLB copy with resized maps) or\n"
      "                      maps/ (OBJ, builtin: the resized maps as PNG)\n"
      "  --json FILE|-       also write the report there\n"
      "  --timings           add wall-clock times to the report\n"
      "  --threads N         model worker threads\n"
      "  --quiet             nothing on stderr but errors\n"
      "\n"
      "Exit status: 0; 1 when the choice fails the criterion on the views (or the\n"
      "held-out views); 2 for bad input (one line: jnd: FILE: problem).\n",
      cli_display_help);
}

static int mkdir_p(const char *dir) {
  char buf[4096];
  snprintf(buf, sizeof buf, "%s", dir);
  for (char *p = buf + 1; *p; p++)
    if (*p == '/') {
      *p = 0;
      if (mkdir(buf, 0777) != 0 && errno != EEXIST) return 0;
      *p = '/';
    }
  if (mkdir(buf, 0777) != 0 && errno != EEXIST) return 0;
  struct stat st;
  return stat(buf, &st) == 0 && S_ISDIR(st.st_mode);
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

static void on_progress(void *user, int done, int total) {
  cli_progress *p = user;
  p->total = total;
  cli_progress_step(p, done);
}

/* 000 Fig. 13, drawn by the library (jnd_texres_matrix_figure) */
static int write_matrix_png(const char *path, const jnd_texres_result *r, int t) {
  jnd_image img;
  int ok = jnd_texres_matrix_figure(r, t, &img) == JND_OK && jnd_image_write_png(path, &img, 8) == JND_OK;
  if (!ok) cli_error("%s", jnd_last_error());
  jnd_image_free(&img);
  return ok;
}

static int parse_sizes(const char *v, int *sizes, int max) {
  int n = 0;
  const char *s = v;
  while (*s && n < max) {
    char *e;
    errno = 0;
    long x = strtol(s, &e, 10);
    if (e == s || errno || x < 1 || x > 32768) return -1;
    sizes[n++] = (int)x;
    if (*e == 0) break;
    if (*e != ',') return -1;
    s = e + 1;
  }
  return n;
}

static int run(int argc, char **argv) {
  const char *model = NULL, *dir = NULL, *v, *cal_path = NULL, *pool_name = NULL;
  cli_common common = {0};
  jnd_texres_params p;
  jnd_texres_defaults(&p);
  int sizes[64], map_size = 2048, timings = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (cli_flag(argv, i, "--help") || cli_flag(argv, i, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_display_opt("texres", argc, argv, &i, &p.model.display)) {
    } else if (cli_opt(argc, argv, &i, "-o", &v) || cli_opt(argc, argv, &i, "--output", &v)) {
      dir = v;
    } else if (cli_opt(argc, argv, &i, "--views", &v)) {
      p.views = cli_int("texres", "--views", v, 1, 4096);
    } else if (cli_opt(argc, argv, &i, "--verify-views", &v)) {
      p.verify_views = cli_int("texres", "--verify-views", v, 0, 4096);
    } else if (cli_opt(argc, argv, &i, "--coverage", &v)) {
      p.coverage = cli_double("texres", "--coverage", v, 0.01, 10);
    } else if (cli_opt(argc, argv, &i, "--distance", &v)) {
      p.distance = cli_double("texres", "--distance", v, 1e-9, 1e12);
    } else if (cli_opt(argc, argv, &i, "--size", &v)) {
      double w, h;
      cli_pair("texres", "--size", v, &w, &h);
      if (w != floor(w) || h != floor(h) || w < 16 || h < 16 || w > 8192 || h > 8192) {
        cli_error("texres: --size: '%s' is not WxH with 16..8192 pixels", v);
        return EXIT_BAD;
      }
      p.width = (int)w;
      p.height = (int)h;
    } else if (cli_opt(argc, argv, &i, "--fov", &v)) {
      p.fov_y_deg = cli_double("texres", "--fov", v, 0.1, 179);
    } else if (cli_opt(argc, argv, &i, "--lights", &v)) {
      p.lights = cli_int("texres", "--lights", v, 0, JND_MAX_LIGHTS);
    } else if (cli_opt(argc, argv, &i, "--seed", &v)) {
      p.seed = (uint64_t)cli_double("texres", "--seed", v, 0, 9007199254740992.0);
    } else if (cli_opt(argc, argv, &i, "--env", &v)) {
      p.env_path = v;
    } else if (cli_opt(argc, argv, &i, "--sizes", &v)) {
      p.nsizes = parse_sizes(v, sizes, 64);
      if (p.nsizes < 1) {
        cli_error("texres: --sizes: '%s' is not a list of sizes in pixels like 1024,512,256", v);
        return EXIT_BAD;
      }
      p.sizes = sizes;
    } else if (cli_opt(argc, argv, &i, "--min-size", &v)) {
      p.min_size = cli_int("texres", "--min-size", v, 1, 32768);
    } else if (cli_opt(argc, argv, &i, "--maps", &v)) {
      p.maps = v;
    } else if (cli_opt(argc, argv, &i, "--p", &v)) {
      p.p_threshold = cli_double("texres", "--p", v, 1e-6, 1 - 1e-6);
    } else if (cli_opt(argc, argv, &i, "--q", &v)) {
      p.max_fraction = cli_double("texres", "--q", v, 0, 0.999);
    } else if (cli_opt(argc, argv, &i, "--pool", &v)) {
      pool_name = v;
    } else if (cli_opt(argc, argv, &i, "--calibration", &v)) {
      cal_path = v;
    } else if (cli_flag(argv, i, "--no-matrix")) {
      p.matrix = 0;
    } else if (cli_flag(argv, i, "--quick-matrix")) {
      p.matrix = 1;
    } else if (cli_opt(argc, argv, &i, "--anisotropy", &v)) {
      p.anisotropy = cli_int("texres", "--anisotropy", v, 1, 16);
    } else if (cli_opt(argc, argv, &i, "--samples", &v)) {
      p.samples = cli_int("texres", "--samples", v, 1, 64);
    } else if (cli_opt(argc, argv, &i, "--platform", &v)) {
      p.platform = v;
    } else if (cli_opt(argc, argv, &i, "--map-size", &v)) {
      map_size = cli_int("texres", "--map-size", v, 8, 8192);
    } else if (cli_opt(argc, argv, &i, "--threads", &v)) {
      p.model.threads = common.threads = cli_threads("texres", v);
    } else if (cli_flag(argv, i, "--timings")) {
      timings = 1;
    } else if (cli_common_opt(argc, argv, &i, &common)) {
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown("texres", a);
    } else if (!model) {
      model = a;
    } else {
      return cli_unknown("texres", a);
    }
  }
  if (!model) {
    cli_error("texres: give a MODEL (a .gltf/.glb/.obj file or builtin); jnd texres --help");
    return EXIT_BAD;
  }
  if (!dir) {
    cli_error("texres: give an output folder with -o OUTDIR; jnd texres --help");
    return EXIT_BAD;
  }
  if (cal_path && jnd_calibration_load(cal_path, &p.calibration) != JND_OK) {
    cli_error("%s", jnd_last_error());
    return EXIT_BAD;
  }
  if (pool_name) {
    jnd_pooling pool;
    if (jnd_pooling_parse(pool_name, &pool) != JND_OK || pool.kind != JND_POOL_PERCENTILE) {
      cli_error("texres: --pool: '%s' is not a percentile like p93", pool_name);
      return EXIT_BAD;
    }
    p.calibration.percentile = pool.percentile;
  }
  p.model.beta = p.calibration.beta;

  double t0 = cli_now();
  jnd_scene *scene = NULL;
  jnd_status st;
  int is_builtin = strncmp(model, "builtin", 7) == 0 && (!model[7] || model[7] == ':');
  if (is_builtin) {
    jnd_builtin_params bp;
    jnd_builtin_defaults(&bp);
    bp.map_size = map_size;
    bp.shape = strcmp(model, "builtin:sphere") == 0;
    st = jnd_scene_builtin(&bp, &scene);
  } else {
    st = jnd_scene_load(model, &scene);
  }
  if (st != JND_OK) {
    cli_error("%s", jnd_last_error());
    return EXIT_BAD;
  }
  for (int i = 0; i < jnd_scene_warning_count(scene); i++) cli_info(&common, "jnd: warning: %s\n", jnd_scene_warning(scene, i));
  if (jnd_scene_map_count(scene) == 0) {
    cli_error("%s: the asset has no texture maps (nothing to choose)", model);
    jnd_scene_free(scene);
    return EXIT_BAD;
  }
  int rc = EXIT_BAD;
  cJSON *report = NULL, *written = NULL;
  jnd_texres_result R = {0};
  cli_progress prog;
  cli_progress_start(&prog, &common, "texres", 1);
  p.progress = on_progress;
  p.progress_user = &prog;
  /* bad --maps before creating anything */
  if (!mkdir_p(dir)) {
    cli_error("%s: cannot create the folder (%s)", dir, strerror(errno));
    goto out;
  }
  st = jnd_texres_run(scene, &p, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  double t_search = cli_now() - t0;

  char path[4400], model_out[4400] = "";
  const char *ext = strrchr(model, '.');
  int gltf = ext && (strcasecmp(ext, ".gltf") == 0 || strcasecmp(ext, ".glb") == 0);
  if (!is_builtin && gltf) {
    char mdir[4200];
    snprintf(mdir, sizeof mdir, "%s/model", dir);
    if (!mkdir_p(mdir) || jnd_texres_write_model(scene, model, mdir, model_out, sizeof model_out) != JND_OK) {
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
      int ok = mkdir_p(mdir) && jnd_scene_map_get(scene, m->map, 0, &im) == JND_OK &&
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
  if (cal_path) cJSON_AddStringToObject(in, "calibration", cal_path);
  cJSON_AddNumberToObject(par, "views", p.views);
  cJSON_AddNumberToObject(par, "verify_views", p.verify_views);
  cJSON_AddNumberToObject(par, "seed", (double)p.seed);
  cJSON_AddNumberToObject(par, "width", p.width);
  cJSON_AddNumberToObject(par, "height", p.height);
  cJSON_AddNumberToObject(par, "coverage", p.coverage);
  if (p.distance > 0) cJSON_AddNumberToObject(par, "distance", p.distance);
  cJSON_AddNumberToObject(par, "fov_y_deg", p.fov_y_deg);
  cJSON_AddNumberToObject(par, "lights", p.lights);
  cJSON_AddNumberToObject(par, "p", p.p_threshold);
  cJSON_AddNumberToObject(par, "q", p.max_fraction);
  cJSON_AddNumberToObject(par, "min_size", p.min_size);
  cJSON *cal = cJSON_AddObjectToObject(par, "calibration");
  cJSON_AddNumberToObject(cal, "percentile", p.calibration.percentile);
  cJSON_AddNumberToObject(cal, "scale", p.calibration.scale);
  cJSON_AddNumberToObject(cal, "bias", p.calibration.bias);
  cJSON_AddNumberToObject(cal, "beta", p.calibration.beta);
  cJSON_AddItemToObject(par, "display", cli_display_json(&p.model.display));
  cJSON_AddNumberToObject(par, "anisotropy", p.anisotropy);
  cJSON_AddNumberToObject(par, "samples", p.samples);

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
    cJSON *cand = cJSON_AddArrayToObject(o, "candidates"), *ser = cJSON_AddArrayToObject(o, "series");
    for (int j = 0; j < m->ncand; j++) {
      cJSON_AddItemToArray(cand, pair(m->cand[j]));
      cJSON_AddItemToArray(ser, isfinite(m->series[j]) ? cJSON_CreateNumber(m->series[j]) : cJSON_CreateNull());
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
    cJSON_AddItemToObject(o, "bytes_before", bytes_json(m->bytes_before));
    cJSON_AddItemToObject(o, "bytes_after", bytes_json(m->bytes_after));
    cJSON_AddItemToArray(jm, o);
  }
  /* memory: RGBA8 with mip chains is the headline, block formats beside it */
  cJSON *mem = cJSON_AddObjectToObject(res, "memory");
  size_t bb = R.before_bytes[JND_TEX_RGBA8], ba = R.after_bytes[JND_TEX_RGBA8];
  cJSON_AddNumberToObject(mem, "before_bytes", (double)bb);
  cJSON_AddNumberToObject(mem, "after_bytes", (double)ba);
  cJSON_AddNumberToObject(mem, "reduction", bb ? 1.0 - (double)ba / bb : 0);
  size_t blk_b = 0, blk_a = 0;
  for (int i = 0; i < R.nmaps; i++) {
    jnd_tex_format f = jnd_slot_block_format(R.maps[i].slot, R.maps[i].channels);
    blk_b += R.maps[i].bytes_before[f];
    blk_a += R.maps[i].bytes_after[f];
  }
  cJSON_AddNumberToObject(mem, "block_before_bytes", (double)blk_b);
  cJSON_AddNumberToObject(mem, "block_after_bytes", (double)blk_a);
  cJSON_AddItemToObject(mem, "formats_before", bytes_json(R.before_bytes));
  cJSON_AddItemToObject(mem, "formats_after", bytes_json(R.after_bytes));
  cJSON *pm = cJSON_AddArrayToObject(mem, "materials");
  for (int mat = 0; mat < jnd_scene_material_count(scene); mat++) {
    size_t b0 = 0, a0 = 0;
    int any = 0;
    for (int i = 0; i < R.nmaps; i++)
      if (R.maps[i].material == mat) any = 1, b0 += R.maps[i].bytes_before[0], a0 += R.maps[i].bytes_after[0];
    if (!any) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "material", jnd_scene_material_name(scene, mat));
    cJSON_AddNumberToObject(o, "before_bytes", (double)b0);
    cJSON_AddNumberToObject(o, "after_bytes", (double)a0);
    cJSON_AddNumberToObject(o, "reduction", b0 ? 1.0 - (double)a0 / b0 : 0);
    cJSON_AddItemToArray(pm, o);
  }
  cJSON *jv = cJSON_AddObjectToObject(res, "views");
  cJSON_AddNumberToObject(jv, "count", R.nviews);
  cJSON *pv = cJSON_AddArrayToObject(jv, "p");
  for (int i = 0; i < R.nviews; i++) cJSON_AddItemToArray(pv, cJSON_CreateNumber(R.view_p[i]));
  cJSON_AddNumberToObject(jv, "fraction_above", R.fraction_above);
  cJSON_AddBoolToObject(jv, "passes", R.passes);
  cJSON_AddNumberToObject(jv, "worst_view", R.worst_view);
  cJSON_AddStringToObject(jv, "heatmap", "worst_view.png");
  if (R.verify_views > 0) {
    cJSON *vv = cJSON_AddObjectToObject(res, "verify");
    cJSON_AddNumberToObject(vv, "views", R.verify_views);
    cJSON_AddNumberToObject(vv, "fraction_above", R.verify_fraction);
    cJSON_AddBoolToObject(vv, "passes", R.verify_passes);
    cJSON *vp = cJSON_AddArrayToObject(vv, "p");
    for (int i = 0; i < R.verify_views; i++) cJSON_AddItemToArray(vp, cJSON_CreateNumber(R.verify_p[i]));
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
  if (model_out[0]) cJSON_AddStringToObject(res, "model", model_out);
  cJSON_AddItemToObject(res, "map_files", written);
  written = NULL;
  cJSON_AddNumberToObject(res, "ppd", R.ppd);
  cJSON_AddNumberToObject(res, "evaluations", R.evaluations);
  cJSON_AddNumberToObject(res, "renderings", R.renderings);
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "search_s", t_search);
    cJSON_AddNumberToObject(t, "total_s", cli_now() - t0);
  }
  snprintf(path, sizeof path, "%s/texres.json", dir);
  if (cli_report_write(report, path) != EXIT_OK) goto out;
  if (common.json_path && cli_report_write(report, common.json_path) != EXIT_OK) goto out;

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
  cli_info(&common, "memory (RGBA8 + mips): %.2f MB -> %.2f MB (-%.0f%%); block-compressed %.2f MB -> %.2f MB\n",
           bb / 1048576.0, ba / 1048576.0, bb ? 100.0 * (1.0 - (double)ba / bb) : 0, blk_b / 1048576.0,
           blk_a / 1048576.0);
  cli_info(&common, "views above P=%.2f: %.0f%% of %d (criterion <= %.0f%%)%s", p.p_threshold, 100 * R.fraction_above,
           R.nviews, 100 * p.max_fraction, R.passes ? "" : "  FAILS");
  if (R.verify_views)
    cli_info(&common, "; held out: %.0f%% of %d%s", 100 * R.verify_fraction, R.verify_views,
             R.verify_passes ? "" : "  FAILS the criterion");
  cli_info(&common, "\n%d evaluations, %d renderings, %.1f s on %s\n", R.evaluations, R.renderings,
           cli_now() - t0, R.renderer);
  rc = (R.passes && (R.verify_views == 0 || R.verify_passes)) ? EXIT_OK : EXIT_ABOVE;
out:
  cJSON_Delete(report);
  cJSON_Delete(written);
  jnd_texres_result_free(&R);
  jnd_scene_free(scene);
  return rc;
}

const jnd_command jnd_cmd_texres = {"texres", "the smallest texture resolution nobody notices (000)", run};
