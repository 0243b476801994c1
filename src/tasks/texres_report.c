/* `jnd texres`'s report (docs/texres.md "The report"): what jnd_texres_run
 * writes as texres.json and returns. */
#include <math.h>
#include <stdio.h>

#include "tasks/report.h"
#include "tasks/tasks.h"

static cJSON *bytes_json(const size_t *b) {
  cJSON *o = cJSON_CreateObject();
  for (int f = 0; f < JND_TEX_FORMATS; f++) cJSON_AddNumberToObject(o, jnd_tex_format_name(f), (double)b[f]);
  return o;
}

static void add_parameters(cJSON *par, const jnd_texres_params *p, const jnd_texres_result *R) {
  cJSON_AddItemToObject(par, "views", report_views_json(&p->judge.views));
  cJSON_AddNumberToObject(par, "verify_views", p->verify_views);
  cJSON_AddItemToObject(par, "criterion", report_criterion_json(&p->judge.criterion, NULL));
  cJSON_AddNumberToObject(par, "margin", p->margin);
  cJSON_AddNumberToObject(par, "confirm_rounds", p->confirm_rounds);
  cJSON_AddNumberToObject(par, "choice_p", R->choice_p);
  cJSON_AddNumberToObject(par, "min_size", p->min_size);
  cJSON *calj = cJSON_AddObjectToObject(par, "calibration");
  cJSON_AddNumberToObject(calj, "percentile", p->judge.calibration.percentile);
  cJSON_AddNumberToObject(calj, "scale", p->judge.calibration.scale);
  cJSON_AddNumberToObject(calj, "bias", p->judge.calibration.bias);
  cJSON_AddNumberToObject(calj, "beta", p->judge.calibration.beta);
  cJSON_AddItemToObject(par, "display", report_display_json(&p->judge.model.display));
  cJSON_AddBoolToObject(par, "matrix", p->matrix != 0);
}

static cJSON *map_json(const jnd_texres_map *m, const jnd_scene *scene) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", m->name);
  cJSON_AddStringToObject(o, "slot", jnd_map_slot_name(m->slot));
  cJSON_AddStringToObject(o, "material", jnd_scene_material_name(scene, m->material));
  cJSON_AddBoolToObject(o, "searched", m->searched);
  cJSON_AddItemToObject(o, "original", report_pair(m->orig));
  cJSON_AddItemToObject(o, "chosen", report_pair(m->chosen));
  cJSON_AddItemToObject(o, "mip_bound", report_pair(m->mip_bound));
  cJSON_AddNumberToObject(o, "mip_min", m->mip_min);
  cJSON_AddItemToObject(o, "eye_bound", report_pair(m->eye_bound));
  cJSON *cand = cJSON_AddArrayToObject(o, "candidates"), *ser = cJSON_AddArrayToObject(o, "series"),
        *part = cJSON_AddArrayToObject(o, "series_decided_early");
  for (int j = 0; j < m->ncand; j++) {
    cJSON_AddItemToArray(cand, report_pair(m->cand[j]));
    cJSON_AddItemToArray(ser, report_number_or_null(m->series[j]));
    cJSON_AddItemToArray(part, cJSON_CreateBool(m->series_partial[j]));
  }
  if (m->fit_ok) {
    cJSON *f = cJSON_AddObjectToObject(o, "psychometric");
    cJSON_AddNumberToObject(f, "mu_log2", m->fit.mu);
    cJSON_AddNumberToObject(f, "sigma_log2", m->fit.sigma);
    cJSON_AddNumberToObject(f, "rmse", m->fit.rmse);
    cJSON_AddNumberToObject(f, "resolution_at_p", m->fit_res);
    cJSON_AddItemToObject(f, "rounded_up", report_pair(m->fit_cand));
  }
  cJSON_AddStringToObject(o, "block_format", jnd_tex_format_name(jnd_slot_block_format(m->slot, m->channels)));
  cJSON_AddNumberToObject(o, "image", m->image);
  return o;
}

