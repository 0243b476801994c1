/* The commands a batch runs, and what each writes: how its command line is
 * made, which options batch sets itself, where its report keeps the numbers
 * summary.json shows, and what the HTML report shows on the asset's page
 * (fields, tables, the pictures it wrote, plots the report draws).
 *
 * A new command is one entry here: the paths are into its JSON report (see
 * jsonpath.c), so most entries need no code; a decision text or a plot is a
 * small function. docs/batch.md says what lod, pop and gaze will need. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "batch/batch.h"
#include "batch/plots.h"

static void size_text(jnd_text *t, const cJSON *size) {
  const cJSON *w = cJSON_GetArrayItem(size, 0), *h = cJSON_GetArrayItem(size, 1);
  if (cJSON_IsNumber(w) && cJSON_IsNumber(h)) jnd_text_printf(t, "%d×%d", w->valueint, h->valueint);
}

/* texres: each searched map's chosen size, "(from W×H)" where it shrank */
static void texres_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  const cJSON *maps[256];
  int n = jnd_json_select(report, "result.maps[]", maps, 256);
  int shown = 0;
  for (int i = 0; i < n && i < 256; i++) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(maps[i], "name");
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(maps[i], "chosen");
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(maps[i], "original");
    if (!cJSON_IsString(name) || !cJSON_IsArray(c)) continue;
    if (chosen) cJSON_AddItemToObject(chosen, name->valuestring, cJSON_Duplicate(c, 1));
    if (shown++) jnd_text_put(out, "; ");
    jnd_text_printf(out, "%s ", name->valuestring);
    size_text(out, c);
    if (o && !cJSON_Compare(o, c, 1)) {
      jnd_text_put(out, " (from ");
      size_text(out, o);
      jnd_text_put(out, ")");
    }
  }
}

/* pca: components kept of the channels, and the bytes they take */
static void pca_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  double k = jnd_json_number(report, "result.components_kept"), c = jnd_json_number(report, "result.channel_count");
  if (!isfinite(k) || !isfinite(c)) return;
  jnd_text_printf(out, "%d of %d components", (int)k, (int)c);
  const cJSON *comps[64];
  int n = jnd_json_select(report, "result.components[]", comps, 64);
  int reduced = 0;
  for (int i = 0; i < n && i < 64; i++) {
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(comps[i], "divisor");
    if (cJSON_IsNumber(d) && d->valueint > 1) reduced++;
  }
  if (reduced) jnd_text_printf(out, ", %d at reduced resolution", reduced);
  if (chosen) {
    cJSON_AddNumberToObject(chosen, "components", k);
    cJSON_AddNumberToObject(chosen, "channels", c);
  }
}

/* diff: the pooled probability and the largest difference */
static void diff_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  (void)chosen;
  double p = jnd_json_number(report, "result.p_detect"), mx = jnd_json_number(report, "result.jnd_max");
  const cJSON *pool[1];
  if (!isfinite(p)) return;
  jnd_text_printf(out, "P(detect) %.3f", p);
  if (jnd_json_select(report, "result.pooling", pool, 1) == 1 && cJSON_IsString(pool[0]))
    jnd_text_printf(out, " (%s)", pool[0]->valuestring);
  if (isfinite(mx)) jnd_text_printf(out, ", max %.3g JND", mx);
}

static void render_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  (void)chosen;
  const cJSON *v[1];
  int n = jnd_json_select(report, "views[]", v, 1);
  if (n > 0) jnd_text_printf(out, "%d views", n);
}

/* lod: per screen the perceptual level (triangles of level 0's) and where
 * each level may be shown from */
