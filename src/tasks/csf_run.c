/* `jnd csf` as one call (jnd_csf_run): the data read, the rows selected,
 * jnd_csf_evaluate, then the rows with their predictions and the report
 * written through one output writer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"

void jnd_csf_run_defaults(jnd_csf_run_params *p) {
  memset(p, 0, sizeof *p);
  jnd_model_defaults(&p->model);
  jnd_csf_options_defaults(&p->options);
  p->every = 1;
  jnd_run_options_defaults(&p->run);
}

void jnd_csf_run_result_free(jnd_csf_run_result *r) {
  if (!r) return;
  jnd_csf_result_free(&r->eval);
  jnd_csf_data_free(&r->data);
  free(r->report);
  free(r);
}

/* the CSV with two or four columns added */
static jnd_status write_rows(const char *path, const jnd_csf_data *d, const jnd_csf_result *r, int cv) {
  size_t cap = 1 << 16, len = 0;
  char *buf = malloc(cap);
  if (!buf) return jnd_fail(JND_ERR_NOMEM, "csf: out of memory");
  int ok = 1;
#define PUT(...)                                                                           \
  do {                                                                                     \
    int need_ = snprintf(NULL, 0, __VA_ARGS__);                                            \
    while (ok && len + need_ + 1 > cap) {                                                  \
      char *nb_ = realloc(buf, cap * 2);                                                   \
      if (!nb_) ok = 0; else { buf = nb_; cap *= 2; }                                      \
    }                                                                                      \
    if (ok) len += snprintf(buf + len, cap - len, __VA_ARGS__);                            \
  } while (0)
  const jnd_csv *t = &d->table;
  for (int k = 0; k < t->ncols; k++) PUT("%s,", t->header[k]);
  PUT("predicted_sensitivity,error_db,%snote\n", cv ? "predicted_cv,error_cv_db," : "");
  for (int i = 0; i < t->nrows; i++) {
    for (int k = 0; k < t->ncols; k++) {
      const char *cell = t->cells[i][k];
      if (strpbrk(cell, ",\"\n")) {
        PUT("\"");
        for (const char *p = cell; *p; p++) PUT(*p == '"' ? "\"\"" : "%c", *p);
        PUT("\",");
      } else {
        PUT("%s,", cell);
      }
    }
    const jnd_csf_row *row = &d->rows[i];
    if (row->use && !isnan(r->predicted[i])) {
      PUT("%.6g,%.4f,", r->predicted[i], 20 * log10(r->predicted[i] / row->measured));
      if (cv) {
        if (!isnan(r->predicted_cv[i]))
          PUT("%.6g,%.4f,", r->predicted_cv[i], 20 * log10(r->predicted_cv[i] / row->measured));
        else
          PUT("NaN,NaN,");
      }
      PUT("%s\n", row->derived_direction ? "colour direction derived (docs/csf.md)" : "");
    } else {
      PUT("NaN,NaN,%sskipped: %s\n", cv ? "NaN,NaN," : "", row->skip ? row->skip : "failed");
    }
  }
#undef PUT
  if (!ok) {
    free(buf);
    return jnd_fail(JND_ERR_NOMEM, "csf: out of memory");
  }
  jnd_status s = jnd_write_file_atomic(path, buf, len);
  free(buf);
  return s;
}

/* --dataset, --static-only, --every: a row left out says why */
static void select_rows(jnd_csf_data *d, const jnd_csf_run_params *p) {
  for (int r = 0; r < d->nrows; r++) {
    jnd_csf_row *row = &d->rows[r];
    if (row->use && p->static_only && row->st.t_frequency > 0) {
      row->use = 0;
      row->skip = "t_frequency > 0 (--static-only)";
    }
    if (row->use && p->ndatasets) {
      int keep = 0;
      for (int k = 0; k < p->ndatasets; k++) keep |= strcmp(p->datasets[k], d->datasets[row->dataset]) == 0;
      if (!keep) {
        row->use = 0;
        row->skip = "other data set";
      }
    }
    if (row->use && p->every > 1 && r % p->every) {
      row->use = 0;
      row->skip = "--every";
    }
  }
}

/* NAME beside data (its folder, or the current one) */
static void beside(const char *data, const char *name, char *out, size_t n) {
  const char *slash = strrchr(data, '/');
  int dir = slash ? (int)(slash - data) + 1 : 0;
  snprintf(out, n, "%.*s%s", dir, data, name);
}

jnd_status jnd_csf_run(const char *data, const jnd_csf_run_params *pp, const char *out_csv,
                       jnd_csf_run_result **out) {
  *out = NULL;
  if (!data) return jnd_fail(JND_ERR_ARG, "csf: needs a CSV of thresholds");
  jnd_csf_run_params p;
  if (pp) p = *pp;
  else jnd_csf_run_defaults(&p);
  char colors_def[4096], bkgs_def[4096];
  beside(data, "color_directions.csv", colors_def, sizeof colors_def);
  beside(data, "backgrounds.csv", bkgs_def, sizeof bkgs_def);
  const char *colors = p.colors ? p.colors : colors_def, *bkgs = p.backgrounds ? p.backgrounds : bkgs_def;
  /* the outputs checked before any work, written staged, published at the end */
  const char *ins[] = {data, colors, bkgs}, *csv_out = NULL;
  report_output o;
  jnd_status s = report_output_open(&o, ins, 3, NULL, NULL);
  if (s) return s;
  if (out_csv) s = jnd_output_add_file(o.w, out_csv, &csv_out);
  if (!s && p.run.report_path && strcmp(p.run.report_path, "-") != 0)
    s = jnd_output_add_file(o.w, p.run.report_path, &o.copy);
  cJSON *report = NULL;
  jnd_csf_run_result *R = jnd_calloc(1, sizeof *R);
  if (!s && !R) s = jnd_fail(JND_ERR_NOMEM, "csf: out of memory");
  if (!s) s = jnd_csf_data_read(data, colors, bkgs, &R->data);
  if (!s) {
    select_rows(&R->data, &p);
    if ((s = jnd_csf_evaluate(&R->data, &p.model, &p.options, &R->eval)))
      s = jnd_fail(s, "%s: %s", data, jnd_last_error());
  }
  if (!s && csv_out) s = write_rows(csv_out, &R->data, &R->eval, p.options.cross_validate);
  if (!s) report = csf_report(data, colors, bkgs, &p, &R->data, &R->eval);
  s = REPORT_OUTPUT_FINISH(&o, s, report, NULL, R);
  if (s) {
    jnd_csf_run_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
