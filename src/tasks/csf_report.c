/* The report of `jnd csf` (jnd_csf_run): the constants as used, the error
 * per data set and pooled, and which rows used a derived colour direction. */
#include <math.h>
#include <string.h>

#include "tasks/report.h"

static cJSON *score_json(const jnd_csf_score *s) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "rows", s->rows);
  cJSON_AddNumberToObject(o, "static_rows", s->static_rows);
  if (s->static_rows) cJSON_AddNumberToObject(o, "rmse_db_static", s->rmse_db_static);
  cJSON_AddNumberToObject(o, "rmse_db", s->rmse_db);
  cJSON_AddNumberToObject(o, "bias_db", s->bias_db);
  if (!isnan(s->cv_rmse_db)) {
    if (s->static_rows) cJSON_AddNumberToObject(o, "cv_rmse_db_static", s->cv_rmse_db_static);
    cJSON_AddNumberToObject(o, "cv_rmse_db", s->cv_rmse_db);
    cJSON_AddNumberToObject(o, "cv_bias_db", s->cv_bias_db);
  }
  return o;
}

/* row q used the same derived direction as row r (same data set, direction, background) */
static int same_derived(const jnd_csf_row *a, const jnd_csf_row *b) {
  return b->derived_direction && b->col_dir_id == a->col_dir_id && b->bkg_id == a->bkg_id && b->dataset == a->dataset;
}

/* which rows used a colour direction derived from its publication, not listed */
static void derived_json(cJSON *result, const jnd_csf_data *d) {
  cJSON *derived = cJSON_AddArrayToObject(result, "derived_directions");
  int nderived = 0;
  for (int r = 0; r < d->nrows; r++) {
    const jnd_csf_row *in = &d->rows[r];
    if (!in->derived_direction) continue;
    nderived++;
    int seen = 0;
    for (int q = 0; q < r && !seen; q++) seen = same_derived(in, &d->rows[q]);
    if (seen) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "dataset", d->datasets[in->dataset]);
    cJSON_AddNumberToObject(o, "col_dir_id", in->col_dir_id);
    cJSON_AddNumberToObject(o, "bkg_id", in->bkg_id);
    cJSON_AddItemToObject(o, "lms", cJSON_CreateDoubleArray(in->st.dir_lms, 3));
    cJSON *lines = cJSON_AddArrayToObject(o, "lines");
    for (int q = r; q < d->nrows; q++)
      if (same_derived(in, &d->rows[q])) cJSON_AddItemToArray(lines, cJSON_CreateNumber(d->rows[q].line));
    cJSON_AddItemToArray(derived, o);
  }
  cJSON_AddNumberToObject(result, "derived_direction_rows", nderived);
}

cJSON *csf_report(const char *data, const char *colors, const char *backgrounds, const jnd_csf_run_params *p,
                  const jnd_csf_data *d, const jnd_csf_result *res) {
  const int cv = p->options.cross_validate;
  cJSON *report = report_new("csf");
  cJSON *inputs = report_section(report, "inputs"), *params = report_section(report, "parameters"),
        *result = report_section(report, "result");
  cJSON_AddStringToObject(inputs, "data", data);
  cJSON_AddStringToObject(inputs, "colors", colors);
  cJSON_AddStringToObject(inputs, "backgrounds", backgrounds);
  const jnd_model_constant *cl[JND_MAX_CONSTANTS];
  const int nc = jnd_model_constants(cl, JND_MAX_CONSTANTS);
  cJSON *consts = cJSON_AddObjectToObject(params, "constants");
  for (int k = 0; k < nc; k++) {
    cJSON *o = cJSON_AddObjectToObject(consts, cl[k]->name);
    cJSON_AddNumberToObject(o, "value", jnd_model_constant_get(&res->params, k));
    cJSON_AddNumberToObject(o, "prior", cl[k]->prior);
    cJSON_AddBoolToObject(o, "fitted", res->fitted[k]);
    if (!isnan(res->sd_ln[k])) cJSON_AddNumberToObject(o, "sd_ln", res->sd_ln[k]);
    if (!isnan(res->fold_sd_ln[k])) cJSON_AddNumberToObject(o, "fold_sd_ln", res->fold_sd_ln[k]);
    if (res->fold_value) {
      cJSON *fv = cJSON_AddObjectToObject(o, "without");
      for (int ds = 0; ds < d->ndatasets; ds++)
        if (!isnan(res->fold_value[(size_t)ds * nc + k]))
          cJSON_AddNumberToObject(fv, d->datasets[ds], res->fold_value[(size_t)ds * nc + k]);
    }
  }
  cJSON_AddNumberToObject(params, "min_band_cpd", res->params.min_band_cpd);
  cJSON_AddNumberToObject(params, "beta", res->params.beta);
  cJSON_AddNumberToObject(params, "minkowski", res->params.minkowski);
  cJSON_AddStringToObject(params, "pooling", "max");
  cJSON_AddBoolToObject(params, "fitted", p->options.fit);
  cJSON_AddBoolToObject(params, "cross_validated", cv);
  cJSON_AddNumberToObject(params, "search_every", p->options.search_every);
  cJSON_AddNumberToObject(params, "prior_weight_db", p->options.prior_weight_db);

  cJSON *per = cJSON_AddObjectToObject(result, "datasets");
  for (int ds = 0; ds < d->ndatasets; ds++)
    if (res->dataset[ds].rows) cJSON_AddItemToObject(per, d->datasets[ds], score_json(&res->dataset[ds]));
  int nskip = 0;
  for (int r = 0; r < d->nrows; r++) nskip += !d->rows[r].use;
  cJSON_AddNumberToObject(result, "rows", res->pooled.rows);
  cJSON_AddNumberToObject(result, "static_rows", res->pooled.static_rows);
  cJSON_AddNumberToObject(result, "skipped", nskip);
  if (res->pooled.static_rows) cJSON_AddNumberToObject(result, "rmse_db_static", res->pooled.rmse_db_static);
  cJSON_AddNumberToObject(result, "rmse_db", res->pooled.rmse_db);
  if (cv) {
    if (res->pooled.static_rows) cJSON_AddNumberToObject(result, "cv_rmse_db_static", res->pooled.cv_rmse_db_static);
    cJSON_AddNumberToObject(result, "cv_rmse_db", res->pooled.cv_rmse_db);
    /* the data sets the cross-validated figures pool: every one, or those
     * --fold named (jnd_csf_options.folds) */
    cJSON *over = cJSON_AddArrayToObject(result, "cv_pooled_over");
    for (int ds = 0; ds < d->ndatasets; ds++)
      if (!isnan(res->dataset[ds].cv_rmse_db))
        cJSON_AddItemToArray(over, cJSON_CreateString(d->datasets[ds]));
    cJSON_AddBoolToObject(result, "cv_every_fold", p->options.nfolds == 0);
  }
  cJSON_AddNumberToObject(result, "model_passes", res->model_passes);
  derived_json(result, d);
  return report;
}
