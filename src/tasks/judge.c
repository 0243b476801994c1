/* The judge: the one rendered judgement every task asks for (DESIGN.md, "the
 * one idea"). Per view, in order:
 *   1. the reference: the scene as it was when the judge was made, rendered
 *      once with its coverage mask, mip levels (000 §4) and, when the view
 *      moves, its motion; the crop is the object's bounding box (a ground
 *      plane excluded) plus a margin for the model's pyramid;
 *   2. a state: the scene as it is now, recognised by the content of its
 *      maps and the identity of its meshes, so that a state judged before
 *      is answered from memory;
 *   3. its rendering: whole, or only the samples of the materials whose
 *      maps changed, composed with the reference (renderer.c explains why
 *      this equals the whole rendering);
 *   4. as the viewer sees it: clamped, sRGB-encoded and through the display
 *      model to cd/m² (004 §3.1, first stage);
 *   5. the JND map of the vision model against the reference (004 §3.1–3.2);
 *   6. the calibration's JND transform and psychometric function (000 §7.1,
 *      eq. 4), pooled with its percentile (000 §6: P93) over the object's
 *      pixels: the view's P;
 *   7. the criterion over the views (000 §9, jnd_criterion_eval). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tasks/tasks.h"


/* One material's samples in a view's reference, for partial re-renders. */
typedef struct {
  int x0, y0, w, h;      /* rectangle of its samples in the frame (w = 0: none) */
  jnd_image old;         /* w × h × 4: resolved samples under the reference maps, coverage */
  double weight;         /* its coverage in pixels: how much a change of it can show */
} mat_part;

typedef struct {
  jnd_view view;
  int x0, y0, w, h;      /* the crop in the frame */
  jnd_image ref_lin;     /* reference, linear RGB, crop */
  jnd_image ref_cdm2;    /* reference as seen, cd/m², crop */
  jnd_image mask;        /* object coverage (the ground left out), crop */
  jnd_image motion;      /* screen displacement, crop (only for a view that moves) */
  short *material;       /* material index per crop pixel (-1: none), from the reference */
  unsigned depth;        /* the reference's multisampled depth (0: none) */
  mat_part *part;        /* per material (partial mode) */
  double *mip_min;       /* per map: the finest level sampled, INFINITY if none */
  double cx, cy;         /* the centre of the object's bounding box in the frame (the frame's: nothing seen) */
  int has_gaze;          /* 1: this view's own fixation point (gaze_x, gaze_y: pixels of the frame) */
  double gaze_x, gaze_y;
  int twin;              /* 1 + an earlier view it equals (same_view), whose reference and judgements
                            it shares: no data of its own; 0: its own */
} jview;

typedef struct {
  uint64_t sum;          /* hash of the key, to compare cheaply first */
  uint64_t *key;         /* nkey */
  double *p;             /* P per view, NaN where not judged */
  int *above;            /* per view × material: object pixels with P > p (where p[v] is known) */
} jstate;

/* A material's samples rendered in one view under one state of its maps:
 * a state of the scene is the reference plus, per changed material, such a
 * rendering, so a material is rendered again only when its own maps change
 * (a descent that enlarges one map re-renders one material). */
typedef struct {
  uint64_t key;          /* the material's maps' state */
  int view, material;
  jnd_image img;         /* over the material's rectangle (mat_part), 3 channels */
} mat_render;

#define RENDER_CACHE_BYTES ((size_t)256 << 20)   /* kept material renderings, oldest dropped first */

struct jnd_judge {
  jnd_scene *scene;
  jnd_judge_params p;
  jnd_renderer *r;
  int own_r;   /* r is the judge's (not p.renderer, borrowed) */
  jnd_model *m;
  int ground;            /* the ground plane's material or -1 */
  int blend_any;         /* a blended material: no partial re-renders */
  int threads;           /* OpenMP threads while the judge works (1 on a CPU rasteriser; 0: default) */
  jview *v;
  int nv, capv;
  int nmaps, nkey;       /* key: a hash per map, then one per mesh */
  int *map_material;     /* per map: its material */
  uint64_t *ref_key, *cur_key, *hashed_version;
  jnd_image *ref_maps;   /* per map: its reference image when that was not the file's */
  int *ref_level;        /* per mesh: the level of detail it was drawn at in the reference */
  jstate *st;
  int nst, capst;
  mat_render *mr;        /* a ring of kept material renderings */
  int nmr, capmr, nextmr;
  size_t mr_bytes;
  uint64_t *mat_key;     /* per material: the state of its maps now */
  jnd_judge_counts counts;
};

/* the view whose reference and judgements view v's are (itself unless a twin) */
static int own(const jnd_judge *j, int v) { return j->v[v].twin ? j->v[v].twin - 1 : v; }

void jnd_judge_defaults(jnd_judge_params *p) {
  memset(p, 0, sizeof *p);
  jnd_view_set_defaults(&p->views);
  p->views.render.width = p->views.render.height = 384;
  jnd_model_defaults(&p->model);
  jnd_calibration_defaults(&p->calibration);
  jnd_criterion_defaults(&p->criterion);
  p->partial = 1;
}

/* ---- states ---- */

/* A 64-bit digest of an image's size and samples. */
static uint64_t image_hash(const jnd_image *img) {
  uint64_t h = jnd_mix64(((uint64_t)img->w << 40) ^ ((uint64_t)img->h << 16) ^ (uint64_t)img->c);
  size_t n = (size_t)img->w * img->h * img->c, i = 0;
  const float *d = img->data;
  for (; i + 2 <= n; i += 2) {
    uint64_t w;
    memcpy(&w, d + i, sizeof w);
    h = (h ^ w) * 0x9E3779B97F4A7C15ULL;
    h ^= h >> 29;
  }
  if (i < n) {
    uint32_t w;
    memcpy(&w, d + i, sizeof w);
    h = (h ^ w) * 0x9E3779B97F4A7C15ULL;
  }
  return jnd_mix64(h);
}

/* A mesh's identity: its version (a level of detail selected with
 * jnd_scene_lod_select gets its own), sizes, material, arrays and a few
 * vertices. A change of level is a change of geometry: rendered whole. */
static uint64_t mesh_key(const jnd_mesh *m) {
  uint64_t h = jnd_mix64(m->nverts * 0x100000001B3ULL ^ m->ntris ^ ((uint64_t)m->material << 48));
  h = jnd_mix64(h ^ m->version);
  h = jnd_mix64(h ^ (uint64_t)(uintptr_t)m->vertices) ^ jnd_mix64((uint64_t)(uintptr_t)m->indices);
  for (size_t v = 0; v < m->nverts && v < 16; v++) {
    uint32_t w;
    memcpy(&w, m->vertices + v * (m->nverts / 16 + 1) % (m->nverts ? m->nverts : 1) * JND_VTX_FLOATS, sizeof w);
    h = jnd_mix64(h ^ w);
  }
  return h;
}

/* the key of the scene's current state into cur_key (maps hashed again only
 * when their version moved) */
static void update_key(jnd_judge *j) {
  const jnd_scene *s = j->scene;
  for (int i = 0; i < j->nmaps; i++)
    if (j->hashed_version[i] != s->maps[i].version) {
      j->cur_key[i] = image_hash(jnd_map_image(&s->maps[i]));
      j->hashed_version[i] = s->maps[i].version;
    }
  for (int k = 0; k < s->nmeshes; k++) j->cur_key[j->nmaps + k] = mesh_key(&s->meshes[k]);
  for (int m = 0; m < s->nmaterials; m++) j->mat_key[m] = 0x51ED270B2F2BF7A5ULL ^ (uint64_t)m;
  for (int i = 0; i < j->nmaps; i++)
    if (j->map_material[i] >= 0) j->mat_key[j->map_material[i]] = jnd_mix64(j->mat_key[j->map_material[i]] ^ j->cur_key[i]) + (uint64_t)i;
}

