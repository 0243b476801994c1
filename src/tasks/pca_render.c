/* pca's rendered choice (docs/pca.md): the material re-rendered with its
 * maps rebuilt from a candidate encoding, judged against the set itself by
 * the judge (judge.c), and the cheapest encoding whose views pass. */
#include <ctype.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"
#include "tasks/tasks.h"
#include "tasks/pca_stages.h"

#define MAXC JND_PCA_MAX_CHANNELS

/* ------------------------------------------------------------------------ */
/* Rendered visibility (the renderer's part)                                */
/* ------------------------------------------------------------------------ */

/* The loop of DESIGN.md for a texture set, asked of the judge: the
 * material rendered with its maps rebuilt from a candidate, against the
 * rendering of the set itself (the judge's reference), P per view pooled
 * over the object as every task pools it (judge.c). */
struct jnd_pca_render {
  char path[1024];
  jnd_pca_render_params p;
  jnd_scene *scene;
  jnd_judge *judge;                        /* made when a set is bound: its state is the reference */
  int material;
  const jnd_texset *set;                   /* bound set (the caller's) */
  int nbound;
  int scene_map[JND_PCA_MAX_MAPS];         /* scene map of each set map */
  jnd_map_slot slot[JND_PCA_MAX_MAPS];
};

void jnd_pca_render_defaults(jnd_pca_render_params *p) {
  memset(p, 0, sizeof *p);
  jnd_judge_defaults(&p->judge);
  p->builtin_map_size = 2048;
}

void jnd_pca_render_free(jnd_pca_render *r) {
  if (!r) return;
  jnd_judge_free(r->judge);
  jnd_scene_free(r->scene);
  free(r);
}

const char *jnd_pca_render_description(const jnd_pca_render *r) {
  return r && r->judge ? jnd_judge_renderer(r->judge) : "";
}

static int render_views(const jnd_pca_render_params *p) {
  return p->judge.views.cameras ? p->judge.views.ncameras : p->judge.views.sampling.count;
}

jnd_status jnd_pca_render_open(const char *model_path, const char *material, const jnd_pca_render_params *p,
                               jnd_pca_render **out) {
  *out = NULL;
  if (!model_path || !material) return jnd_fail(JND_ERR_ARG, "rendered visibility needs a model and a material");
  int nv = render_views(p);
  if (nv < 1 || nv > JND_PCA_MAX_VIEWS)
    return jnd_fail(JND_ERR_ARG, "%s: %d views (1 to %d)", model_path, nv, JND_PCA_MAX_VIEWS);
  jnd_pca_render *r = jnd_calloc(1, sizeof *r);
  if (!r) return JND_ERR_NOMEM;
  snprintf(r->path, sizeof r->path, "%s", model_path);
  r->p = *p;
  jnd_status s = jnd_scene_open(model_path, p->builtin_map_size, &r->scene);
  if (s != JND_OK) goto fail;
  r->material = -1;
  int nm = jnd_scene_material_count(r->scene);
  for (int i = 0; i < nm && r->material < 0; i++)
    if (strcmp(jnd_scene_material_name(r->scene, i), material) == 0) r->material = i;
  if (r->material < 0) {
    char list[512] = "";
    for (int i = 0; i < nm; i++) {
      size_t n = strlen(list);
      snprintf(list + n, sizeof list - n, "%s'%s'", i ? ", " : "", jnd_scene_material_name(r->scene, i));
    }
    s = jnd_fail(JND_ERR_ARG, "%s: no material '%s' (it has %s)", model_path, material, nm ? list : "none");
    goto fail;
  }
  *out = r;
  return JND_OK;
fail:
  jnd_pca_render_free(r);
  return s;
}

