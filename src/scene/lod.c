/* Levels of detail of a scene: the chain made with meshoptimizer 0.18, levels
 * taken from other files, and the selection of the level in use.
 *
 * How a level of one mesh is made (docs/lod.md):
 *  1. Seams. meshopt_simplify keeps the topology of the index buffer it is
 *     given: vertices that share a position but not their attributes are a
 *     seam, and a seam only collapses along itself. The index buffer handed
 *     to it is a shadow index buffer over position, both uv sets and the
 *     vertex colour (meshopt_generateShadowIndexBufferMulti): uv and colour
 *     seams are kept, while vertices that differ only in their normal (hard
 *     edges, faceted meshes) are one vertex to the simplifier, which would
 *     otherwise get stuck on them (meshoptimizer's README recommends this).
 *  2. Normals. Each corner of a simplified triangle then takes, among the
 *     input's vertices that share its position, uv and colour, the one whose
 *     normal is closest to the triangle's own: a hard edge stays hard where
 *     the simplified surface still bends there, and smooth vertices (one
 *     normal each) are untouched.
 *  3. Targets. meshopt_simplify runs with no target count and the level's
 *     error target (converted from the scene's extent to the mesh's, since
 *     meshoptimizer measures error relative to the vertex buffer it gets);
 *     its result_error is the level's error. Levels aimed at triangle ratios
 *     run with a target count and no error bound.
 *  4. Sources. Not every level is made from the input: level k is made
 *     from the coarsest earlier level whose target is at most a quarter of
 *     its own (the input when there is none), with the error left over as
 *     its budget; its error is then the source's plus the step's, an upper
 *     bound. With the default doubling targets the first two levels come
 *     from the input and each later one from the level two before it, so
 *     at least 3/4 of every target is spent on the level itself. A pass
 *     over a 1 M-triangle input costs more than the rest of the chain, so
 *     where a mesh of the input is large enough to be cut in slabs (step 5)
 *     only level 1 is made from the input and level 2 from level 1 (half
 *     its target left for the step). The sources are fixed by the targets
 *     and level 0's size, so the chain does not depend on the thread count.
 *  5. Slabs. meshopt_simplify runs on one thread; a large source is cut
 *     into slabs simplified in parallel with their cuts locked, joined, and
 *     the level made from the joined mesh (slab_of_triangles, below).
 *  6. Fallback. Where meshopt_simplify stopped short of the target because
 *     no edge can collapse at all any more (a probe with no error bound
 *     collapses nothing), meshopt_simplifySloppy is tried from the same
 *     source with the same budget, and kept if it has fewer triangles; the
 *     level says so (JND_LOD_SLOPPY), since sloppy simplification ignores
 *     seams.
 *  7. Chain. A mesh never gets more triangles than at the level before, and
 *     a level with no fewer triangles in all than the one before is dropped. */
#include <float.h>
#include <math.h>
#include <meshoptimizer.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"

enum { MAX_LEVELS = 64 };

static const double default_errors[] = {1.0 / 4096, 1.0 / 2048, 1.0 / 1024, 1.0 / 512, 1.0 / 256,
                                        1.0 / 128,  1.0 / 64,   1.0 / 32,   1.0 / 16};

void jnd_lod_defaults(jnd_lod_params *p) {
  memset(p, 0, sizeof *p);
  p->lock_border = -1;
  p->allow_sloppy = 1;
}

/* ---- level storage ---- */

static void free_level(jnd_lod_level *L, int nmeshes) {
  if (!L->mesh) return;
  for (int i = 0; i < nmeshes; i++) {
    free(L->mesh[i].vertices);
    free(L->mesh[i].indices);
  }
  free(L->mesh);
  L->mesh = NULL;
}

void jnd_scene_lod_free(jnd_scene *s) {
  for (int k = 0; k < s->nlod; k++) free_level(&s->lod[k], s->nmeshes);
  free(s->lod);
  s->lod = NULL;
  s->nlod = s->lod_now = 0;
}

/* distinct vertices the triangles of (indices, ntris) use */
static size_t used_vertices(const uint32_t *idx, size_t ntris, size_t nverts, unsigned char *mark) {
  memset(mark, 0, nverts);
  size_t n = 0;
  for (size_t i = 0; i < 3 * ntris; i++)
    if (!mark[idx[i]]) mark[idx[i]] = 1, n++;
  return n;
}

static jnd_status level_counts(const jnd_scene *s, jnd_lod_level *L) {
  size_t most = 1;
  for (int i = 0; i < s->nmeshes; i++) {
    const jnd_lod_mesh *m = &L->mesh[i];
    size_t nv = m->vertices ? m->nverts : s->lod[0].mesh[i].nverts;
    if (nv > most) most = nv;
  }
  unsigned char *mark = jnd_alloc(most, 1);
  if (!mark) return JND_ERR_NOMEM;
  L->info.triangles = L->info.vertices = 0;
  for (int i = 0; i < s->nmeshes; i++) {
    const jnd_lod_mesh *m = &L->mesh[i];
    size_t nv = m->vertices ? m->nverts : s->lod[0].mesh[i].nverts;
    L->info.triangles += m->ntris;
    L->info.vertices += used_vertices(m->indices, m->ntris, nv, mark);
  }
  free(mark);
  return JND_OK;
}

