/* `jnd calibrate`'s report, which is the calibration file every
 * --calibration reads back (jnd_calibration_load: result.calibration). */
#include <stdio.h>

#include "tasks/report.h"
#include "tasks/tasks.h"

cJSON *calibrate_report(const char *csv_path, const jnd_calibrate_run_params *p, const jnd_calibrate_result *R,
                        const jnd_calib_scene *scenes, const char *const *maps, const char *histogram) {
  cJSON *report = report_new("calibrate");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(in, "thresholds", csv_path);
  if (p->pairs) cJSON_AddStringToObject(in, "pairs", p->pairs);
  cJSON_AddNumberToObject(par, "folds", p->fit.folds);
  cJSON_AddNumberToObject(par, "threshold_p", p->fit.threshold_p);
  cJSON_AddNumberToObject(par, "beta", p->fit.beta);
  cJSON_AddNumberToObject(par, "bias_min", p->fit.bias_min);
  cJSON_AddNumberToObject(par, "bias_max", p->fit.bias_max);
  cJSON_AddItemToObject(par, "display", report_display_json(&p->judge.model.display));
  cJSON_AddItemToObject(par, "views", report_views_json(&p->judge.views));
  cJSON *cal = cJSON_AddObjectToObject(res, "calibration");
  cJSON_AddNumberToObject(cal, "percentile", R->cal.percentile);
  cJSON_AddNumberToObject(cal, "scale", R->cal.scale);
  cJSON_AddNumberToObject(cal, "bias", R->cal.bias);
  cJSON_AddNumberToObject(cal, "beta", R->cal.beta);
  cJSON_AddNumberToObject(cal, "threshold_p", R->cal.threshold_p);
  cJSON_AddNumberToObject(cal, "mae_px", R->cal.mae_px);
  cJSON_AddNumberToObject(res, "train_mae_px", R->mae_px);
  cJSON_AddNumberToObject(res, "cv_mae_px", R->cv_mae_px);
  cJSON *fm = cJSON_AddArrayToObject(res, "fold_mae_px");
  for (int k = 0; k < R->folds; k++) cJSON_AddItemToArray(fm, cJSON_CreateNumber(R->fold_mae_px[k]));
  cJSON *pm = cJSON_AddObjectToObject(res, "percentile_train_mae_px");
  for (int k = 0; k < JND_CALIB_NPCT; k++) {
    char key[8];
    snprintf(key, sizeof key, "p%d", JND_CALIB_PCT_LO + k);
    cJSON_AddNumberToObject(pm, key, R->pct_mae_px[k]);
  }
  cJSON *js = cJSON_AddArrayToObject(res, "scenes");
  for (int k = 0; k < R->nscenes; k++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "scene", scenes[k].name);
    if (maps[k][0]) cJSON_AddStringToObject(o, "map", maps[k]);
    cJSON_AddNumberToObject(o, "mu", scenes[k].mu);
    cJSON_AddNumberToObject(o, "sigma", scenes[k].sigma);
    jnd_psychometric m = {scenes[k].mu, scenes[k].sigma > 1e-9 ? scenes[k].sigma : 1e-9, 0, 0};
    cJSON_AddNumberToObject(o, "measured_px", jnd_psychometric_resolution(&m, p->fit.threshold_p));
    cJSON_AddNumberToObject(o, "predicted_px", R->predicted_px[k]);
    cJSON_AddNumberToObject(o, "heldout_error_px", R->errors_px[k]);
    cJSON_AddItemToArray(js, o);
  }
  if (histogram) cJSON_AddStringToObject(res, "histogram", histogram);
  return report;
}
