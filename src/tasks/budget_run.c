/* `jnd budget` as one call (jnd_budget_run): the search of budget.c, then
 * the model, pareto.png and budget.json written through one output
 * writer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"
#include "tasks/report.h"

/* model/NAME.glb: the chosen finest level and the coarser ones, MSFT_lod
 * with MSFT_screencoverage (lod's coverages of those levels), the maps at
 * the chosen sizes; *rel its path under the folder */
static jnd_status write_model(const char *model, jnd_budget_result *R, const char *dir, const char *out_dir,
                              const double *coverage, char *rel, size_t nrel) {
  char mdir[4200], stem[256], path[4600];
  snprintf(mdir, sizeof mdir, "%s/model", dir);
  jnd_status st = jnd_make_dirs(mdir);
  if (st) return st;
  jnd_model_stem(model, stem, sizeof stem);
  snprintf(rel, nrel, "model/%s.glb", stem);
  snprintf(path, sizeof path, "%s/%s", dir, rel);
  st = jnd_scene_write_lod_glb_from(R->lod.scene, path, coverage, R->levels[0].level);
  snprintf(R->model_path, sizeof R->model_path, "%s/%s", out_dir, rel);   /* where it will be */
  return st;
}

jnd_status jnd_budget_run(const char *model, const jnd_budget_params *pp, const char *out_dir,
                          jnd_budget_result **out) {
  *out = NULL;
  if (!model || !out_dir) return jnd_fail(JND_ERR_ARG, "budget: give a model and an output folder");
  jnd_budget_params p;
  if (pp) p = *pp;
  else jnd_budget_defaults(&p);
  double t0 = jnd_seconds();
  /* the outputs checked against every input before any work */
  int nin = 5 + (p.lod.nlevel_paths > 0 ? p.lod.nlevel_paths : 0);
  const char **inputs = jnd_calloc((size_t)nin, sizeof *inputs);
  if (!inputs) return jnd_fail(JND_ERR_NOMEM, "budget: out of memory");
  const char *fixed[5] = {model, p.texres.judge.views.render.env_path, p.texres.judge.views.cameras_path,
                          p.texres.judge.calibration.path, p.lod.poi.env_path};
  memcpy(inputs, fixed, sizeof fixed);
  for (int i = 0; i < p.lod.nlevel_paths; i++) inputs[5 + i] = p.lod.level_paths[i];
  report_output o;
  jnd_status s = report_output_open(&o, inputs, nin, out_dir, &p.run);
  free(inputs);
  if (s != JND_OK) return s;
  jnd_budget_result *R = jnd_calloc(1, sizeof *R);
  cJSON *report = NULL;
  char rel[512] = "";
  double coverage[64];
  if (s == JND_OK && !R) s = jnd_fail(JND_ERR_NOMEM, "budget: out of memory");
  if (s == JND_OK) s = jnd_budget_search(model, &p, R);
  if (s == JND_OK) {
    for (int j = 0; j < R->nlevels && j < 64; j++) coverage[j] = R->lod.coverage[R->levels[j].level];
    if (R->nlevels > 64) s = jnd_fail(JND_ERR_LIMIT, "%s: more than 64 levels to write", model);
  }
  if (s == JND_OK) s = jnd_make_dirs(o.dir);
  if (s == JND_OK) s = write_model(model, R, o.dir, out_dir, coverage, rel, sizeof rel);
  if (s == JND_OK) {
    jnd_image img = {0};
    char path[4400];
    snprintf(path, sizeof path, "%s/pareto.png", o.dir);
    s = jnd_budget_pareto_plot(R, &p.texres.judge.criterion, &img);
    if (s == JND_OK) s = jnd_image_write_png(path, &img, 8);
    jnd_image_free(&img);
  }
  if (s == JND_OK) {
    double total = jnd_seconds() - t0;
    report = budget_report(model, &p, R, rel, coverage, p.run.timings ? &total : NULL);
  }
  s = REPORT_OUTPUT_FINISH(&o, s, report, "budget.json", R);
  if (s != JND_OK) {
    jnd_budget_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