/* memory as a GPU holds it: each unique image once, with its mip chain;
 * RGBA8 is the headline, block formats beside it */
static cJSON *memory_json(const jnd_texres_result *R) {
  cJSON *mem = cJSON_CreateObject();
  size_t bb = R->before_bytes[JND_TEX_RGBA8], ba = R->after_bytes[JND_TEX_RGBA8];
  cJSON_AddNumberToObject(mem, "before_bytes", (double)bb);
  cJSON_AddNumberToObject(mem, "after_bytes", (double)ba);
  cJSON_AddNumberToObject(mem, "reduction", bb ? 1.0 - (double)ba / bb : 0);
  cJSON_AddNumberToObject(mem, "block_before_bytes", (double)R->block_before_bytes);
  cJSON_AddNumberToObject(mem, "block_after_bytes", (double)R->block_after_bytes);
  cJSON_AddItemToObject(mem, "formats_before", bytes_json(R->before_bytes));
  cJSON_AddItemToObject(mem, "formats_after", bytes_json(R->after_bytes));
  cJSON *jimg = cJSON_AddArrayToObject(mem, "images");
  for (int t = 0; t < R->nimages; t++) {
    const jnd_texres_image *im = &R->images[t];
    cJSON *o = cJSON_CreateObject(), *users = cJSON_AddArrayToObject(o, "maps");
    for (int i = 0; i < R->nmaps; i++)
      if (R->maps[i].image == t) cJSON_AddItemToArray(users, cJSON_CreateString(R->maps[i].name));
    cJSON_AddItemToObject(o, "original", report_pair(im->orig));
    cJSON_AddItemToObject(o, "chosen", report_pair(im->chosen));
    cJSON_AddStringToObject(o, "block_format", jnd_tex_format_name(im->block_format));
    cJSON_AddItemToObject(o, "bytes_before", bytes_json(im->bytes_before));
    cJSON_AddItemToObject(o, "bytes_after", bytes_json(im->bytes_after));
    cJSON_AddItemToArray(jimg, o);
  }
  return mem;
}

static cJSON *matrix_json(const jnd_texres_result *R, int t) {
  const jnd_texres_matrix *mx = &R->matrix[t];
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "columns", R->maps[mx->map_a].name);
  cJSON_AddStringToObject(o, "rows", R->maps[mx->map_b].name);
  cJSON *sa = cJSON_AddArrayToObject(o, "column_sizes"), *sb = cJSON_AddArrayToObject(o, "row_sizes");
  for (int a = 0; a < mx->na; a++) cJSON_AddItemToArray(sa, cJSON_CreateNumber(mx->size_a[a]));
  for (int b = 0; b < mx->nb; b++) cJSON_AddItemToArray(sb, cJSON_CreateNumber(mx->size_b[b]));
  cJSON *pv = cJSON_AddArrayToObject(o, "p");   /* [view][row][column] */
  for (int v = 0; v < mx->nviews; v++) {
    cJSON *tab = cJSON_CreateArray();
    for (int b = 0; b < mx->nb; b++) {
      cJSON *row = cJSON_CreateArray();
      for (int a = 0; a < mx->na; a++)
        cJSON_AddItemToArray(row, cJSON_CreateNumber(mx->p[((size_t)v * mx->na + a) * mx->nb + b]));
      cJSON_AddItemToArray(tab, row);
    }
    cJSON_AddItemToArray(pv, tab);
  }
  cJSON *stt = cJSON_AddArrayToObject(o, "stat");
  for (int b = 0; b < mx->nb; b++) {
    cJSON *row = cJSON_CreateArray();
    for (int a = 0; a < mx->na; a++) cJSON_AddItemToArray(row, cJSON_CreateNumber(mx->stat[a * mx->nb + b]));
    cJSON_AddItemToArray(stt, row);
  }
  if (mx->best_a >= 0) {
    int best[2] = {mx->size_a[mx->best_a], mx->size_b[mx->best_b]};
    cJSON_AddItemToObject(o, "best", report_pair(best));
  }
  cJSON_AddBoolToObject(o, "complete", mx->complete);
  char name[64];
  snprintf(name, sizeof name, "matrix_%d.png", t);
  cJSON_AddStringToObject(o, "png", name);
  return o;
}

