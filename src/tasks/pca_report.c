/* `jnd pca`'s report (docs/pca.md "The report"): what jnd_pca_run writes as
 * pca.json and returns. */
#include <math.h>
#include <stdio.h>

#include "tasks/report.h"
#include "tasks/tasks.h"

/* an infinite PSNR (a lossless channel) as 999 dB: JSON has no infinity */
static double json_db(double db) { return isfinite(db) ? db : 999.0; }

static cJSON *numbers(const double *v, int n) {
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; i < n; i++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
  return a;
}

static const char *rule_name(jnd_pca_rule r) {
  switch (r) {
  case JND_PCA_RULE_RENDERED: return "rendered";
  case JND_PCA_RULE_ENERGY: return "energy";
  case JND_PCA_RULE_PSNR: return "psnr";
  case JND_PCA_RULE_COMPONENTS: return "components";
  default: return "auto";
  }
}

/* pooled P per view of one rendered measurement */
static cJSON *visibility_json(const jnd_pca_visibility *v) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddItemToObject(o, "p_per_view", numbers(v->p, v->views));
  cJSON_AddNumberToObject(o, "views_above", v->above);
  cJSON_AddNumberToObject(o, "p_criterion", v->p_criterion);
  cJSON_AddBoolToObject(o, "pass", v->pass);
  return o;
}

static void add_inputs(cJSON *inputs, const jnd_pca_result *R) {
  cJSON *maps = cJSON_AddArrayToObject(inputs, "maps");
  for (int i = 0; i < R->set.nmaps; i++) {
    const jnd_texset_map *m = &R->set.maps[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "path", R->labels[i]);
    cJSON_AddStringToObject(o, "name", m->name);
    cJSON_AddNumberToObject(o, "width", m->file_w);
    cJSON_AddNumberToObject(o, "height", m->file_h);
    cJSON_AddNumberToObject(o, "file_channels", m->file_channels);
    char used[5] = {0};
    for (int k = 0; k < m->count; k++) used[k] = "rgba"[m->src[k]];
    cJSON_AddStringToObject(o, "channels_used", used);
    cJSON_AddNumberToObject(o, "identical_channels_left_out", m->duplicates);
    cJSON_AddNumberToObject(o, "constant_channels_left_out", m->constants);
    cJSON_AddBoolToObject(o, "resampled", m->resampled);
    cJSON_AddItemToArray(maps, o);
  }
}

static void add_parameters(cJSON *params, const jnd_pca_params *p, const jnd_pca_result *R) {
  cJSON_AddStringToObject(params, "criterion", rule_name(R->rule));
  if (R->rule == JND_PCA_RULE_ENERGY) cJSON_AddNumberToObject(params, "energy", p->energy);
  if (R->rule == JND_PCA_RULE_PSNR) cJSON_AddNumberToObject(params, "psnr_db", p->psnr_db);
  if (R->rule == JND_PCA_RULE_PSNR || R->rule == JND_PCA_RULE_RENDERED)
    cJSON_AddNumberToObject(params, "max_scale", p->max_scale);
  if (p->model) cJSON_AddStringToObject(params, "model", p->model);
  if (p->material) cJSON_AddStringToObject(params, "material", p->material);
  if (p->channels) cJSON_AddStringToObject(params, "channels", p->channels);
  cJSON_AddBoolToObject(params, "standardise", 0);
  cJSON_AddBoolToObject(params, "mean_centre", 1);
  cJSON *wj = cJSON_AddObjectToObject(params, "weights");
  for (int c = 0; c < R->set.c; c++) cJSON_AddNumberToObject(wj, R->set.names[c], R->weights[c]);
}

