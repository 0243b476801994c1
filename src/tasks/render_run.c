/* `jnd render` as one call (jnd_render_run): the asset opened and edited,
 * every view rendered, its frames and views.json written through one output
 * writer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"

void jnd_render_defaults(jnd_render_params *p) {
  memset(p, 0, sizeof *p);
  jnd_view_set_defaults(&p->views);
  p->views.render.width = p->views.render.height = 512;
  p->env_intensity = 1;
  p->exposure = 1;
  p->motion_orbit_deg = 0.5;
  p->outputs = JND_RENDER_COLOR | JND_RENDER_MASK;
  jnd_run_options_defaults(&p->run);
}

void jnd_render_result_free(jnd_render_result *r) {
  if (!r) return;
  free(r->report);
  free(r);
}

/* MAP matches "MAT/SLOT" with "*" for the material, or a bare "*". */
static int map_matches(const char *pattern, const char *name) {
  if (strcmp(pattern, "*") == 0) return 1;
  if (strncmp(pattern, "*/", 2) == 0) {
    const char *slash = strrchr(name, '/');
    return slash && strcmp(slash + 1, pattern + 2) == 0;
  }
  return strcmp(pattern, name) == 0;
}

static jnd_status apply_edit(jnd_scene *scene, const jnd_map_edit *e) {
  int hits = 0;
  jnd_image img = {0};
  jnd_image_info info;
  jnd_status st = e->file ? jnd_image_read(e->file, &img, &info) : JND_OK;
  for (int i = 0; !st && i < jnd_scene_map_count(scene); i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    if (!map_matches(e->map, mi.name)) continue;
    hits++;
    if (e->file && info.encoding == JND_ENCODING_LINEAR && mi.kind == JND_MAP_KIND_COLOR) {
      st = jnd_fail(JND_ERR_ARG, "%s: a linear image cannot replace the colour map %s (give PNG/JPEG)", e->file,
                    mi.name);
      break;
    }
    if (e->file) {
      st = jnd_scene_map_set(scene, i, &img);
    } else if (e->w > 0) {
      st = jnd_scene_map_resize(scene, i, e->w, e->h);
    } else {
      int w = (int)lround(mi.orig_width * e->factor), h = (int)lround(mi.orig_height * e->factor);
      st = jnd_scene_map_resize(scene, i, w < 1 ? 1 : w, h < 1 ? 1 : h);
    }
    if (st) st = jnd_fail(st, "%s: %s", mi.name, jnd_last_error());
  }
  jnd_image_free(&img);
  if (!st && !hits)
    st = jnd_fail(JND_ERR_ARG, "%s: no such map in %s (jnd render %s --list-maps)", e->map, jnd_scene_path(scene),
                  jnd_scene_path(scene));
  return st;
}

/* The camera orbited by deg about the vertical axis through the target. */
static void orbit(const jnd_camera *c, double deg, jnd_camera *out) {
  *out = *c;
  double a = deg * M_PI / 180, cs = cos(a), sn = sin(a);
  double dx = c->eye[0] - c->target[0], dz = c->eye[2] - c->target[2];
  out->eye[0] = c->target[0] + cs * dx + sn * dz;
  out->eye[2] = c->target[2] - sn * dx + cs * dz;
}

/* dir/name as PNG (bits 0: EXR with channel names), listed in the view under key */
static jnd_status write_image(const char *dir, const char *name, const jnd_image *img, int bits,
                              const char *const *names, cJSON *view, const char *key) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  jnd_status st = bits ? jnd_image_write_png(path, img, bits) : jnd_image_write_exr(path, img, names, 0);
  if (!st) cJSON_AddStringToObject(view, key, name);
  return st;
}

/* one view's frame written as the outputs ask, listed in jv; mip_min the
 * finest level each map is sampled at over the views so far */
