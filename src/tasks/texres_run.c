/* jnd_texres_run: `jnd texres` as one library call — the model read, the
 * search of texres.c, and every output (the model copy or the maps, the
 * pictures, texres.json) written through one output writer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/core.h"
#include "tasks/report.h"
#include "tasks/tasks.h"

static int is_gltf(const char *model) {
  const char *ext = strrchr(model, '.');
  return ext && (strcasecmp(ext, ".gltf") == 0 || strcasecmp(ext, ".glb") == 0);
}

/* OBJ and the built-in asset: each resized image once as a PNG file in
 * dir/maps (no model copy), named after the first map that samples it (the
 * report's maps[].image says which maps share it); the names written,
 * relative to dir, go to files */
static jnd_status write_maps(const jnd_scene *scene, const jnd_texres_result *R, const char *dir, cJSON *files) {
  char mdir[4200], path[4400];
  snprintf(mdir, sizeof mdir, "%s/maps", dir);
  for (int t = 0; t < R->nimages; t++) {
    const jnd_texres_image *im = &R->images[t];
    const jnd_texres_map *m = &R->maps[im->first_map];
    if (im->chosen[0] == im->orig[0] && im->chosen[1] == im->orig[1]) continue;
    char name[200];
    snprintf(name, sizeof name, "%s_%dx%d.png", m->name, im->chosen[0], im->chosen[1]);
    for (char *q = name; *q; q++)
      if (*q == '/' || *q == ' ' || *q == '#') *q = '_';
    snprintf(path, sizeof path, "%s/%s", mdir, name);
    jnd_image pixels = {0};
    jnd_status s = jnd_make_dirs(mdir);
    if (s == JND_OK) s = jnd_scene_map_get(scene, m->map, 0, &pixels);
    if (s == JND_OK) s = jnd_image_write_png(path, &pixels, 8);
    jnd_image_free(&pixels);
    if (s != JND_OK) return s;
    char rel[260];
    snprintf(rel, sizeof rel, "maps/%s", name);
    cJSON_AddItemToArray(files, cJSON_CreateString(rel));
  }
  return JND_OK;
}

/* 000 Fig. 13 as matrix_N.png */
static jnd_status write_matrices(const jnd_texres_result *R, const char *dir) {
  for (int t = 0; t < R->nmatrix; t++) {
    char path[4400];
    snprintf(path, sizeof path, "%s/matrix_%d.png", dir, t);
    jnd_image img = {0};
    jnd_status s = jnd_texres_matrix_figure(R, t, &img);
    if (s == JND_OK) s = jnd_image_write_png(path, &img, 8);
    jnd_image_free(&img);
    if (s != JND_OK) return s;
  }
  return JND_OK;
}

jnd_status jnd_texres_run(const char *model, const jnd_texres_params *pp, const char *out_dir,
                          jnd_texres_result **out) {
  *out = NULL;
  if (!model || !out_dir) return jnd_fail(JND_ERR_ARG, "texres: give a model and an output folder");
  jnd_texres_params p;
  if (pp) p = *pp;
  else jnd_texres_defaults(&p);
  double t0 = jnd_seconds();
  /* the outputs checked against every input before any work */
  const char *inputs[] = {model, p.judge.views.render.env_path, p.judge.views.cameras_path,
                          p.judge.calibration.path};
  report_output o;
  jnd_status s = report_output_open(&o, inputs, 4, out_dir, &p.run);
  if (s != JND_OK) return s;
  jnd_scene *scene = NULL;
  jnd_texres_result *R = jnd_calloc(1, sizeof *R);
  cJSON *report = NULL, *map_files = cJSON_CreateArray();
  char model_out[4400] = "", *final_model = NULL;
  if (!R || !map_files) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_scene_open(model, p.run.map_size, &scene);
  for (int i = 0; s == JND_OK && p.run.warning && i < jnd_scene_warning_count(scene); i++)
    p.run.warning(p.run.warning_user, jnd_scene_warning(scene, i));
  if (s == JND_OK && jnd_scene_map_count(scene) == 0)
    s = jnd_fail(JND_ERR_ARG, "%s: the asset has no texture maps (nothing to choose)", model);
  if (s == JND_OK) s = jnd_make_dirs(o.dir);
  if (s == JND_OK) s = jnd_texres_search(scene, &p, R);
  double t_search = jnd_seconds() - t0;
  if (s == JND_OK && is_gltf(model)) {
    char mdir[4200];
    snprintf(mdir, sizeof mdir, "%s/model", o.dir);
    s = jnd_make_dirs(mdir);
    if (s == JND_OK) s = jnd_texres_write_model(scene, model, mdir, model_out, sizeof model_out);
    if (s == JND_OK) {   /* where it will be: the final folder, not the staging */
      size_t n = strlen(out_dir) + strlen(model_out) + 1;
      final_model = jnd_alloc(n, 1);
      if (!final_model) s = JND_ERR_NOMEM;
      else snprintf(final_model, n, "%s%s", out_dir, model_out + strlen(o.dir));
    }
  } else if (s == JND_OK) {
    s = write_maps(scene, R, o.dir, map_files);
  }
  if (s == JND_OK) {
    char path[4400];
    snprintf(path, sizeof path, "%s/worst_view.png", o.dir);
    s = jnd_image_write_png(path, &R->worst_heatmap, 8);
  }
  if (s == JND_OK) s = write_matrices(R, o.dir);
  if (s == JND_OK) {
    double timings[2] = {t_search, jnd_seconds() - t0};
    report = texres_report(model, &p, R, scene, final_model, map_files, p.run.timings ? timings : NULL);
    map_files = NULL;
  }
  if (s == JND_OK) R->passes = R->views.pass && (R->verify_views == 0 || R->verify.pass);
  s = REPORT_OUTPUT_FINISH(&o, s, report, "texres.json", R);
  cJSON_Delete(map_files);
  free(final_model);
  jnd_scene_free(scene);
  if (s != JND_OK) {
    jnd_texres_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
