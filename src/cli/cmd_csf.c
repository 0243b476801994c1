/* jnd csf DATA.csv — the vision model against human contrast thresholds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include <omp.h>

static void help(void) {
  printf(
      "usage: jnd csf DATA.csv [options]\n"
      "\n"
      "Predicts the contrast sensitivity of every stimulus in a castleCSF-format CSV\n"
      "(Gabors, gratings, discs; any colour direction, luminance, size, eccentricity)\n"
      "with the vision model: each stimulus is synthesised over its background and the\n"
      "contrast where the model's max-pooled probability of detection is 0.5 is found in\n"
      "log contrast. Prints the RMS error in dB (20 log10 predicted/measured) per data\n"
      "set and pooled, over static rows (t_frequency = 0) and over all rows.\n"
      "\n"
      "options:\n"
      "  -o FILE             write every input column plus predicted_sensitivity, error_db\n"
      "  --json FILE|-       JSON report\n"
      "  --colors FILE       colour directions (default: color_directions.csv beside DATA)\n"
      "  --backgrounds FILE  backgrounds (default: backgrounds.csv beside DATA)\n"
      "  --dataset NAME      only rows of this data set (repeatable)\n"
      "  --static-only       skip rows with t_frequency > 0\n"
      "  --every N           only every N-th row (a quick look)\n"
      "  --sensitivity S, --sens-rg S, --sens-yv S\n"
      "                      override the model's fitted CSF multipliers\n"
      "  --fit               fit the three multipliers to the data (least squares in dB)\n"
      "                      and report them; predictions are then made with the fit\n"
      "  --fit-rounds N      rounds of that fit (default 4; implies --fit)\n"
      "  --min-band CPD, --summation CYCLES, --summation-beta B, --eye-velocity DPS,\n"
      "  --chroma-sat TD, --rg-cutoff CPD, --yv-cutoff CPD\n"
      "                      override the model's other fitted constants (docs/model.md;\n"
      "                      scripts/fit-model.sh searches them)\n"
      "  --threads N         rows are predicted in parallel (results do not depend on it)\n"
      "  --quiet\n");
}

typedef struct {
  jnd_csf_stimulus st;
  int use;             /* 1: predict */
  const char *skip;    /* reason when not used */
  double measured, predicted, err_db;
  int dataset;         /* index into the data set list */
  int chan;            /* 0 achromatic, 1 red–green, 2 yellow–violet: the dominant channel, for --fit */
} row_t;

static char *dir_of(const char *path) {
  char *d = strdup(path);
  char *slash = strrchr(d, '/');
  if (slash)
    slash[1] = 0;
  else
    d[0] = 0;
  return d;
}

/* which opponent channel carries a stimulus (for the fit): the largest of
 * |A|, |a|, |b| of its cone-contrast vector weighted by a rough CSF ratio */
static int dominant_channel(const jnd_csf_stimulus *s) {
  double c[3];
  for (int i = 0; i < 3; i++) c[i] = s->dir_lms[i] / s->bkg_lms[i];
  double A = fabs((2 * c[0] + c[1] + c[2] / 20) / 3.05), a = fabs(c[0] - 12.0 / 11 * c[1] + c[2] / 11),
         b = fabs((c[0] + c[1] - 2 * c[2]) / 9);
  /* chromatic channels are about as sensitive per unit as A at low frequency (fit) */
  double wA = A, wa = a * 0.5, wb = b * 0.5;
  if (wA >= wa && wA >= wb) return 0;
  return wa >= wb ? 1 : 2;
}

static double rmse(const row_t *rows, int n, int ds, int static_only) {
  double s = 0;
  int k = 0;
  for (int i = 0; i < n; i++) {
    if (!rows[i].use || isnan(rows[i].err_db)) continue;
    if (ds >= 0 && rows[i].dataset != ds) continue;
    if (static_only && rows[i].st.t_frequency > 0) continue;
    s += rows[i].err_db * rows[i].err_db;
    k++;
  }
  return k ? sqrt(s / k) : NAN;
}

