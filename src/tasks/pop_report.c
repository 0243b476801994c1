/* The report of `jnd pop` (jnd_pop_run): the pair's regions, scores and
 * weights in both forms; a sequence's table; the asset form's chain,
 * motion, views and switch table. */
#include <math.h>

#include "tasks/report.h"

static cJSON *int4(const int *v) {
  cJSON *a = cJSON_CreateArray();
  for (int k = 0; k < 4; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
  return a;
}

/* a number, or null where it is undefined (no region) */
static void add_num(cJSON *o, const char *key, double v) { cJSON_AddItemToObject(o, key, report_number_or_null(v)); }

static cJSON *weight_json(const jnd_pop_weight_stats *w) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddBoolToObject(o, "present", w->present);
  if (w->present) {
    cJSON_AddNumberToObject(o, "mean", w->mean);
    cJSON_AddNumberToObject(o, "min", w->min);
    cJSON_AddNumberToObject(o, "pixels_below_half", (double)w->below_half);
  }
  return o;
}

/* the pair's result: regions, scores, weights (the same fields in both forms) */
static void result_json(cJSON *res, const jnd_pop_result *r, int max_regions) {
  cJSON_AddNumberToObject(res, "width", r->w);
  cJSON_AddNumberToObject(res, "height", r->h);
  cJSON_AddNumberToObject(res, "region_count", r->nregions);
  cJSON *regs = cJSON_AddArrayToObject(res, "regions");
  for (int k = 0; k < r->nregions && k < max_regions; k++) {
    const jnd_pop_region *g = &r->regions[k];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "pixels", (double)g->pixels);
    cJSON_AddNumberToObject(o, "sigma", g->sigma);
    cJSON_AddNumberToObject(o, "rating", g->rating);
    cJSON_AddItemToObject(o, "bbox", int4(g->bbox));
    cJSON_AddNumberToObject(o, "jnd_max", g->jnd_max);
    cJSON_AddItemToArray(regs, o);
  }
  add_num(res, "max_rating", r->max_rating);
  cJSON_AddNumberToObject(res, "coverage", r->coverage);
  cJSON_AddStringToObject(res, "coverage_score", jnd_pop_coverage_name(r->coverage_score));
  add_num(res, "rating_top", r->rating_top);
  cJSON_AddStringToObject(res, "rating_score", jnd_pop_rating_name(r->rating_score));
  cJSON_AddNumberToObject(res, "detection_score", r->detection_score);
  cJSON_AddNumberToObject(res, "max_delta_e94", r->max_delta_e94);
  cJSON_AddNumberToObject(res, "jnd_max", r->jnd_max);
  cJSON_AddNumberToObject(res, "object_pixels", (double)r->object_pixels);
  cJSON_AddNumberToObject(res, "covered_pixels", (double)r->covered_pixels);
  cJSON *wj = cJSON_AddObjectToObject(res, "weights");
  cJSON_AddItemToObject(wj, "disocclusion", weight_json(&r->disocclusion));
  cJSON_AddItemToObject(wj, "flicker", weight_json(&r->flicker));
  cJSON_AddItemToObject(wj, "user", weight_json(&r->user));
}

static void params_json(cJSON *params, const jnd_pop_run_params *p) {
  const jnd_model_params *mp = &p->model;
  const jnd_pop_params *pp = &p->pop;
  cJSON_AddItemToObject(params, "display", report_display_json(&mp->display));
  cJSON_AddNumberToObject(params, "fps", mp->fps);
  cJSON_AddNumberToObject(params, "threshold_jnd", pp->threshold_jnd);
  cJSON_AddNumberToObject(params, "minkowski", pp->minkowski);
  cJSON_AddNumberToObject(params, "depth_tolerance", pp->depth_tolerance);
  cJSON *fl = cJSON_AddObjectToObject(params, "flicker");
  cJSON_AddNumberToObject(fl, "ratio_lo", pp->flicker_ratio_lo);
  cJSON_AddNumberToObject(fl, "ratio_hi", pp->flicker_ratio_hi);
  cJSON_AddNumberToObject(fl, "motion_lo_px", pp->flicker_motion_lo_px);
  cJSON_AddNumberToObject(fl, "motion_hi_px", pp->flicker_motion_hi_px);
  cJSON_AddNumberToObject(params, "top_regions", pp->top_regions);
  cJSON *ct = cJSON_AddArrayToObject(params, "coverage_thresholds");
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp->coverage_small));
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp->coverage_large));
  cJSON_AddItemToArray(ct, cJSON_CreateNumber(pp->coverage_huge));
  cJSON *rt = cJSON_AddArrayToObject(params, "rating_thresholds");
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp->rating_low));
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp->rating_high));
  cJSON_AddItemToArray(rt, cJSON_CreateNumber(pp->rating_very_high));
  cJSON_AddNumberToObject(params, "sensitivity", mp->sensitivity);
  cJSON_AddNumberToObject(params, "sens_rg", mp->sens_rg);
  cJSON_AddNumberToObject(params, "sens_yv", mp->sens_yv);
  if (isfinite(p->fail_above)) cJSON_AddNumberToObject(params, "fail_above", p->fail_above);
}

