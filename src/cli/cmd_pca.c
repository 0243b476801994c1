/* jnd pca MAP... -o OUTDIR — a texture set in fewer channels (001). Parses
 * the options, calls jnd_pca_run, writes the files and the report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd pca MAP... -o OUTDIR [options]\n"
      "       jnd pca [MAP...] --model FILE.glb --material NAME -o OUTDIR [options]\n"
      "\n"
      "Packs the maps of one material (albedo, normal, roughness, ...) as a (w*h) x C\n"
      "matrix, decorrelates it by PCA (Wronski's texture-set compression: paper 001) and\n"
      "keeps the first components, each at its own resolution and bit depth. Writes the\n"
      "components packed four to an RGBA texture as an engine samples them, a C x (K+1)\n"
      "reconstruction matrix (K+1 multiply-adds per channel in a shader), and PSNR per\n"
      "channel, with and without GPU block compression.\n"
      "\n"
      "Maps: PNG, JPEG, HDR, EXR of one size (others are resampled to the largest,\n"
      "with a warning; a different shape is an error). Values are used as stored.\n"
      "Channels are named MAP.r/.g/.b/.a after the file stem less the prefix all maps\n"
      "share (Default_albedo.jpg -> albedo.r); a map with one informative channel (grey,\n"
      "grey stored as RGB, or constant) is named MAP; constant channels are left out.\n"
      "\n"
      "what to keep (one rule; the default says which it used):\n"
      "  (default)           with --model: the cheapest encoding whose rendering passes\n"
      "                      the criterion below (rendered visibility); without: the\n"
      "                      fewest components holding --energy of the variance\n"
      "  --energy F          fraction of the total variance to keep (0.99)\n"
      "  --components K      keep the first K components (all: every one; the default\n"
      "                      with --bits or --resolutions)\n"
      "  --bits B[,B...]     8 (default) or 16 bits per kept component\n"
      "                      (the last repeats): 16,16,8\n"
      "  --resolutions LIST  size divisor per kept component, powers of two\n"
      "                      up to 8: 1,1,1,1,2,2,2,4,4 (the last repeats; default all 1)\n"
      "  --psnr DB           the smallest storage (K, resolutions, bits) whose every\n"
      "                      channel reaches DB dB PSNR\n"
      "  --max-scale S       coarsest resolution --psnr and the rendered search may use:\n"
      "                      1/2^S (default 2)\n"
      "\n"
      "rendered visibility (the material re-rendered with the reconstructed maps, judged\n"
      "as `jnd texres` judges: P per view pooled over the object):\n"
      "  --model FILE.glb    a model using the set (glTF, GLB, OBJ, or builtin);\n"
      "                      without MAP files the set is the material's own maps\n"
      "  --material NAME     the material of --model that uses the set\n"
      "  --slot FILE=SLOT    the material slot a MAP file replaces: baseColor,\n"
      "                      metallicRoughness, normal, occlusion, emissive (default:\n"
      "                      guessed from the name: albedo/color, normal, metal/rough,\n"
      "                      ao/occlusion, emissive)\n"
      "\n"
      "%s"
      "\n"
      "%s"
      "\n"
      "%s"
      "\n"
      "how to decompose:\n"
      "  --channels SPEC     pick channels per map: normal=rg,metalRoughness=gb\n"
      "  --weight SPEC       importance per map or channel (001): albedo=2,height=0.75\n"
      "                      (no standardisation: ranges already carry importance)\n"
      "\n"
      "outputs:\n"
      "  -o, --output DIR    folder for pca.json, components_N.png, contribution.png\n"
      "  --write-maps        also write each map as reconstructed: OUTDIR/MAP.png\n"
      "  --no-bc             skip the block-compression comparison (faster)\n"
      "%s"
      "\n"
      "pca.json: .result.energy[] (per component, descending), .result.total_variance,\n"
      ".result.channels[] {name, psnr_db, psnr_float_db, psnr_bc4_db, psnr_bc1_db,\n"
      "psnr_plain_bc_db}, .result.textures[] {file, bits, components}, .result.storage_bytes,\n"
      ".result.original_bytes (the maps as stored, 8 bits per channel: the baseline),\n"
      ".result.rendered {p_per_view, pass, criterion, block_compressed, search} with\n"
      "--model, .result.reconstruction (C rows of K+1: channel c = sum_k R[c][k]*q_k +\n"
      "R[c][K], q_k the stored component value 0..1). PSNR is 10*log10(1/MSE) on values\n"
      "0..1; 999 stands for an exact reconstruction.\n"
      "\n"
      "examples:\n"
      "  jnd pca Default_*.jpg -o out --components 5\n"
      "  jnd pca albedo.png normal.png rough.png -o out --psnr 40 --weight albedo=2\n"
      "  jnd pca --model controller.glb --material body -o out --p 0.2\n"
      "\n"
      "Paper numbers: 001 is Wronski's texture-set PCA; 000 (Wolski et al. 2019) the\n"
      "criterion and pooling. include/jnd.h lists them all.\n"
      "Exit status: 0, 2 for bad input.\n",
      cli_views_help, cli_criterion_help, cli_display_help, cli_common_help);
}

static double json_db(double db) { return isfinite(db) ? db : 999.0; }

/* "1,1,2,4" → scale exponents (powers of two up to 2^JND_PCA_MAX_SCALE) */
static void parse_resolutions(cli_args *a, const char *v, int *scale, int *n) {
  int d[JND_PCA_MAX_CHANNELS];
  *n = cli_int_list(a, "--resolutions", v, 1, 1 << JND_PCA_MAX_SCALE, d, JND_PCA_MAX_CHANNELS);
  for (int k = 0; k < *n && !a->bad; k++) {
    int s = 0;
    while ((1 << s) < d[k]) s++;
    if ((1 << s) != d[k]) {
      cli_error("--resolutions: %d is not a power of two up to %d", d[k], 1 << JND_PCA_MAX_SCALE);
      a->bad = 1;
    }
    scale[k] = s;
  }
}

