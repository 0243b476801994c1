/* The commands a batch runs, and what each writes: how its command line is
 * made, which options batch sets itself, where its report keeps the numbers
 * summary.json shows, and what the HTML report shows on the asset's page
 * (fields, tables, the pictures it wrote, plots the report draws).
 *
 * A new command is one entry here: the paths are into its JSON report,
 * named in the library's schema of the reports (tasks/report_schema.h; a
 * test checks that every path here is one the schema lists and that each
 * task's run writes it), so most entries need no code; a decision text or a
 * plot is a small function. docs/batch.md says what lod, pop and gaze will need. */
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
  int n = jnd_json_select(report, RS_TEXRES_MAPS, maps, 256);
  int shown = 0;
  for (int i = 0; i < n && i < 256; i++) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(maps[i], RS_TEXRES_MAPS_NAME);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(maps[i], RS_TEXRES_MAPS_CHOSEN);
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(maps[i], RS_TEXRES_MAPS_ORIGINAL);
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
  double k = jnd_json_number(report, RS_PCA_COMPONENTS_KEPT), c = jnd_json_number(report, RS_PCA_CHANNEL_COUNT);
  if (!isfinite(k) || !isfinite(c)) return;
  jnd_text_printf(out, "%d of %d components", (int)k, (int)c);
  const cJSON *comps[64];
  int n = jnd_json_select(report, RS_PCA_COMPONENTS, comps, 64);
  int reduced = 0;
  for (int i = 0; i < n && i < 64; i++) {
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(comps[i], RS_PCA_COMPONENTS_DIVISOR);
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
  double p = jnd_json_number(report, RS_DIFF_P_DETECT), mx = jnd_json_number(report, RS_DIFF_JND_MAX);
  const cJSON *pool[1];
  if (!isfinite(p)) return;
  jnd_text_printf(out, "P(detect) %.3f", p);
  if (jnd_json_select(report, RS_DIFF_POOLING, pool, 1) == 1 && cJSON_IsString(pool[0]))
    jnd_text_printf(out, " (%s)", pool[0]->valuestring);
  if (isfinite(mx)) jnd_text_printf(out, ", max %.3g JND", mx);
}

static void render_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  (void)chosen;
  const cJSON *v[1];
  int n = jnd_json_select(report, RS_RENDER_VIEWS, v, 1);
  if (n > 0) jnd_text_printf(out, "%d views", n);
}

/* lod: per screen the perceptual level (triangles of level 0's) and where
 * each level may be shown from */
static void lod_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  const cJSON *scr[16];
  int n = jnd_json_select(report, RS_LOD_SCREENS, scr, 16);
  double t0 = jnd_json_number(report, RS_LOD_LEVEL0_TRIANGLES);
  cJSON *cs = chosen ? cJSON_AddObjectToObject(chosen, "perceptual_level") : NULL;
  int shown = 0;
  for (int i = 0; i < n && i < 16; i++) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(scr[i], RS_LOD_SCREENS_NAME);
    const cJSON *lv = cJSON_GetObjectItemCaseSensitive(scr[i], RS_LOD_SCREENS_PERCEPTUAL_LEVEL);
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(scr[i], RS_LOD_SCREENS_PERCEPTUAL_TRIANGLES);
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
  int nr = jnd_json_select(report, RS_GAZE_LEVEL_ROWS, rows, 256), nd = jnd_json_select(report, RS_GAZE_DISTANCES_EACH, d, 256),
      ne = jnd_json_select(report, RS_GAZE_ECCENTRICITIES_EACH, e, 256);
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
  double n = jnd_json_number(report, RS_POP_REGION_COUNT), r = jnd_json_number(report, RS_POP_MAX_RATING),
         d = jnd_json_number(report, RS_POP_DETECTION_SCORE);
  if (!isfinite(n) || !isfinite(d)) return;
  if (n > 0 && isfinite(r)) jnd_text_printf(out, "%d popping region%s, max R %.2f", (int)n, n == 1 ? "" : "s", r);
  else jnd_text_put(out, "no popping region");
  jnd_text_printf(out, ", detection score %d of 5", (int)d);
  const cJSON *rows[256];
  int k = jnd_json_select(report, RS_POP_SWITCH, rows, 256);
  if (k > 0) jnd_text_printf(out, "; %d switch distance%s", k, k == 1 ? "" : "s");
  if (chosen) {
    cJSON_AddNumberToObject(chosen, "detection_score", d);
    if (k > 0) cJSON_AddItemToObject(chosen, "switch", cJSON_Duplicate(cJSON_GetObjectItem(cJSON_GetObjectItem(report, RS_POP_RESULT), RS_POP_SWITCH_KEY), 1));
  }
}