static uint64_t key_sum(const uint64_t *key, int n) {
  uint64_t h = 0x243F6A8885A308D3ULL;
  for (int i = 0; i < n; i++) h = jnd_mix64(h ^ key[i]) + (uint64_t)i;
  return h;
}

/* the entry of the current state (cur_key), made when new */
static jstate *find_state(jnd_judge *j) {
  uint64_t sum = key_sum(j->cur_key, j->nkey);
  for (int e = 0; e < j->nst; e++)
    if (j->st[e].sum == sum && memcmp(j->st[e].key, j->cur_key, (size_t)j->nkey * sizeof *j->cur_key) == 0)
      return &j->st[e];
  if (j->nst == j->capst) {
    int cap = j->capst ? 2 * j->capst : 32;
    jstate *ns = realloc(j->st, (size_t)cap * sizeof *ns);
    if (!ns) return NULL;
    j->st = ns;
    j->capst = cap;
  }
  jstate *e = &j->st[j->nst];
  e->sum = sum;
  e->key = jnd_alloc((size_t)j->nkey, sizeof *e->key);
  e->p = jnd_alloc((size_t)(j->capv ? j->capv : 1), sizeof *e->p);
  e->above = jnd_calloc((size_t)(j->capv ? j->capv : 1) * (size_t)(j->scene->nmaterials + 1), sizeof *e->above);
  if (!e->key || !e->p || !e->above) {
    free(e->key);
    free(e->p);
    free(e->above);
    return NULL;
  }
  memcpy(e->key, j->cur_key, (size_t)j->nkey * sizeof *e->key);
  for (int v = 0; v < j->capv; v++) e->p[v] = NAN;
  j->nst++;
  j->counts.states++;
  return e;
}

static void forget_states(jnd_judge *j) {
  for (int e = 0; e < j->nst; e++) {
    free(j->st[e].key);
    free(j->st[e].p);
    free(j->st[e].above);
  }
  j->nst = 0;
}

/* What differs from the reference: changed[m] per material (a map of it
 * differs), *geometry (a mesh differs), *any. *partial_ok: the changes can
 * be rendered as only the changed materials' samples. */
typedef struct {
  unsigned char *changed;   /* per material */
  int geometry, any, partial_ok;
} change_set;

static void find_changes(const jnd_judge *j, change_set *c) {
  const jnd_scene *s = j->scene;
  memset(c->changed, 0, (size_t)s->nmaterials);
  c->geometry = c->any = 0;
  for (int i = 0; i < j->nmaps; i++)
    if (j->cur_key[i] != j->ref_key[i] && j->map_material[i] >= 0) c->changed[j->map_material[i]] = 1, c->any = 1;
  for (int k = j->nmaps; k < j->nkey; k++)
    if (j->cur_key[k] != j->ref_key[k]) c->geometry = c->any = 1;
  c->partial_ok = j->p.partial && !c->geometry && !j->blend_any;
  /* an alpha-masked material whose base colour (its alpha) changed may cover
   * other samples than in the reference */
  for (int m = 0; m < s->nmaterials && c->partial_ok; m++) {
    int bc = s->materials[m].map[JND_MAP_BASE_COLOR];
    if (c->changed[m] && s->materials[m].alpha_mode == JND_ALPHA_MASK && bc >= 0 && j->cur_key[bc] != j->ref_key[bc])
      c->partial_ok = 0;
  }
}

/* ---- images of a view ---- */

static jnd_status crop(const jnd_image *in, int x0, int y0, int w, int h, jnd_image *out) {
  jnd_status s = jnd_image_alloc(out, w, h, in->c);
  if (s != JND_OK) return s;
  for (int ch = 0; ch < in->c; ch++)
    for (int y = 0; y < h; y++)
      memcpy(out->data + ((size_t)ch * h + y) * w, in->data + ((size_t)ch * in->h + y + y0) * in->w + x0,
             (size_t)w * sizeof(float));
  return JND_OK;
}

/* step 4: linear RGB as the viewer sees it (jnd_judge_show) */
static jnd_status seen(const jnd_judge *j, const jnd_image *linear, jnd_image *cdm2, jnd_image *srgb_out) {
  return jnd_judge_show(&j->p.model.display, linear, NULL, 0, NULL, cdm2, srgb_out);
}

static void progress(jnd_judge *j) {
  if (j->p.progress)
    j->p.progress(j->p.progress_user, j->counts.references + j->counts.renderings + j->counts.partial_renderings);
}

static void view_free(jnd_judge *j, jview *v) {
  jnd_image_free(&v->ref_lin);
  jnd_image_free(&v->ref_cdm2);
  jnd_image_free(&v->mask);
  jnd_image_free(&v->motion);
  free(v->material);
  v->material = NULL;
  if (v->depth) jnd_render_drop_depth(j->r, v->depth);
  v->depth = 0;
  if (v->part)
    for (int m = 0; m < j->scene->nmaterials; m++) jnd_image_free(&v->part[m].old);
  free(v->part);
  free(v->mip_min);
  v->part = NULL;
  v->mip_min = NULL;
}

/* A borrowed renderer may have been sized by another judge since: its
 * targets back to this judge's size (nothing to do on the judge's own). */
static jnd_status sized(jnd_judge *j) {
  return jnd_renderer_resize(j->r, j->p.views.render.width, j->p.views.render.height);
}

/* Whether a reference needs the renderer's auxiliary pass, a second drawing
 * of the scene (one sample per pixel) for the mip level of each map, the
 * material of each pixel and the motion: not for a scene without maps, ground
 * plane, motion or a second material, whose covered pixels are all its one
 * material's. Skipping it takes about 7% off a lod run (docs/judge.md). */
static int reference_needs_aux(const jnd_judge *j, const jnd_view *v) {
  return j->nmaps > 0 || j->ground >= 0 || v->has_prev || j->scene->nmaterials > 1;
}

