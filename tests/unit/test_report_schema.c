/* The schema of the task reports (src/tasks/report_schema.h): each task's
 * run writes every field the schema lists, of the kind it says, and batch
 * reads no path the schema does not list. A writer that renames a field, or
 * a batch entry that names one spelt otherwise, fails here. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "batch/batch.h"
#include "tasks/report_schema.h"
#include "test.h"
#include "task_params.h"

static int kind_is(const cJSON *v, report_kind k) {
  switch (k) {
    case RS_NUMBER: return cJSON_IsNumber(v);
    case RS_NUMBER_OR_NULL: return cJSON_IsNumber(v) || cJSON_IsNull(v);
    case RS_TEXT: return cJSON_IsString(v);
    case RS_BOOL: return cJSON_IsBool(v);
    case RS_LIST: return cJSON_IsArray(v);
    case RS_OBJECT: return cJSON_IsObject(v);
  }
  return 0;
}

/* Every field of task's schema in the report's text: present when it has
 * no condition or one of the conditions that hold for this run (NULL-ended
 * RS_WHEN_* list), and of its kind wherever present. */
static void reads_through_the_schema(const char *task, const char *text, const char *const *hold) {
  cJSON *doc = cJSON_Parse(text);
  CHECK(doc != NULL);
  int n = 0;
  const report_field *f = report_schema(task, &n);
  CHECK(f != NULL && n > 0);
  for (int i = 0; doc && f && i < n; i++) {
    int needed = !f[i].when;
    for (int h = 0; hold && hold[h]; h++) needed |= f[i].when && strcmp(f[i].when, hold[h]) == 0;
    const cJSON *v[256];
    int k = jnd_json_select(doc, f[i].path, v, 256);
    if (needed && k == 0) fprintf(stderr, "%s: %s is missing\n", task, f[i].path);
    CHECK(!needed || k > 0);
    for (int j = 0; j < k && j < 256; j++) {
      if (!kind_is(v[j], f[i].kind)) fprintf(stderr, "%s: %s is not of its kind\n", task, f[i].path);
      CHECK(kind_is(v[j], f[i].kind));
    }
  }
  cJSON_Delete(doc);
}

static int in_schema(const char *task, const char *path) {
  int n = 0;
  const report_field *f = report_schema(task, &n);
  if (path && strncmp(path, "max:", 4) == 0) path += 4;
  for (int i = 0; f && i < n; i++)
    if (strcmp(f[i].path, path) == 0) return 1;
  fprintf(stderr, "batch's %s entry reads '%s', which the schema does not list\n", task, path);
  return 0;
}

TEST(batch_reads_only_fields_the_schema_lists) {
  static const char *tasks[] = {"texres", "pca", "diff", "render", "lod", "gaze", "pop"};
  for (int t = 0; t < 7; t++) {
    const jnd_batch_command *c = jnd_batch_command_find(tasks[t]);
    CHECK(c != NULL);
    if (!c) continue;
    const char *top[] = {c->memory_before, c->memory_after, c->p_detect};
    for (int i = 0; i < 3; i++)
      if (top[i]) CHECK(in_schema(c->name, top[i]));
    for (int i = 0; i < 16 && c->fields[i].label; i++) CHECK(in_schema(c->name, c->fields[i].path));
    for (int i = 0; i < 3 && c->tables[i].title; i++) {
      CHECK(in_schema(c->name, c->tables[i].rows));
      for (int j = 0; j < 10 && c->tables[i].cols[j].label; j++) {
        char full[512];
        snprintf(full, sizeof full, "%s.%s", c->tables[i].rows, c->tables[i].cols[j].path);
        CHECK(in_schema(c->name, full));
      }
    }
    for (int i = 0; i < 8; i++)
      if (c->pictures[i].path) CHECK(in_schema(c->name, c->pictures[i].path));
  }
  int n = 0;
  CHECK(report_schema("no such task", &n) == NULL && n == 0);
}

static const char *out_dir(const char *name) {
  static char path[1200];
  snprintf(path, sizeof path, "%s/report_schema_%s", test_tmp_dir(), name);
  jnd_remove_tree(path);
  return path;
}

TEST(a_diff_report_has_every_field_of_the_schema) {
  jnd_image ref, test;
  CHECK_OK(jnd_example_pair(96, 64, &ref, &test));
  char rp[1200], tp[1200];
  snprintf(rp, sizeof rp, "%s/report_schema_ref.png", test_tmp_dir());
  snprintf(tp, sizeof tp, "%s/report_schema_test.png", test_tmp_dir());
  CHECK_OK(jnd_image_write_png(rp, &ref, 8));
  CHECK_OK(jnd_image_write_png(tp, &test, 8));
  jnd_image_free(&ref);
  jnd_image_free(&test);
  jnd_diff_params p;
  jnd_diff_defaults(&p);
  jnd_diff_result *r = NULL;
  CHECK_OK(jnd_diff_run(rp, tp, &p, &r));
  if (r) reads_through_the_schema("diff", r->report, NULL);
  jnd_diff_result_free(r);
}

