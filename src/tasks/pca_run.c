/* `jnd pca` as one call (001; docs/pca.md): the set (map files, or a model
 * material's own maps), the decomposition, the choice of an encoding by the
 * rule asked for — rendered visibility through the judge when there is a
 * model, else an energy target, or a PSNR floor, or as given — its encoding,
 * block-compression measurements and, with a model, the judge's P for the
 * chosen encoding and its block-compressed variants. Also the packing of
 * the components into textures as an engine samples them. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/report.h"
#include "tasks/tasks.h"

/* the default energy target: the fewest components keeping 99% of the
 * variance (001 reads the knee of the same curve; the knee is reported) */
#define PCA_ENERGY 0.99

void jnd_pca_defaults(jnd_pca_params *p) {
  memset(p, 0, sizeof *p);
  jnd_pca_render_defaults(&p->render);
  p->rule = JND_PCA_RULE_AUTO;
  p->energy = PCA_ENERGY;
  p->max_scale = 2;
  p->components = -1;
  p->block_compression = 1;
  jnd_run_options_defaults(&p->run);
}

void jnd_pca_result_clear(jnd_pca_result *r) {
  jnd_texset_free(&r->set);
  jnd_pca_encoded_free(&r->enc);
  jnd_pca_encoded_free(&r->enc_float);
  free(r->log);
  free(r->report);
  memset(r, 0, sizeof *r);
}

void jnd_pca_result_free(jnd_pca_result *r) {
  if (!r) return;
  jnd_pca_result_clear(r);
  free(r);
}

__attribute__((format(printf, 2, 3))) static void stage(const jnd_pca_params *p, const char *fmt, ...) {
  if (!p->progress) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  p->progress(p->progress_user, line, 0, 0);
}

/* "FILE=SLOT" bindings (or the slot each map's name suggests) */
static jnd_status slots_for_maps(const jnd_pca_params *p, const jnd_texset *set, jnd_map_slot *slots) {
  for (int i = 0; i < set->nmaps; i++) {
    int found = 0;
    const char *path = p->maps[i], *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    for (int k = 0; k < p->nslots && !found; k++) {
      const char *eq = strrchr(p->slots[k], '=');
      if (!eq) return jnd_fail(JND_ERR_ARG, "--slot: '%s' is not FILE=SLOT", p->slots[k]);
      size_t n = (size_t)(eq - p->slots[k]);
      if (!((strlen(path) == n && strncmp(path, p->slots[k], n) == 0) ||
            (strlen(base) == n && strncmp(base, p->slots[k], n) == 0)))
        continue;
      int s = 0;
      while (s < JND_MAP_SLOTS && strcmp(jnd_map_slot_name((jnd_map_slot)s), eq + 1) != 0) s++;
      if (s == JND_MAP_SLOTS)
        return jnd_fail(JND_ERR_ARG, "--slot: '%s' is not a slot (baseColor, metallicRoughness, normal, occlusion, emissive)",
                        eq + 1);
      slots[i] = (jnd_map_slot)s;
      found = 1;
    }
    if (!found && !jnd_pca_slot_guess(set->maps[i].name, &slots[i]))
      return jnd_fail(JND_ERR_ARG, "%s: no material slot fits this map's name (give --slot FILE=SLOT)", path);
  }
  return JND_OK;
}

/* the distinct images of a set's maps at 8 bits per channel as their files had them */
static size_t maps_8bit_bytes(const jnd_texset *set) {
  size_t b = 0;
  for (int i = 0; i < set->nmaps; i++) b += (size_t)set->maps[i].file_w * set->maps[i].file_h * set->maps[i].file_channels;
  return b;
}

/* The unique images the set's maps come from, as a GPU holds them: a map
 * file named twice, or one image of a model bound to two slots (a packed
 * occlusion-roughness-metal image), counts once. */
