/* Texture resolution nobody notices (Wolski et al. 2019, 000 §4–§9).
 *
 * The loop of DESIGN.md: shrink a map (Lanczos-3, 000 §4), render the asset
 * from sampled views as an engine would, compare each view with the
 * full-resolution rendering through the vision model, pool the probability
 * map (P93, 000 §6, or a calibration, 000 §7), and keep the smallest maps for
 * which at most a fraction q of the views exceed P = p (000 §9: q = 0.1,
 * p = 0.2). The search (docs/texres.md):
 *   1. the mip-usage bound of 000 §4: a map whose level 0 no pixel samples
 *      can be halved without change, so candidates start at the bound;
 *   2. per map, the series from the bound down with the other maps at full
 *      resolution, stopping one candidate after the criterion fails
 *      (detection grows as resolution falls, so the rest would fail too);
 *      000 eq. 1 fitted to the series regularises it (000 §6);
 *   3. the per-map choices together; while the combination fails, the map
 *      whose one step up helps most is enlarged (coordinate descent);
 *   4. the final combination is verified on every view, and optionally on
 *      held-out views.
 * With a material's baseColor and normal maps both searched, the full matrix
 * of their candidates is also evaluated, as 000 Fig. 13. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"

/* ---- memory accounting (000 Table 2) ---- */

static const struct {
  const char *name;
  int bw, bh, block_bytes;  /* a block of bw × bh texels takes block_bytes */
} tex_formats[JND_TEX_FORMATS] = {
    {"rgba8", 1, 1, 4},   {"bc1", 4, 4, 8},      {"bc4", 4, 4, 8}, {"bc5", 4, 4, 16},
    {"bc7", 4, 4, 16},    {"astc4x4", 4, 4, 16}, {"astc6x6", 6, 6, 16},
};

const char *jnd_tex_format_name(jnd_tex_format f) {
  return f >= 0 && f < JND_TEX_FORMATS ? tex_formats[f].name : "?";
}

size_t jnd_texture_bytes(jnd_tex_format f, int w, int h, int mips) {
  if (f < 0 || f >= JND_TEX_FORMATS || w < 1 || h < 1) return 0;
  size_t total = 0;
  for (;;) {
    size_t bx = (size_t)(w + tex_formats[f].bw - 1) / tex_formats[f].bw;
    size_t by = (size_t)(h + tex_formats[f].bh - 1) / tex_formats[f].bh;
    total += bx * by * (size_t)tex_formats[f].block_bytes;
    if (!mips || (w == 1 && h == 1)) break;
    w = w > 1 ? w / 2 : 1;
    h = h > 1 ? h / 2 : 1;
  }
  return total;
}

jnd_tex_format jnd_slot_block_format(jnd_map_slot slot, int channels) {
  switch (slot) {
  case JND_MAP_BASE_COLOR: return JND_TEX_BC7;
  case JND_MAP_NORMAL: return JND_TEX_BC5;
  case JND_MAP_OCCLUSION: return JND_TEX_BC4;
  default: return channels == 1 ? JND_TEX_BC4 : JND_TEX_BC1;
  }
}

void jnd_texres_defaults(jnd_texres_params *p) {
  memset(p, 0, sizeof *p);
  p->views = 8;
  p->seed = 1;
  p->width = p->height = 384;
  p->coverage = 0.8;
  p->fov_y_deg = 45;
  p->lights = 1;
  p->anisotropy = 8;
  p->samples = 4;
  p->p_threshold = 0.2;   /* 000 §9 */
  p->max_fraction = 0.1;  /* 000 §9 */
  p->min_size = 32;
  p->matrix = 2;
  jnd_calibration_defaults(&p->calibration);
  jnd_model_defaults(&p->model);
}

void jnd_texres_result_free(jnd_texres_result *r) {
  free(r->maps);
  free(r->view_p);
  free(r->verify_p);
  jnd_image_free(&r->worst_heatmap);
  for (int i = 0; i < r->nmatrix; i++) {
    free(r->matrix[i].p);
    free(r->matrix[i].stat);
  }
  free(r->matrix);
  memset(r, 0, sizeof *r);
}

/* ---- the search ---- */

#define JND_TEXRES_MAX_MAPS 256
#define CROP_MARGIN 16   /* pixels around the object kept for the model's pyramid */

typedef struct {
  int x0, y0, w, h;       /* crop of the object's bounding box */
  jnd_image ref;          /* cd/m², cropped */
  jnd_image ref_srgb;     /* display signal, cropped (heatmap backdrop) */
  jnd_image mask;         /* coverage, cropped */
} view_ref;

typedef struct {
  int cur;                /* candidate in use (−1: the file's map) */
  jnd_image cache[JND_TEXRES_MAX_CAND];
} map_state;

typedef struct {
  jnd_scene *scene;
  const jnd_texres_params *p;
  jnd_renderer *r;
  jnd_model *m;
  jnd_texres_result *res;
  map_state *ms;
  int done, total;        /* progress */
  /* evaluations already made on the choice views: the combination (candidate
   * index per map) and the pooled P per view, so that no combination is
   * rendered twice (series, descent, matrix and verification share cells) */
  int ncache, capcache;
  int *cache_k;           /* ncache × nmaps */
  double *cache_p;        /* ncache × nviews */
  const jnd_view *cache_views;
} ctx;

static void progress(ctx *c) {
  c->done++;
  if (c->done > c->total) c->total = c->done;
  if (c->p->progress) c->p->progress(c->p->progress_user, c->done, c->total);
}

