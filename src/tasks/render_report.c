/* `jnd render`'s report (docs/render.md "views.json"): what jnd_render_run
 * writes as views.json and returns. The views' entries are filled as the
 * frames are written (render_run.c), with their cameras and lights from
 * here. */
#include <math.h>

#include "tasks/report.h"

static cJSON *vec3_json(const double v[3]) {
  cJSON *a = cJSON_CreateArray();
  for (int k = 0; k < 3; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
  return a;
}

static cJSON *camera_json(const jnd_camera *c) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddItemToObject(o, "eye", vec3_json(c->eye));
  cJSON_AddItemToObject(o, "target", vec3_json(c->target));
  cJSON_AddItemToObject(o, "up", vec3_json(c->up));
  cJSON_AddNumberToObject(o, "fov_y_deg", c->fov_y_deg);
  cJSON_AddNumberToObject(o, "znear", c->znear);
  cJSON_AddNumberToObject(o, "zfar", c->zfar);
  return o;
}

static cJSON *light_json(const jnd_light *L) {
  static const char *const types[] = {"directional", "point", "spot"};
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "type", types[L->type]);
  if (L->type != JND_LIGHT_DIRECTIONAL) cJSON_AddItemToObject(o, "position", vec3_json(L->position));
  if (L->type != JND_LIGHT_POINT) cJSON_AddItemToObject(o, "direction", vec3_json(L->direction));
  cJSON_AddItemToObject(o, "color", vec3_json(L->color));
  cJSON_AddNumberToObject(o, "intensity", L->intensity);
  if (L->range > 0) cJSON_AddNumberToObject(o, "range", L->range);
  if (L->type == JND_LIGHT_SPOT) {
    cJSON_AddNumberToObject(o, "inner_deg", L->inner_deg);
    cJSON_AddNumberToObject(o, "outer_deg", L->outer_deg);
  }
  return o;
}

cJSON *render_report(const char *model, const jnd_render_params *p, const jnd_scene *scene, int nviews,
                     const char *renderer) {
  const jnd_view_set *vs = &p->views;
  cJSON *report = report_new("render");
  cJSON *in = report_section(report, "inputs");
  cJSON_AddStringToObject(in, "model", model);
  if (vs->render.env_path) cJSON_AddStringToObject(in, "env", vs->render.env_path);
  if (vs->cameras_path) cJSON_AddStringToObject(in, "cameras", vs->cameras_path);
  cJSON *par = report_section(report, "parameters");
  cJSON_AddNumberToObject(par, "views", nviews);
  cJSON_AddNumberToObject(par, "seed", (double)vs->sampling.seed);
  cJSON_AddNumberToObject(par, "width", vs->render.width);
  cJSON_AddNumberToObject(par, "height", vs->render.height);
  cJSON_AddNumberToObject(par, "coverage", vs->sampling.coverage);
  if (vs->sampling.distance > 0) cJSON_AddNumberToObject(par, "distance", vs->sampling.distance);
  cJSON_AddNumberToObject(par, "fov_y_deg", vs->sampling.fov_y_deg);
  cJSON_AddNumberToObject(par, "env_intensity", p->env_intensity);
  cJSON_AddNumberToObject(par, "env_rotation_deg", p->env_rotation_deg);
  cJSON_AddNumberToObject(par, "exposure", p->exposure);
  cJSON_AddStringToObject(par, "background", p->background_env ? "env" : "black");
  cJSON_AddNumberToObject(par, "samples", vs->render.samples);
  cJSON_AddNumberToObject(par, "anisotropy", vs->render.anisotropy);
  cJSON *res = report_section(report, "result");
  cJSON_AddStringToObject(res, "renderer", renderer);
  double centre[3], radius;
  jnd_scene_bounds(scene, centre, &radius);
  cJSON_AddItemToObject(res, "centre", vec3_json(centre));
  cJSON_AddNumberToObject(res, "radius", radius);
  cJSON_AddNumberToObject(res, "triangles", (double)jnd_scene_triangle_count(scene));
  cJSON_AddNumberToObject(res, "lod", p->lod);
  cJSON_AddNumberToObject(res, "lod_levels", jnd_scene_lod_count(scene));
  cJSON_AddNumberToObject(res, "materials", jnd_scene_material_count(scene));
  cJSON *jmaps = cJSON_AddArrayToObject(report, "maps");
  for (int i = 0; i < jnd_scene_map_count(scene); i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "name", mi.name);
    cJSON_AddNumberToObject(m, "width", mi.width);
    cJSON_AddNumberToObject(m, "height", mi.height);
    cJSON_AddNumberToObject(m, "orig_width", mi.orig_width);
    cJSON_AddNumberToObject(m, "orig_height", mi.orig_height);
    cJSON_AddNumberToObject(m, "uv_set", mi.uv_set);
    cJSON *uvt = cJSON_AddArrayToObject(m, "uv_transform");
    for (int k = 0; k < 6; k++) cJSON_AddItemToArray(uvt, cJSON_CreateNumber(mi.uv_transform[k]));
    cJSON_AddItemToArray(jmaps, m);
  }
  cJSON_AddArrayToObject(report, "views");
  return report;
}

void render_report_view_end(cJSON *jv, const jnd_view *view) {
  cJSON_AddItemToObject(jv, "camera", camera_json(&view->camera));
  if (view->has_prev) cJSON_AddItemToObject(jv, "prev_camera", camera_json(&view->prev_camera));
  cJSON *jl = cJSON_AddArrayToObject(jv, "lights");
  for (int l = 0; l < view->nlights; l++) cJSON_AddItemToArray(jl, light_json(&view->lights[l]));
}

void render_report_end(cJSON *report, const double *mip_min, const jnd_render_result *R, int timings) {
  if (mip_min) {
    cJSON *jmaps = cJSON_GetObjectItemCaseSensitive(report, "maps");
    for (int i = 0; i < cJSON_GetArraySize(jmaps); i++) {
      cJSON *m = cJSON_GetArrayItem(jmaps, i);
      if (isfinite(mip_min[i])) cJSON_AddNumberToObject(m, "mip_min", mip_min[i]);
    }
  }
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(report_section(report, "result"), "timings");
    cJSON_AddNumberToObject(t, "load_s", R->load_s);
    cJSON_AddNumberToObject(t, "renderer_s", R->renderer_s);
    cJSON_AddNumberToObject(t, "render_s", R->render_s);
    cJSON_AddNumberToObject(t, "fps", R->render_s > 0 ? R->views / R->render_s : 0);
  }
}
