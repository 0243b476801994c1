/* jnd report: the static HTML report of a batch's output folder. */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

static void help(void) {
  printf("usage: jnd report OUT [--quiet]\n"
         "\n"
         "Writes OUT/report/index.html and a page per asset from OUT/summary.json (jnd batch\n"
         "merge OUT writes it): the library's totals, a table of the assets that sorts by any\n"
         "column and filters by status, and per asset the numbers of its JSON report and the\n"
         "pictures that justify its decision (worst views, heatmaps, texres matrices, PCA\n"
         "energies, ...), with plots jnd draws. Static files that work from file:// with no\n"
         "network: open OUT/report/index.html in a browser. See docs/batch.md.\n"
         "\n"
         "Exit status: 0, 2 when OUT has no summary or cannot be written.\n");
}

static int run(int argc, char **argv) {
  cli_common common = {0};
  const char *out = NULL;
  cli_args args = cli_args_start(argc, argv, "report"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    if (cli_help(ap)) {
      help();
      return EXIT_OK;
    } else if (cli_common_opt(ap, &common)) {
    } else if (!cli_operand(ap, &out, NULL, 1)) {
      return EXIT_BAD;
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!out) return cli_bad("report: needs the batch's output folder (jnd report OUT)");
  char index[4096];
  if (jnd_batch_report(out, index, sizeof index) != JND_OK) return cli_bad("%s", jnd_last_error());
  cli_info(&common, "jnd report: wrote %s\n", index);
  return EXIT_OK;
}

const jnd_command jnd_cmd_report = {"report", "the static HTML report of a batch (OUT/report/index.html)", run};
