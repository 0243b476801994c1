/* `jnd budget`'s report (docs/budget.md "The report"): what jnd_budget_run
 * writes as budget.json and returns. */
#include <math.h>

#include "tasks/report.h"

static const char *kind_name(int scale) {
  return scale == -1 ? "searched" : scale == -2 ? "separate" : scale == -3 ? "encoded" : "ladder";
}

static cJSON *sizes_json(const jnd_budget_result *R, int (*sizes)[2]) {
  cJSON *o = cJSON_CreateObject();
  for (int i = 0; i < R->nmaps; i++) cJSON_AddItemToObject(o, R->map_names[i], report_pair(sizes[i]));
  return o;
}

static cJSON *layout_json(const jnd_pca_encoding *e) {
  cJSON *o = cJSON_CreateObject(), *sc = cJSON_CreateArray(), *bits = cJSON_CreateArray();
  cJSON_AddNumberToObject(o, "components", e->components);
  for (int k = 0; k < e->components; k++) {
    cJSON_AddItemToArray(sc, cJSON_CreateNumber(e->scale[k]));
    cJSON_AddItemToArray(bits, cJSON_CreateNumber(e->bits[k]));
  }
  cJSON_AddItemToObject(o, "scale", sc);
  cJSON_AddItemToObject(o, "bits", bits);
  return o;
}

/* `jnd pca`'s own choice per material, the separate candidate's third part */
static cJSON *separate_pca_json(const jnd_budget_result *R) {
  static const char *status[] = {"shared", "none passes", "dearer than its images", "taken"};
  cJSON *a = cJSON_CreateArray();
  for (int m = 0; m < R->npca; m++) {
    const jnd_budget_pca *q = &R->pca[m];
    if (!q->maps) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "material", jnd_scene_material_name(R->lod.scene, q->material));
    cJSON_AddStringToObject(o, "status", status[q->status]);
    cJSON_AddItemToObject(o, "statistic", report_number_or_null(q->statistic));
    if (q->status >= JND_BUDGET_PCA_DEARER) {
      cJSON_AddItemToObject(o, "encoding", layout_json(&q->encoding));
      cJSON_AddNumberToObject(o, "components_bytes", (double)q->components_bytes);
    }
    cJSON_AddNumberToObject(o, "images_bytes", (double)q->images_bytes);
    cJSON_AddItemToArray(a, o);
  }
  return a;
}

/* a level's held-out verification: its views, the statistic, pass at p */
static void add_verification(cJSON *o, const jnd_budget_level *L) {
  cJSON_AddNumberToObject(o, "views", L->views);
  cJSON_AddItemToObject(o, "statistic", report_number_or_null(L->statistic));
  cJSON_AddBoolToObject(o, "pass", L->pass);
}

static cJSON *candidate_json(const jnd_budget_result *R, int i, int with_sizes) {
  const jnd_budget_candidate *x = &R->candidates[i];
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "index", i);
  cJSON_AddStringToObject(o, "kind", kind_name(x->scale));
  cJSON_AddNumberToObject(o, "level", x->level);
  if (x->scale >= 0) {
    cJSON_AddNumberToObject(o, "halvings", x->scale);
    cJSON_AddBoolToObject(o, "inferred", x->inferred);
  }
  cJSON_AddNumberToObject(o, "memory_bytes", (double)x->memory_bytes);
  cJSON_AddNumberToObject(o, "triangles", (double)x->triangles);
  cJSON_AddNumberToObject(o, "cost_bytes", x->cost);
  cJSON_AddItemToObject(o, "statistic", report_number_or_null(x->statistic));
  cJSON_AddBoolToObject(o, "pass", x->pass);
  if (x->scale < 0) cJSON_AddBoolToObject(o, "passes_with_margin", x->searched_pass);
  if (x->held_out_fail) cJSON_AddBoolToObject(o, "dropped_on_held_out", 1);   /* step 6 */
  cJSON_AddBoolToObject(o, "pareto", x->pareto);
  int npacked = 0;   /* the materials packed by 001's PCA */
  for (int m = 0; m < jnd_scene_material_count(R->lod.scene); m++) {
    int in = 0;
    for (int q = 0; q < R->nmaps && !in; q++) {
      jnd_map_info mi;
      in = x->packed[q] && jnd_scene_map_info(R->lod.scene, q, &mi) == JND_OK && mi.material == m;
    }
    npacked += in;
  }
  cJSON_AddNumberToObject(o, "packed_materials", npacked);
  if (with_sizes) {
    cJSON_AddItemToObject(o, "sizes", sizes_json(R, x->sizes));
    cJSON *f = cJSON_AddObjectToObject(o, "formats");   /* per map: its image's GPU encoding */
    for (int m = 0; m < R->nmaps; m++)
      cJSON_AddStringToObject(f, R->map_names[m], x->packed[m] ? "pca" : jnd_tex_format_name(x->formats[m]));
    int packed = 0;
    for (int m = 0; m < R->nmaps; m++) packed += x->packed[m] > 0;
    if (packed) {   /* per map packed: its material's principal components (001), BC4/BC5 */
      cJSON *k = cJSON_AddObjectToObject(o, "pca_components");
      for (int m = 0; m < R->nmaps; m++)
        if (x->packed[m]) cJSON_AddNumberToObject(k, R->map_names[m], x->packed[m]);
      cJSON *lay = NULL;   /* per material packed in `jnd pca`'s own layout: its components' scales and bits */
      for (int m = 0; m < jnd_scene_material_count(R->lod.scene); m++)
        if (x->layouts[m].components > 0) {
          if (!lay) lay = cJSON_AddObjectToObject(o, "pca_layouts");
          cJSON_AddItemToObject(lay, jnd_scene_material_name(R->lod.scene, m), layout_json(&x->layouts[m]));
        }
    }
  }
  return o;
}