/* Level 0 takes over the file's arrays on first use. */
static jnd_status ensure_levels(jnd_scene *s) {
  if (s->nlod > 0) return JND_OK;
  jnd_lod_level *L = jnd_calloc(1, sizeof *L);
  jnd_lod_mesh *m = L ? jnd_calloc(s->nmeshes ? (size_t)s->nmeshes : 1, sizeof *m) : NULL;
  if (!m) {
    free(L);
    return JND_ERR_NOMEM;
  }
  for (int i = 0; i < s->nmeshes; i++) {
    m[i].vertices = s->meshes[i].vertices;
    m[i].nverts = s->meshes[i].nverts;
    m[i].indices = s->meshes[i].indices;
    m[i].ntris = s->meshes[i].ntris;
    m[i].version = s->meshes[i].version;
  }
  L->mesh = m;
  L->info.method = JND_LOD_INPUT;
  L->info.target_ratio = NAN;
  s->lod = L;
  s->nlod = 1;
  s->lod_now = 0;
  jnd_status st = level_counts(s, L);
  if (st) {
    /* give the arrays back to the meshes */
    free(m);
    free(L);
    s->lod = NULL;
    s->nlod = 0;
  }
  return st;
}

int jnd_scene_lod_count(const jnd_scene *s) { return s->nlod > 0 ? s->nlod : 1; }
int jnd_scene_lod_selected(const jnd_scene *s) { return s->nlod > 0 ? s->lod_now : 0; }

jnd_status jnd_scene_lod_info(const jnd_scene *s, int level, jnd_lod_level_info *out) {
  if (level < 0 || level >= jnd_scene_lod_count(s))
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the chain has %d)", s->path, level, jnd_scene_lod_count(s));
  if (s->nlod > 0) {
    *out = s->lod[level].info;
    return JND_OK;
  }
  memset(out, 0, sizeof *out);
  out->method = JND_LOD_INPUT;
  out->target_ratio = NAN;
  out->triangles = jnd_scene_triangle_count(s);
  for (int i = 0; i < s->nmeshes; i++) {
    unsigned char *mark = jnd_alloc(s->meshes[i].nverts ? s->meshes[i].nverts : 1, 1);
    if (!mark) return JND_ERR_NOMEM;
    out->vertices += used_vertices(s->meshes[i].indices, s->meshes[i].ntris, s->meshes[i].nverts, mark);
    free(mark);
  }
  return JND_OK;
}

/* mesh i drawn at level (a simplified level indexes level 0's vertices) */
static void use_level(jnd_scene *s, int i, int level) {
  const jnd_lod_mesh *m = &s->lod[level].mesh[i], *base = &s->lod[0].mesh[i];
  jnd_mesh *d = &s->meshes[i];
  d->vertices = m->vertices ? m->vertices : base->vertices;
  d->nverts = m->vertices ? m->nverts : base->nverts;
  d->indices = m->indices;
  d->ntris = m->ntris;
  d->version = m->version;
}

jnd_status jnd_scene_lod_select(jnd_scene *s, int level) {
  if (level < 0 || level >= jnd_scene_lod_count(s))
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the chain has %d)", s->path, level, jnd_scene_lod_count(s));
  if (s->nlod == 0) return JND_OK;
  for (int i = 0; i < s->nmeshes; i++) use_level(s, i, level);
  s->lod_now = level;
  return JND_OK;
}

jnd_status jnd_scene_lod_select_mesh(jnd_scene *s, int mesh, int level) {
  if (mesh < 0 || mesh >= s->nmeshes)
    return jnd_fail(JND_ERR_ARG, "%s: mesh %d out of range (the scene has %d)", s->path, mesh, s->nmeshes);
  if (level < 0 || level >= jnd_scene_lod_count(s))
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the chain has %d)", s->path, level, jnd_scene_lod_count(s));
  if (s->nlod > 0) use_level(s, mesh, level);
  return JND_OK;
}

int jnd_scene_lod_mesh_level(const jnd_scene *s, int mesh) {
  if (mesh < 0 || mesh >= s->nmeshes) return -1;
  for (int k = 0; k < s->nlod; k++)
    if (s->lod[k].mesh[mesh].version == s->meshes[mesh].version) return k;
  return 0;
}

/* ---- geometry helpers ---- */

static const float *pos(const float *verts, uint32_t v) { return verts + (size_t)v * JND_VTX_FLOATS; }

static void face_normal(const float *a, const float *b, const float *c, double n[3]) {
  double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

static double scene_extent(const jnd_scene *s);

double jnd_scene_extent(const jnd_scene *s) {
  if (s->nlod == 0) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, e = 0;
    for (int i = 0; i < s->nmeshes; i++)
      for (size_t t = 0; t < 3 * s->meshes[i].ntris; t++) {
        const float *p = pos(s->meshes[i].vertices, s->meshes[i].indices[t]);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], p[k]), hi[k] = fmax(hi[k], p[k]);
      }
    for (int k = 0; k < 3; k++)
      if (hi[k] - lo[k] > e) e = hi[k] - lo[k];
    return e;
  }
  return scene_extent(s);
}

/* The largest side of the bounding box of level 0 (meshopt_simplifyScale's
 * unit, over every mesh). */
static double scene_extent(const jnd_scene *s) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < s->nmeshes; i++) {
    const jnd_lod_mesh *m = &s->lod[0].mesh[i];
    for (size_t t = 0; t < 3 * m->ntris; t++) {
      const float *p = pos(m->vertices, m->indices[t]);
      for (int k = 0; k < 3; k++) {
        if (p[k] < lo[k]) lo[k] = p[k];
        if (p[k] > hi[k]) hi[k] = p[k];
      }
    }
  }
  double e = 0;
  for (int k = 0; k < 3; k++)
    if (hi[k] - lo[k] > e) e = hi[k] - lo[k];
  return e;
}

