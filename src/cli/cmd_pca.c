/* jnd pca MAP... -o OUTDIR — a texture set in fewer channels (001). Parses
 * the options, calls jnd_pca_run (which writes the files and the report)
 * and prints a summary. */
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

static double shown_db(double db) { return isfinite(db) ? db : 999.0; }   /* as the report has it */

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

static void warn(void *user, const char *line) { cli_info(user, "jnd: warning: %s\n", line); }

/* the human summary; the energy is the share of the variance the kept components hold */
static void summary(const cli_common *c, const jnd_pca_params *p, const jnd_pca_result *R, const char *dir,
                    double t0) {
  const jnd_pca_encoded *enc = &R->enc;
  int C = R->set.c, K = enc->enc.components;
  double kept = 0;
  for (int k = 0; k < K && R->pca.total_variance > 0; k++) kept += R->pca.energy[k] / R->pca.total_variance;
  cli_info(c, "jnd pca: %d maps, %d x %d, %d channels; the %d component%s kept hold%s %.1f%% of the energy, knee at %d\n",
           R->set.nmaps, R->set.w, R->set.h, C, K, K == 1 ? "" : "s", K == 1 ? "s" : "", 100.0 * kept, R->pca.knee);
  for (int i = 0; i < R->set.nmaps; i++)
    if (R->set.maps[i].duplicates)
      cli_info(c, "  %s: %d identical channel(s) counted once\n", R->set.maps[i].name, R->set.maps[i].duplicates);
  cli_info(c, "  kept %d components (rule: %s)\n", K, rule_name(R->rule));
  /* per image before and after, with the maps that sample it (texres's table) */
  cli_info(c, "  %-44s %11s %10s %10s\n", "image (the maps that sample it)", "size", "before MiB", "after MiB");
  for (int t = 0; t < R->nimages; t++) {
    char users[256] = "", size[32];
    size_t n = 0;
    for (int i = 0; i < R->set.nmaps && n < sizeof users; i++)
      if (R->image_of[i] == t) {   /* a file by its name; a model's map as MATERIAL/SLOT */
        const char *slash = p->nmaps ? strrchr(R->labels[i], '/') : NULL;
        n += (size_t)snprintf(users + n, sizeof users - n, "%s%s", n ? ", " : "", slash ? slash + 1 : R->labels[i]);
      }
    snprintf(size, sizeof size, "%dx%d", R->images[t].width, R->images[t].height);
    cli_info(c, "  %-44.44s %11s %10.3f %10.3f\n", users, size, R->images[t].bytes / 1048576.0, 0.0);
  }
  for (int t = 0; t < R->ntextures; t++) {
    char name[64], size[32];
    snprintf(name, sizeof name, "components_%d.png (%d channels, %d bits)", t, R->textures[t].channels,
             R->textures[t].bits);
    snprintf(size, sizeof size, "%dx%d", R->textures[t].width, R->textures[t].height);
    cli_info(c, "  %-44.44s %11s %10.3f %10.3f\n", name, size, 0.0, R->textures[t].bytes / 1048576.0);
  }
  cli_info(c, "  memory as a GPU holds it: %.3f MiB -> %.3f MiB (%+.0f%%)\n", R->gpu_before_bytes / 1048576.0,
           R->gpu_after_bytes / 1048576.0,
           R->gpu_before_bytes ? 100.0 * ((double)R->gpu_after_bytes / R->gpu_before_bytes - 1) : 0.0);
  cli_info(c, "  %-22s %9s %9s", "channel", "PSNR dB", "float");
  if (R->has_bc) cli_info(c, " %9s %9s %9s", "PCA+BC4", "PCA+BC1", "plain BC");
  cli_info(c, "\n");
  for (int ch = 0; ch < C; ch++) {
    cli_info(c, "  %-22s %9.2f %9.2f", R->set.names[ch], shown_db(enc->psnr_db[ch]), shown_db(R->enc_float.psnr_db[ch]));
    if (R->has_bc)
      cli_info(c, " %9.2f %9.2f %9.2f", shown_db(R->bc.psnr_pca_bc4_db[ch]), shown_db(R->bc.psnr_pca_bc1_db[ch]),
               shown_db(R->bc.psnr_plain_db[ch]));
    cli_info(c, "\n");
  }
  if (R->has_bc)
    cli_info(c, "  block-compressed: PCA+BC4 %.2f MiB, PCA+BC1 %.2f MiB, plain BC %.2f MiB\n",
             R->bc.bytes_pca_bc4 / 1048576.0, R->bc.bytes_pca_bc1 / 1048576.0, R->bc.bytes_plain / 1048576.0);
  if (R->rendered) {
    cli_info(c, "  rendered: %d views of %s on %s; criterion P <= %.3g in all but %d view(s)\n", R->vis.views,
             p->material, R->renderer, p->render.judge.criterion.p, R->vis.allowed);
    if (R->log) cli_info(c, "  search: %d candidates, %d rendered\n", R->log->candidates, R->log->tried);
    print_views(c, "chosen", &R->vis);
    if (p->block_compression) {
      print_views(c, "PCA+BC4", &R->vis_bc[0]);
      print_views(c, "PCA+BC1", &R->vis_bc[1]);
      print_views(c, "plain BC", &R->vis_bc[2]);
    }
  }
  cli_info(c, "  %.1f s; wrote %s/pca.json\n", jnd_seconds() - t0, dir);
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
    if (cli_help(ap)) {
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
    } else if (!cli_operand(ap, paths, &npaths, JND_PCA_MAX_MAPS)) {
      return EXIT_BAD;
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
  p.write_maps = write_maps;
  p.run.map_size = vo.map_size;
  p.run.report_path = common.json_path;
  p.run.timings = common.timings;
  p.run.warning = warn;
  p.run.warning_user = &common;
  cli_progress prog;
  cli_progress_start(&prog, &common, "pca", 1);
  p.progress = cli_progress_callback;
  p.progress_user = &prog;
  double t0 = jnd_seconds();
  jnd_pca_result *R = NULL;
  jnd_status st = jnd_pca_run(p.model, &p, outdir, &R);
  cli_progress_end(&prog);
  if (st != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  if (rc == EXIT_OK) summary(&common, &p, R, outdir, t0);
  jnd_pca_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_pca = {"pca", "a texture set in fewer channels: PCA of its maps (001)", run};
