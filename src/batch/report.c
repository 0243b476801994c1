/* The HTML report of a batch: static pages jnd writes itself, readable from
 * file:// with no network (no CDN, no framework; the little script it has is
 * inline).
 *   1. read OUT/summary.json (jnd batch merge)
 *   2. a page per asset, OUT/report/<id>.html: its row, the fields and
 *      tables the table of commands names in its JSON report, the pictures
 *      it wrote (referenced where they are, ../<id>/...), and the plots this
 *      report draws from its numbers (PNG files under OUT/report/<id>/); for a failure,
 *      the error and the end of its log
 *   3. the index, OUT/report/index.html: the totals and a table of every
 *      asset, sortable by any column and filterable by status; each number
 *      carries its exact value (data-value) beside the rounded text
 * Every file is written atomically. */
#include <dirent.h>
#include <fnmatch.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "batch/batch.h"
#include "core/core.h"

#define MAX_PICTURES 64
#define NELEM(a) ((int)(sizeof(a) / sizeof((a)[0])))

static const char STYLE[] =
    "body{font:15px/1.45 system-ui,-apple-system,'Segoe UI',sans-serif;margin:0 auto;max-width:1280px;"
    "padding:1em 2em;color:#222;background:#fafafa}"
    "h1{font-size:1.6em;margin:.4em 0}h2{font-size:1.2em;margin:1.4em 0 .5em}"
    "a{color:#0b5cad}table{border-collapse:collapse;background:#fff;margin:.5em 0}"
    "th,td{border:1px solid #ddd;padding:.3em .6em;text-align:left;vertical-align:top}"
    "th{background:#f0f0f0}td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}"
    "#assets th{cursor:pointer;user-select:none}#assets th[aria-sort=ascending]::after{content:' \\25B2'}"
    "#assets th[aria-sort=descending]::after{content:' \\25BC'}"
    ".status{font-weight:600;padding:.1em .5em;border-radius:.3em;white-space:nowrap}"
    ".ok{background:#d9f2dd;color:#14532d}.above{background:#fdf0c8;color:#6b4a00}"
    ".failed{background:#fbd9d9;color:#7f1d1d}.pending{background:#e5e7eb;color:#374151}"
    ".totals{display:flex;flex-wrap:wrap;gap:.8em;margin:.5em 0}"
    ".totals div{background:#fff;border:1px solid #ddd;border-radius:.4em;padding:.5em .9em}"
    ".totals b{display:block;font-size:1.3em}"
    "figure{margin:1em 0;background:#fff;border:1px solid #ddd;padding:.6em;display:inline-block;max-width:100%}"
    "figure img{max-width:100%;height:auto;display:block}figure.many img{display:inline-block;margin:0 .4em .4em 0;"
    "vertical-align:top}figcaption{font-size:.9em;color:#444;max-width:60em}"
    "pre{background:#fff;border:1px solid #ddd;padding:.6em;overflow:auto;white-space:pre-wrap}"
    "dl{display:grid;grid-template-columns:max-content auto;gap:.2em 1em}dt{color:#555}dd{margin:0}"
    "nav{margin:.5em 0}.controls{margin:1em 0}td.decision{max-width:32em}td.error{max-width:28em;color:#7f1d1d}";

/* sorting by a column (numbers by data-value, missing ones last) and
 * filtering by status; nothing else runs */