static double scene_area(const jnd_scene *s) {
  double area = 0;
  for (int i = 0; i < s->nmeshes; i++) {
    const jnd_lod_mesh *m = &s->lod[0].mesh[i];
    for (size_t t = 0; t < m->ntris; t++) {
      double n[3];
      face_normal(pos(m->vertices, m->indices[3 * t]), pos(m->vertices, m->indices[3 * t + 1]),
                  pos(m->vertices, m->indices[3 * t + 2]), n);
      area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
  }
  return area;
}

/* ---- one mesh's simplification ---- */

/* What every level of one mesh shares: the shadow representative of each
 * vertex (same position, uvs and colour) and, per representative, the list
 * of the vertices it stands for (to take normals back). */
typedef struct {
  const float *verts;
  size_t nverts;
  uint32_t *rep;     /* nverts */
  uint32_t *next;    /* nverts: the next vertex with the same representative, UINT32_MAX at the end */
} mesh_prep;

static jnd_status prep_mesh(const jnd_lod_mesh *m, mesh_prep *p) {
  memset(p, 0, sizeof *p);
  p->verts = m->vertices;
  p->nverts = m->nverts;
  size_t n = m->nverts ? m->nverts : 1, n3 = (n + 2) / 3 * 3;   /* meshoptimizer wants whole triangles */
  p->rep = jnd_alloc(n3, sizeof *p->rep);
  p->next = jnd_alloc(n, sizeof *p->next);
  uint32_t *ident = jnd_alloc(n3, sizeof *ident);
  if (!p->rep || !p->next || !ident) {
    free(ident);
    return JND_ERR_NOMEM;
  }
  for (size_t v = 0; v < n3; v++) ident[v] = (uint32_t)(v < m->nverts ? v : 0);
  const size_t stride = JND_VTX_FLOATS * sizeof(float);
  /* position, uv0, uv1, colour: the attributes whose seams are kept */
  struct meshopt_Stream streams[4] = {{m->vertices, 3 * sizeof(float), stride},
                                      {m->vertices + 10, 2 * sizeof(float), stride},
                                      {m->vertices + 12, 2 * sizeof(float), stride},
                                      {m->vertices + 14, 4 * sizeof(float), stride}};
  if (m->nverts) meshopt_generateShadowIndexBufferMulti(p->rep, ident, n3, m->nverts, streams, 4);
  free(ident);
  /* lists: a representative heads its list (it is its class's first vertex) */
  uint32_t *tail = jnd_alloc(n, sizeof *tail);
  if (!tail) return JND_ERR_NOMEM;
  for (size_t v = 0; v < m->nverts; v++) {
    p->next[v] = UINT32_MAX;
    uint32_t r = p->rep[v];
    if (r == v) tail[v] = (uint32_t)v;
    else {
      p->next[tail[r]] = (uint32_t)v;
      tail[r] = (uint32_t)v;
    }
  }
  free(tail);
  return JND_OK;
}

static void prep_free(mesh_prep *p) {
  free(p->rep);
  free(p->next);
}

/* Step 2: each corner takes the vertex of its class whose normal is closest
 * to the triangle's normal. idx holds representatives in, vertices out. */
static void take_normals(const mesh_prep *p, uint32_t *idx, size_t ntris) {
  for (size_t t = 0; t < ntris; t++) {
    uint32_t *c = idx + 3 * t;
    double n[3];
    face_normal(pos(p->verts, c[0]), pos(p->verts, c[1]), pos(p->verts, c[2]), n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0)) continue;
    for (int k = 0; k < 3; k++) {
      uint32_t best = c[k];
      if (p->next[best] == UINT32_MAX) continue;   /* one normal: nothing to choose */
      double best_dot = -INFINITY;
      for (uint32_t v = c[k]; v != UINT32_MAX; v = p->next[v]) {
        const float *q = pos(p->verts, v) + 3;
        double d = (q[0] * n[0] + q[1] * n[1] + q[2] * n[2]) / len;
        if (d > best_dot + 1e-12) {
          best_dot = d;
          best = v;
        }
      }
      c[k] = best;
    }
  }
}

/* A source level as meshoptimizer sees it: representatives, compacted. */
typedef struct {
  float *pos;          /* nc × 3 */
  uint32_t *idx;       /* 3 × ntris, compact ids */
  uint32_t *orig;      /* nc: the representative each compact vertex is */
  size_t nc, ntris;
  double scale;        /* meshopt_simplifyScale of pos */
} compact_src;

/* The vertices that idx (ni indices into nverts vertices whose positions
 * are `positions`, stride floats apart) uses, gathered in first-use order
 * (meshopt_optimizeVertexFetchRemap): *pos (× 3 floats) and *orig (the
 * original vertex of each), idx rewritten to the compact ids; *nc of them. */