static int predict_all(row_t *rows, int n, const jnd_model_params *mp, int threads, const cli_common *c,
                       const char *label) {
  cli_progress pr;
  cli_progress_start(&pr, c, label, n);
  int done = 0, failed = 0;
  char msg[512] = "";
  jnd_model_params p = *mp;
  p.threads = 1;
  /* each thread keeps its own models; rows are independent, so results do not
   * depend on the thread count */
  jnd_csf_context *ctxs[256] = {0};
  if (threads > 256) threads = 256;
  for (int t = 0; t < threads; t++)
    if (jnd_csf_context_create(&p, &ctxs[t]) != JND_OK) {
      for (int k = 0; k < t; k++) jnd_csf_context_free(ctxs[k]);
      cli_error("csf: out of memory");
      return 0;
    }
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (int i = 0; i < n; i++) {
    if (!rows[i].use) continue;
    double sens;
    if (jnd_csf_threshold(ctxs[omp_get_thread_num()], &rows[i].st, &sens, NULL) != JND_OK) {
#pragma omp critical
      {
        if (!failed) snprintf(msg, sizeof msg, "row %d: %s", i + 2, jnd_last_error());
        failed = 1;
      }
      continue;
    }
    rows[i].predicted = sens;
    rows[i].err_db = 20 * log10(sens / rows[i].measured);
#pragma omp critical
    cli_progress_step(&pr, ++done);
  }
  cli_progress_end(&pr);
  for (int t = 0; t < threads; t++) jnd_csf_context_free(ctxs[t]);
  if (failed) cli_error("csf: %s", msg);
  return !failed;
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  jnd_model_params mp;
  jnd_model_defaults(&mp);
  const char *data = NULL, *out_csv = NULL, *colors = NULL, *bkgs = NULL;
  const char *only[16];
  int nonly = 0, static_only = 0, every = 1, fit = 0, fit_rounds = 4;
  cli_args args = cli_args_start(argc, argv, "csf"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_flag(ap, "--help") || cli_flag(ap, "-h")) {
      help();
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      out_csv = v;
    } else if (cli_opt(ap, "--colors", &v)) {
      colors = v;
    } else if (cli_opt(ap, "--backgrounds", &v)) {
      bkgs = v;
    } else if (cli_opt(ap, "--dataset", &v)) {
      if (nonly < 16) only[nonly++] = v;
    } else if (cli_flag(ap, "--static-only")) {
      static_only = 1;
    } else if (cli_opt(ap, "--every", &v)) {
      every = cli_int(ap, "--every", v, 1, 1000000);
    } else if (cli_opt(ap, "--sensitivity", &v)) {
      mp.sensitivity = cli_double(ap, "--sensitivity", v, 1e-6, 1e6);
    } else if (cli_opt(ap, "--sens-rg", &v)) {
      mp.sens_rg = cli_double(ap, "--sens-rg", v, 0, 1e6);
    } else if (cli_opt(ap, "--sens-yv", &v)) {
      mp.sens_yv = cli_double(ap, "--sens-yv", v, 0, 1e6);
    } else if (cli_opt(ap, "--min-band", &v)) {
      mp.min_band_cpd = cli_double(ap, "--min-band", v, 0.02, 10);
    } else if (cli_opt(ap, "--summation", &v)) {
      mp.summation_cycles = cli_double(ap, "--summation", v, 0, 20);
    } else if (cli_opt(ap, "--summation-beta", &v)) {
      mp.summation_beta = cli_double(ap, "--summation-beta", v, 1, 20);
    } else if (cli_opt(ap, "--eye-velocity", &v)) {
      mp.eye_velocity_dps = cli_double(ap, "--eye-velocity", v, 0, 300);
    } else if (cli_opt(ap, "--chroma-sat", &v)) {
      mp.chroma_sat_td = cli_double(ap, "--chroma-sat", v, 0, 1e7);
    } else if (cli_opt(ap, "--rg-cutoff", &v)) {
      mp.rg_cutoff_cpd = cli_double(ap, "--rg-cutoff", v, 0.1, 100);
    } else if (cli_opt(ap, "--yv-cutoff", &v)) {
      mp.yv_cutoff_cpd = cli_double(ap, "--yv-cutoff", v, 0.1, 100);
    } else if (cli_opt(ap, "--fit-rounds", &v)) {
      fit_rounds = cli_int(ap, "--fit-rounds", v, 1, 20);
      fit = 1;
    } else if (cli_flag(ap, "--fit")) {
      fit = 1;
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
  if (!data) {
    cli_error("csf: needs a CSV of thresholds (jnd csf --help)");
    return EXIT_BAD;
  }
  char *dir = dir_of(data);
  char colors_def[4096], bkgs_def[4096];
  snprintf(colors_def, sizeof colors_def, "%scolor_directions.csv", dir);
  snprintf(bkgs_def, sizeof bkgs_def, "%sbackgrounds.csv", dir);
  free(dir);
  if (!colors) colors = colors_def;
  if (!bkgs) bkgs = bkgs_def;

  jnd_csf_data data_set = {0};
  row_t *rows = NULL;
  cJSON *report = NULL;
  int rc = EXIT_BAD;
  if (jnd_csf_data_read(data, colors, bkgs, &data_set) != JND_OK) {
    cli_error("%s", jnd_last_error());
    goto out;
  }
  const jnd_csv t = data_set.table;
  const int nds = data_set.ndatasets;
  char **dsnames = data_set.datasets;
  rows = calloc(t.nrows ? t.nrows : 1, sizeof *rows);
  if (!rows) goto out;
  for (int r = 0; r < t.nrows; r++) {
    row_t *row = &rows[r];
    const jnd_csf_row *in = &data_set.rows[r];
    row->st = in->st;
    row->dataset = in->dataset;
    row->measured = in->measured;
    row->err_db = NAN;
    row->use = in->use;
    row->skip = in->skip;
    const jnd_csf_stimulus *s = &row->st;
    const char *ds = dsnames[in->dataset];
    if (row->use && static_only && s->t_frequency > 0) {
      row->use = 0;
      row->skip = "t_frequency > 0 (--static-only)";
    }
    if (row->use && nonly) {
      int keep = 0;
      for (int k = 0; k < nonly; k++) keep |= strcmp(only[k], ds) == 0;
      if (!keep) {
        row->use = 0;
        row->skip = "other data set";
      }
    }
    if (row->use && r % every) {
      row->use = 0;
      row->skip = "--every";
    }
    row->chan = dominant_channel(s);
  }
  int threads = common.threads > 0 ? common.threads : 0;
  if (threads == 0) {
#ifdef _OPENMP
    threads = omp_get_max_threads();
#else
    threads = 1;
#endif
  }
  if (fit) {
    /* multiplicative fit of the three CSF multipliers: each round moves a
     * channel's multiplier by the mean dB error of the rows it dominates */
    for (int round = 0; round < fit_rounds; round++) {
      if (!predict_all(rows, t.nrows, &mp, threads, &common, "fitting")) goto out;
      double sum[3] = {0}, cnt[3] = {0};
      for (int r = 0; r < t.nrows; r++) {
        if (!rows[r].use || isnan(rows[r].err_db) || rows[r].st.t_frequency > 0) continue;
        sum[rows[r].chan] += rows[r].err_db;
        cnt[rows[r].chan]++;
      }
      double *mult[3] = {&mp.sensitivity, &mp.sens_rg, &mp.sens_yv};
      for (int k = 0; k < 3; k++)
        if (cnt[k] > 0) *mult[k] *= pow(10, -sum[k] / cnt[k] / 20);
      cli_info(&common, "fit round %d: static RMSE %.2f dB -> sensitivity %.4g, sens_rg %.4g, sens_yv %.4g\n", round + 1,
               rmse(rows, t.nrows, -1, 1), mp.sensitivity, mp.sens_rg, mp.sens_yv);
    }
  }
  if (!predict_all(rows, t.nrows, &mp, threads, &common, "csf")) goto out;

  report = cli_report_new("csf");
  cJSON *inputs = cli_report_section(report, "inputs"), *params = cli_report_section(report, "parameters"),
        *res = cli_report_section(report, "result");
  cJSON_AddStringToObject(inputs, "data", data);
  cJSON_AddStringToObject(inputs, "colors", colors);
  cJSON_AddStringToObject(inputs, "backgrounds", bkgs);
  cJSON_AddNumberToObject(params, "sensitivity", mp.sensitivity);
  cJSON_AddNumberToObject(params, "sens_rg", mp.sens_rg);
  cJSON_AddNumberToObject(params, "sens_yv", mp.sens_yv);
  cJSON_AddNumberToObject(params, "beta", mp.beta);
  cJSON_AddNumberToObject(params, "minkowski", mp.minkowski);
  cJSON_AddStringToObject(params, "pooling", "max");
  cJSON_AddBoolToObject(params, "fitted", fit);
  cJSON *per = cJSON_AddObjectToObject(res, "datasets");
  cli_info(&common, "%-14s %6s %12s %12s\n", "dataset", "rows", "static dB", "all dB");
  for (int d = 0; d < nds; d++) {
    int n = 0, ns = 0;
    for (int r = 0; r < t.nrows; r++)
      if (rows[r].use && rows[r].dataset == d) {
        n++;
        ns += rows[r].st.t_frequency <= 0;
      }
    if (!n) continue;
    double rs = rmse(rows, t.nrows, d, 1), ra = rmse(rows, t.nrows, d, 0);
    cJSON *o = cJSON_AddObjectToObject(per, dsnames[d]);
    cJSON_AddNumberToObject(o, "rows", n);
    cJSON_AddNumberToObject(o, "static_rows", ns);
    if (ns) cJSON_AddNumberToObject(o, "rmse_db_static", rs);
    cJSON_AddNumberToObject(o, "rmse_db", ra);
    cli_info(&common, "%-14s %6d %12.2f %12.2f\n", dsnames[d], n, ns ? rs : NAN, ra);
  }
  /* which rows used a colour direction derived from its publication, not listed */
  cJSON *derived = cJSON_AddArrayToObject(res, "derived_directions");
  int nderived = 0;
  for (int r = 0; r < t.nrows; r++) {
    const jnd_csf_row *in = &data_set.rows[r];
    if (!in->derived_direction) continue;
    nderived++;
    int seen = 0;
    for (int q = 0; q < r && !seen; q++)
      seen = data_set.rows[q].derived_direction && data_set.rows[q].col_dir_id == in->col_dir_id &&
             data_set.rows[q].bkg_id == in->bkg_id && data_set.rows[q].dataset == in->dataset;
    if (seen) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "dataset", dsnames[in->dataset]);
    cJSON_AddNumberToObject(o, "col_dir_id", in->col_dir_id);
    cJSON_AddNumberToObject(o, "bkg_id", in->bkg_id);
    cJSON_AddItemToObject(o, "lms", cJSON_CreateDoubleArray(in->st.dir_lms, 3));
    cJSON *lines = cJSON_AddArrayToObject(o, "lines");
    for (int q = r; q < t.nrows; q++) {
      const jnd_csf_row *o2 = &data_set.rows[q];
      if (o2->derived_direction && o2->col_dir_id == in->col_dir_id && o2->bkg_id == in->bkg_id &&
          o2->dataset == in->dataset)
        cJSON_AddItemToArray(lines, cJSON_CreateNumber(o2->line));
    }
    cJSON_AddItemToArray(derived, o);
  }
  cJSON_AddNumberToObject(res, "derived_direction_rows", nderived);
  int nused = 0, nskip = 0;
  for (int r = 0; r < t.nrows; r++) nused += rows[r].use, nskip += !rows[r].use;
  double ps = rmse(rows, t.nrows, -1, 1), pa = rmse(rows, t.nrows, -1, 0);
  cJSON_AddNumberToObject(res, "rows", nused);
  cJSON_AddNumberToObject(res, "skipped", nskip);
  if (!isnan(ps)) cJSON_AddNumberToObject(res, "rmse_db_static", ps);
  if (!isnan(pa)) cJSON_AddNumberToObject(res, "rmse_db", pa);
  cli_info(&common, "%-14s %6d %12.2f %12.2f\n", "pooled", nused, ps, pa);

  if (out_csv) {
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    if (!buf) goto out;
#define PUT(...)                                                                           \
  do {                                                                                     \
    int need_ = snprintf(NULL, 0, __VA_ARGS__);                                            \
    while (len + need_ + 1 > cap) {                                                        \
      cap *= 2;                                                                            \
      char *nb_ = realloc(buf, cap);                                                       \
      if (!nb_) { free(buf); goto out; }                                                   \
      buf = nb_;                                                                           \
    }                                                                                      \
    len += snprintf(buf + len, cap - len, __VA_ARGS__);                                    \
  } while (0)
    for (int k = 0; k < t.ncols; k++) PUT("%s,", t.header[k]);
    PUT("predicted_sensitivity,error_db,note\n");
    for (int r = 0; r < t.nrows; r++) {
      for (int k = 0; k < t.ncols; k++) {
        const char *cell = t.cells[r][k];
        if (strpbrk(cell, ",\"\n")) {
          PUT("\"");
          for (const char *p = cell; *p; p++) PUT(*p == '"' ? "\"\"" : "%c", *p);
          PUT("\",");
        } else {
          PUT("%s,", cell);
        }
      }
      if (rows[r].use && !isnan(rows[r].err_db))
        PUT("%.6g,%.4f,%s\n", rows[r].predicted, rows[r].err_db,
            data_set.rows[r].derived_direction ? "colour direction derived (docs/csf.md)" : "");
      else
        PUT("NaN,NaN,skipped: %s\n", rows[r].skip ? rows[r].skip : "failed");
    }
#undef PUT
    jnd_status s = jnd_write_file_atomic(out_csv, buf, len);
    free(buf);
    if (s != JND_OK) {
      cli_error("%s", jnd_last_error());
      goto out;
    }
  }
  if (common.json_path && cli_report_write(report, common.json_path) != EXIT_OK) goto out;
  rc = EXIT_OK;
out:
  cJSON_Delete(report);
  free(rows);
  jnd_csf_data_free(&data_set);
  return rc;
}

const jnd_command jnd_cmd_csf = {"csf", "the vision model against human contrast-sensitivity data", run};