static void count_images(const jnd_pca_params *p, const jnd_pca_render *rr, jnd_pca_result *out) {
  int id[JND_PCA_MAX_MAPS];
  out->nimages = 0;
  out->gpu_before_bytes = 0;
  for (int i = 0; i < out->set.nmaps; i++) {
    id[i] = p->nmaps ? i : pca_render_slot_image(rr, out->slots[i]);
    int first = i;
    for (int j = 0; j < i && first == i; j++)
      if (p->nmaps ? strcmp(p->maps[j], p->maps[i]) == 0 : id[j] == id[i] && id[i] >= 0) first = j;
    if (first != i) {
      out->image_of[i] = out->image_of[first];
      continue;
    }
    const jnd_texset_map *m = &out->set.maps[i];
    out->image_of[i] = out->nimages;
    out->images[out->nimages].first_map = i;
    out->images[out->nimages].width = m->file_w;
    out->images[out->nimages].height = m->file_h;
    out->images[out->nimages].bytes = jnd_texture_bytes(JND_TEX_RGBA8, m->file_w, m->file_h, 1);
    out->gpu_before_bytes += out->images[out->nimages++].bytes;
  }
}

/* The packing of enc's components into textures (jnd_pca_pack's rule): tex
 * gets *n layouts, each with its bytes as a GPU holds it (texels of 1 (R),
 * 2 (RG) or 4 (RGB is stored RGBA) channels of 1 or 2 bytes, with mips), and
 * *bytes their sum. A choice decides it once (jnd_pca_choose); its files are
 * written from that layout (write_files). */
static void pack_layout(const jnd_pca_encoded *enc, jnd_pca_texture_info *tex, int *n, size_t *bytes) {
  int K = enc->enc.components, used[JND_PCA_MAX_CHANNELS] = {0};
  *n = 0;
  *bytes = 0;
  for (int k = 0; k < K; k++) {
    if (used[k]) continue;
    /* the next components of the same size and depth share the texture */
    jnd_pca_texture_info *t = &tex[(*n)++];
    memset(t, 0, sizeof *t);
    t->bits = enc->enc.bits[k] == 16 ? 16 : 8;
    for (int j = k; j < K && t->channels < 4; j++)
      if (!used[j] && enc->enc.scale[j] == enc->enc.scale[k] && (enc->enc.bits[j] == 16 ? 16 : 8) == t->bits) {
        used[j] = 1;
        t->comp[t->channels++] = j;
      }
    t->width = enc->comp[k].w;
    t->height = enc->comp[k].h;
    int texel = (t->channels == 3 ? 4 : t->channels) * t->bits / 8;
    /* RGBA8's chain is 4 bytes a texel over every level */
    t->bytes = jnd_texture_bytes(JND_TEX_RGBA8, t->width, t->height, 1) / 4 * texel;
    *bytes += t->bytes;
  }
}

int pca_map_samples_texture(const jnd_pca_result *R, int map, int tex) {
  const jnd_texset_map *m = &R->set.maps[map];
  const jnd_pca_texture_info *t = &R->textures[tex];
  const int K = R->enc.enc.components;
  for (int c = m->first; c < m->first + m->count; c++)
    for (int j = 0; j < t->channels; j++)
      if (R->enc.recon[(size_t)c * (K + 1) + t->comp[j]] != 0) return 1;
  return 0;
}

/* a texture of the layout as an image: its components in its channels */
static jnd_status pack_texture(const jnd_pca_encoded *enc, const jnd_pca_texture_info *info, jnd_pca_texture *tex) {
  memset(tex, 0, sizeof *tex);
  tex->bits = info->bits;
  tex->ncomp = info->channels;
  memcpy(tex->comp, info->comp, sizeof tex->comp);
  jnd_status s = jnd_image_alloc(&tex->image, info->width, info->height, tex->ncomp);
  if (s != JND_OK) return s;
  size_t np = (size_t)tex->image.w * tex->image.h;
  for (int q = 0; q < tex->ncomp; q++)
    memcpy(tex->image.data + q * np, enc->comp[tex->comp[q]].data, np * sizeof(float));
  return JND_OK;
}

