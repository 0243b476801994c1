/* `jnd lod`'s report (docs/lod.md "The report"): what jnd_lod_run writes
 * as lod.json and returns. */
#include <math.h>

#include "tasks/report.h"

static const char *method_name(jnd_lod_method m) {
  switch (m) {
  case JND_LOD_INPUT: return "input";
  case JND_LOD_SIMPLIFIED: return "simplified";
  case JND_LOD_SLOPPY: return "sloppy";
  default: return "imported";
  }
}

cJSON *lod_report(const char *model, const jnd_lod_run_params *p, const jnd_lod_result *R, const char *model_rel) {
  cJSON *report = report_new("lod");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  cJSON *jl = cJSON_AddArrayToObject(in, "levels");
  for (int i = 0; i < p->nlevel_paths; i++) cJSON_AddItemToArray(jl, cJSON_CreateString(p->level_paths[i]));
  cJSON *jc = cJSON_AddObjectToObject(par, "chain");
  cJSON *je = cJSON_AddArrayToObject(jc, p->chain.ratios ? "ratios" : "errors");
  for (int k = 0; k < (p->chain.ratios ? p->chain.nratios : p->chain.errors ? p->chain.nerrors : 9); k++)
    cJSON_AddItemToArray(je, cJSON_CreateNumber(p->chain.ratios ? p->chain.ratios[k] : p->chain.errors ? p->chain.errors[k] : ldexp(1, k - 12)));
  cJSON_AddNumberToObject(jc, "lock_border", p->chain.lock_border);
  cJSON_AddBoolToObject(jc, "allow_sloppy", p->chain.allow_sloppy);
  cJSON_AddBoolToObject(jc, "rebuild", p->rebuild);
  cJSON_AddBoolToObject(par, "analyse", p->analyse);
  cJSON_AddNumberToObject(par, "views", p->poi.views);
  cJSON_AddNumberToObject(par, "seed", (double)p->poi.seed);
  cJSON_AddNumberToObject(par, "coverage", p->poi.coverage);
  cJSON_AddNumberToObject(par, "fov_y_deg", p->poi.fov_y_deg);
  cJSON_AddNumberToObject(par, "lights", p->poi.lights);
  cJSON_AddNumberToObject(par, "virtual_scale", p->poi.virtual_scale);
  cJSON_AddNumberToObject(par, "max_virtual_px", p->poi.max_virtual_px);
  cJSON_AddNumberToObject(par, "surface_samples", p->poi.surface_samples);
  cJSON_AddNumberToObject(par, "meshopt_pixels", p->poi.meshopt_pixels);
  cJSON_AddNumberToObject(par, "pixel_error", p->poi.pixel_error);
  cJSON_AddBoolToObject(par, "textures", p->poi.textures);
  cJSON *jpc = cJSON_AddObjectToObject(par, "perceptual");
  cJSON_AddBoolToObject(jpc, "enabled", p->perceptual && p->analyse);
  cJSON_AddItemToObject(jpc, "distance", p->sw.distance > 0 ? cJSON_CreateNumber(p->sw.distance) : cJSON_CreateNull());
  cJSON_AddNumberToObject(jpc, "views", p->sw.judge.views.sampling.count);
  cJSON_AddStringToObject(jpc, "task", jnd_viewing_task_name(p->sw.judge.model.display.task));
  cJSON_AddItemToObject(jpc, "criterion", report_criterion_json(&p->sw.judge.criterion, NULL));
  cJSON_AddNumberToObject(jpc, "far_coverage", p->sw.far_coverage);
  cJSON_AddNumberToObject(jpc, "tolerance", p->sw.tolerance);
  cJSON_AddNumberToObject(jpc, "max_px", p->sw.max_px);
  cJSON_AddNumberToObject(jpc, "samples", p->sw.judge.views.render.samples);
  cJSON *jpop = cJSON_AddObjectToObject(jpc, "pop");
  cJSON_AddBoolToObject(jpop, "enabled", p->sw.pop);
  cJSON_AddStringToObject(jpop, "motion", p->sw.pop_motion == JND_POP_OBJECT ? "spin" : p->sw.pop_motion == JND_POP_PAN ? "pan" : "orbit");
  cJSON_AddNumberToObject(jpop, "speed_dps", p->sw.pop_speed);
  cJSON_AddNumberToObject(jpop, "rating_limit", p->sw.pop_rating_limit);
  cJSON_AddStringToObject(jpop, "task", jnd_viewing_task_name(JND_TASK_FLICKER)); /* pop_model_create */

  cJSON_AddStringToObject(res, "chain_source", R->chain_source);
  int n = jnd_scene_lod_count(R->scene);
  const jnd_poi_result *P = R->analysed ? &R->poi : NULL;
  cJSON *jlev = cJSON_AddArrayToObject(res, "levels");
  for (int k = 0; k < n; k++) {
    jnd_lod_level_info li;
    jnd_scene_lod_info(R->scene, k, &li);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", k);
    cJSON_AddNumberToObject(o, "triangles", (double)li.triangles);
    cJSON_AddItemToObject(o, "error", report_number_or_null(li.error));
    cJSON_AddNumberToObject(o, "vertices", (double)li.vertices);
    cJSON_AddItemToObject(o, "error_abs", report_number_or_null(li.error_abs));
    cJSON_AddItemToObject(o, "target_error", report_number_or_null(k ? li.target_error : NAN));
    cJSON_AddItemToObject(o, "target_ratio", report_number_or_null(li.target_ratio));
    cJSON_AddStringToObject(o, "method", method_name(li.method));
    cJSON_AddNumberToObject(o, "sloppy_meshes", li.sloppy_meshes);
    if (li.source[0]) cJSON_AddStringToObject(o, "source", li.source);
    if (P) {
      cJSON_AddNumberToObject(o, "distance_rms", P->distance[k].rms / P->extent);
      cJSON_AddNumberToObject(o, "distance_max", P->distance[k].max / P->extent);
    }
    cJSON_AddItemToArray(jlev, o);
  }
  if (P) {
    cJSON_AddNumberToObject(res, "extent", P->extent);
    cJSON_AddNumberToObject(res, "radius", P->radius);
    cJSON_AddNumberToObject(res, "virtual_px", P->virtual_px);
    cJSON_AddNumberToObject(res, "renderings", P->renderings);
    cJSON_AddStringToObject(res, "renderer", P->renderer);
    cJSON *js = cJSON_AddArrayToObject(res, "screens");
    for (int i = 0; i < P->nscreens; i++) {
      const jnd_poi_screen_result *S = &P->screens[i];
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "name", S->screen.name);
      cJSON_AddNumberToObject(o, "width_px", S->screen.width_px);
      cJSON_AddNumberToObject(o, "height_px", S->screen.height_px);
      cJSON_AddNumberToObject(o, "ppd", S->screen.ppd);
      cJSON_AddNumberToObject(o, "object_px", S->object_px);
      cJSON_AddNumberToObject(o, "m2_px", S->m2_px);
      cJSON *cv = cJSON_AddArrayToObject(o, "curve");
      for (int k = 0; k < S->nlevels; k++) {
        const jnd_poi_point *q = &S->curve[k];
        cJSON *c = cJSON_CreateObject();
        cJSON_AddNumberToObject(c, "level", k);
        cJSON_AddNumberToObject(c, "error", q->error);
        cJSON_AddNumberToObject(c, "error_lit", q->error_lit);
        cJSON_AddNumberToObject(c, "object", q->object);
        cJSON_AddNumberToObject(c, "e_p", q->e_p);
        cJSON_AddNumberToObject(c, "m_p", q->m_p);
        cJSON_AddNumberToObject(c, "meshopt_px", q->meshopt_px);
        cJSON_AddNumberToObject(c, "deviation_px", q->deviation_px);
        cJSON_AddItemToArray(cv, c);
      }
      cJSON_AddNumberToObject(o, "poi_level", S->poi_level);
      cJSON_AddNumberToObject(o, "poi_triangles", (double)P->levels[S->poi_level].triangles);
      cJSON_AddNumberToObject(o, "poi_level_unlit", S->poi_level_unlit);
      cJSON_AddNumberToObject(o, "poi_triangles_unlit", (double)P->levels[S->poi_level_unlit].triangles);
      cJSON *rules = cJSON_AddObjectToObject(o, "rules");
      cJSON *rm = cJSON_AddObjectToObject(rules, "meshopt"), *rp = cJSON_AddObjectToObject(rules, "pixel_error");
      cJSON_AddNumberToObject(rm, "pixels", p->poi.meshopt_pixels);
      cJSON_AddNumberToObject(rm, "level", S->meshopt_level);
      cJSON_AddNumberToObject(rm, "triangles", (double)P->levels[S->meshopt_level].triangles);
      cJSON_AddNumberToObject(rp, "pixels", p->poi.pixel_error);
      cJSON_AddNumberToObject(rp, "level", S->pixel_level);
      cJSON_AddNumberToObject(rp, "triangles", (double)P->levels[S->pixel_level].triangles);
      if (i < R->nsw) {
        const jnd_lod_switch_result *W = &R->sw[i];
        cJSON_AddNumberToObject(o, "perceptual_level", W->perceptual_level);
        cJSON_AddNumberToObject(o, "perceptual_triangles", (double)P->levels[W->perceptual_level].triangles);
        cJSON_AddNumberToObject(o, "perceptual_statistic", W->statistic[W->perceptual_level]);
        /* never (INFINITY) is null */
        cJSON *sd = cJSON_AddArrayToObject(o, "switch_distance_m"), *sc = cJSON_AddArrayToObject(o, "switch_coverage");
        cJSON *jst = cJSON_AddArrayToObject(o, "statistic"), *pm = cJSON_AddArrayToObject(o, "p_max");
        /* its components: the criterion (a), popping (b; null where never or not searched) and what decided */
        cJSON *sda = cJSON_AddArrayToObject(o, "switch_distance_criterion_m"),
              *sdb = cJSON_AddArrayToObject(o, "switch_distance_pop_m"), *sby = cJSON_AddArrayToObject(o, "switch_by"),
              *jpr = cJSON_AddArrayToObject(o, "pop");
        /* the screen's scale each level was judged at at its criterion distance (1: the screen's own) */
        cJSON *ssc = cJSON_AddArrayToObject(o, "switch_scale");
        for (int k = 0; k < W->nlevels; k++) {
          cJSON_AddItemToArray(sda, report_number_or_null(W->switch_distance_criterion[k]));
          cJSON_AddItemToArray(ssc, report_number_or_null(W->switch_scale[k]));
          cJSON_AddItemToArray(sdb, report_number_or_null(W->switch_distance_pop[k]));
          cJSON_AddItemToArray(sby, cJSON_CreateString(jnd_lod_switch_by_name(W->switch_by[k])));
          if (k == 0) continue;
          int searched = !isnan(W->switch_distance_pop[k]);
          cJSON *r = cJSON_CreateObject();
          cJSON_AddNumberToObject(r, "level", k);
          cJSON_AddBoolToObject(r, "searched", searched);
          cJSON_AddBoolToObject(r, "never", searched && isinf(W->switch_distance_pop[k]));
          cJSON_AddItemToObject(r, "distance_m", report_number_or_null(W->switch_distance_pop[k]));
          /* the largest R there; null: not searched or no popping region */
          cJSON_AddItemToObject(r, "max_rating", report_number_or_null(W->pop_max_rating[k]));
          cJSON_AddItemToArray(jpr, r);
        }
        cJSON_AddNumberToObject(o, "pop_evaluations", W->pop_evaluations);
        for (int k = 0; k < W->nlevels; k++) {
          cJSON_AddItemToArray(sd, report_number_or_null(W->switch_distance[k]));
          cJSON_AddItemToArray(sc, cJSON_CreateNumber(W->switch_coverage[k]));
          cJSON_AddItemToArray(jst, report_number_or_null(W->statistic[k]));
          cJSON_AddItemToArray(pm, report_number_or_null(W->p_max[k]));
        }
        cJSON *vc = cJSON_AddObjectToObject(o, "viewing_condition");
        cJSON_AddNumberToObject(vc, "distance", W->view_distance);
        cJSON_AddNumberToObject(vc, "coverage", W->view_coverage);
        cJSON_AddNumberToObject(vc, "window_px", W->window_px);
        cJSON_AddNumberToObject(vc, "scale", W->scale);
        cJSON *jw = cJSON_AddObjectToObject(o, "judge");
        cJSON_AddNumberToObject(jw, "distances", W->distances);
        cJSON_AddNumberToObject(jw, "judgements", W->judgements);
        cJSON_AddNumberToObject(jw, "references", W->counts.references);
        cJSON_AddNumberToObject(jw, "renderings", W->counts.renderings);
        cJSON_AddNumberToObject(jw, "view_judgements", W->counts.view_judgements);
      } else {
        cJSON_AddNullToObject(o, "perceptual_level");
        cJSON_AddNullToObject(o, "switch_distance_m");
      }
      if (i < R->nplots) cJSON_AddStringToObject(o, "pareto_png", R->plots[i]);
      cJSON_AddItemToArray(js, o);
    }
    if (R->nsw == 0) cJSON_AddStringToObject(res, "perceptual", "not asked (--no-perceptual)");
    /* before and after: level 0 and the first screen's perceptual choice, as
     * the written model stores a level and a GPU holds it (jnd_scene_lod_bytes:
     * the attributes each mesh's material uses, 32-bit indices) */
    if (R->nsw > 0) {
      const jnd_lod_level_info *l0 = &P->levels[0], *l1 = &P->levels[R->sw[0].perceptual_level];
      cJSON *mem = cJSON_AddObjectToObject(res, "memory"), *tri = cJSON_AddObjectToObject(res, "triangles");
      cJSON_AddStringToObject(mem, "screen", R->sw[0].screen.name);
      cJSON_AddNumberToObject(mem, "level", R->sw[0].perceptual_level);
      cJSON_AddNumberToObject(mem, "before_bytes", (double)R->memory_before_bytes);
      cJSON_AddNumberToObject(mem, "after_bytes", (double)R->memory_after_bytes);
      cJSON_AddNumberToObject(tri, "before", (double)l0->triangles);
      cJSON_AddNumberToObject(tri, "after", (double)l1->triangles);
    }
    cJSON *jt = cJSON_AddArrayToObject(res, "textures");
    for (int t = 0; t < P->ntextures; t++) {
      const jnd_poi_texture *T = &P->textures[t];
      cJSON *o = cJSON_CreateObject();
      cJSON_AddStringToObject(o, "name", T->name);
      cJSON *lv = cJSON_AddArrayToObject(o, "levels");
      for (int k = 0; k < T->nlevels; k++) {
        cJSON_AddItemToArray(lv, report_pair(T->size[k]));
      }
      cJSON *sc = cJSON_AddArrayToObject(o, "screens");
      for (int i = 0; i < T->nscreens; i++) {
        cJSON *so = cJSON_CreateObject();
        cJSON_AddStringToObject(so, "name", P->screens[i].screen.name);
        cJSON *cv = cJSON_AddArrayToObject(so, "curve");
        for (int k = 0; k < T->nlevels; k++) {
          cJSON *c = cJSON_CreateObject();
          size_t x = (size_t)i * T->nlevels + k;
          cJSON_AddNumberToObject(c, "level", k);
          cJSON_AddNumberToObject(c, "e_p", T->e_p[x]);
          cJSON_AddNumberToObject(c, "m_p", T->m_p[x]);
          cJSON_AddNumberToObject(c, "error", T->error[x]);
          cJSON_AddItemToArray(cv, c);
        }
        cJSON_AddNumberToObject(so, "poi_level", T->poi_level[i]);
        cJSON_AddItemToObject(so, "poi_size", report_pair(T->size[T->poi_level[i]]));
        cJSON_AddNumberToObject(so, "poi_level_ep", T->poi_level_ep[i]);
        cJSON_AddItemToArray(sc, so);
      }
      cJSON_AddItemToArray(jt, o);
    }
  }
  cJSON *jm = cJSON_AddObjectToObject(res, "model");
  cJSON_AddStringToObject(jm, "path", model_rel);
  cJSON *cov = cJSON_AddArrayToObject(jm, "screen_coverage");
  for (int k = 0; k < n; k++) cJSON_AddItemToArray(cov, cJSON_CreateNumber(R->coverage[k]));
  cJSON_AddStringToObject(jm, "screen_coverage_rule", R->coverage_rule);
  if (p->run.timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "load_s", R->load_s);
    cJSON_AddNumberToObject(t, "load_cpu_s", R->load_cpu_s);
    cJSON_AddNumberToObject(t, "chain_s", R->chain_s);
    cJSON_AddNumberToObject(t, "chain_cpu_s", R->chain_cpu_s);
    cJSON_AddNumberToObject(t, "analysis_s", R->analysis_s);
    cJSON_AddNumberToObject(t, "analysis_cpu_s", R->analysis_cpu_s);
    cJSON_AddNumberToObject(t, "write_s", R->write_s);
  }
  return report;
}