static void parse_bits(cli_args *a, const char *v, int *bits, int *n) {
  *n = cli_int_list(a, "--bits", v, 8, 16, bits, JND_PCA_MAX_CHANNELS);
  for (int k = 0; k < *n && !a->bad; k++)
    if (bits[k] != 8 && bits[k] != 16) {
      cli_error("--bits: %d (8 or 16 per component)", bits[k]);
      a->bad = 1;
    }
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

static const char *rule_name(jnd_pca_rule r) {
  switch (r) {
  case JND_PCA_RULE_RENDERED: return "rendered";
  case JND_PCA_RULE_ENERGY: return "energy";
  case JND_PCA_RULE_PSNR: return "psnr";
  case JND_PCA_RULE_COMPONENTS: return "components";
  default: return "auto";
  }
}

/* the files: packed components, the contribution plot, rebuilt maps */
static int write_files(const char *outdir, const jnd_pca_result *R, int write_maps, cJSON *textures) {
  jnd_pca_texture tex[JND_PCA_MAX_CHANNELS];
  int ntex = 0, ok = 1;
  char path[4200], name[64];
  if (jnd_pca_pack(&R->enc, tex, &ntex) != JND_OK) return cli_lib_error(), 0;
  for (int t = 0; t < ntex; t++) {
    snprintf(name, sizeof name, "components_%d.png", t);
    snprintf(path, sizeof path, "%s/%s", outdir, name);
    if (ok && jnd_image_write_png(path, &tex[t].image, tex[t].bits) != JND_OK) ok = (cli_lib_error(), 0);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "file", name);
    cJSON_AddNumberToObject(o, "width", tex[t].image.w);
    cJSON_AddNumberToObject(o, "height", tex[t].image.h);
    cJSON_AddNumberToObject(o, "bits", tex[t].bits);
    cJSON *cs = cJSON_AddArrayToObject(o, "components");   /* in channels R, G, B, A */
    for (int q = 0; q < tex[t].ncomp; q++) cJSON_AddItemToArray(cs, cJSON_CreateNumber(tex[t].comp[q]));
    cJSON_AddItemToArray(textures, o);
    jnd_image_free(&tex[t].image);
  }
  jnd_image plot = {0};
  snprintf(path, sizeof path, "%s/contribution.png", outdir);
  if (ok && (jnd_pca_contribution_plot(&R->pca, &R->set, &plot) != JND_OK || jnd_image_write_png(path, &plot, 8) != JND_OK))
    ok = (cli_lib_error(), 0);
  jnd_image_free(&plot);
  if (ok && write_maps) {
    jnd_image rec = {0};
    if (jnd_pca_reconstruct(&R->enc, NULL, &rec) != JND_OK) return cli_lib_error(), 0;
    for (int i = 0; i < R->set.nmaps && ok; i++) {
      jnd_image mi = {0};
      snprintf(path, sizeof path, "%s/%s.png", outdir, R->set.maps[i].name);
      if (jnd_texset_map_image(&R->set, &rec, i, &mi) != JND_OK || jnd_image_write_png(path, &mi, 8) != JND_OK)
        ok = (cli_lib_error(), 0);
      jnd_image_free(&mi);
    }
    jnd_image_free(&rec);
  }
  return ok;
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  cli_views vo;
  cli_display disp;
  cli_calibration cal = {0};
  jnd_pca_params p;
  jnd_pca_defaults(&p);
  cli_views_init(&vo, p.render.judge.views.render.width, p.render.judge.views.render.height);
  cli_display_init(&disp);
  const char *paths[JND_PCA_MAX_MAPS], *slot_specs[JND_PCA_MAX_MAPS], *outdir = NULL, *res_spec = NULL, *v;
  int npaths = 0, nslots = 0, write_maps = 0, rules = 0, criterion_given = 0;
  cli_args args = cli_args_start(argc, argv, "pca"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *a = argv[args.i];
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_criterion_opt(ap, &p.render.judge.criterion)) {
      criterion_given = 1;
    } else if (cli_views_opt(ap, &vo) || cli_display_opt(ap, &disp) || cli_calibration_opt(ap, &cal) ||
               cli_common_opt(ap, &common)) {
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      outdir = v;
    } else if (cli_opt(ap, "--components", &v)) {
      p.components = strcmp(v, "all") == 0 ? -1 : cli_int(ap, "--components", v, 0, JND_PCA_MAX_CHANNELS);
      p.rule = JND_PCA_RULE_COMPONENTS, rules++;
    } else if (cli_opt(ap, "--energy", &v)) {
      p.energy = cli_double(ap, "--energy", v, 1e-6, 1);
      p.rule = JND_PCA_RULE_ENERGY, rules++;
    } else if (cli_opt(ap, "--psnr", &v)) {
      p.psnr_db = cli_double(ap, "--psnr", v, 1, 150);
      p.rule = JND_PCA_RULE_PSNR, rules++;
    } else if (cli_opt(ap, "--bits", &v)) {
      parse_bits(ap, v, p.bits, &p.nbits);
    } else if (cli_opt(ap, "--resolutions", &v)) {
      res_spec = v;
    } else if (cli_opt(ap, "--max-scale", &v)) {
      p.max_scale = cli_int(ap, "--max-scale", v, 0, JND_PCA_MAX_SCALE);
    } else if (cli_opt(ap, "--slot", &v)) {
      if (nslots >= JND_PCA_MAX_MAPS) return cli_bad("pca: at most %d --slot options", JND_PCA_MAX_MAPS);
      slot_specs[nslots++] = v;
    } else if (cli_opt(ap, "--model", &v)) {
      p.model = v;
    } else if (cli_opt(ap, "--material", &v)) {
      p.material = v;
    } else if (cli_opt(ap, "--channels", &v)) {
      p.channels = v;
    } else if (cli_opt(ap, "--weight", &v)) {
      p.weights = v;
    } else if (cli_flag(ap, "--write-maps")) {
      write_maps = 1;
    } else if (cli_flag(ap, "--no-bc")) {
      p.block_compression = 0;
    } else if (a[0] == '-' && a[1]) {
      return cli_unknown(ap);
    } else if (npaths < JND_PCA_MAX_MAPS) {
      paths[npaths++] = a;
    } else {
      return cli_bad("pca: at most %d maps", JND_PCA_MAX_MAPS);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (res_spec) {
    parse_resolutions(ap, res_spec, p.scale, &p.nscale);
    if (args.bad) return EXIT_BAD;
  }
  if ((npaths == 0 && !p.model) || !outdir) return cli_bad("pca: needs maps (or --model) and -o OUTDIR (jnd pca --help)");
  if (rules > 1) return cli_bad("pca: give one of --components, --energy, --psnr");
  if (criterion_given && !p.model) return cli_bad("pca: --p and --q judge renderings: they need --model FILE.glb and --material NAME");
  if ((p.nbits || p.nscale) && p.rule == JND_PCA_RULE_AUTO) p.rule = JND_PCA_RULE_COMPONENTS;   /* all, as given */
  if ((p.nbits || p.nscale) && p.rule != JND_PCA_RULE_COMPONENTS) return cli_bad("pca: --bits and --resolutions go with --components");
  if (p.model && !p.material) return cli_bad("pca: --model needs --material NAME");
  if (nslots && !(p.model && npaths)) return cli_bad("pca: --slot needs MAP files and --model");
  if (!cli_calibration_get(&cal, &p.render.judge.calibration)) return EXIT_BAD;
  p.maps = paths;
  p.nmaps = npaths;
  p.slots = slot_specs;
  p.nslots = nslots;
  p.render.judge.views = vo.set;
  p.render.judge.model.display = cli_display_get(&disp);
  p.render.judge.model.threads = common.threads;
  p.render.builtin_map_size = vo.map_size;
  if (vo.cameras) return cli_bad("pca: --cameras is not supported here yet (sampled views only)");

  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *ins[JND_PCA_MAX_MAPS + 4] = {p.model, p.render.judge.views.render.env_path, cal.path}, *final_dir = outdir;
  const char *json_out = common.json_path;
  for (int k = 0; k < npaths; k++) ins[3 + k] = paths[k];
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 3 + npaths) != EXIT_OK ||
      cli_out_dir(outw, final_dir, &outdir) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    return cli_out_end(outw, EXIT_BAD);
  cli_progress prog;
  cli_progress_start(&prog, &common, "pca", 1);
  p.progress = cli_progress_callback;
  p.progress_user = &prog;
  double t0 = jnd_seconds();
  jnd_pca_result R;
  jnd_status st = jnd_pca_run(&p, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) return cli_out_end(outw, cli_lib_error());
  int rc = EXIT_BAD;
  cJSON *report = cli_report_new("pca");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON *textures = cJSON_CreateArray();
  for (int i = 0; i < R.set.nmaps; i++) {
    const jnd_texset_map *m = &R.set.maps[i];
    if (m->resampled)
      cli_info(&common, "jnd: warning: %s: %d x %d resampled to %d x %d (Lanczos-3)\n", R.labels[i], m->file_w,
               m->file_h, R.set.w, R.set.h);
  }
  if (!write_files(outdir, &R, write_maps, textures)) {
    cJSON_Delete(textures);
    goto out;
  }

  /* report */
  const jnd_pca_encoded *enc = &R.enc;
  int C = R.set.c, K = enc->enc.components;
  cJSON *maps = cJSON_AddArrayToObject(inputs, "maps");
  for (int i = 0; i < R.set.nmaps; i++) {
    const jnd_texset_map *m = &R.set.maps[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "path", R.labels[i]);
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
  }
  cJSON_AddStringToObject(params, "criterion", rule_name(R.rule));
  if (R.rule == JND_PCA_RULE_ENERGY) cJSON_AddNumberToObject(params, "energy", p.energy);
  if (R.rule == JND_PCA_RULE_PSNR) cJSON_AddNumberToObject(params, "psnr_db", p.psnr_db);
  if (R.rule == JND_PCA_RULE_PSNR || R.rule == JND_PCA_RULE_RENDERED) cJSON_AddNumberToObject(params, "max_scale", p.max_scale);
  if (p.model) cJSON_AddStringToObject(params, "model", p.model);
  if (p.material) cJSON_AddStringToObject(params, "material", p.material);
  if (p.channels) cJSON_AddStringToObject(params, "channels", p.channels);
  cJSON_AddBoolToObject(params, "standardise", 0);
  cJSON_AddBoolToObject(params, "mean_centre", 1);
  cJSON *wj = cJSON_AddObjectToObject(params, "weights");
  for (int c = 0; c < C; c++) cJSON_AddNumberToObject(wj, R.set.names[c], R.weights[c]);

  cJSON_AddNumberToObject(res, "width", R.set.w);
  cJSON_AddNumberToObject(res, "height", R.set.h);
  cJSON_AddNumberToObject(res, "channel_count", C);
  cJSON_AddNumberToObject(res, "components_kept", K);
  cJSON *chs = cJSON_AddArrayToObject(res, "channels");
  for (int c = 0; c < C; c++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", R.set.names[c]);
    cJSON_AddStringToObject(o, "map", R.set.maps[R.set.map_of[c]].name);
    cJSON_AddNumberToObject(o, "mean", R.pca.mean[c]);
    cJSON_AddNumberToObject(o, "weight", R.pca.weight[c]);
    cJSON_AddNumberToObject(o, "psnr_db", json_db(enc->psnr_db[c]));
    cJSON_AddNumberToObject(o, "psnr_float_db", json_db(R.enc_float.psnr_db[c]));
    if (R.has_bc) {
      cJSON_AddNumberToObject(o, "psnr_bc4_db", json_db(R.bc.psnr_pca_bc4_db[c]));
      cJSON_AddNumberToObject(o, "psnr_bc1_db", json_db(R.bc.psnr_pca_bc1_db[c]));
      cJSON_AddNumberToObject(o, "psnr_plain_bc_db", json_db(R.bc.psnr_plain_db[c]));
    }
    cJSON_AddItemToArray(chs, o);
  }
  double sv[JND_PCA_MAX_CHANNELS], frac[JND_PCA_MAX_CHANNELS], cum[JND_PCA_MAX_CHANNELS], acc = 0;
  for (int k = 0; k < C; k++) {
    sv[k] = sqrt(R.pca.energy[k]);
    frac[k] = R.pca.total_variance > 0 ? R.pca.energy[k] / R.pca.total_variance : 0;
    acc += frac[k];
    cum[k] = acc;
  }
  cJSON_AddItemToObject(res, "energy", numbers(R.pca.energy, C));
  cJSON_AddItemToObject(res, "energy_fraction", numbers(frac, C));
  cJSON_AddItemToObject(res, "cumulative_energy", numbers(cum, C));
  cJSON_AddItemToObject(res, "singular_values", numbers(sv, C));
  cJSON_AddNumberToObject(res, "total_variance", R.pca.total_variance);
  cJSON_AddNumberToObject(res, "knee", R.pca.knee);
  double contrib[JND_PCA_MAX_CHANNELS * JND_PCA_MAX_CHANNELS];
  jnd_pca_contribution(&R.pca, contrib);
  cJSON *cm = cJSON_AddArrayToObject(res, "contribution");
  for (int k = 0; k < C; k++) cJSON_AddItemToArray(cm, numbers(contrib + k * C, C));
  cJSON *comps = cJSON_AddArrayToObject(res, "components");
  for (int k = 0; k < K; k++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "width", enc->comp[k].w);
    cJSON_AddNumberToObject(o, "height", enc->comp[k].h);
    cJSON_AddNumberToObject(o, "divisor", 1 << enc->enc.scale[k]);
    cJSON_AddNumberToObject(o, "bits", enc->enc.bits[k]);
    cJSON_AddNumberToObject(o, "scale", enc->scale[k]);
    cJSON_AddNumberToObject(o, "offset", enc->offset[k]);
    cJSON_AddItemToArray(comps, o);
  }
  cJSON_AddItemToObject(res, "textures", textures);
  cJSON *rm = cJSON_AddArrayToObject(res, "reconstruction");
  for (int c = 0; c < C; c++) cJSON_AddItemToArray(rm, numbers(enc->recon + (size_t)c * (K + 1), K + 1));
  cJSON_AddStringToObject(res, "reconstruction_layout",
                          "C rows (channels, in result.channels order) of K+1: channel c = "
                          "sum_k R[c][k] * q_k + R[c][K], q_k = component k as stored (0..1)");
  cJSON_AddNumberToObject(res, "storage_bytes", (double)enc->storage_bytes);
  cJSON_AddNumberToObject(res, "original_bytes", (double)R.original_bytes);
  cJSON_AddNumberToObject(res, "reduction", R.original_bytes ? 1.0 - (double)enc->storage_bytes / R.original_bytes : 0);
  if (R.has_bc) {
    cJSON *b = cJSON_AddObjectToObject(res, "block_compression");
    cJSON_AddNumberToObject(b, "pca_bc4_bytes", (double)R.bc.bytes_pca_bc4);
    cJSON_AddNumberToObject(b, "pca_bc1_bytes", (double)R.bc.bytes_pca_bc1);
    cJSON_AddNumberToObject(b, "plain_bc_bytes", (double)R.bc.bytes_plain);
    cJSON_AddStringToObject(b, "plain_formats", "BC1 for RGB maps, BC4 for grey, BC5 for 2 channels, BC1+BC4 for RGBA");
  }
  if (R.rendered) {
    cJSON *rj = cJSON_AddObjectToObject(res, "rendered");
    cJSON_AddStringToObject(rj, "model", p.model);
    cJSON_AddStringToObject(rj, "material", p.material);
    cJSON_AddStringToObject(rj, "renderer", R.renderer);
    cJSON *sj = cJSON_AddObjectToObject(rj, "slots");
    for (int i = 0; i < R.set.nmaps; i++) cJSON_AddStringToObject(sj, R.set.maps[i].name, jnd_map_slot_name(R.slots[i]));
    cJSON_AddNumberToObject(rj, "views", R.vis.views);
    cJSON_AddItemToObject(rj, "view_set", cli_views_json(&vo));
    cJSON_AddItemToObject(rj, "display", cli_display_json(&p.render.judge.model.display));
    char pool[32];
    snprintf(pool, sizeof pool, "p%g", p.render.judge.calibration.percentile);
    cJSON_AddStringToObject(rj, "pooling", pool);
    jnd_criterion_result cr = {0};
    cr.views = R.vis.views, cr.above = R.vis.above, cr.allowed = R.vis.allowed, cr.statistic = R.vis.p_criterion;
    cr.pass = R.vis.pass, cr.fraction_above = R.vis.views ? (double)R.vis.above / R.vis.views : 0;
    cr.fraction_upper = jnd_binomial_upper(R.vis.above, R.vis.views, p.render.judge.criterion.confidence);
    cJSON_AddItemToObject(rj, "criterion", cli_criterion_json(&p.render.judge.criterion, &cr));
    cJSON_AddItemToObject(rj, "p_per_view", numbers(R.vis.p, R.vis.views));
    cJSON_AddNumberToObject(rj, "views_above", R.vis.above);
    cJSON_AddNumberToObject(rj, "p_criterion", R.vis.p_criterion);
    cJSON_AddBoolToObject(rj, "pass", R.vis.pass);
    if (p.block_compression) {
      cJSON *bj = cJSON_AddObjectToObject(rj, "block_compressed");
      const char *bn[3] = {"pca_bc4", "pca_bc1", "plain_bc"};
      for (int k = 0; k < 3; k++) {
        cJSON *o = visibility_json(&R.vis_bc[k]);
        cJSON_AddNumberToObject(o, "bytes", (double)R.bytes_bc[k]);
        cJSON_AddItemToObject(bj, bn[k], o);
      }
    }
    if (R.log) {
      cJSON *search = cJSON_AddObjectToObject(rj, "search");
      cJSON_AddNumberToObject(search, "candidates", R.log->candidates);
      cJSON_AddNumberToObject(search, "rendered", R.log->tried);
      cJSON *tried = cJSON_AddArrayToObject(search, "tried");
      for (int t = 0; t < R.log->tried; t++) {
        cJSON *o = visibility_json(&R.log->vis[t]);
        cJSON_AddNumberToObject(o, "components", R.log->enc[t].components);
        cJSON_AddNumberToObject(o, "storage_bytes", (double)R.log->storage_bytes[t]);
        cJSON_AddNumberToObject(o, "psnr_floor_db", R.log->psnr_target_db[t]);
        cJSON_AddItemToArray(tried, o);
      }
    }
  }
  if (common.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings_s");
    static const char *const stage[6] = {"read", "decomposition", "choice", "encoding", "block_compression", "rendering"};
    for (int k = 0; k < 6; k++)
      if (k < 5 || R.rendered) cJSON_AddNumberToObject(t, stage[k], R.seconds[k]);
    cJSON_AddNumberToObject(t, "total", jnd_seconds() - t0);
  }
  char path[4200];
  snprintf(path, sizeof path, "%s/pca.json", outdir);
  if (cli_report_write(report, path) != EXIT_OK) goto out;
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto out;

  /* human summary; the energy is the share of the variance the kept components hold */
  cli_info(&common, "jnd pca: %d maps, %d x %d, %d channels; the %d component%s kept hold%s %.1f%% of the energy, knee at %d\n",
           R.set.nmaps, R.set.w, R.set.h, C, K, K == 1 ? "" : "s", K == 1 ? "s" : "", K > 0 ? 100.0 * cum[K - 1] : 0.0,
           R.pca.knee);
  for (int i = 0; i < R.set.nmaps; i++)
    if (R.set.maps[i].duplicates)
      cli_info(&common, "  %s: %d identical channel(s) counted once\n", R.set.maps[i].name, R.set.maps[i].duplicates);
  cli_info(&common, "  kept %d components (rule: %s), %.3f MiB against %.3f MiB of the maps as stored\n", K,
           rule_name(R.rule), enc->storage_bytes / 1048576.0, R.original_bytes / 1048576.0);
  cli_info(&common, "  %-22s %9s %9s", "channel", "PSNR dB", "float");
  if (R.has_bc) cli_info(&common, " %9s %9s %9s", "PCA+BC4", "PCA+BC1", "plain BC");
  cli_info(&common, "\n");
  for (int c = 0; c < C; c++) {
    cli_info(&common, "  %-22s %9.2f %9.2f", R.set.names[c], json_db(enc->psnr_db[c]), json_db(R.enc_float.psnr_db[c]));
    if (R.has_bc)
      cli_info(&common, " %9.2f %9.2f %9.2f", json_db(R.bc.psnr_pca_bc4_db[c]), json_db(R.bc.psnr_pca_bc1_db[c]),
               json_db(R.bc.psnr_plain_db[c]));
    cli_info(&common, "\n");
  }
  if (R.has_bc)
    cli_info(&common, "  block-compressed: PCA+BC4 %.2f MiB, PCA+BC1 %.2f MiB, plain BC %.2f MiB\n",
             R.bc.bytes_pca_bc4 / 1048576.0, R.bc.bytes_pca_bc1 / 1048576.0, R.bc.bytes_plain / 1048576.0);
  if (R.rendered) {
    cli_info(&common, "  rendered: %d views of %s on %s; criterion P <= %.3g in all but %d view(s)\n", R.vis.views,
             p.material, R.renderer, p.render.judge.criterion.p, R.vis.allowed);
    if (R.log) cli_info(&common, "  search: %d candidates, %d rendered\n", R.log->candidates, R.log->tried);
    print_views(&common, "chosen", &R.vis);
    if (p.block_compression) {
      print_views(&common, "PCA+BC4", &R.vis_bc[0]);
      print_views(&common, "PCA+BC1", &R.vis_bc[1]);
      print_views(&common, "plain BC", &R.vis_bc[2]);
    }
  }
  cli_info(&common, "  %.1f s; wrote %s/pca.json\n", jnd_seconds() - t0, final_dir);
  rc = EXIT_OK;
out:
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  jnd_pca_result_free(&R);
  return rc;
}

const jnd_command jnd_cmd_pca = {"pca", "a texture set in fewer channels: PCA of its maps (001)", run};