static jnd_status write_view(const jnd_render_params *p, const jnd_scene *scene, const jnd_view *view,
                             const jnd_frame *f, int i, const char *dir, cJSON *jv, double *mip_min) {
  int width = p->views.render.width, height = p->views.render.height;
  size_t P = (size_t)width * height;
  unsigned outputs = p->outputs;
  char name[64];
  jnd_image tmp = {0};
  jnd_status st = JND_OK;
  cJSON_AddNumberToObject(jv, "index", i);
  if (outputs & JND_RENDER_COLOR) {
    snprintf(name, sizeof name, "view_%03d.png", i);
    st = jnd_render_to_srgb(&f->color, &tmp);
    if (!st) st = write_image(dir, name, &tmp, 8, NULL, jv, "color");
    jnd_image_free(&tmp);
    if (!st && (outputs & JND_RENDER_EXR)) {
      snprintf(name, sizeof name, "view_%03d.exr", i);
      st = write_image(dir, name, &f->color, 0, NULL, jv, "color_exr");
    }
  }
  double cover = 0;
  for (size_t k = 0; k < P; k++) cover += f->mask.data[k];
  cJSON_AddNumberToObject(jv, "coverage", cover / ((double)width * height));
  if (!st && (outputs & JND_RENDER_MASK)) {
    snprintf(name, sizeof name, "view_%03d_mask.png", i);
    st = write_image(dir, name, &f->mask, 8, NULL, jv, "mask");
  }
  if (!st && (outputs & JND_RENDER_DEPTH)) {
    double scale = view->camera.zfar > 0 ? view->camera.zfar : 1;
    for (size_t k = 0; k < P; k++)
      if (f->depth.data[k] > scale) scale = f->depth.data[k];
    if (jnd_image_alloc(&tmp, width, height, 1) == JND_OK) {
      for (size_t k = 0; k < P; k++) tmp.data[k] = (float)(f->depth.data[k] / scale);
      snprintf(name, sizeof name, "view_%03d_depth.png", i);
      st = write_image(dir, name, &tmp, 16, NULL, jv, "depth");
      cJSON_AddNumberToObject(jv, "depth_scale", scale);
      jnd_image_free(&tmp);
    }
    if (!st && (outputs & JND_RENDER_EXR)) {
      snprintf(name, sizeof name, "view_%03d_depth.exr", i);
      st = write_image(dir, name, &f->depth, 0, NULL, jv, "depth_exr");
    }
  }
  if (!st && (outputs & JND_RENDER_MOTION)) {
    double mx = 0;
    for (size_t k = 0; k < 2 * P; k++)
      if (fabs(f->motion.data[k]) > mx) mx = fabs(f->motion.data[k]);
    double scale = mx > 0 ? pow(2, ceil(log2(mx))) : 1;
    if (jnd_image_alloc(&tmp, width, height, 3) == JND_OK) {
      for (size_t k = 0; k < 2 * P; k++) tmp.data[k] = (float)(0.5 + f->motion.data[k] / (2 * scale));
      snprintf(name, sizeof name, "view_%03d_motion.png", i);
      st = write_image(dir, name, &tmp, 16, NULL, jv, "motion");
      cJSON_AddNumberToObject(jv, "motion_scale", scale);
      jnd_image_free(&tmp);
    }
    if (!st && (outputs & JND_RENDER_EXR)) {
      static const char *const xy[2] = {"X", "Y"};
      snprintf(name, sizeof name, "view_%03d_motion.exr", i);
      st = write_image(dir, name, &f->motion, 0, xy, jv, "motion_exr");
    }
  }
  if (!st && (outputs & JND_RENDER_MIP)) {
    if (jnd_image_alloc(&tmp, width, height, 4) == JND_OK) {
      for (size_t k = 0; k < 4 * P; k++) tmp.data[k] = (float)((f->mip.data[k] + 1) / 64.0);
      snprintf(name, sizeof name, "view_%03d_mip.png", i);
      st = write_image(dir, name, &tmp, 16, NULL, jv, "mip");
      jnd_image_free(&tmp);
    }
    if (!st && (outputs & JND_RENDER_EXR)) {
      /* one channel per slot, named for it (readers order EXR channels by name) */
      static const char *const slots[5] = {"baseColor", "metallicRoughness", "normal", "occlusion", "emissive"};
      snprintf(name, sizeof name, "view_%03d_mip.exr", i);
      st = write_image(dir, name, &f->mip, 0, slots, jv, "mip_exr");
    }
    /* the finest level each map is sampled at in this view (000 §4: a
     * map never sampled at level 0 can be halved) */
    cJSON *mm = cJSON_AddObjectToObject(jv, "mip_min");
    for (int mi = 0; mi < jnd_scene_map_count(scene); mi++) {
      jnd_map_info info;
      jnd_scene_map_info(scene, mi, &info);
      double lo = INFINITY;
      const float *lv = f->mip.data + (size_t)info.slot * P;
      for (size_t k = 0; k < P; k++)
        if ((int)lroundf(f->material.data[k]) == info.material && lv[k] >= 0 && lv[k] < lo) lo = lv[k];
      if (isfinite(lo)) {
        cJSON_AddNumberToObject(mm, info.name, lo);
        if (lo < mip_min[mi]) mip_min[mi] = lo;
      }
    }
  }
  if (!st) render_report_view_end(jv, view);
  return st;
}