int jnd_pca_slot_guess(const char *name, jnd_map_slot *slot) {
  char low[128];
  size_t n = 0;
  for (; name[n] && n + 1 < sizeof low; n++) low[n] = (char)tolower((unsigned char)name[n]);
  low[n] = 0;
  for (int i = 0; i < JND_MAP_SLOTS; i++) {
    char sn[32];
    const char *t = jnd_map_slot_name((jnd_map_slot)i);
    size_t k = 0;
    for (; t[k] && k + 1 < sizeof sn; k++) sn[k] = (char)tolower((unsigned char)t[k]);
    sn[k] = 0;
    if (strcmp(low, sn) == 0) {
      *slot = (jnd_map_slot)i;
      return 1;
    }
  }
  /* "ao" as a whole word: the name itself or delimited by _ - . space */
  int ao = 0;
  for (const char *q = strstr(low, "ao"); q && !ao; q = strstr(q + 1, "ao"))
    ao = (q == low || strchr("_-. ", q[-1])) && (!q[2] || strchr("_-. ", q[2]));
  struct {
    const char *word;
    jnd_map_slot slot;
  } const rules[] = {{"emissive", JND_MAP_EMISSIVE},         {"emission", JND_MAP_EMISSIVE},
                     {"normal", JND_MAP_NORMAL},             {"metal", JND_MAP_METALLIC_ROUGHNESS},
                     {"rough", JND_MAP_METALLIC_ROUGHNESS},  {"orm", JND_MAP_METALLIC_ROUGHNESS},
                     {"occlusion", JND_MAP_OCCLUSION},       {"basecolor", JND_MAP_BASE_COLOR},
                     {"base_color", JND_MAP_BASE_COLOR},     {"albedo", JND_MAP_BASE_COLOR},
                     {"diffuse", JND_MAP_BASE_COLOR},        {"color", JND_MAP_BASE_COLOR},
                     {"colour", JND_MAP_BASE_COLOR}};
  for (size_t i = 0; i < sizeof rules / sizeof rules[0]; i++) {
    if (rules[i].slot == JND_MAP_OCCLUSION && ao) break;
    if (strstr(low, rules[i].word)) {
      *slot = rules[i].slot;
      return 1;
    }
  }
  if (ao) {
    *slot = JND_MAP_OCCLUSION;
    return 1;
  }
  return 0;
}

/* The material's maps as a set, the channels the shader reads; orig 1:
 * the file's versions, 0: as the scene uses them now (jnd budget packs a
 * candidate's sizes). map_of (may be NULL) receives each set map's scene
 * map. n == 0 is left to the caller (set->nmaps 0, JND_OK). */
jnd_status pca_scene_material_set(const jnd_scene *scene, int material, int orig, const char *channels,
                                  jnd_texset *set, jnd_map_slot *slots, int *map_of, size_t *orig_bytes) {
  memset(set, 0, sizeof *set);
  if (orig_bytes) *orig_bytes = 0;
  jnd_image maps[JND_MAP_SLOTS];
  memset(maps, 0, sizeof maps);
  const char *names[JND_MAP_SLOTS];
  int image[JND_MAP_SLOTS];   /* the file's image each sampled (jnd_map_info.image) */
  char picks[256] = "";
  int n = 0;
  jnd_status s = JND_OK;
  const char *mname = jnd_scene_material_name(scene, material);
  for (int slot = 0; slot < JND_MAP_SLOTS && s == JND_OK; slot++) {
    char full[256];
    snprintf(full, sizeof full, "%s/%s", mname, jnd_map_slot_name((jnd_map_slot)slot));
    int idx = jnd_scene_map_find(scene, full);
    if (idx < 0) continue;
    jnd_map_info mi;
    if ((s = jnd_scene_map_info(scene, idx, &mi)) != JND_OK) break;
    if ((s = jnd_scene_map_get(scene, idx, orig, &maps[n])) != JND_OK) break;
    image[n] = mi.image;
    names[n] = jnd_map_slot_name((jnd_map_slot)slot);
    slots[n] = (jnd_map_slot)slot;
    if (map_of) map_of[n] = idx;
    /* the channels the shader reads (docs/render.md "Materials") */
    const char *use = slot == JND_MAP_METALLIC_ROUGHNESS && maps[n].c >= 3 ? "gb"
                      : slot == JND_MAP_OCCLUSION && maps[n].c >= 2       ? "r"
                                                                          : NULL;
    int given = 0;   /* an explicit pick for this slot wins */
    if (channels && *channels) {
      size_t ln = strlen(names[n]);
      for (const char *q = strstr(channels, names[n]); q && !given; q = strstr(q + 1, names[n]))
        given = (q == channels || q[-1] == ',') && q[ln] == '=';
    }
    if (use && !given) {
      size_t k = strlen(picks);
      snprintf(picks + k, sizeof picks - k, "%s%s=%s", k ? "," : "", names[n], use);
    }
    int shared = 0;   /* one image of the file bound to two slots (packed occlusion): counted once */
    for (int j = 0; j < n && !shared; j++) shared = image[j] == image[n];
    if (orig_bytes && !shared) *orig_bytes += (size_t)maps[n].w * maps[n].h * maps[n].c;
    n++;
  }
  if (s == JND_OK && n > 0 && channels && *channels) {
    size_t k = strlen(picks);
    snprintf(picks + k, sizeof picks - k, "%s%s", k ? "," : "", channels);
  }
  if (s == JND_OK && n > 0) s = jnd_texset_from_images(maps, names, n, picks, set);
  for (int i = 0; i < n; i++) jnd_image_free(&maps[i]);
  return s;
}

