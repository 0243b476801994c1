/* Merge: what every shard recorded in OUT, as one summary in manifest order.
 *   1. read the plan (the manifest's rows as the runs saw them)
 *   2. per row: its error, or its record (none: pending; a record of other
 *      options: pending too), and for a result the numbers of the command's
 *      report through the table of commands (commands.c)
 *   3. totals, then summary.json and summary.csv, each written atomically
 * Nothing here depends on which shard ran what or when, so n shards give
 * the bytes of a single run (timings, when asked for, aside). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "batch/batch.h"
#include "tasks/report.h"
#include "core/core.h"

static cJSON *number_or_null(double v) { return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull(); }

static cJSON *read_record(const char *out_dir, const char *id) {
  char name[JND_BATCH_MAX_ID + 32];
  snprintf(name, sizeof name, JND_BATCH_DIR "/records/%s.json", id);
  char *path = jnd_path_join(out_dir, name);
  cJSON *doc = path ? jnd_json_read(path) : NULL;
  free(path);
  return doc;
}

static const char *str(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsString(v) ? v->valuestring : NULL;
}

static int same(const char *a, const char *b) { return a && b && strcmp(a, b) == 0; }

/* step 2: one row's entry */
static cJSON *entry(const char *out_dir, const jnd_batch_row *r, int timings) {
  cJSON *e = cJSON_CreateObject();
  jnd_batch_row_json(e, r);
  jnd_asset_status st = JND_ASSET_PENDING;
  double code = NAN, before = NAN, after = NAN, p = NAN, seconds = NAN;
  jnd_text error = {0}, decision = {0};
  cJSON *chosen = cJSON_CreateObject();
  const jnd_batch_command *cmd = jnd_batch_command_find(r->command);
  cJSON *rec = r->error || !cmd ? NULL : read_record(out_dir, r->id);
  if (r->error) {
    st = JND_ASSET_FAILED;
    jnd_text_put(&error, r->error);
  } else if (rec && same(str(rec, "command"), r->command) && same(str(rec, "asset"), r->asset) &&
             same(str(rec, "options"), r->options) && jnd_asset_status_parse(str(rec, "status"), &st)) {
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(rec, "exit_status");
    code = cJSON_IsNumber(x) ? x->valuedouble : NAN;
    x = cJSON_GetObjectItemCaseSensitive(rec, "seconds");
    seconds = cJSON_IsNumber(x) ? x->valuedouble : NAN;
    if (st == JND_ASSET_FAILED && str(rec, "error")) jnd_text_put(&error, str(rec, "error"));
    if (st == JND_ASSET_OK || st == JND_ASSET_ABOVE) {
      char rel[JND_BATCH_MAX_ID + 64];
      snprintf(rel, sizeof rel, "%s/%s", r->id, cmd->json_name);
      char *path = jnd_path_join(out_dir, rel);
      cJSON *rep = path ? jnd_json_read(path) : NULL;
      free(path);
      if (!rep) {
        st = JND_ASSET_FAILED;
        jnd_text_printf(&error, "%s is missing or unreadable (removed after the run?)", rel);
      } else {
        before = jnd_json_number(rep, cmd->memory_before);
        after = jnd_json_number(rep, cmd->memory_after);
        p = jnd_json_number(rep, cmd->p_detect);
        if (cmd->decision) cmd->decision(rep, &decision, chosen);
        cJSON_AddStringToObject(e, "report", rel);
      }
      cJSON_Delete(rep);
    }
  }
  cJSON_Delete(rec);
  cJSON_AddStringToObject(e, "status", jnd_asset_status_name(st));
  cJSON_AddItemToObject(e, "exit_status", number_or_null(code));
  char *err = jnd_text_take(&error), *dec = jnd_text_take(&decision);
  if (err && err[0]) cJSON_AddStringToObject(e, "error", err);
  else cJSON_AddNullToObject(e, "error");
  cJSON_AddItemToObject(e, "memory_before_bytes", number_or_null(before));
  cJSON_AddItemToObject(e, "memory_after_bytes", number_or_null(after));
  cJSON_AddItemToObject(e, "reduction", number_or_null(before > 0 && isfinite(after) ? 1 - after / before : NAN));
  cJSON_AddItemToObject(e, "p_detect", number_or_null(p));
  cJSON_AddStringToObject(e, "decision", dec ? dec : "");
  cJSON_AddItemToObject(e, "chosen", chosen);
  if (timings) cJSON_AddItemToObject(e, "seconds", number_or_null(seconds));
  free(err);
  free(dec);
  return e;
}