TEST(every_rendering_task_report_has_every_field_of_the_schema) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  {
    jnd_texres_params p;
    jnd_texres_defaults(&p);
    p.judge.views.sampling.count = 2;
    p.judge.views.render.width = p.judge.views.render.height = 96;
    p.judge.views.render.samples = 1;
    p.run.map_size = 128;
    p.confirm_rounds = 0;
    p.min_size = 16;
    p.verify_views = 1;
    jnd_texres_result *r = NULL;
    CHECK_OK(jnd_texres_run("builtin", &p, out_dir("texres"), &r));
    static const char *const hold[] = {RS_WHEN_VERIFY, NULL};
    if (r) reads_through_the_schema("texres", r->report, hold);
    jnd_texres_result_free(r);
  }
  {
    jnd_pca_params p;
    jnd_pca_defaults(&p);
    p.material = "builtin";
    p.render.builtin_map_size = p.run.map_size = 64;
    p.render.judge.views.sampling.count = 1;
    p.render.judge.views.render.width = p.render.judge.views.render.height = 64;
    jnd_pca_result *r = NULL;
    CHECK_OK(jnd_pca_run("builtin", &p, out_dir("pca"), &r));
    static const char *const hold[] = {RS_WHEN_RENDERED, RS_WHEN_BC, NULL};
    if (r) reads_through_the_schema("pca", r->report, hold);
    jnd_pca_result_free(r);
  }
  {
    jnd_render_params p;
    jnd_render_defaults(&p);
    p.views.sampling.count = 1;
    p.views.render.width = 64;
    p.views.render.height = 48;
    p.run.map_size = 64;
    jnd_render_result *r = NULL;
    CHECK_OK(jnd_render_run("builtin:sphere", &p, out_dir("render"), &r));
    static const char *const hold[] = {RS_WHEN_COLOR, NULL};
    if (r) reads_through_the_schema("render", r->report, hold);
    jnd_render_result_free(r);
  }
  {
    jnd_lod_run_params p;
    jnd_poi_screen screen;
    CHECK_OK(task_lod_params(&p, &screen));   /* task_runs.c's lod */
    jnd_lod_result *r = NULL;
    CHECK_OK(jnd_lod_run("builtin:sphere", &p, out_dir("lod"), &r));
    static const char *const hold[] = {RS_WHEN_PERCEPTUAL, NULL};
    if (r) reads_through_the_schema("lod", r->report, hold);
    jnd_lod_result_free(r);
  }
  {
    jnd_gaze_run_params p;
    jnd_gaze_run_defaults(&p);
    static const double dist[] = {20, 80}, ecc[] = {0, 30};
    p.run.map_size = 32;
    p.table.orientations = 1;
    p.table.distances_m = dist;
    p.table.ndistances = 2;
    p.table.eccentricities_deg = ecc;
    p.table.neccentricities = 2;
    p.table.min_px = 48;
    p.table.max_px = 64;
    jnd_gaze_run_result *r = NULL;
    CHECK_OK(jnd_gaze_run("builtin:sphere", &p, out_dir("gaze"), &r));
    if (r) reads_through_the_schema("gaze", r->report, NULL);
    jnd_gaze_run_result_free(r);
  }
  {
    jnd_pop_run_params p;
    jnd_pop_run_defaults(&p);
    static const double errors[] = {0.1}, speeds[] = {0};
    p.asset.views.render.width = p.asset.views.render.height = 64;
    p.asset.views.sampling.count = 1;
    p.asset.builtin_map_size = 64;
    p.asset.chain.errors = errors;
    p.asset.chain.nerrors = 1;
    p.asset.decide = 1;
    p.asset.speeds = speeds;
    p.asset.nspeeds = 1;
    p.asset.search.tolerance = 0.3;
    jnd_pop_run_result *r = NULL;
    CHECK_OK(jnd_pop_run("builtin:sphere", &p, out_dir("pop"), &r));
    static const char *const hold[] = {RS_WHEN_ASSET, RS_WHEN_DECIDE, NULL};
    if (r) reads_through_the_schema("pop", r->report, hold);
    jnd_pop_run_result_free(r);
  }
}

RUN_TESTS(batch_reads_only_fields_the_schema_lists, a_diff_report_has_every_field_of_the_schema,
          every_rendering_task_report_has_every_field_of_the_schema)
