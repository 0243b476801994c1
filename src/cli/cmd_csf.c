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
      "  --fold NAME         with --cross-validate: compute only this data set's fold\n"
      "                      (repeatable; the same fold as in the full run, but the\n"
      "                      pooled cross-validated figure covers only these sets)\n"
      "  --fit-only A,B,...  fit only these constants (default: all but those\n"
      "                      --list-constants shows as held at their prior)\n"
      "  --search-every N    fits search on every N-th row of each data set (default 1);\n"
      "                      every reported figure uses all rows; each search row\n"
      "                      stands for the N rows it was picked from\n"
      "  --prior-weight DB   the priors weigh as much as one row off by DB per prior\n"
      "                      width, against every row of the data (default 5.66)\n"
      "  --iterations N      Levenberg-Marquardt iterations of a fit (default 40)\n"
      "  --set NAME=VALUE    set one of the model's constants (repeatable);\n"
      "                      --list-constants shows them with their priors\n"
      "  --min-band CPD      lowest band peak (not fitted)\n"
      "  --threads N         rows are predicted in parallel (results do not depend on it)\n"
      "  --quiet\n");
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

static void print_score(const cli_common *c, const char *name, const jnd_csf_score *s, int cv) {
  cli_info(c, "%-14s %6d %10.2f %10.2f", name, s->rows, s->static_rows ? s->rmse_db_static : NAN, s->rmse_db);
  if (cv) cli_info(c, " %12.2f %10.2f %10.2f", s->static_rows ? s->cv_rmse_db_static : NAN, s->cv_rmse_db, s->cv_bias_db);
  cli_info(c, "\n");
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  jnd_csf_run_params p;
  jnd_csf_run_defaults(&p);
  jnd_csf_options *opt = &p.options;
  const char *data = NULL, *out_csv = NULL;
  const char *only[16], *folds[16];
  cli_args args = cli_args_start(argc, argv, "csf"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_flag(ap, "--list-constants")) {
      return list_constants();
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      out_csv = v;
    } else if (cli_opt(ap, "--colors", &v)) {
      p.colors = v;
    } else if (cli_opt(ap, "--backgrounds", &v)) {
      p.backgrounds = v;
    } else if (cli_opt(ap, "--dataset", &v)) {
      if (p.ndatasets == 16) return cli_bad("csf: at most 16 --dataset options");
      only[p.ndatasets++] = v;
      p.datasets = only;
    } else if (cli_flag(ap, "--static-only")) {
      p.static_only = 1;
    } else if (cli_opt(ap, "--every", &v)) {
      p.every = cli_int(ap, "--every", v, 1, 1000000);
    } else if (cli_flag(ap, "--fit")) {
      opt->fit = 1;
    } else if (cli_flag(ap, "--cross-validate")) {
      opt->cross_validate = 1;
    } else if (cli_opt(ap, "--fold", &v)) {
      if (opt->nfolds == 16) return cli_bad("csf: at most 16 --fold options");
      folds[opt->nfolds++] = v;
      opt->folds = folds;
    } else if (cli_opt(ap, "--fit-only", &v)) {
      if (parse_fit_only(v, &opt->fit_mask) != EXIT_OK) return EXIT_BAD;
      opt->fit_mask_set = 1;
    } else if (cli_opt(ap, "--search-every", &v)) {
      opt->search_every = cli_int(ap, "--search-every", v, 1, 1000);
    } else if (cli_opt(ap, "--prior-weight", &v)) {
      opt->prior_weight_db = cli_double(ap, "--prior-weight", v, 0.01, 1000);
    } else if (cli_opt(ap, "--iterations", &v)) {
      opt->max_iterations = cli_int(ap, "--iterations", v, 0, 1000);
    } else if (cli_opt(ap, "--set", &v)) {
      if (parse_set(v, &p.model) != EXIT_OK) return EXIT_BAD;
    } else if (cli_opt(ap, "--min-band", &v)) {
      p.model.min_band_cpd = cli_double(ap, "--min-band", v, 0.02, 10);
    } else if (cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &data, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!data) return cli_bad("csf: needs a CSV of thresholds (jnd csf --help)");
  if (opt->nfolds && !opt->cross_validate) return cli_bad("csf: --fold needs --cross-validate");
  progress_state ps = {&common, {0}, "", isatty(2)};
  opt->threads = common.threads;
  opt->progress = progress;
  opt->user = &ps;
  cli_run_options(&p.run, &common, 0);
  jnd_csf_run_result *R = NULL;
  jnd_status st = jnd_csf_run(data, &p, out_csv, &R);
  if (ps.tty) cli_progress_end(&ps.bar);
  if (st != JND_OK) return cli_lib_error();
  int rc = cli_report_print(R->report, common.json_path);
  const jnd_csf_data *d = &R->data;
  const jnd_csf_result *res = &R->eval;
  const int cv = opt->cross_validate;
  cli_info(&common, "%-14s %6s %10s %10s", "dataset", "rows", "static dB", "all dB");
  if (cv) cli_info(&common, " %12s %10s %10s", "LOSO static", "LOSO all", "LOSO bias");
  cli_info(&common, "\n");
  for (int ds = 0; ds < d->ndatasets; ds++)
    if (res->dataset[ds].rows) print_score(&common, d->datasets[ds], &res->dataset[ds], cv);
  print_score(&common, "pooled", &res->pooled, cv);
  if (opt->fit) {
    const jnd_model_constant *cl[JND_MAX_CONSTANTS];
    const int nc = jnd_model_constants(cl, JND_MAX_CONSTANTS);
    cli_info(&common, "fitted constants (± one posterior standard deviation)\n");
    for (int k = 0; k < nc; k++)
      if (res->fitted[k]) {
        double v = jnd_model_constant_get(&res->params, k);
        cli_info(&common, "  %-20s %10.4g  (%.3g .. %.3g)\n", cl[k]->name, v, v * exp(-res->sd_ln[k]),
                 v * exp(res->sd_ln[k]));
      }
  }
  jnd_csf_run_result_free(R);
  return rc;
}

const jnd_command jnd_cmd_csf = {"csf", "the vision model against human contrast-sensitivity data", run};