static void add_channels(cJSON *res, const jnd_pca_result *R) {
  const jnd_pca_encoded *enc = &R->enc;
  cJSON *chs = cJSON_AddArrayToObject(res, "channels");
  for (int c = 0; c < R->set.c; c++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", R->set.names[c]);
    cJSON_AddStringToObject(o, "map", R->set.maps[R->set.map_of[c]].name);
    cJSON_AddNumberToObject(o, "mean", R->pca.mean[c]);
    cJSON_AddNumberToObject(o, "weight", R->pca.weight[c]);
    cJSON_AddNumberToObject(o, "psnr_db", json_db(enc->psnr_db[c]));
    cJSON_AddNumberToObject(o, "psnr_float_db", json_db(R->enc_float.psnr_db[c]));
    if (R->has_bc) {
      cJSON_AddNumberToObject(o, "psnr_bc4_db", json_db(R->bc.psnr_pca_bc4_db[c]));
      cJSON_AddNumberToObject(o, "psnr_bc1_db", json_db(R->bc.psnr_pca_bc1_db[c]));
      cJSON_AddNumberToObject(o, "psnr_plain_bc_db", json_db(R->bc.psnr_plain_db[c]));
    }
    cJSON_AddItemToArray(chs, o);
  }
}

static void add_energy(cJSON *res, const jnd_pca_result *R) {
  int C = R->set.c;
  double sv[JND_PCA_MAX_CHANNELS], frac[JND_PCA_MAX_CHANNELS], cum[JND_PCA_MAX_CHANNELS], acc = 0;
  for (int k = 0; k < C; k++) {
    sv[k] = sqrt(R->pca.energy[k]);
    frac[k] = R->pca.total_variance > 0 ? R->pca.energy[k] / R->pca.total_variance : 0;
    acc += frac[k];
    cum[k] = acc;
  }
  cJSON_AddItemToObject(res, "energy", numbers(R->pca.energy, C));
  cJSON_AddItemToObject(res, "energy_fraction", numbers(frac, C));
  cJSON_AddItemToObject(res, "cumulative_energy", numbers(cum, C));
  cJSON_AddItemToObject(res, "singular_values", numbers(sv, C));
  cJSON_AddNumberToObject(res, "total_variance", R->pca.total_variance);
  cJSON_AddNumberToObject(res, "knee", R->pca.knee);
  double contrib[JND_PCA_MAX_CHANNELS * JND_PCA_MAX_CHANNELS];
  jnd_pca_contribution(&R->pca, contrib);
  cJSON *cm = cJSON_AddArrayToObject(res, "contribution");
  for (int k = 0; k < C; k++) cJSON_AddItemToArray(cm, numbers(contrib + k * C, C));
}

/* memory as a GPU holds it: each unique source image once (RGBA8 + mips)
 * with the maps that sample it, before and after (0: the packed textures
 * replace it), and the packed textures (+ mips) with the maps that sample
 * them: texres's shape (result.memory.images[]) */
static cJSON *memory_json(const jnd_pca_result *R) {
  cJSON *mem = cJSON_CreateObject();
  cJSON_AddNumberToObject(mem, "before_bytes", (double)R->gpu_before_bytes);
  cJSON_AddNumberToObject(mem, "after_bytes", (double)R->gpu_after_bytes);
  cJSON_AddNumberToObject(mem, "reduction",
                          R->gpu_before_bytes ? 1.0 - (double)R->gpu_after_bytes / R->gpu_before_bytes : 0);
  cJSON *imgs = cJSON_AddArrayToObject(mem, "images");
  for (int t = 0; t < R->nimages; t++) {
    cJSON *o = cJSON_CreateObject(), *users = cJSON_AddArrayToObject(o, "maps");
    for (int i = 0; i < R->set.nmaps; i++)
      if (R->image_of[i] == t) cJSON_AddItemToArray(users, cJSON_CreateString(R->labels[i]));
    cJSON_AddNumberToObject(o, "width", R->images[t].width);
    cJSON_AddNumberToObject(o, "height", R->images[t].height);
    cJSON_AddNumberToObject(o, "bytes", (double)R->images[t].bytes);
    cJSON_AddNumberToObject(o, "bytes_before", (double)R->images[t].bytes);
    cJSON_AddNumberToObject(o, "bytes_after", 0);   /* every map it held is reconstructed from the textures */
    cJSON_AddItemToArray(imgs, o);
  }
  cJSON *tex = cJSON_AddArrayToObject(mem, "textures");
  for (int t = 0; t < R->ntextures; t++) {
    cJSON *o = cJSON_CreateObject();
    char name[64];
    snprintf(name, sizeof name, "components_%d.png", t);
    cJSON_AddStringToObject(o, "file", name);
    cJSON *users = cJSON_AddArrayToObject(o, "maps");
    for (int i = 0; i < R->set.nmaps; i++)
      if (pca_map_samples_texture(R, i, t)) cJSON_AddItemToArray(users, cJSON_CreateString(R->labels[i]));
    cJSON_AddNumberToObject(o, "width", R->textures[t].width);
    cJSON_AddNumberToObject(o, "height", R->textures[t].height);
    cJSON_AddNumberToObject(o, "channels", R->textures[t].channels);
    cJSON_AddNumberToObject(o, "bits", R->textures[t].bits);
    cJSON_AddNumberToObject(o, "bytes", (double)R->textures[t].bytes);
    cJSON_AddItemToArray(tex, o);
  }
  return mem;
}

