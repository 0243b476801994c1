/* jnd csf DATA.csv — the vision model against human contrast thresholds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"

static void help(void) {
  printf(
      "usage: jnd csf DATA.csv [options]\n"
      "\n"
      "Predicts the contrast sensitivity of every stimulus in a castleCSF-format CSV\n"
      "(Gabors, gratings, discs; any colour direction, luminance, size, eccentricity,\n"
      "temporal frequency) with the vision model: each stimulus is synthesised over its\n"
      "background and the contrast where the model's max-pooled probability of detection\n"
      "is 0.5 is found in log contrast. Prints the RMS error in dB (20 log10\n"
      "predicted/measured) per data set and pooled, over static rows (t_frequency = 0)\n"
      "and over all rows. With --cross-validate, also the error of each data set\n"
      "predicted by constants fitted on the other data sets only: the model's accuracy\n"
      "on data it has not seen (docs/model.md).\n"
      "\n"
      "options:\n"
      "  -o FILE             write every input column plus predicted_sensitivity, error_db\n"
      "                      (and predicted_cv, error_cv_db with --cross-validate)\n"
      "  --json FILE|-       JSON report\n"
      "  --colors FILE       colour directions (default: color_directions.csv beside DATA)\n"
      "  --backgrounds FILE  backgrounds (default: backgrounds.csv beside DATA)\n"
      "  --dataset NAME      only rows of this data set (repeatable)\n"
      "  --static-only       skip rows with t_frequency > 0\n"
      "  --every N           only every N-th row (a quick look)\n"
      "  --fit               fit the model's constants to the rows (maximum a posteriori,\n"
      "                      docs/model.md) and predict with them\n"
      "  --cross-validate    leave-one-data-set-out: refit on all data sets but one,\n"
      "                      predict that one, for each data set\n"
      "  --fit-only A,B,...  fit only these constants (default: all but those\n"
      "                      --list-constants shows as held at their prior)\n"
      "  --search-every N    fits search on every N-th row of each data set (default 1);\n"
      "                      every reported figure uses all rows\n"
      "  --iterations N      Levenberg-Marquardt iterations of a fit (default 40)\n"
      "  --set NAME=VALUE    set one of the model's constants (repeatable);\n"
      "                      --list-constants shows them with their priors\n"
      "  --min-band CPD      lowest band peak (not fitted)\n"
      "  --threads N         rows are predicted in parallel (results do not depend on it)\n"
      "  --quiet\n");
}

static char *dir_of(const char *path) {
  char *d = strdup(path);
  char *slash = strrchr(d, '/');
  if (slash)
    slash[1] = 0;
  else
    d[0] = 0;
  return d;
}

static int list_constants(void) {
  const jnd_model_constant *c[JND_MAX_CONSTANTS];
  int n = jnd_model_constants(c, JND_MAX_CONSTANTS);
  jnd_model_params p;
  jnd_model_defaults(&p);
  printf("%-24s %12s %12s %8s %6s  %s\n", "constant", "default", "prior", "prior sd", "fitted", "what (prior's source)");
  for (int k = 0; k < n; k++)
    printf("%-24s %12.5g %12.5g %8.2f %6s  %s (%s)\n", c[k]->name, jnd_model_constant_get(&p, k), c[k]->prior,
           c[k]->prior_sd, c[k]->held ? "held" : "yes", c[k]->what, c[k]->source);
  return EXIT_OK;
}

/* progress: a bar on a terminal, else one line per stage */
typedef struct {
  const cli_common *c;
  cli_progress bar;
  char stage[64];
  int tty;
} progress_state;

static void progress(void *user, const char *stage, int done, int total) {
  progress_state *ps = user;
  if (ps->c->quiet) return;
  if (strcmp(stage, ps->stage) != 0) {
    if (ps->tty) cli_progress_end(&ps->bar);
    snprintf(ps->stage, sizeof ps->stage, "%s", stage);
    if (ps->tty)
      cli_progress_start(&ps->bar, ps->c, ps->stage, total);
    else
      fprintf(stderr, "jnd csf: %s\n", stage);
  }
  if (ps->tty) cli_progress_step(&ps->bar, done);
}

