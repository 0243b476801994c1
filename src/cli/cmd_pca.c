/* jnd pca MAP... -o OUTDIR — a texture set in fewer channels (001). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd pca MAP... -o OUTDIR [options]\n"
      "       jnd pca [MAP...] --model FILE.glb --material NAME -o OUTDIR [options]\n"
      "\n"
      "Packs the maps of one material (albedo, normal, roughness, ...) as a (w*h) x C\n"
      "matrix, decorrelates it by PCA (Wronski, 001) and keeps the first components,\n"
      "each at its own resolution and bit depth. Writes the component images, a\n"
      "(C) x (K+1) reconstruction matrix (K+1 multiply-adds per channel in a shader),\n"
      "and PSNR per channel, with and without GPU block compression.\n"
      "\n"
      "Maps: PNG, JPEG, HDR, EXR of one size (others are resampled to the largest,\n"
      "with a warning; a different shape is an error). Values are used as stored.\n"
      "Channels are named MAP.r/.g/.b/.a after the file stem less the prefix all maps\n"
      "share (Default_albedo.jpg -> albedo.r); a grey map stored as RGB counts once\n"
      "and is named MAP; constant channels are left out.\n"
      "\n"
      "what to keep:\n"
      "  --components K      keep the first K components (default: all)\n"
      "  --bits B[,B...]     8 (default) or 16 bits for every kept component, or a\n"
      "                      list per component (the last repeats): 16,16,8\n"
      "  --resolutions LIST  size divisor per component, powers of two up to 8:\n"
      "                      1,1,1,1,2,2,2,4,4 = 4 at full, 3 at half, 2 at quarter\n"
      "                      (the last repeats; default all 1). Box down, Lanczos-3 up.\n"
      "  --psnr DB           the smallest storage (K, resolutions, bits) whose every\n"
      "                      channel reaches DB dB PSNR (chooses bits and resolutions)\n"
      "  --max-scale S       coarsest resolution --psnr may use: 1/2^S (default 2)\n"
      "  --max-p P           the smallest storage whose rendered difference a viewer\n"
      "                      notices with probability <= P (pooled p93 per view) in all\n"
      "                      but --max-fraction of the views; needs --model (with a\n"
      "                      model and no other criterion: --max-p 0.2)\n"
      "\n"
      "rendered visibility (the material re-rendered with the reconstructed maps):\n"
      "  --model FILE.glb    a model using the set (glTF, GLB, OBJ, or builtin);\n"
      "                      without MAP files the set is the material's own maps\n"
      "  --material NAME     the material of --model that uses the set\n"
      "  --slot FILE=SLOT    the material slot a MAP file replaces: baseColor,\n"
      "                      metallicRoughness, normal, occlusion, emissive (default:\n"
      "                      guessed from the name: albedo/color, normal, metal/rough,\n"
      "                      ao/occlusion, emissive)\n"
      "  --max-fraction Q    fraction of views allowed above --max-p (default 0.1)\n"
      "  --views N           sampled views (default 8)\n"
      "  --size WxH          rendered image size (default 512x512)\n"
      "  --coverage F        fraction of the image height the object fills (0.8)\n"
      "  --seed S            seed of the view sampling (1)\n"
      "  --map-size N        side of the builtin asset's maps (2048)\n"
      "  --platform P        EGL platform: device or surfaceless (default: auto)\n"
      "  --display NAME ...  the display the renderings are seen on (jnd diff --help)\n"
      "\n"
      "how to decompose:\n"
      "  --channels SPEC     pick channels per map: normal=rg,metalRoughness=gb\n"
      "  --weight SPEC       importance per map or channel (001): albedo=2,height=0.75\n"
      "                      (no standardisation: ranges already carry importance)\n"
      "\n"
      "outputs:\n"
      "  -o, --out OUTDIR    folder for pca.json, component_NN.png, contribution.png\n"
      "  --write-maps        also write each map as reconstructed: OUTDIR/MAP.png\n"
      "  --no-bc             skip the block-compression comparison (faster)\n"
      "  --json FILE|-       also write the JSON report there (- for stdout)\n"
      "  --timings           add wall-clock seconds per stage to the JSON (they vary)\n"
      "  --quiet             nothing on stderr but errors\n"
      "\n"
      "pca.json: .result.energy[] (per component, descending), .result.total_variance,\n"
      ".result.channels[] {name, psnr_db, psnr_float_db, psnr_bc4_db, psnr_bc1_db,\n"
      "psnr_plain_bc_db}, .result.storage_bytes, .result.storage_maps_8bit_bytes (the\n"
      "original maps), .result.rendered {p_per_view, pass, block_compressed, search}\n"
      "with --model, .result.reconstruction (C rows of K+1:\n"
      "channel c = sum_k R[c][k]*q_k + R[c][K], q_k the stored component value 0..1).\n"
      "PSNR is 10*log10(1/MSE) on values 0..1; 999 stands for an exact reconstruction.\n"
      "\n"
      "examples:\n"
      "  jnd pca Default_*.jpg -o out --components 5\n"
      "  jnd pca albedo.png normal.png rough.png -o out --psnr 40 --weight albedo=2\n"
      "  jnd pca --model controller.glb --material body -o out --max-p 0.2\n"
      "\n"
      "Exit status: 0, 2 for bad input.\n");
}

static double json_db(double db) { return isfinite(db) ? db : 999.0; }

static int make_dir(const char *path) {
  if (mkdir(path, 0777) == 0 || errno == EEXIST) {
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return 1;
  }
  cli_error("%s: cannot create the output folder (%s)", path, strerror(errno));
  return 0;
}

/* "1,1,2,4" → scale exponents; the last repeats */
static int parse_resolutions(const char *v, int *scale, int *n) {
  char buf[512];
  snprintf(buf, sizeof buf, "%s", v);
  char *save = NULL;
  *n = 0;
  for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int d = cli_int("pca", "--resolutions", tok, 1, 1 << JND_PCA_MAX_SCALE), s = 0;
    while ((1 << s) < d) s++;
    if ((1 << s) != d || *n >= JND_PCA_MAX_CHANNELS) {
      cli_error("pca: --resolutions: %d is not a power of two up to %d (or too many)", d, 1 << JND_PCA_MAX_SCALE);
      return 0;
    }
    scale[(*n)++] = s;
  }
  return *n > 0;
}