jnd_status jnd_pca_choose(const jnd_pca_params *p, jnd_pca_result *out) {
  memset(out, 0, sizeof *out);
  if (p->nmaps > JND_PCA_MAX_MAPS) return jnd_fail(JND_ERR_LIMIT, "pca: at most %d maps", JND_PCA_MAX_MAPS);
  if (p->nmaps == 0 && !p->model) return jnd_fail(JND_ERR_ARG, "pca: needs maps or a model");
  if (p->model && !p->material) return jnd_fail(JND_ERR_ARG, "pca: a model needs a material");
  if (p->nslots && !(p->model && p->nmaps)) return jnd_fail(JND_ERR_ARG, "pca: --slot needs map files and a model");
  jnd_pca_rule rule = p->rule == JND_PCA_RULE_AUTO ? (p->model ? JND_PCA_RULE_RENDERED : JND_PCA_RULE_ENERGY) : p->rule;
  if (rule == JND_PCA_RULE_RENDERED && !p->model)
    return jnd_fail(JND_ERR_ARG, "pca: a rendered choice needs a model and a material");
  if (rule == JND_PCA_RULE_ENERGY && !(p->energy > 0 && p->energy <= 1))
    return jnd_fail(JND_ERR_ARG, "pca: energy target %g is outside (0, 1]", p->energy);
  out->rule = rule;
  double t0 = jnd_seconds();
  jnd_pca_render *rr = NULL;
  jnd_status s = JND_OK;
  size_t orig_bytes = 0;
  if (p->model && (s = jnd_pca_render_open(p->model, p->material, &p->render, &rr)) != JND_OK) return s;
  s = p->nmaps ? jnd_texset_read(p->maps, p->nmaps, p->channels, &out->set)
               : jnd_pca_render_material_set(rr, p->channels, &out->set, out->slots, &orig_bytes);
  for (int i = 0; s == JND_OK && i < out->set.nmaps; i++) {
    if (p->nmaps) snprintf(out->labels[i], sizeof out->labels[i], "%s", p->maps[i]);
    else snprintf(out->labels[i], sizeof out->labels[i], "%s/%s", p->material, out->set.maps[i].name);
  }
  if (s == JND_OK && p->model && p->nmaps) s = slots_for_maps(p, &out->set, out->slots);
  out->original_bytes = p->nmaps ? maps_8bit_bytes(&out->set) : orig_bytes;
  if (s == JND_OK) count_images(p, rr, out);
  out->seconds[0] = jnd_seconds() - t0;
  /* every input checked before the first progress line or rendering */
  double t1 = jnd_seconds();
  if (s == JND_OK) s = jnd_texset_parse_weights(&out->set, p->weights, out->weights);
  if (s == JND_OK) s = jnd_pca_analyse(&out->set, out->weights, &out->pca);
  out->seconds[1] = jnd_seconds() - t1;
  if (s == JND_OK && p->model) {
    double tr = jnd_seconds();
    s = jnd_pca_render_bind(rr, &out->set, out->slots);
    out->seconds[5] += jnd_seconds() - tr;
    if (s == JND_OK) {
      out->rendered = 1;
      snprintf(out->renderer, sizeof out->renderer, "%s", jnd_pca_render_description(rr));
    }
  }
  if (s != JND_OK) goto done;
  stage(p, "set: %d maps, %d x %d, %d channels, knee at %d%s%s", out->set.nmaps, out->set.w, out->set.h, out->set.c,
        out->pca.knee, out->rendered ? "; references rendered on " : "", out->rendered ? out->renderer : "");

  /* the rule */
  int C = out->set.c;
  jnd_pca_encoding e;
  jnd_pca_encoding_default(&out->pca, &e);
  double t2 = jnd_seconds();
  switch (rule) {
  case JND_PCA_RULE_COMPONENTS:
    e.components = p->components < 0 || p->components > C ? C : p->components;
    for (int k = 0; k < C; k++) {
      e.bits[k] = p->nbits ? p->bits[k < p->nbits ? k : p->nbits - 1] : 8;
      e.scale[k] = p->nscale ? p->scale[k < p->nscale ? k : p->nscale - 1] : 0;
    }
    break;
  case JND_PCA_RULE_ENERGY: {
    double acc = 0;
    e.components = C;
    for (int k = 0; k < C; k++) {
      acc += out->pca.energy[k];
      if (acc >= p->energy * out->pca.total_variance * (1 - 1e-12)) {
        e.components = k + 1;
        break;
      }
    }
    break;
  }
  case JND_PCA_RULE_PSNR:
    s = jnd_pca_choose_psnr(&out->set, &out->pca, p->psnr_db, p->max_scale, &e);
    break;
  default: {
    double tr = jnd_seconds();
    out->log = jnd_calloc(1, sizeof *out->log);
    s = out->log ? jnd_pca_choose_rendered(rr, &out->set, &out->pca, p->max_scale, &e, &out->vis, out->log)
                 : JND_ERR_NOMEM;
    out->seconds[5] += jnd_seconds() - tr;
    break;
  }
  }
  out->seconds[2] = jnd_seconds() - t2;
  if (s != JND_OK) goto done;
  double t3 = jnd_seconds();
  if ((s = jnd_pca_encode(&out->set, &out->pca, &e, &out->enc)) != JND_OK) goto done;
  /* the same K without resizing or quantisation: PSNR "in float" */
  jnd_pca_encoding ef = e;
  for (int k = 0; k < C; k++) ef.scale[k] = ef.bits[k] = 0;
  if ((s = jnd_pca_encode(&out->set, &out->pca, &ef, &out->enc_float)) != JND_OK) goto done;
  pack_layout(&out->enc, out->textures, &out->ntextures, &out->gpu_after_bytes);
  out->seconds[3] = jnd_seconds() - t3;
  stage(p, "chose %d of %d components (%s), %zu bytes", out->enc.enc.components, C,
        rule == JND_PCA_RULE_RENDERED ? "rendered" : rule == JND_PCA_RULE_ENERGY ? "energy"
                                    : rule == JND_PCA_RULE_PSNR                  ? "psnr"
                                                                                 : "components",
        out->enc.storage_bytes);
  if (p->model) {
    double tr = jnd_seconds();
    jnd_image rec = {0};
    if (rule != JND_PCA_RULE_RENDERED) {   /* the encoding chosen otherwise, measured as it is */
      s = jnd_pca_reconstruct(&out->enc, NULL, &rec);
      if (s == JND_OK) s = jnd_pca_render_measure(rr, &rec, &out->vis);
      jnd_image_free(&rec);
    }
    for (int v = 0; v < 3 && p->block_compression && s == JND_OK; v++) {
      s = jnd_pca_block_compressed(&out->set, &out->enc, (jnd_pca_bc_variant)v, &rec, &out->bytes_bc[v]);
      if (s == JND_OK) s = jnd_pca_render_measure(rr, &rec, &out->vis_bc[v]);
      jnd_image_free(&rec);
    }
    out->seconds[5] += jnd_seconds() - tr;
    if (s != JND_OK) goto done;
    stage(p, "rendered: %d of %d views above P = %g", out->vis.above, out->vis.views, p->render.judge.criterion.p);
  }
  double t4 = jnd_seconds();
  if (p->block_compression) {
    if ((s = jnd_pca_block_compression(&out->set, &out->enc, &out->bc)) != JND_OK) goto done;
    out->has_bc = 1;
  }
  out->seconds[4] = jnd_seconds() - t4;
done:
  jnd_pca_render_free(rr);
  if (s != JND_OK) jnd_pca_result_clear(out);
  return s;
}