static double num(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static void csv_number(jnd_text *t, double v) {
  if (!isfinite(v)) return;
  if (v == floor(v) && fabs(v) < 1e15) jnd_text_printf(t, "%.0f", v);
  else jnd_text_printf(t, "%.10g", v);
}

static const char *const CSV_COLUMNS[] = {"id", "line", "asset", "command", "options", "status", "exit_status",
                                          "error", "memory_before_bytes", "memory_after_bytes", "reduction",
                                          "p_detect", "decision", "seconds"};

static char *summary_csv(const cJSON *assets, int timings) {
  jnd_text t = {0};
  int ncol = (int)(sizeof CSV_COLUMNS / sizeof CSV_COLUMNS[0]) - (timings ? 0 : 1);
  for (int c = 0; c < ncol; c++) jnd_text_printf(&t, "%s%s", c ? "," : "", CSV_COLUMNS[c]);
  jnd_text_put(&t, "\n");
  const cJSON *e;
  cJSON_ArrayForEach(e, assets) {
    for (int c = 0; c < ncol; c++) {
      if (c) jnd_text_put(&t, ",");
      const cJSON *v = cJSON_GetObjectItemCaseSensitive(e, CSV_COLUMNS[c]);
      if (cJSON_IsString(v)) jnd_text_csv(&t, v->valuestring);
      else if (cJSON_IsNumber(v)) csv_number(&t, v->valuedouble);
    }
    jnd_text_put(&t, "\n");
  }
  return jnd_text_take(&t);
}

jnd_status jnd_batch_merge(const char *out_dir, int timings, jnd_batch_totals *totals) {
  jnd_batch_totals local;
  if (!totals) totals = &local;
  memset(totals, 0, sizeof *totals);
  jnd_batch_manifest m;
  jnd_status s = jnd_batch_plan_read(out_dir, &m);
  if (s != JND_OK) return s;
  cJSON *doc = report_new("batch merge");
  cJSON_AddStringToObject(report_section(doc, "inputs"), "manifest", m.source);
  cJSON *par = report_section(doc, "parameters");
  cJSON_AddBoolToObject(par, "timings", timings != 0);
  cJSON *res = report_section(doc, "result");
  cJSON *tot = cJSON_AddObjectToObject(res, "totals");
  cJSON *assets = cJSON_AddArrayToObject(res, "assets");
  double before = 0, after = 0, seconds = 0;
  int with_memory = 0;
  for (int i = 0; i < m.nrows; i++) {
    cJSON *e = entry(out_dir, &m.rows[i], timings);
    cJSON_AddItemToArray(assets, e);
    jnd_asset_status st = JND_ASSET_PENDING;
    jnd_asset_status_parse(str(e, "status"), &st);
    totals->assets++;
    if (st == JND_ASSET_OK) totals->ok++;
    else if (st == JND_ASSET_ABOVE) totals->above++;
    else if (st == JND_ASSET_FAILED) totals->failed++;
    else totals->pending++;
    double b = num(e, "memory_before_bytes"), a = num(e, "memory_after_bytes");
    if (isfinite(b) && isfinite(a)) {
      before += b;
      after += a;
      with_memory++;
    }
    if (isfinite(num(e, "seconds"))) seconds += num(e, "seconds");
  }
  cJSON_AddNumberToObject(tot, "assets", totals->assets);
  cJSON_AddNumberToObject(tot, "ok", totals->ok);
  cJSON_AddNumberToObject(tot, "above", totals->above);
  cJSON_AddNumberToObject(tot, "failed", totals->failed);
  cJSON_AddNumberToObject(tot, "pending", totals->pending);
  cJSON_AddNumberToObject(tot, "with_memory", with_memory);
  cJSON_AddNumberToObject(tot, "memory_before_bytes", before);
  cJSON_AddNumberToObject(tot, "memory_after_bytes", after);
  cJSON_AddItemToObject(tot, "reduction", number_or_null(before > 0 ? 1 - after / before : NAN));
  if (timings) cJSON_AddNumberToObject(tot, "seconds", round(seconds * 1000) / 1000);
  char *json_path = jnd_path_join(out_dir, "summary.json"), *csv_path = jnd_path_join(out_dir, "summary.csv");
  char *csv = summary_csv(assets, timings);
  if (!json_path || !csv_path || !csv) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_json_write(json_path, doc);
  if (s == JND_OK) s = jnd_write_file_atomic(csv_path, csv, strlen(csv));
  free(json_path);
  free(csv_path);
  free(csv);
  cJSON_Delete(doc);
  jnd_batch_manifest_free(&m);
  return s;
}