/* crop of a planar image */
static jnd_status crop(const jnd_image *in, int x0, int y0, int w, int h, jnd_image *out) {
  jnd_status s = jnd_image_alloc(out, w, h, in->c);
  if (s != JND_OK) return s;
  for (int ch = 0; ch < in->c; ch++)
    for (int y = 0; y < h; y++)
      memcpy(out->data + ((size_t)ch * h + y) * w, in->data + ((size_t)ch * in->h + y + y0) * in->w + x0,
             (size_t)w * sizeof(float));
  return JND_OK;
}

/* the rendering as the viewer sees it: display signal (sRGB, clamped as a
 * display shows it) → the display model → cd/m², cropped */
static jnd_status seen(ctx *c, const jnd_image *linear, const view_ref *v, jnd_image *cdm2, jnd_image *srgb_out) {
  jnd_image cr = {0}, srgb = {0};
  jnd_status s = crop(linear, v->x0, v->y0, v->w, v->h, &cr);
  if (s == JND_OK) s = jnd_render_to_srgb(&cr, &srgb);
  if (s == JND_OK) s = jnd_display_apply(&c->p->model.display, &srgb, JND_ENCODING_SRGB, 0, cdm2);
  jnd_image_free(&cr);
  if (s == JND_OK && srgb_out) *srgb_out = srgb;
  else jnd_image_free(&srgb);
  return s;
}

static jnd_status render_ref(ctx *c, const jnd_view *view, view_ref *v, jnd_frame *f) {
  jnd_view vv = *view;
  vv.outputs = JND_OUT_COLOR | JND_OUT_MASK | JND_OUT_MIP;
  memset(f, 0, sizeof *f);
  jnd_status s = jnd_render(c->r, c->scene, &vv, f);
  if (s != JND_OK) return s;
  c->res->renderings++;
  int W = f->mask.w, H = f->mask.h, x0 = W, y0 = H, x1 = -1, y1 = -1;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++)
      if (f->mask.data[(size_t)y * W + x] > 0.5f) {
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
      }
  if (x1 < 0) x0 = y0 = 0, x1 = W - 1, y1 = H - 1; /* nothing on screen: the whole frame */
  v->x0 = jnd_clampi(x0 - CROP_MARGIN, 0, W - 1);
  v->y0 = jnd_clampi(y0 - CROP_MARGIN, 0, H - 1);
  v->w = jnd_clampi(x1 + CROP_MARGIN, 0, W - 1) - v->x0 + 1;
  v->h = jnd_clampi(y1 + CROP_MARGIN, 0, H - 1) - v->y0 + 1;
  if ((s = seen(c, &f->color, v, &v->ref, &v->ref_srgb)) != JND_OK) return s;
  return crop(&f->mask, v->x0, v->y0, v->w, v->h, &v->mask);
}

static void view_ref_free(view_ref *v) {
  jnd_image_free(&v->ref);
  jnd_image_free(&v->ref_srgb);
  jnd_image_free(&v->mask);
}

/* The mip level lev of a map as the driver makes it (000 §4: a map whose
 * level 0 is never sampled can drop it, and what remains is its own mip
 * chain): 2^lev × 2^lev boxes, colour averaged in linear light as GL does
 * for sRGB textures, everything else as stored. Used for the candidate at
 * the mip-usage bound, so that it renders as the reference does; smaller
 * candidates are Lanczos-3 (000 §4). */
static float srgb_decode(float v) { return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f); }
static float srgb_encode(float v) {
  v = v < 0 ? 0 : v > 1 ? 1 : v;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1 / 2.4f) - 0.055f;
}

static jnd_status box_mip(const jnd_image *orig, int lev, jnd_map_kind kind, jnd_image *out) {
  int w = orig->w >> lev, h = orig->h >> lev;
  jnd_status s = jnd_image_alloc(out, w, h, orig->c);
  if (s != JND_OK) return s;
  size_t n = (size_t)orig->w * orig->h;
  float *tmp = jnd_alloc(n, sizeof *tmp);
  if (!tmp) {
    jnd_image_free(out);
    return JND_ERR_NOMEM;
  }
  for (int ch = 0; ch < orig->c; ch++) {
    int colour = kind == JND_MAP_KIND_COLOR && ch < 3;
    const float *src = orig->data + (size_t)ch * n;
    for (size_t i = 0; i < n; i++) tmp[i] = colour ? srgb_decode(src[i]) : src[i];
    float *dst = out->data + (size_t)ch * w * h;
    pca_box_down(tmp, orig->w, orig->h, lev, dst);
    if (colour)
      for (size_t i = 0; i < (size_t)w * h; i++) dst[i] = srgb_encode(dst[i]);
  }
  free(tmp);
  return JND_OK;
}

/* The finest mip level the views are taken to sample: the shader's estimate
 * of the level (the reference formula of anisotropic filtering) can differ
 * from what a driver samples by up to half a level — derivatives are taken
 * per 2×2 quad and drivers approximate the anisotropic footprint — so the
 * bound keeps half a level of margin. Without it, a map cut at the estimated
 * level rendered visibly differently on llvmpipe. */
#define MIP_MARGIN 0.5
static int bound_level(const jnd_texres_map *m) {
  int lev = (int)floor(m->mip_min - MIP_MARGIN + 1e-6);
  return lev < 0 ? 0 : lev;
}

/* candidate k is the mip-usage bound and an exact level of the map's chain */
static int is_mip_level(const jnd_texres_map *m, int k) {
  if (m->cand[k][0] != m->mip_bound[0] || m->cand[k][1] != m->mip_bound[1] || bound_level(m) < 1) return 0;
  int lev = bound_level(m);
  return lev < 31 && (m->orig[0] >> lev) == m->cand[k][0] && (m->orig[1] >> lev) == m->cand[k][1] &&
         (m->orig[0] % (1 << lev)) == 0 && (m->orig[1] % (1 << lev)) == 0;
}

