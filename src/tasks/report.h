/* The reports and outputs of the task runs (jnd_<task>_run): the JSON
 * envelope every report shares, the JSON of the shared parameter groups,
 * and the one way a run registers its inputs and outputs with the output
 * writer and publishes its report. Internal to the library; the command
 * line prints what the runs return. */
#ifndef JND_TASKS_REPORT_H
#define JND_TASKS_REPORT_H

#include <cjson/cJSON.h>

#include "jnd.h"

/* {"jnd_version", "command", "inputs", "parameters", "result"} */
cJSON *report_new(const char *command);
cJSON *report_section(cJSON *report, const char *name);

cJSON *report_display_json(const jnd_display *d);
/* The view set as the options gave it: the cameras file or the sampling, and the rendering. */
cJSON *report_views_json(const jnd_view_set *vs);
/* The criterion (p, q), with the outcome when r is not NULL. */
cJSON *report_criterion_json(const jnd_criterion *c, const jnd_criterion_result *r);
/* The report's text as every run writes it: cJSON_Print and a newline
 * (allocated; NULL when out of memory). */
char *report_text(const cJSON *report);
/* [w, h] */
cJSON *report_pair(const int *wh);
/* v, or null where it is not finite (never, unknown) */
cJSON *report_number_or_null(double v);

/* A run's output writer: every input (what each references too: glTF
 * buffers and images, an OBJ's .mtl and textures; NULL entries skipped)
 * registered, then out_dir as the run's folder (*staged_dir: where to write)
 * and o->report_path (when a file) as a second copy of the report. Refused
 * with one error before anything is written. *w is the caller's
 * (jnd_output_free). */
typedef struct {
  jnd_output *w;
  const char *dir;           /* staged out_dir (NULL when no out_dir) */
  const char *copy;          /* staged report copy (NULL: none or "-") */
} report_output;
jnd_status report_output_open(report_output *o, const char *const *inputs, int ninputs, const char *out_dir,
                              const jnd_run_options *run);

/* Registers run->report_path (when a file) as the report's copy, o->copy:
 * report_output_open does it after out_dir; a run whose outputs are files
 * (calibrate) opens with neither and calls it after registering them. */
jnd_status report_output_add_copy(report_output *o, const jnd_run_options *run);

/* More inputs, as report_output_open registers them (a run that learns its
 * inputs from a table registers them as it reads it). */
jnd_status report_output_add_inputs(report_output *o, const char *const *inputs, int ninputs);

/* Writes the report as dir/name (without a dir: name is the staged path of
 * the report file) and to the copy, and returns its text (*text allocated,
 * ending in a newline) — before the commit. */
jnd_status report_output_write(report_output *o, cJSON *report, const char *name, char **text);

/* Publishes everything when st is JND_OK, else removes it; frees the
 * writer. Returns st, or the commit's error. */
jnd_status report_output_end(report_output *o, jnd_status st);

/* The end of every run: when st is JND_OK, writes report (taken; NULL:
 * out of memory building it) as report_output_write does, its text into
 * *text (text NULL: there is nowhere to put it, JND_ERR_NOMEM), then ends
 * as report_output_end does: everything published, or all removed on any
 * error. Returns st, the write's or the commit's error. */
jnd_status report_output_finish(report_output *o, jnd_status st, cJSON *report, const char *name, char **text);

/* How every run ends, R its result (any jnd_<task>_result, whose report's
 * text goes into R->report) or NULL where the run failed before making it
 * (st is then an error: nothing is published). The one place that guards
 * R:
 *   if (s == JND_OK) report = <task>_report(...);
 *   s = REPORT_OUTPUT_FINISH(&o, s, report, "<task>.json", R);   */
#define REPORT_OUTPUT_FINISH(o, st, report, name, R) \
  report_output_finish((o), (st), (report), (name), (R) ? &(R)->report : NULL)

/* ---- each task's report, built by its <task>_report.c ---- */

/* jnd diff's report: mp the model's parameters as run (the calibration's
 * beta), timings NULL or {load_s, model_s, total_s}. */
cJSON *diff_report(const char *ref, const char *test, const jnd_image_info *ri, const jnd_image_info *ti,
                   const jnd_diff_params *p, const jnd_model_params *mp, const jnd_model *model,
                   const jnd_diff_result *R, const double *timings);

/* views.json before the frames: the parameters, the asset, its maps and an
 * empty "views"; render_report_view_end adds a view's camera and lights
 * after its files, render_report_end the maps' mip_min (NULL: none) and
 * the timings. */
cJSON *render_report(const char *model, const jnd_render_params *p, const jnd_scene *scene, int nviews,
                     const char *renderer);
void render_report_view_end(cJSON *jv, const jnd_view *view);
void render_report_end(cJSON *report, const double *mip_min, const jnd_render_result *R, int timings);

/* lod.json: model_rel the written model's path under the folder. */
cJSON *lod_report(const char *model, const jnd_lod_run_params *p, const jnd_lod_result *R, const char *model_rel);

/* texres.json: model_out the published model's path (NULL: none), map_files
 * (taken) the maps written as PNG, timings NULL or {search_s, total_s}. */
cJSON *texres_report(const char *model, const jnd_texres_params *p, const jnd_texres_result *R,
                     const jnd_scene *scene, const char *model_out, cJSON *map_files, const double *timings);

/* pca.json: textures (taken) the packed component files, total_s NULL or
 * the run's wall time (then the stages' too). */
cJSON *pca_report(const jnd_pca_params *p, const jnd_pca_result *R, cJSON *textures, const double *total_s);

/* budget.json: model_rel the written model's path under the folder,
 * coverage its MSFT_screencoverage per written level, timings NULL or
 * {total_s}. */
cJSON *budget_report(const char *model, const jnd_budget_params *p, const jnd_budget_result *R, const char *model_rel,
                     const double *coverage, const double *timings);

/* The calibration file's report (also what --calibration reads back). */
cJSON *calibrate_report(const char *csv_path, const jnd_calibrate_run_params *p, const jnd_calibrate_result *R,
                        const jnd_calib_scene *scenes, const char *const *maps, const char *histogram);

/* csf's report: colors, backgrounds the files read (the defaults resolved). */
cJSON *csf_report(const char *data, const char *colors, const char *backgrounds, const jnd_csf_run_params *p,
                  const jnd_csf_data *d, const jnd_csf_result *res);

/* gaze's reports: the table (p the table's parameters as run, the models
 * read), the fit, the synthetic observers. */
cJSON *gaze_table_report(const char *model, const jnd_gaze_run_params *rp, const jnd_gaze_table_params *p,
                         const jnd_gaze_run_result *R);
cJSON *gaze_fit_report(const char *data, const jnd_gaze_fit_params *fp, const jnd_gaze_fit_result *r);
cJSON *gaze_observers_report(const jnd_gaze_run_params *rp, const jnd_gaze_run_result *R);
/* 1: distance d of the table was judged below the display's ppd (its window capped at max_px) */
int gaze_reduced_ppd(const jnd_gaze_table_params *p, const jnd_gaze_table *T, int d);

/* pop.json: model NULL for the frame form, ap the asset form's parameters
 * as run, timings NULL or {write_s, total_s}. */
cJSON *pop_report(const char *model, const jnd_pop_run_params *p, const jnd_pop_asset_params *ap,
                  const jnd_pop_run_result *R, const double *timings);

#endif
