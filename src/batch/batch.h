/* Internal pieces of the batch layer: text buffers with escapes, shell words,
 * JSON paths, the table of commands a batch can run, and the folder layout
 * of a batch's output. See docs/batch.md. */
#ifndef JND_BATCH_H
#define JND_BATCH_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "jnd.h"
#include "tasks/report_schema.h"

/* ---- text ---- */

typedef struct {
  char *s;
  size_t len, cap;
  int failed; /* an allocation failed: the text is incomplete */
} jnd_text;

void jnd_text_put(jnd_text *t, const char *s);
void jnd_text_putn(jnd_text *t, const char *s, size_t n);
void jnd_text_printf(jnd_text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void jnd_text_html(jnd_text *t, const char *s);  /* escaped for HTML text and attributes */
void jnd_text_csv(jnd_text *t, const char *s);   /* one CSV field, quoted where needed */
void jnd_text_shell(jnd_text *t, const char *s); /* one shell word, quoted where needed */
/* The string (caller frees), "" for an empty text; NULL with JND_ERR_NOMEM
 * recorded when an append failed. t is empty afterwards. */
char *jnd_text_take(jnd_text *t);
void jnd_text_free(jnd_text *t);

/* ---- shell words ---- */

/* Splits s into words as a POSIX shell would (blanks, '…', "…", \), without
 * any expansion; unquoted $ ` ; & | < > ( ) * ? [ and a leading ~ or # are
 * refused (JND_ERR_FORMAT "options: ..."). *argv is allocated (jnd_words_free). */
jnd_status jnd_shell_split(const char *s, int *argc, char ***argv);
void jnd_words_free(int argc, char **argv);
/* The words as one shell-quoted line (caller frees); NULL when out of memory. */
char *jnd_shell_join(int argc, char *const *argv);

/* ---- JSON paths ----
 * Reports are read through the library's schema of them: jnd_json_select,
 * jnd_json_number and the RS_* paths of tasks/report_schema.h. */

/* ---- the commands a batch runs ---- */

typedef enum {
  JND_FMT_TEXT = 0, /* a string, or a number with %g */
  JND_FMT_NUMBER,   /* a number, 4 significant digits */
  JND_FMT_P,        /* a probability, 3 decimals */
  JND_FMT_BYTES,    /* bytes in MiB with the exact count in a tooltip */
  JND_FMT_PERCENT,  /* a fraction as a percentage */
  JND_FMT_SIZE,     /* [w, h] as w × h */
  JND_FMT_BOOL,     /* yes / no */
  JND_FMT_LIST      /* an array of numbers, 3 significant digits each */
} jnd_batch_fmt;

typedef struct {
  const char *label;
  const char *path; /* JSON path in the command's report */
  jnd_batch_fmt fmt;
} jnd_batch_field;

/* A table on the asset's page: a row per element of rows (a path ending in
 * []), a column per field (paths relative to the element). */
typedef struct {
  const char *title;
  const char *rows;
  jnd_batch_field cols[10];
} jnd_batch_table;

/* A picture the command wrote: a file name in OUT/<id>/, a glob of names
 * ("pareto_*.png"), or a JSON path to names ("result.matrices[].png"). */
typedef struct {
  const char *file, *glob, *path;
  const char *caption;
} jnd_batch_picture;

/* A picture the report draws from the command's report (PNG at path);
 * returns 0 when the report has nothing to draw, 1 when written, -1 on error
 * (jnd_last_error() set). */
typedef int (*jnd_batch_plot_fn)(const cJSON *report, const char *path);
typedef struct {
  const char *name; /* file name under report/<id>/ */
  jnd_batch_plot_fn draw;
  const char *caption;
} jnd_batch_plot;

typedef struct {
  const char *name;        /* the jnd command */
  /* the command line: jnd NAME [asset_flag] ASSET OPTIONS... OUT_ARGS... --quiet */
  const char *asset_flag;  /* NULL: the asset is the first positional argument */
  const char *out_args[8]; /* "{out}" is replaced by the asset's output folder */
  const char *json_name;   /* its report in OUT/<id>/ */
  const char *reserved[8]; /* options a manifest may not give: batch sets them */
  int exit1_complete;      /* exit status 1 means "complete, above the criterion" */
  /* summary.json */
  const char *memory_before, *memory_after, *p_detect; /* JSON paths or NULL */
  /* a short text of what was decided, and the same as JSON into chosen
   * (an object; NULL: none) */
  void (*decision)(const cJSON *report, jnd_text *out, cJSON *chosen);
  /* the asset's page in the report */
  jnd_batch_field fields[16];
  jnd_batch_table tables[3];
  jnd_batch_picture pictures[8];
  jnd_batch_plot plots[4];
} jnd_batch_command;

/* The command of that name, or NULL. */
const jnd_batch_command *jnd_batch_command_find(const char *name);
/* ", "-separated names of the commands a batch knows (static text). */
const char *jnd_batch_command_list(void);

/* ---- the output folder ----
 * OUT/<id>/                   the command's outputs, exactly as it writes them
 * OUT/_batch/manifest.json    the plan: every row of the manifest, its errors
 * OUT/_batch/records/<id>.json  how an asset's last run went (the commit point)
 * OUT/_batch/logs/<id>.log    its command's stderr
 * OUT/_batch/work/<id>/       a run in progress (never read as a result)
 * OUT/summary.json, summary.csv, report/   merge and report */
#define JND_BATCH_DIR "_batch"

/* Reads and parses a JSON file (at most 256 MiB); NULL with jnd_last_error(). */
cJSON *jnd_json_read(const char *path);
/* Writes a cJSON document atomically, formatted, with a final newline. */
jnd_status jnd_json_write(const char *path, const cJSON *doc);
/* mkdir -p */
jnd_status jnd_mkdirs(const char *path);
/* rm -rf (no error when missing) */
jnd_status jnd_remove_tree(const char *path);
/* "%s/%s" into a new string (NULL when out of memory). */
char *jnd_path_join(const char *a, const char *b);

/* The status names used in records and summaries. */
const char *jnd_asset_status_name(jnd_asset_status s);
int jnd_asset_status_parse(const char *name, jnd_asset_status *s);

/* Adds a row's id, line, asset, command and options to o. */
void jnd_batch_row_json(cJSON *o, const jnd_batch_row *r);
/* The plan's rows as JSON, and back. */
cJSON *jnd_batch_plan_json(const jnd_batch_manifest *m);
jnd_status jnd_batch_plan_read(const char *out_dir, jnd_batch_manifest *m);

#endif