/* puts map i at candidate k (−1: the file's map); resampled maps are kept */
static jnd_status set_map(ctx *c, int i, int k) {
  map_state *m = &c->ms[i];
  const jnd_texres_map *tm = &c->res->maps[i];
  if (m->cur == k) return JND_OK;
  if (k < 0 || (tm->cand[k][0] == tm->orig[0] && tm->cand[k][1] == tm->orig[1])) {
    jnd_scene_map_restore(c->scene, tm->map);
  } else if (m->cache[k].data) {
    jnd_status s = jnd_scene_map_set(c->scene, tm->map, &m->cache[k]);
    if (s != JND_OK) return s;
  } else if (is_mip_level(tm, k)) {
    jnd_image orig = {0};
    int lev = 0;
    while ((tm->orig[0] >> lev) != tm->cand[k][0]) lev++;
    jnd_status s = jnd_scene_map_get(c->scene, tm->map, 1, &orig);
    if (s == JND_OK) s = box_mip(&orig, lev, jnd_map_slot_kind(tm->slot), &m->cache[k]);
    jnd_image_free(&orig);
    if (s == JND_OK) s = jnd_scene_map_set(c->scene, tm->map, &m->cache[k]);
    if (s != JND_OK) return s;
  } else {
    jnd_status s = jnd_scene_map_resize(c->scene, tm->map, tm->cand[k][0], tm->cand[k][1]);
    if (s == JND_OK) s = jnd_scene_map_get(c->scene, tm->map, 0, &m->cache[k]);
    if (s != JND_OK) return s;
  }
  m->cur = k;
  return JND_OK;
}

/* pooled P of one view with the maps as they are now; jnd_keep (optional)
 * receives the JND map */
static jnd_status eval_view(ctx *c, const jnd_view *view, const view_ref *v, double *P, jnd_image *jnd_keep) {
  jnd_view vv = *view;
  vv.outputs = JND_OUT_COLOR;
  jnd_frame f = {0};
  jnd_status s = jnd_render(c->r, c->scene, &vv, &f);
  if (s != JND_OK) return s;
  c->res->renderings++;
  jnd_image test = {0}, map = {0};
  s = seen(c, &f.color, v, &test, NULL);
  jnd_frame_free(&f);
  if (s == JND_OK) s = jnd_model_diff(c->m, &v->ref, &test, NULL, &map);
  jnd_image_free(&test);
  if (s != JND_OK) return s;
  *P = jnd_calibration_pool(&c->p->calibration, &map, &v->mask);
  if (!isfinite(*P)) *P = 0; /* no pixel of the object: nothing to see */
  if (jnd_keep) *jnd_keep = map;
  else jnd_image_free(&map);
  progress(c);
  return JND_OK;
}

/* the criterion statistic (000 §9, jnd_criterion_eval): "statistic <= p" is
 * exactly "at most a fraction q of the views above p" */
static double criterion_stat(const ctx *c, const double *P, int n) {
  jnd_criterion_result r;
  if (jnd_criterion_eval(P, n, c->p->p_threshold, c->p->max_fraction, 0.9, &r) != JND_OK) return INFINITY;
  return r.statistic;
}

/* all views with candidate sizes k[i] (−1: file's map); P[nviews] */
static jnd_status eval_combo(ctx *c, const int *k_in, const jnd_view *views, const view_ref *refs, int nviews,
                             double *P, double *stat) {
  jnd_status s;
  int nm = c->res->nmaps, use_cache = views == c->cache_views;
  int k[JND_TEXRES_MAX_MAPS];
  for (int i = 0; i < nm; i++) {
    const jnd_texres_map *m = &c->res->maps[i];
    k[i] = k_in[i] >= 0 && m->cand[k_in[i]][0] == m->orig[0] && m->cand[k_in[i]][1] == m->orig[1] ? -1 : k_in[i];
  }
  if (use_cache)
    for (int e = 0; e < c->ncache; e++)
      if (memcmp(c->cache_k + (size_t)e * nm, k, (size_t)nm * sizeof *k) == 0) {
        memcpy(P, c->cache_p + (size_t)e * nviews, (size_t)nviews * sizeof *P);
        *stat = criterion_stat(c, P, nviews);
        return JND_OK;
      }
  for (int i = 0; i < nm; i++)
    if ((s = set_map(c, i, k[i])) != JND_OK) return s;
  c->res->evaluations++;
  for (int v = 0; v < nviews; v++)
    if ((s = eval_view(c, &views[v], &refs[v], &P[v], NULL)) != JND_OK) return s;
  *stat = criterion_stat(c, P, nviews);
  if (use_cache) {
    if (c->ncache == c->capcache) {
      int cap = c->capcache ? 2 * c->capcache : 64;
      int *nk = realloc(c->cache_k, (size_t)cap * nm * sizeof *nk);
      if (nk) c->cache_k = nk;
      double *np = realloc(c->cache_p, (size_t)cap * nviews * sizeof *np);
      if (np) c->cache_p = np;
      if (!nk || !np) return JND_OK; /* no room: just not cached */
      c->capcache = cap;
    }
    memcpy(c->cache_k + (size_t)c->ncache * nm, k, (size_t)nm * sizeof *k);
    memcpy(c->cache_p + (size_t)c->ncache * nviews, P, (size_t)nviews * sizeof *P);
    c->ncache++;
  }
  return JND_OK;
}

