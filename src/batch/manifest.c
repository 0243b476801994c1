/* Manifests: the list of assets a batch runs, from a CSV file, a JSON file
 * or a glob, each row checked on its own so that one bad row fails alone.
 *   1. parse the rows (CSV: RFC 4180 records under the header
 *      id,asset,command,options; JSON: a list of objects; glob: sorted matches)
 *   2. check each row: its id, its command, its options (shell words, none
 *      of those batch sets itself)
 *   3. mark later rows whose id repeats an earlier one (ignoring case, since
 *      ids are folder names and some file systems ignore case)
 *   4. look for each asset file, relative to the manifest's folder */
#include <ctype.h>
#include <errno.h>
#include <glob.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "batch/batch.h"
#include "core/core.h"
#include "io/io.h"

#define MAX_MANIFEST_BYTES ((size_t)64 << 20)
#define MAX_ROWS 1000000

void jnd_batch_manifest_free(jnd_batch_manifest *m) {
  if (!m) return;
  for (int i = 0; i < m->nrows; i++) {
    jnd_batch_row *r = &m->rows[i];
    free(r->id);
    free(r->asset);
    free(r->command);
    free(r->options);
    free(r->error);
    jnd_words_free(r->argc, r->argv);
  }
  free(m->rows);
  free(m->source);
  free(m->base_dir);
  memset(m, 0, sizeof *m);
}

static char *sdup(const char *s) {
  char *d = strdup(s ? s : "");
  if (!d) jnd_fail(JND_ERR_NOMEM, "out of memory");
  return d;
}

/* where a row is, for its messages: "assets.csv:3", "assets.json: entry 3" */
typedef enum { WHERE_LINE, WHERE_ENTRY, WHERE_MATCH } where_kind;

