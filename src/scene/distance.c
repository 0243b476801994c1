/* Distances between two levels of a scene: points sampled on level 0's
 * surface (uniformly by area), each taken to the nearest point of another
 * level's surface through a bounding-volume hierarchy. This is the
 * surface-to-surface part of 003 eq. 1: the area-weighted mean over the
 * triangles T_i of S1 of l^p(T_i, S2), where the mean over a triangle of
 * d(x, S2)^p is estimated by the samples that fall in it; with samples
 * spread by area, the area-weighted sum is their plain mean. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"

/* ---- closest point on a triangle (Ericson, Real-Time Collision Detection, §5.1.5) ---- */

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* squared distance from p to triangle abc */
static double point_triangle_d2(const double p[3], const double a[3], const double b[3], const double c[3]) {
  double ab[3], ac[3], ap[3], q[3];
  for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
  double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) {
    memcpy(q, a, sizeof q);
  } else {
    double bp[3];
    for (int k = 0; k < 3; k++) bp[k] = p[k] - b[k];
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
      memcpy(q, b, sizeof q);
    } else {
      double vc = d1 * d4 - d3 * d2;
      if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
      } else {
        double cp[3];
        for (int k = 0; k < 3; k++) cp[k] = p[k] - c[k];
        double d5 = dot(ab, cp), d6 = dot(ac, cp);
        if (d6 >= 0 && d5 <= d6) {
          memcpy(q, c, sizeof q);
        } else {
          double vb = d5 * d2 - d1 * d6;
          if (vb <= 0 && d2 >= 0 && d6 <= 0) {
            double w = d2 / (d2 - d6);
            for (int k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
          } else {
            double va = d3 * d6 - d5 * d4;
            if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
              double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
              for (int k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
            } else {
              double den = va + vb + vc;
              if (!(fabs(den) > 0)) { /* degenerate: the nearest vertex */
                double da = dot(ap, ap), db = dot(bp, bp), dc = dot(cp, cp);
                return fmin(da, fmin(db, dc));
              }
              double v = vb / den, w = vc / den;
              for (int k = 0; k < 3; k++) q[k] = a[k] + ab[k] * v + ac[k] * w;
            }
          }
        }
      }
    }
  }
  double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
  return dot(d, d);
}

/* ---- a bounding-volume hierarchy over the triangles of one level ---- */

typedef struct {
  float lo[3], hi[3];
  uint32_t first, count;   /* leaf: triangles [first, first + count); inner: count 0, children first, first + 1 */
} bvh_node;

typedef struct {
  double (*tri)[9];        /* triangle corners, in leaf order */
  size_t ntris;
  bvh_node *node;
  size_t nnodes;
} bvh;

enum { LEAF = 4 };

static void bvh_free(bvh *b) {
  free(b->tri);
  free(b->node);
}

typedef struct {
  double c[3];
  uint32_t t;
} centroid;

static int by_axis(const void *x, const void *y, void *axis) {
  int ax = *(const int *)axis;
  double a = ((const centroid *)x)->c[ax], b = ((const centroid *)y)->c[ax];
  if (a != b) return a < b ? -1 : 1;
  uint32_t i = ((const centroid *)x)->t, j = ((const centroid *)y)->t;
  return (i > j) - (i < j);
}

/* builds the subtree of node n over cen[first, first + count) */
static void build(bvh *b, const double (*src)[9], centroid *cen, size_t n, size_t first, size_t count) {
  bvh_node *nd = &b->node[n];
  for (int k = 0; k < 3; k++) nd->lo[k] = INFINITY, nd->hi[k] = -INFINITY;
  double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = first; i < first + count; i++) {
    const double *t = src[cen[i].t];
    for (int v = 0; v < 3; v++)
      for (int k = 0; k < 3; k++) {
        /* boxes widened outward to the float grid so that they contain the triangle */
        float lo = (float)t[3 * v + k], hi = lo;
        if ((double)lo > t[3 * v + k]) lo = nextafterf(lo, -INFINITY);
        if ((double)hi < t[3 * v + k]) hi = nextafterf(hi, INFINITY);
        if (lo < nd->lo[k]) nd->lo[k] = lo;
        if (hi > nd->hi[k]) nd->hi[k] = hi;
      }
    for (int k = 0; k < 3; k++) {
      clo[k] = fmin(clo[k], cen[i].c[k]);
      chi[k] = fmax(chi[k], cen[i].c[k]);
    }
  }
  if (count <= LEAF) {
    nd->first = (uint32_t)first;
    nd->count = (uint32_t)count;
    for (size_t i = first; i < first + count; i++) memcpy(b->tri[i], src[cen[i].t], sizeof b->tri[i]);
    return;
  }
  int ax = 0;
  for (int k = 1; k < 3; k++)
    if (chi[k] - clo[k] > chi[ax] - clo[ax]) ax = k;
  qsort_r(cen + first, count, sizeof *cen, by_axis, &ax);
  size_t half = count / 2, left = b->nnodes;
  b->nnodes += 2;
  nd->first = (uint32_t)left;
  nd->count = 0;
  build(b, src, cen, left, first, half);
  build(b, src, cen, left + 1, first + half, count - half);
}