/* Renders the reference of view jv (the scene must be in its reference state). */
static jnd_status render_reference(jnd_judge *j, jview *jv) {
  const jnd_scene *s = j->scene;
  jnd_view vv = jv->view;
  int aux = reference_needs_aux(j, &vv);
  vv.outputs = JND_OUT_COLOR | JND_OUT_MASK | (aux ? JND_OUT_MIP : 0) | (vv.has_prev ? JND_OUT_MOTION : 0);
  jnd_frame f;
  jnd_status st = sized(j);
  if (st == JND_OK) st = jnd_render(j->r, s, &vv, &f);
  if (st != JND_OK) return st;
  j->counts.references++;
  int W = f.mask.w, H = f.mask.h;
  size_t P = (size_t)W * H;
  /* the object's pixels: coverage, without the ground plane */
  if (j->ground >= 0)
    for (size_t q = 0; q < P; q++)
      if ((int)lroundf(f.material.data[q]) == j->ground) f.mask.data[q] = 0;
  int x0 = W, y0 = H, x1 = -1, y1 = -1, ax0 = W, ay0 = H, ax1 = -1, ay1 = -1;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      float c = f.mask.data[(size_t)y * W + x];
      if (c > 0.5f) {
        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
        y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
      }
      if (c > 0) {
        ax0 = x < ax0 ? x : ax0, ax1 = x > ax1 ? x : ax1;
        ay0 = y < ay0 ? y : ay0, ay1 = y > ay1 ? y : ay1;
      }
    }
  jv->cx = x1 < 0 ? 0.5 * (W - 1) : 0.5 * (x0 + x1);
  jv->cy = x1 < 0 ? 0.5 * (H - 1) : 0.5 * (y0 + y1);
  /* nothing on screen, or a fixation point given in the frame's pixels
   * (eccentricity is measured from it): the whole frame */
  if (x1 < 0 || j->p.model.has_gaze) x0 = y0 = 0, x1 = W - 1, y1 = H - 1;
  jv->x0 = jnd_clampi(x0 - JUDGE_CROP_MARGIN, 0, W - 1);
  jv->y0 = jnd_clampi(y0 - JUDGE_CROP_MARGIN, 0, H - 1);
  jv->w = jnd_clampi(x1 + JUDGE_CROP_MARGIN, 0, W - 1) - jv->x0 + 1;
  jv->h = jnd_clampi(y1 + JUDGE_CROP_MARGIN, 0, H - 1) - jv->y0 + 1;
  st = crop(&f.color, jv->x0, jv->y0, jv->w, jv->h, &jv->ref_lin);
  if (st == JND_OK) st = seen(j, &jv->ref_lin, &jv->ref_cdm2, NULL);
  if (st == JND_OK) st = crop(&f.mask, jv->x0, jv->y0, jv->w, jv->h, &jv->mask);
  if (st == JND_OK && vv.has_prev) st = crop(&f.motion, jv->x0, jv->y0, jv->w, jv->h, &jv->motion);
  if (st == JND_OK && !(jv->material = jnd_alloc((size_t)jv->w * jv->h, sizeof *jv->material))) st = JND_ERR_NOMEM;
  for (int y = 0; st == JND_OK && y < jv->h; y++)
    for (int x = 0; x < jv->w; x++) {
      size_t q = (size_t)(y + jv->y0) * W + x + jv->x0;
      short own = f.mask.data[q] > 0 && s->nmaterials == 1 ? 0 : -1;   /* without the pass: the one material */
      jv->material[(size_t)y * jv->w + x] = aux ? (short)lroundf(f.material.data[q]) : own;
    }
  /* 000 §4: the finest mip level of each map, pooled per map through the
   * material each pixel shows */
  jv->mip_min = jnd_alloc((size_t)(j->nmaps ? j->nmaps : 1), sizeof *jv->mip_min);
  if (st == JND_OK && !jv->mip_min) st = JND_ERR_NOMEM;
  for (int i = 0; st == JND_OK && i < j->nmaps; i++) {
    jnd_map_info mi;
    jnd_scene_map_info(s, i, &mi);
    const float *lv = f.mip.data + (size_t)mi.slot * P;
    double lo = INFINITY;
    for (size_t q = 0; q < P; q++)
      if (lv[q] >= 0 && lv[q] < lo && (int)lroundf(f.material.data[q]) == mi.material) lo = lv[q];
    jv->mip_min[i] = lo;
  }
  jnd_frame_free(&f);
  progress(j);
  /* (no maps: no partial re-renders, whose states differ only in maps) */
  if (st != JND_OK || !j->p.partial || j->blend_any || ax1 < 0 || j->nmaps == 0) return st;

  /* partial re-renders: the depth, and each textured material's samples
   * under the reference maps, over the rectangle of every covered pixel */
  if ((st = jnd_render_keep_depth(j->r, &jv->depth)) != JND_OK) return st;
  jv->part = jnd_calloc((size_t)s->nmaterials, sizeof *jv->part);
  unsigned char *only = jnd_calloc((size_t)s->nmaterials, 1);
  if (!jv->part || !only) {
    free(only);
    return JND_ERR_NOMEM;
  }
  for (int m = 0; m < s->nmaterials && st == JND_OK; m++) {
    int textured = 0;
    for (int k = 0; k < JND_MAP_SLOTS; k++) textured |= s->materials[m].map[k] >= 0;
    if (!textured) continue;
    memset(only, 0, (size_t)s->nmaterials);
    only[m] = 1;
    jnd_image full = {0};
    int rw = ax1 - ax0 + 1, rh = ay1 - ay0 + 1;
    if ((st = jnd_render_materials(j->r, s, &jv->view, jv->depth, only, ax0, ay0, rw, rh, &full)) != JND_OK) break;
    j->counts.references++;
    const float *a = full.data + (size_t)3 * rw * rh;
    int bx0 = rw, by0 = rh, bx1 = -1, by1 = -1;
    double weight = 0;
    for (int y = 0; y < rh; y++)
      for (int x = 0; x < rw; x++)
        if (a[(size_t)y * rw + x] > 0) {
          weight += a[(size_t)y * rw + x];
          bx0 = x < bx0 ? x : bx0, bx1 = x > bx1 ? x : bx1;
          by0 = y < by0 ? y : by0, by1 = y > by1 ? y : by1;
        }
    mat_part *pt = &jv->part[m];
    if (bx1 >= 0) {
      pt->x0 = ax0 + bx0;
      pt->y0 = ay0 + by0;
      pt->w = bx1 - bx0 + 1;
      pt->h = by1 - by0 + 1;
      pt->weight = weight;
      st = crop(&full, bx0, by0, pt->w, pt->h, &pt->old);
    }
    jnd_image_free(&full);
    progress(j);
  }
  free(only);
  return st;
}

/* Material m's samples in view v under the current state of its maps, from
 * the kept renderings or rendered now over its rectangle. *out stays owned
 * by the judge. */
static jnd_status material_render(jnd_judge *j, int v, int m, const jnd_image **out) {
  uint64_t key = j->mat_key[m];
  for (int e = 0; e < j->nmr; e++)
    if (j->mr[e].key == key && j->mr[e].view == v && j->mr[e].material == m) {
      *out = &j->mr[e].img;
      return JND_OK;
    }
  const mat_part *pt = &j->v[v].part[m];
  unsigned char *only = jnd_calloc((size_t)j->scene->nmaterials, 1);
  if (!only) return JND_ERR_NOMEM;
  only[m] = 1;
  jnd_image img = {0};
  jnd_status st = sized(j);
  if (st == JND_OK)
    st = jnd_render_materials(j->r, j->scene, &j->v[v].view, j->v[v].depth, only, pt->x0, pt->y0, pt->w, pt->h, &img);
  free(only);
  if (st != JND_OK) return st;
  img.c = 3;   /* the coverage plane stays allocated behind the colour */
  j->counts.partial_renderings++;
  progress(j);
  /* keep it: in a ring, the oldest dropped first once over the budget */
  size_t bytes = (size_t)img.w * img.h * 4 * sizeof(float);
  while (j->nmr > 0 && j->mr_bytes + bytes > RENDER_CACHE_BYTES) {
    int e = j->nextmr % j->nmr;
    j->mr_bytes -= (size_t)j->mr[e].img.w * j->mr[e].img.h * 4 * sizeof(float);
    jnd_image_free(&j->mr[e].img);
    j->mr[e] = j->mr[--j->nmr];
    j->nextmr = j->nmr ? (e + 1) % j->nmr : 0;
  }
  if (j->nmr == j->capmr) {
    int cap = j->capmr ? 2 * j->capmr : 64;
    mat_render *n = realloc(j->mr, (size_t)cap * sizeof *n);
    if (!n) {
      jnd_image_free(&img);
      return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
    }
    j->mr = n;
    j->capmr = cap;
  }
  mat_render *e = &j->mr[j->nmr++];
  e->key = key;
  e->view = v;
  e->material = m;
  e->img = img;
  j->mr_bytes += bytes;
  *out = &e->img;
  return JND_OK;
}

static void forget_renders(jnd_judge *j) {
  for (int e = 0; e < j->nmr; e++) jnd_image_free(&j->mr[e].img);
  j->nmr = 0;
  j->nextmr = 0;
  j->mr_bytes = 0;
}

/* Images of the current state in view v: test in cd/m² (crop), and when
 * srgb is not NULL the display signal. Returns with *unchanged = 1 (and no
 * image) when the view cannot differ from its reference. */
