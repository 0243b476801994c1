/* Texture resolution nobody notices (Wolski et al. 2019, 000 §4–§9).
 *
 * The candidates are a map's original and its reductions (Lanczos-3, 000
 * §4); the judgement of a combination is the judge's (judge.c: render the
 * views, show them on the display, compare with the full-resolution
 * rendering, pool P93 or a calibration over the object, 000 §6–§7; at most
 * a fraction q of the views above P = p, 000 §9). The search
 * (docs/texres.md):
 *   1. the mip-usage bound of 000 §4: a map whose level 0 no pixel samples
 *      can be halved without change, so candidates start at the bound;
 *   2. per map, the series from the bound down with the other maps at full
 *      resolution, searched by bisection: detection never falls as a map
 *      shrinks, so the passing candidates are a prefix of the series;
 *      000 eq. 1 fitted to the judged points regularises it (000 §6);
 *   3. the per-map choices together; while the combination fails, the map
 *      whose one step up helps the failing views most is enlarged
 *      (coordinate descent);
 *   4. the final combination on every view, and optionally on held-out
 *      views (another seed); the choice is made with p·(1 − margin) so that
 *      it holds there (docs/texres.md "Held-out views").
 * The baseColor × normal matrices of 000 Fig. 13 only on request. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"
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

/* The held-out safeguard (docs/texres.md "Held-out views"): a choice is
 * made with the threshold p·(1 − margin) on its views. */
#define TEXRES_MARGIN 0.5
/* and must pass this many further sets of views it was not chosen on */
#define TEXRES_CONFIRM_ROUNDS 2
#define TEXRES_MAX_CONFIRM_ROUNDS 16

void jnd_texres_defaults(jnd_texres_params *p) {
  memset(p, 0, sizeof *p);
  jnd_judge_defaults(&p->judge);
  p->margin = TEXRES_MARGIN;
  p->confirm_rounds = TEXRES_CONFIRM_ROUNDS;
  p->min_size = 32;
  p->matrix = 0;
  jnd_run_options_defaults(&p->run);
}

void jnd_texres_result_clear(jnd_texres_result *r) {
  free(r->maps);
  free(r->images);
  free(r->view_p);
  free(r->view_judge);
  free(r->verify_p);
  jnd_image_free(&r->worst_heatmap);
  for (int i = 0; i < r->nmatrix; i++) {
    free(r->matrix[i].p);
    free(r->matrix[i].stat);
  }
  free(r->matrix);
  free(r->report);
  memset(r, 0, sizeof *r);
}

void jnd_texres_result_free(jnd_texres_result *r) {
  if (!r) return;
  jnd_texres_result_clear(r);
  free(r);
}

/* ---- the search ---- */

#define JND_TEXRES_MAX_MAPS 256

typedef struct {
  int cur;                /* candidate in use (−1: the file's map) */
  jnd_image cache[JND_TEXRES_MAX_CAND];
} map_state;

typedef struct {
  jnd_scene *scene;
  const jnd_texres_params *p;
  jnd_judge *j;
  jnd_texres_result *res;
  map_state *ms;
  int *first;             /* per map: the first map that samples its image (the image's leader) */
  int total;              /* progress estimate (renderings) */
  /* The choice's views come in sets: the first, then each confirmation
   * set. Set i is the judge's views sets[i][0] … sets[i][0] + sets[i][1] − 1;
   * choice view v (0 … nviews − 1) counts them in set order. They are
   * named, not taken as the judge's views [0, nviews): a judge shared with
   * other searches (budget's, one search a mesh level) holds their
   * confirmation and held-out views between this search's sets. */
  int sets[1 + TEXRES_MAX_CONFIRM_ROUNDS][2];
  int nsets;
  int nviews;             /* the choice's views, all sets */
  double choice_p;        /* p·(1 − margin) */
} ctx;

/* the judge's index of choice view v */
static int judge_view(const ctx *c, int v) {
  for (int i = 0; i < c->nsets; v -= c->sets[i][1], i++)
    if (v < c->sets[i][1]) return c->sets[i][0] + v;
  return -1;
}

/* The choice holds when every set of views passes the criterion on its own:
 * views joining from a confirmation set must not loosen it (with more views
 * in one set, ⌊q·n⌋ would allow more above p). P and fail by choice view. */