static void row_fail(jnd_batch_row *r, const char *name, where_kind k, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void row_fail(jnd_batch_row *r, const char *name, where_kind k, const char *fmt, ...) {
  if (r->error) return; /* the first problem is the one reported */
  char msg[768];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  jnd_text t = {0};
  if (k == WHERE_LINE) jnd_text_printf(&t, "%s:%d: %s", name, r->line, msg);
  else if (k == WHERE_ENTRY) jnd_text_printf(&t, "%s: entry %d: %s", name, r->line, msg);
  else jnd_text_printf(&t, "%s: match %d (%s): %s", name, r->line, r->asset, msg);
  /* one line, whatever the row held */
  for (size_t i = 0; i < t.len; i++)
    if (t.s[i] == '\n' || t.s[i] == '\r') t.s[i] = ' ';
  r->error = jnd_text_take(&t);
}

static int id_valid(const char *id) {
  size_t n = strlen(id);
  if (n == 0 || n > JND_BATCH_MAX_ID || !isalnum((unsigned char)id[0])) return 0;
  for (size_t i = 0; i < n; i++)
    if (!isalnum((unsigned char)id[i]) && !strchr("._-", id[i])) return 0;
  return 1;
}

/* names OUT/ holds besides the assets' folders */
static int id_reserved(const char *id) {
  static const char *const names[] = {"report", "summary.json", "summary.csv", JND_BATCH_DIR};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
    if (strcasecmp(id, names[i]) == 0) return 1;
  return 0;
}

/* steps 2: one row's id, command and options */
static void row_check(jnd_batch_row *r, const char *name, where_kind k) {
  if (!r->id[0]) row_fail(r, name, k, "no id");
  else if (!id_valid(r->id))
    row_fail(r, name, k, "id '%.120s' is not a folder name jnd batch makes: letters, digits, '.', '_', '-', "
             "beginning with a letter or digit, at most %d bytes", r->id, JND_BATCH_MAX_ID);
  else if (id_reserved(r->id)) row_fail(r, name, k, "id '%s' is a name the output folder uses itself", r->id);
  if (!r->asset[0]) row_fail(r, name, k, "no asset");
  const jnd_batch_command *c = jnd_batch_command_find(r->command);
  if (!r->command[0]) row_fail(r, name, k, "no command (jnd batch runs %s)", jnd_batch_command_list());
  else if (!c) row_fail(r, name, k, "unknown command '%.60s' (jnd batch runs %s)", r->command, jnd_batch_command_list());
  if (!r->argv && !r->error) {
    if (jnd_shell_split(r->options, &r->argc, &r->argv) != JND_OK) row_fail(r, name, k, "%s", jnd_last_error());
  }
  for (int i = 0; c && i < r->argc && !r->error; i++)
    for (int j = 0; j < (int)(sizeof c->reserved / sizeof c->reserved[0]) && c->reserved[j]; j++) {
      size_t n = strlen(c->reserved[j]);
      if (strcmp(r->argv[i], c->reserved[j]) == 0 || (strncmp(r->argv[i], c->reserved[j], n) == 0 && r->argv[i][n] == '='))
        row_fail(r, name, k, "options: %s is set by jnd batch (each asset's outputs go to OUT/<id>/)", c->reserved[j]);
    }
}

static int cmp_id_ci(const void *a, const void *b) {
  const jnd_batch_row *x = *(jnd_batch_row *const *)a, *y = *(jnd_batch_row *const *)b;
  int c = strcasecmp(x->id, y->id);
  return c ? c : (x->line > y->line) - (x->line < y->line);
}

/* step 3: the first row of an id keeps it; the later ones fail */
static jnd_status mark_duplicates(jnd_batch_manifest *m, const char *name, where_kind k) {
  if (m->nrows < 2) return JND_OK;
  jnd_batch_row **by = jnd_alloc((size_t)m->nrows, sizeof *by);
  if (!by) return JND_ERR_NOMEM;
  for (int i = 0; i < m->nrows; i++) by[i] = &m->rows[i];
  qsort(by, (size_t)m->nrows, sizeof *by, cmp_id_ci);
  for (int i = 1; i < m->nrows; i++) {
    jnd_batch_row *first = by[i - 1];
    if (!by[i]->id[0] || strcasecmp(by[i]->id, first->id) != 0) continue;
    /* the first of the run of equal ids is where the run began */
    int j = i - 1;
    while (j > 0 && strcasecmp(by[j - 1]->id, by[i]->id) == 0) j--;
    first = by[j];
    if (strcmp(by[i]->id, first->id) == 0)
      row_fail(by[i], name, k, "duplicate id '%s' (first %s %d)", by[i]->id, k == WHERE_LINE ? "on line" : "as entry",
               first->line);
    else
      row_fail(by[i], name, k, "id '%s' differs only in case from '%s' (%s %d): both would be one folder on some "
               "file systems", by[i]->id, first->id, k == WHERE_LINE ? "line" : "entry", first->line);
  }
  free(by);
  return JND_OK;
}

static jnd_batch_row *add_row(jnd_batch_manifest *m, int *cap) {
  if (m->nrows == *cap) {
    if (*cap >= MAX_ROWS) {
      jnd_fail(JND_ERR_LIMIT, "more than %d rows", MAX_ROWS);
      return NULL;
    }
    int nc = *cap ? *cap * 2 : 16;
    jnd_batch_row *nr = realloc(m->rows, sizeof *nr * (size_t)nc);
    if (!nr) {
      jnd_fail(JND_ERR_NOMEM, "out of memory");
      return NULL;
    }
    m->rows = nr;
    *cap = nc;
  }
  jnd_batch_row *r = &m->rows[m->nrows++];
  memset(r, 0, sizeof *r);
  return r;
}

static jnd_status finish(jnd_batch_manifest *m, const char *name, where_kind k) {
  for (int i = 0; i < m->nrows; i++) row_check(&m->rows[i], name, k);
  return mark_duplicates(m, name, k);
}

static jnd_status fail_free(jnd_batch_manifest *m, jnd_status s) {
  jnd_batch_manifest_free(m);
  return s;
}

/* ---- CSV ---- */

static const char *const COLUMNS[4] = {"id", "asset", "command", "options"};

jnd_status jnd_batch_manifest_parse_csv(const char *name, const char *text, size_t n, jnd_batch_manifest *out) {
  memset(out, 0, sizeof *out);
  size_t pos = 0, counted = 0;
  int line = 1;
  if (n >= 3 && (unsigned char)text[0] == 0xEF && (unsigned char)text[1] == 0xBB && (unsigned char)text[2] == 0xBF)
    pos = counted = 3;
  char **f;
  int nf;
  int r = jnd_csv_record(text, n, &pos, &f, &nf);
  if (r <= 0)
    return jnd_fail(JND_ERR_FORMAT, "%s: %s", name, r == 0 ? "empty manifest (the header is id,asset,command,options)"
                                                             : "malformed CSV header");
  int col[4] = {-1, -1, -1, -1};
  jnd_status s = JND_OK;
  for (int i = 0; i < nf && s == JND_OK; i++) {
    char *h = f[i];
    while (*h == ' ') h++;
    size_t hl = strlen(h);
    while (hl && h[hl - 1] == ' ') h[--hl] = 0;
    int k = -1;
    for (int j = 0; j < 4; j++)
      if (strcmp(h, COLUMNS[j]) == 0) k = j;
    if (k < 0) s = jnd_fail(JND_ERR_FORMAT, "%s:1: unknown column '%.60s' (the header is id,asset,command,options)", name, h);
    else if (col[k] >= 0) s = jnd_fail(JND_ERR_FORMAT, "%s:1: column '%s' twice", name, h);
    else col[k] = i;
  }
  for (int j = 0; j < 3 && s == JND_OK; j++)
    if (col[j] < 0) s = jnd_fail(JND_ERR_FORMAT, "%s:1: no column '%s' (the header is id,asset,command,options)", name, COLUMNS[j]);
  jnd_words_free(nf, f);
  if (s != JND_OK) return s;
  int cap = 0, header_cols = 0;
  for (int j = 0; j < 4; j++)
    if (col[j] + 1 > header_cols) header_cols = col[j] + 1;
  for (;;) {
    for (; counted < pos; counted++)
      if (text[counted] == '\n') line++;
    r = jnd_csv_record(text, n, &pos, &f, &nf);
    if (r == 0) break;
    if (r < 0) return fail_free(out, jnd_fail(JND_ERR_FORMAT, "%s:%d: malformed CSV record (a quote not closed?)", name, line));
    if (nf == 1 && !f[0][0]) { /* blank line */
      jnd_words_free(nf, f);
      continue;
    }
    jnd_batch_row *row = add_row(out, &cap);
    if (!row) {
      jnd_words_free(nf, f);
      return fail_free(out, jnd_fail(JND_ERR_LIMIT, "%s: %s", name, jnd_last_error()));
    }
    row->line = line;
    const char *v[4];
    for (int j = 0; j < 4; j++) v[j] = col[j] >= 0 && col[j] < nf ? f[col[j]] : "";
    row->id = sdup(v[0]);
    row->asset = sdup(v[1]);
    row->command = sdup(v[2]);
    row->options = sdup(v[3]);
    if (nf != header_cols) {
      row_fail(row, name, WHERE_LINE, "%d fields where the header has %d", nf, header_cols);
    }
    jnd_words_free(nf, f);
    if (!row->id || !row->asset || !row->command || !row->options) return fail_free(out, JND_ERR_NOMEM);
  }
  if (out->nrows == 0) return fail_free(out, jnd_fail(JND_ERR_FORMAT, "%s: no assets under the header", name));
  s = finish(out, name, WHERE_LINE);
  return s == JND_OK ? JND_OK : fail_free(out, s);
}

/* ---- JSON ---- */

jnd_status jnd_batch_manifest_parse_json(const char *name, const char *text, size_t n, jnd_batch_manifest *out) {
  memset(out, 0, sizeof *out);
  cJSON *root = cJSON_ParseWithLength(text, n);
  const cJSON *list = root;
  if (cJSON_IsObject(root)) list = cJSON_GetObjectItemCaseSensitive(root, "assets");
  if (!cJSON_IsArray(list)) {
    cJSON_Delete(root);
    return jnd_fail(JND_ERR_FORMAT, "%s: not a JSON list of assets (or {\"assets\": [...]}) of "
                    "{\"id\", \"asset\", \"command\", \"options\"}", name);
  }
  int cap = 0, line = 0;
  jnd_status s = JND_OK;
  const cJSON *e;
  cJSON_ArrayForEach(e, list) {
    jnd_batch_row *row = add_row(out, &cap);
    if (!row) {
      s = jnd_fail(JND_ERR_LIMIT, "%s: %s", name, jnd_last_error());
      break;
    }
    row->line = ++line;
    const char *v[3] = {"", "", ""};
    const cJSON *opt = NULL;
    if (!cJSON_IsObject(e)) {
      row_fail(row, name, WHERE_ENTRY, "not an object {\"id\", \"asset\", \"command\", \"options\"}");
    } else {
      const cJSON *m;
      cJSON_ArrayForEach(m, e) {
        int k = -1;
        for (int j = 0; j < 4; j++)
          if (m->string && strcmp(m->string, COLUMNS[j]) == 0) k = j;
        if (k < 0) {
          row_fail(row, name, WHERE_ENTRY, "unknown key '%.60s' (the keys are id, asset, command, options)",
                   m->string ? m->string : "");
        } else if (k == 3) {
          opt = m;
        } else if (!cJSON_IsString(m)) {
          row_fail(row, name, WHERE_ENTRY, "\"%s\" is not a string", COLUMNS[k]);
        } else {
          v[k] = m->valuestring;
        }
      }
    }
    row->id = sdup(v[0]);
    row->asset = sdup(v[1]);
    row->command = sdup(v[2]);
    if (opt && cJSON_IsArray(opt)) {
      /* a list of words: taken as they are, shown shell-quoted */
      int nw = cJSON_GetArraySize(opt), k = 0;
      row->argv = jnd_calloc((size_t)nw + 1, sizeof *row->argv);
      const cJSON *w;
      cJSON_ArrayForEach(w, opt) {
        if (!row->argv) break;
        if (!cJSON_IsString(w)) {
          row_fail(row, name, WHERE_ENTRY, "\"options\" holds a word that is not a string");
          break;
        }
        if (!(row->argv[k] = sdup(w->valuestring))) break;
        row->argc = ++k;
      }
      row->options = row->argv ? jnd_shell_join(row->argc, row->argv) : NULL;
    } else {
      if (opt && !cJSON_IsString(opt) && !cJSON_IsNull(opt))
        row_fail(row, name, WHERE_ENTRY, "\"options\" is neither a string nor a list of strings");
      row->options = sdup(cJSON_IsString(opt) ? opt->valuestring : "");
    }
    if (!row->id || !row->asset || !row->command || !row->options) {
      s = JND_ERR_NOMEM;
      break;
    }
  }
  cJSON_Delete(root);
  if (s == JND_OK && out->nrows == 0) s = jnd_fail(JND_ERR_FORMAT, "%s: no assets in the list", name);
  if (s == JND_OK) s = finish(out, name, WHERE_ENTRY);
  return s == JND_OK ? JND_OK : fail_free(out, s);
}

/* ---- glob ---- */

static int is_builtin(const char *asset) { return strcmp(asset, "builtin") == 0 || strncmp(asset, "builtin:", 8) == 0; }

/* the id of a match: its path less the folders every match shares and the
 * extension, '/' → '-', other characters outside the id alphabet → '_' */
static char *glob_id(const char *path, size_t shared) {
  const char *p = path + shared;
  char *id = sdup(p);
  if (!id) return NULL;
  char *slash = strrchr(id, '/'), *dot = strrchr(id, '.');
  if (dot && dot > id && (!slash || dot > slash + 1)) *dot = 0;
  for (char *c = id; *c; c++)
    if (*c == '/') *c = '-';
    else if (!isalnum((unsigned char)*c) && !strchr("._-", *c)) *c = '_';
  if (strlen(id) > JND_BATCH_MAX_ID) id[JND_BATCH_MAX_ID] = 0;
  return id;
}

static jnd_status manifest_glob(const char *pattern, const char *command, const char *options, jnd_batch_manifest *out) {
  glob_t g;
  int rc = glob(pattern, GLOB_ERR, NULL, &g);
  if (rc != 0) {
    if (rc != GLOB_NOMATCH) globfree(&g);
    return jnd_fail(JND_ERR_IO, "%s: %s", pattern, rc == GLOB_NOMATCH ? "no file matches" : "cannot be searched");
  }
  /* the folders every match shares */
  size_t shared = 0;
  if (g.gl_pathc > 0) {
    const char *a = g.gl_pathv[0];
    size_t common = strlen(a);
    for (size_t i = 1; i < g.gl_pathc; i++) {
      size_t k = 0;
      while (k < common && g.gl_pathv[i][k] == a[k]) k++;
      common = k;
    }
    for (size_t k = 0; k < common; k++)
      if (a[k] == '/') shared = k + 1;
    if (g.gl_pathc == 1) shared = strrchr(a, '/') ? (size_t)(strrchr(a, '/') - a) + 1 : 0;
  }
  int cap = 0;
  jnd_status s = JND_OK;
  for (size_t i = 0; i < g.gl_pathc && s == JND_OK; i++) {
    jnd_batch_row *row = add_row(out, &cap);
    if (!row) {
      s = JND_ERR_LIMIT;
      break;
    }
    row->line = (int)i + 1;
    row->asset = sdup(g.gl_pathv[i]);
    row->id = glob_id(g.gl_pathv[i], shared);
    row->command = sdup(command);
    row->options = sdup(options);
    if (!row->asset || !row->id || !row->command || !row->options) s = JND_ERR_NOMEM;
  }
  globfree(&g);
  if (s == JND_OK) s = finish(out, pattern, WHERE_MATCH);
  return s == JND_OK ? JND_OK : fail_free(out, s);
}

/* ---- reading ---- */

static int is_json_name(const char *path) {
  size_t n = strlen(path);
  return n >= 5 && strcasecmp(path + n - 5, ".json") == 0;
}

/* step 4 */
static void check_assets(jnd_batch_manifest *m, const char *name, where_kind k) {
  for (int i = 0; i < m->nrows; i++) {
    jnd_batch_row *r = &m->rows[i];
    if (r->error || is_builtin(r->asset)) continue;
    char *path = r->asset[0] == '/' ? sdup(r->asset) : jnd_path_join(m->base_dir, r->asset);
    struct stat st;
    const char *why = NULL;
    if (!path) why = "out of memory";
    else if (stat(path, &st) != 0) why = errno == ENOENT ? "no such file" : strerror(errno);
    else if (!S_ISREG(st.st_mode)) why = "not a file";
    if (why && k == WHERE_MATCH) row_fail(r, name, k, "%s", why);
    else if (why) row_fail(r, name, k, "%s: %s", r->asset, why);
    free(path);
  }
}

/* Rows name their manifest by its file name, not by the path it was given
 * as: a summary must not depend on the folder a run started in (a Slurm
 * task starts elsewhere than a run by hand). */
static const char *file_name(const char *path) {
  const char *slash = strrchr(path, '/');
  return slash ? slash + 1 : path;
}

void jnd_batch_manifest_check(jnd_batch_manifest *m) {
  check_assets(m, file_name(m->source), is_json_name(m->source) ? WHERE_ENTRY : WHERE_LINE);
}

static char *absolute(const char *path) {
  if (path[0] == '/') return sdup(path);
  char cwd[PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) {
    jnd_fail(JND_ERR_IO, "the working folder: %s", strerror(errno));
    return NULL;
  }
  return jnd_path_join(cwd, path);
}

jnd_status jnd_batch_manifest_read(const char *path, const char *command, const char *options,
                                   jnd_batch_manifest *out) {
  memset(out, 0, sizeof *out);
  jnd_status s;
  if (command) {
    s = manifest_glob(path, command, options ? options : "", out);
    if (s != JND_OK) return s;
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd)) return fail_free(out, jnd_fail(JND_ERR_IO, "the working folder: %s", strerror(errno)));
    out->base_dir = sdup(cwd);
  } else {
    unsigned char *buf;
    size_t n;
    s = jnd_read_file(path, MAX_MANIFEST_BYTES, &buf, &n);
    if (s != JND_OK) return s;
    s = is_json_name(path) ? jnd_batch_manifest_parse_json(file_name(path), (const char *)buf, n, out)
                           : jnd_batch_manifest_parse_csv(file_name(path), (const char *)buf, n, out);
    free(buf);
    if (s != JND_OK) return s;
  }
  out->source = absolute(path);
  if (!command && out->source) {
    out->base_dir = sdup(out->source);
    char *slash = out->base_dir ? strrchr(out->base_dir, '/') : NULL;
    if (slash) *(slash == out->base_dir ? slash + 1 : slash) = 0;
  }
  if (!out->source || !out->base_dir) return fail_free(out, JND_ERR_NOMEM);
  check_assets(out, command ? path : file_name(path), command ? WHERE_MATCH : is_json_name(path) ? WHERE_ENTRY : WHERE_LINE);
  return JND_OK;
}