static const char SCRIPT[] =
    "(function(){var t=document.getElementById('assets'),b=t.tBodies[0],hs=t.tHead.rows[0].cells,"
    "f=document.getElementById('status-filter'),n=document.getElementById('shown');"
    "function key(r,i,num){var c=r.cells[i],v=c.getAttribute('data-value');"
    "if(num){return v===null||v===''?null:parseFloat(v);}return (v!==null?v:c.textContent).toLowerCase();}"
    "Array.prototype.forEach.call(hs,function(h,i){h.addEventListener('click',function(){"
    "var num=h.getAttribute('data-type')==='num',asc=h.getAttribute('aria-sort')!=='ascending';"
    "Array.prototype.forEach.call(hs,function(x){x.removeAttribute('aria-sort');});"
    "h.setAttribute('aria-sort',asc?'ascending':'descending');"
    "var rows=Array.prototype.slice.call(b.rows);rows.sort(function(p,q){var a=key(p,i,num),c=key(q,i,num);"
    "if(a===c)return 0;if(a===null)return 1;if(c===null)return -1;return (a<c?-1:1)*(asc?1:-1);});"
    "rows.forEach(function(r){b.appendChild(r);});});});"
    "function filter(){var s=f.value,k=0;Array.prototype.forEach.call(b.rows,function(r){"
    "var show=!s||r.getAttribute('data-status')===s;r.hidden=!show;if(show)k++;});n.textContent=k+' shown';}"
    "f.addEventListener('change',filter);filter();})();";

static void page_head(jnd_text *t, const char *title) {
  jnd_text_put(t, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                  "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>");
  jnd_text_html(t, title);
  jnd_text_printf(t, "</title>\n<style>%s</style>\n</head>\n<body>\n", STYLE);
}

/* a URL path segment: unreserved characters as they are, the rest %XX */
static void url(jnd_text *t, const char *s) {
  for (; *s; s++) {
    unsigned char c = (unsigned char)*s;
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || strchr("-._~/", c))
      jnd_text_putn(t, s, 1);
    else
      jnd_text_printf(t, "%%%02X", c);
  }
}

/* bytes in one unit everywhere jnd shows memory: MiB (2^20 bytes), with
 * four decimals under 0.01 MiB so that a small asset does not read 0.00 */
static void bytes_text(jnd_text *t, double v) {
  double x = v / 1048576.0;
  jnd_text_printf(t, fabs(x) >= 0.01 || x == 0 ? "%.2f MiB" : "%.4f MiB", x);
}

static void number_text(jnd_text *t, double v, jnd_batch_fmt fmt) {
  if (fmt == JND_FMT_P) jnd_text_printf(t, "%.3f", v);
  else if (fmt == JND_FMT_BYTES) bytes_text(t, v);
  else if (fmt == JND_FMT_PERCENT) jnd_text_printf(t, "%.1f%%", 100 * v);
  else jnd_text_printf(t, "%.4g", v);
}

/* a value of a command's report as text, in its format */
static void value_text(jnd_text *t, const cJSON *v, jnd_batch_fmt fmt) {
  if (!v || cJSON_IsNull(v)) {
    jnd_text_put(t, "—");
  } else if (cJSON_IsBool(v)) {
    jnd_text_put(t, cJSON_IsTrue(v) ? "yes" : "no");
  } else if (cJSON_IsNumber(v)) {
    number_text(t, v->valuedouble, fmt);
  } else if (cJSON_IsString(v)) {
    jnd_text_html(t, v->valuestring);
  } else if (cJSON_IsArray(v) && fmt == JND_FMT_SIZE && cJSON_GetArraySize(v) == 2) {
    jnd_text_printf(t, "%g×%g", cJSON_GetArrayItem(v, 0)->valuedouble, cJSON_GetArrayItem(v, 1)->valuedouble);
  } else if (cJSON_IsArray(v)) {
    int k = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, v) {
      if (k == 32) {
        jnd_text_put(t, ", …");
        break;
      }
      if (k++) jnd_text_put(t, ", ");
      if (cJSON_IsNumber(e)) jnd_text_printf(t, "%.3g", e->valuedouble);
      else value_text(t, e, JND_FMT_TEXT);
    }
  } else {
    jnd_text_put(t, "…");
  }
}