jnd_status jnd_pca_render_material_set(const jnd_pca_render *r, const char *channels, jnd_texset *set,
                                       jnd_map_slot *slots, size_t *orig_bytes) {
  jnd_status s = pca_scene_material_set(r->scene, r->material, 1, channels, set, slots, NULL, orig_bytes);
  if (s == JND_OK && set->nmaps == 0)
    s = jnd_fail(JND_ERR_ARG, "%s: material '%s' has no texture maps", r->path,
                 jnd_scene_material_name(r->scene, r->material));
  return s;
}

int pca_render_slot_image(const jnd_pca_render *r, jnd_map_slot slot) {
  char full[256];
  snprintf(full, sizeof full, "%s/%s", jnd_scene_material_name(r->scene, r->material), jnd_map_slot_name(slot));
  int idx = jnd_scene_map_find(r->scene, full);
  jnd_map_info mi;
  if (idx < 0 || jnd_scene_map_info(r->scene, idx, &mi) != JND_OK) return -1;
  return mi.image;
}

/* puts map i of the set, rebuilt from channels, into its slot */
static jnd_status set_map(jnd_pca_render *r, const jnd_image *channels, int i) {
  const jnd_texset_map *m = &r->set->maps[i];
  jnd_image img = {0}, back = {0};
  jnd_status s = jnd_texset_map_image(r->set, channels, i, &img);
  if (s == JND_OK && m->resampled) {
    s = jnd_resample_map(&img, m->file_w, m->file_h, jnd_map_slot_kind(r->slot[i]), 0, &back);
    jnd_image_free(&img);
    img = back;
  }
  if (s == JND_OK) s = jnd_scene_map_set(r->scene, r->scene_map[i], &img);
  jnd_image_free(&img);
  return s;
}

jnd_status jnd_pca_render_bind(jnd_pca_render *r, const jnd_texset *set, const jnd_map_slot *slots) {
  if (!set || !set->data || set->nmaps < 1) return jnd_fail(JND_ERR_ARG, "%s: no texture set to bind", r->path);
  const char *mname = jnd_scene_material_name(r->scene, r->material);
  for (int i = 0; i < r->nbound; i++) jnd_scene_map_restore(r->scene, r->scene_map[i]);
  r->nbound = 0;
  r->set = set;
  for (int i = 0; i < set->nmaps; i++) {
    if ((int)slots[i] < 0 || slots[i] >= JND_MAP_SLOTS)
      return jnd_fail(JND_ERR_ARG, "%s: map '%s' has no slot", r->path, set->maps[i].name);
    for (int j = 0; j < i; j++)
      if (slots[j] == slots[i])
        return jnd_fail(JND_ERR_ARG, "%s: maps '%s' and '%s' both go to slot %s", r->path, set->maps[j].name,
                        set->maps[i].name, jnd_map_slot_name(slots[i]));
    char full[256];
    snprintf(full, sizeof full, "%s/%s", mname, jnd_map_slot_name(slots[i]));
    r->scene_map[i] = jnd_scene_map_find(r->scene, full);
    r->slot[i] = slots[i];
    if (r->scene_map[i] < 0)
      return jnd_fail(JND_ERR_ARG, "%s: material '%s' has no %s texture to replace with '%s'", r->path, mname,
                      jnd_map_slot_name(slots[i]), set->maps[i].name);
  }
  r->nbound = set->nmaps;
  jnd_image own = {set->w, set->h, set->c, set->data};
  jnd_status s = JND_OK;
  for (int i = 0; i < r->nbound && s == JND_OK; i++) s = set_map(r, &own, i);
  /* the set itself in its slots is the reference */
  if (s == JND_OK) s = r->judge ? jnd_judge_set_reference(r->judge) : jnd_judge_create(r->scene, &r->p.judge, &r->judge);
  return s;
}

jnd_status jnd_pca_render_measure(jnd_pca_render *r, const jnd_image *channels, jnd_pca_visibility *out) {
  memset(out, 0, sizeof *out);
  if (!r->set || !r->nbound || !r->judge) return jnd_fail(JND_ERR_ARG, "%s: no texture set bound", r->path);
  jnd_status s = JND_OK;
  for (int i = 0; i < r->nbound && s == JND_OK; i++) s = set_map(r, channels, i);
  int n = jnd_judge_view_count(r->judge);
  jnd_judgement j;
  if (s == JND_OK) s = jnd_judge_eval(r->judge, 0, n, 0, out->p, &j);
  if (s != JND_OK) return s;
  out->views = n;
  out->allowed = j.criterion.allowed;
  out->above = j.criterion.above;
  out->p_criterion = j.criterion.statistic;
  out->pass = j.criterion.pass;
  return JND_OK;
}