static jnd_status render_state(jnd_judge *j, int v, const change_set *c, jnd_image *test, jnd_image *srgb,
                               int *unchanged) {
  jview *jv = &j->v[v];
  const jnd_scene *s = j->scene;
  *unchanged = 0;
  if (!c->any) {
    *unchanged = 1;
    return JND_OK;
  }
  jnd_status st;
  if (c->partial_ok && jv->part) {
    int any = 0;
    for (int m = 0; m < s->nmaterials; m++) any |= c->changed[m] && jv->part[m].w > 0;
    if (!any) {   /* none of the changed materials is seen in this view */
      *unchanged = 1;
      return JND_OK;
    }
    /* the reference minus the changed materials' old samples plus their new ones */
    jnd_image lin = {0};
    if ((st = jnd_image_alloc(&lin, jv->w, jv->h, 3)) != JND_OK) return st;
    memcpy(lin.data, jv->ref_lin.data, (size_t)jv->w * jv->h * 3 * sizeof(float));
    for (int m = 0; m < s->nmaterials && st == JND_OK; m++) {
      const mat_part *pt = &jv->part[m];
      if (!c->changed[m] || pt->w == 0) continue;
      const jnd_image *now = NULL;
      if ((st = material_render(j, v, m, &now)) != JND_OK) break;
      for (int ch = 0; ch < 3; ch++) {
        float *d = lin.data + (size_t)ch * jv->w * jv->h;
        for (int y = pt->y0; y < pt->y0 + pt->h; y++) {
          if (y < jv->y0 || y >= jv->y0 + jv->h) continue;
          const float *nw = now->data + ((size_t)ch * pt->h + (y - pt->y0)) * pt->w;
          const float *od = pt->old.data + ((size_t)ch * pt->h + (y - pt->y0)) * pt->w;
          for (int x = pt->x0; x < pt->x0 + pt->w; x++)
            if (x >= jv->x0 && x < jv->x0 + jv->w) d[(size_t)(y - jv->y0) * jv->w + (x - jv->x0)] += nw[x - pt->x0] - od[x - pt->x0];
        }
      }
    }
    if (st == JND_OK) st = seen(j, &lin, test, srgb);
    jnd_image_free(&lin);
    return st;
  }
  jnd_view vv = jv->view;
  vv.outputs = JND_OUT_COLOR;
  jnd_frame f;
  if ((st = sized(j)) != JND_OK || (st = jnd_render(j->r, s, &vv, &f)) != JND_OK) return st;
  j->counts.renderings++;
  progress(j);
  jnd_image lin = {0};
  st = crop(&f.color, jv->x0, jv->y0, jv->w, jv->h, &lin);
  jnd_frame_free(&f);
  if (st == JND_OK) st = seen(j, &lin, test, srgb);
  jnd_image_free(&lin);
  return st;
}

/* The object's pixels of each material whose P exceeds p (counts has
 * nmaterials entries): where in the view the difference is. P > p is
 * JND > the JND the calibration maps to p, a monotone threshold. */
static void count_above(const jnd_judge *j, const jview *jv, const jnd_image *map, int *counts) {
  const jnd_calibration *cal = &j->p.calibration;
  double jt = (jnd_probability_inverse(j->p.criterion.p, cal->beta) - cal->bias) / cal->scale;
  int nm = j->scene->nmaterials;
  memset(counts, 0, (size_t)nm * sizeof *counts);
  for (size_t q = 0; q < (size_t)jv->w * jv->h; q++)
    if (jv->mask.data[q] > 0.5f && map->data[q] > jt && jv->material[q] >= 0 && jv->material[q] < nm)
      counts[jv->material[q]]++;
}

/* P of view v in the current state; jnd_keep (may be NULL) receives the JND
 * map, counts (may be NULL) the pixels above p per material. */
static jnd_status judge_view(jnd_judge *j, int v, const change_set *c, double *P, jnd_image *jnd_keep,
                             jnd_image *srgb, int *counts) {
  jview *jv = &j->v[v];
  jnd_image test = {0}, map = {0};
  int unchanged;
  jnd_status st = render_state(j, v, c, &test, srgb, &unchanged);
  if (st != JND_OK) return st;
  j->counts.view_judgements++;
  if (unchanged) {
    *P = 0;
    if (counts) memset(counts, 0, (size_t)j->scene->nmaterials * sizeof *counts);
    if (jnd_keep) st = jnd_image_alloc(jnd_keep, jv->w, jv->h, 1);
    if (st == JND_OK && srgb) st = jnd_render_to_srgb(&jv->ref_lin, srgb);
    return st;
  }
  jnd_diff_inputs in = {0};
  if (jv->motion.data) in.motion = &jv->motion;
  /* the view's fixation point, else the judge's, in the crop's pixels */
  if (jv->has_gaze) jnd_model_set_gaze(j->m, 1, jv->gaze_x - jv->x0, jv->gaze_y - jv->y0);
  else jnd_model_set_gaze(j->m, j->p.model.has_gaze, j->p.model.gaze_x - jv->x0, j->p.model.gaze_y - jv->y0);
  st = jnd_model_diff(j->m, &jv->ref_cdm2, &test, &in, &map);
  jnd_image_free(&test);
  if (st != JND_OK) return st;
  *P = jnd_calibration_pool(&j->p.calibration, &map, &jv->mask);
  if (!isfinite(*P)) *P = 0;   /* no pixel of the object: nothing to see */
  if (counts) count_above(j, jv, &map, counts);
  if (jnd_keep) *jnd_keep = map;
  else jnd_image_free(&map);
  return JND_OK;
}

/* ---- the judge ---- */

static jnd_status grow_views(jnd_judge *j, int n) {
  if (j->nv + n <= j->capv) return JND_OK;
  int cap = j->capv ? j->capv : 8;
  while (cap < j->nv + n) cap *= 2;
  jview *nv = realloc(j->v, (size_t)cap * sizeof *nv);
  if (!nv) return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
  j->v = nv;
  memset(j->v + j->capv, 0, (size_t)(cap - j->capv) * sizeof *nv);
  for (int e = 0; e < j->nst; e++) {
    double *p = realloc(j->st[e].p, (size_t)cap * sizeof *p);
    if (!p) return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
    for (int v = j->capv; v < cap; v++) p[v] = NAN;
    j->st[e].p = p;
    size_t per = (size_t)j->scene->nmaterials + 1;
    int *ab = realloc(j->st[e].above, (size_t)cap * per * sizeof *ab);
    if (!ab) return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
    memset(ab + (size_t)j->capv * per, 0, (size_t)(cap - j->capv) * per * sizeof *ab);
    j->st[e].above = ab;
  }
  j->capv = cap;
  return JND_OK;
}

/* Puts the scene's maps and meshes' levels of detail in their reference
 * state for fn, then back. */
static jnd_status with_reference_maps(jnd_judge *j, jnd_status (*fn)(jnd_judge *, void *), void *arg) {
  update_key(j);
  jnd_scene *s = j->scene;
  jnd_image *saved = jnd_calloc((size_t)(j->nmaps ? j->nmaps : 1), sizeof *saved);
  int *level = jnd_alloc((size_t)(s->nmeshes ? s->nmeshes : 1), sizeof *level);
  if (!saved || !level) {
    free(saved);
    free(level);
    return JND_ERR_NOMEM;
  }
  jnd_status st = JND_OK;
  /* the reference's level of detail of each mesh, the current one kept */
  for (int k = 0; k < s->nmeshes; k++) level[k] = jnd_scene_lod_mesh_level(s, k);
  for (int k = 0; k < s->nmeshes && st == JND_OK; k++)
    if (level[k] != j->ref_level[k]) st = jnd_scene_lod_select_mesh(s, k, j->ref_level[k]);
  for (int i = 0; i < j->nmaps && st == JND_OK; i++) {
    if (j->cur_key[i] == j->ref_key[i]) continue;
    if ((st = jnd_scene_map_get(s, i, 0, &saved[i])) != JND_OK) break;
    if (j->ref_maps[i].data) st = jnd_scene_map_set(s, i, &j->ref_maps[i]);
    else jnd_scene_map_restore(s, i);
  }
  if (st == JND_OK) st = fn(j, arg);
  for (int i = 0; i < j->nmaps; i++) {
    if (!saved[i].data) continue;
    jnd_status s2 = jnd_scene_map_set(s, i, &saved[i]);
    if (st == JND_OK) st = s2;
    jnd_image_free(&saved[i]);
  }
  for (int k = 0; k < s->nmeshes; k++)
    if (level[k] != jnd_scene_lod_mesh_level(s, k)) {
      jnd_status s2 = jnd_scene_lod_select_mesh(s, k, level[k]);
      if (st == JND_OK) st = s2;
    }
  free(saved);
  free(level);
  return st;
}