jnd_status jnd_batch_shard_parse(const char *spec, int *index, int *count) {
  char *e1, *e2;
  errno = 0;
  long i = strtol(spec, &e1, 10);
  long n = *e1 == '/' ? strtol(e1 + 1, &e2, 10) : 0;
  if (*e1 != '/' || e1 == spec || *e2 || e2 == e1 + 1 || errno || i < 0 || n < 1 || n > 100000)
    return jnd_fail(JND_ERR_ARG, "shard '%s': expected I/N, 0 <= I < N <= 100000 (I counts from 0, as Slurm's "
                    "array task ids do)", spec);
  if (i >= n)
    return jnd_fail(JND_ERR_ARG, "shard '%s': index %ld is not below the count %ld (shards are 0..%ld)", spec, i, n, n - 1);
  *index = (int)i;
  *count = (int)n;
  return JND_OK;
}

/* ---- the plan: the rows as the run saw them, for merge ---- */

void jnd_batch_row_json(cJSON *o, const jnd_batch_row *r) {
  cJSON_AddStringToObject(o, "id", r->id);
  cJSON_AddNumberToObject(o, "line", r->line);
  cJSON_AddStringToObject(o, "asset", r->asset);
  cJSON_AddStringToObject(o, "command", r->command);
  cJSON_AddStringToObject(o, "options", r->options);
}

