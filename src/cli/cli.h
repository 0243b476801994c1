/* The command-line tool's shared pieces: the subcommand table, the option
 * parsers every command shares (one per option group: common, display,
 * views, criterion), the JSON report envelope, progress and messages.
 * The CLI uses only include/jnd.h from the library.
 *
 * Parsers never exit: a bad value prints one line ("jnd: ...") and sets the
 * parse state's `bad`; the command then returns EXIT_BAD. So a batch that
 * runs commands in one process survives a bad asset. */
#ifndef JND_CLI_H
#define JND_CLI_H

#include <stdio.h>

#include "jnd.h"

/* Exit statuses (DESIGN.md): 0 fine, 1 visible difference above --fail-above, 2 bad input. */
enum { EXIT_OK = 0, EXIT_ABOVE = 1, EXIT_BAD = 2 };

typedef struct {
  const char *name;
  const char *summary;                      /* one line for `jnd --help` */
  int (*run)(int argc, char **argv);        /* argv[0] is the subcommand name */
} jnd_command;

/* ---- parsing ---- */

/* Where parsing is: argv[i] is the argument at hand. */
typedef struct {
  int argc;
  char **argv;
  int i;
  const char *cmd;   /* the subcommand, for messages */
  int bad;           /* 1 once an error has been printed */
} cli_args;

cli_args cli_args_start(int argc, char **argv, const char *cmd);

/* Matches "--name VALUE" or "--name=VALUE" at argv[i]; advances i past the
 * value. Returns 1 on a match (value in *val); a missing value is an error
 * (bad set, *val = ""). */
int cli_opt(cli_args *a, const char *name, const char **val);
/* Matches a flag "--name". */
int cli_flag(const cli_args *a, const char *name);

/* Numbers: the value, or after an error (printed, bad set) lo. Messages are
 * "jnd: OPT: ..." naming the option, the same from every command. */
double cli_double(cli_args *a, const char *opt, const char *v, double lo, double hi);
int cli_int(cli_args *a, const char *opt, const char *v, int lo, int hi);
/* "A,B": two numbers */
void cli_pair(cli_args *a, const char *opt, const char *v, double *x, double *y);
/* "WxH": two integers in lo..hi */
void cli_size(cli_args *a, const char *opt, const char *v, int lo, int hi, int *w, int *h);
/* "1024,512,256": integers in lo..hi, at most max; returns the count */
int cli_int_list(cli_args *a, const char *opt, const char *v, int lo, int hi, int *out, int max);
/* "1,2.5,10": numbers in lo..hi, at most max; returns the count */
int cli_double_list(cli_args *a, const char *opt, const char *v, double lo, double hi, double *out, int max);
/* --errors LIST, the one parser of every command that makes a chain: error
 * targets relative to the model's extent (the largest side of its bounding
 * box), numbers or fractions ("0.001,1/256"), rising, each in
 * [CLI_ERRORS_MIN, 1] (docs/lod.md). Returns the count (at most max). The
 * lower bound: float32 positions resolve about 1e-7 of an extent, so a
 * smaller target asks meshoptimizer for nothing it can measure. */
#define CLI_ERRORS_MIN 1e-6
int cli_errors(cli_args *a, const char *v, double *out, int max);