/* budget: the chosen finest level and its cost, beside texres + pca + lod chosen separately */
static void budget_decision(const cJSON *report, jnd_text *out, cJSON *chosen) {
  double lv = jnd_json_number(report, "result.chosen.level"), c = jnd_json_number(report, "result.comparison.chosen_cost_bytes"),
         se = jnd_json_number(report, "result.comparison.separate_cost_bytes");
  if (!isfinite(lv) || !isfinite(c)) return;
  jnd_text_printf(out, "level %d, %.3f MiB of textures and mesh", (int)lv, c / 1048576.0);
  if (isfinite(se)) jnd_text_printf(out, " (texres + pca + lod separately: %.3f MiB)", se / 1048576.0);
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
        .memory_before = RS_TEXRES_MEMORY_BEFORE,
        .memory_after = RS_TEXRES_MEMORY_AFTER,
        .p_detect = RS_MAX(RS_TEXRES_VIEWS_P_EACH),
        .decision = texres_decision,
        .fields = {{"memory before (unique images, RGBA8 + mips)", RS_TEXRES_MEMORY_BEFORE, JND_FMT_BYTES},
                   {"memory after", RS_TEXRES_MEMORY_AFTER, JND_FMT_BYTES},
                   {"reduction", RS_TEXRES_MEMORY_REDUCTION, JND_FMT_PERCENT},
                   {"block-compressed before", RS_TEXRES_MEMORY_BLOCK_BEFORE, JND_FMT_BYTES},
                   {"block-compressed after", RS_TEXRES_MEMORY_BLOCK_AFTER, JND_FMT_BYTES},
                   {"passes the criterion", RS_TEXRES_VIEWS_PASSES, JND_FMT_BOOL},
                   {"P per view (pooled)", RS_TEXRES_VIEWS_P, JND_FMT_LIST},
                   {"fraction of views above p", RS_TEXRES_VIEWS_FRACTION_ABOVE, JND_FMT_PERCENT},
                   {"held-out views pass", RS_TEXRES_VERIFY_PASSES, JND_FMT_BOOL},
                   {"criterion: P above", RS_TEXRES_CRITERION_P, JND_FMT_P},
                   {"criterion: fraction of views allowed above", RS_TEXRES_CRITERION_Q, JND_FMT_PERCENT},
                   {"pixels per degree", RS_TEXRES_PPD, JND_FMT_NUMBER},
                   {"renderer", RS_TEXRES_RENDERER, JND_FMT_TEXT}},
        .tables = {{"Maps",
                    RS_TEXRES_MAPS,
                    {{"map", RS_TEXRES_MAPS_NAME, JND_FMT_TEXT},
                     {"original", RS_TEXRES_MAPS_ORIGINAL, JND_FMT_SIZE},
                     {"chosen", RS_TEXRES_MAPS_CHOSEN, JND_FMT_SIZE},
                     {"mip bound", RS_TEXRES_MAPS_MIP_BOUND, JND_FMT_SIZE},
                     {"eye bound", RS_TEXRES_MAPS_EYE_BOUND, JND_FMT_SIZE},
                     {"eq. 1 size at p", RS_TEXRES_MAPS_RESOLUTION_AT_P, JND_FMT_NUMBER},
                     {"format", RS_TEXRES_MAPS_BLOCK_FORMAT, JND_FMT_TEXT},
                     {"image", RS_TEXRES_MAPS_IMAGE, JND_FMT_NUMBER}}},
                   {"Images (each once, as a GPU holds it)",
                    RS_TEXRES_IMAGES,
                    {{"maps that sample it", RS_TEXRES_IMAGES_MAPS, JND_FMT_LIST},
                     {"original", RS_TEXRES_IMAGES_ORIGINAL, JND_FMT_SIZE},
                     {"chosen", RS_TEXRES_IMAGES_CHOSEN, JND_FMT_SIZE},
                     {"format", RS_TEXRES_IMAGES_BLOCK_FORMAT, JND_FMT_TEXT},
                     {"RGBA8 + mips before", RS_TEXRES_IMAGES_BEFORE_RGBA8, JND_FMT_BYTES},
                     {"RGBA8 + mips after", RS_TEXRES_IMAGES_AFTER_RGBA8, JND_FMT_BYTES}}}},
        .pictures = {{.file = "worst_view.png",
                      .caption = "The view where a change is most likely seen, at the chosen sizes: the object as "
                                 "rendered and where the model predicts a visible difference (JND, log scale)"},
                     {.path = RS_TEXRES_MATRICES_PNG,
                      .caption = "P per view for each pair of baseColor (columns) and normal (rows) sizes, and the "
                                 "criterion statistic over the views; the chosen pair is outlined in red (000 Fig. 13)"}},
        .plots = {{"series.png", jnd_plot_texres_series,
                   "Each map alone at each candidate size: the criterion statistic (the view quantile of pooled P) "
                   "against the size; open triangles with an arrow up are lower bounds (judging stopped once the "
                   "candidate failed); the dashed grey line is the criterion's p, the red one the choice line "
                   "p(1 - margin) a size must stay below"}},
    },
    {
        .name = "pca",
        .asset_flag = "--model",
        .out_args = {"-o", "{out}"},
        .json_name = "pca.json",
        .reserved = {"-o", "--out", "--output", "--json"},
        .memory_before = RS_PCA_MEMORY_BEFORE,
        .memory_after = RS_PCA_MEMORY_AFTER,
        .p_detect = RS_PCA_RENDERED_P_CRITERION,
        .decision = pca_decision,
        .fields = {{"memory before (unique images, RGBA8 + mips)", RS_PCA_MEMORY_BEFORE, JND_FMT_BYTES},
                   {"memory after (packed components + mips)", RS_PCA_MEMORY_AFTER, JND_FMT_BYTES},
                   {"channels", RS_PCA_CHANNEL_COUNT, JND_FMT_NUMBER},
                   {"components kept", RS_PCA_COMPONENTS_KEPT, JND_FMT_NUMBER},
                   {"knee of the energy curve", RS_PCA_KNEE, JND_FMT_NUMBER},
                   {"rendered: passes", RS_PCA_RENDERED_PASS, JND_FMT_BOOL},
                   {"rendered: P at the criterion", RS_PCA_RENDERED_P_CRITERION, JND_FMT_P},
                   {"rendered: P per view", RS_PCA_RENDERED_P_PER_VIEW, JND_FMT_LIST},
                   {"maps' width (px)", RS_PCA_WIDTH, JND_FMT_NUMBER}},
        .tables = {{"Channels",
                    RS_PCA_CHANNELS,
                    {{"channel", RS_PCA_CHANNELS_NAME, JND_FMT_TEXT},
                     {"PSNR dB", RS_PCA_CHANNELS_PSNR, JND_FMT_NUMBER},
                     {"PSNR BC4 dB", RS_PCA_CHANNELS_PSNR_BC4, JND_FMT_NUMBER},
                     {"PSNR BC1 dB", RS_PCA_CHANNELS_PSNR_BC1, JND_FMT_NUMBER},
                     {"PSNR plain BC dB", RS_PCA_CHANNELS_PSNR_PLAIN_BC, JND_FMT_NUMBER}}},
                   {"Components stored",
                    RS_PCA_TEXTURES,
                    {{"file", RS_PCA_TEXTURES_FILE, JND_FMT_TEXT},
                     {"width", RS_PCA_TEXTURES_WIDTH, JND_FMT_NUMBER},
                     {"height", RS_PCA_TEXTURES_HEIGHT, JND_FMT_NUMBER},
                     {"bits", RS_PCA_TEXTURES_BITS, JND_FMT_NUMBER}}}},
        .pictures = {{.file = "contribution.png",
                      .caption = "How much each channel feeds each component (001's |S·Tᵀ|)"},
                     {.path = RS_PATH(RS_PCA_TEXTURES, RS_PCA_TEXTURES_FILE), .caption = "The stored components, packed four to a texture"}},
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
        .p_detect = RS_DIFF_P_DETECT,
        .decision = diff_decision,
        .fields = {{"P(detect), pooled", RS_DIFF_P_DETECT, JND_FMT_P},
                   {"pooling", RS_DIFF_POOLING, JND_FMT_TEXT},
                   {"P median pixel", RS_DIFF_P_P50, JND_FMT_P},
                   {"P 99th percentile", RS_DIFF_P_P99, JND_FMT_P},
                   {"mean JND", RS_DIFF_JND_MEAN, JND_FMT_NUMBER},
                   {"93rd percentile JND", RS_DIFF_JND_P93, JND_FMT_NUMBER},
                   {"max JND", RS_DIFF_JND_MAX, JND_FMT_NUMBER},
                   {"width", RS_DIFF_WIDTH, JND_FMT_NUMBER},
                   {"height", RS_DIFF_HEIGHT, JND_FMT_NUMBER},
                   {"display", RS_DIFF_DISPLAY_NAME, JND_FMT_TEXT}},
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
        .fields = {{"renderer", RS_RENDER_RENDERER, JND_FMT_TEXT}},
        .pictures = {{.path = RS_PATH(RS_RENDER_VIEWS, RS_RENDER_VIEWS_COLOR), .caption = "The rendered views"}},
    },
    {
        .name = "lod",
        .out_args = {"-o", "{out}"},
        .json_name = "lod.json",
        .reserved = {"-o", "--output", "--json"},
        .memory_before = RS_LOD_MEMORY_BEFORE,
        .memory_after = RS_LOD_MEMORY_AFTER,
        .p_detect = RS_MAX(RS_PATH(RS_LOD_SCREENS, RS_LOD_SCREENS_PERCEPTUAL_STATISTIC)),
        .decision = lod_decision,
        .fields = {{"triangles before (level 0)", RS_LOD_TRIANGLES_BEFORE, JND_FMT_NUMBER},
                   {"triangles after (first screen's perceptual level)", RS_LOD_TRIANGLES_AFTER, JND_FMT_NUMBER},
                   {"memory before (float attributes, 32-bit indices)", RS_LOD_MEMORY_BEFORE, JND_FMT_BYTES},
                   {"memory after", RS_LOD_MEMORY_AFTER, JND_FMT_BYTES},
                   {"screen of the after figures", RS_LOD_MEMORY_SCREEN, JND_FMT_TEXT},
                   {"chain", RS_LOD_CHAIN_SOURCE, JND_FMT_TEXT},
                   {"criterion: P above", RS_LOD_CRITERION_P, JND_FMT_P},
                   {"criterion: fraction of views allowed above", RS_LOD_CRITERION_Q, JND_FMT_PERCENT},
                   {"model's switch coverages", RS_LOD_MODEL_SCREEN_COVERAGE, JND_FMT_LIST},
                   {"renderer", RS_LOD_RENDERER, JND_FMT_TEXT}},
        .tables = {{"Levels",
                    RS_LOD_LEVELS,
                    {{"level", RS_LOD_LEVELS_LEVEL, JND_FMT_NUMBER},
                     {"triangles", RS_LOD_LEVELS_TRIANGLES, JND_FMT_NUMBER},
                     {"meshoptimizer error", RS_LOD_LEVELS_ERROR, JND_FMT_NUMBER},
                     {"method", RS_LOD_LEVELS_METHOD, JND_FMT_TEXT}}},
                   {"Screens",
                    RS_LOD_SCREENS,
                    {{"screen", RS_LOD_SCREENS_NAME, JND_FMT_TEXT},
                     {"perceptual level", RS_LOD_SCREENS_PERCEPTUAL_LEVEL, JND_FMT_NUMBER},
                     {"its triangles", RS_LOD_SCREENS_PERCEPTUAL_TRIANGLES, JND_FMT_NUMBER},
                     {"003 PoI (lit)", RS_LOD_SCREENS_POI_TRIANGLES, JND_FMT_NUMBER},
                     {"meshopt 1 px rule", RS_LOD_SCREENS_MESHOPT_TRIANGLES, JND_FMT_NUMBER},
                     {"0.5 px rule", RS_LOD_SCREENS_PIXEL_ERROR_TRIANGLES, JND_FMT_NUMBER},
                     {"switch distances", RS_LOD_SCREENS_SWITCH_DISTANCE, JND_FMT_LIST},
                     {"switch coverages", RS_LOD_SCREENS_SWITCH_COVERAGE, JND_FMT_LIST}}}},
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
        .fields = {{"threshold (2AFC)", RS_GAZE_THRESHOLD, JND_FMT_P},
                   {"orientations", RS_GAZE_ORIENTATIONS, JND_FMT_NUMBER},
                   {"distances (m)", RS_GAZE_DISTANCES, JND_FMT_LIST},
                   {"eccentricities (deg)", RS_GAZE_ECCENTRICITIES, JND_FMT_LIST},
                   {"triangles per level", RS_GAZE_TRIANGLES, JND_FMT_LIST},
                   {"renderer", RS_GAZE_RENDERER, JND_FMT_TEXT}},
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
        .fields = {{"largest R (004: < 1 rarely visible, > 3 easily)", RS_POP_MAX_RATING, JND_FMT_NUMBER},
                   {"popping regions", RS_POP_REGION_COUNT, JND_FMT_NUMBER},
                   {"detection score (1..5)", RS_POP_DETECTION_SCORE, JND_FMT_NUMBER},
                   {"coverage score", RS_POP_COVERAGE_SCORE, JND_FMT_TEXT},
                   {"rating score", RS_POP_RATING_SCORE, JND_FMT_TEXT},
                   {"max ΔE*94 (baseline)", RS_POP_MAX_DELTA_E94, JND_FMT_NUMBER},
                   {"camera distance", RS_POP_DISTANCE, JND_FMT_NUMBER},
                   {"distances in", RS_POP_DISTANCE_UNIT, JND_FMT_TEXT},
                   {"renderer", RS_POP_RENDERER, JND_FMT_TEXT}},
        .tables = {{"Popping regions",
                    RS_POP_REGIONS,
                    {{"pixels", RS_POP_REGIONS_PIXELS, JND_FMT_NUMBER},
                     {"Σ", RS_POP_REGIONS_SIGMA, JND_FMT_NUMBER},
                     {"R", RS_POP_REGIONS_RATING, JND_FMT_NUMBER},
                     {"max JND", RS_POP_REGIONS_JND_MAX, JND_FMT_NUMBER}}},
                   {"Popping-free switch distances",
                    RS_POP_SWITCH,
                    {{"level", RS_POP_SWITCH_LEVEL, JND_FMT_NUMBER},
                     {"speed °/s", RS_POP_SWITCH_SPEED, JND_FMT_NUMBER},
                     {"distance", RS_POP_SWITCH_DISTANCE, JND_FMT_NUMBER},
                     {"1-pixel rule distance", RS_POP_SWITCH_PIXEL_RULE, JND_FMT_NUMBER},
                     {"search", RS_POP_SWITCH_STATUS, JND_FMT_TEXT}}}},
        .pictures = {{.file = "regions.png",
                      .caption = "The switching frame with its popping regions coloured by R (004 Fig. 4)"},
                     {.path = RS_POP_SWITCH_PLOT,
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
                   {"cost of texres + pca + lod separately", "result.comparison.separate_cost_bytes", JND_FMT_BYTES},
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
                                 "level, the Pareto front, the choice and texres + pca + lod chosen separately marked"}},
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
