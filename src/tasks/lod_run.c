/* `jnd lod` as one call (jnd_lod_run): the chain and the analysis
 * (jnd_lod_analyse), then the model, the plots and the report written
 * through one output writer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"
#include "tasks/tasks.h"

/* model/NAME.glb: every level, MSFT_lod with MSFT_screencoverage; *rel its
 * path under the folder */
static jnd_status write_model(const char *model, jnd_lod_result *R, const char *dir, const char *out_dir,
                              char *rel, size_t nrel) {
  char mdir[4200], stem[256], path[4600];
  snprintf(mdir, sizeof mdir, "%s/model", dir);
  jnd_status st = jnd_make_dirs(mdir);
  if (st) return st;
  jnd_model_stem(model, stem, sizeof stem);
  snprintf(rel, nrel, "model/%s.glb", stem);
  snprintf(path, sizeof path, "%s/%s", dir, rel);
  st = jnd_scene_write_lod_glb(R->scene, path, R->coverage);
  snprintf(R->model_path, sizeof R->model_path, "%s/%s", out_dir, rel);   /* where it will be */
  return st;
}

/* pareto_SCREEN.png per screen (003's curves, the choices marked) */
static jnd_status write_plots(jnd_lod_result *R, const char *dir) {
  jnd_status st = JND_OK;
  for (int i = 0; R->analysed && !st && i < R->poi.nscreens && i < 16; i++) {
    jnd_image img = {0};
    char name[96], path[4400];
    snprintf(name, sizeof name, "pareto_%s.png", R->poi.screens[i].screen.name);
    for (char *q = name; *q; q++)
      if (*q == '/' || *q == ' ' || *q == '@') *q = '_';
    snprintf(path, sizeof path, "%s/%s", dir, name);
    int perc = i < R->nsw ? R->sw[i].perceptual_level : -1;
    if (!(st = jnd_poi_pareto_plot(&R->poi, i, perc, &img))) st = jnd_image_write_png(path, &img, 8);
    jnd_image_free(&img);
    snprintf(R->plots[R->nplots++], sizeof R->plots[0], "%s", name);
  }
  return st;
}

jnd_status jnd_lod_run(const char *model, const jnd_lod_run_params *pp, const char *out_dir, jnd_lod_result **out) {
  *out = NULL;
  if (!model || !out_dir) return jnd_fail(JND_ERR_ARG, "lod: give a model and an output folder");
  jnd_lod_run_params p;
  if (pp) p = *pp;
  else jnd_lod_run_defaults(&p);
  /* the parameters and the outputs checked before any work */
  jnd_status s = lod_switch_check(&p.sw);
  if (s != JND_OK) return s;
  int nin = 2 + (p.nlevel_paths > 0 ? p.nlevel_paths : 0);
  const char **inputs = jnd_calloc((size_t)nin, sizeof *inputs);
  if (!inputs) return jnd_fail(JND_ERR_NOMEM, "lod: out of memory");
  inputs[0] = model;
  inputs[1] = p.poi.env_path;
  for (int i = 0; i < p.nlevel_paths; i++) inputs[2 + i] = p.level_paths[i];
  report_output o;
  s = report_output_open(&o, inputs, nin, out_dir, &p.run);
  free(inputs);
  if (s != JND_OK) return s;
  jnd_lod_result *R = jnd_calloc(1, sizeof *R);
  cJSON *report = NULL;
  char rel[512] = "";
  if (!R) s = jnd_fail(JND_ERR_NOMEM, "lod: out of memory");
  if (s == JND_OK) s = jnd_lod_analyse(model, &p, R);
  /* memory before and after: level 0 and the first screen's perceptual choice */
  if (s == JND_OK && R->nsw > 0) {
    s = jnd_scene_lod_bytes(R->scene, 0, &R->memory_before_bytes);
    if (s == JND_OK) s = jnd_scene_lod_bytes(R->scene, R->sw[0].perceptual_level, &R->memory_after_bytes);
  }
  /* outputs, last */
  double t0 = jnd_seconds();
  if (s == JND_OK && p.progress) p.progress(p.progress_user, "writing", 0, 1);
  if (s == JND_OK) s = write_model(model, R, o.dir, out_dir, rel, sizeof rel);
  if (s == JND_OK) s = write_plots(R, o.dir);
  if (s == JND_OK && p.progress) p.progress(p.progress_user, "writing", 1, 1);
  if (s == JND_OK) {
    R->write_s += jnd_seconds() - t0;
    report = lod_report(model, &p, R, rel);
  }
  s = REPORT_OUTPUT_FINISH(&o, s, report, "lod.json", R);
  if (s != JND_OK) {
    jnd_lod_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