typedef struct {
  int first, n;
} view_range;

static jnd_status render_references(jnd_judge *j, void *arg) {
  const view_range *r = arg;
  for (int v = r->first; v < r->first + r->n; v++) {
    if (j->v[v].twin) continue;   /* its reference is the view it equals */
    jnd_status st = render_reference(j, &j->v[v]);
    if (st != JND_OK) return st;
  }
  return JND_OK;
}

/* records the scene's current state as the reference */
static jnd_status take_reference(jnd_judge *j) {
  jnd_scene *s = j->scene;
  for (int i = 0; i < j->nmaps; i++) {
    jnd_image_free(&j->ref_maps[i]);
    j->hashed_version[i] = 0;
    if (s->maps[i].now.data) {
      jnd_status st = jnd_scene_map_get(s, i, 0, &j->ref_maps[i]);
      if (st != JND_OK) return st;
    }
  }
  for (int k = 0; k < s->nmeshes; k++) j->ref_level[k] = jnd_scene_lod_mesh_level(s, k);
  update_key(j);
  memcpy(j->ref_key, j->cur_key, (size_t)j->nkey * sizeof *j->ref_key);
  forget_states(j);
  return JND_OK;
}

void jnd_judge_free(jnd_judge *j) {
  if (!j) return;
  for (int v = 0; v < j->nv; v++) view_free(j, &j->v[v]);
  free(j->v);
  forget_states(j);
  free(j->st);
  if (j->ref_maps)
    for (int i = 0; i < j->nmaps; i++) jnd_image_free(&j->ref_maps[i]);
  free(j->ref_maps);
  free(j->ref_level);
  forget_renders(j);
  free(j->mr);
  free(j->mat_key);
  free(j->map_material);
  free(j->ref_key);
  free(j->cur_key);
  free(j->hashed_version);
  jnd_model_free(j->m);
  if (j->own_r) jnd_renderer_free(j->r);
  free(j);
}

static jnd_status make_model(jnd_judge *j);

jnd_status jnd_judge_create(jnd_scene *scene, const jnd_judge_params *p, jnd_judge **out) {
  *out = NULL;
  const jnd_criterion *cr = &p->criterion;
  if (!(cr->p > 0 && cr->p < 1) || !(cr->q >= 0 && cr->q < 1) || !(cr->confidence > 0 && cr->confidence < 1))
    return jnd_fail(JND_ERR_ARG, "judge: criterion p %g, q %g, confidence %g out of range", cr->p, cr->q,
                    cr->confidence);
  if (!(p->calibration.percentile >= 0 && p->calibration.percentile <= 100) || !(p->calibration.beta > 0))
    return jnd_fail(JND_ERR_ARG, "judge: calibration out of range");
  jnd_judge *j = jnd_calloc(1, sizeof *j);
  if (!j) return JND_ERR_NOMEM;
  j->scene = scene;
  j->p = *p;
  j->p.views.cameras = NULL;   /* made into views below; the caller's array is not kept */
  j->p.views.cameras_path = NULL;
  j->nmaps = scene->nmaps;
  j->nkey = scene->nmaps + scene->nmeshes;
  double c[3], rad;
  jnd_scene_subject_bounds(scene, c, &rad, &j->ground);
  for (int k = 0; k < scene->nmeshes; k++)
    j->blend_any |= scene->materials[scene->meshes[k].material].alpha_mode == JND_ALPHA_BLEND;
  size_t nk = (size_t)(j->nkey ? j->nkey : 1), nm = (size_t)(j->nmaps ? j->nmaps : 1);
  j->ref_key = jnd_calloc(nk, sizeof *j->ref_key);
  j->cur_key = jnd_calloc(nk, sizeof *j->cur_key);
  j->hashed_version = jnd_calloc(nm, sizeof *j->hashed_version);
  j->ref_maps = jnd_calloc(nm, sizeof *j->ref_maps);
  j->ref_level = jnd_calloc(scene->nmeshes ? (size_t)scene->nmeshes : 1, sizeof *j->ref_level);
  j->map_material = jnd_calloc(nm, sizeof *j->map_material);
  j->mat_key = jnd_calloc((size_t)scene->nmaterials + 1, sizeof *j->mat_key);
  jnd_status st = j->ref_key && j->cur_key && j->hashed_version && j->ref_maps && j->ref_level && j->map_material && j->mat_key
                      ? JND_OK
                      : JND_ERR_NOMEM;
  for (int i = 0; i < j->nmaps && st == JND_OK; i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    j->map_material[i] = mi.material;
  }
  jnd_view *views = NULL;
  int n = 0;
  if (st == JND_OK) st = jnd_view_set_make(scene, &p->views, &views, &n);
  if (st == JND_OK) {
    j->own_r = !p->renderer;
    if (p->renderer) j->r = p->renderer;
    else st = judge_renderer(&p->views.render, 0, &j->r);
  }
  if (st == JND_OK) st = make_model(j);
  if (st == JND_OK) st = take_reference(j);
  if (st == JND_OK) st = jnd_judge_add_views(j, views, n, NULL);
  free(views);
  if (st != JND_OK) {
    jnd_judge_free(j);
    return st;
  }
  *out = j;
  return JND_OK;
}

/* a and b give the same image of the same scene: every field equal, the
 * doubles bit for bit (jnd_light has padding: compared field by field) */
static int same_doubles(const double *a, const double *b, int n) { return memcmp(a, b, (size_t)n * sizeof *a) == 0; }

static int same_camera(const jnd_camera *a, const jnd_camera *b) {
  return same_doubles(a->eye, b->eye, 3) && same_doubles(a->target, b->target, 3) && same_doubles(a->up, b->up, 3) &&
         same_doubles(&a->fov_y_deg, &b->fov_y_deg, 1) && same_doubles(&a->znear, &b->znear, 1) &&
         same_doubles(&a->zfar, &b->zfar, 1);
}

static int same_view(const jnd_view *a, const jnd_view *b) {
  if (!same_camera(&a->camera, &b->camera) || !same_doubles(a->model, b->model, 16) || a->has_prev != b->has_prev ||
      a->nlights != b->nlights || !same_doubles(&a->env_intensity, &b->env_intensity, 1) ||
      !same_doubles(&a->env_rotation_deg, &b->env_rotation_deg, 1) || !same_doubles(&a->exposure, &b->exposure, 1) ||
      a->background_env != b->background_env || a->unlit != b->unlit || a->outputs != b->outputs ||
      a->shade_prev != b->shade_prev)
    return 0;
  if (a->has_prev && (!same_camera(&a->prev_camera, &b->prev_camera) || !same_doubles(a->prev_model, b->prev_model, 16)))
    return 0;
  for (int k = 0; k < a->nlights && k < JND_MAX_LIGHTS; k++) {
    const jnd_light *x = &a->lights[k], *y = &b->lights[k];
    if (x->type != y->type || !same_doubles(x->position, y->position, 3) || !same_doubles(x->direction, y->direction, 3) ||
        !same_doubles(x->color, y->color, 3) || !same_doubles(&x->intensity, &y->intensity, 1) ||
        !same_doubles(&x->range, &y->range, 1) || !same_doubles(&x->inner_deg, &y->inner_deg, 1) ||
        !same_doubles(&x->outer_deg, &y->outer_deg, 1))
      return 0;
  }
  return 1;
}

