/* `jnd gaze` as one call (jnd_gaze_run): the table of a model's chain, a
 * fit of observers' answers, or synthetic observers, each written with its
 * report through one output writer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"

void jnd_gaze_run_defaults(jnd_gaze_run_params *p) {
  memset(p, 0, sizeof *p);
  p->mode = JND_GAZE_RUN_TABLE;
  jnd_gaze_table_defaults(&p->table);
  jnd_gaze_fit_defaults(&p->fit);
  jnd_gaze_observers_defaults(&p->observers);
  jnd_run_options_defaults(&p->run);
  p->run.map_size = 512;
}

void jnd_gaze_run_result_free(jnd_gaze_run_result *r) {
  if (!r) return;
  jnd_gaze_table_free(&r->table);
  jnd_gaze_observers_free(&r->observers);
  free(r->report);
  free(r);
}

/* dir/name */
static void join(const char *dir, const char *name, char *out, size_t n) { snprintf(out, n, "%s/%s", dir, name); }

/* 002's table: gaze.png, gaze.csv, the chain made here; *report gaze.json's */
static jnd_status run_table(const char *model, const jnd_gaze_run_params *rp, report_output *o,
                            jnd_gaze_run_result *R, cJSON **report) {
  jnd_gaze_table_params p = rp->table;
  if (p.max_px < p.min_px) return jnd_fail(JND_ERR_ARG, "--max-px: %d is below --min-px %d", p.max_px, p.min_px);
  jnd_status s = JND_OK;
  for (int i = 0; i < rp->nmodel_files && !s; i++) s = jnd_gaze_model_read(rp->model_files[i], &p.model);
  jnd_scene *scene = NULL;
  if (!s) s = jnd_scene_open(model, rp->run.map_size, &scene);
  if (s) return s;
  R->input_levels = jnd_scene_lod_count(scene);
  double t0 = jnd_seconds();
  s = jnd_gaze_table_run(scene, &p, &R->table);
  R->table_s = jnd_seconds() - t0;
  const jnd_gaze_table *T = &R->table;
  for (int d = 0; !s && d < T->nd; d++) {
    R->nreduced += gaze_reduced_ppd(&p, T, d);
    R->nwindowed += T->windowed[d];
  }
  char path[4400];
  jnd_image fig = {0};
  if (!s) s = jnd_make_dirs(o->dir);
  if (!s) s = jnd_gaze_table_figure(T, p.threshold, jnd_asset_length_unit(model), &fig);
  join(o->dir, "gaze.png", path, sizeof path);
  if (!s) s = jnd_image_write_png(path, &fig, 8);
  jnd_image_free(&fig);
  join(o->dir, "gaze.csv", path, sizeof path);
  if (!s) s = jnd_gaze_table_write_csv(T, path);
  /* the chain the table's levels index: the input's, or the one made here, written beside the table */
  char stem[256];
  jnd_model_stem(model, stem, sizeof stem);
  if (R->input_levels < 2) snprintf(R->chain_model, sizeof R->chain_model, "model/%s.glb", stem);
  else snprintf(R->chain_model, sizeof R->chain_model, "%s", model);
  join(o->dir, "model", path, sizeof path);
  if (!s && R->input_levels < 2) s = jnd_make_dirs(path);
  join(o->dir, R->chain_model, path, sizeof path);
  if (!s && R->input_levels < 2) s = jnd_scene_write_lod_glb(scene, path, NULL);
  if (!s) *report = gaze_table_report(model, rp, &p, R);
  jnd_scene_free(scene);
  return s;
}

/* 002's models fitted to answers; *report gaze_fit.json's (written when there is a folder) */
static jnd_status run_fit(const char *data, const jnd_gaze_run_params *rp, report_output *o, jnd_gaze_run_result *R,
                          cJSON **report) {
  jnd_gaze_data d;
  jnd_status s = jnd_gaze_data_read(data, &d);
  if (s) return s;
  s = jnd_gaze_fit(&d, &rp->fit, &R->fit);
  jnd_gaze_data_free(&d);
  if (!s && o->dir) s = jnd_make_dirs(o->dir);
  if (!s) *report = gaze_fit_report(data, &rp->fit, &R->fit);
  return s;
}