/* "8" or "16,16,8" */
static int parse_bits(const char *v, int *bits, int *n) {
  char buf[512];
  snprintf(buf, sizeof buf, "%s", v);
  char *save = NULL;
  *n = 0;
  for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int b = cli_int("pca", "--bits", tok, 8, 16);
    if ((b != 8 && b != 16) || *n >= JND_PCA_MAX_CHANNELS) {
      cli_error("pca: --bits: %d (8 or 16 per component)", b);
      return 0;
    }
    bits[(*n)++] = b;
  }
  return *n > 0;
}

static cJSON *numbers(const double *v, int n) {
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; i < n; i++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
  return a;
}

/* pooled P per view of one rendered measurement */
static cJSON *visibility_json(const jnd_pca_visibility *v) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddItemToObject(o, "p_per_view", numbers(v->p, v->views));
  cJSON_AddNumberToObject(o, "views_above", v->above);
  cJSON_AddNumberToObject(o, "p_criterion", v->p_criterion);
  cJSON_AddBoolToObject(o, "pass", v->pass);
  return o;
}

static void print_views(const cli_common *c, const char *label, const jnd_pca_visibility *v) {
  cli_info(c, "  %-18s P per view:", label);
  for (int i = 0; i < v->views; i++) cli_info(c, " %.3f", v->p[i]);
  cli_info(c, "  (%d above, %s)\n", v->above, v->pass ? "passes" : "fails");
}