static int sets_pass(const ctx *c, const double *P, unsigned char *fail) {
  int all = 1;
  for (int i = 0, first = 0; i < c->nsets; first += c->sets[i][1], i++) {
    jnd_criterion_result r;
    int n = c->sets[i][1];
    const jnd_criterion *cr = &c->p->judge.criterion;
    if (jnd_criterion_eval(P + first, n, c->choice_p, cr->q, cr->confidence, &r) != JND_OK || !r.pass) {
      all = 0;
      for (int v = first; fail && v < first + n; v++) fail[v] = P[v] > c->choice_p;
    } else if (fail) {
      memset(fail + first, 0, (size_t)n);
    }
  }
  return all;
}

static int renderings(const ctx *c) {
  jnd_judge_counts k;
  jnd_judge_get_counts(c->j, &k);
  return k.references + k.renderings + k.partial_renderings;
}

static void on_render(void *user, int done) {
  ctx *c = user;
  if (done > c->total) c->total = done;
  if (c->p->progress) c->p->progress(c->p->progress_user, NULL, done, c->total);
}

__attribute__((format(printf, 2, 3))) static void stage(ctx *c, const char *fmt, ...) {
  if (!c->p->progress) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  int done = renderings(c);
  c->p->progress(c->p->progress_user, line, done, c->total > done ? c->total : done);
}

/* The mip level lev of a map as the driver makes it (000 §4: a map whose
 * level 0 is never sampled can drop it, and what remains is its own mip
 * chain): 2^lev × 2^lev boxes, colour averaged in linear light as GL does
 * for sRGB textures, everything else as stored. Used for the candidate at
 * the mip-usage bound, so that it renders as the reference does; smaller
 * candidates are Lanczos-3 (000 §4). */
static jnd_status box_mip(const jnd_image *orig, int lev, jnd_map_kind kind, jnd_image *out) {
  return jnd_box_reduce_map(orig, lev, kind, out);
}

/* The finest mip level the views are taken to sample: the shader's estimate
 * of the level (the reference formula of anisotropic filtering) can differ
 * from what a driver samples by up to half a level — derivatives are taken
 * per 2×2 quad and drivers approximate the anisotropic footprint — so the
 * bound keeps half a level of margin. Without it, a map cut at the estimated
 * level rendered visibly differently on llvmpipe. */
#define MIP_MARGIN 0.5
int texres_mip_bound_level(double mip_min) {
  int lev = (int)floor(mip_min - MIP_MARGIN + 1e-6);
  return lev < 0 ? 0 : lev;
}

static int bound_level(const jnd_texres_map *m) { return texres_mip_bound_level(m->mip_min); }

/* candidate k is the mip-usage bound and an exact level of the map's chain */
static int is_mip_level(const jnd_texres_map *m, int k) {
  if (m->cand[k][0] != m->mip_bound[0] || m->cand[k][1] != m->mip_bound[1] || bound_level(m) < 1) return 0;
  int lev = bound_level(m);
  return lev < 31 && (m->orig[0] >> lev) == m->cand[k][0] && (m->orig[1] >> lev) == m->cand[k][1] &&
         (m->orig[0] % (1 << lev)) == 0 && (m->orig[1] % (1 << lev)) == 0;
}

static int is_orig(const jnd_texres_map *m, int k) {
  return k < 0 || (m->cand[k][0] == m->orig[0] && m->cand[k][1] == m->orig[1]);
}

/* puts map i at candidate k (−1: the file's map); resampled maps are kept */
static jnd_status set_map(ctx *c, int i, int k) {
  map_state *m = &c->ms[i];
  const jnd_texres_map *tm = &c->res->maps[i];
  if (m->cur == k) return JND_OK;
  jnd_status s = JND_OK;
  if (is_orig(tm, k)) {
    jnd_scene_map_restore(c->scene, tm->map);
  } else if (m->cache[k].data) {
    s = jnd_scene_map_set(c->scene, tm->map, &m->cache[k]);
  } else if (is_mip_level(tm, k)) {
    jnd_image orig = {0};
    int lev = 0;
    while ((tm->orig[0] >> lev) != tm->cand[k][0]) lev++;
    s = jnd_scene_map_get(c->scene, tm->map, 1, &orig);
    if (s == JND_OK) s = box_mip(&orig, lev, jnd_map_slot_kind(tm->slot), &m->cache[k]);
    jnd_image_free(&orig);
    if (s == JND_OK) s = jnd_scene_map_set(c->scene, tm->map, &m->cache[k]);
  } else {
    s = jnd_scene_map_resize(c->scene, tm->map, tm->cand[k][0], tm->cand[k][1]);
    if (s == JND_OK) s = jnd_scene_map_get(c->scene, tm->map, 0, &m->cache[k]);
  }
  if (s != JND_OK) return s;
  m->cur = k;
  return JND_OK;
}

