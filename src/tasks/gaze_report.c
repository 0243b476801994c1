/* The reports of `jnd gaze` (jnd_gaze_run): the table's, the fit's and the
 * synthetic observers'. */
#include <math.h>

#include "tasks/report.h"

static cJSON *matrix_int(const int *v, int rows, int cols) {
  cJSON *a = cJSON_CreateArray();
  for (int r = 0; r < rows; r++) cJSON_AddItemToArray(a, cJSON_CreateIntArray(v + (size_t)r * cols, cols));
  return a;
}

/* [d][e][k] */
static cJSON *cube(const double *v, int nd, int ne, int nk) {
  cJSON *a = cJSON_CreateArray();
  for (int d = 0; d < nd; d++) {
    cJSON *row = cJSON_CreateArray();
    for (int e = 0; e < ne; e++) cJSON_AddItemToArray(row, cJSON_CreateDoubleArray(v + ((size_t)d * ne + e) * nk, nk));
    cJSON_AddItemToArray(a, row);
  }
  return a;
}

int gaze_reduced_ppd(const jnd_gaze_table_params *p, const jnd_gaze_table *T, int d) {
  return T->ppd[d] < 0.99 * p->measure.model.display.ppd;
}

cJSON *gaze_table_report(const char *model, const jnd_gaze_run_params *rp, const jnd_gaze_table_params *p,
                         const jnd_gaze_run_result *R) {
  const jnd_gaze_table *T = &R->table;
  cJSON *report = report_new("gaze");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  cJSON_AddStringToObject(in, "chain", R->input_levels > 1 ? "input (MSFT_lod or levels of the file)" : "made by jnd gaze");
  /* cJSON makes no array of none */
  cJSON_AddItemToObject(in, "params", rp->nmodel_files ? cJSON_CreateStringArray(rp->model_files, rp->nmodel_files)
                                                       : cJSON_CreateArray());
  cJSON_AddNumberToObject(par, "threshold", p->threshold);
  cJSON_AddNumberToObject(par, "orientations", p->orientations);
  cJSON_AddNumberToObject(par, "seed", (double)p->seed);
  cJSON_AddNumberToObject(par, "min_px", p->min_px);
  cJSON_AddNumberToObject(par, "max_px", p->max_px);
  cJSON_AddBoolToObject(par, "near_window", p->near_window);
  cJSON_AddItemToObject(par, "display", report_display_json(&p->measure.model.display));
  char pool[32];
  cJSON_AddStringToObject(par, "pooling", jnd_pooling_name(&p->measure.pool, pool, sizeof pool));
  cJSON_AddNumberToObject(par, "background", p->measure.background);
  cJSON *gm = cJSON_AddObjectToObject(par, "model");
  cJSON_AddNumberToObject(gm, "alpha", p->model.alpha);
  cJSON_AddNumberToObject(gm, "beta", p->model.beta);
  cJSON_AddNumberToObject(gm, "s_deg", p->model.s_deg);
  cJSON_AddNumberToObject(gm, "b", p->model.b);
  cJSON_AddNumberToObject(gm, "w_g", p->model.w_g);
  cJSON_AddNumberToObject(gm, "w_vdp", p->model.w_vdp);
  cJSON_AddNumberToObject(gm, "k_s", p->model.k_s);
  cJSON_AddNumberToObject(gm, "gamma", p->model.gamma);
  cJSON_AddNumberToObject(gm, "w_t", p->model.w_t);
  cJSON_AddNumberToObject(gm, "gamma_t", p->model.gamma_t);
  cJSON_AddItemToObject(res, "distances_m", cJSON_CreateDoubleArray(T->distances_m, T->nd));
  cJSON_AddItemToObject(res, "eccentricities_deg", cJSON_CreateDoubleArray(T->eccentricities_deg, T->ne));
  cJSON_AddItemToObject(res, "level", matrix_int(T->level, T->nd, T->ne));
  cJSON_AddItemToObject(res, "level_raw", matrix_int(T->level_raw, T->nd, T->ne));
  cJSON_AddItemToObject(res, "p_spatial", cube(T->p_spatial, T->nd, T->ne, T->nlevels));
  cJSON_AddItemToObject(res, "p_switch", cube(T->p_switch, T->nd, T->ne, T->nlevels));
  cJSON_AddItemToObject(res, "ppd", cJSON_CreateDoubleArray(T->ppd, T->nd));
  /* a near object's window is capped at max_px: judged at fewer pixels per
   * degree than the display has (docs/gaze.md "The table", step 1) */
  const double display_ppd = p->measure.model.display.ppd;
  cJSON_AddNumberToObject(res, "display_ppd", display_ppd);
  cJSON_AddItemToObject(res, "windowed", cJSON_CreateIntArray(T->windowed, T->nd));
  cJSON *reduced = cJSON_AddArrayToObject(res, "reduced_ppd");
  for (int d = 0; d < T->nd; d++) cJSON_AddItemToArray(reduced, cJSON_CreateBool(gaze_reduced_ppd(p, T, d)));
  cJSON_AddItemToObject(res, "side_px", cJSON_CreateIntArray(T->side_px, T->nd));
  cJSON *tri = cJSON_AddArrayToObject(res, "triangles");
  for (int k = 0; k < T->nlevels; k++) cJSON_AddItemToArray(tri, cJSON_CreateNumber((double)T->triangles[k]));
  cJSON_AddNumberToObject(res, "renderings", T->renderings);
  cJSON_AddStringToObject(res, "renderer", T->renderer);
  cJSON_AddStringToObject(res, "csv", "gaze.csv");
  cJSON_AddStringToObject(res, "png", "gaze.png");
  cJSON_AddStringToObject(res, "chain_model", R->chain_model);
  if (rp->run.timings) cJSON_AddNumberToObject(res, "table_s", R->table_s);
  return report;
}