static void add_encoding(cJSON *res, const jnd_pca_result *R, cJSON *textures) {
  const jnd_pca_encoded *enc = &R->enc;
  int C = R->set.c, K = enc->enc.components;
  cJSON *comps = cJSON_AddArrayToObject(res, "components");
  for (int k = 0; k < K; k++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "width", enc->comp[k].w);
    cJSON_AddNumberToObject(o, "height", enc->comp[k].h);
    cJSON_AddNumberToObject(o, "divisor", 1 << enc->enc.scale[k]);
    cJSON_AddNumberToObject(o, "bits", enc->enc.bits[k]);
    cJSON_AddNumberToObject(o, "scale", enc->scale[k]);
    cJSON_AddNumberToObject(o, "offset", enc->offset[k]);
    cJSON_AddItemToArray(comps, o);
  }
  cJSON_AddItemToObject(res, "textures", textures);
  cJSON *rm = cJSON_AddArrayToObject(res, "reconstruction");
  for (int c = 0; c < C; c++) cJSON_AddItemToArray(rm, numbers(enc->recon + (size_t)c * (K + 1), K + 1));
  cJSON_AddStringToObject(res, "reconstruction_layout",
                          "C rows (channels, in result.channels order) of K+1: channel c = "
                          "sum_k R[c][k] * q_k + R[c][K], q_k = component k as stored (0..1)");
  cJSON_AddNumberToObject(res, "storage_bytes", (double)enc->storage_bytes);
  cJSON_AddNumberToObject(res, "original_bytes", (double)R->original_bytes);
  cJSON_AddNumberToObject(res, "reduction",
                          R->original_bytes ? 1.0 - (double)enc->storage_bytes / R->original_bytes : 0);
  cJSON_AddItemToObject(res, "memory", memory_json(R));
  if (R->has_bc) {
    cJSON *b = cJSON_AddObjectToObject(res, "block_compression");
    cJSON_AddNumberToObject(b, "pca_bc4_bytes", (double)R->bc.bytes_pca_bc4);
    cJSON_AddNumberToObject(b, "pca_bc1_bytes", (double)R->bc.bytes_pca_bc1);
    cJSON_AddNumberToObject(b, "plain_bc_bytes", (double)R->bc.bytes_plain);
    cJSON_AddStringToObject(b, "plain_formats", "BC1 for RGB maps, BC4 for grey, BC5 for 2 channels, BC1+BC4 for RGBA");
  }
}

