/* `jnd diff`'s report (docs/model.md "The report"): what jnd_diff_run
 * writes to run.report_path and returns. */
#include <math.h>

#include "tasks/report.h"

cJSON *diff_report(const char *ref, const char *test, const jnd_image_info *ri, const jnd_image_info *ti,
                   const jnd_diff_params *p, const jnd_model_params *mp, const jnd_model *model,
                   const jnd_diff_result *R, const double *timings) {
  const jnd_diff_stats *st = &R->stats;
  cJSON *report = report_new("diff");
  cJSON *inputs = report_section(report, "inputs"), *params = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(inputs, "reference", ref);
  cJSON_AddStringToObject(inputs, "test", test);
  cJSON_AddStringToObject(inputs, "reference_format", ri->format);
  cJSON_AddStringToObject(inputs, "test_format", ti->format);
  if (p->motion_path) cJSON_AddStringToObject(inputs, "motion", p->motion_path);
  if (p->weights_path) cJSON_AddStringToObject(inputs, "weights", p->weights_path);
  if (p->calibration_path) cJSON_AddStringToObject(inputs, "calibration", p->calibration_path);
  cJSON_AddItemToObject(params, "display", report_display_json(&mp->display));
  cJSON_AddStringToObject(params, "pooling", R->pooling);
  cJSON_AddNumberToObject(params, "beta", mp->beta);
  cJSON_AddNumberToObject(params, "minkowski", mp->minkowski);
  cJSON_AddNumberToObject(params, "sensitivity", mp->sensitivity);
  cJSON_AddNumberToObject(params, "sens_rg", mp->sens_rg);
  cJSON_AddNumberToObject(params, "sens_yv", mp->sens_yv);
  if (p->motion_path) cJSON_AddNumberToObject(params, "fps", mp->fps);
  if (mp->has_gaze) {
    cJSON *g = cJSON_AddArrayToObject(params, "gaze");
    cJSON_AddItemToArray(g, cJSON_CreateNumber(mp->gaze_x));
    cJSON_AddItemToArray(g, cJSON_CreateNumber(mp->gaze_y));
  }
  if (p->fail_above >= 0) cJSON_AddNumberToObject(params, "fail_above", p->fail_above);
  cJSON_AddNumberToObject(res, "p_detect", st->p_detect);
  cJSON_AddStringToObject(res, "pooling", R->pooling);
  cJSON_AddNumberToObject(res, "p_p50", st->p_p50);
  cJSON_AddNumberToObject(res, "p_p93", st->p_p93);
  cJSON_AddNumberToObject(res, "p_p99", st->p_p99);
  cJSON_AddNumberToObject(res, "p_max", st->p_max);
  cJSON_AddNumberToObject(res, "p_mean", st->p_mean);
  cJSON_AddNumberToObject(res, "jnd_mean", st->jnd_mean);
  cJSON_AddNumberToObject(res, "jnd_p93", st->jnd_p93);
  cJSON_AddNumberToObject(res, "jnd_max", st->jnd_max);
  cJSON_AddNumberToObject(res, "jnd_minkowski", st->jnd_minkowski);
  cJSON_AddNumberToObject(res, "width", R->width);
  cJSON_AddNumberToObject(res, "height", R->height);
  double bands[16];
  int nb = jnd_model_band_peaks(model, bands, 16);
  cJSON *ba = cJSON_AddArrayToObject(res, "bands_cpd");
  for (int b = 0; b < nb && b < 16; b++) cJSON_AddItemToArray(ba, cJSON_CreateNumber(round(bands[b] * 1e4) / 1e4));
  if (p->fail_above >= 0) cJSON_AddBoolToObject(res, "above_threshold", R->above);
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "load_s", timings[0]);
    cJSON_AddNumberToObject(t, "model_s", timings[1]);
    cJSON_AddNumberToObject(t, "total_s", timings[2]);
    cJSON_AddNumberToObject(t, "megapixels_per_s", (double)R->width * R->height / 1e6 / timings[2]);
  }
  return report;
}