/* The maps that sample one image are one texture on the GPU, so they take
 * one size: the largest any of them is at (its most demanding slot; −1, the
 * file's, is the largest of all). Their candidate lists are the same (same
 * original, same mip bound), so one index means one size. */
static void unify(const ctx *c, int *k) {
  for (int i = 0; i < c->res->nmaps; i++)
    if (c->first[i] != i && k[i] < k[c->first[i]]) k[c->first[i]] = k[i];
  for (int i = 0; i < c->res->nmaps; i++) k[i] = k[c->first[i]];
}

static jnd_status set_combo(ctx *c, const int *k) {
  for (int i = 0; i < c->res->nmaps; i++) {
    jnd_status s = set_map(c, i, k[i]);
    if (s != JND_OK) return s;
  }
  return JND_OK;
}

/* The combination k (candidate per map, −1: the file's) on views [first,
 * first + n): P per view into P (may be NULL) and the criterion statistic
 * with the choice threshold; flags as jnd_judge_eval. *pass (may be NULL):
 * the criterion with the choice threshold holds. */
static jnd_status judge_combo(ctx *c, const int *k, int first, int n, unsigned flags, double *P, double *stat,
                              int *pass, int *partial) {
  jnd_status s = set_combo(c, k);
  if (s != JND_OK) return s;
  jnd_judgement r;
  if ((s = jnd_judge_eval(c->j, first, n, flags, P, &r)) != JND_OK) return s;
  if (stat) *stat = r.criterion.statistic;
  if (pass) *pass = r.criterion.pass;
  if (partial) *partial = r.judged < n;
  return JND_OK;
}

/* combination k on every choice view, set by set (no early decision), into
 * P (c->nviews values); *stat and *pass the criterion at the choice
 * threshold over all of them together, as the judge gives it for one range */