/* answers drawn from jnd's own model: spatial.csv, temporal.csv; *report observers.json's */
static jnd_status run_observers(const jnd_gaze_run_params *rp, report_output *o, jnd_gaze_run_result *R,
                                cJSON **report) {
  const jnd_gaze_observers_params *p = &rp->observers;
  if (p->max_px < p->min_px) return jnd_fail(JND_ERR_ARG, "--max-px: %d is below --min-px %d", p->max_px, p->min_px);
  jnd_scene *scenes[64] = {0};
  jnd_status s = JND_OK;
  for (int i = 0; i < rp->nmodels && !s; i++) s = jnd_scene_open(rp->models[i], rp->run.map_size, &scenes[i]);
  if (!s) s = jnd_gaze_observers_run(scenes, rp->nmodels, p, &R->observers);
  const jnd_gaze_observers *O = &R->observers;
  double ps = 0, pw = 0;
  for (int i = 0; !s && i < O->n; i++) ps += O->stimuli[i].p_spatial, pw += O->stimuli[i].p_switch;
  R->mean_p_spatial = O->n ? ps / O->n : 0;
  R->mean_p_switch = O->n ? pw / O->n : 0;
  char path[4400];
  if (!s) s = jnd_make_dirs(o->dir);
  join(o->dir, "spatial.csv", path, sizeof path);
  if (!s) s = jnd_gaze_observers_write_csv(O, 0, path);
  join(o->dir, "temporal.csv", path, sizeof path);
  if (!s) s = jnd_gaze_observers_write_csv(O, 1, path);
  if (!s) *report = gaze_observers_report(rp, R);
  for (int i = 0; i < rp->nmodels; i++) jnd_scene_free(scenes[i]);
  return s;
}

jnd_status jnd_gaze_run(const char *input, const jnd_gaze_run_params *pp, const char *out_dir,
                        jnd_gaze_run_result **out) {
  *out = NULL;
  jnd_gaze_run_params p;
  if (pp) p = *pp;
  else jnd_gaze_run_defaults(&p);
  /* every input, then the folder and the report's copy: checked before any work */
  const char *ins[80] = {0};
  int nin = 0;
  if (p.mode == JND_GAZE_RUN_OBSERVERS) {
    if (p.nmodels < 1 || p.nmodels > 64) return jnd_fail(JND_ERR_ARG, "gaze observers: give 1 to 64 models");
    if (!out_dir) return jnd_fail(JND_ERR_ARG, "gaze observers: give an output folder");
    for (int i = 0; i < p.nmodels; i++) ins[nin++] = p.models[i];
    ins[nin++] = p.observers.render.env_path;
  } else if (p.mode == JND_GAZE_RUN_FIT) {
    if (!input) return jnd_fail(JND_ERR_ARG, "gaze fit: give a CSV of trials");
    ins[nin++] = input;
  } else {
    if (!input || !out_dir) return jnd_fail(JND_ERR_ARG, "gaze: give a model and an output folder");
    if (p.nmodel_files > 8) return jnd_fail(JND_ERR_ARG, "--params: at most 8 files");
    ins[nin++] = input;
    ins[nin++] = p.table.render.env_path;
    for (int i = 0; i < p.nmodel_files; i++) ins[nin++] = p.model_files[i];
  }
  report_output o;
  jnd_status s = report_output_open(&o, ins, nin, out_dir, &p.run);
  if (s) return s;
  jnd_gaze_run_result *R = jnd_calloc(1, sizeof *R);
  if (!R) return report_output_end(&o, jnd_fail(JND_ERR_NOMEM, "gaze: out of memory"));
  R->mode = p.mode;
  cJSON *report = NULL;
  const char *name = p.mode == JND_GAZE_RUN_OBSERVERS ? "observers.json"
                     : p.mode == JND_GAZE_RUN_FIT     ? (o.dir ? "gaze_fit.json" : NULL)
                                                      : "gaze.json";
  s = p.mode == JND_GAZE_RUN_OBSERVERS ? run_observers(&p, &o, R, &report)
      : p.mode == JND_GAZE_RUN_FIT     ? run_fit(input, &p, &o, R, &report)
                                       : run_table(input, &p, &o, R, &report);
  s = REPORT_OUTPUT_FINISH(&o, s, report, name, R);
  if (s) {
    jnd_gaze_run_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