/* ---- packing ---- */

jnd_status jnd_pca_pack(const jnd_pca_encoded *enc, jnd_pca_texture *tex, int *n) {
  jnd_pca_texture_info info[JND_PCA_MAX_CHANNELS];
  int ninfo;
  size_t bytes;
  pack_layout(enc, info, &ninfo, &bytes);
  *n = 0;
  jnd_status s = JND_OK;
  for (int t = 0; t < ninfo && s == JND_OK; t++)
    if ((s = pack_texture(enc, &info[t], &tex[t])) == JND_OK) *n = t + 1;
  if (s != JND_OK) {
    for (int i = 0; i < *n; i++) jnd_image_free(&tex[i].image);
    *n = 0;
  }
  return s;
}

/* ---- the task: the choice and its files (jnd_pca_run) ---- */

/* the packed components (listed in textures), the contribution plot, the
 * rebuilt maps */
static jnd_status write_files(const char *dir, const jnd_pca_result *R, int write_maps, cJSON *textures) {
  char path[4200], name[64];
  jnd_status s = JND_OK;
  for (int t = 0; t < R->ntextures && s == JND_OK; t++) {   /* the choice's packing (pack_layout) */
    jnd_pca_texture tex;
    snprintf(name, sizeof name, "components_%d.png", t);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    s = pack_texture(&R->enc, &R->textures[t], &tex);
    if (s == JND_OK) s = jnd_image_write_png(path, &tex.image, tex.bits);
    jnd_image_free(&tex.image);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "file", name);
    cJSON_AddNumberToObject(o, "width", R->textures[t].width);
    cJSON_AddNumberToObject(o, "height", R->textures[t].height);
    cJSON_AddNumberToObject(o, "bits", R->textures[t].bits);
    cJSON *cs = cJSON_AddArrayToObject(o, "components");   /* in channels R, G, B, A */
    for (int q = 0; q < R->textures[t].channels; q++)
      cJSON_AddItemToArray(cs, cJSON_CreateNumber(R->textures[t].comp[q]));
    cJSON_AddItemToArray(textures, o);
  }
  jnd_image plot = {0};
  snprintf(path, sizeof path, "%s/contribution.png", dir);
  if (s == JND_OK) s = jnd_pca_contribution_plot(&R->pca, &R->set, &plot);
  if (s == JND_OK) s = jnd_image_write_png(path, &plot, 8);
  jnd_image_free(&plot);
  if (s == JND_OK && write_maps) {
    jnd_image rec = {0};
    s = jnd_pca_reconstruct(&R->enc, NULL, &rec);
    for (int i = 0; i < R->set.nmaps && s == JND_OK; i++) {
      jnd_image mi = {0};
      snprintf(path, sizeof path, "%s/%s.png", dir, R->set.maps[i].name);
      s = jnd_texset_map_image(&R->set, &rec, i, &mi);
      if (s == JND_OK) s = jnd_image_write_png(path, &mi, 8);
      jnd_image_free(&mi);
    }
    jnd_image_free(&rec);
  }
  return s;
}