static jnd_status bvh_build(const jnd_scene *s, int level, bvh *b) {
  memset(b, 0, sizeof *b);
  const jnd_lod_level *L = s->nlod > 0 ? &s->lod[level] : NULL;
  size_t nt = 0;
  for (int i = 0; i < s->nmeshes; i++) nt += L ? L->mesh[i].ntris : s->meshes[i].ntris;
  if (nt == 0) return JND_OK;
  double (*src)[9] = jnd_alloc(nt, sizeof *src);
  centroid *cen = jnd_alloc(nt, sizeof *cen);
  b->tri = jnd_alloc(nt, sizeof *b->tri);
  b->node = jnd_alloc(2 * nt, sizeof *b->node);
  if (!src || !cen || !b->tri || !b->node) {
    free(src);
    free(cen);
    bvh_free(b);
    return JND_ERR_NOMEM;
  }
  size_t t = 0;
  for (int i = 0; i < s->nmeshes; i++) {
    const float *verts = L ? (L->mesh[i].vertices ? L->mesh[i].vertices : s->lod[0].mesh[i].vertices)
                           : s->meshes[i].vertices;
    const uint32_t *idx = L ? L->mesh[i].indices : s->meshes[i].indices;
    size_t n = L ? L->mesh[i].ntris : s->meshes[i].ntris;
    for (size_t j = 0; j < n; j++, t++) {
      for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) src[t][3 * v + k] = verts[(size_t)idx[3 * j + v] * JND_VTX_FLOATS + k];
      for (int k = 0; k < 3; k++) cen[t].c[k] = (src[t][k] + src[t][3 + k] + src[t][6 + k]) / 3;
      cen[t].t = (uint32_t)t;
    }
  }
  b->ntris = nt;
  b->nnodes = 1;
  build(b, (const double (*)[9])src, cen, 0, 0, nt);
  free(src);
  free(cen);
  return JND_OK;
}

static double box_d2(const bvh_node *n, const double p[3]) {
  double d2 = 0;
  for (int k = 0; k < 3; k++) {
    double d = p[k] < n->lo[k] ? n->lo[k] - p[k] : p[k] > n->hi[k] ? p[k] - n->hi[k] : 0;
    d2 += d * d;
  }
  return d2;
}

/* squared distance from p to the nearest triangle: depth first, nearer child first, pruned by box distance */
static double bvh_nearest_d2(const bvh *b, const double p[3]) {
  if (b->ntris == 0) return INFINITY;
  uint32_t stack[128];
  int sp = 0;
  double best = INFINITY;
  stack[sp++] = 0;
  while (sp > 0) {
    const bvh_node *n = &b->node[stack[--sp]];
    if (box_d2(n, p) >= best) continue;
    if (n->count > 0) {
      for (uint32_t i = n->first; i < n->first + n->count; i++) {
        const double *t = b->tri[i];
        double d2 = point_triangle_d2(p, t, t + 3, t + 6);
        if (d2 < best) best = d2;
      }
      continue;
    }
    uint32_t l = n->first, r = n->first + 1;
    double dl = box_d2(&b->node[l], p), dr = box_d2(&b->node[r], p);
    /* the nearer child is popped first */
    if (dl < dr) {
      if (dr < best) stack[sp++] = r;
      if (dl < best) stack[sp++] = l;
    } else {
      if (dl < best) stack[sp++] = l;
      if (dr < best) stack[sp++] = r;
    }
  }
  return best;
}

/* ---- sampling level 0 ---- */

