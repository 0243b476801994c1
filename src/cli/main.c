/* jnd — the command-line tool: `jnd <command> [options]`. */
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

static const jnd_command *const commands[] = {
#define X(n) &jnd_cmd_##n,
    JND_COMMANDS(X)
#undef X
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

static void usage(FILE *f) {
  fprintf(f,
          "jnd %s — the cheapest asset nobody will notice\n"
          "\n"
          "A model of human vision (Schwarz & Stamminger 2009) predicts, per pixel, the\n"
          "probability that a viewer notices a change; jnd uses it to compare images and\n"
          "to choose texture sizes, encodings and LODs that stay below a threshold.\n"
          "\n"
          "usage: jnd <command> [options]     jnd <command> --help for its options\n"
          "\n"
          "commands:\n",
          jnd_version());
  for (size_t i = 0; i < NCOMMANDS; i++)
    if (commands[i]) fprintf(f, "  %-10s %s\n", commands[i]->name, commands[i]->summary);
  fprintf(f,
          "\n"
          "examples:\n"
          "  jnd diff ref.png test.png --display standard-fhd --heatmap where.png\n"
          "  jnd diff a.png b.png --fail-above 0.2 --json -     # gate a render regression\n"
          "\n"
          "Exit status: 0 fine, 1 difference above --fail-above, 2 bad input.\n");
}

int main(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return EXIT_BAD;
  }
  const char *cmd = argv[1];
  if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
    if (argc >= 3 && strcmp(cmd, "help") == 0) {
      for (size_t i = 0; i < NCOMMANDS; i++)
        if (commands[i] && strcmp(commands[i]->name, argv[2]) == 0) {
          char *hargv[] = {argv[2], "--help", NULL};
          return commands[i]->run(2, hargv);
        }
    }
    usage(stdout);
    return EXIT_OK;
  }
  if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "-V") == 0) {
    printf("jnd %s\n", jnd_version());
    return EXIT_OK;
  }
  for (size_t i = 0; i < NCOMMANDS; i++)
    if (commands[i] && strcmp(commands[i]->name, cmd) == 0) return commands[i]->run(argc - 1, argv + 1);
  cli_error("unknown command '%s' (jnd --help lists them)", cmd);
  return EXIT_BAD;
}