static int parse_fit_only(const char *v, unsigned long long *mask) {
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", v);
  *mask = 0;
  for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int k = jnd_model_constant_find(tok);
    if (k < 0) return cli_bad("csf: --fit-only: no constant '%s' (jnd csf --list-constants)", tok);
    *mask |= 1ull << k;
  }
  return EXIT_OK;
}

static int parse_set(const char *v, jnd_model_params *p) {
  const char *eq = strchr(v, '=');
  char name[64];
  if (!eq || eq == v || (size_t)(eq - v) >= sizeof name) return cli_bad("csf: --set: expected NAME=VALUE, not '%s'", v);
  memcpy(name, v, (size_t)(eq - v));
  name[eq - v] = 0;
  int k = jnd_model_constant_find(name);
  if (k < 0) return cli_bad("csf: --set: no constant '%s' (jnd csf --list-constants)", name);
  char *end;
  double x = strtod(eq + 1, &end);
  if (end == eq + 1 || *end) return cli_bad("csf: --set %s: '%s' is not a number", name, eq + 1);
  if (jnd_model_constant_set(p, k, x) != JND_OK) return cli_bad("csf: --set: %s", jnd_last_error());
  return EXIT_OK;
}

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

static void print_score(const cli_common *c, const char *name, const jnd_csf_score *s, int cv) {
  cli_info(c, "%-14s %6d %10.2f %10.2f", name, s->rows, s->static_rows ? s->rmse_db_static : NAN, s->rmse_db);
  if (cv) cli_info(c, " %12.2f %10.2f %10.2f", s->static_rows ? s->cv_rmse_db_static : NAN, s->cv_rmse_db, s->cv_bias_db);
  cli_info(c, "\n");
}