static cJSON *rendered_json(const jnd_pca_params *p, const jnd_pca_result *R) {
  cJSON *rj = cJSON_CreateObject();
  cJSON_AddStringToObject(rj, "model", p->model);
  cJSON_AddStringToObject(rj, "material", p->material);
  cJSON_AddStringToObject(rj, "renderer", R->renderer);
  cJSON *sj = cJSON_AddObjectToObject(rj, "slots");
  for (int i = 0; i < R->set.nmaps; i++) cJSON_AddStringToObject(sj, R->set.maps[i].name, jnd_map_slot_name(R->slots[i]));
  cJSON_AddNumberToObject(rj, "views", R->vis.views);
  cJSON_AddItemToObject(rj, "view_set", report_views_json(&p->render.judge.views));
  cJSON_AddItemToObject(rj, "display", report_display_json(&p->render.judge.model.display));
  char pool[32];
  snprintf(pool, sizeof pool, "p%g", p->render.judge.calibration.percentile);
  cJSON_AddStringToObject(rj, "pooling", pool);
  jnd_criterion_result cr = {0};
  cr.views = R->vis.views, cr.above = R->vis.above, cr.allowed = R->vis.allowed, cr.statistic = R->vis.p_criterion;
  cr.pass = R->vis.pass, cr.fraction_above = R->vis.views ? (double)R->vis.above / R->vis.views : 0;
  cr.fraction_upper = jnd_binomial_upper(R->vis.above, R->vis.views, p->render.judge.criterion.confidence);
  cJSON_AddItemToObject(rj, "criterion", report_criterion_json(&p->render.judge.criterion, &cr));
  cJSON_AddItemToObject(rj, "p_per_view", numbers(R->vis.p, R->vis.views));
  cJSON_AddNumberToObject(rj, "views_above", R->vis.above);
  cJSON_AddNumberToObject(rj, "p_criterion", R->vis.p_criterion);
  cJSON_AddBoolToObject(rj, "pass", R->vis.pass);
  if (p->block_compression) {
    cJSON *bj = cJSON_AddObjectToObject(rj, "block_compressed");
    const char *bn[3] = {"pca_bc4", "pca_bc1", "plain_bc"};
    for (int k = 0; k < 3; k++) {
      cJSON *o = visibility_json(&R->vis_bc[k]);
      cJSON_AddNumberToObject(o, "bytes", (double)R->bytes_bc[k]);
      cJSON_AddItemToObject(bj, bn[k], o);
    }
  }
  if (R->log) {
    cJSON *search = cJSON_AddObjectToObject(rj, "search");
    cJSON_AddNumberToObject(search, "candidates", R->log->candidates);
    cJSON_AddNumberToObject(search, "rendered", R->log->tried);
    cJSON *tried = cJSON_AddArrayToObject(search, "tried");
    for (int t = 0; t < R->log->tried; t++) {
      cJSON *o = visibility_json(&R->log->vis[t]);
      cJSON_AddNumberToObject(o, "components", R->log->enc[t].components);
      cJSON_AddNumberToObject(o, "storage_bytes", (double)R->log->storage_bytes[t]);
      cJSON_AddNumberToObject(o, "psnr_floor_db", R->log->psnr_target_db[t]);
      cJSON_AddItemToArray(tried, o);
    }
  }
  return rj;
}

cJSON *pca_report(const jnd_pca_params *p, const jnd_pca_result *R, cJSON *textures, const double *total_s) {
  cJSON *report = report_new("pca");
  cJSON *res = report_section(report, "result");
  add_inputs(report_section(report, "inputs"), R);
  add_parameters(report_section(report, "parameters"), p, R);
  cJSON_AddNumberToObject(res, "width", R->set.w);
  cJSON_AddNumberToObject(res, "height", R->set.h);
  cJSON_AddNumberToObject(res, "channel_count", R->set.c);
  cJSON_AddNumberToObject(res, "components_kept", R->enc.enc.components);
  add_channels(res, R);
  add_energy(res, R);
  add_encoding(res, R, textures);
  if (R->rendered) cJSON_AddItemToObject(res, "rendered", rendered_json(p, R));
  if (total_s) {
    cJSON *t = cJSON_AddObjectToObject(res, "timings_s");
    static const char *const stage[6] = {"read", "decomposition", "choice", "encoding", "block_compression", "rendering"};
    for (int k = 0; k < 6; k++)
      if (k < 5 || R->rendered) cJSON_AddNumberToObject(t, stage[k], R->seconds[k]);
    cJSON_AddNumberToObject(t, "total", *total_s);
  }
  return report;
}