/* the longer side's candidates (descending) of a map */
static void make_candidates(const jnd_texres_params *p, jnd_texres_map *m) {
  int W = m->orig[0], H = m->orig[1], L = W > H ? W : H;
  int sides[64], n = 0;
  sides[n++] = L;
  if (p->sizes && p->nsizes > 0) {
    for (int i = 0; i < p->nsizes && n < 64; i++)
      if (p->sizes[i] < L && p->sizes[i] >= 1) sides[n++] = p->sizes[i];
  } else {
    for (int s = L / 2; s >= p->min_size && s >= 1 && n < 64; s /= 2) sides[n++] = s;
  }
  /* descending, unique */
  for (int i = 1; i < n; i++)
    for (int j = i; j > 0 && sides[j] > sides[j - 1]; j--) {
      int t = sides[j];
      sides[j] = sides[j - 1];
      sides[j - 1] = t;
    }
  m->ncand = 0;
  for (int i = 0; i < n && m->ncand < JND_TEXRES_MAX_CAND; i++) {
    if (m->ncand && sides[i] == m->cand[m->ncand - 1][W >= H ? 0 : 1]) continue;
    int s = sides[i], other = (int)lround((double)s * (W >= H ? H : W) / L);
    if (other < 1) other = 1;
    m->cand[m->ncand][0] = W >= H ? s : other;
    m->cand[m->ncand][1] = W >= H ? other : s;
    m->ncand++;
  }
}

static int longer(const int *wh) { return wh[0] > wh[1] ? wh[0] : wh[1]; }

static size_t map_bytes(const jnd_texres_map *m, const int *wh) {
  return jnd_texture_bytes(JND_TEX_RGBA8, wh[0], wh[1], 1);
}

/* is map i among those to search? */
static int wanted(const char *list, const jnd_map_info *mi) {
  if (!list || !*list) return 1;
  const char *slash = strrchr(mi->name, '/');
  const char *slot = slash ? slash + 1 : mi->name;
  const char *s = list;
  while (*s) {
    const char *e = strchr(s, ',');
    size_t n = e ? (size_t)(e - s) : strlen(s);
    if ((strlen(mi->name) == n && strncmp(mi->name, s, n) == 0) || (strlen(slot) == n && strncmp(slot, s, n) == 0) ||
        (n > 2 && strncmp(s, "*/", 2) == 0 && strlen(slot) == n - 2 && strncmp(slot, s + 2, n - 2) == 0))
      return 1;
    if (!e) break;
    s = e + 1;
  }
  return 0;
}

/* every name in the list must name a map or a slot */
static jnd_status check_list(const jnd_scene *scene, const char *list) {
  if (!list || !*list) return JND_OK;
  const char *s = list;
  while (*s) {
    const char *e = strchr(s, ',');
    size_t n = e ? (size_t)(e - s) : strlen(s);
    char name[160];
    snprintf(name, sizeof name, "%.*s", (int)(n < 150 ? n : 150), s);
    int hit = 0;
    for (int i = 0; i < jnd_scene_map_count(scene) && !hit; i++) {
      jnd_map_info mi;
      jnd_scene_map_info(scene, i, &mi);
      hit = wanted(name, &mi);
    }
    if (!hit) {
      int is_slot = 0;
      const char *bare = strncmp(name, "*/", 2) == 0 ? name + 2 : name;
      for (int k = 0; k < JND_MAP_SLOTS; k++) is_slot |= strcmp(bare, jnd_map_slot_name((jnd_map_slot)k)) == 0;
      return jnd_fail(JND_ERR_ARG, "%s: %s '%s' (maps are MATERIAL/SLOT, slots %s, %s, %s, %s, %s)",
                      jnd_scene_path(scene), is_slot ? "no map in slot" : "no such map or slot", name,
                      jnd_map_slot_name(0), jnd_map_slot_name(1), jnd_map_slot_name(2), jnd_map_slot_name(3),
                      jnd_map_slot_name(4));
    }
    if (!e) break;
    s = e + 1;
  }
  return JND_OK;
}

static jnd_status sample_views(const jnd_scene *scene, const jnd_texres_params *p, int count, uint64_t seed,
                               jnd_view **out) {
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = count;
  vs.seed = seed;
  vs.coverage = p->coverage;
  vs.distance = p->distance;
  vs.fov_y_deg = p->fov_y_deg;
  vs.aspect = (double)p->width / p->height;
  vs.lights = p->lights;
  *out = jnd_calloc((size_t)count, sizeof **out);
  if (!*out) return JND_ERR_NOMEM;
  return jnd_views_sample(scene, &vs, *out);
}

/* mip bound and eye bound of map m from the finest level any pixel samples */
static void bounds_from_level(const jnd_texres_params *p, jnd_texres_map *m) {
  int L = longer(m->orig);
  if (m->mip_min < 0) { /* never on screen: nothing to see at any size */
    m->mip_bound[0] = m->cand[m->ncand - 1][0];
    m->mip_bound[1] = m->cand[m->ncand - 1][1];
    m->eye_bound[0] = m->mip_bound[0];
    m->eye_bound[1] = m->mip_bound[1];
    return;
  }
  int lev = bound_level(m);
  for (int k = 0; k < 2; k++) {
    m->mip_bound[k] = m->orig[k] >> lev;
    if (m->mip_bound[k] < 1) m->mip_bound[k] = 1;
  }
  /* the eye resolves at most 60 cpd, the display at most its Nyquist limit
   * ppd/2: a texel smaller than 1/(2·cmax) degree is never resolved. At the
   * finest pixel a texel of the full map is 2^−mip_min pixels = 1/(ppd·2^mip)
   * degrees across. */
  double ppd = p->model.display.ppd, cmax = fmin(60.0, ppd / 2);
  double factor = pow(2.0, m->mip_min) * ppd / (2 * cmax);
  for (int k = 0; k < 2; k++) {
    m->eye_bound[k] = (int)ceil(m->orig[k] / factor - 1e-9);
    if (m->eye_bound[k] < 1) m->eye_bound[k] = 1;
  }
  (void)L;
}