static jnd_status compact_vertices(uint32_t *idx, size_t ni, size_t nverts, const float *positions, size_t stride,
                                   float **pos_out, uint32_t **orig_out, size_t *nc_out) {
  *pos_out = NULL;
  *orig_out = NULL;
  *nc_out = 0;
  uint32_t *remap = jnd_alloc(nverts ? nverts : 1, sizeof *remap);
  if (!remap) return JND_ERR_NOMEM;
  size_t nc = meshopt_optimizeVertexFetchRemap(remap, idx, ni, nverts);
  float *cp = jnd_alloc(nc ? nc : 1, 3 * sizeof(float));
  uint32_t *orig = jnd_alloc(nc ? nc : 1, sizeof *orig);
  if (!cp || !orig) {
    free(remap), free(cp), free(orig);
    return JND_ERR_NOMEM;
  }
  for (size_t v = 0; v < nverts; v++) {
    if (remap[v] == UINT32_MAX) continue;
    memcpy(cp + 3 * (size_t)remap[v], positions + v * stride, 3 * sizeof(float));
    orig[remap[v]] = (uint32_t)v;
  }
  for (size_t i = 0; i < ni; i++) idx[i] = remap[idx[i]];
  free(remap);
  *pos_out = cp;
  *orig_out = orig;
  *nc_out = nc;
  return JND_OK;
}

static jnd_status make_compact(const mesh_prep *p, const jnd_lod_mesh *src, compact_src *c) {
  memset(c, 0, sizeof *c);
  size_t ni = 3 * src->ntris;
  c->ntris = src->ntris;
  if (!(c->idx = jnd_alloc(ni ? ni : 1, sizeof *c->idx))) return JND_ERR_NOMEM;
  for (size_t i = 0; i < ni; i++) c->idx[i] = p->rep[src->indices[i]];
  jnd_status st = compact_vertices(c->idx, ni, p->nverts, p->verts, JND_VTX_FLOATS, &c->pos, &c->orig, &c->nc);
  if (st) return st;
  c->scale = c->nc ? meshopt_simplifyScale(c->pos, c->nc, 3 * sizeof(float)) : 0;
  return JND_OK;
}

static void compact_free(compact_src *c) {
  free(c->pos);
  free(c->idx);
  free(c->orig);
}

typedef struct {
  int source;             /* the level it is made from */
  double budget_abs;      /* error budget, object units (errors); INFINITY (ratios) */
  double ratio;           /* triangle ratio (ratios), else NaN */
  double target;          /* the level's error target relative to the extent (errors), else NaN */
} level_plan;

/* Step 5: a large source in slabs. meshopt_simplify runs on one thread, and
 * one pass over a 1 M-triangle source takes about 1.6 s of the 2 s a whole
 * chain may take. A source of more than slab_triangles (2^18) triangles is cut into
 * slabs of about equal triangle counts across the longest side of its
 * bounding box (by triangle centroid, binned: the cut depends on the
 * geometry alone, never on the thread count); each slab is simplified on
 * its own, in parallel, with its cut locked (a cut is an open border to
 * the slab: meshopt_SimplifyLockBorder) and the level's whole budget; the
 * slabs are joined, and the level is made from the joined mesh with what is
 * left of the budget, the cuts free again. The joined mesh's error (the
 * largest slab's) adds to the level's bound. */
enum { SLAB_TRIS = 1 << 18, SLAB_BINS = 4096, MAX_SLABS = 255 };

static int slab_count(const compact_src *c, double budget_abs, size_t slab_tris) {
  if (c->ntris <= slab_tris || !(budget_abs > 0)) return 0;
  size_t n = (c->ntris + slab_tris - 1) / slab_tris;
  return n > MAX_SLABS ? MAX_SLABS : (int)n;
}

/* slab[t]: the slab (0..nslabs − 1) triangle t of c falls in */
static jnd_status slab_of_triangles(const compact_src *c, int nslabs, unsigned char *slab) {
  float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
  for (size_t v = 0; v < c->nc; v++)
    for (int k = 0; k < 3; k++) {
      if (c->pos[3 * v + k] < lo[k]) lo[k] = c->pos[3 * v + k];
      if (c->pos[3 * v + k] > hi[k]) hi[k] = c->pos[3 * v + k];
    }
  int a = 0;
  for (int k = 1; k < 3; k++)
    if (hi[k] - lo[k] > hi[a] - lo[a]) a = k;
  double span = 3.0 * ((double)hi[a] - lo[a]), per = span > 0 ? SLAB_BINS / span : 0;
  uint16_t *bin = jnd_alloc(c->ntris, sizeof *bin);
  size_t *count = jnd_calloc(SLAB_BINS, sizeof *count);
  if (!bin || !count) {
    free(bin);
    free(count);
    return JND_ERR_NOMEM;
  }
  for (size_t t = 0; t < c->ntris; t++) {
    const uint32_t *q = c->idx + 3 * t;
    double x = (double)c->pos[3 * q[0] + a] + c->pos[3 * q[1] + a] + c->pos[3 * q[2] + a] - 3.0 * lo[a];
    int b = (int)(x * per);
    bin[t] = (uint16_t)(b < 0 ? 0 : b >= SLAB_BINS ? SLAB_BINS - 1 : b);
    count[bin[t]]++;
  }
  /* a bin goes to the slab its middle triangle falls in, counted along the axis */
  unsigned char of_bin[SLAB_BINS];
  size_t before = 0;
  for (int b = 0; b < SLAB_BINS; b++) {
    size_t s = (before + count[b] / 2) * (size_t)nslabs / c->ntris;
    of_bin[b] = (unsigned char)(s < (size_t)nslabs ? s : (size_t)nslabs - 1);
    before += count[b];
  }
  for (size_t t = 0; t < c->ntris; t++) slab[t] = of_bin[bin[t]];
  free(bin);
  free(count);
  return JND_OK;
}

typedef struct {
  uint32_t *idx;          /* the slab simplified: c's compact ids */
  size_t n;               /* indices */
  double error_abs;       /* meshoptimizer's result error, object units */
} slab_result;

/* Simplifies slab s of c with its open borders locked: within the budget
 * (errors) or to its share of target_count (ratios). */