jnd_status jnd_scene_surface_samples(const jnd_scene *s, int samples, uint64_t seed, double **out) {
  *out = NULL;
  if (samples < 1) return jnd_fail(JND_ERR_ARG, "surface samples: %d (at least 1)", samples);
  const jnd_lod_level *L = s->nlod > 0 ? &s->lod[0] : NULL;
  size_t nt = 0;
  for (int i = 0; i < s->nmeshes; i++) nt += L ? L->mesh[i].ntris : s->meshes[i].ntris;
  double *cum = jnd_alloc(nt + 1, sizeof *cum), (*tri)[9] = jnd_alloc(nt ? nt : 1, sizeof *tri);
  double *pts = jnd_alloc((size_t)samples, 3 * sizeof(double));
  if (!cum || !tri || !pts) {
    free(cum);
    free(tri);
    free(pts);
    return JND_ERR_NOMEM;
  }
  size_t t = 0;
  cum[0] = 0;
  for (int i = 0; i < s->nmeshes; i++) {
    const float *verts = L ? L->mesh[i].vertices : s->meshes[i].vertices;
    const uint32_t *idx = L ? L->mesh[i].indices : s->meshes[i].indices;
    size_t n = L ? L->mesh[i].ntris : s->meshes[i].ntris;
    for (size_t j = 0; j < n; j++, t++) {
      for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) tri[t][3 * v + k] = verts[(size_t)idx[3 * j + v] * JND_VTX_FLOATS + k];
      double e1[3], e2[3];
      for (int k = 0; k < 3; k++) e1[k] = tri[t][3 + k] - tri[t][k], e2[k] = tri[t][6 + k] - tri[t][k];
      double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      cum[t + 1] = cum[t] + 0.5 * sqrt(dot(c, c));
    }
  }
  double area = cum[nt];
  if (!(area > 0)) {
    free(cum);
    free(tri);
    free(pts);
    return jnd_fail(JND_ERR_FORMAT, "%s: every triangle has zero area", s->path);
  }
  /* stratified by area: sample k falls at cumulative area (k + u) / n, so
   * every triangle gets its share of samples within one */
  jnd_rng rng;
  jnd_rng_seed(&rng, seed);
  size_t tri_i = 0;
  for (int k = 0; k < samples; k++) {
    double a = (k + jnd_rng_uniform(&rng)) / samples * area;
    while (tri_i + 1 < nt && cum[tri_i + 1] <= a) tri_i++;
    double r1 = sqrt(jnd_rng_uniform(&rng)), r2 = jnd_rng_uniform(&rng);
    const double *T = tri[tri_i];
    for (int q = 0; q < 3; q++)
      pts[3 * k + q] = (1 - r1) * T[q] + r1 * (1 - r2) * T[3 + q] + r1 * r2 * T[6 + q];
  }
  free(cum);
  free(tri);
  *out = pts;
  return JND_OK;
}

jnd_status jnd_scene_points_distance(const jnd_scene *s, int level, const double *pts, int n,
                                     jnd_surface_distance *out) {
  memset(out, 0, sizeof *out);
  if (level < 0 || level >= jnd_scene_lod_count(s))
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range", s->path, level);
  bvh b;
  jnd_status st = bvh_build(s, level, &b);
  if (st) return st == JND_ERR_NOMEM ? jnd_fail(st, "%s: out of memory", s->path) : st;
  double *d = jnd_alloc((size_t)(n > 0 ? n : 1), sizeof *d);
  if (!d) {
    bvh_free(&b);
    return JND_ERR_NOMEM;
  }
#pragma omp parallel for schedule(dynamic, 256)
  for (int k = 0; k < n; k++) d[k] = sqrt(bvh_nearest_d2(&b, pts + 3 * (size_t)k));
  /* sums in sample order: the same for every thread count */
  double s1 = 0, s2 = 0, mx = 0;
  for (int k = 0; k < n; k++) {
    s1 += d[k];
    s2 += d[k] * d[k];
    if (d[k] > mx) mx = d[k];
  }
  out->samples = n;
  out->mean = n ? s1 / n : 0;
  out->rms = n ? sqrt(s2 / n) : 0;
  out->max = mx;
  free(d);
  bvh_free(&b);
  return JND_OK;
}

jnd_status jnd_scene_lod_distance(const jnd_scene *s, int level, int samples, uint64_t seed,
                                  jnd_surface_distance *out) {
  memset(out, 0, sizeof *out);
  double *pts = NULL;
  jnd_status st = jnd_scene_surface_samples(s, samples, seed, &pts);
  if (!st) st = jnd_scene_points_distance(s, level, pts, samples, out);
  free(pts);
  return st;
}