/* Unreal's ScreenSize and Unity's screenRelativeTransitionHeight of a
 * switch: both the bounding sphere's projected diameter over the screen's
 * height at the switch distance, for the vertical field of view
 * (jnd_coverage_at_distance: tan(asin(r / d)) / tan(fov / 2)) */
static cJSON *engines_json(const jnd_budget_result *R, int level) {
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; i < R->lod.nsw; i++) {
    const jnd_lod_switch_result *w = &R->lod.sw[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "screen", w->screen.name);
    cJSON_AddItemToObject(o, "switch_distance", report_number_or_null(w->switch_distance[level]));
    double h = level == 0 ? 1 : w->switch_coverage[level];
    cJSON_AddNumberToObject(o, "unreal_screen_size", h);
    cJSON_AddNumberToObject(o, "unity_screen_relative_transition_height", h);
    cJSON_AddItemToArray(a, o);
  }
  return a;
}

cJSON *budget_report(const char *model, const jnd_budget_params *p, const jnd_budget_result *R, const char *model_rel,
                     const double *coverage, const double *timings) {
  cJSON *report = report_new("budget");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  const jnd_texres_params *tp = &p->texres;
  cJSON_AddStringToObject(par, "mode", R->mode ? "budget" : "cheapest");
  cJSON_AddItemToObject(par, "memory_bytes", p->memory_bytes > 0 ? cJSON_CreateNumber(p->memory_bytes) : cJSON_CreateNull());
  cJSON_AddItemToObject(par, "triangles", p->triangles > 0 ? cJSON_CreateNumber(p->triangles) : cJSON_CreateNull());
  cJSON_AddNumberToObject(par, "bytes_per_triangle", R->bytes_per_triangle);
  cJSON_AddStringToObject(par, "bytes_per_triangle_source", p->bytes_per_triangle > 0 ? "given" : "level 0's vertex and index bytes per triangle");
  cJSON_AddNumberToObject(par, "coverage", p->lod.poi.coverage);
  cJSON_AddItemToObject(par, "display", report_display_json(&tp->judge.model.display));
  cJSON_AddItemToObject(par, "views", report_views_json(&tp->judge.views));
  cJSON_AddItemToObject(par, "criterion", report_criterion_json(&tp->judge.criterion, NULL));
  cJSON_AddNumberToObject(par, "margin", tp->margin);
  cJSON_AddNumberToObject(par, "min_size", tp->min_size);
  cJSON_AddNumberToObject(par, "verify_views", p->verify_views);
  cJSON *js = cJSON_AddArrayToObject(par, "screens");
  for (int i = 0; i < R->lod.nsw; i++) {
    const jnd_poi_screen *s = &R->lod.sw[i].screen;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", s->name);
    cJSON_AddItemToObject(o, "size", report_pair((int[]){s->width_px, s->height_px}));
    cJSON_AddNumberToObject(o, "ppd", s->ppd);
    cJSON_AddItemToArray(js, o);
  }
  cJSON_AddNumberToObject(par, "fov_y_deg", p->lod.poi.fov_y_deg);

  cJSON_AddStringToObject(res, "chain_source", R->lod.chain_source);
  cJSON *jc = cJSON_AddArrayToObject(res, "chain");
  for (int k = 0; k < jnd_scene_lod_count(R->lod.scene); k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(R->lod.scene, k, &li);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", k);
    cJSON_AddNumberToObject(o, "triangles", (double)li.triangles);
    cJSON *jp = cJSON_AddArrayToObject(o, "perceptual_on");
    for (int i = 0; i < R->lod.nsw; i++)
      if (R->lod.sw[i].perceptual_level == k) cJSON_AddItemToArray(jp, cJSON_CreateString(R->lod.sw[i].screen.name));
    cJSON_AddItemToArray(jc, o);
  }
  cJSON_AddItemToObject(res, "chosen", candidate_json(R, R->chosen, 1));
  cJSON *jse = candidate_json(R, R->separate, 1);
  cJSON_AddItemToObject(res, "separate", jse);
  /* judged as the chosen one is: its levels on the same held-out views at
   * each switch distance, the criterion at p */
  cJSON *jsv = cJSON_AddArrayToObject(jse, "verification");
  for (int j = 0; j < R->nseparate_levels; j++) {
    const jnd_budget_level *L = &R->separate_levels[j];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", L->level);
    cJSON_AddItemToObject(o, "switch_distance", report_number_or_null(L->switch_distance));
    add_verification(o, L);
    cJSON_AddItemToArray(jsv, o);
  }
  /* the separate candidate: texres's sizes, `jnd pca`'s choice per material, lod's perceptual level */
  cJSON_AddStringToObject(res, "separate_is", "texres + pca + lod");
  cJSON_AddItemToObject(res, "separate_pca", separate_pca_json(R));
  const jnd_budget_candidate *ch = &R->candidates[R->chosen], *se = &R->candidates[R->separate];
  cJSON *cmp = cJSON_AddObjectToObject(res, "comparison");
  for (int i = 0; i < R->ncandidates; i++)   /* the file as it is: level 0, every map at its size */
    if (R->candidates[i].level == 0 && R->candidates[i].scale == 0)
      cJSON_AddNumberToObject(cmp, "original_cost_bytes", R->candidates[i].cost);
  cJSON_AddNumberToObject(cmp, "chosen_cost_bytes", ch->cost);
  cJSON_AddNumberToObject(cmp, "separate_cost_bytes", se->cost);
  cJSON_AddNumberToObject(cmp, "saving_bytes", se->cost - ch->cost);
  cJSON_AddBoolToObject(cmp, "separate_passes_with_margin", se->searched_pass);
  /* step 7: the separate candidate taken instead of the joint search's own choice */
  cJSON_AddBoolToObject(cmp, "separate_taken", R->separate_taken);
  cJSON_AddNumberToObject(cmp, "joint_index", R->joint);
  cJSON_AddNumberToObject(cmp, "joint_cost_bytes", R->candidates[R->joint].cost);
  if (R->separate_taken) cJSON_AddItemToObject(cmp, "joint", candidate_json(R, R->joint, 1));
  cJSON *jl = cJSON_AddArrayToObject(res, "levels");
  for (int j = 0; j < R->nlevels; j++) {
    const jnd_budget_level *L = &R->levels[j];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "written_level", j);
    cJSON_AddNumberToObject(o, "level", L->level);
    cJSON_AddItemToObject(o, "switch_distance", report_number_or_null(L->switch_distance));
    cJSON_AddNumberToObject(o, "switch_coverage", L->switch_coverage);
    cJSON_AddItemToObject(o, "msft_screencoverage", report_number_or_null(coverage ? coverage[j] : NAN));
    cJSON_AddNumberToObject(o, "triangles", (double)L->triangles);
    cJSON_AddNumberToObject(o, "geometry_bytes", (double)L->geometry_bytes);
    cJSON_AddNumberToObject(o, "texture_bytes", (double)L->texture_bytes);
    cJSON_AddItemToObject(o, "sizes", sizes_json(R, L->sizes));
    add_verification(cJSON_AddObjectToObject(o, "verification"), L);
    cJSON_AddItemToObject(o, "engines", engines_json(R, L->level));
    cJSON_AddItemToArray(jl, o);
  }
  cJSON *jf = cJSON_AddArrayToObject(res, "pareto");
  for (int i = 0; i < R->ncandidates; i++)
    if (R->candidates[i].pareto) cJSON_AddItemToArray(jf, candidate_json(R, i, 0));
  cJSON *ja = cJSON_AddArrayToObject(res, "candidates");
  for (int i = 0; i < R->ncandidates; i++) cJSON_AddItemToArray(ja, candidate_json(R, i, 0));
  cJSON_AddStringToObject(res, "model", model_rel);
  cJSON_AddStringToObject(res, "pareto_plot", "pareto.png");
  cJSON_AddBoolToObject(res, "passes", R->passes);
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "search_s", R->search_s);
    cJSON_AddNumberToObject(t, "verify_s", R->verify_s);
    cJSON_AddNumberToObject(t, "total_s", timings[0]);
  }
  return report;
}