cJSON *texres_report(const char *model, const jnd_texres_params *p, const jnd_texres_result *R,
                     const jnd_scene *scene, const char *model_out, cJSON *map_files, const double *timings) {
  cJSON *report = report_new("texres");
  cJSON *in = report_section(report, "inputs"), *par = report_section(report, "parameters"),
        *res = report_section(report, "result");
  cJSON_AddStringToObject(in, "model", model);
  if (p->judge.calibration.path) cJSON_AddStringToObject(in, "calibration", p->judge.calibration.path);
  add_parameters(par, p, R);

  cJSON_AddStringToObject(res, "renderer", R->renderer);
  cJSON *jm = cJSON_AddArrayToObject(res, "maps");
  for (int i = 0; i < R->nmaps; i++) cJSON_AddItemToArray(jm, map_json(&R->maps[i], scene));
  cJSON_AddItemToObject(res, "memory", memory_json(R));
  cJSON *jv = cJSON_AddObjectToObject(res, "views");
  cJSON_AddNumberToObject(jv, "count", R->nviews);
  cJSON *pv = cJSON_AddArrayToObject(jv, "p");
  for (int i = 0; i < R->nviews; i++) cJSON_AddItemToArray(pv, cJSON_CreateNumber(R->view_p[i]));
  cJSON_AddNumberToObject(jv, "fraction_above", R->views.fraction_above);
  cJSON_AddBoolToObject(jv, "passes", R->views.pass);
  cJSON_AddNumberToObject(jv, "worst_view", R->worst_view);
  cJSON_AddStringToObject(jv, "heatmap", "worst_view.png");
  cJSON_AddItemToObject(jv, "criterion", report_criterion_json(&p->judge.criterion, &R->views));
  if (R->verify_views > 0) {
    cJSON *vv = cJSON_AddObjectToObject(res, "verify");
    cJSON_AddNumberToObject(vv, "views", R->verify_views);
    cJSON_AddNumberToObject(vv, "fraction_above", R->verify.fraction_above);
    cJSON_AddBoolToObject(vv, "passes", R->verify.pass);
    cJSON *vp = cJSON_AddArrayToObject(vv, "p");
    for (int i = 0; i < R->verify_views; i++) cJSON_AddItemToArray(vp, cJSON_CreateNumber(R->verify_p[i]));
    cJSON_AddItemToObject(vv, "criterion", report_criterion_json(&p->judge.criterion, &R->verify));
  }
  cJSON *jmx = cJSON_AddArrayToObject(res, "matrices");
  for (int t = 0; t < R->nmatrix; t++) cJSON_AddItemToArray(jmx, matrix_json(R, t));
  if (model_out) cJSON_AddStringToObject(res, "model", model_out);
  cJSON_AddItemToObject(res, "map_files", map_files);
  cJSON_AddNumberToObject(res, "ppd", R->ppd);
  cJSON_AddNumberToObject(res, "evaluations", R->evaluations);
  cJSON_AddNumberToObject(res, "renderings", R->renderings);
  cJSON *rc = cJSON_AddObjectToObject(res, "rendering_counts");
  cJSON_AddNumberToObject(rc, "references", R->counts.references);
  cJSON_AddNumberToObject(rc, "whole", R->counts.renderings);
  cJSON_AddNumberToObject(rc, "partial", R->counts.partial_renderings);
  cJSON_AddNumberToObject(rc, "view_judgements", R->counts.view_judgements);
  cJSON_AddNumberToObject(rc, "reused", R->counts.reused);
  if (timings) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings");
    cJSON_AddNumberToObject(t, "search_s", timings[0]);
    cJSON_AddNumberToObject(t, "total_s", timings[1]);
  }
  return report;
}
