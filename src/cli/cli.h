/* The command-line tool's shared pieces: the subcommand table, argument
 * parsing helpers, the JSON report envelope, progress and messages.
 * The CLI uses only include/jnd.h from the library. */
#ifndef JND_CLI_H
#define JND_CLI_H

#include <cjson/cJSON.h>
#include <stdio.h>

#include "jnd.h"

/* Exit statuses (DESIGN.md): 0 fine, 1 visible difference above --fail-above, 2 bad input. */
enum { EXIT_OK = 0, EXIT_ABOVE = 1, EXIT_BAD = 2 };

typedef struct {
  const char *name;
  const char *summary;                      /* one line for `jnd --help` */
  int (*run)(int argc, char **argv);        /* argv[0] is the subcommand name */
} jnd_command;

/* ---- options shared by many subcommands ---- */
typedef struct {
  int quiet;
  const char *json_path;   /* NULL: none; "-": stdout */
  int threads;
} cli_common;

/* Matches "--name VALUE" or "--name=VALUE" at argv[*i]; advances *i past the
 * value. Returns 1 on a match (value in *val), 0 otherwise; a missing value
 * prints an error and exits 2. */
int cli_opt(int argc, char **argv, int *i, const char *name, const char **val);
/* Matches a flag "--name". */
int cli_flag(char **argv, int i, const char *name);

/* Parse numbers or exit 2 with "jnd CMD: --opt: ..." */
double cli_double(const char *cmd, const char *opt, const char *v, double lo, double hi);
int cli_int(const char *cmd, const char *opt, const char *v, int lo, int hi);
/* --threads N (1..1024), made the default of every parallel region */
int cli_threads(const char *cmd, const char *v);
/* "A,B" pairs of numbers */
void cli_pair(const char *cmd, const char *opt, const char *v, double *a, double *b);

/* Prints "jnd: MSG" to stderr (one line). */
void cli_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* The same, returning EXIT_BAD: `return cli_bad("%s: problem", path);` */
int cli_bad(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints an error for an unknown option and the hint to use --help; returns EXIT_BAD. */
int cli_unknown(const char *cmd, const char *arg);
/* Human messages to stderr unless quiet. */
void cli_info(const cli_common *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The options every subcommand has: --json FILE|- and --quiet (-q). Returns
 * 1 if argv[*i] was one of them (advancing *i past a value). */
int cli_common_opt(int argc, char **argv, int *i, cli_common *c);

/* Display options: --display PRESET, --ppd, --peak, --black, --ambient,
 * --reflectivity, --exr-scale. Returns 1 if argv[*i] was one of them. */
int cli_display_opt(const char *cmd, int argc, char **argv, int *i, jnd_display *d);
extern const char *const cli_display_help;

/* The JSON report: {"jnd_version", "command", "inputs", "parameters", "result"}. */
cJSON *cli_report_new(const char *command);
cJSON *cli_report_section(cJSON *report, const char *name);
cJSON *cli_display_json(const jnd_display *d);
/* Writes the report to path ("-" = stdout) atomically; returns EXIT_OK or EXIT_BAD. */
int cli_report_write(cJSON *report, const char *path);

/* A progress bar on stderr when it is a terminal and not quiet. */
typedef struct {
  int enabled, total, done;
  const char *label;
  double t0;
} cli_progress;
void cli_progress_start(cli_progress *p, const cli_common *c, const char *label, int total);
void cli_progress_step(cli_progress *p, int done);
void cli_progress_end(cli_progress *p);

double cli_now(void);   /* monotonic seconds */

/* Subcommands (each in cmd_<name>.c). Missing ones are weak and skipped. */
#define JND_COMMANDS(X) \
  X(diff) X(csf) X(example) X(render) X(texres) X(calibrate) X(pca) X(lod) X(gaze) X(pop) X(batch) X(report)
#define X(n) extern const jnd_command jnd_cmd_##n __attribute__((weak));
JND_COMMANDS(X)
#undef X

#endif