static jnd_status add_views(jnd_judge *j, const jnd_view *views, int n, int *first) {
  if (n < 1 || !views) return jnd_fail(JND_ERR_ARG, "judge: no views to add");
  jnd_status st = grow_views(j, n);
  if (st != JND_OK) return st;
  view_range r = {j->nv, n};
  for (int v = 0; v < n; v++) {
    jview *jv = &j->v[j->nv + v];
    memset(jv, 0, sizeof *jv);
    jv->view = views[v];
    /* a view added before (budget's levels each add texres's confirmation
     * and held-out views, same seeds): its twin, rendered and judged once */
    for (int u = 0; u < j->nv + v && !jv->twin; u++)
      if (!j->v[u].twin && !j->v[u].has_gaze && same_view(&j->v[u].view, &views[v])) jv->twin = u + 1;
  }
  j->nv += n;
  st = with_reference_maps(j, render_references, &r);
  if (st != JND_OK) {
    for (int v = r.first; v < j->nv; v++) view_free(j, &j->v[v]);
    j->nv = r.first;
    return st;
  }
  if (first) *first = r.first;
  return JND_OK;
}

jnd_status jnd_judge_add_views(jnd_judge *j, const jnd_view *views, int n, int *first) {
  int previous = jnd_threads_enter(j->threads);
  jnd_status st = add_views(j, views, n, first);
  jnd_threads_leave(previous);
  return st;
}

static jnd_status set_reference(jnd_judge *j) {
  forget_renders(j);
  jnd_status st = take_reference(j);
  if (st != JND_OK) return st;
  for (int v = 0; v < j->nv; v++) {
    jview keep = j->v[v];   /* its view and fixation point */
    view_free(j, &j->v[v]);
    memset(&j->v[v], 0, sizeof j->v[v]);
    j->v[v].view = keep.view;
    j->v[v].has_gaze = keep.has_gaze;
    j->v[v].gaze_x = keep.gaze_x;
    j->v[v].gaze_y = keep.gaze_y;
    j->v[v].twin = keep.twin;
  }
  view_range r = {0, j->nv};
  return render_references(j, &r);
}

jnd_status jnd_judge_set_reference(jnd_judge *j) {
  int previous = jnd_threads_enter(j->threads);
  jnd_status st = set_reference(j);
  jnd_threads_leave(previous);
  return st;
}

/* the vision model for the judge's parameters */
static jnd_status make_model(jnd_judge *j) {
  jnd_model_free(j->m);
  j->m = NULL;
  /* On a CPU rasteriser OpenMP workers spin after each parallel region
   * against the rasteriser's threads (the model's: 8× slower on 2 cores; the
   * scene's resampling between states: a quarter of texres's CPU time on the
   * 6-material bench asset): one thread each is faster there unless threads
   * were asked for. */
  jnd_model_params mp = j->p.model;
  mp.beta = j->p.calibration.beta;
  const char *desc = jnd_renderer_description(j->r);
  int cpu = strstr(desc, "llvmpipe") || strstr(desc, "softpipe");
  if (mp.threads == 0 && cpu) mp.threads = 1;
  if (j->scene->threads == 0 && cpu) j->scene->threads = 1;
  if (cpu) j->threads = 1;
  return jnd_model_create(&mp, &j->m);
}

jnd_status jnd_judge_set_gaze(jnd_judge *j, int has_gaze, double x, double y) {
  if (has_gaze != j->p.model.has_gaze)
    return jnd_fail(JND_ERR_ARG, "judge: a fixation point is set when the judge is made (model.has_gaze)");
  if (!has_gaze) return JND_OK;
  j->p.model.gaze_x = x;
  j->p.model.gaze_y = y;
  for (int v = 0; v < j->nv; v++) j->v[v].has_gaze = 0;   /* every view: the judge's point */
  forget_states(j);   /* every P depends on where the viewer looks */
  jnd_model_set_gaze(j->m, 1, x, y);   /* the same model: the fixation point is read per comparison */
  return JND_OK;
}

/* what was judged on view v is forgotten in every state (its fixation point moved) */
static void forget_view(jnd_judge *j, int v) {
  size_t per = (size_t)j->scene->nmaterials + 1;
  for (int e = 0; e < j->nst; e++) {
    j->st[e].p[v] = NAN;
    memset(j->st[e].above + (size_t)v * per, 0, per * sizeof *j->st[e].above);
  }
}

/* A fixation point is a view's own: view v and its twins (or the view it
 * is a twin of) get references of their own, rendered now. */
static jnd_status separate(jnd_judge *j, int v) {
  for (int w = 0; w < j->nv; w++) {
    if (!j->v[w].twin || (w != v && own(j, w) != v)) continue;   /* v itself, or a twin of v */
    j->v[w].twin = 0;
    view_range r = {w, 1};
    jnd_status st = with_reference_maps(j, render_references, &r);
    if (st != JND_OK) return st;
  }
  return JND_OK;
}

jnd_status jnd_judge_set_view_gaze(jnd_judge *j, int v, int has_gaze, double x, double y) {
  if (v < 0 || v >= j->nv) return jnd_fail(JND_ERR_ARG, "judge: view %d of %d", v, j->nv);
  if (has_gaze && !(isfinite(x) && isfinite(y))) return jnd_fail(JND_ERR_ARG, "judge: a fixation point must be finite");
  jview *jv = &j->v[v];
  has_gaze = has_gaze != 0;
  if (jv->has_gaze == has_gaze && (!has_gaze || (jv->gaze_x == x && jv->gaze_y == y))) return JND_OK;
  int previous = jnd_threads_enter(j->threads);
  jnd_status st = separate(j, v);
  jnd_threads_leave(previous);
  if (st != JND_OK) return st;
  jv = &j->v[v];
  jv->has_gaze = has_gaze;
  jv->gaze_x = has_gaze ? x : 0;
  jv->gaze_y = has_gaze ? y : 0;
  forget_view(j, v);
  return JND_OK;
}

jnd_status judge_renderer(const jnd_renderer_params *rp, int side, jnd_renderer **r) {
  jnd_renderer_params q;
  if (rp) q = *rp;
  else jnd_renderer_defaults(&q);
  if (side > 0) q.width = q.height = side;
  return jnd_renderer_create(&q, r);
}

double judge_fixation_left_of(double cx, double ecc_deg, double ppd) {
  const double dist_px = 1.0 / tan(M_PI / 180.0 / ppd);   /* the viewing distance in pixels */
  return cx - dist_px * tan(ecc_deg * M_PI / 180.0);
}

jnd_status jnd_judge_set_view_eccentricity(jnd_judge *j, int v, double ecc_deg, double *x, double *y) {
  if (v < 0 || v >= j->nv) return jnd_fail(JND_ERR_ARG, "judge: view %d of %d", v, j->nv);
  if (!(ecc_deg >= 0 && ecc_deg < 90))
    return jnd_fail(JND_ERR_ARG, "judge: eccentricity %g degrees outside [0, 90)", ecc_deg);
  const jview *jv = &j->v[own(j, v)];
  double gx = judge_fixation_left_of(jv->cx, ecc_deg, j->p.model.display.ppd), gy = jv->cy;
  if (x) *x = gx;
  if (y) *y = gy;
  return jnd_judge_set_view_gaze(j, v, 1, gx, gy);
}

int jnd_judge_view_count(const jnd_judge *j) { return j->nv; }
const jnd_view *jnd_judge_view(const jnd_judge *j, int v) { return v >= 0 && v < j->nv ? &j->v[v].view : NULL; }
const char *jnd_judge_renderer(const jnd_judge *j) { return jnd_renderer_description(j->r); }
void jnd_judge_get_counts(const jnd_judge *j, jnd_judge_counts *out) { *out = j->counts; }