static jnd_status simplify_slab(const compact_src *c, const unsigned char *slab, int s, double budget_abs,
                                size_t target_count, unsigned options, slab_result *out) {
  memset(out, 0, sizeof *out);
  size_t ni = 0;
  for (size_t t = 0; t < c->ntris; t++) ni += slab[t] == s ? 3 : 0;
  if (ni == 0) return JND_OK;
  uint32_t *idx = jnd_alloc(ni, sizeof *idx), *dst = jnd_alloc(ni, sizeof *dst), *back = NULL;
  float *pos = NULL;
  size_t nv = 0;
  if (!idx || !dst) {
    free(idx), free(dst);
    return JND_ERR_NOMEM;
  }
  for (size_t t = 0, i = 0; t < c->ntris; t++)
    if (slab[t] == s) memcpy(idx + 3 * i++, c->idx + 3 * t, 3 * sizeof *idx);
  jnd_status st = compact_vertices(idx, ni, c->nc, c->pos, 3, &pos, &back, &nv);
  if (st) {
    free(idx), free(dst);
    return st;
  }
  double scale = meshopt_simplifyScale(pos, nv, 3 * sizeof(float));
  float target = 10.0f;   /* no error bound: 10 × the extent */
  size_t count = 0;
  if (isfinite(budget_abs)) {
    double rel = scale > 0 ? budget_abs / scale : 0;
    target = (float)(rel > 10 ? 10 : rel);
  } else {
    count = 3 * (size_t)((double)(target_count / 3) * (double)(ni / 3) / (double)c->ntris);
  }
  float err = 0;
  size_t n = meshopt_simplify(dst, idx, ni, pos, nv, 3 * sizeof(float), count, target,
                              options | meshopt_SimplifyLockBorder, &err);
  for (size_t i = 0; i < n; i++) dst[i] = back[dst[i]];
  free(idx), free(back), free(pos);
  out->idx = dst;
  out->n = n;
  out->error_abs = (double)err * scale;
  return JND_OK;
}

/* The slabs of one mesh joined again, as a level over the input's vertices
 * (representatives): what the level is then made from. */
static jnd_status join_slabs(const compact_src *c, const slab_result *r, int nslabs, const jnd_lod_mesh *src,
                             jnd_lod_mesh *out) {
  memset(out, 0, sizeof *out);
  size_t n = 0;
  for (int s = 0; s < nslabs; s++) n += r[s].n;
  if (!(out->indices = jnd_alloc(n ? n : 1, sizeof *out->indices))) return JND_ERR_NOMEM;
  out->error_abs = 0;
  for (int s = 0; s < nslabs; s++) {
    for (size_t i = 0; i < r[s].n; i++) out->indices[out->ntris * 3 + i] = c->orig[r[s].idx[i]];
    out->ntris += r[s].n / 3;
    if (r[s].error_abs > out->error_abs) out->error_abs = r[s].error_abs;
  }
  out->error_abs += src->error_abs;
  out->sloppy = src->sloppy;
  return JND_OK;
}

/* Makes one mesh's level: out gets indices (input vertex ids), ntris, the
 * error bound (source's + step's) and whether sloppy made it. */
static jnd_status simplify_one(const mesh_prep *p, const jnd_lod_mesh *src, const compact_src *cs,
                               const level_plan *plan, size_t tris0, unsigned options, int allow_sloppy,
                               jnd_lod_mesh *out) {
  memset(out, 0, sizeof *out);
  if (src->ntris == 0) {
    out->indices = jnd_alloc(1, sizeof *out->indices);
    out->error_abs = src->error_abs;
    return out->indices ? JND_OK : JND_ERR_NOMEM;
  }
  const compact_src c = *cs;
  size_t ni = 3 * c.ntris, target_count = 0;
  float target = 10.0f;   /* no error bound: 10 × the extent */
  if (isfinite(plan->budget_abs)) {
    double rel = c.scale > 0 ? plan->budget_abs / c.scale : 0;
    target = (float)(rel > 10 ? 10 : rel < 0 ? 0 : rel);
  } else {
    target_count = 3 * (size_t)floor(plan->ratio * (double)tris0);
  }
  uint32_t *dst = jnd_alloc(ni, sizeof *dst), *probe = jnd_alloc(ni, sizeof *probe);
  if (!dst || !probe) {
    free(dst);
    free(probe);
    return JND_ERR_NOMEM;
  }
  float err = 0;
  size_t n = target > 0 || target_count > 0
                 ? meshopt_simplify(dst, c.idx, ni, c.pos, c.nc, 3 * sizeof(float), target_count, target, options, &err)
                 : 0;
  if (n == 0 && !(target > 0 || target_count > 0)) {   /* no budget: the source as it is */
    memcpy(dst, c.idx, ni * sizeof *dst);
    n = ni;
  }
  int sloppy = 0;
  /* Step 6: stuck short of the target? */
  if (allow_sloppy && n > target_count && err < target && n >= 3) {
    float perr = 0;
    size_t pn = meshopt_simplify(probe, dst, n, c.pos, c.nc, 3 * sizeof(float), n - 3, 10.0f, options, &perr);
    if (pn >= n) {
      float serr = 0;
      size_t sn = meshopt_simplifySloppy(probe, c.idx, ni, c.pos, c.nc, 3 * sizeof(float), target_count, target, &serr);
      if (sn > 0 && sn < n && serr <= target) {
        memcpy(dst, probe, sn * sizeof *dst);
        n = sn;
        err = serr;
        sloppy = 1;
      }
    }
  }
  free(probe);
  for (size_t i = 0; i < n; i++) dst[i] = c.orig[dst[i]];
  take_normals(p, dst, n / 3);
  out->indices = dst;
  out->ntris = n / 3;
  out->error_abs = src->error_abs + (double)err * c.scale;
  out->sloppy = sloppy || src->sloppy;
  return JND_OK;
}