/* the sequence's table: .result.frames[] */
static void frames_json(cJSON *res, const jnd_pop_sequence_result *q) {
  cJSON_AddNumberToObject(res, "worst_frame", q->rows[q->worst].frame);
  cJSON *fr = cJSON_AddArrayToObject(res, "frames");
  for (int i = 0; i < q->nrows; i++) {
    const jnd_pop_frame_row *w = &q->rows[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "frame", w->frame);
    add_num(o, "max_rating", w->max_rating);
    cJSON_AddNumberToObject(o, "detection_score", w->detection_score);
    cJSON_AddNumberToObject(o, "regions", w->nregions);
    cJSON_AddNumberToObject(o, "max_delta_e94", w->max_delta_e94);
    cJSON_AddNumberToObject(o, "coverage", w->coverage);
    cJSON_AddStringToObject(o, "coverage_score", jnd_pop_coverage_name(w->coverage_score));
    add_num(o, "rating_top", w->rating_top);
    cJSON_AddStringToObject(o, "rating_score", jnd_pop_rating_name(w->rating_score));
    cJSON_AddNumberToObject(o, "jnd_max", w->jnd_max);
    cJSON_AddItemToArray(fr, o);
  }
}

static const char *motion_name(jnd_pop_motion_kind k) {
  return k == JND_POP_ORBIT ? "orbit" : k == JND_POP_TRANSLATE ? "translate" : k == JND_POP_PAN ? "pan" : "spin";
}

static const char *switch_status_name(jnd_pop_switch_status s) {
  return s == JND_POP_SWITCH_FOUND ? "found" : s == JND_POP_SWITCH_NEAREST ? "nearest" : "none";
}

/* the asset form's own report parts: chain, motion, views, switch table */
static void asset_json(cJSON *inputs, cJSON *params, cJSON *res, const char *model, const jnd_pop_asset_params *ap,
                       const jnd_pop_asset_report *R) {
  static const double default_speeds[] = {0, 30, 120};
  const double *speeds = ap->speeds ? ap->speeds : default_speeds;
  const int nspeeds = ap->speeds ? ap->nspeeds : 3;
  cJSON_AddStringToObject(inputs, "model", model);
  cJSON *jl = cJSON_AddArrayToObject(inputs, "levels");
  for (int i = 0; i < ap->nlevel_paths; i++) cJSON_AddItemToArray(jl, cJSON_CreateString(ap->level_paths[i]));
  jnd_view_set vs = ap->views;
  if (ap->cameras) vs.cameras_path = ap->cameras;
  cJSON_AddItemToObject(params, "views", report_views_json(&vs));
  cJSON *mo = cJSON_AddObjectToObject(params, "motion");
  cJSON_AddStringToObject(mo, "kind", motion_name(ap->motion.kind));
  cJSON_AddNumberToObject(mo, "speed", ap->motion.speed);
  cJSON_AddStringToObject(mo, "unit", ap->motion.kind == JND_POP_TRANSLATE ? "m/s" : "deg/s");
  if (ap->motion.kind == JND_POP_TRANSLATE) {
    cJSON *d = cJSON_AddArrayToObject(mo, "direction");
    for (int k = 0; k < 3; k++) cJSON_AddItemToArray(d, cJSON_CreateNumber(ap->motion.direction[k]));
  }
  cJSON_AddNumberToObject(mo, "unit_m", ap->motion.unit_m);
  cJSON_AddNumberToObject(params, "switch_level", ap->level);
  cJSON_AddNumberToObject(params, "frame", ap->frame);
  if (ap->decide) {
    cJSON *se = cJSON_AddObjectToObject(params, "search");
    cJSON *sj = cJSON_AddArrayToObject(se, "speeds_dps");
    for (int s = 0; s < nspeeds; s++) cJSON_AddItemToArray(sj, cJSON_CreateNumber(speeds[s]));
    cJSON_AddNumberToObject(se, "rating_limit", ap->search.rating_limit);
    cJSON_AddNumberToObject(se, "tolerance", ap->search.tolerance);
    cJSON_AddNumberToObject(se, "coverage_near", ap->search.coverage_near);
    cJSON_AddNumberToObject(se, "coverage_far", ap->search.coverage_far);
    cJSON_AddStringToObject(se, "pixel_rule", "level's error_abs covers 1 pixel of the image height at the distance");
  }
  cJSON_AddStringToObject(res, "renderer", R->renderer);
  cJSON_AddStringToObject(res, "chain_source", R->chain_source);
  cJSON *lv = cJSON_AddArrayToObject(res, "levels");
  for (int k = 0; k < R->nlevels; k++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", k);
    cJSON_AddNumberToObject(o, "triangles", (double)R->levels[k].triangles);
    add_num(o, "error_abs", R->levels[k].error_abs);
    cJSON_AddItemToArray(lv, o);
  }
  cJSON_AddNumberToObject(res, "views", R->nviews);
  cJSON_AddNumberToObject(res, "distance_m", R->pair_distance * ap->motion.unit_m);
  cJSON_AddStringToObject(res, "distance_unit", R->distance_unit); /* of every distance_m */
  if (!ap->decide) return;
  cJSON *sw = cJSON_AddArrayToObject(res, "switch");
  for (int i = 0; i < R->nrows; i++) {
    const jnd_pop_switch_row *w = &R->rows[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "level", w->level);
    cJSON_AddNumberToObject(o, "speed_dps", w->speed_dps);
    add_num(o, "distance_m", w->distance_m);
    add_num(o, "distance_m_pixel_rule", w->distance_m_pixel_rule);
    cJSON_AddStringToObject(o, "status", switch_status_name(w->sw.status));
    add_num(o, "max_rating", w->sw.max_rating);
    cJSON_AddNumberToObject(o, "evaluations", w->sw.evaluations);
    cJSON_AddItemToArray(sw, o);
  }
  cJSON_AddStringToObject(cJSON_GetObjectItem(res, "outputs"), "switch", "switch.png");
}