/* Prints "jnd: MSG" to stderr (one line). */
void cli_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* The same, returning EXIT_BAD: `return cli_bad("%s: problem", path);` */
int cli_bad(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prints an error for an unknown option or argument and the hint to use --help; returns EXIT_BAD. */
int cli_unknown(cli_args *a);
/* --help or -h at argv[i] (the command then prints its help and returns EXIT_OK). */
int cli_help(const cli_args *a);
/* The tail of every command's option loop, once argv[i] matched none of
 * its options: an option the command does not know ("-x", "--x"; "-" alone
 * is an operand) or an operand past the max it takes is an error (printed,
 * bad set); otherwise the operand is appended to ops[*n] (n NULL: ops is
 * one slot, max 1). Returns 1 when taken, 0 after an error:
 *   } else if (!cli_operand(ap, &model, NULL, 1)) {
 *     return EXIT_BAD;
 *   }                                                                     */
int cli_operand(cli_args *a, const char **ops, int *n, int max);
/* Prints "jnd: MESSAGE" with the library's last error; returns EXIT_BAD. */
int cli_lib_error(void);

/* ---- option groups ---- */

/* --json FILE|-, --quiet (-q), --threads N, --timings */
typedef struct {
  int quiet;
  const char *json_path;   /* NULL: none; "-": stdout */
  int threads;             /* 0: OpenMP's default; else made the default of every parallel region */
  int timings;
} cli_common;
int cli_common_opt(cli_args *a, cli_common *c);
extern const char *const cli_common_help;

/* --display PRESET, --ppd, --peak, --black, --ambient, --reflectivity,
 * --exr-scale, --task. A quantity given explicitly wins over the preset's,
 * whatever the order of the options: cli_display_get applies them last. */
typedef struct {
  jnd_display preset;
  double value[6];   /* ppd, peak, black, ambient, reflectivity, exr scale */
  unsigned given;    /* bit k: value[k] was given */
  jnd_viewing_task task;
  int task_given;
} cli_display;
/* --task side-by-side|flicker alone (in cli_display_opt too): 1 when it was
 * the option, *t set when its value is a task (a->bad otherwise). The help
 * line every command that judges shows, display options or not. */
int cli_task_opt(cli_args *a, jnd_viewing_task *t);
#define CLI_TASK_HELP                                                                  \
  "  --task T            how the viewer compares the two images, so what P means:\n"   \
  "                      side-by-side (default: in two places, looked at in turn for\n" \
  "                      as long as they like; a uniform change is seen at about\n"   \
  "                      CIEDE2000 1) or flicker (toggled in place, as FLIP's\n"      \
  "                      flipping: stricter, every transient seen). A gate or an\n"   \
  "                      asset pipeline asks whether its users would see the\n"       \
  "                      change, and they never see the two toggled in place\n"       \
  "                      (docs/model.md \"Viewing task\")\n"
void cli_display_init(cli_display *d);
int cli_display_opt(cli_args *a, cli_display *d);
jnd_display cli_display_get(const cli_display *d);
extern const char *const cli_display_help;
/* 1 when --exr-scale was given (jnd_diff_params.exr_scale_given: no
 * warning about a linear input that looks relative). */
int cli_display_exr_scale_given(const cli_display *d);

/* The views of every rendering command: --views --seed --size --coverage
 * --distance --fov --elevation --lights --light-intensity --cameras
 * --samples --anisotropy --env --platform --map-size, one set of limits. */
enum {
  CLI_VIEWS = 1u << 0, CLI_SEED = 1u << 1, CLI_SIZE = 1u << 2, CLI_COVERAGE = 1u << 3,
  CLI_DISTANCE = 1u << 4, CLI_FOV = 1u << 5, CLI_ELEVATION = 1u << 6, CLI_LIGHTS = 1u << 7,
  CLI_LIGHT_INTENSITY = 1u << 8, CLI_CAMERAS = 1u << 9, CLI_ENV = 1u << 10, CLI_SAMPLES = 1u << 11,
  CLI_ANISOTROPY = 1u << 12, CLI_PLATFORM = 1u << 13, CLI_MAP_SIZE = 1u << 14
};
typedef struct {
  jnd_view_set set;
  const char *cameras;     /* --cameras FILE (also set.cameras_path: jnd_view_set_make reads it) */
  int map_size;            /* --map-size: side of the built-in asset's maps */
  unsigned given;          /* CLI_* bits of the options given */
} cli_views;
/* Defaults: jnd_view_set_defaults at width × height pixels. */
void cli_views_init(cli_views *v, int width, int height);
int cli_views_opt(cli_args *a, cli_views *v);
/* A command that renders its own way (its own image sizes, cameras or
 * sampling) still reads the view options with cli_views_opt, so that a bad
 * value gets the same refusal everywhere; then it refuses the options it has
 * no use for: one line "jnd: CMD: --opt does not apply (why)", EXIT_BAD;
 * 0 when every option given is in `allowed`. */
int cli_views_only(const cli_views *v, unsigned allowed, const char *cmd, const char *why);
extern const char *const cli_views_help;

/* --p P and --q Q: the view criterion (000 §9) */
int cli_criterion_opt(cli_args *a, jnd_criterion *c);
extern const char *const cli_criterion_help;

/* --pool pNN and --calibration FILE: the pooling of P per view. The file is
 * loaded by cli_calibration_get (its percentile unless --pool is given). */
typedef struct {
  const char *path;
  const char *pool;
} cli_calibration;
int cli_calibration_opt(cli_args *a, cli_calibration *c);
int cli_calibration_get(const cli_calibration *c, jnd_calibration *out);   /* 0 after an error */

/* ---- output ---- */

/* Human messages to stderr unless quiet. */
void cli_info(const cli_common *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A run's report text (jnd_<task>_run's result) to standard output when path
 * is "-" (the run itself wrote it to a file path); EXIT_OK or EXIT_BAD. */
int cli_report_print(const char *text, const char *path);
/* A run's shared options from the common ones: the builtin's map side, the
 * report's copy (--json), --timings, and warnings printed as
 * "jnd: warning: ..." unless --quiet (c must outlive the run). */
void cli_run_options(jnd_run_options *o, const cli_common *c, int map_size);

/* The run's output writer (jnd_output, docs/outputs.md), opened before any
 * work: inputs (each an asset or image: the files it references too) and
 * then outputs are registered, the run writes to the staged names, and
 * cli_out_end publishes them or removes them all. Each returns EXIT_OK, or
 * EXIT_BAD after printing the writer's one-line refusal. A NULL path is
 * skipped (*staged NULL); "-" stays "-". */
int cli_out_open(jnd_output **w);
int cli_out_inputs(jnd_output *w, const char *const *paths, int n);
int cli_out_file(jnd_output *w, const char *path, const char **staged);
int cli_out_dir(jnd_output *w, const char *path, const char **staged);
/* Commits when rc is EXIT_OK or EXIT_ABOVE (a failed commit: EXIT_BAD),
 * else removes every staged output; frees w (NULL is fine); returns rc. */
int cli_out_end(jnd_output *w, int rc);

/* Progress on stderr unless quiet: a bar when stderr is a terminal; else a
 * line per stage (cli_progress_line), with the elapsed time. */
typedef struct {
  int enabled, tty, total, done;
  const char *label;
  double t0;
} cli_progress;
void cli_progress_start(cli_progress *p, const cli_common *c, const char *label, int total);
void cli_progress_step(cli_progress *p, int done);
void cli_progress_line(cli_progress *p, const char *line);
void cli_progress_end(cli_progress *p);
/* For a few long steps (pop's switch searches): a line per step, terminal or
 * log, with the steps done of the total, the time so far and an estimate of
 * the time left (the mean step so far times the steps left). */
void cli_progress_count(cli_progress *p, int done);
double cli_progress_eta(const cli_progress *p);   /* seconds left at the mean step so far (0 before one) */
/* The library's progress callback shape: line NULL after a step, else a stage summary. */
void cli_progress_callback(void *user, const char *line, int done, int total);


/* Subcommands (each in cmd_<name>.c). Missing ones are weak and skipped. */
#define JND_COMMANDS(X) \
  X(diff) X(csf) X(example) X(render) X(texres) X(calibrate) X(pca) X(lod) X(gaze) X(pop) X(batch) X(report) X(budget)
#define X(n) extern const jnd_command jnd_cmd_##n __attribute__((weak));
JND_COMMANDS(X)
#undef X

#endif