cJSON *jnd_batch_plan_json(const jnd_batch_manifest *m) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "source", m->source);
  cJSON_AddStringToObject(o, "base_dir", m->base_dir);
  cJSON *rows = cJSON_AddArrayToObject(o, "rows");
  for (int i = 0; i < m->nrows; i++) {
    const jnd_batch_row *r = &m->rows[i];
    cJSON *j = cJSON_CreateObject();
    jnd_batch_row_json(j, r);
    if (r->error) cJSON_AddStringToObject(j, "error", r->error);
    cJSON_AddItemToArray(rows, j);
  }
  return o;
}

static char *str_of(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsString(v) ? sdup(v->valuestring) : NULL;
}

jnd_status jnd_batch_plan_read(const char *out_dir, jnd_batch_manifest *m) {
  memset(m, 0, sizeof *m);
  char *path = jnd_path_join(out_dir, JND_BATCH_DIR "/manifest.json");
  if (!path) return JND_ERR_NOMEM;
  cJSON *doc = jnd_json_read(path);
  if (!doc) {
    jnd_status s = jnd_fail(JND_ERR_IO, "%s: no batch has run in this folder (%s)", out_dir, jnd_last_error());
    free(path);
    return s;
  }
  const cJSON *rows = cJSON_GetObjectItemCaseSensitive(doc, "rows");
  jnd_status s = JND_OK;
  m->source = str_of(doc, "source");
  m->base_dir = str_of(doc, "base_dir");
  if (!cJSON_IsArray(rows) || !m->source || !m->base_dir) s = jnd_fail(JND_ERR_FORMAT, "%s: not a batch plan", path);
  int cap = 0;
  const cJSON *e;
  cJSON_ArrayForEach(e, rows) {
    if (s != JND_OK) break;
    jnd_batch_row *r = add_row(m, &cap);
    if (!r) {
      s = JND_ERR_NOMEM;
      break;
    }
    const cJSON *line = cJSON_GetObjectItemCaseSensitive(e, "line");
    r->line = cJSON_IsNumber(line) ? line->valueint : 0;
    r->id = str_of(e, "id");
    r->asset = str_of(e, "asset");
    r->command = str_of(e, "command");
    r->options = str_of(e, "options");
    r->error = str_of(e, "error");
    if (!r->id || !r->asset || !r->command || !r->options) s = jnd_fail(JND_ERR_FORMAT, "%s: row %d is incomplete", path, m->nrows);
  }
  cJSON_Delete(doc);
  free(path);
  return s == JND_OK ? JND_OK : fail_free(m, s);
}