/* a picture's file: relative, inside the asset's folder, and there */
static int picture_ok(const char *dir, const char *name) {
  if (!name[0] || name[0] == '/' || strstr(name, "..") || strlen(name) > 512) return 0;
  char *path = jnd_path_join(dir, name);
  struct stat st;
  int ok = path && stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0;
  free(path);
  return ok;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* the names a picture entry stands for, in a stable order */
static int picture_names(const jnd_batch_picture *pic, const cJSON *rep, const char *dir, char **names, int max) {
  int n = 0;
  if (pic->file) {
    if (picture_ok(dir, pic->file) && (names[n] = strdup(pic->file))) n++;
  } else if (pic->path) {
    const cJSON *v[MAX_PICTURES];
    int k = jnd_json_select(rep, pic->path, v, MAX_PICTURES);
    for (int i = 0; i < k && i < MAX_PICTURES && n < max; i++)
      if (cJSON_IsString(v[i]) && picture_ok(dir, v[i]->valuestring) && (names[n] = strdup(v[i]->valuestring))) n++;
  } else if (pic->glob) {
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)) && n < max)
      if (fnmatch(pic->glob, e->d_name, 0) == 0 && picture_ok(dir, e->d_name) && (names[n] = strdup(e->d_name))) n++;
    if (d) closedir(d);
    qsort(names, (size_t)n, sizeof *names, cmp_str);
  }
  return n;
}

/* a figure of one or more pictures with one caption */
static void figure_img(jnd_text *t, const char *src, const char *alt) {
  jnd_text_put(t, "<img src=\"");
  url(t, src);
  jnd_text_put(t, "\" alt=\"");
  jnd_text_html(t, alt);
  jnd_text_put(t, "\">");
}

static void figure_end(jnd_text *t, const char *caption) {
  if (caption) {
    jnd_text_put(t, "<figcaption>");
    jnd_text_html(t, caption);
    jnd_text_put(t, "</figcaption>");
  }
  jnd_text_put(t, "</figure>\n");
}

static const char *str(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsString(v) ? v->valuestring : NULL;
}