/* the mip bound becomes a candidate when it is not one (explicit --sizes,
 * a bound under the floor), so that the search can start exactly there */
static void insert_bound(jnd_texres_map *m) {
  int Lb = longer(m->mip_bound), at = m->ncand;
  for (int k = 0; k < m->ncand; k++) {
    if (longer(m->cand[k]) == Lb) return;
    if (longer(m->cand[k]) < Lb && at == m->ncand) at = k;
  }
  if (m->ncand >= JND_TEXRES_MAX_CAND) return;
  for (int k = m->ncand; k > at; k--) {
    m->cand[k][0] = m->cand[k - 1][0];
    m->cand[k][1] = m->cand[k - 1][1];
  }
  m->cand[at][0] = m->mip_bound[0];
  m->cand[at][1] = m->mip_bound[1];
  m->ncand++;
}

/* restricts candidates to those within the mip bound; returns the index of
 * the first allowed one */
static int first_allowed(const jnd_texres_map *m) {
  int Lb = longer(m->mip_bound);
  for (int k = 0; k < m->ncand; k++)
    if (longer(m->cand[k]) <= Lb) return k;
  return m->ncand - 1;
}

static int last_evaluated(const jnd_texres_map *m) {
  int last = 0;
  for (int j = 0; j < m->ncand; j++)
    if (isfinite(m->series[j])) last = j;
  return last;
}

static jnd_status run_matrix(ctx *c, int ia, int ib, const jnd_view *views, const view_ref *refs, int nviews,
                             const int *start, jnd_texres_matrix *mx) {
  jnd_texres_result *R = c->res;
  const jnd_texres_map *A = &R->maps[ia], *B = &R->maps[ib];
  int a0 = start[ia], b0 = start[ib];
  memset(mx, 0, sizeof *mx);
  mx->map_a = ia;
  mx->map_b = ib;
  mx->na = A->ncand - a0;
  mx->nb = B->ncand - b0;
  if (c->p->matrix < 2) {
    /* down to each map's first failure on its own: smaller sizes of either
     * map fail alone already, so their cells only add time */
    mx->na = last_evaluated(A) - a0 + 1;
    mx->nb = last_evaluated(B) - b0 + 1;
    mx->complete = A->ncand - a0 == mx->na && B->ncand - b0 == mx->nb;
  } else {
    mx->complete = 1;
  }
  mx->nviews = nviews;
  for (int a = 0; a < mx->na; a++) mx->size_a[a] = longer(A->cand[a0 + a]);
  for (int b = 0; b < mx->nb; b++) mx->size_b[b] = longer(B->cand[b0 + b]);
  mx->p = jnd_calloc((size_t)nviews * mx->na * mx->nb, sizeof *mx->p);
  mx->stat = jnd_calloc((size_t)mx->na * mx->nb, sizeof *mx->stat);
  if (!mx->p || !mx->stat) return JND_ERR_NOMEM;
  int *k = jnd_calloc((size_t)R->nmaps, sizeof *k);
  double *P = jnd_calloc((size_t)nviews, sizeof *P);
  if (!k || !P) {
    free(k);
    free(P);
    return JND_ERR_NOMEM;
  }
  for (int i = 0; i < R->nmaps; i++) k[i] = -1;
  mx->best_a = mx->best_b = -1;
  size_t best_bytes = (size_t)-1;
  jnd_status s = JND_OK;
  for (int a = 0; a < mx->na && s == JND_OK; a++)
    for (int b = 0; b < mx->nb && s == JND_OK; b++) {
      k[ia] = a0 + a;
      k[ib] = b0 + b;
      double st;
      if ((s = eval_combo(c, k, views, refs, nviews, P, &st)) != JND_OK) break;
      for (int v = 0; v < nviews; v++) mx->p[((size_t)v * mx->na + a) * mx->nb + b] = P[v];
      mx->stat[a * mx->nb + b] = st;
      size_t bytes = map_bytes(A, A->cand[a0 + a]) + map_bytes(B, B->cand[b0 + b]);
      if (st <= c->p->p_threshold && bytes < best_bytes) {
        best_bytes = bytes;
        mx->best_a = a;
        mx->best_b = b;
      }
    }
  free(k);
  free(P);
  return s;
}

/* The renderer and the vision model of a run. On a CPU rasteriser (llvmpipe,
 * softpipe) the model's OpenMP workers would spin against the rasteriser's
 * threads between frames (8× slower on 2 cores): one model thread is faster
 * there unless threads were asked for. */
static jnd_status open_renderer_and_model(const jnd_texres_params *p, jnd_renderer **r, jnd_model **m) {
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = p->width;
  rp.height = p->height;
  rp.samples = p->samples;
  rp.anisotropy = p->anisotropy;
  rp.env_path = p->env_path;
  rp.platform = p->platform;
  jnd_status s = jnd_renderer_create(&rp, r);
  if (s != JND_OK) return s;
  jnd_model_params mp = p->model;
  const char *desc = jnd_renderer_description(*r);
  if (mp.threads == 0 && (strstr(desc, "llvmpipe") || strstr(desc, "softpipe"))) mp.threads = 1;
  return jnd_model_create(&mp, m);
}