static void lod_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  const cJSON *scr[16];
  int n = jnd_json_select(report, "result.screens[]", scr, 16);
  double t0 = jnd_json_number(report, "result.levels[0].triangles");
  cJSON *cs = chosen ? cJSON_AddObjectToObject(chosen, "perceptual_level") : NULL;
  int shown = 0;
  for (int i = 0; i < n && i < 16; i++) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(scr[i], "name");
    const cJSON *lv = cJSON_GetObjectItemCaseSensitive(scr[i], "perceptual_level");
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(scr[i], "perceptual_triangles");
    if (!cJSON_IsString(name) || !cJSON_IsNumber(lv) || !cJSON_IsNumber(tr)) continue;
    if (shown++) jnd_text_put(out, "; ");
    jnd_text_printf(out, "%s level %d (%.0f", name->valuestring, lv->valueint, tr->valuedouble);
    if (isfinite(t0)) jnd_text_printf(out, " of %.0f", t0);
    jnd_text_put(out, " triangles)");
    if (cs) cJSON_AddNumberToObject(cs, name->valuestring, lv->valueint);
  }
  if (!shown) jnd_text_put(out, "no perceptual choice (--no-perceptual)");
}

/* gaze: the table's range of levels over its grid */
static void gaze_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  const cJSON *rows[256], *d[256], *e[256];
  int nr = jnd_json_select(report, "result.level[]", rows, 256), nd = jnd_json_select(report, "result.distances_m[]", d, 256),
      ne = jnd_json_select(report, "result.eccentricities_deg[]", e, 256);
  int lo = 1 << 30, hi = -1;
  for (int i = 0; i < nr && i < 256; i++)
    for (const cJSON *c = rows[i] ? rows[i]->child : NULL; c; c = c->next)
      if (cJSON_IsNumber(c)) lo = c->valueint < lo ? c->valueint : lo, hi = c->valueint > hi ? c->valueint : hi;
  if (hi < 0) return;
  jnd_text_printf(out, "levels %d–%d over %d distances × %d eccentricities", lo, hi, nd, ne);
  if (chosen) {
    cJSON_AddNumberToObject(chosen, "finest", lo);
    cJSON_AddNumberToObject(chosen, "coarsest", hi);
  }
}

/* pop: the switch's popping (its regions' largest R and the detection
 * score), and with --decide the popping-free switch distances */
static void pop_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  double n = jnd_json_number(report, "result.region_count"), r = jnd_json_number(report, "result.max_rating"),
         d = jnd_json_number(report, "result.detection_score");
  if (!isfinite(n) || !isfinite(d)) return;
  if (n > 0 && isfinite(r)) jnd_text_printf(out, "%d popping region%s, max R %.2f", (int)n, n == 1 ? "" : "s", r);
  else jnd_text_put(out, "no popping region");
  jnd_text_printf(out, ", detection score %d of 5", (int)d);
  const cJSON *rows[256];
  int k = jnd_json_select(report, "result.switch[]", rows, 256);
  if (k > 0) jnd_text_printf(out, "; %d switch distance%s", k, k == 1 ? "" : "s");
  if (chosen) {
    cJSON_AddNumberToObject(chosen, "detection_score", d);
    if (k > 0) cJSON_AddItemToObject(chosen, "switch", cJSON_Duplicate(cJSON_GetObjectItem(cJSON_GetObjectItem(report, "result"), "switch"), 1));
  }
}

/* budget: the chosen finest level and its cost, beside texres + lod's */
static void budget_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  double lv = jnd_json_number(report, "result.chosen.level"), c = jnd_json_number(report, "result.comparison.chosen_cost_bytes"),
         se = jnd_json_number(report, "result.comparison.separate_cost_bytes");
  if (!isfinite(lv) || !isfinite(c)) return;
  jnd_text_printf(out, "level %d, %.3f MiB of textures and mesh", (int)lv, c / 1048576.0);
  if (isfinite(se)) jnd_text_printf(out, " (texres + lod separately: %.3f MiB)", se / 1048576.0);
  if (chosen) {
    cJSON_AddNumberToObject(chosen, "level", lv);
    cJSON_AddNumberToObject(chosen, "cost_bytes", c);
  }
}