static double num(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* the last lines of a failed asset's log */
static void log_tail(jnd_text *t, const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return;
  char buf[4096];
  fseek(f, 0, SEEK_END);
  long size = ftell(f);
  fseek(f, size > (long)sizeof buf - 1 ? size - (long)sizeof buf + 1 : 0, SEEK_SET);
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = 0;
  if (!n) return;
  jnd_text_put(t, "<h2>End of its log</h2>\n<pre>");
  jnd_text_html(t, buf);
  jnd_text_put(t, "</pre>\n");
}

static void dl_item(jnd_text *t, const char *term, const char *value) {
  if (!value || !value[0]) return;
  jnd_text_put(t, "<dt>");
  jnd_text_html(t, term);
  jnd_text_put(t, "</dt><dd>");
  jnd_text_html(t, value);
  jnd_text_put(t, "</dd>\n");
}

/* step 2: one asset's page; plots go to report/<id>/ */
static jnd_status asset_page(const char *out_dir, const char *report_dir, const cJSON *e, const char *prev,
                             const char *next) {
  const char *id = str(e, "id"), *status = str(e, "status"), *command = str(e, "command");
  if (!id || !status || !command) return jnd_fail(JND_ERR_FORMAT, "summary.json: an asset without id, status or command");
  const jnd_batch_command *cmd = jnd_batch_command_find(command);
  char *asset_dir = jnd_path_join(out_dir, id);
  char *plot_dir = jnd_path_join(report_dir, id);
  if (!asset_dir || !plot_dir) {
    free(asset_dir), free(plot_dir);
    return JND_ERR_NOMEM;
  }
  cJSON *rep = NULL, *rec = NULL;
  if (cmd && str(e, "report")) {
    char *p = jnd_path_join(out_dir, str(e, "report"));
    rep = p ? jnd_json_read(p) : NULL;
    free(p);
  }
  {
    char name[JND_BATCH_MAX_ID + 32];
    snprintf(name, sizeof name, JND_BATCH_DIR "/records/%s.json", id);
    char *p = jnd_path_join(out_dir, name);
    rec = p ? jnd_json_read(p) : NULL;
    free(p);
  }
  jnd_text t = {0};
  page_head(&t, id);
  jnd_text_put(&t, "<nav><a href=\"index.html\">all assets</a>");
  if (prev) {
    jnd_text_put(&t, " · <a href=\"");
    url(&t, prev);
    jnd_text_put(&t, ".html\">previous</a>");
  }
  if (next) {
    jnd_text_put(&t, " · <a href=\"");
    url(&t, next);
    jnd_text_put(&t, ".html\">next</a>");
  }
  jnd_text_put(&t, "</nav>\n<h1>");
  jnd_text_html(&t, id);
  jnd_text_printf(&t, " <span class=\"status %s\">%s</span></h1>\n<dl>\n", status, status);
  dl_item(&t, "asset", str(e, "asset"));
  dl_item(&t, "command", command);
  dl_item(&t, "options", str(e, "options"));
  dl_item(&t, "decision", str(e, "decision"));
  dl_item(&t, "error", str(e, "error"));
  if (rec) dl_item(&t, "command line", str(rec, "command_line"));
  char buf[64];
  double code = num(e, "exit_status"), secs = num(e, "seconds");
  if (isfinite(code)) {
    snprintf(buf, sizeof buf, "%.0f", code);
    dl_item(&t, "exit status", buf);
  }
  if (isfinite(secs)) {
    snprintf(buf, sizeof buf, "%.1f s", secs);
    dl_item(&t, "time", buf);
  }
  jnd_text_put(&t, "</dl>\n");
  if (rep) {
    jnd_text_put(&t, "<p>Its outputs: <a href=\"../");
    url(&t, id);
    jnd_text_put(&t, "/\">");
    jnd_text_html(&t, id);
    jnd_text_put(&t, "/</a>, its report <a href=\"../");
    url(&t, str(e, "report"));
    jnd_text_put(&t, "\">");
    jnd_text_html(&t, cmd->json_name);
    jnd_text_put(&t, "</a>.</p>\n");
  }
  jnd_status s = JND_OK;
  if (rep) {
    /* the numbers */
    int any = 0;
    for (int i = 0; i < NELEM(cmd->fields) && cmd->fields[i].label; i++) {
      const cJSON *v[1];
      if (jnd_json_select(rep, cmd->fields[i].path, v, 1) != 1) continue;
      if (!any++) jnd_text_put(&t, "<h2>Numbers</h2>\n<table class=\"fields\">\n");
      jnd_text_put(&t, "<tr><th>");
      jnd_text_html(&t, cmd->fields[i].label);
      jnd_text_put(&t, "</th><td>");
      value_text(&t, v[0], cmd->fields[i].fmt);
      jnd_text_put(&t, "</td></tr>\n");
    }
    if (any) jnd_text_put(&t, "</table>\n");
    for (int k = 0; k < NELEM(cmd->tables) && cmd->tables[k].title; k++) {
      const jnd_batch_table *tb = &cmd->tables[k];
      const cJSON *rows[256];
      int nr = jnd_json_select(rep, tb->rows, rows, 256);
      if (nr < 1) continue;
      jnd_text_put(&t, "<h2>");
      jnd_text_html(&t, tb->title);
      jnd_text_put(&t, "</h2>\n<table>\n<tr>");
      for (int c = 0; c < NELEM(tb->cols) && tb->cols[c].label; c++) {
        jnd_text_put(&t, "<th>");
        jnd_text_html(&t, tb->cols[c].label);
        jnd_text_put(&t, "</th>");
      }
      jnd_text_put(&t, "</tr>\n");
      for (int r = 0; r < nr && r < 256; r++) {
        jnd_text_put(&t, "<tr>");
        for (int c = 0; c < NELEM(tb->cols) && tb->cols[c].label; c++) {
          const cJSON *v[1];
          int has = jnd_json_select(rows[r], tb->cols[c].path, v, 1) == 1;
          jnd_text_put(&t, has && cJSON_IsNumber(v[0]) ? "<td class=\"num\">" : "<td>");
          value_text(&t, has ? v[0] : NULL, tb->cols[c].fmt);
          jnd_text_put(&t, "</td>");
        }
        jnd_text_put(&t, "</tr>\n");
      }
      jnd_text_put(&t, "</table>\n");
    }
    /* the pictures it wrote, then the ones drawn here */
    int heading = 0;
    for (int k = 0; k < NELEM(cmd->pictures) && (cmd->pictures[k].file || cmd->pictures[k].path || cmd->pictures[k].glob); k++) {
      char *names[MAX_PICTURES];
      int n = picture_names(&cmd->pictures[k], rep, asset_dir, names, MAX_PICTURES);
      if (n && !heading++) jnd_text_put(&t, "<h2>Pictures</h2>\n");
      if (n) jnd_text_put(&t, n > 1 ? "<figure class=\"many\">" : "<figure>");
      for (int i = 0; i < n; i++) {
        jnd_text src = {0};
        jnd_text_printf(&src, "../%s/%s", id, names[i]);
        char *sp = jnd_text_take(&src);
        if (sp) figure_img(&t, sp, names[i]);
        free(sp);
        free(names[i]);
      }
      if (n) figure_end(&t, cmd->pictures[k].caption);
    }
    for (int k = 0; k < NELEM(cmd->plots) && cmd->plots[k].name && s == JND_OK; k++) {
      if ((s = jnd_mkdirs(plot_dir)) != JND_OK) break;
      char *p = jnd_path_join(plot_dir, cmd->plots[k].name);
      int r = p ? cmd->plots[k].draw(rep, p) : -1;
      free(p);
      if (r < 0) {
        s = jnd_fail(JND_ERR_IO, "report of %s: %s", id, jnd_last_error());
        break;
      }
      if (r == 0) continue;
      if (!heading++) jnd_text_put(&t, "<h2>Pictures</h2>\n");
      jnd_text src = {0};
      jnd_text_printf(&src, "%s/%s", id, cmd->plots[k].name);
      char *sp = jnd_text_take(&src);
      jnd_text_put(&t, "<figure>");
      if (sp) figure_img(&t, sp, cmd->plots[k].name);
      figure_end(&t, cmd->plots[k].caption);
      free(sp);
    }
  } else if (strcmp(status, "failed") == 0 && rec && str(rec, "log")) {
    char *p = jnd_path_join(out_dir, str(rec, "log"));
    if (p) log_tail(&t, p);
    free(p);
  }
  jnd_text_put(&t, "</body>\n</html>\n");
  char name[JND_BATCH_MAX_ID + 8];
  snprintf(name, sizeof name, "%s.html", id);
  char *path = jnd_path_join(report_dir, name);
  char *html = jnd_text_take(&t);
  if (s == JND_OK) s = path && html ? jnd_write_file_atomic(path, html, strlen(html)) : JND_ERR_NOMEM;
  free(path), free(html), free(asset_dir), free(plot_dir);
  cJSON_Delete(rep);
  cJSON_Delete(rec);
  return s;
}

/* a cell of the index: the rounded text, the exact value in data-value */
static void num_cell(jnd_text *t, const cJSON *e, const char *key, jnd_batch_fmt fmt) {
  double v = num(e, key);
  if (!isfinite(v)) {
    jnd_text_put(t, "<td class=\"num\" data-value=\"\">—</td>");
    return;
  }
  jnd_text_printf(t, "<td class=\"num\" data-value=\"%.17g\"", v);
  if (fmt == JND_FMT_BYTES) jnd_text_printf(t, " title=\"%.0f bytes\"", v);
  jnd_text_put(t, ">");
  if (fmt == JND_FMT_NUMBER) jnd_text_printf(t, "%.1f", v);
  else number_text(t, v, fmt);
  jnd_text_put(t, "</td>");
}

static void total(jnd_text *t, const char *id, const char *label, const cJSON *tot, const char *key, jnd_batch_fmt fmt) {
  double v = num(tot, key);
  jnd_text_printf(t, "<div id=\"total-%s\"", id);
  if (isfinite(v)) jnd_text_printf(t, " data-value=\"%.17g\"", v);
  jnd_text_put(t, "><b>");
  if (!isfinite(v)) jnd_text_put(t, "—");
  else if (fmt == JND_FMT_TEXT) jnd_text_printf(t, "%.0f", v);
  else number_text(t, v, fmt);
  jnd_text_printf(t, "</b>%s</div>\n", label);
}

/* step 3 */
static char *index_page(const cJSON *doc, const cJSON *assets) {
  const cJSON *res = cJSON_GetObjectItemCaseSensitive(doc, "result");
  const cJSON *tot = cJSON_GetObjectItemCaseSensitive(res, "totals");
  const cJSON *in = cJSON_GetObjectItemCaseSensitive(doc, "inputs");
  int timings = cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(tot, "seconds"));
  jnd_text t = {0};
  page_head(&t, "jnd batch report");
  jnd_text_put(&t, "<h1>jnd batch report</h1>\n<p>Manifest <code>");
  jnd_text_html(&t, str(in, "manifest") ? str(in, "manifest") : "?");
  jnd_text_put(&t, "</code>, merged by jnd ");
  jnd_text_html(&t, str(doc, "jnd_version") ? str(doc, "jnd_version") : "?");
  jnd_text_put(&t, " (<a href=\"../summary.json\">summary.json</a>, <a href=\"../summary.csv\">summary.csv</a>).</p>\n"
                   "<div class=\"totals\">\n");
  total(&t, "assets", "assets", tot, "assets", JND_FMT_TEXT);
  total(&t, "ok", "ok", tot, "ok", JND_FMT_TEXT);
  total(&t, "above", "above the criterion", tot, "above", JND_FMT_TEXT);
  total(&t, "failed", "failed", tot, "failed", JND_FMT_TEXT);
  total(&t, "pending", "pending", tot, "pending", JND_FMT_TEXT);
  total(&t, "memory_before_bytes", "memory before", tot, "memory_before_bytes", JND_FMT_BYTES);
  total(&t, "memory_after_bytes", "memory after", tot, "memory_after_bytes", JND_FMT_BYTES);
  total(&t, "reduction", "smaller", tot, "reduction", JND_FMT_PERCENT);
  if (timings) total(&t, "seconds", "seconds of work", tot, "seconds", JND_FMT_NUMBER);
  jnd_text_put(&t, "</div>\n<p>Memory counts the assets that report it (texres: maps as RGBA8 with mip chains; "
                   "pca: maps as 8-bit files against the stored components). Click a column to sort.</p>\n"
                   "<div class=\"controls\"><label>Status <select id=\"status-filter\"><option value=\"\">all</option>"
                   "<option>ok</option><option>above</option><option>failed</option><option>pending</option>"
                   "</select></label> <span id=\"shown\"></span></div>\n"
                   "<table id=\"assets\">\n<thead><tr><th data-key=\"id\">id</th><th data-key=\"command\">command</th>"
                   "<th data-key=\"status\">status</th>"
                   "<th data-key=\"p_detect\" data-type=\"num\">P(detect)</th>"
                   "<th data-key=\"memory_before_bytes\" data-type=\"num\">memory before</th>"
                   "<th data-key=\"memory_after_bytes\" data-type=\"num\">memory after</th>"
                   "<th data-key=\"reduction\" data-type=\"num\">smaller</th>"
                   "<th data-key=\"decision\">decision</th>");
  if (timings) jnd_text_put(&t, "<th data-key=\"seconds\" data-type=\"num\">seconds</th>");
  jnd_text_put(&t, "<th data-key=\"error\">error</th></tr></thead>\n<tbody>\n");
  const cJSON *e;
  cJSON_ArrayForEach(e, assets) {
    const char *id = str(e, "id"), *status = str(e, "status");
    if (!id || !status) continue;
    jnd_text_printf(&t, "<tr data-status=\"%s\" data-id=\"", status);
    jnd_text_html(&t, id);
    jnd_text_put(&t, "\"><td><a href=\"");
    url(&t, id);
    jnd_text_put(&t, ".html\">");
    jnd_text_html(&t, id);
    jnd_text_put(&t, "</a></td><td>");
    jnd_text_html(&t, str(e, "command") ? str(e, "command") : "");
    jnd_text_printf(&t, "</td><td data-value=\"%s\"><span class=\"status %s\">%s</span></td>", status, status, status);
    num_cell(&t, e, "p_detect", JND_FMT_P);
    num_cell(&t, e, "memory_before_bytes", JND_FMT_BYTES);
    num_cell(&t, e, "memory_after_bytes", JND_FMT_BYTES);
    num_cell(&t, e, "reduction", JND_FMT_PERCENT);
    jnd_text_put(&t, "<td class=\"decision\">");
    jnd_text_html(&t, str(e, "decision") ? str(e, "decision") : "");
    jnd_text_put(&t, "</td>");
    if (timings) num_cell(&t, e, "seconds", JND_FMT_NUMBER);
    jnd_text_put(&t, "<td class=\"error\">");
    jnd_text_html(&t, str(e, "error") ? str(e, "error") : "");
    jnd_text_put(&t, "</td></tr>\n");
  }
  jnd_text_printf(&t, "</tbody>\n</table>\n<script>%s</script>\n</body>\n</html>\n", SCRIPT);
  return jnd_text_take(&t);
}