double jnd_judge_mip_min(const jnd_judge *j, int map, int first, int n) {
  if (map < 0 || map >= j->nmaps) return -1;
  double lo = INFINITY;
  for (int v = first; v < first + n && v < j->nv; v++)
    if (v >= 0 && j->v[own(j, v)].mip_min[map] < lo) lo = j->v[own(j, v)].mip_min[map];
  return isfinite(lo) ? lo : -1;
}

static jnd_status changes_now(jnd_judge *j, change_set *c) {
  c->changed = jnd_calloc((size_t)(j->scene->nmaterials ? j->scene->nmaterials : 1), 1);
  if (!c->changed) return JND_ERR_NOMEM;
  update_key(j);
  find_changes(j, c);
  return JND_OK;
}

static jnd_status eval(jnd_judge *j, int first, int n, unsigned flags, double *p, jnd_judgement *out) {
  if (first < 0 || n < 1 || first + n > j->nv)
    return jnd_fail(JND_ERR_ARG, "judge: views %d..%d of %d", first, first + n - 1, j->nv);
  change_set c;
  jnd_status st = changes_now(j, &c);
  if (st != JND_OK) return st;
  jstate *e = find_state(j);
  int *order = jnd_alloc((size_t)n, sizeof *order);
  double *w = jnd_alloc((size_t)n, sizeof *w);
  if (!e || !order || !w) {
    free(c.changed);
    free(order);
    free(w);
    return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
  }
  /* with DECIDE, the views where the changed materials cover most first:
   * where a failure is likeliest (stable: ties keep their index order) */
  for (int k = 0; k < n; k++) {
    order[k] = first + k;
    w[k] = 0;
    const jview *jv = &j->v[own(j, first + k)];
    if ((flags & JND_JUDGE_DECIDE) && jv->part)
      for (int m = 0; m < j->scene->nmaterials; m++)
        if (c.changed[m]) w[k] += jv->part[m].weight;
  }
  if (flags & JND_JUDGE_DECIDE)
    for (int a = 1; a < n; a++)
      for (int b = a; b > 0 && w[b] > w[b - 1]; b--) {
        double tw = w[b];
        w[b] = w[b - 1], w[b - 1] = tw;
        int to = order[b];
        order[b] = order[b - 1], order[b - 1] = to;
      }
  int allowed = (int)floor(j->p.criterion.q * n + 1e-9), above = 0, judged = 0;
  for (int k = 0; k < n && st == JND_OK; k++) {
    int v = own(j, order[k]);
    if (isnan(e->p[v])) {
      double P;
      if ((st = judge_view(j, v, &c, &P, NULL, NULL, e->above + (size_t)v * (j->scene->nmaterials + 1))) != JND_OK) break;
      e->p[v] = P;
    } else {
      j->counts.reused++;
    }
    judged++;
    above += e->p[v] > j->p.criterion.p;
    if ((flags & JND_JUDGE_DECIDE) && above > allowed) break;
  }
  free(order);
  free(w);
  free(c.changed);
  if (st != JND_OK) return st;
  double *q = p ? p : jnd_alloc((size_t)n, sizeof *q);
  if (!q) return JND_ERR_NOMEM;
  for (int k = 0; k < n; k++) q[k] = e->p[own(j, first + k)];
  if (out) {
    out->views = n;
    out->judged = judged;
    double *z = jnd_alloc((size_t)n, sizeof *z);
    if (!z) st = JND_ERR_NOMEM;
    for (int k = 0; z && k < n; k++) z[k] = isnan(q[k]) ? 0 : q[k];
    if (st == JND_OK)
      st = jnd_criterion_eval(z, n, j->p.criterion.p, j->p.criterion.q, j->p.criterion.confidence, &out->criterion);
    if (st == JND_OK && judged < n) out->criterion.pass = 0;
    free(z);
  }
  if (!p) free(q);
  return st;
}

jnd_status jnd_judge_eval(jnd_judge *j, int first, int n, unsigned flags, double *p, jnd_judgement *out) {
  int previous = jnd_threads_enter(j->threads);
  jnd_status st = eval(j, first, n, flags, p, out);
  jnd_threads_leave(previous);
  return st;
}

static jnd_status view_images(jnd_judge *j, int v, jnd_image *jmap, jnd_image *frame, jnd_image *mask,
                              jnd_image *heatmap, int crop_out[4]) {
  if (v < 0 || v >= j->nv) return jnd_fail(JND_ERR_ARG, "judge: view %d of %d", v, j->nv);
  v = own(j, v);
  const jview *jv = &j->v[v];
  change_set c;
  jnd_status st = changes_now(j, &c);
  if (st != JND_OK) return st;
  jnd_image map = {0}, srgb = {0};
  double P;
  st = judge_view(j, v, &c, &P, &map, &srgb, NULL);
  free(c.changed);
  if (st == JND_OK && heatmap) {
    jnd_image ref_srgb = {0};
    st = jnd_render_to_srgb(&jv->ref_lin, &ref_srgb);
    if (st == JND_OK) st = jnd_heatmap(&ref_srgb, &map, 1, heatmap);
    jnd_image_free(&ref_srgb);
  }
  if (st == JND_OK && mask) st = crop(&jv->mask, 0, 0, jv->w, jv->h, mask);
  if (st == JND_OK && crop_out) crop_out[0] = jv->x0, crop_out[1] = jv->y0, crop_out[2] = jv->w, crop_out[3] = jv->h;
  if (st == JND_OK && jmap) *jmap = map;
  else jnd_image_free(&map);
  if (st == JND_OK && frame) *frame = srgb;
  else jnd_image_free(&srgb);
  return st;
}

jnd_status jnd_judge_view_images(jnd_judge *j, int v, jnd_image *jmap, jnd_image *frame, jnd_image *mask,
                                 jnd_image *heatmap, int crop_out[4]) {
  int previous = jnd_threads_enter(j->threads);
  jnd_status st = view_images(j, v, jmap, frame, mask, heatmap, crop_out);
  jnd_threads_leave(previous);
  return st;
}

jnd_status jnd_judge_material_counts(jnd_judge *j, int v, int *counts) {
  if (v < 0 || v >= j->nv) return jnd_fail(JND_ERR_ARG, "judge: view %d of %d", v, j->nv);
  v = own(j, v);
  update_key(j);
  jstate *e = find_state(j);
  if (!e) return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
  if (isnan(e->p[v])) return jnd_fail(JND_ERR_ARG, "judge: view %d is not judged in this state", v);
  memcpy(counts, e->above + (size_t)v * (j->scene->nmaterials + 1), (size_t)j->scene->nmaterials * sizeof *counts);
  return JND_OK;
}

/* ---- renderings compared as pairs ---- */

/* linear RGB (a rendering) → sRGB 8-bit codes, into out (allocated once):
 * the display's curve (jnd_srgb_encode) rounded as the PNG writer rounds */
static jnd_status show_codes(const jnd_image *lin, display_codes *out) {
  size_t n = (size_t)lin->w * lin->h * 3;
  if (!out->px || out->w != lin->w || out->h != lin->h) {
    free(out->px);
    out->px = NULL;
    if (!(out->px = jnd_alloc(n, 1))) return JND_ERR_NOMEM;
  }
  out->w = lin->w, out->h = lin->h, out->c = 3;
  const float *v = lin->data;
  uint8_t *px = out->px;
#pragma omp parallel for simd schedule(static)
  for (size_t i = 0; i < n; i++) px[i] = (uint8_t)(jnd_srgb_encode(v[i]) * 255.0 + 0.5);
  return JND_OK;
}