/* encodes e, reconstructs and measures */
static jnd_status measure_encoding(jnd_pca_render *r, const jnd_texset *set, const jnd_pca *pca, const float *proj,
                                   const jnd_pca_encoding *e, jnd_pca_visibility *vis, size_t *bytes) {
  jnd_pca_encoded enc;
  jnd_status s = pca_encode_from(set, pca, proj, e, &enc);
  if (s != JND_OK) return s;
  jnd_image rec = {0};
  s = jnd_pca_reconstruct(&enc, NULL, &rec);
  if (s == JND_OK) s = jnd_pca_render_measure(r, &rec, vis);
  *bytes = enc.storage_bytes;
  jnd_image_free(&rec);
  jnd_pca_encoded_free(&enc);
  return s;
}

static void search_log_add(jnd_pca_search_log *log, const jnd_pca_encoding *e, size_t bytes, double floor_db,
                           const jnd_pca_visibility *v) {
  if (!log || log->tried >= JND_PCA_MAX_TRIED) return;
  int t = log->tried++;
  log->enc[t] = *e;
  log->storage_bytes[t] = bytes;
  log->psnr_target_db[t] = floor_db;
  log->vis[t] = *v;
}

int pca_same_encoding(const jnd_pca_encoding *a, const jnd_pca_encoding *b) {
  if (a->components != b->components) return 0;
  for (int k = 0; k < a->components; k++)
    if (a->scale[k] != b->scale[k] || a->bits[k] != b->bits[k]) return 0;
  return 1;
}