/* ---- the chain ---- */

/* Makes level k of every mesh from its source (step 4): each source is
 * compacted, large ones are simplified in slabs first (step 5), then the
 * level is made. Every job writes its own slot, so the level does not
 * depend on the thread count. */
static jnd_status make_level(const mesh_prep *prep, jnd_lod_level *lv, int k, const level_plan *plan, int nmeshes,
                             size_t slab_tris, unsigned options, int allow_sloppy, int nthreads) {
  size_t n = (size_t)nmeshes;
  compact_src *cs = jnd_calloc(2 * n, sizeof *cs);     /* sources, then joined slabs */
  jnd_lod_mesh *joined = jnd_calloc(n, sizeof *joined);
  unsigned char **slab = jnd_calloc(n, sizeof *slab);
  int *first = jnd_calloc(n + 1, sizeof *first);       /* mesh i's slab jobs: first[i] .. first[i + 1] − 1 */
  jnd_status *res = jnd_calloc(n, sizeof *res);
  double *left = jnd_calloc(n, sizeof *left);          /* the budget left after the source's own error */
  slab_result *sr = NULL;
  jnd_status st = cs && joined && slab && first && res && left ? JND_OK : JND_ERR_NOMEM;
  const jnd_lod_mesh *src = lv[plan->source].mesh;
  if (!st) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
    for (int i = 0; i < nmeshes; i++) res[i] = make_compact(&prep[i], &src[i], &cs[i]);
    for (int i = 0; i < nmeshes && !st; i++) st = res[i];
  }
  for (int i = 0; i < nmeshes && !st; i++) {
    left[i] = isfinite(plan->budget_abs) ? fmax(0, plan->budget_abs - src[i].error_abs) : INFINITY;
    int ns = slab_count(&cs[i], left[i], slab_tris);
    first[i + 1] = first[i] + ns;
    if (ns && !(slab[i] = jnd_alloc(cs[i].ntris, 1))) st = JND_ERR_NOMEM;
    if (ns && !st) st = slab_of_triangles(&cs[i], ns, slab[i]);
  }
  int jobs = first[n];
  if (!st && jobs) {
    jnd_status *sres = jnd_calloc((size_t)jobs, sizeof *sres);
    sr = jnd_calloc((size_t)jobs, sizeof *sr);
    st = sres && sr ? JND_OK : JND_ERR_NOMEM;
    if (!st) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
      for (int j = 0; j < jobs; j++) {
        int i = 0;
        while (first[i + 1] <= j) i++;
        size_t count = isfinite(plan->ratio) ? 3 * (size_t)floor(plan->ratio * (double)lv[0].mesh[i].ntris) : 0;
        sres[j] = simplify_slab(&cs[i], slab[i], j - first[i], left[i], count, options, &sr[j]);
      }
      for (int j = 0; j < jobs && !st; j++) st = sres[j];
    }
    free(sres);
    for (int i = 0; i < nmeshes && !st; i++)
      if (first[i + 1] > first[i]) {
        st = join_slabs(&cs[i], sr + first[i], first[i + 1] - first[i], &src[i], &joined[i]);
        if (!st) st = make_compact(&prep[i], &joined[i], &cs[n + i]);
        if (!st && isfinite(left[i])) left[i] = fmax(0, plan->budget_abs - joined[i].error_abs);
      }
  }
  if (!st) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
    for (int i = 0; i < nmeshes; i++) {
      int slabs = first[i + 1] > first[i];
      level_plan pl = *plan;
      pl.budget_abs = left[i];
      res[i] = simplify_one(&prep[i], slabs ? &joined[i] : &src[i], &cs[slabs ? n + (size_t)i : (size_t)i], &pl,
                            lv[0].mesh[i].ntris, options, allow_sloppy, &lv[k].mesh[i]);
    }
    for (int i = 0; i < nmeshes && !st; i++) st = res[i];
  }
  for (int j = 0; sr && j < jobs; j++) free(sr[j].idx);
  for (size_t i = 0; cs && i < 2 * n; i++) compact_free(&cs[i]);
  for (size_t i = 0; i < n; i++) {
    if (joined) free(joined[i].indices);
    if (slab) free(slab[i]);
  }
  free(sr), free(left), free(cs), free(joined), free(slab), free(first), free(res);
  return st;
}