cJSON *pop_report(const char *model, const jnd_pop_run_params *p, const jnd_pop_asset_params *ap,
                  const jnd_pop_run_result *R, const double *timings) {
  const jnd_pop_result *pair = R->pair;
  cJSON *report = report_new("pop");
  cJSON *inputs = report_section(report, "inputs"), *params = report_section(report, "parameters"),
        *res = report_section(report, "result");
  if (!model) {
    const jnd_pop_paths *f = &p->frames;
    const char *in_keys[] = {"new", "expected", "displacement", "displacement_expected", "depth", "depth_expected",
                             "prev_depth", "prev_depth_expected", "weights", "prev_frame", "prev_shading", "mask"};
    const char *in_vals[] = {f->actual, f->expected, f->displacement, f->displacement_expected, f->depth,
                             f->depth_expected, f->prev_depth, f->prev_depth_expected, f->weights, f->prev_color,
                             f->prev_shading, f->mask};
    for (size_t k = 0; k < sizeof in_keys / sizeof in_keys[0]; k++)
      if (in_vals[k]) cJSON_AddStringToObject(inputs, in_keys[k], in_vals[k]);
    if (p->sequence) {
      cJSON *fr = cJSON_AddArrayToObject(inputs, "frames");
      cJSON_AddItemToArray(fr, cJSON_CreateNumber(p->seq.first));
      cJSON_AddItemToArray(fr, cJSON_CreateNumber(p->seq.last));
    }
  }
  params_json(params, p);
  result_json(res, pair, p->max_regions);
  cJSON *outs = cJSON_AddObjectToObject(res, "outputs");
  cJSON_AddStringToObject(outs, "regions", "regions.png");
  if (p->sequence) {
    cJSON_AddStringToObject(outs, "frames", "frames.csv");
    frames_json(res, &R->sequence);
  }
  if (p->maps) {
    cJSON_AddStringToObject(outs, "jnd", "jnd.exr");
    if (pair->weights.data) cJSON_AddStringToObject(outs, "weights", "weights.exr");
  }
  if (model) asset_json(inputs, params, res, model, ap, &R->asset);
  if (isfinite(p->fail_above)) cJSON_AddBoolToObject(res, "above_threshold", R->above);
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "read_s", pair->timings.read_s);
    cJSON_AddNumberToObject(t, "weights_s", pair->timings.weights_s);
    cJSON_AddNumberToObject(t, "model_s", pair->timings.model_s);
    cJSON_AddNumberToObject(t, "regions_s", pair->timings.regions_s);
    cJSON_AddNumberToObject(t, "picture_s", pair->timings.picture_s);
    if (model) {
      cJSON_AddNumberToObject(t, "load_s", R->asset.load_s);
      cJSON_AddNumberToObject(t, "render_s", R->asset.render_s);
      cJSON_AddNumberToObject(t, "decide_s", R->asset.decide_s);
    }
    cJSON_AddNumberToObject(t, "write_s", timings[0]);
    cJSON_AddNumberToObject(t, "total_s", timings[1]);
  }
  return report;
}