jnd_status jnd_pca_choose_rendered(jnd_pca_render *r, const jnd_texset *set, const jnd_pca *pca, int max_scale,
                                   jnd_pca_encoding *out, jnd_pca_visibility *vis, jnd_pca_search_log *log) {
  enum { FAMILY = 26 };   /* 24 PSNR floors and the lossless candidate */
  memset(out, 0, sizeof *out);
  if (vis) memset(vis, 0, sizeof *vis);
  if (log) {
    memset(log, 0, sizeof *log);
    log->chosen = -1;
  }
  if (r->set != set) return jnd_fail(JND_ERR_ARG, "%s: the set is not the one bound", r->path);
  psnr_chooser ch;
  jnd_status s = pca_chooser_init(set, pca, max_scale, &ch);
  if (s != JND_OK) return s;
  jnd_pca_encoding fam[FAMILY];
  double floor_db[FAMILY];
  size_t bytes[FAMILY];
  int n = 0;
  /* the family: the cheapest encoding for each PSNR floor (001's measure,
   * fast to search), then all components at 16 bits */
  for (int db = 14; db <= 60 && s == JND_OK; db += 2) {
    jnd_pca_encoding e;
    s = pca_chooser_run(&ch, set, pca, db, &e);
    if (s == JND_ERR_ARG) {   /* unreachable floor: the higher ones are too */
      s = JND_OK;
      break;
    }
    if (s != JND_OK) break;
    fam[n] = e;
    floor_db[n++] = db;
  }
  if (s == JND_OK) {
    jnd_pca_encoding e;
    jnd_pca_encoding_default(pca, &e);
    for (int k = 0; k < set->c; k++) e.bits[k] = 16;
    fam[n] = e;
    floor_db[n++] = 0;
  }
  /* deduplicate, sort by storage (stable: insertion) */
  int m = 0;
  for (int i = 0; i < n; i++) {
    int dup = 0;
    for (int j = 0; j < m && !dup; j++) dup = pca_same_encoding(&fam[j], &fam[i]);
    if (dup) continue;
    fam[m] = fam[i];
    floor_db[m] = floor_db[i];
    bytes[m] = jnd_pca_storage_bytes(&fam[m], set->c, set->w, set->h);
    for (int j = m; j > 0 && bytes[j] < bytes[j - 1]; j--) {
      jnd_pca_encoding te = fam[j];
      fam[j] = fam[j - 1];
      fam[j - 1] = te;
      double td = floor_db[j];
      floor_db[j] = floor_db[j - 1];
      floor_db[j - 1] = td;
      size_t tb = bytes[j];
      bytes[j] = bytes[j - 1];
      bytes[j - 1] = tb;
    }
    m++;
  }
  if (log) log->candidates = m;
  /* bisection for the first candidate that passes */
  int lo = 0, hi = m, best = -1;
  jnd_pca_encoding best_enc;
  jnd_pca_visibility best_vis;
  size_t best_bytes = 0;
  memset(&best_enc, 0, sizeof best_enc);
  memset(&best_vis, 0, sizeof best_vis);
  while (lo < hi && s == JND_OK) {
    int mid = lo + (hi - lo) / 2;
    jnd_pca_visibility v;
    size_t b = 0;
    s = measure_encoding(r, set, pca, ch.proj, &fam[mid], &v, &b);
    if (s != JND_OK) break;
    search_log_add(log, &fam[mid], b, floor_db[mid], &v);
    if (v.pass) {
      hi = mid;
      best = mid;
      best_enc = fam[mid];
      best_vis = v;
      best_bytes = b;
    } else {
      lo = mid + 1;
    }
  }
  /* The floors are 2 dB apart, and one step can double the storage (a
   * component going from 8 to 16 bits): bisect the floor between the
   * candidate below, which failed (lo only moves past failures), and the
   * chosen one. */
  if (s == JND_OK && best > 0 && floor_db[best] > 0 && floor_db[best - 1] > 0) {
    double f_lo = floor_db[best - 1], f_hi = floor_db[best];
    for (int it = 0; it < 3 && s == JND_OK; it++) {
      double f = 0.5 * (f_lo + f_hi);
      jnd_pca_encoding e;
      s = pca_chooser_run(&ch, set, pca, f, &e);
      if (s != JND_OK) break;
      size_t b = jnd_pca_storage_bytes(&e, set->c, set->w, set->h);
      if (b >= best_bytes) {   /* nothing cheaper above f */
        f_hi = f;
        continue;
      }
      if (pca_same_encoding(&e, &fam[best - 1])) {   /* known to fail */
        f_lo = f;
        continue;
      }
      jnd_pca_visibility v;
      s = measure_encoding(r, set, pca, ch.proj, &e, &v, &b);
      if (s != JND_OK) break;
      search_log_add(log, &e, b, f, &v);
      if (v.pass) {
        best_enc = e;
        best_vis = v;
        best_bytes = b;
        f_hi = f;
      } else {
        f_lo = f;
      }
    }
  }
  pca_chooser_free(&ch);
  if (s != JND_OK) return s;
  if (best < 0)
    return jnd_fail(JND_ERR_ARG, "%s: no encoding keeps P <= %g in all but %g of the views, not even all components at 16 bits",
                    r->path, r->p.judge.criterion.p, r->p.judge.criterion.q);
  if (log)
    for (int t = 0; t < log->tried; t++)
      if (pca_same_encoding(&log->enc[t], &best_enc)) log->chosen = t;
  *out = best_enc;
  if (vis) *vis = best_vis;
  return JND_OK;
}

/* The hook of tasks.h: the simple call. */
jnd_status pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc, const char *model_path,
                                   const char *material, double *p_detect) {
  if (p_detect) *p_detect = NAN;
  if (!set || !enc) return jnd_fail(JND_ERR_ARG, "%s: rendered visibility needs a set and an encoding",
                                    model_path ? model_path : "--model");
  jnd_map_slot slots[JND_PCA_MAX_MAPS];
  for (int i = 0; i < set->nmaps; i++)
    if (!jnd_pca_slot_guess(set->maps[i].name, &slots[i]))
      return jnd_fail(JND_ERR_ARG, "%s: no material slot fits the map name '%s'", model_path ? model_path : "--model",
                      set->maps[i].name);
  jnd_pca_render_params p;
  jnd_pca_render_defaults(&p);
  jnd_pca_render *r = NULL;
  jnd_status s = jnd_pca_render_open(model_path, material, &p, &r);
  if (s == JND_OK) s = jnd_pca_render_bind(r, set, slots);
  jnd_image rec = {0};
  jnd_pca_visibility v;
  if (s == JND_OK) s = jnd_pca_reconstruct(enc, NULL, &rec);
  if (s == JND_OK) s = jnd_pca_render_measure(r, &rec, &v);
  if (s == JND_OK && p_detect) *p_detect = v.p_criterion;
  jnd_image_free(&rec);
  jnd_pca_render_free(r);
  return s;
}

jnd_status jnd_pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc, const char *model_path,
                                       const char *material, double *p_detect) {
  return pca_rendered_visibility(set, enc, model_path, material, p_detect);
}