cJSON *gaze_fit_report(const char *data, const jnd_gaze_fit_params *fp, const jnd_gaze_fit_result *r) {
  cJSON *report = report_new("gaze fit");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(in, "data", data);
  cJSON_AddNumberToObject(par, "folds", fp->folds);
  cJSON_AddNumberToObject(par, "seed", (double)fp->seed);
  cJSON_AddNumberToObject(par, "confidence", fp->confidence);
  if (!r->temporal) cJSON_AddNumberToObject(par, "b", fp->start.b);
  cJSON_AddStringToObject(res, "model", r->temporal ? "temporal" : "spatial");
  cJSON_AddNumberToObject(res, "trials", r->trials);
  cJSON_AddNumberToObject(res, "stimuli", r->stimuli);
  cJSON_AddNumberToObject(res, "neg_log_likelihood", r->neg_loglik);
  cJSON *jp = cJSON_AddObjectToObject(res, "parameters");
  for (int i = 0; i < r->nparams; i++) {
    cJSON *o = cJSON_AddObjectToObject(jp, r->names[i]);
    cJSON_AddNumberToObject(o, "value", r->value[i]);
    if (isfinite(r->ci_lo[i])) {
      cJSON_AddNumberToObject(o, "ci_lo", r->ci_lo[i]);
      cJSON_AddNumberToObject(o, "ci_hi", r->ci_hi[i]);
    } else {
      cJSON_AddNullToObject(o, "ci_lo");
      cJSON_AddNullToObject(o, "ci_hi");
    }
  }
  cJSON *all = cJSON_AddObjectToObject(res, "all_data");
  cJSON_AddNumberToObject(all, "pearson_r", r->r_all);
  cJSON_AddNumberToObject(all, "mae", r->mae_all);
  cJSON *cv = cJSON_AddObjectToObject(res, "cross_validation");
  cJSON_AddItemToObject(cv, "pearson_r", cJSON_CreateDoubleArray(r->fold_r, r->folds));
  cJSON_AddItemToObject(cv, "mae", cJSON_CreateDoubleArray(r->fold_mae, r->folds));
  cJSON_AddNumberToObject(cv, "pearson_r_mean", r->r_mean);
  cJSON_AddNumberToObject(cv, "pearson_r_sd", r->r_sd);
  cJSON_AddNumberToObject(cv, "mae_mean", r->mae_mean);
  cJSON_AddNumberToObject(cv, "mae_sd", r->mae_sd);
  return report;
}

cJSON *gaze_observers_report(const jnd_gaze_run_params *rp, const jnd_gaze_run_result *R) {
  const jnd_gaze_observers_params *p = &rp->observers;
  const jnd_gaze_observers *O = &R->observers;
  cJSON *report = report_new("gaze observers");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddItemToObject(in, "models", cJSON_CreateStringArray(rp->models, rp->nmodels));
  cJSON_AddNumberToObject(par, "orientations", p->orientations);
  cJSON_AddNumberToObject(par, "answers", p->answers);
  cJSON_AddNumberToObject(par, "seed", (double)p->seed);
  cJSON_AddNumberToObject(par, "switch_hz", p->measure.switch_hz);
  cJSON_AddNumberToObject(res, "stimuli", O->n);
  cJSON_AddNumberToObject(res, "trials_per_model", (double)O->n * O->answers);
  cJSON_AddNumberToObject(res, "mean_p_spatial", R->mean_p_spatial);
  cJSON_AddNumberToObject(res, "mean_p_switch", R->mean_p_switch);
  cJSON_AddStringToObject(res, "spatial_csv", "spatial.csv");
  cJSON_AddStringToObject(res, "temporal_csv", "temporal.csv");
  return report;
}