jnd_status judge_render_level(jnd_renderer *r, jnd_scene *scene, int level, const jnd_view *v, jnd_frame *f) {
  jnd_status st = jnd_scene_lod_select(scene, level);
  return st ? st : jnd_render(r, scene, v, f);
}

jnd_status judge_level_codes(jnd_renderer *r, jnd_scene *scene, int level, const jnd_view *v, int unlit,
                             display_codes *out) {
  jnd_view w = *v;
  w.unlit = unlit;
  w.outputs = JND_OUT_COLOR;
  jnd_frame f;
  jnd_status st = judge_render_level(r, scene, level, &w, &f);
  if (st) return st;
  st = show_codes(&f.color, out);
  jnd_frame_free(&f);
  return st;
}

/* ---- the display path ---- */

jnd_status jnd_judge_show(const jnd_display *d, const jnd_image *linear, const jnd_image *coverage,
                          double background, const unsigned char *grey, jnd_image *cdm2, jnd_image *srgb) {
  if (linear->c < 3) return jnd_fail(JND_ERR_ARG, "judge: a frame to show needs 3 channels, not %d", linear->c);
  size_t n = (size_t)linear->w * linear->h;
  if (coverage && (coverage->w != linear->w || coverage->h != linear->h || coverage->c < 1))
    return jnd_fail(JND_ERR_ARG, "judge: a frame's coverage differs from it in size");
  jnd_image over = {0}, sig = {0};
  jnd_status st = JND_OK;
  if (coverage) {
    /* the rendering is over black: the background shows through by
     * 1 − coverage (a pixel half covered is half the grey) */
    if ((st = jnd_image_alloc(&over, linear->w, linear->h, 3)) != JND_OK) return st;
    const float bg = (float)background;
    for (int ch = 0; ch < 3; ch++) {
      const float *src = linear->data + (size_t)ch * n;
      float *dst = over.data + (size_t)ch * n;
      for (size_t q = 0; q < n; q++) {
        float k = coverage->data[q] < 0 ? 0 : coverage->data[q] > 1 ? 1 : coverage->data[q];
        dst[q] = grey && grey[q] ? bg : src[q] + (1 - k) * bg;
      }
    }
    linear = &over;
  }
  st = jnd_render_to_srgb(linear, &sig);
  jnd_image_free(&over);
  if (st == JND_OK) st = jnd_display_apply(d, &sig, JND_ENCODING_SRGB, 0, cdm2);
  if (st == JND_OK && srgb) *srgb = sig;
  else jnd_image_free(&sig);
  return st;
}

/* ---- two frames against each other ---- */

typedef struct {
  double ppd;     /* the display's pixels per degree it was made for */
  jnd_model *m;   /* NULL while its maker creates it */
  int busy;       /* 1: a caller is comparing with it */
} pair_model;

struct jnd_pair_judge {
  jnd_model_params p;
  pair_model *pool;   /* grows; callers hold indices, never pointers into it */
  int n, cap;
};

jnd_status jnd_pair_judge_create(const jnd_model_params *model, jnd_pair_judge **out) {
  *out = NULL;
  if (!(model->display.ppd >= 1 && model->display.ppd <= 1000))
    return jnd_fail(JND_ERR_ARG, "judge: pixels per degree must be in [1, 1000], not %g", model->display.ppd);
  jnd_pair_judge *j = jnd_calloc(1, sizeof *j);
  if (!j) return JND_ERR_NOMEM;
  j->p = *model;
  j->p.has_gaze = 0;
  *out = j;
  return JND_OK;
}

void jnd_pair_judge_free(jnd_pair_judge *j) {
  if (!j) return;
  for (int i = 0; i < j->n; i++) jnd_model_free(j->pool[i].m);
  free(j->pool);
  free(j);
}

int jnd_pair_judge_models(const jnd_pair_judge *j) {
  int made = 0;
  for (int i = 0; i < j->n; i++) made += j->pool[i].m != NULL;
  return made;
}

/* A model at ppd for this caller alone: a free one kept, or a new slot
 * (*fresh = 1, its model for the caller to make). -1: out of memory. */
static int take_model(jnd_pair_judge *j, double ppd, int *fresh) {
  int got = -1;
  *fresh = 0;
#pragma omp critical(jnd_pair_judge_pool)
  {
    for (int i = 0; i < j->n && got < 0; i++)
      if (!j->pool[i].busy && j->pool[i].m && j->pool[i].ppd == ppd) got = i;
    if (got < 0) {
      if (j->n == j->cap) {
        int cap = j->cap ? 2 * j->cap : 4;
        pair_model *np = realloc(j->pool, (size_t)cap * sizeof *np);
        if (np) j->pool = np, j->cap = cap;
      }
      if (j->n < j->cap) {
        got = j->n++;
        j->pool[got] = (pair_model){ppd, NULL, 0};
        *fresh = 1;
      }
    }
    if (got >= 0) j->pool[got].busy = 1;
  }
  return got;
}

static void give_model(jnd_pair_judge *j, int i, jnd_model *made) {
#pragma omp critical(jnd_pair_judge_pool)
  {
    if (made) j->pool[i].m = made;
    j->pool[i].busy = 0;
  }
}

jnd_status jnd_pair_judge_compare(jnd_pair_judge *j, const jnd_image *a, const jnd_image *cov_a,
                                  const jnd_image *b, const jnd_image *cov_b, const jnd_pair_view *v,
                                  jnd_image *jmap) {
  memset(jmap, 0, sizeof *jmap);
  if (a->w != b->w || a->h != b->h || (cov_a && (cov_a->w != a->w || cov_a->h != a->h)) ||
      (cov_b && (cov_b->w != b->w || cov_b->h != b->h)))
    return jnd_fail(JND_ERR_ARG, "judge: the two frames and their coverages differ in size");
  const double ppd = v->ppd > 0 ? v->ppd : j->p.display.ppd;
  int fresh, slot = take_model(j, ppd, &fresh);
  if (slot < 0) return jnd_fail(JND_ERR_NOMEM, "judge: out of memory");
  jnd_model *m = NULL, *made = NULL;
  jnd_status st = JND_OK;
  if (fresh) {
    jnd_model_params mp = j->p;
    mp.display.ppd = ppd;
    st = jnd_model_create(&mp, &made);
    m = made;
  } else {
#pragma omp critical(jnd_pair_judge_pool)
    m = j->pool[slot].m;
  }
  jnd_image ra = {0}, rb = {0};
  if (st == JND_OK) {
    jnd_model_set_gaze(m, v->has_gaze, v->gaze_x, v->gaze_y);
    st = jnd_judge_show(&j->p.display, a, cov_a, v->background, v->grey, &ra, NULL);
  }
  if (st == JND_OK) st = jnd_judge_show(&j->p.display, b, cov_b, v->background, v->grey, &rb, NULL);
  jnd_diff_inputs in;
  memset(&in, 0, sizeof in);
  in.temporal_hz = v->temporal_hz;
  if (st == JND_OK) st = jnd_model_diff_consume(m, &ra, &rb, &in, jmap);
  jnd_image_free(&ra);
  jnd_image_free(&rb);
  if (fresh && st != JND_OK && made) {
    jnd_model_free(made);
    made = NULL;
  }
  /* a slot whose model could not be made stays busy and empty: never handed out */
  if (!fresh || made) give_model(j, slot, made);
  return st;
}

/* ---- the object's window ---- */

void object_window(double object_px, double grow, int margin_px, int min_px, int max_px, int round_up, int *side,
                   double *scale) {
  double want = object_px * grow;
  int n = round_up ? (int)ceil(want) : (int)lround(fmax(want, min_px));
  n += 2 * margin_px;
  if (n < min_px) n = min_px;
  *scale = 1;
  if (n > max_px) {
    n = max_px;
    *scale = (max_px - 2 * margin_px) / want;
  }
  *side = n;
}