static jnd_status judge_choice(ctx *c, const int *k, double *P, double *stat, int *pass) {
  jnd_status s = JND_OK;
  for (int i = 0, v = 0; i < c->nsets && s == JND_OK; v += c->sets[i][1], i++)
    s = judge_combo(c, k, c->sets[i][0], c->sets[i][1], 0, P + v, NULL, NULL, NULL);
  if (s != JND_OK || (!stat && !pass)) return s;
  const jnd_criterion *cr = &c->p->judge.criterion;
  jnd_criterion_result r;
  s = jnd_criterion_eval(P, c->nviews, c->choice_p > 0 ? c->choice_p : cr->p, cr->q, cr->confidence, &r);
  if (stat) *stat = r.statistic;
  if (pass) *pass = r.pass;
  return s;
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

static size_t map_bytes(const int *wh) { return jnd_texture_bytes(JND_TEX_RGBA8, wh[0], wh[1], 1); }

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

/* mip bound and eye bound of map m from the finest level any pixel samples */
static void bounds_from_level(const jnd_texres_params *p, jnd_texres_map *m) {
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
  double ppd = p->judge.model.display.ppd, cmax = fmin(60.0, ppd / 2);
  double factor = pow(2.0, m->mip_min) * ppd / (2 * cmax);
  for (int k = 0; k < 2; k++) {
    m->eye_bound[k] = (int)ceil(m->orig[k] / factor - 1e-9);
    if (m->eye_bound[k] < 1) m->eye_bound[k] = 1;
  }
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

static jnd_status run_matrix(ctx *c, int ia, int ib, const int *start, jnd_texres_matrix *mx) {
  jnd_texres_result *R = c->res;
  const jnd_texres_map *A = &R->maps[ia], *B = &R->maps[ib];
  int a0 = start[ia], b0 = start[ib], nviews = c->nviews;
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
    if (mx->na < 1) mx->na = 1;
    if (mx->nb < 1) mx->nb = 1;
    mx->complete = A->ncand - a0 == mx->na && B->ncand - b0 == mx->nb;
  } else {
    mx->complete = 1;
  }
  mx->nviews = nviews;
  for (int a = 0; a < mx->na; a++) mx->size_a[a] = longer(A->cand[a0 + a]);
  for (int b = 0; b < mx->nb; b++) mx->size_b[b] = longer(B->cand[b0 + b]);
  mx->p = jnd_calloc((size_t)nviews * mx->na * mx->nb, sizeof *mx->p);
  mx->stat = jnd_calloc((size_t)mx->na * mx->nb, sizeof *mx->stat);
  int *k = jnd_calloc((size_t)R->nmaps, sizeof *k);
  double *P = jnd_calloc((size_t)nviews, sizeof *P);
  jnd_status s = mx->p && mx->stat && k && P ? JND_OK : JND_ERR_NOMEM;
  for (int i = 0; i < R->nmaps; i++) k[i] = -1;
  mx->best_a = mx->best_b = -1;
  size_t best_bytes = (size_t)-1;
  for (int a = 0; a < mx->na && s == JND_OK; a++)
    for (int b = 0; b < mx->nb && s == JND_OK; b++) {
      k[ia] = a0 + a;
      k[ib] = b0 + b;
      double st;
      int pass;
      if ((s = judge_choice(c, k, P, &st, &pass)) != JND_OK) break;
      for (int v = 0; v < nviews; v++) mx->p[((size_t)v * mx->na + a) * mx->nb + b] = P[v];
      mx->stat[a * mx->nb + b] = st;
      size_t bytes = map_bytes(A->cand[a0 + a]) + map_bytes(B->cand[b0 + b]);
      if (pass && bytes < best_bytes) {
        best_bytes = bytes;
        mx->best_a = a;
        mx->best_b = b;
      }
    }
  free(k);
  free(P);
  return s;
}

/* Per map alone (the others at the file's size): the candidates from the
 * bound down, by bisection. Detection never falls as a map shrinks, so the
 * candidates that pass are the first ones of the series; lo is the last
 * known to pass (start − 1: none judged yet, the bound taken as passing),
 * hi the first known to fail. About log2(n + 1) judgements instead of n. */
static jnd_status search_map(ctx *c, int i, int start, int *k) {
  jnd_texres_map *m = &c->res->maps[i];
  int lo = start - 1, hi = m->ncand, judged = 0;
  if (is_orig(m, start)) {   /* the reference itself */
    m->series[start] = 0;
    lo = start;
  }
  jnd_status s = JND_OK;
  while (hi - lo > 1 && s == JND_OK) {
    int mid = lo + (hi - lo + 1) / 2, pass, partial;
    double st;
    k[i] = mid;
    /* before confirmation: the first set, one range */
    if ((s = judge_combo(c, k, c->sets[0][0], c->sets[0][1], JND_JUDGE_DECIDE, NULL, &st, &pass, &partial)) != JND_OK)
      break;
    judged++;
    m->series[mid] = st;
    m->series_partial[mid] = (unsigned char)partial;
    if (pass) lo = mid;
    else hi = mid;
  }
  k[i] = -1;
  if (s != JND_OK) return s;
  int choice = lo >= start ? lo : start;
  m->chosen[0] = m->cand[choice][0];
  m->chosen[1] = m->cand[choice][1];
  /* 000 eq. 1 over the judged points, in log2 resolution (docs/texres.md) */
  double rr[JND_TEXRES_MAX_CAND], pp[JND_TEXRES_MAX_CAND];
  int n = 0;
  for (int j = 0; j < m->ncand; j++)
    if (isfinite(m->series[j])) rr[n] = longer(m->cand[j]), pp[n++] = m->series[j];
  if (n >= 2 && jnd_psychometric_fit(rr, pp, n, 1, &m->fit) == JND_OK) {
    m->fit_ok = 1;
    m->fit_res = jnd_psychometric_resolution(&m->fit, c->choice_p);
    int best = start;
    for (int j = start; j < m->ncand; j++)
      if (longer(m->cand[j]) >= m->fit_res - 1e-6) best = j;
    m->fit_cand[0] = m->cand[best][0];
    m->fit_cand[1] = m->cand[best][1];
  }
  stage(c, "%s: %d judgements, %dx%d of %dx%d (bound %dx%d)", m->name, judged, m->chosen[0], m->chosen[1],
        m->orig[0], m->orig[1], m->mip_bound[0], m->mip_bound[1]);
  return JND_OK;
}

/* The choices together. Each map alone may use up the view's budget: P93
 * is P at the 93rd percentile of the object's pixels, so at most 7% of them
 * may lie above p, and the maps of different materials spend that share on
 * different pixels. So while the combination fails, the material with the
 * most pixels above p in the failing views (jnd_judge_material_counts) gets
 * one of its maps one candidate larger: the one most visible on its own
 * (its series statistic at its current size). One judgement a round. */
static jnd_status descend(ctx *c, int *k, const int *start) {
  int nm = c->res->nmaps, N = c->nviews, nmat = jnd_scene_material_count(c->scene), rounds = 0;
  double *P = jnd_calloc((size_t)N, sizeof *P), *score = jnd_calloc((size_t)nmat + 1, sizeof *score);
  int *cnt = jnd_calloc((size_t)nmat + 1, sizeof *cnt);
  unsigned char *fail = jnd_calloc((size_t)N, 1);
  jnd_status s = P && score && cnt && fail ? JND_OK : JND_ERR_NOMEM;
  int pass = 0;
  if (s == JND_OK) s = judge_choice(c, k, P, NULL, NULL);
  if (s == JND_OK) pass = sets_pass(c, P, fail);
  for (; s == JND_OK && !pass && rounds < 16 * nm; rounds++) {
    memset(score, 0, (size_t)nmat * sizeof *score);
    for (int v = 0; v < N && s == JND_OK; v++) {
      if (!fail[v]) continue;
      if ((s = jnd_judge_material_counts(c->j, judge_view(c, v), cnt)) != JND_OK) break;
      for (int m = 0; m < nmat; m++) score[m] += cnt[m];
    }
    int best_i = -1;
    double best_score = -1, best_vis = -1;
    for (int i = 0; i < nm && s == JND_OK; i++) {
      const jnd_texres_map *m = &c->res->maps[i];
      if (!m->searched || k[i] <= start[i] || m->material < 0) continue;
      double sc = score[m->material], vis = isfinite(m->series[k[i]]) ? m->series[k[i]] : 0;
      if (sc > best_score || (sc == best_score && vis > best_vis)) best_i = i, best_score = sc, best_vis = vis;
    }
    if (s != JND_OK || best_i < 0) break; /* every map at its bound */
    k[best_i]--;
    unify(c, k);  /* its image, with every slot that samples it */
    s = judge_choice(c, k, P, NULL, NULL);
    if (s == JND_OK) pass = sets_pass(c, P, fail);
  }
  if (s == JND_OK) stage(c, "together: %d map(s) enlarged one step, %s", rounds, pass ? "passes" : "still fails");
  free(P);
  free(score);
  free(cnt);
  free(fail);
  return s;
}

/* Views the choice was not made on (another seed: another rotation of the
 * spiral and other lights): the combination must pass them too, as a set of
 * their own, or they join the choice's views (each set judged on its own)
 * and the descent goes on (docs/texres.md "Held-out views"). Seeds differ
 * from the held-out check's. */
static jnd_status confirm(ctx *c, int *k, const int *start) {
  const jnd_texres_params *p = c->p;
  int N0 = c->sets[0][1];
  for (int round = 0; round < p->confirm_rounds; round++) {
    jnd_view_set vs = p->judge.views;
    vs.cameras = NULL;
    vs.cameras_path = NULL;
    vs.sampling.count = N0;
    vs.sampling.seed = p->judge.views.sampling.seed + 1000003u * (uint64_t)(round + 1);
    jnd_view *views = NULL;
    int n = 0, first = 0, pass = 0;
    double stat = 0;
    jnd_status s = jnd_view_set_make(c->scene, &vs, &views, &n);
    if (s == JND_OK) s = jnd_judge_add_views(c->j, views, n, &first);
    free(views);
    if (s == JND_OK) s = judge_combo(c, k, first, n, JND_JUDGE_DECIDE, NULL, &stat, &pass, NULL);
    if (s != JND_OK) return s;
    /* they are the choice's views from now on, a set of their own */
    c->sets[c->nsets][0] = first;
    c->sets[c->nsets][1] = n;
    c->nsets++;
    c->nviews += n;
    stage(c, "confirmation views %d: the choice %s (statistic %s%.3f)", round + 1, pass ? "holds" : "fails",
          pass ? "" : ">= ", stat);
    if (pass) break;
    if ((s = descend(c, k, start)) != JND_OK) return s;
  }
  return JND_OK;
}

/* The held-out views: another seed gives another rotation of the spiral
 * and other lights. */
static jnd_status held_out(ctx *c, const int *k) {
  const jnd_texres_params *p = c->p;
  int M = p->verify_views;
  jnd_texres_result *out = c->res;
  jnd_view_set vs = p->judge.views;
  vs.cameras = NULL;
  vs.cameras_path = NULL;
  vs.sampling.count = M;
  vs.sampling.seed = p->judge.views.sampling.seed * 7919u + 104729u;
  jnd_view *views = NULL;
  int n = 0, first = 0;
  jnd_status s = jnd_view_set_make(c->scene, &vs, &views, &n);
  if (s == JND_OK) s = jnd_judge_add_views(c->j, views, n, &first);
  free(views);
  out->verify_views = M;
  out->verify_p = jnd_calloc((size_t)M, sizeof *out->verify_p);
  if (s == JND_OK && !out->verify_p) s = JND_ERR_NOMEM;
  if (s == JND_OK) s = judge_combo(c, k, first, M, 0, out->verify_p, NULL, NULL, NULL);
  const jnd_criterion *cr = &p->judge.criterion;
  if (s == JND_OK) s = jnd_criterion_eval(out->verify_p, M, cr->p, cr->q, cr->confidence, &out->verify);
  if (s == JND_OK)
    stage(c, "held-out views: %d of %d above P = %g (%s; at most %.0f%% of all views above, %.0f%% confidence)",
          out->verify.above, M, cr->p, out->verify.pass ? "passes" : "FAILS", 100 * out->verify.fraction_upper,
          100 * cr->confidence);
  return s;
}

/* Memory before and after as a GPU holds it (000 Table 2, with mip chains):
 * each unique image once, however many slots sample it, at its one size. */
static jnd_status count_images(ctx *c) {
  jnd_texres_result *R = c->res;
  R->images = jnd_calloc((size_t)R->nmaps, sizeof *R->images);
  if (!R->images) return JND_ERR_NOMEM;
  for (int i = 0; i < R->nmaps; i++) {
    jnd_texres_map *m = &R->maps[i];
    if (c->first[i] == i) {
      jnd_texres_image *im = &R->images[R->nimages];
      im->first_map = i;
      memcpy(im->orig, m->orig, sizeof im->orig);
      memcpy(im->chosen, m->chosen, sizeof im->chosen);
      im->block_format = jnd_slot_block_format(m->slot, m->channels);
      m->image = R->nimages++;
    } else {
      m->image = R->maps[c->first[i]].image;
    }
    jnd_texres_image *im = &R->images[m->image];
    jnd_tex_format f = jnd_slot_block_format(m->slot, m->channels);
    /* 12 × 12 texels: whole blocks of every format, so bytes per texel compare */
    if (jnd_texture_bytes(f, 12, 12, 0) > jnd_texture_bytes(im->block_format, 12, 12, 0)) im->block_format = f;
    im->nmaps++;
  }
  for (int t = 0; t < R->nimages; t++) {
    jnd_texres_image *im = &R->images[t];
    for (int f = 0; f < JND_TEX_FORMATS; f++) {
      im->bytes_before[f] = jnd_texture_bytes((jnd_tex_format)f, im->orig[0], im->orig[1], 1);
      im->bytes_after[f] = jnd_texture_bytes((jnd_tex_format)f, im->chosen[0], im->chosen[1], 1);
      R->before_bytes[f] += im->bytes_before[f];
      R->after_bytes[f] += im->bytes_after[f];
    }
    R->block_before_bytes += im->bytes_before[im->block_format];
    R->block_after_bytes += im->bytes_after[im->block_format];
  }
  return JND_OK;
}

jnd_status jnd_texres_search(jnd_scene *scene, const jnd_texres_params *pp, jnd_texres_result *out) {
  memset(out, 0, sizeof *out);
  jnd_texres_params pd;
  if (!pp) {
    jnd_texres_defaults(&pd);
    pp = &pd;
  }
  const jnd_texres_params *p = pp;
  const jnd_criterion *cr = &p->judge.criterion;
  /* one line naming the parameter (the Python package relies on it) */
  if (!(cr->p > 0 && cr->p < 1) || !(cr->q >= 0 && cr->q < 1))
    return jnd_fail(JND_ERR_ARG, "texres: criterion p %g, q %g (p in (0, 1), q in [0, 1))", cr->p, cr->q);
  if (p->min_size < 1) return jnd_fail(JND_ERR_ARG, "texres: smallest size %d is not positive", p->min_size);
  if (p->verify_views < 0) return jnd_fail(JND_ERR_ARG, "texres: %d held-out views is negative", p->verify_views);
  if (!(p->margin >= 0 && p->margin < 1))
    return jnd_fail(JND_ERR_ARG, "texres: margin %g is outside [0, 1)", p->margin);
  if (p->confirm_rounds < 0 || p->confirm_rounds > TEXRES_MAX_CONFIRM_ROUNDS)
    return jnd_fail(JND_ERR_ARG, "texres: %d confirmation rounds (0..%d)", p->confirm_rounds,
                    TEXRES_MAX_CONFIRM_ROUNDS);
  int nall = jnd_scene_map_count(scene);
  if (nall == 0) return jnd_fail(JND_ERR_ARG, "%s: the asset has no texture maps", jnd_scene_path(scene));
  if (nall > JND_TEXRES_MAX_MAPS)
    return jnd_fail(JND_ERR_LIMIT, "%s: %d texture maps (at most %d)", jnd_scene_path(scene), nall, JND_TEXRES_MAX_MAPS);
  jnd_status s = check_list(scene, p->maps);
  if (s != JND_OK) return s;

  ctx c = {.scene = scene, .p = p, .res = out, .choice_p = cr->p * (1 - p->margin)};
  int *k = NULL, *start = NULL;
  int nsearch = 0;
  out->nmaps = nall;
  out->choice_p = c.choice_p;
  out->maps = jnd_calloc((size_t)nall, sizeof *out->maps);
  c.ms = jnd_calloc((size_t)nall, sizeof *c.ms);
  c.first = jnd_calloc((size_t)nall, sizeof *c.first);
  k = jnd_calloc((size_t)nall, sizeof *k);
  start = jnd_calloc((size_t)nall, sizeof *start);
  if (!out->maps || !c.ms || !c.first || !k || !start) {
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
    /* a shared image of another size cannot be (the same file's pixels):
     * then the map is taken as its own image */
    c.first[i] = mi.image >= 0 && mi.image < i && out->maps[mi.image].orig[0] == m->orig[0] &&
                         out->maps[mi.image].orig[1] == m->orig[1]
                     ? c.first[mi.image]
                     : i;
    m->searched = wanted(p->maps, &mi);
    nsearch += m->searched;
    make_candidates(p, m);
    for (int j = 0; j < JND_TEXRES_MAX_CAND; j++) m->series[j] = NAN;
    c.ms[i].cur = -1;
    k[i] = -1;
  }
  out->ppd = p->judge.model.display.ppd;

  /* the judge: views and their reference renderings (full resolution); it
   * decides with the choice threshold, the report states p */
  jnd_judge_params jp = p->judge;
  jp.criterion.p = c.choice_p > 0 ? c.choice_p : cr->p;
  jp.progress = on_render;
  jp.progress_user = &c;
  c.nviews = p->judge.views.cameras ? p->judge.views.ncameras : p->judge.views.sampling.count;
  c.sets[0][0] = 0;   /* the first set: the judge's first views (a shared judge's too) */
  c.sets[0][1] = c.nviews;
  c.nsets = 1;
  c.total = c.nviews * (2 + 3 * nsearch) + 2 * p->verify_views;
  /* the reference is level 0; the candidates draw p->level (a mesh level
   * changed is rendered whole, the maps' states still memoised) */
  if ((s = jnd_scene_lod_select(scene, 0)) != JND_OK) goto done;
  if (p->judge_shared) {
    if (jnd_judge_view_count(p->judge_shared) < c.nviews) {
      s = jnd_fail(JND_ERR_ARG, "texres: the shared judge has %d views, the search %d",
                   jnd_judge_view_count(p->judge_shared), c.nviews);
      goto done;
    }
    c.j = p->judge_shared;
  } else if ((s = jnd_judge_create(scene, &jp, &c.j)) != JND_OK) {
    goto done;
  }
  if (p->level && (s = jnd_scene_lod_select(scene, p->level)) != JND_OK) goto done;
  snprintf(out->renderer, sizeof out->renderer, "%s", jnd_judge_renderer(c.j));
  for (int i = 0; i < nall; i++) out->maps[i].mip_min = jnd_judge_mip_min(c.j, i, 0, c.nviews);
  /* an image's level 0 can go only when no slot that samples it samples it */
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i], *f = &out->maps[c.first[i]];
    if (m->mip_min >= 0 && (f->mip_min < 0 || m->mip_min < f->mip_min)) f->mip_min = m->mip_min;
  }
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i];
    m->mip_min = out->maps[c.first[i]].mip_min;
    bounds_from_level(p, m);
    if (m->mip_min >= 0) insert_bound(m);
    start[i] = first_allowed(m);
  }
  stage(&c, "references: %d views at %dx%d on %s", c.nviews, p->judge.views.render.width,
        p->judge.views.render.height, out->renderer);

  /* per-map series from the bound down */
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i];
    if (!m->searched) {
      m->chosen[0] = m->orig[0];
      m->chosen[1] = m->orig[1];
      continue;
    }
    if ((s = search_map(&c, i, start[i], k)) != JND_OK) goto done;
  }

  /* the choices together */
  for (int i = 0; i < nall; i++) {
    k[i] = -1;
    if (!out->maps[i].searched) continue;
    for (int j = 0; j < out->maps[i].ncand; j++)
      if (out->maps[i].cand[j][0] == out->maps[i].chosen[0] && out->maps[i].cand[j][1] == out->maps[i].chosen[1])
        k[i] = j;
  }
  unify(&c, k);
  if ((s = descend(&c, k, start)) != JND_OK) goto done;
  if ((s = confirm(&c, k, start)) != JND_OK) goto done;

  /* the matrices of 000 Fig. 13, on request */
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
      c.total += c.nviews * (out->maps[ia].ncand - start[ia]) * (out->maps[ib].ncand - start[ib]);
      s = run_matrix(&c, ia, ib, start, &out->matrix[out->nmatrix]);
      out->nmatrix++;
      if (s != JND_OK) goto done;
      /* with exactly these two maps searched the matrix is the search */
      jnd_texres_matrix *mx = &out->matrix[out->nmatrix - 1];
      if (nsearch == 2 && mx->best_a >= 0) {
        k[ia] = start[ia] + mx->best_a;
        k[ib] = start[ib] + mx->best_b;
      }
      stage(&c, "matrix %s x %s: %d x %d cells", out->maps[ia].name, out->maps[ib].name, mx->na, mx->nb);
    }
  }
  /* the choice: one size per image (a matrix's pair may share an image with other slots) */
  unify(&c, k);
  for (int i = 0; i < nall; i++) {
    jnd_texres_map *m = &out->maps[i];
    m->chosen[0] = k[i] >= 0 ? m->cand[k[i]][0] : m->orig[0];
    m->chosen[1] = k[i] >= 0 ? m->cand[k[i]][1] : m->orig[1];
  }

  /* the final combination on every view (judged already: no rendering) */
  out->nviews = c.nviews;
  out->view_p = jnd_calloc((size_t)c.nviews, sizeof *out->view_p);
  out->view_judge = jnd_calloc((size_t)c.nviews, sizeof *out->view_judge);
  if (!out->view_p || !out->view_judge) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  for (int v = 0; v < c.nviews; v++) out->view_judge[v] = judge_view(&c, v);
  if ((s = judge_choice(&c, k, out->view_p, NULL, NULL)) != JND_OK) goto done;
  if ((s = jnd_criterion_eval(out->view_p, c.nviews, cr->p, cr->q, cr->confidence, &out->views)) != JND_OK) goto done;
  out->worst_view = out->views.worst_view;
  {
    /* 000's picture of the worst view: the object beside its heatmap */
    jnd_image map = {0}, frame = {0};
    s = jnd_judge_view_images(c.j, out->view_judge[out->worst_view], &map, &frame, NULL, NULL, NULL);
    if (s == JND_OK)
      s = texres_worst_view_figure(&frame, &map, out->worst_view, c.nviews, out->view_p[out->worst_view],
                                   &out->worst_heatmap);
    jnd_image_free(&map);
    jnd_image_free(&frame);
    if (s != JND_OK) goto done;
  }
  if (p->verify_views > 0 && (s = held_out(&c, k)) != JND_OK) goto done;

  if ((s = count_images(&c)) != JND_OK) goto done;
  /* leave the scene with the chosen maps */
  for (int i = 0; i < nall; i++) {
    int j = -1;
    for (int q = 0; q < out->maps[i].ncand; q++)
      if (out->maps[i].cand[q][0] == out->maps[i].chosen[0] && out->maps[i].cand[q][1] == out->maps[i].chosen[1]) j = q;
    if ((s = set_map(&c, i, j)) != JND_OK) goto done;
  }
  jnd_judge_get_counts(c.j, &out->counts);
  out->evaluations = out->counts.states;
  out->renderings = out->counts.references + out->counts.renderings + out->counts.partial_renderings;
  s = JND_OK;
done:
  if (c.ms)
    for (int i = 0; i < nall; i++)
      for (int j = 0; j < JND_TEXRES_MAX_CAND; j++) jnd_image_free(&c.ms[i].cache[j]);
  free(c.ms);
  free(c.first);
  free(k);
  free(start);
  if (!p->judge_shared) jnd_judge_free(c.j);
  if (p->level) jnd_scene_lod_select(scene, 0);
  if (s != JND_OK) jnd_texres_result_clear(out);
  return s;
}