jnd_status jnd_texres_run(jnd_scene *scene, const jnd_texres_params *pp, jnd_texres_result *out) {
  memset(out, 0, sizeof *out);
  jnd_texres_params pd;
  if (!pp) {
    jnd_texres_defaults(&pd);
    pp = &pd;
  }
  const jnd_texres_params *p = pp;
  if (p->views < 1 || p->width < 8 || p->height < 8 || !(p->p_threshold > 0 && p->p_threshold < 1) ||
      !(p->max_fraction >= 0 && p->max_fraction < 1) || p->min_size < 1 || p->verify_views < 0)
    return jnd_fail(JND_ERR_ARG, "texres: parameters out of range");
  int nall = jnd_scene_map_count(scene);
  if (nall == 0) return jnd_fail(JND_ERR_ARG, "%s: the asset has no texture maps", jnd_scene_path(scene));
  if (nall > JND_TEXRES_MAX_MAPS)
    return jnd_fail(JND_ERR_LIMIT, "%s: %d texture maps (at most %d)", jnd_scene_path(scene), nall, JND_TEXRES_MAX_MAPS);
  jnd_status s = check_list(scene, p->maps);
  if (s != JND_OK) return s;

  ctx c = {scene, p, NULL, NULL, out, NULL, 0, 0, 0, 0, NULL, NULL, NULL};
  jnd_view *views = NULL, *vviews = NULL;
  view_ref *refs = NULL, *vrefs = NULL;
  double *P = NULL;
  int *k = NULL, *start = NULL;
  int N = p->views, nsearch = 0;
  out->nmaps = nall;
  out->maps = jnd_calloc((size_t)nall, sizeof *out->maps);
  c.ms = jnd_calloc((size_t)nall, sizeof *c.ms);
  if (!out->maps || !c.ms) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  for (int i = 0; i < nall; i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    jnd_scene_map_restore(scene, i);
    jnd_texres_map *m = &out->maps[i];
    snprintf(m->name, sizeof m->name, "%s", mi.name);
    m->map = i;
    m->material = mi.material;
    m->slot = mi.slot;
    m->channels = mi.channels;
    m->orig[0] = mi.orig_width;
    m->orig[1] = mi.orig_height;
    m->searched = wanted(p->maps, &mi);
    nsearch += m->searched;
    make_candidates(p, m);
    m->mip_min = INFINITY;
    for (int j = 0; j < JND_TEXRES_MAX_CAND; j++) m->series[j] = NAN;
    c.ms[i].cur = -1;
  }
  out->ppd = p->model.display.ppd;

  if ((s = open_renderer_and_model(p, &c.r, &c.m)) != JND_OK) goto done;
  snprintf(out->renderer, sizeof out->renderer, "%s", jnd_renderer_description(c.r));

  /* views and their reference renderings (full resolution), mip levels */
  if ((s = sample_views(scene, p, N, p->seed, &views)) != JND_OK) goto done;
  c.cache_views = views;
  refs = jnd_calloc((size_t)N, sizeof *refs);
  P = jnd_calloc((size_t)(N > p->verify_views ? N : p->verify_views) + 1, sizeof *P);
  k = jnd_calloc((size_t)nall, sizeof *k);
  start = jnd_calloc((size_t)nall, sizeof *start);
  if (!refs || !P || !k || !start) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  /* progress estimate: references, series, a combination or two, matrices */
  c.total = N * (1 + 2) + p->verify_views * 2;
  for (int i = 0; i < nall; i++) c.total += out->maps[i].searched ? N * out->maps[i].ncand : 0;
  for (int v = 0; v < N; v++) {
    jnd_frame f;
    if ((s = render_ref(&c, &views[v], &refs[v], &f)) != JND_OK) {
      jnd_frame_free(&f);
      goto done;
    }
    size_t px = (size_t)f.mip.w * f.mip.h;
    for (int i = 0; i < nall; i++) {
      jnd_texres_map *m = &out->maps[i];
      const float *lv = f.mip.data + (size_t)m->slot * px;
      for (size_t q = 0; q < px; q++)
        if (lv[q] >= 0 && (int)lroundf(f.material.data[q]) == m->material && lv[q] < m->mip_min) m->mip_min = lv[q];
    }
    jnd_frame_free(&f);
    progress(&c);
  }
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i];
    if (!isfinite(m->mip_min)) m->mip_min = -1;
    bounds_from_level(p, m);
    if (m->mip_min >= 0) insert_bound(m);
    start[i] = first_allowed(m);
  }

  /* per-map series from the bound down */
  for (int i = 0; i < nall; i++) k[i] = -1;
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i];
    if (!m->searched) {
      m->chosen[0] = m->orig[0];
      m->chosen[1] = m->orig[1];
      continue;
    }
    int choice = start[i];
    for (int j = start[i]; j < m->ncand; j++) {
      double st;
      if (m->cand[j][0] == m->orig[0] && m->cand[j][1] == m->orig[1]) {
        st = 0; /* the reference itself */
      } else {
        k[i] = j;
        if ((s = eval_combo(&c, k, views, refs, N, P, &st)) != JND_OK) goto done;
      }
      m->series[j] = st;
      if (st > p->p_threshold) break;
      choice = j;
    }
    k[i] = -1;
    m->chosen[0] = m->cand[choice][0];
    m->chosen[1] = m->cand[choice][1];
    /* 000 eq. 1 over the series, in log2 resolution (docs/texres.md) */
    double rr[JND_TEXRES_MAX_CAND], pp2[JND_TEXRES_MAX_CAND];
    int n = 0;
    for (int j = 0; j < m->ncand; j++)
      if (isfinite(m->series[j])) rr[n] = longer(m->cand[j]), pp2[n++] = m->series[j];
    if (n >= 2 && jnd_psychometric_fit(rr, pp2, n, 1, &m->fit) == JND_OK) {
      m->fit_ok = 1;
      m->fit_res = jnd_psychometric_resolution(&m->fit, p->p_threshold);
      int best = start[i];
      for (int j = start[i]; j < m->ncand; j++)
        if (longer(m->cand[j]) >= m->fit_res - 1e-6) best = j;
      m->fit_cand[0] = m->cand[best][0];
      m->fit_cand[1] = m->cand[best][1];
    }
  }

  /* the choices together; enlarge while the combination fails */
  for (int i = 0; i < nall; i++) {
    k[i] = -1;
    if (!out->maps[i].searched) continue;
    for (int j = 0; j < out->maps[i].ncand; j++)
      if (out->maps[i].cand[j][0] == out->maps[i].chosen[0] && out->maps[i].cand[j][1] == out->maps[i].chosen[1])
        k[i] = j;
  }
  double stat;
  if ((s = eval_combo(&c, k, views, refs, N, P, &stat)) != JND_OK) goto done;
  for (int round = 0; stat > p->p_threshold && round < 64; round++) {
    int best_i = -1;
    double best_stat = INFINITY;
    for (int i = 0; i < nall; i++) {
      if (!out->maps[i].searched || k[i] <= start[i]) continue;
      k[i]--;
      double st;
      s = eval_combo(&c, k, views, refs, N, P, &st);
      k[i]++;
      if (s != JND_OK) goto done;
      if (st < best_stat) best_stat = st, best_i = i;
    }
    if (best_i < 0) break; /* every map at its bound */
    k[best_i]--;
    if ((s = eval_combo(&c, k, views, refs, N, P, &stat)) != JND_OK) goto done;
  }
  for (int i = 0; i < nall; i++)
    if (out->maps[i].searched && k[i] >= 0) {
      out->maps[i].chosen[0] = out->maps[i].cand[k[i]][0];
      out->maps[i].chosen[1] = out->maps[i].cand[k[i]][1];
    }

  /* the matrices of 000 Fig. 13 */
  if (p->matrix) {
    int nm = jnd_scene_material_count(scene);
    out->matrix = jnd_calloc((size_t)nm + 1, sizeof *out->matrix);
    if (!out->matrix) {
      s = JND_ERR_NOMEM;
      goto done;
    }
    for (int mat = 0; mat < nm; mat++) {
      int ia = -1, ib = -1;
      for (int i = 0; i < nall; i++) {
        if (out->maps[i].material != mat || !out->maps[i].searched) continue;
        if (out->maps[i].slot == JND_MAP_BASE_COLOR) ia = i;
        if (out->maps[i].slot == JND_MAP_NORMAL) ib = i;
      }
      if (ia < 0 || ib < 0) continue;
      c.total += N * (out->maps[ia].ncand - start[ia]) * (out->maps[ib].ncand - start[ib]);
      s = run_matrix(&c, ia, ib, views, refs, N, start, &out->matrix[out->nmatrix]);
      out->nmatrix++;
      if (s != JND_OK) goto done;
      /* with exactly these two maps searched the matrix is the search */
      jnd_texres_matrix *mx = &out->matrix[out->nmatrix - 1];
      if (nsearch == 2 && mx->best_a >= 0) {
        k[ia] = start[ia] + mx->best_a;
        k[ib] = start[ib] + mx->best_b;
        for (int q = 0; q < 2; q++) {
          int i = q ? ib : ia;
          out->maps[i].chosen[0] = out->maps[i].cand[k[i]][0];
          out->maps[i].chosen[1] = out->maps[i].cand[k[i]][1];
        }
      }
    }
  }

  /* verification of the final combination on every view */
  out->nviews = N;
  out->view_p = jnd_calloc((size_t)N, sizeof *out->view_p);
  if (!out->view_p) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  if ((s = eval_combo(&c, k, views, refs, N, out->view_p, &out->stat)) != JND_OK) goto done;
  jnd_criterion_result cr;
  if ((s = jnd_criterion_eval(out->view_p, N, p->p_threshold, p->max_fraction, 0.9, &cr)) != JND_OK) goto done;
  out->worst_view = cr.worst_view;
  out->fraction_above = cr.fraction_above;
  out->passes = cr.pass;
  {
    /* the choice on the scene: eval_combo answers a combination it has seen
     * from its cache without setting the maps, and the matrices leave their
     * last pair set, so the worst view would show other sizes */
    for (int i = 0; i < nall; i++)
      if ((s = set_map(&c, i, k[i])) != JND_OK) goto done;
    jnd_image map = {0};
    double pw;
    if ((s = eval_view(&c, &views[out->worst_view], &refs[out->worst_view], &pw, &map)) != JND_OK) goto done;
    s = texres_worst_view_figure(&refs[out->worst_view].ref_srgb, &map, out->worst_view, N, out->view_p[out->worst_view],
                                 &out->worst_heatmap);
    jnd_image_free(&map);
    if (s != JND_OK) goto done;
  }

  /* held-out views: references at full resolution, then the choice */
  if (p->verify_views > 0) {
    int M = p->verify_views;
    out->verify_views = M;
    out->verify_p = jnd_calloc((size_t)M, sizeof *out->verify_p);
    vrefs = jnd_calloc((size_t)M, sizeof *vrefs);
    if (!out->verify_p || !vrefs) {
      s = JND_ERR_NOMEM;
      goto done;
    }
    /* another seed: a different rotation of the spiral and other lights */
    if ((s = sample_views(scene, p, M, p->seed * 7919u + 104729u, &vviews)) != JND_OK) goto done;
    for (int i = 0; i < nall; i++)
      if ((s = set_map(&c, i, -1)) != JND_OK) goto done;
    for (int v = 0; v < M; v++) {
      jnd_frame f;
      s = render_ref(&c, &vviews[v], &vrefs[v], &f);
      jnd_frame_free(&f);
      if (s != JND_OK) goto done;
      progress(&c);
    }
    double st;
    if ((s = eval_combo(&c, k, vviews, vrefs, M, out->verify_p, &st)) != JND_OK) goto done;
    if ((s = jnd_criterion_eval(out->verify_p, M, p->p_threshold, p->max_fraction, 0.9, &cr)) != JND_OK) goto done;
    out->verify_fraction = cr.fraction_above;
    out->verify_passes = cr.pass;
  }

  /* memory before and after, with mip chains */
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i];
    for (int f = 0; f < JND_TEX_FORMATS; f++) {
      m->bytes_before[f] = jnd_texture_bytes((jnd_tex_format)f, m->orig[0], m->orig[1], 1);
      m->bytes_after[f] = jnd_texture_bytes((jnd_tex_format)f, m->chosen[0], m->chosen[1], 1);
      out->before_bytes[f] += m->bytes_before[f];
      out->after_bytes[f] += m->bytes_after[f];
    }
  }
  /* leave the scene with the chosen maps */
  for (int i = 0; i < nall; i++) {
    int j = -1;
    for (int q = 0; q < out->maps[i].ncand; q++)
      if (out->maps[i].cand[q][0] == out->maps[i].chosen[0] && out->maps[i].cand[q][1] == out->maps[i].chosen[1]) j = q;
    if ((s = set_map(&c, i, j)) != JND_OK) goto done;
  }
  s = JND_OK;
