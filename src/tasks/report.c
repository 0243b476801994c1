/* The reports and outputs of the task runs: see report.h. */
#include "tasks/report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"

void jnd_run_options_defaults(jnd_run_options *o) {
  memset(o, 0, sizeof *o);
  o->map_size = 2048;
}

cJSON *report_new(const char *command) {
  cJSON *r = cJSON_CreateObject();
  cJSON_AddStringToObject(r, "jnd_version", jnd_version());
  cJSON_AddStringToObject(r, "command", command);
  cJSON_AddObjectToObject(r, "inputs");
  cJSON_AddObjectToObject(r, "parameters");
  cJSON_AddObjectToObject(r, "result");
  return r;
}

cJSON *report_section(cJSON *report, const char *name) {
  return cJSON_GetObjectItemCaseSensitive(report, name);
}

cJSON *report_pair(const int *wh) {
  cJSON *a = cJSON_CreateArray();
  cJSON_AddItemToArray(a, cJSON_CreateNumber(wh[0]));
  cJSON_AddItemToArray(a, cJSON_CreateNumber(wh[1]));
  return a;
}

cJSON *report_number_or_null(double v) { return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull(); }

cJSON *report_display_json(const jnd_display *d) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", d->name);
  cJSON_AddNumberToObject(o, "ppd", d->ppd);
  cJSON_AddNumberToObject(o, "peak_cdm2", d->peak_cdm2);
  cJSON_AddNumberToObject(o, "black_cdm2", d->black_cdm2);
  cJSON_AddNumberToObject(o, "ambient_lux", d->ambient_lux);
  cJSON_AddNumberToObject(o, "reflectivity", d->reflectivity);
  cJSON_AddNumberToObject(o, "exr_scale", d->exr_scale);
  cJSON_AddStringToObject(o, "task", jnd_viewing_task_name(d->task));
  if (d->diagonal_in > 0) {
    cJSON_AddNumberToObject(o, "diagonal_in", d->diagonal_in);
    cJSON_AddNumberToObject(o, "width_px", d->width_px);
    cJSON_AddNumberToObject(o, "height_px", d->height_px);
    cJSON_AddNumberToObject(o, "distance_m", d->distance_m);
  }
  return o;
}

cJSON *report_views_json(const jnd_view_set *vs) {
  const jnd_view_sampling *s = &vs->sampling;
  cJSON *o = cJSON_CreateObject();
  if (vs->cameras_path) {
    cJSON_AddStringToObject(o, "cameras", vs->cameras_path);
  } else {
    cJSON_AddNumberToObject(o, "views", s->count);
    cJSON_AddNumberToObject(o, "seed", (double)s->seed);
    if (s->distance > 0) cJSON_AddNumberToObject(o, "distance", s->distance);
    else cJSON_AddNumberToObject(o, "coverage", s->coverage);
    cJSON_AddNumberToObject(o, "fov_y_deg", s->fov_y_deg);
    if (!isnan(s->min_elevation_deg)) cJSON_AddNumberToObject(o, "min_elevation_deg", s->min_elevation_deg);
    cJSON_AddNumberToObject(o, "max_elevation_deg", s->max_elevation_deg);
    cJSON_AddNumberToObject(o, "lights", s->lights);
  }
  cJSON_AddNumberToObject(o, "width", vs->render.width);
  cJSON_AddNumberToObject(o, "height", vs->render.height);
  cJSON_AddNumberToObject(o, "samples", vs->render.samples);
  cJSON_AddNumberToObject(o, "anisotropy", vs->render.anisotropy);
  if (vs->render.env_path) cJSON_AddStringToObject(o, "env", vs->render.env_path);
  return o;
}