jnd_status jnd_pca_run(const char *model, const jnd_pca_params *pp, const char *out_dir, jnd_pca_result **out) {
  *out = NULL;
  if (!out_dir) return jnd_fail(JND_ERR_ARG, "pca: give an output folder");
  jnd_pca_params p;
  if (pp) p = *pp;
  else jnd_pca_defaults(&p);
  p.model = model;
  if (p.nmaps > JND_PCA_MAX_MAPS) return jnd_fail(JND_ERR_LIMIT, "pca: at most %d maps", JND_PCA_MAX_MAPS);
  if (p.render.judge.views.cameras_path)
    return jnd_fail(JND_ERR_ARG, "pca: --cameras is not supported here yet (sampled views only)");
  double t0 = jnd_seconds();
  /* the outputs checked against every input before any work */
  const char *inputs[JND_PCA_MAX_MAPS + 3] = {model, p.render.judge.views.render.env_path,
                                              p.render.judge.calibration.path};
  for (int k = 0; k < p.nmaps; k++) inputs[3 + k] = p.maps[k];
  report_output o;
  jnd_status s = report_output_open(&o, inputs, 3 + p.nmaps, out_dir, &p.run);
  if (s != JND_OK) return s;
  jnd_pca_result *R = jnd_calloc(1, sizeof *R);
  cJSON *report = NULL, *textures = cJSON_CreateArray();
  if (!R || !textures) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = jnd_pca_choose(&p, R);
  for (int i = 0; s == JND_OK && p.run.warning && i < R->set.nmaps; i++) {
    const jnd_texset_map *m = &R->set.maps[i];
    if (!m->resampled) continue;
    char line[400];
    snprintf(line, sizeof line, "%s: %d x %d resampled to %d x %d (Lanczos-3)", R->labels[i], m->file_w, m->file_h,
             R->set.w, R->set.h);
    p.run.warning(p.run.warning_user, line);
  }
  if (s == JND_OK) s = write_files(o.dir, R, p.write_maps, textures);
  if (s == JND_OK) {
    double total = jnd_seconds() - t0;
    report = pca_report(&p, R, textures, p.run.timings ? &total : NULL);
    textures = NULL;
  }
  s = REPORT_OUTPUT_FINISH(&o, s, report, "pca.json", R);
  cJSON_Delete(textures);
  if (s != JND_OK) {
    jnd_pca_result_free(R);
    return s;
  }
  *out = R;
  return JND_OK;
}