jnd_status jnd_batch_report(const char *out_dir, char *index_path, size_t n) {
  char *sum_path = jnd_path_join(out_dir, "summary.json");
  cJSON *doc = sum_path ? jnd_json_read(sum_path) : NULL;
  if (!doc) {
    jnd_status s = jnd_fail(JND_ERR_IO, "%s: %s (jnd batch merge %s writes it)", sum_path ? sum_path : out_dir,
                            jnd_last_error(), out_dir);
    free(sum_path);
    return s;
  }
  free(sum_path);
  const cJSON *assets = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(doc, "result"), "assets");
  jnd_status s = cJSON_IsArray(assets) ? JND_OK : jnd_fail(JND_ERR_FORMAT, "%s/summary.json: no result.assets", out_dir);
  /* through the output writer: the reports read are inputs (an asset whose
   * id is "report" would have its folder replaced), OUT/report is staged
   * and published whole at the end */
  char *final_dir = jnd_path_join(out_dir, "report"), *sum = jnd_path_join(out_dir, "summary.json");
  jnd_output *w = NULL;
  const char *report_dir = NULL;
  if (s == JND_OK) s = final_dir && sum ? jnd_output_open(&w) : JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_output_add_input(w, sum);
  const cJSON *e, *prev = NULL;
  cJSON_ArrayForEach(e, assets) {
    if (s != JND_OK || !str(e, "report")) continue;
    char *p = jnd_path_join(out_dir, str(e, "report"));
    s = p ? jnd_output_add_input(w, p) : JND_ERR_NOMEM;
    free(p);
  }
  if (s == JND_OK) s = jnd_output_add_dir(w, final_dir, &report_dir);
  cJSON_ArrayForEach(e, assets) {
    if (s != JND_OK) break;
    s = asset_page(out_dir, report_dir, e, prev ? str(prev, "id") : NULL, e->next ? str(e->next, "id") : NULL);
    prev = e;
  }
  char *html = s == JND_OK ? index_page(doc, assets) : NULL;
  char *path = report_dir ? jnd_path_join(report_dir, "index.html") : NULL;
  if (s == JND_OK) s = html && path ? jnd_write_file_atomic(path, html, strlen(html)) : JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_output_commit(w);
  jnd_output_free(w);
  if (s == JND_OK && index_path && n) snprintf(index_path, n, "%s/index.html", final_dir);
  free(html), free(path), free(final_dir), free(sum);
  cJSON_Delete(doc);
  return s;
}