cJSON *report_criterion_json(const jnd_criterion *c, const jnd_criterion_result *r) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "p", c->p);
  cJSON_AddNumberToObject(o, "q", c->q);
  if (r) {
    cJSON_AddNumberToObject(o, "views", r->views);
    cJSON_AddNumberToObject(o, "above", r->above);
    cJSON_AddNumberToObject(o, "allowed", r->allowed);
    cJSON_AddNumberToObject(o, "statistic", r->statistic);
    cJSON_AddNumberToObject(o, "fraction_above", r->fraction_above);
    cJSON_AddNumberToObject(o, "fraction_upper", r->fraction_upper);
    cJSON_AddNumberToObject(o, "confidence", c->confidence);
    cJSON_AddBoolToObject(o, "passes", r->pass);
  }
  return o;
}

jnd_status report_output_add_inputs(report_output *o, const char *const *inputs, int ninputs) {
  jnd_status s = JND_OK;
  for (int k = 0; k < ninputs && s == JND_OK; k++) {
    if (!inputs[k]) continue;
    char **files = NULL;
    int count = 0;
    s = jnd_asset_files(inputs[k], &files, &count);
    for (int f = 0; f < count && s == JND_OK; f++) s = jnd_output_add_input(o->w, files[f]);
    jnd_asset_files_free(files, count);
  }
  return s;
}

jnd_status report_output_add_copy(report_output *o, const jnd_run_options *run) {
  if (!run || !run->report_path || strcmp(run->report_path, "-") == 0) return JND_OK;
  return jnd_output_add_file(o->w, run->report_path, &o->copy);
}

jnd_status report_output_open(report_output *o, const char *const *inputs, int ninputs, const char *out_dir,
                              const jnd_run_options *run) {
  memset(o, 0, sizeof *o);
  jnd_status s = jnd_output_open(&o->w);
  if (s == JND_OK) s = report_output_add_inputs(o, inputs, ninputs);
  if (s == JND_OK && out_dir) s = jnd_output_add_dir(o->w, out_dir, &o->dir);
  if (s == JND_OK) s = report_output_add_copy(o, run);
  if (s != JND_OK) {
    jnd_output_free(o->w);
    o->w = NULL;
  }
  return s;
}

char *report_text(const cJSON *report) {
  char *t = cJSON_Print(report);
  size_t n = t ? strlen(t) : 0;
  char *full = t ? jnd_alloc(n + 2, 1) : NULL;
  if (full) {
    memcpy(full, t, n);
    full[n] = '\n';
    full[n + 1] = 0;
  }
  free(t);
  return full;
}

jnd_status report_output_write(report_output *o, cJSON *report, const char *name, char **text) {
  *text = NULL;
  char *full = report_text(report);
  if (!full) return jnd_fail(JND_ERR_NOMEM, "out of memory writing the report");
  size_t n = strlen(full) - 1;
  jnd_status s = JND_OK;
  if (o->dir && name) {
    size_t len = strlen(o->dir) + strlen(name) + 2;
    char *path = jnd_alloc(len, 1);
    if (!path) s = JND_ERR_NOMEM;
    else {
      snprintf(path, len, "%s/%s", o->dir, name);
      s = jnd_write_file_atomic(path, full, n + 1);
      free(path);
    }
  } else if (name) {
    s = jnd_write_file_atomic(name, full, n + 1);
  }
  if (s == JND_OK && o->copy) s = jnd_write_file_atomic(o->copy, full, n + 1);
  if (s != JND_OK) {
    free(full);
    return s;
  }
  *text = full;
  return JND_OK;
}

jnd_status report_output_end(report_output *o, jnd_status st) {
  if (st == JND_OK && o->w) st = jnd_output_commit(o->w);
  jnd_output_free(o->w);
  o->w = NULL;
  return st;
}

jnd_status report_output_finish(report_output *o, jnd_status st, cJSON *report, const char *name, char **text) {
  if (st == JND_OK) st = report && text ? report_output_write(o, report, name, text) : JND_ERR_NOMEM;
  cJSON_Delete(report);
  return report_output_end(o, st);
}