jnd_status jnd_scene_lod_build(jnd_scene *s, const jnd_lod_params *p) {
  jnd_lod_params d;
  if (!p) {
    jnd_lod_defaults(&d);
    p = &d;
  }
  const double *targets = p->errors;
  int nt = p->nerrors, by_ratio = 0;
  if (!targets && p->ratios) {
    targets = p->ratios;
    nt = p->nratios;
    by_ratio = 1;
  } else if (!targets) {
    targets = default_errors;
    nt = (int)(sizeof default_errors / sizeof *default_errors);
  }
  if (nt < 1 || nt > MAX_LEVELS - 1)
    return jnd_fail(JND_ERR_ARG, "lod: %d targets (1..%d)", nt, MAX_LEVELS - 1);
  for (int k = 0; k < nt; k++) {
    double t = targets[k], prev = k ? targets[k - 1] : (by_ratio ? 1 : 0);
    if (!isfinite(t) || (by_ratio ? !(t >= 0 && t < prev) : !(t > prev && t <= 1)))
      return jnd_fail(JND_ERR_ARG, "lod: %s targets must %s (target %d is %g)",
                      by_ratio ? "triangle-ratio" : "error", by_ratio ? "fall from below 1 to 0" : "rise within (0, 1]",
                      k + 1, t);
  }
  /* meshoptimizer, opened on first use (meshopt_lazy.c) */
  if (!jnd_meshopt_ready()) return jnd_fail(JND_ERR_IO, "lod: %s", jnd_last_error());
  jnd_status st = ensure_levels(s);
  if (st) return st;
  /* drop an earlier chain, keep level 0 */
  for (int k = 1; k < s->nlod; k++) free_level(&s->lod[k], s->nmeshes);
  s->nlod = 1;
  jnd_scene_lod_select(s, 0);
  if (!(scene_area(s) > 0)) return jnd_fail(JND_ERR_FORMAT, "%s: every triangle has zero area", s->path);
  double extent = scene_extent(s);
  if (!(extent > 0) || !isfinite(extent)) return jnd_fail(JND_ERR_FORMAT, "%s: the meshes have no extent", s->path);

  /* step 4: each level's source, fixed by the targets and level 0's size */
  size_t slab_tris = p->slab_triangles > 0 ? (size_t)p->slab_triangles : SLAB_TRIS;
  int big = 0;
  for (int i = 0; i < s->nmeshes; i++) big |= s->lod[0].mesh[i].ntris > slab_tris;
  level_plan plan[MAX_LEVELS];
  for (int k = 1; k <= nt; k++) {
    level_plan *L = &plan[k];
    L->source = by_ratio || (k > 1 && big) ? k - 1 : 0;
    for (int j = 1; j < k && !by_ratio; j++)
      if (targets[j - 1] <= targets[k - 1] / 4) L->source = j;
    L->ratio = by_ratio ? targets[k - 1] : NAN;
    L->target = by_ratio ? NAN : targets[k - 1];
    L->budget_abs = by_ratio ? INFINITY : targets[k - 1] * extent;
  }
  int lock = p->lock_border < 0 ? s->nmeshes > 1 : p->lock_border != 0;
  unsigned options = lock ? meshopt_SimplifyLockBorder : 0;

  jnd_lod_level *lv = jnd_calloc((size_t)nt + 1, sizeof *lv);
  mesh_prep *prep = jnd_calloc((size_t)s->nmeshes, sizeof *prep);
  if (!lv || !prep) {
    free(lv);
    free(prep);
    return JND_ERR_NOMEM;
  }
  lv[0] = s->lod[0];
  for (int k = 1; k <= nt && !st; k++)
    if (!(lv[k].mesh = jnd_calloc((size_t)s->nmeshes, sizeof *lv[k].mesh))) st = JND_ERR_NOMEM;
  for (int i = 0; i < s->nmeshes && !st; i++) st = prep_mesh(&lv[0].mesh[i], &prep[i]);
  int nthreads = jnd_threads(p->threads);
  for (int k = 1; k <= nt && !st; k++)
    st = make_level(prep, lv, k, &plan[k], s->nmeshes, slab_tris, options, p->allow_sloppy, nthreads);
  if (st == JND_ERR_NOMEM) st = jnd_fail(JND_ERR_NOMEM, "%s: out of memory", s->path);
  for (int i = 0; i < s->nmeshes; i++) prep_free(&prep[i]);
  free(prep);

  /* step 7: monotone per mesh; levels that add nothing are dropped */
  int kept = 1;
  for (int k = 1; k <= nt && !st; k++) {
    jnd_lod_level *prev = &lv[kept - 1], *L = &lv[k];
    size_t total = 0, before = 0;
    for (int i = 0; i < s->nmeshes && !st; i++) {
      jnd_lod_mesh *m = &L->mesh[i];
      const jnd_lod_mesh *q = &prev->mesh[i];
      before += q->ntris;
      if (m->ntris > q->ntris || (m->ntris == q->ntris && m->error_abs > q->error_abs)) {
        free(m->indices);
        m->indices = jnd_alloc(3 * q->ntris + 1, sizeof *m->indices);
        if (!m->indices) {
          st = JND_ERR_NOMEM;
          break;
        }
        memcpy(m->indices, q->indices, 3 * q->ntris * sizeof *m->indices);
        m->ntris = q->ntris;
        m->error_abs = q->error_abs;
        m->sloppy = q->sloppy;
      }
      total += m->ntris;
    }
    if (st) break;
    if (total >= before) {
      free_level(L, s->nmeshes);
      continue;
    }
    jnd_lod_level_info *in = &L->info;
    memset(in, 0, sizeof *in);
    in->method = JND_LOD_SIMPLIFIED;
    in->target_error = plan[k].target;
    in->target_ratio = plan[k].ratio;
    for (int i = 0; i < s->nmeshes; i++) {
      L->mesh[i].version = jnd_scene_next_version();
      if (L->mesh[i].error_abs > in->error_abs) in->error_abs = L->mesh[i].error_abs;
      if (L->mesh[i].sloppy) in->sloppy_meshes++;
    }
    if (in->sloppy_meshes) in->method = JND_LOD_SLOPPY;
    in->error = in->error_abs / extent;
    if (k != kept) {
      lv[kept] = *L;
      memset(L, 0, sizeof *L);
    }
    kept++;
  }
  if (st) {
    for (int k = 1; k <= nt; k++) free_level(&lv[k], s->nmeshes);
    free(lv);
    return st;
  }
  free(s->lod);
  s->lod = lv;
  s->nlod = kept;
  for (int k = 1; k < kept && !st; k++) st = level_counts(s, &s->lod[k]);
  jnd_scene_lod_select(s, 0);
  return st;
}