jnd_status jnd_render_run(const char *model, const jnd_render_params *pp, const char *out_dir,
                          jnd_render_result **out) {
  *out = NULL;
  if (!model || !out_dir) return jnd_fail(JND_ERR_ARG, "render: give a model and an output folder");
  jnd_render_params p;
  if (pp) p = *pp;
  else jnd_render_defaults(&p);
  double t0 = jnd_seconds();
  /* the outputs checked against every input before any work */
  int nin = 3 + (p.nedits > 0 ? p.nedits : 0);
  const char **inputs = jnd_calloc((size_t)nin, sizeof *inputs);
  if (!inputs) return jnd_fail(JND_ERR_NOMEM, "render: out of memory");
  inputs[0] = model;
  inputs[1] = p.views.render.env_path;
  inputs[2] = p.views.cameras_path;
  for (int e = 0; e < p.nedits; e++) inputs[3 + e] = p.edits[e].file;
  report_output o;
  jnd_status st = report_output_open(&o, inputs, nin, out_dir, &p.run);
  free(inputs);
  if (st) return st;
  jnd_scene *scene = NULL;
  jnd_renderer *r = NULL;
  jnd_view *views = NULL;
  double *mip_min = NULL;
  cJSON *report = NULL;
  int nviews = 0;
  jnd_render_result *R = jnd_calloc(1, sizeof *R);
  if (!R) st = jnd_fail(JND_ERR_NOMEM, "render: out of memory");
  if (!st) st = jnd_scene_open(model, p.run.map_size, &scene);
  for (int i = 0; !st && i < jnd_scene_warning_count(scene); i++) {
    if (p.strict) st = jnd_fail(JND_ERR_FORMAT, "%s", jnd_scene_warning(scene, i));
    else if (p.run.warning) p.run.warning(p.run.warning_user, jnd_scene_warning(scene, i));
  }
  if (!st) st = jnd_scene_lod_select(scene, p.lod);
  for (int e = 0; !st && e < p.nedits; e++) st = apply_edit(scene, &p.edits[e]);
  R->load_s = jnd_seconds() - t0;
  /* views (read before the output folder exists, so that bad cameras leave nothing behind) */
  if (!st) {
    jnd_view_set vs = p.views;
    if (p.nlights) vs.sampling.lights = 0;
    st = jnd_view_set_make(scene, &vs, &views, &nviews);
  }
  unsigned gl_outputs = JND_OUT_COLOR | JND_OUT_MASK;
  if (p.outputs & JND_RENDER_DEPTH) gl_outputs |= JND_OUT_DEPTH;
  if (p.outputs & JND_RENDER_MOTION) gl_outputs |= JND_OUT_MOTION;
  if (p.outputs & JND_RENDER_MIP) gl_outputs |= JND_OUT_MIP;
  for (int i = 0; !st && i < nviews; i++) {
    jnd_view *w = &views[i];
    if (p.nlights) {
      w->nlights = p.nlights;
      memcpy(w->lights, p.lights, (size_t)p.nlights * sizeof *p.lights);
    }
    w->env_intensity = p.env_intensity;
    w->env_rotation_deg = p.env_rotation_deg;
    w->exposure = p.exposure;
    w->background_env = p.background_env;
    w->outputs = gl_outputs;
    if (!w->has_prev && (p.outputs & JND_RENDER_MOTION) && p.motion_orbit_deg != 0) {
      orbit(&w->camera, p.motion_orbit_deg, &w->prev_camera);
      w->has_prev = 1;
    }
  }
  double t1 = jnd_seconds();
  if (!st) st = jnd_renderer_create(&p.views.render, &r);
  R->renderer_s = jnd_seconds() - t1;
  /* the folder only now: a bad environment or no OpenGL leaves nothing behind either */
  if (!st) st = jnd_make_dirs(o.dir);
  if (!st) {
    snprintf(R->renderer, sizeof R->renderer, "%s", jnd_renderer_description(r));
    R->views = nviews;
    R->triangles = jnd_scene_triangle_count(scene);
    report = render_report(model, &p, scene, nviews, R->renderer);
    int nmaps = jnd_scene_map_count(scene);
    mip_min = jnd_calloc((size_t)nmaps + 1, sizeof *mip_min);
    if (!report || !mip_min) st = jnd_fail(JND_ERR_NOMEM, "render: out of memory");
    for (int i = 0; i < nmaps && mip_min; i++) mip_min[i] = INFINITY;
  }
  cJSON *jviews = report ? cJSON_GetObjectItemCaseSensitive(report, "views") : NULL;
  for (int i = 0; !st && i < nviews; i++) {
    jnd_frame f;
    double tr = jnd_seconds();
    if ((st = jnd_render(r, scene, &views[i], &f))) {
      st = jnd_fail(st, "%s: %s", model, jnd_last_error());
      break;
    }
    R->render_s += jnd_seconds() - tr;
    cJSON *jv = cJSON_CreateObject();
    cJSON_AddItemToArray(jviews, jv);
    st = write_view(&p, scene, &views[i], &f, i, o.dir, jv, mip_min);
    jnd_frame_free(&f);
    if (p.progress) p.progress(p.progress_user, NULL, i + 1, nviews);
  }
  if (!st) {
    render_report_end(report, (p.outputs & JND_RENDER_MIP) ? mip_min : NULL, R, p.run.timings);
  }
  st = REPORT_OUTPUT_FINISH(&o, st, report, "views.json", R);
  free(mip_min);
  free(views);
  jnd_renderer_free(r);
  jnd_scene_free(scene);
  if (st) {
    jnd_render_result_free(R);
    return st;
  }
  *out = R;
  return JND_OK;
}