/* the CSV with two or four columns added */
static int write_rows(const char *path, const jnd_csf_data *d, const jnd_csf_result *r, int cv) {
  size_t cap = 1 << 16, len = 0;
  char *buf = malloc(cap);
  if (!buf) return cli_bad("csf: out of memory");
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
    return cli_bad("csf: out of memory");
  }
  jnd_status s = jnd_write_file_atomic(path, buf, len);
  free(buf);
  return s == JND_OK ? EXIT_OK : cli_bad("%s", jnd_last_error());
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  jnd_model_params mp;
  jnd_model_defaults(&mp);
  jnd_csf_options opt;
  jnd_csf_options_defaults(&opt);
  const char *data = NULL, *out_csv = NULL, *colors = NULL, *bkgs = NULL;
  const char *only[16];
  int nonly = 0, static_only = 0, every = 1;
  cli_args args = cli_args_start(argc, argv, "csf"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_flag(ap, "--list-constants")) {
      return list_constants();
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      out_csv = v;
    } else if (cli_opt(ap, "--colors", &v)) {
      colors = v;
    } else if (cli_opt(ap, "--backgrounds", &v)) {
      bkgs = v;
    } else if (cli_opt(ap, "--dataset", &v)) {
      if (nonly == 16) return cli_bad("csf: at most 16 --dataset options");
      only[nonly++] = v;
    } else if (cli_flag(ap, "--static-only")) {
      static_only = 1;
    } else if (cli_opt(ap, "--every", &v)) {
      every = cli_int(ap, "--every", v, 1, 1000000);
    } else if (cli_flag(ap, "--fit")) {
      opt.fit = 1;
    } else if (cli_flag(ap, "--cross-validate")) {
      opt.cross_validate = 1;
    } else if (cli_opt(ap, "--fit-only", &v)) {
      if (parse_fit_only(v, &opt.fit_mask) != EXIT_OK) return EXIT_BAD;
      opt.fit_mask_set = 1;
    } else if (cli_opt(ap, "--search-every", &v)) {
      opt.search_every = cli_int(ap, "--search-every", v, 1, 1000);
    } else if (cli_opt(ap, "--iterations", &v)) {
      opt.max_iterations = cli_int(ap, "--iterations", v, 0, 1000);
    } else if (cli_opt(ap, "--set", &v)) {
      if (parse_set(v, &mp) != EXIT_OK) return EXIT_BAD;
    } else if (cli_opt(ap, "--min-band", &v)) {
      mp.min_band_cpd = cli_double(ap, "--min-band", v, 0.02, 10);
    } else if (cli_common_opt(ap, &common)) {
    } else if (argv[args.i][0] == '-' && argv[args.i][1]) {
      return cli_unknown(ap);
    } else if (!data) {
      data = argv[args.i];
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!data) return cli_bad("csf: needs a CSV of thresholds (jnd csf --help)");
  char *dir = dir_of(data);
  char colors_def[4096], bkgs_def[4096];
  snprintf(colors_def, sizeof colors_def, "%scolor_directions.csv", dir);
  snprintf(bkgs_def, sizeof bkgs_def, "%sbackgrounds.csv", dir);
  free(dir);
  if (!colors) colors = colors_def;
  if (!bkgs) bkgs = bkgs_def;

  jnd_csf_data d = {0};
  jnd_csf_result res = {0};
  cJSON *report = NULL;
  int rc = EXIT_BAD;
  /* the outputs checked before any work, written staged, published at the end */
  jnd_output *outw = NULL;
  const char *ins[] = {data, colors, bkgs}, *json_out = NULL;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_inputs(outw, ins, 3) != EXIT_OK ||
      cli_out_file(outw, out_csv, &out_csv) != EXIT_OK || cli_out_file(outw, common.json_path, &json_out) != EXIT_OK)
    goto out;
  if (jnd_csf_data_read(data, colors, bkgs, &d) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  for (int r = 0; r < d.nrows; r++) {
    jnd_csf_row *row = &d.rows[r];
    if (row->use && static_only && row->st.t_frequency > 0) {
      row->use = 0;
      row->skip = "t_frequency > 0 (--static-only)";
    }
    if (row->use && nonly) {
      int keep = 0;
      for (int k = 0; k < nonly; k++) keep |= strcmp(only[k], d.datasets[row->dataset]) == 0;
      if (!keep) {
        row->use = 0;
        row->skip = "other data set";
      }
    }
    if (row->use && r % every) {
      row->use = 0;
      row->skip = "--every";
    }
  }
  progress_state ps = {&common, {0}, "", isatty(2)};
  opt.threads = common.threads;
  opt.progress = progress;
  opt.user = &ps;
  if (jnd_csf_evaluate(&d, &mp, &opt, &res) != JND_OK) {
    if (ps.tty) cli_progress_end(&ps.bar);
    cli_error("%s: %s", data, jnd_last_error());
    goto out;
  }
  if (ps.tty) cli_progress_end(&ps.bar);
  const int cv = opt.cross_validate;

  report = cli_report_new("csf");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *result = cli_report_section(report, "result");
  cJSON_AddStringToObject(inputs, "data", data);
  cJSON_AddStringToObject(inputs, "colors", colors);
  cJSON_AddStringToObject(inputs, "backgrounds", bkgs);
  const jnd_model_constant *cl[JND_MAX_CONSTANTS];
  const int nc = jnd_model_constants(cl, JND_MAX_CONSTANTS);
  cJSON *consts = cJSON_AddObjectToObject(params, "constants");
  for (int k = 0; k < nc; k++) {
    cJSON *o = cJSON_AddObjectToObject(consts, cl[k]->name);
    cJSON_AddNumberToObject(o, "value", jnd_model_constant_get(&res.params, k));
    cJSON_AddNumberToObject(o, "prior", cl[k]->prior);
    cJSON_AddBoolToObject(o, "fitted", res.fitted[k]);
    if (!isnan(res.sd_ln[k])) cJSON_AddNumberToObject(o, "sd_ln", res.sd_ln[k]);
    if (!isnan(res.fold_sd_ln[k])) cJSON_AddNumberToObject(o, "fold_sd_ln", res.fold_sd_ln[k]);
    if (res.fold_value) {
      cJSON *fv = cJSON_AddObjectToObject(o, "without");
      for (int ds = 0; ds < d.ndatasets; ds++)
        if (!isnan(res.fold_value[(size_t)ds * nc + k]))
          cJSON_AddNumberToObject(fv, d.datasets[ds], res.fold_value[(size_t)ds * nc + k]);
    }
  }
  cJSON_AddNumberToObject(params, "min_band_cpd", res.params.min_band_cpd);
  cJSON_AddNumberToObject(params, "beta", res.params.beta);
  cJSON_AddNumberToObject(params, "minkowski", res.params.minkowski);
  cJSON_AddStringToObject(params, "pooling", "max");
  cJSON_AddBoolToObject(params, "fitted", opt.fit);
  cJSON_AddBoolToObject(params, "cross_validated", cv);
  cJSON_AddNumberToObject(params, "search_every", opt.search_every);
  cJSON_AddNumberToObject(params, "prior_weight_db", opt.prior_weight_db);

  cJSON *per = cJSON_AddObjectToObject(result, "datasets");
  cli_info(&common, "%-14s %6s %10s %10s", "dataset", "rows", "static dB", "all dB");
  if (cv) cli_info(&common, " %12s %10s %10s", "LOSO static", "LOSO all", "LOSO bias");
  cli_info(&common, "\n");
  for (int ds = 0; ds < d.ndatasets; ds++) {
    if (!res.dataset[ds].rows) continue;
    cJSON_AddItemToObject(per, d.datasets[ds], score_json(&res.dataset[ds]));
    print_score(&common, d.datasets[ds], &res.dataset[ds], cv);
  }
  print_score(&common, "pooled", &res.pooled, cv);
  int nskip = 0;
  for (int r = 0; r < d.nrows; r++) nskip += !d.rows[r].use;
  cJSON_AddNumberToObject(result, "rows", res.pooled.rows);
  cJSON_AddNumberToObject(result, "static_rows", res.pooled.static_rows);
  cJSON_AddNumberToObject(result, "skipped", nskip);
  if (res.pooled.static_rows) cJSON_AddNumberToObject(result, "rmse_db_static", res.pooled.rmse_db_static);
  cJSON_AddNumberToObject(result, "rmse_db", res.pooled.rmse_db);
  if (cv) {
    if (res.pooled.static_rows) cJSON_AddNumberToObject(result, "cv_rmse_db_static", res.pooled.cv_rmse_db_static);
    cJSON_AddNumberToObject(result, "cv_rmse_db", res.pooled.cv_rmse_db);
  }
  cJSON_AddNumberToObject(result, "model_passes", res.model_passes);
  if (opt.fit) {
    cli_info(&common, "fitted constants (± one posterior standard deviation)\n");
    for (int k = 0; k < nc; k++)
      if (res.fitted[k]) {
        double v = jnd_model_constant_get(&res.params, k);
        cli_info(&common, "  %-20s %10.4g  (%.3g .. %.3g)\n", cl[k]->name, v, v * exp(-res.sd_ln[k]),
                 v * exp(res.sd_ln[k]));
      }
  }

  /* which rows used a colour direction derived from its publication, not listed */
  cJSON *derived = cJSON_AddArrayToObject(result, "derived_directions");
  int nderived = 0;
  for (int r = 0; r < d.nrows; r++) {
    const jnd_csf_row *in = &d.rows[r];
    if (!in->derived_direction) continue;
    nderived++;
    int seen = 0;
    for (int q = 0; q < r && !seen; q++)
      seen = d.rows[q].derived_direction && d.rows[q].col_dir_id == in->col_dir_id && d.rows[q].bkg_id == in->bkg_id &&
             d.rows[q].dataset == in->dataset;
    if (seen) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "dataset", d.datasets[in->dataset]);
    cJSON_AddNumberToObject(o, "col_dir_id", in->col_dir_id);
    cJSON_AddNumberToObject(o, "bkg_id", in->bkg_id);
    cJSON_AddItemToObject(o, "lms", cJSON_CreateDoubleArray(in->st.dir_lms, 3));
    cJSON *lines = cJSON_AddArrayToObject(o, "lines");
    for (int q = r; q < d.nrows; q++) {
      const jnd_csf_row *o2 = &d.rows[q];
      if (o2->derived_direction && o2->col_dir_id == in->col_dir_id && o2->bkg_id == in->bkg_id &&
          o2->dataset == in->dataset)
        cJSON_AddItemToArray(lines, cJSON_CreateNumber(o2->line));
    }
    cJSON_AddItemToArray(derived, o);
  }
  cJSON_AddNumberToObject(result, "derived_direction_rows", nderived);

  if (out_csv && write_rows(out_csv, &d, &res, cv) != EXIT_OK) goto out;
  if (json_out && cli_report_write(report, json_out) != EXIT_OK) goto out;
  rc = EXIT_OK;
out:
  rc = cli_out_end(outw, rc);
  cJSON_Delete(report);
  jnd_csf_result_free(&res);
  jnd_csf_data_free(&d);
  return rc;
}

const jnd_command jnd_cmd_csf = {"csf", "the vision model against human contrast-sensitivity data", run};