static const jnd_batch_command COMMANDS[] = {
    {
        .name = "texres",
        .out_args = {"-o", "{out}"},
        .json_name = "texres.json",
        .reserved = {"-o", "--output", "--json"},
        .exit1_complete = 1,
        .memory_before = "result.memory.before_bytes",
        .memory_after = "result.memory.after_bytes",
        .p_detect = "max:result.views.p[]",
        .decision = texres_decision,
        .fields = {{"memory before (unique images, RGBA8 + mips)", "result.memory.before_bytes", JND_FMT_BYTES},
                   {"memory after", "result.memory.after_bytes", JND_FMT_BYTES},
                   {"reduction", "result.memory.reduction", JND_FMT_PERCENT},
                   {"block-compressed before", "result.memory.block_before_bytes", JND_FMT_BYTES},
                   {"block-compressed after", "result.memory.block_after_bytes", JND_FMT_BYTES},
                   {"passes the criterion", "result.views.passes", JND_FMT_BOOL},
                   {"P per view (pooled)", "result.views.p", JND_FMT_LIST},
                   {"fraction of views above p", "result.views.fraction_above", JND_FMT_PERCENT},
                   {"held-out views pass", "result.verify.passes", JND_FMT_BOOL},
                   {"criterion: P above", "parameters.criterion.p", JND_FMT_P},
                   {"criterion: fraction of views allowed above", "parameters.criterion.q", JND_FMT_PERCENT},
                   {"pixels per degree", "result.ppd", JND_FMT_NUMBER},
                   {"renderer", "result.renderer", JND_FMT_TEXT}},
        .tables = {{"Maps",
                    "result.maps[]",
                    {{"map", "name", JND_FMT_TEXT},
                     {"original", "original", JND_FMT_SIZE},
                     {"chosen", "chosen", JND_FMT_SIZE},
                     {"mip bound", "mip_bound", JND_FMT_SIZE},
                     {"eye bound", "eye_bound", JND_FMT_SIZE},
                     {"eq. 1 size at p", "psychometric.resolution_at_p", JND_FMT_NUMBER},
                     {"format", "block_format", JND_FMT_TEXT},
                     {"image", "image", JND_FMT_NUMBER}}},
                   {"Images (each once, as a GPU holds it)",
                    "result.memory.images[]",
                    {{"maps that sample it", "maps", JND_FMT_LIST},
                     {"original", "original", JND_FMT_SIZE},
                     {"chosen", "chosen", JND_FMT_SIZE},
                     {"format", "block_format", JND_FMT_TEXT},
                     {"RGBA8 + mips before", "bytes_before.rgba8", JND_FMT_BYTES},
                     {"RGBA8 + mips after", "bytes_after.rgba8", JND_FMT_BYTES}}}},
        .pictures = {{.file = "worst_view.png",
                      .caption = "The view where a change is most likely seen, at the chosen sizes: the object as "
                                 "rendered and where the model predicts a visible difference (JND, log scale)"},
                     {.path = "result.matrices[].png",
                      .caption = "P per view for each pair of baseColor (columns) and normal (rows) sizes, and the "
                                 "criterion statistic over the views; the chosen pair is outlined in red (000 Fig. 13)"}},
        .plots = {{"series.png", jnd_plot_texres_series,
                   "Each map alone at each candidate size: the criterion statistic (the view quantile of pooled P) "
                   "against the size; open triangles with an arrow up are lower bounds (judging stopped once the "
                   "candidate failed); the dashed grey line is the threshold p"}},
    },
    {
        .name = "pca",
        .asset_flag = "--model",
        .out_args = {"-o", "{out}"},
        .json_name = "pca.json",
        .reserved = {"-o", "--out", "--output", "--json"},
        .memory_before = "result.memory.before_bytes",
        .memory_after = "result.memory.after_bytes",
        .p_detect = "result.rendered.p_criterion",
        .decision = pca_decision,
        .fields = {{"memory before (unique images, RGBA8 + mips)", "result.memory.before_bytes", JND_FMT_BYTES},
                   {"memory after (packed components + mips)", "result.memory.after_bytes", JND_FMT_BYTES},
                   {"channels", "result.channel_count", JND_FMT_NUMBER},
                   {"components kept", "result.components_kept", JND_FMT_NUMBER},
                   {"knee of the energy curve", "result.knee", JND_FMT_NUMBER},
                   {"rendered: passes", "result.rendered.pass", JND_FMT_BOOL},
                   {"rendered: P at the criterion", "result.rendered.p_criterion", JND_FMT_P},
                   {"rendered: P per view", "result.rendered.p_per_view", JND_FMT_LIST},
                   {"maps' width (px)", "result.width", JND_FMT_NUMBER}},
        .tables = {{"Channels",
                    "result.channels[]",
                    {{"channel", "name", JND_FMT_TEXT},
                     {"PSNR dB", "psnr_db", JND_FMT_NUMBER},
                     {"PSNR BC4 dB", "psnr_bc4_db", JND_FMT_NUMBER},
                     {"PSNR BC1 dB", "psnr_bc1_db", JND_FMT_NUMBER},
                     {"PSNR plain BC dB", "psnr_plain_bc_db", JND_FMT_NUMBER}}},
                   {"Components stored",
                    "result.textures[]",
                    {{"file", "file", JND_FMT_TEXT},
                     {"width", "width", JND_FMT_NUMBER},
                     {"height", "height", JND_FMT_NUMBER},
                     {"bits", "bits", JND_FMT_NUMBER}}}},
        .pictures = {{.file = "contribution.png",
                      .caption = "How much each channel feeds each component (001's |S·Tᵀ|)"},
                     {.path = "result.textures[].file", .caption = "The stored components, packed four to a texture"}},
        .plots = {{"energy.png", jnd_plot_pca_energy,
                   "Energy of each component and the cumulative share; the dashed line marks the components kept and the "
                   "share of the energy they hold"}},
    },
    {
        .name = "diff",
        .out_args = {"--json", "{out}/diff.json", "--heatmap", "{out}/heatmap.png"},
        .json_name = "diff.json",
        .reserved = {"--json", "--heatmap", "--map"},
        .exit1_complete = 1,
        .p_detect = "result.p_detect",
        .decision = diff_decision,
        .fields = {{"P(detect), pooled", "result.p_detect", JND_FMT_P},
                   {"pooling", "result.pooling", JND_FMT_TEXT},
                   {"P median pixel", "result.p_p50", JND_FMT_P},
                   {"P 99th percentile", "result.p_p99", JND_FMT_P},
                   {"mean JND", "result.jnd_mean", JND_FMT_NUMBER},
                   {"93rd percentile JND", "result.jnd_p93", JND_FMT_NUMBER},
                   {"max JND", "result.jnd_max", JND_FMT_NUMBER},
                   {"width", "result.width", JND_FMT_NUMBER},
                   {"height", "result.height", JND_FMT_NUMBER},
                   {"display", "parameters.display.name", JND_FMT_TEXT}},
        .pictures = {{.file = "heatmap.png",
                      .caption = "Where a viewer would notice the difference (JND on a log scale over a grey copy of "
                                 "the reference)"}},
    },
    {
        .name = "render",
        .out_args = {"-o", "{out}"},
        .json_name = "views.json",
        .reserved = {"-o", "--output", "--json"},
        .decision = render_decision,
        .fields = {{"renderer", "result.renderer", JND_FMT_TEXT}},
        .pictures = {{.path = "views[].color", .caption = "The rendered views"}},
    },
    {
        .name = "lod",
        .out_args = {"-o", "{out}"},
        .json_name = "lod.json",
        .reserved = {"-o", "--output", "--json"},
        .memory_before = "result.memory.before_bytes",
        .memory_after = "result.memory.after_bytes",
        .p_detect = "max:result.screens[].perceptual_statistic",
        .decision = lod_decision,
        .fields = {{"triangles before (level 0)", "result.triangles.before", JND_FMT_NUMBER},
                   {"triangles after (first screen's perceptual level)", "result.triangles.after", JND_FMT_NUMBER},
                   {"memory before (float attributes, 32-bit indices)", "result.memory.before_bytes", JND_FMT_BYTES},
                   {"memory after", "result.memory.after_bytes", JND_FMT_BYTES},
                   {"screen of the after figures", "result.memory.screen", JND_FMT_TEXT},
                   {"chain", "result.chain_source", JND_FMT_TEXT},
                   {"criterion: P above", "parameters.perceptual.criterion.p", JND_FMT_P},
                   {"criterion: fraction of views allowed above", "parameters.perceptual.criterion.q", JND_FMT_PERCENT},
                   {"model's switch coverages", "result.model.screen_coverage", JND_FMT_LIST},
                   {"renderer", "result.renderer", JND_FMT_TEXT}},
        .tables = {{"Levels",
                    "result.levels[]",
                    {{"level", "level", JND_FMT_NUMBER},
                     {"triangles", "triangles", JND_FMT_NUMBER},
                     {"meshoptimizer error", "error", JND_FMT_NUMBER},
                     {"method", "method", JND_FMT_TEXT}}},
                   {"Screens",
                    "result.screens[]",
                    {{"screen", "name", JND_FMT_TEXT},
                     {"perceptual level", "perceptual_level", JND_FMT_NUMBER},
                     {"its triangles", "perceptual_triangles", JND_FMT_NUMBER},
                     {"003 PoI (lit)", "poi_triangles", JND_FMT_NUMBER},
                     {"meshopt 1 px rule", "rules.meshopt.triangles", JND_FMT_NUMBER},
                     {"0.5 px rule", "rules.pixel_error.triangles", JND_FMT_NUMBER},
                     {"switch distances", "switch_distance_m", JND_FMT_LIST},
                     {"switch coverages", "switch_coverage", JND_FMT_LIST}}}},
        .pictures = {{.glob = "pareto_*.png",
                      .caption = "003's Pareto curves per screen (error against triangles, unlit and lit) with "
                                 "003's knees, the rules of thumb and the perceptual choice marked"}},
    },
    {
        .name = "gaze",
        .out_args = {"-o", "{out}"},
        .json_name = "gaze.json",
        .reserved = {"-o", "--output", "--json"},
        .decision = gaze_decision,
        .fields = {{"threshold (2AFC)", "parameters.threshold", JND_FMT_P},
                   {"orientations", "parameters.orientations", JND_FMT_NUMBER},
                   {"distances (m)", "result.distances_m", JND_FMT_LIST},
                   {"eccentricities (deg)", "result.eccentricities_deg", JND_FMT_LIST},
                   {"triangles per level", "result.triangles", JND_FMT_LIST},
                   {"renderer", "result.renderer", JND_FMT_TEXT}},
        .pictures = {{.file = "gaze.png",
                      .caption = "The coarsest level nobody notices, over distance and eccentricity from the gaze "
                                 "(002's L(d, ecc))"}},
    },
    {
        .name = "pop",
        .out_args = {"-o", "{out}"},
        .json_name = "pop.json",
        .reserved = {"-o", "--output", "--json"},
        .exit1_complete = 1,
        .decision = pop_decision,
        .fields = {{"largest R (004: < 1 rarely visible, > 3 easily)", "result.max_rating", JND_FMT_NUMBER},
                   {"popping regions", "result.region_count", JND_FMT_NUMBER},
                   {"detection score (1..5)", "result.detection_score", JND_FMT_NUMBER},
                   {"coverage score", "result.coverage_score", JND_FMT_TEXT},
                   {"rating score", "result.rating_score", JND_FMT_TEXT},
                   {"max ΔE*94 (baseline)", "result.max_delta_e94", JND_FMT_NUMBER},
                   {"camera distance", "result.distance_m", JND_FMT_NUMBER},
                   {"distances in", "result.distance_unit", JND_FMT_TEXT},
                   {"renderer", "result.renderer", JND_FMT_TEXT}},
        .tables = {{"Popping regions",
                    "result.regions[]",
                    {{"pixels", "pixels", JND_FMT_NUMBER},
                     {"Σ", "sigma", JND_FMT_NUMBER},
                     {"R", "rating", JND_FMT_NUMBER},
                     {"max JND", "jnd_max", JND_FMT_NUMBER}}},
                   {"Popping-free switch distances",
                    "result.switch[]",
                    {{"level", "level", JND_FMT_NUMBER},
                     {"speed °/s", "speed_dps", JND_FMT_NUMBER},
                     {"distance", "distance_m", JND_FMT_NUMBER},
                     {"1-pixel rule distance", "distance_m_pixel_rule", JND_FMT_NUMBER},
                     {"search", "status", JND_FMT_TEXT}}}},
        .pictures = {{.file = "regions.png",
                      .caption = "The switching frame with its popping regions coloured by R (004 Fig. 4)"},
                     {.path = "result.outputs.switch",
                      .caption = "Popping-free switch distance per level, one line per speed, beside the 1-pixel "
                                 "geometric-error rule"}},
    },
    {
        .name = "budget",
        .out_args = {"-o", "{out}"},
        .json_name = "budget.json",
        .reserved = {"-o", "--output", "--json"},
        .exit1_complete = 1,
        .memory_before = "result.comparison.original_cost_bytes",
        .memory_after = "result.comparison.chosen_cost_bytes",
        .p_detect = "result.chosen.statistic",
        .decision = budget_decision,
        .fields = {{"mode", "parameters.mode", JND_FMT_TEXT},
                   {"cost of the file (textures + level 0's mesh)", "result.comparison.original_cost_bytes", JND_FMT_BYTES},
                   {"cost chosen", "result.comparison.chosen_cost_bytes", JND_FMT_BYTES},
                   {"cost of texres + lod separately", "result.comparison.separate_cost_bytes", JND_FMT_BYTES},
                   {"chosen: textures", "result.chosen.memory_bytes", JND_FMT_BYTES},
                   {"chosen: triangles", "result.chosen.triangles", JND_FMT_NUMBER},
                   {"chosen: statistic", "result.chosen.statistic", JND_FMT_P},
                   {"bytes per triangle", "parameters.bytes_per_triangle", JND_FMT_NUMBER},
                   {"chain", "result.chain_source", JND_FMT_TEXT}},
        .tables = {{"Written levels",
                    "result.levels[]",
                    {{"level", "level", JND_FMT_NUMBER},
                     {"from distance", "switch_distance", JND_FMT_NUMBER},
                     {"triangles", "triangles", JND_FMT_NUMBER},
                     {"texture bytes", "texture_bytes", JND_FMT_BYTES},
                     {"held-out statistic", "verification.statistic", JND_FMT_P}}}},
        .pictures = {{.file = "pareto.png",
                      .caption = "Texture memory against the statistic of every candidate, one series per mesh "
                                 "level, the Pareto front, the choice and texres + lod chosen separately marked"}},
    },
};
#define NCOMMANDS (sizeof COMMANDS / sizeof COMMANDS[0])

const jnd_batch_command *jnd_batch_command_find(const char *name) {
  for (size_t i = 0; i < NCOMMANDS; i++)
    if (name && strcmp(COMMANDS[i].name, name) == 0) return &COMMANDS[i];
  return NULL;
}

const char *jnd_batch_command_list(void) {
  static char list[256];
  size_t k = 0;
  for (size_t i = 0; i < NCOMMANDS; i++)
    k += (size_t)snprintf(list + k, sizeof list - k, "%s%s", i ? ", " : "", COMMANDS[i].name);
  return list;
}