done:
  if (refs)
    for (int v = 0; v < N; v++) view_ref_free(&refs[v]);
  if (vrefs)
    for (int v = 0; v < p->verify_views; v++) view_ref_free(&vrefs[v]);
  if (c.ms)
    for (int i = 0; i < nall; i++)
      for (int j = 0; j < JND_TEXRES_MAX_CAND; j++) jnd_image_free(&c.ms[i].cache[j]);
  free(c.ms);
  free(c.cache_k);
  free(c.cache_p);
  free(refs);
  free(vrefs);
  free(views);
  free(vviews);
  free(P);
  free(k);
  free(start);
  jnd_model_free(c.m);
  jnd_renderer_free(c.r);
  if (s != JND_OK) jnd_texres_result_free(out);
  return s;
}

/* ---- the model's JND series of one map, for calibration (000 §6–§7) ---- */

jnd_status jnd_texres_series_percentiles(jnd_scene *scene, const char *map, const int *sizes, int nres,
                                         const jnd_texres_params *p, double *out) {
  int mi_idx = jnd_scene_map_find(scene, map);
  if (mi_idx < 0) return jnd_fail(JND_ERR_ARG, "%s: no map %s", jnd_scene_path(scene), map);
  if (nres < 1 || !sizes || p->views < 1) return jnd_fail(JND_ERR_ARG, "%s: no sizes or views", map);
  jnd_map_info mi;
  jnd_scene_map_info(scene, mi_idx, &mi);
  jnd_texres_result res = {0};
  res.nmaps = 0;
  ctx c = {scene, p, NULL, NULL, &res, NULL, 0, 0, 0, 0, NULL, NULL, NULL};
  jnd_view *views = NULL;
  view_ref *refs = NULL;
  float *all = NULL;
  jnd_status s;
  if ((s = open_renderer_and_model(p, &c.r, &c.m)) != JND_OK) goto done;
  if ((s = sample_views(scene, p, p->views, p->seed, &views)) != JND_OK) goto done;
  refs = jnd_calloc((size_t)p->views, sizeof *refs);
  if (!refs) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  jnd_scene_map_restore(scene, mi_idx);
  size_t total = 0;
  for (int v = 0; v < p->views; v++) {
    jnd_frame f;
    s = render_ref(&c, &views[v], &refs[v], &f);
    jnd_frame_free(&f);
    if (s != JND_OK) goto done;
    total += (size_t)refs[v].w * refs[v].h;
  }
  all = jnd_alloc(total ? total : 1, sizeof *all);
  if (!all) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  int L = mi.orig_width > mi.orig_height ? mi.orig_width : mi.orig_height;
  for (int r = 0; r < nres; r++) {
    int w = (int)lround((double)sizes[r] * mi.orig_width / L), h = (int)lround((double)sizes[r] * mi.orig_height / L);
    if ((s = jnd_scene_map_resize(scene, mi_idx, w < 1 ? 1 : w, h < 1 ? 1 : h)) != JND_OK) goto done;
    size_t n = 0;
    for (int v = 0; v < p->views; v++) {
      jnd_image jm = {0};
      double P;
      if ((s = eval_view(&c, &views[v], &refs[v], &P, &jm)) != JND_OK) goto done;
      size_t px = (size_t)jm.w * jm.h;
      for (size_t q = 0; q < px; q++)
        if (refs[v].mask.data[q] > 0.5f) all[n++] = jm.data[q];
      jnd_image_free(&jm);
    }
    /* percentiles over the object's pixels of every view together */
    jnd_image pooled = {(int)(n ? n : 1), 1, 1, all};
    if (!n) all[0] = 0;
    if ((s = jnd_calib_percentiles(&pooled, NULL, out + (size_t)r * JND_CALIB_NPCT)) != JND_OK) goto done;
  }
  jnd_scene_map_restore(scene, mi_idx);
done:
  if (refs)
    for (int v = 0; v < p->views; v++) view_ref_free(&refs[v]);
  free(refs);
  free(views);
  free(all);
  jnd_model_free(c.m);
  jnd_renderer_free(c.r);
  return s;
}
