/* jnd example -o DIR — writes the built-in synthetic image pair. */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

static int run(int argc, char **argv) {
  const char *dir = NULL;
  int w = 768, h = 512;
  cli_args args = cli_args_start(argc, argv, "example"), *ap = &args;
  for (; args.i < argc && !args.bad; args.i++) {
    const char *v;
    if (cli_help(ap)) {
      printf("usage: jnd example -o DIR [--size WxH]\n\n"
             "Writes the built-in synthetic pair DIR/reference.png and DIR/test.png (default\n"
             "768x512): a reference with gradients, gratings, edges, colour and texture, and\n"
             "a test with four known distortions, one per quadrant: a 3x3 blur (top left),\n"
             "1%% noise (top right), a colour shift (bottom left), a faint 1%% luminance step\n"
             "(bottom right). Try: jnd diff DIR/reference.png DIR/test.png --heatmap where.png\n");
      return EXIT_OK;
    } else if (cli_opt(ap, "-o", &v) || cli_opt(ap, "--output", &v)) {
      dir = v;
    } else if (cli_opt(ap, "--size", &v)) {
      cli_size(ap, "--size", v, 64, 8192, &w, &h);
    } else {
      return cli_unknown(ap);
    }
  }
  if (args.bad) return EXIT_BAD;
  if (!dir) {
    cli_error("example: needs -o DIR (jnd example --help)");
    return EXIT_BAD;
  }
  /* staged and published together (docs/outputs.md) */
  jnd_output *outw = NULL;
  const char *staged = NULL;
  if (cli_out_open(&outw) != EXIT_OK || cli_out_dir(outw, dir, &staged) != EXIT_OK) return cli_out_end(outw, EXIT_BAD);
  jnd_image ref, test;
  if (jnd_example_pair(w, h, &ref, &test) != JND_OK) {
    cli_error("example: %s", jnd_last_error());
    return cli_out_end(outw, EXIT_BAD);
  }
  char p1[4096], p2[4096];
  snprintf(p1, sizeof p1, "%s/reference.png", staged);
  snprintf(p2, sizeof p2, "%s/test.png", staged);
  int rc = EXIT_OK;
  if (jnd_image_write_png(p1, &ref, 8) != JND_OK || jnd_image_write_png(p2, &test, 8) != JND_OK) {
    cli_error("%s", jnd_last_error());
    rc = EXIT_BAD;
  }
  jnd_image_free(&ref);
  jnd_image_free(&test);
  rc = cli_out_end(outw, rc);
  if (rc == EXIT_OK) fprintf(stderr, "wrote %s/reference.png and %s/test.png (%dx%d)\n", dir, dir, w, h);
  return rc;
}

const jnd_command jnd_cmd_example = {"example", "write the built-in synthetic image pair (for the demo)", run};