/* "FILE=SLOT" options → the slot of each map path */
static int slots_for_maps(const jnd_texset *set, const char *const *paths, const char *const *slot_specs, int nspecs,
                          jnd_map_slot *slots) {
  for (int i = 0; i < set->nmaps; i++) {
    int found = 0;
    for (int k = 0; k < nspecs && !found; k++) {
      const char *eq = strrchr(slot_specs[k], '=');
      if (!eq) {
        cli_error("pca: --slot: '%s' is not FILE=SLOT", slot_specs[k]);
        return 0;
      }
      size_t n = (size_t)(eq - slot_specs[k]);
      const char *base = strrchr(paths[i], '/');
      base = base ? base + 1 : paths[i];
      if ((strlen(paths[i]) == n && strncmp(paths[i], slot_specs[k], n) == 0) ||
          (strlen(base) == n && strncmp(base, slot_specs[k], n) == 0)) {
        int s = 0;
        while (s < JND_MAP_SLOTS && strcmp(jnd_map_slot_name((jnd_map_slot)s), eq + 1) != 0) s++;
        if (s == JND_MAP_SLOTS) {
          cli_error("pca: --slot: '%s' is not a slot (baseColor, metallicRoughness, normal, occlusion, emissive)",
                    eq + 1);
          return 0;
        }
        slots[i] = (jnd_map_slot)s;
        found = 1;
      }
    }
    if (!found && !jnd_pca_slot_guess(set->maps[i].name, &slots[i])) {
      cli_error("%s: no material slot fits this map's name (give --slot FILE=SLOT)", paths[i]);
      return 0;
    }
  }
  return 1;
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  const char *paths[JND_PCA_MAX_MAPS], *outdir = NULL, *channels = NULL, *weight_spec = NULL;
  const char *model = NULL, *material = NULL, *res_spec = NULL;
  int npaths = 0, components = -1, max_scale = 2, no_bc = 0, timings = 0, write_maps = 0;
  int bits[JND_PCA_MAX_CHANNELS], nbits = 0;
  double t_read = 0, t_analyse = 0, t_choose = 0, t_encode = 0, t_bc = 0;
  double psnr_target = -1, max_p = 0.2;
  int has_max_p = 0;
  jnd_pca_render_params rp;
  jnd_pca_render_defaults(&rp);
  const char *slot_specs[JND_PCA_MAX_MAPS];
  int nslot_specs = 0;
  for (int i = 1; i < argc; i++) {
    const char *v;
    if (cli_flag(argv, i, "--help") || cli_flag(argv, i, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_opt(argc, argv, &i, "--out", &v) || cli_opt(argc, argv, &i, "-o", &v)) {
      outdir = v;
    } else if (cli_opt(argc, argv, &i, "--components", &v)) {
      components = cli_int("pca", "--components", v, 0, JND_PCA_MAX_CHANNELS);
    } else if (cli_opt(argc, argv, &i, "--bits", &v)) {
      if (!parse_bits(v, bits, &nbits)) return EXIT_BAD;
    } else if (cli_opt(argc, argv, &i, "--resolutions", &v)) {
      res_spec = v;
    } else if (cli_opt(argc, argv, &i, "--psnr", &v)) {
      psnr_target = cli_double("pca", "--psnr", v, 1, 150);
    } else if (cli_opt(argc, argv, &i, "--max-scale", &v)) {
      max_scale = cli_int("pca", "--max-scale", v, 0, JND_PCA_MAX_SCALE);
    } else if (cli_opt(argc, argv, &i, "--max-p", &v)) {
      max_p = cli_double("pca", "--max-p", v, 0, 1);
      has_max_p = 1;
    } else if (cli_opt(argc, argv, &i, "--max-fraction", &v)) {
      rp.max_fraction = cli_double("pca", "--max-fraction", v, 0, 0.99);
    } else if (cli_opt(argc, argv, &i, "--views", &v)) {
      rp.views = cli_int("pca", "--views", v, 1, JND_PCA_MAX_VIEWS);
    } else if (cli_opt(argc, argv, &i, "--size", &v)) {
      double w = 0, h = 0;
      cli_pair("pca", "--size", v, &w, &h);
      if (w < 16 || h < 16 || w > 8192 || h > 8192 || w != (int)w || h != (int)h) {
        cli_error("pca: --size: '%s' is not WxH with 16..8192 pixels", v);
        return EXIT_BAD;
      }
      rp.width = (int)w;
      rp.height = (int)h;
    } else if (cli_opt(argc, argv, &i, "--coverage", &v)) {
      rp.coverage = cli_double("pca", "--coverage", v, 0.01, 10);
    } else if (cli_opt(argc, argv, &i, "--seed", &v)) {
      rp.seed = (uint64_t)cli_int("pca", "--seed", v, 0, 2147483647);
    } else if (cli_opt(argc, argv, &i, "--map-size", &v)) {
      rp.builtin_map_size = cli_int("pca", "--map-size", v, 8, 8192);
    } else if (cli_opt(argc, argv, &i, "--platform", &v)) {
      rp.platform = v;
    } else if (cli_opt(argc, argv, &i, "--slot", &v)) {
      if (nslot_specs >= JND_PCA_MAX_MAPS) {
        cli_error("pca: at most %d --slot options", JND_PCA_MAX_MAPS);
        return EXIT_BAD;
      }
      slot_specs[nslot_specs++] = v;
    } else if (cli_display_opt("pca", argc, argv, &i, &rp.model.display)) {
      continue;
    } else if (cli_opt(argc, argv, &i, "--model", &v)) {
      model = v;
    } else if (cli_opt(argc, argv, &i, "--material", &v)) {
      material = v;
    } else if (cli_opt(argc, argv, &i, "--channels", &v)) {
      channels = v;
    } else if (cli_opt(argc, argv, &i, "--weight", &v)) {
      weight_spec = v;
    } else if (cli_flag(argv, i, "--write-maps")) {
      write_maps = 1;
    } else if (cli_flag(argv, i, "--timings")) {
      timings = 1;
    } else if (cli_flag(argv, i, "--no-bc")) {
      no_bc = 1;
    } else if (cli_common_opt(argc, argv, &i, &common)) {
    } else if (argv[i][0] == '-' && argv[i][1]) {
      return cli_unknown("pca", argv[i]);
    } else if (npaths < JND_PCA_MAX_MAPS) {
      paths[npaths++] = argv[i];
    } else {
      cli_error("pca: at most %d maps", JND_PCA_MAX_MAPS);
      return EXIT_BAD;
    }
  }
  if ((npaths == 0 && !model) || !outdir) {
    cli_error("pca: needs maps (or --model) and -o OUTDIR (jnd pca --help)");
    return EXIT_BAD;
  }
  int criteria = (components >= 0) + (psnr_target > 0) + has_max_p;
  if (criteria > 1) {
    cli_error("pca: give one of --components, --psnr, --max-p");
    return EXIT_BAD;
  }
  if (model && criteria == 0) has_max_p = 1;   /* with a model, --max-p 0.2 is the default */
  if (has_max_p && !model) {
    cli_error("pca: --max-p needs --model FILE.glb and --material NAME");
    return EXIT_BAD;
  }
  if (model && !material) {
    cli_error("pca: --model needs --material NAME");
    return EXIT_BAD;
  }
  if (nslot_specs && !(model && npaths)) {
    cli_error("pca: --slot needs MAP files and --model");
    return EXIT_BAD;
  }
  rp.max_p = max_p;
  int scales[JND_PCA_MAX_CHANNELS] = {0}, nscales = 0;
  if (res_spec && !parse_resolutions(res_spec, scales, &nscales)) return EXIT_BAD;

  int rc = EXIT_BAD;
  jnd_pca_render *rr = NULL;
  jnd_pca_search_log *slog = NULL;
  jnd_map_slot slots[JND_PCA_MAX_MAPS];
  size_t orig_bytes = 0;
  jnd_pca_visibility vis, vis_bc[3];
  size_t bytes_bc[3] = {0};
  double t_render = 0;
  memset(&vis, 0, sizeof vis);
  memset(vis_bc, 0, sizeof vis_bc);
  char labels[JND_PCA_MAX_MAPS][160];
  jnd_texset set = {0};
  jnd_pca_encoded enc = {0}, encf = {0};
  jnd_pca_bc_report bc;
  cJSON *report = NULL;
  cli_progress prog;
  cli_progress_start(&prog, &common, "pca", 6);
  double t0 = cli_now();
  if (model && jnd_pca_render_open(model, material, &rp, &rr) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("%s", jnd_last_error());
    goto out;
  }
  if ((npaths ? jnd_texset_read(paths, npaths, channels, &set)
              : jnd_pca_render_material_set(rr, channels, &set, slots, &orig_bytes)) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("%s", jnd_last_error());
    goto out;
  }
  for (int i = 0; i < set.nmaps && !npaths; i++) {   /* the material's maps are named MATERIAL/SLOT */
    snprintf(labels[i], sizeof labels[i], "%s/%s", material, set.maps[i].name);
    paths[i] = labels[i];
  }
  if (model && npaths && !slots_for_maps(&set, paths, slot_specs, nslot_specs, slots)) {
    cli_progress_end(&prog);
    goto out;
  }
  cli_progress_step(&prog, 1);
  t_read = cli_now() - t0;
  if (model) {
    double tr = cli_now();
    if (jnd_pca_render_bind(rr, &set, slots) != JND_OK) {
      cli_progress_end(&prog);
      cli_error("%s", jnd_last_error());
      goto out;
    }
    t_render += cli_now() - tr;
  }
  for (int i = 0; i < set.nmaps; i++) {
    const jnd_texset_map *m = &set.maps[i];
    if (m->resampled)
      cli_info(&common, "\njnd: warning: %s: %d x %d resampled to %d x %d (Lanczos-3)\n", paths[i], m->file_w,
               m->file_h, set.w, set.h);
  }
  double weights[JND_PCA_MAX_CHANNELS];
  if (jnd_texset_parse_weights(&set, weight_spec, weights) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("pca: %s", jnd_last_error());
    goto out;
  }
  if (!make_dir(outdir)) goto out;
  jnd_pca pca;
  if (jnd_pca_analyse(&set, weights, &pca) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("pca: %s", jnd_last_error());
    goto out;
  }
  cli_progress_step(&prog, 2);
  t_analyse = cli_now() - t0 - t_read;
  int C = set.c;
  jnd_pca_encoding e;
  jnd_pca_encoding_default(&pca, &e);
  const char *criterion = "all";
  if (components >= 0) {
    e.components = components > C ? C : components;
    criterion = "components";
  }
  for (int k = 0; k < C; k++) {
    e.bits[k] = nbits ? bits[k < nbits ? k : nbits - 1] : 8;
    e.scale[k] = nscales ? scales[k < nscales ? k : nscales - 1] : 0;
  }
  if (psnr_target > 0) {
    criterion = "psnr";
    if (jnd_pca_choose_psnr(&set, &pca, psnr_target, max_scale, &e) != JND_OK) {
      cli_progress_end(&prog);
      cli_error("pca: %s", jnd_last_error());
      goto out;
    }
  }
  if (has_max_p) {
    criterion = "max_p";
    double tr = cli_now();
    slog = calloc(1, sizeof *slog);
    if (!slog || jnd_pca_choose_rendered(rr, &set, &pca, max_scale, &e, &vis, slog) != JND_OK) {
      cli_progress_end(&prog);
      cli_error("%s", slog ? jnd_last_error() : "pca: out of memory");
      goto out;
    }
    t_render += cli_now() - tr;
  }
  cli_progress_step(&prog, 3);
  t_choose = cli_now() - t0 - t_read - t_analyse;
  if (jnd_pca_encode(&set, &pca, &e, &enc) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("pca: %s", jnd_last_error());
    goto out;
  }
  if (model) {
    double tr = cli_now();
    jnd_image rec = {0};
    jnd_status st = JND_OK;
    if (!has_max_p) {   /* the encoding asked for, measured as it is */
      st = jnd_pca_reconstruct(&enc, NULL, &rec);
      if (st == JND_OK) st = jnd_pca_render_measure(rr, &rec, &vis);
      jnd_image_free(&rec);
    }
    for (int v = 0; v < 3 && !no_bc && st == JND_OK; v++) {
      st = jnd_pca_block_compressed(&set, &enc, (jnd_pca_bc_variant)v, &rec, &bytes_bc[v]);
      if (st == JND_OK) st = jnd_pca_render_measure(rr, &rec, &vis_bc[v]);
      jnd_image_free(&rec);
    }
    if (st != JND_OK) {
      cli_progress_end(&prog);
      cli_error("%s", jnd_last_error());
      goto out;
    }
    t_render += cli_now() - tr;
  }
  /* the same K without resizing or quantisation: PSNR "in float" */
  jnd_pca_encoding ef = e;
  for (int k = 0; k < C; k++) {
    ef.scale[k] = 0;
    ef.bits[k] = 0;
  }
  if (jnd_pca_encode(&set, &pca, &ef, &encf) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("pca: %s", jnd_last_error());
    goto out;
  }
  cli_progress_step(&prog, 4);
  t_encode = cli_now() - t0 - t_read - t_analyse - t_choose;
  if (!no_bc && jnd_pca_block_compression(&set, &enc, &bc) != JND_OK) {
    cli_progress_end(&prog);
    cli_error("pca: %s", jnd_last_error());
    goto out;
  }
  cli_progress_step(&prog, 5);
  t_bc = cli_now() - t0 - t_read - t_analyse - t_choose - t_encode;

  /* files */
  int K = enc.enc.components;
  char path[4096];
  for (int k = 0; k < K; k++) {
    snprintf(path, sizeof path, "%s/component_%02d.png", outdir, k);
    if (jnd_image_write_png(path, &enc.comp[k], enc.enc.bits[k] == 16 ? 16 : 8) != JND_OK) {
      cli_progress_end(&prog);
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  {
    jnd_image plot = {0};
    snprintf(path, sizeof path, "%s/contribution.png", outdir);
    jnd_status s = jnd_pca_contribution_plot(&pca, &set, &plot);
    if (s == JND_OK) s = jnd_image_write_png(path, &plot, 8);
    jnd_image_free(&plot);
    if (s != JND_OK) {
      cli_progress_end(&prog);
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  if (write_maps) {
    jnd_image rec = {0};
    if (jnd_pca_reconstruct(&enc, NULL, &rec) != JND_OK) {
      cli_progress_end(&prog);
      cli_error("pca: %s", jnd_last_error());
      goto out;
    }
    for (int i = 0; i < set.nmaps; i++) {
      jnd_image mi = {0};
      snprintf(path, sizeof path, "%s/%s.png", outdir, set.maps[i].name);
      jnd_status s = jnd_texset_map_image(&set, &rec, i, &mi);
      if (s == JND_OK) s = jnd_image_write_png(path, &mi, 8);
      jnd_image_free(&mi);
      if (s != JND_OK) {
        jnd_image_free(&rec);
        cli_progress_end(&prog);
        cli_error("%s", jnd_last_error());
        goto out;
      }
    }
    jnd_image_free(&rec);
  }
  cli_progress_step(&prog, 6);
  cli_progress_end(&prog);

  /* report */
  report = cli_report_new("pca");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON *maps = cJSON_AddArrayToObject(inputs, "maps");
  size_t plain8 = 0;
  for (int i = 0; i < set.nmaps; i++) {
    const jnd_texset_map *m = &set.maps[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "path", paths[i]);
    cJSON_AddStringToObject(o, "name", m->name);
    cJSON_AddNumberToObject(o, "width", m->file_w);
    cJSON_AddNumberToObject(o, "height", m->file_h);
    cJSON_AddNumberToObject(o, "file_channels", m->file_channels);
    char used[5] = {0};
    for (int k = 0; k < m->count; k++) used[k] = "rgba"[m->src[k]];
    cJSON_AddStringToObject(o, "channels_used", used);
    cJSON_AddNumberToObject(o, "identical_channels_left_out", m->duplicates);
    cJSON_AddNumberToObject(o, "constant_channels_left_out", m->constants);
    cJSON_AddBoolToObject(o, "resampled", m->resampled);
    cJSON_AddItemToArray(maps, o);
    plain8 += (size_t)m->file_w * m->file_h * m->file_channels;
  }
  if (model && !npaths) plain8 = orig_bytes;   /* a packed image bound to two slots counts once */
  cJSON_AddStringToObject(params, "criterion", criterion);
  if (psnr_target > 0) cJSON_AddNumberToObject(params, "psnr_db", psnr_target);
  if (psnr_target > 0) cJSON_AddNumberToObject(params, "max_scale", max_scale);
  if (has_max_p) cJSON_AddNumberToObject(params, "max_p", max_p);
  if (model) cJSON_AddStringToObject(params, "model", model);
  if (material) cJSON_AddStringToObject(params, "material", material);
  if (channels) cJSON_AddStringToObject(params, "channels", channels);
  cJSON_AddBoolToObject(params, "standardise", 0);
  cJSON_AddBoolToObject(params, "mean_centre", 1);
  cJSON *wj = cJSON_AddObjectToObject(params, "weights");
  for (int c = 0; c < C; c++) cJSON_AddNumberToObject(wj, set.names[c], weights[c]);

  cJSON_AddNumberToObject(res, "width", set.w);
  cJSON_AddNumberToObject(res, "height", set.h);
  cJSON_AddNumberToObject(res, "channel_count", C);
  cJSON_AddNumberToObject(res, "components_kept", K);
  cJSON *chs = cJSON_AddArrayToObject(res, "channels");
  for (int c = 0; c < C; c++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", set.names[c]);
    cJSON_AddStringToObject(o, "map", set.maps[set.map_of[c]].name);
    cJSON_AddNumberToObject(o, "mean", pca.mean[c]);
    cJSON_AddNumberToObject(o, "weight", pca.weight[c]);
    cJSON_AddNumberToObject(o, "psnr_db", json_db(enc.psnr_db[c]));
    cJSON_AddNumberToObject(o, "psnr_float_db", json_db(encf.psnr_db[c]));
    if (!no_bc) {
      cJSON_AddNumberToObject(o, "psnr_bc4_db", json_db(bc.psnr_pca_bc4_db[c]));
      cJSON_AddNumberToObject(o, "psnr_bc1_db", json_db(bc.psnr_pca_bc1_db[c]));
      cJSON_AddNumberToObject(o, "psnr_plain_bc_db", json_db(bc.psnr_plain_db[c]));
    }
    cJSON_AddItemToArray(chs, o);
  }
  double sv[JND_PCA_MAX_CHANNELS], frac[JND_PCA_MAX_CHANNELS], cum[JND_PCA_MAX_CHANNELS], acc = 0;
  for (int k = 0; k < C; k++) {
    sv[k] = sqrt(pca.energy[k]);
    frac[k] = pca.total_variance > 0 ? pca.energy[k] / pca.total_variance : 0;
    acc += frac[k];
    cum[k] = acc;
  }
  cJSON_AddItemToObject(res, "energy", numbers(pca.energy, C));
  cJSON_AddItemToObject(res, "energy_fraction", numbers(frac, C));
  cJSON_AddItemToObject(res, "cumulative_energy", numbers(cum, C));
  cJSON_AddItemToObject(res, "singular_values", numbers(sv, C));
  cJSON_AddNumberToObject(res, "total_variance", pca.total_variance);
  cJSON_AddNumberToObject(res, "knee", pca.knee);
  double contrib[JND_PCA_MAX_CHANNELS * JND_PCA_MAX_CHANNELS];
  jnd_pca_contribution(&pca, contrib);
  cJSON *cm = cJSON_AddArrayToObject(res, "contribution");
  for (int k = 0; k < C; k++) cJSON_AddItemToArray(cm, numbers(contrib + k * C, C));
  cJSON *comps = cJSON_AddArrayToObject(res, "components");
  for (int k = 0; k < K; k++) {
    cJSON *o = cJSON_CreateObject();
    snprintf(path, sizeof path, "component_%02d.png", k);
    cJSON_AddStringToObject(o, "file", path);
    cJSON_AddNumberToObject(o, "width", enc.comp[k].w);
    cJSON_AddNumberToObject(o, "height", enc.comp[k].h);
    cJSON_AddNumberToObject(o, "divisor", 1 << enc.enc.scale[k]);
    cJSON_AddNumberToObject(o, "bits", enc.enc.bits[k]);
    cJSON_AddNumberToObject(o, "scale", enc.scale[k]);
    cJSON_AddNumberToObject(o, "offset", enc.offset[k]);
    cJSON_AddItemToArray(comps, o);
  }
  cJSON *rm = cJSON_AddArrayToObject(res, "reconstruction");
  for (int c = 0; c < C; c++) cJSON_AddItemToArray(rm, numbers(enc.recon + (size_t)c * (K + 1), K + 1));
  cJSON_AddStringToObject(res, "reconstruction_layout",
                          "C rows (channels, in result.channels order) of K+1: channel c = "
                          "sum_k R[c][k] * q_k + R[c][K], q_k = component k as stored (0..1)");
  cJSON_AddNumberToObject(res, "storage_bytes", (double)enc.storage_bytes);
  cJSON_AddNumberToObject(res, "storage_maps_8bit_bytes", (double)plain8);
  cJSON_AddNumberToObject(res, "storage_channels_8bit_bytes", (double)set.w * set.h * C);
  if (!no_bc) {
    cJSON *b = cJSON_AddObjectToObject(res, "block_compression");
    cJSON_AddNumberToObject(b, "pca_bc4_bytes", (double)bc.bytes_pca_bc4);
    cJSON_AddNumberToObject(b, "pca_bc1_bytes", (double)bc.bytes_pca_bc1);
    cJSON_AddNumberToObject(b, "plain_bc_bytes", (double)bc.bytes_plain);
    cJSON_AddStringToObject(b, "plain_formats", "BC1 for RGB maps, BC4 for grey, BC5 for 2 channels, BC1+BC4 for RGBA");
  }
  if (model) {
    cJSON *rj = cJSON_AddObjectToObject(res, "rendered");
    cJSON_AddStringToObject(rj, "model", model);
    cJSON_AddStringToObject(rj, "material", material);
    cJSON_AddStringToObject(rj, "renderer", jnd_pca_render_description(rr));
    cJSON *sj = cJSON_AddObjectToObject(rj, "slots");
    for (int i = 0; i < set.nmaps; i++) cJSON_AddStringToObject(sj, set.maps[i].name, jnd_map_slot_name(slots[i]));
    cJSON_AddNumberToObject(rj, "views", rp.views);
    cJSON_AddNumberToObject(rj, "width", rp.width);
    cJSON_AddNumberToObject(rj, "height", rp.height);
    cJSON_AddNumberToObject(rj, "coverage", rp.coverage);
    cJSON_AddNumberToObject(rj, "seed", (double)rp.seed);
    cJSON_AddItemToObject(rj, "display", cli_display_json(&rp.model.display));
    cJSON_AddStringToObject(rj, "pooling", "p93");
    cJSON *cj = cJSON_AddObjectToObject(rj, "criterion");
    cJSON_AddNumberToObject(cj, "max_p", rp.max_p);
    cJSON_AddNumberToObject(cj, "max_fraction", rp.max_fraction);
    cJSON_AddNumberToObject(cj, "views_allowed_above", vis.allowed);
    cJSON_AddItemToObject(rj, "p_per_view", numbers(vis.p, vis.views));
    cJSON_AddNumberToObject(rj, "views_above", vis.above);
    cJSON_AddNumberToObject(rj, "p_criterion", vis.p_criterion);
    cJSON_AddBoolToObject(rj, "pass", vis.pass);
    if (!no_bc) {
      cJSON *bj = cJSON_AddObjectToObject(rj, "block_compressed");
      const char *bn[3] = {"pca_bc4", "pca_bc1", "plain_bc"};
      for (int v = 0; v < 3; v++) {
        cJSON *o = visibility_json(&vis_bc[v]);
        cJSON_AddNumberToObject(o, "bytes", (double)bytes_bc[v]);
        cJSON_AddItemToObject(bj, bn[v], o);
      }
    }
    if (slog) {
      cJSON *search = cJSON_AddObjectToObject(rj, "search");
      cJSON_AddNumberToObject(search, "candidates", slog->candidates);
      cJSON_AddNumberToObject(search, "rendered", slog->tried);
      cJSON *tried = cJSON_AddArrayToObject(search, "tried");
      for (int t = 0; t < slog->tried; t++) {
        cJSON *o = visibility_json(&slog->vis[t]);
        cJSON_AddNumberToObject(o, "components", slog->enc[t].components);
        cJSON_AddNumberToObject(o, "storage_bytes", (double)slog->storage_bytes[t]);
        cJSON_AddNumberToObject(o, "psnr_floor_db", slog->psnr_target_db[t]);
        cJSON_AddItemToArray(tried, o);
      }
    }
  }
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings_s");
    cJSON_AddNumberToObject(t, "read", t_read);
    cJSON_AddNumberToObject(t, "decomposition", t_analyse);
    cJSON_AddNumberToObject(t, "choice", t_choose);
    cJSON_AddNumberToObject(t, "encoding", t_encode);
    cJSON_AddNumberToObject(t, "block_compression", t_bc);
    if (model) cJSON_AddNumberToObject(t, "rendering", t_render);
    cJSON_AddNumberToObject(t, "total", cli_now() - t0);
  }

  snprintf(path, sizeof path, "%s/pca.json", outdir);
  if (cli_report_write(report, path) != EXIT_OK) goto out;
  if (common.json_path && cli_report_write(report, common.json_path) != EXIT_OK) goto out;

  /* human summary */
  cli_info(&common, "jnd pca: %d maps, %d x %d, %d channels; energy in the first 5: %.1f%%, knee at %d\n",
           set.nmaps, set.w, set.h, C, 100.0 * cum[C < 5 ? C - 1 : 4], pca.knee);
  for (int i = 0; i < set.nmaps; i++)
    if (set.maps[i].duplicates)
      cli_info(&common, "  %s: %d identical channel(s) counted once\n", set.maps[i].name, set.maps[i].duplicates);
  cli_info(&common, "  kept %d components (%s), %.2f MB against %.2f MB of 8-bit channels\n", K, criterion,
           enc.storage_bytes / 1e6, (double)set.w * set.h * C / 1e6);
  cli_info(&common, "  %-22s %9s %9s", "channel", "PSNR dB", "float");
  if (!no_bc) cli_info(&common, " %9s %9s %9s", "PCA+BC4", "PCA+BC1", "plain BC");
  cli_info(&common, "\n");
  for (int c = 0; c < C; c++) {
    cli_info(&common, "  %-22s %9.2f %9.2f", set.names[c], json_db(enc.psnr_db[c]), json_db(encf.psnr_db[c]));
    if (!no_bc)
      cli_info(&common, " %9.2f %9.2f %9.2f", json_db(bc.psnr_pca_bc4_db[c]), json_db(bc.psnr_pca_bc1_db[c]),
               json_db(bc.psnr_plain_db[c]));
    cli_info(&common, "\n");
  }
  if (!no_bc)
    cli_info(&common, "  block-compressed: PCA+BC4 %.2f MB, PCA+BC1 %.2f MB, plain BC %.2f MB\n",
             bc.bytes_pca_bc4 / 1e6, bc.bytes_pca_bc1 / 1e6, bc.bytes_plain / 1e6);
  if (model) {
    cli_info(&common, "  rendered: %d views of %s at %dx%d on %s; criterion P <= %.3g in all but %d view(s)\n",
             rp.views, material, rp.width, rp.height, jnd_pca_render_description(rr), rp.max_p, vis.allowed);
    if (slog) cli_info(&common, "  search: %d candidates, %d rendered\n", slog->candidates, slog->tried);
    cli_info(&common, "  storage %.3f MB against %.3f MB of original maps\n", enc.storage_bytes / 1e6, plain8 / 1e6);
    print_views(&common, "chosen", &vis);
    if (!no_bc) {
      print_views(&common, "PCA+BC4", &vis_bc[0]);
      print_views(&common, "PCA+BC1", &vis_bc[1]);
      print_views(&common, "plain BC", &vis_bc[2]);
    }
  }
  cli_info(&common, "  %.1f s; wrote %s/pca.json\n", cli_now() - t0, outdir);
  rc = EXIT_OK;
out:
  cJSON_Delete(report);
  free(slog);
  jnd_pca_render_free(rr);
  jnd_pca_encoded_free(&enc);
  jnd_pca_encoded_free(&encf);
  jnd_texset_free(&set);
  return rc;
}

const jnd_command jnd_cmd_pca = {"pca", "a texture set in fewer channels: PCA of its maps (001)", run};