/* ---- levels from other files ---- */

jnd_status jnd_scene_lod_add(jnd_scene *s, jnd_scene *level, const char *source) {
  jnd_status st = ensure_levels(s);
  if (!st && s->nlod >= MAX_LEVELS) st = jnd_fail(JND_ERR_LIMIT, "%s: more than %d levels", source, MAX_LEVELS);
  /* every material of the level must be one of ours (by name) */
  int *to = NULL;
  if (!st && !(to = jnd_calloc((size_t)level->nmaterials + 1, sizeof *to))) st = JND_ERR_NOMEM;
  for (int m = 0; m < level->nmaterials && !st; m++) {
    to[m] = -1;
    for (int i = 0; i < s->nmeshes && to[m] < 0; i++)
      if (strcmp(s->materials[s->meshes[i].material].name, level->materials[m].name) == 0) to[m] = i;
  }
  for (int j = 0; j < level->nmeshes && !st; j++)
    if (level->meshes[j].ntris && to[level->meshes[j].material] < 0)
      st = jnd_fail(JND_ERR_ARG, "%s: material '%s' is not a material of %s", source,
                    level->materials[level->meshes[j].material].name, s->path);
  jnd_lod_level L = {0};
  if (!st && !(L.mesh = jnd_calloc((size_t)s->nmeshes, sizeof *L.mesh))) st = JND_ERR_NOMEM;
  for (int i = 0; i < s->nmeshes && !st; i++) {
    size_t nv = 0, nt = 0;
    for (int j = 0; j < level->nmeshes; j++)
      if (level->meshes[j].ntris && to[level->meshes[j].material] == i) {
        nv += level->meshes[j].nverts;
        nt += level->meshes[j].ntris;
      }
    if (nv > UINT32_MAX) {
      st = jnd_fail(JND_ERR_LIMIT, "%s: too many vertices", source);
      break;
    }
    jnd_lod_mesh *m = &L.mesh[i];
    m->vertices = jnd_alloc(nv ? nv : 1, JND_VTX_FLOATS * sizeof(float));
    m->indices = jnd_alloc(nt ? 3 * nt : 1, sizeof *m->indices);
    if (!m->vertices || !m->indices) {
      st = JND_ERR_NOMEM;
      break;
    }
    for (int j = 0; j < level->nmeshes; j++) {
      const jnd_mesh *q = &level->meshes[j];
      if (!q->ntris || to[q->material] != i) continue;
      memcpy(m->vertices + m->nverts * JND_VTX_FLOATS, q->vertices, q->nverts * JND_VTX_FLOATS * sizeof(float));
      for (size_t t = 0; t < 3 * q->ntris; t++) m->indices[3 * m->ntris + t] = (uint32_t)(m->nverts + q->indices[t]);
      m->nverts += q->nverts;
      m->ntris += q->ntris;
    }
    m->error_abs = NAN;
    m->version = jnd_scene_next_version();
  }
  free(to);
  jnd_scene_free(level);
  if (!st) {
    jnd_lod_level *grown = realloc(s->lod, (size_t)(s->nlod + 1) * sizeof *grown);
    if (!grown) st = JND_ERR_NOMEM;
    else s->lod = grown;
  }
  if (st) {
    free_level(&L, s->nmeshes);
    return st == JND_ERR_NOMEM ? jnd_fail(st, "%s: out of memory", source) : st;
  }
  L.info.method = JND_LOD_IMPORTED;
  L.info.target_error = L.info.target_ratio = L.info.error = L.info.error_abs = NAN;
  snprintf(L.info.source, sizeof L.info.source, "%s", source);
  s->lod[s->nlod] = L;
  s->nlod++;
  return level_counts(s, &s->lod[s->nlod - 1]);
}

/* ---- the chain a task measures ---- */

jnd_status jnd_scene_lod_chain(jnd_scene *s, const char *name, const jnd_lod_chain_params *p, const char **source) {
  jnd_lod_chain_params d = {0};
  if (!p) p = &d;
  jnd_status st = JND_OK;
  if (p->nlevel_paths > 0) {
    *source = "levels";
    if (jnd_scene_lod_count(s) > 1)
      return jnd_fail(JND_ERR_ARG, "%s: has MSFT_lod levels already; give level files only for a file without", name);
    for (int i = 0; i < p->nlevel_paths && !st; i++) {
      jnd_scene *lv = NULL;
      if (!(st = jnd_scene_load(p->level_paths[i], &lv))) st = jnd_scene_lod_add(s, lv, p->level_paths[i]);
    }
  } else if (jnd_scene_lod_count(s) > 1 && !p->rebuild) {
    *source = "file";
  } else {
    *source = "made";
    jnd_lod_params lp;
    jnd_lod_defaults(&lp);
    st = jnd_scene_lod_build(s, p->chain ? p->chain : &lp);
  }
  if (!st && jnd_scene_lod_count(s) < 2)
    st = jnd_fail(JND_ERR_FORMAT, "%s: meshoptimizer made no level with fewer triangles (%zu triangles; try larger "
                  "error targets)", name, jnd_scene_triangle_count(s));
  return st;
}
