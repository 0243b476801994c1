/* Connected regions of a difference map (004 §3.2, "popping regions"): seeds
 * are pixels flagged by the caller whose value is at least the threshold;
 * regions grow from them over the eight neighbours while the value stays at
 * or above the threshold. Growing from a seed over that condition reaches
 * exactly the seed's 8-connected component of {value >= threshold}, so the
 * regions are those components that hold at least one seed; this file
 * labels the components and keeps the seeded ones.
 *
 * Deterministic and parallel-safe, whatever the thread count:
 *   1. the image is cut into strips of STRIP rows — a fixed height, not one
 *      strip per thread — and each strip is labelled on its own (union–find
 *      over the W, NW, N, NE neighbours inside the strip; a thread writes
 *      only its strip's entries of the parent array);
 *   2. the seams between strips are joined on one thread, in order;
 *   3. one pass in raster order gives every component its number (the order
 *      of its first pixel) and accumulates its statistics in double, in
 *      raster order.
 * Union always hangs the larger root under the smaller, so a root is its
 * component's first pixel and the partition, the numbering and every sum
 * are the same bits for 1 or N threads. No global state: all memory is the
 * caller's or allocated here. */
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "pool/pool.h"

enum { STRIP = 64 };

static uint32_t find(uint32_t *parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]]; /* path halving */
    i = parent[i];
  }
  return i;
}

static void unite(uint32_t *parent, uint32_t a, uint32_t b) {
  a = find(parent, a);
  b = find(parent, b);
  if (a < b)
    parent[b] = a;
  else if (b < a)
    parent[a] = b;
}

/* union–find over rows [y0, y1) with neighbours inside those rows only */
static void label_strip(const float *map, float t, int w, int y0, int y1, uint32_t *parent) {
  for (int y = y0; y < y1; y++) {
    const float *row = map + (size_t)y * w, *up = row - w;
    for (int x = 0; x < w; x++) {
      uint32_t i = (uint32_t)((size_t)y * w + x);
      if (!(row[x] >= t)) continue;
      parent[i] = i;
      if (x > 0 && row[x - 1] >= t) unite(parent, i, i - 1);
      if (y > y0) {
        for (int dx = -1; dx <= 1; dx++) {
          int xx = x + dx;
          if (xx >= 0 && xx < w && up[xx] >= t) unite(parent, i, (uint32_t)(i - w + dx));
        }
      }
    }
  }
}

jnd_status jnd_regions_find(const float *map, const uint8_t *seed, int w, int h, float threshold, double exponent,
                            int threads, int32_t *labels, jnd_region **out, int *nout) {
  *out = NULL;
  *nout = 0;
  size_t n = (size_t)w * h;
  if (w < 1 || h < 1) return jnd_fail(JND_ERR_ARG, "regions: empty map");
  if (n >= (size_t)UINT32_MAX) return jnd_fail(JND_ERR_LIMIT, "regions: %d × %d pixels is too many", w, h);
  if (!(threshold > 0)) return jnd_fail(JND_ERR_ARG, "regions: the threshold must be positive");
  uint32_t *parent = jnd_alloc(n, sizeof *parent);
  if (!parent) return JND_ERR_NOMEM;
  const int nstrips = (h + STRIP - 1) / STRIP;
#pragma omp parallel for num_threads(jnd_threads(threads)) schedule(static)
  for (int s = 0; s < nstrips; s++) {
    int y0 = s * STRIP, y1 = y0 + STRIP < h ? y0 + STRIP : h;
    label_strip(map, threshold, w, y0, y1, parent);
  }
  /* the seams: the first row of each strip against the last row of the one above */
  for (int s = 1; s < nstrips; s++) {
    int y = s * STRIP;
    const float *row = map + (size_t)y * w, *up = row - w;
    for (int x = 0; x < w; x++) {
      if (!(row[x] >= threshold)) continue;
      uint32_t i = (uint32_t)((size_t)y * w + x);
      for (int dx = -1; dx <= 1; dx++) {
        int xx = x + dx;
        if (xx >= 0 && xx < w && up[xx] >= threshold) unite(parent, i, (uint32_t)(i - w + dx));
      }
    }
  }
  /* numbering in raster order: a root is its component's first pixel */
  const float e = (float)exponent;
  size_t cap = 64;
  int ncomp = 0;
  jnd_region *comp = jnd_alloc(cap, sizeof *comp);
  uint8_t *seeded = jnd_alloc(cap, 1);
  jnd_status st = comp && seeded ? JND_OK : JND_ERR_NOMEM;
  for (size_t i = 0; i < n && st == JND_OK; i++) {
    const float v = map[i];
    if (!(v >= threshold)) {
      labels[i] = -1;
      continue;
    }
    uint32_t r = find(parent, (uint32_t)i);
    int id;
    if (r == i) {
      if ((size_t)ncomp == cap) {
        cap *= 2;
        jnd_region *c2 = realloc(comp, cap * sizeof *comp);
        if (c2) comp = c2;
        uint8_t *s2 = c2 ? realloc(seeded, cap) : NULL;
        if (s2) seeded = s2;
        if (!c2 || !s2) {
          st = jnd_fail(JND_ERR_NOMEM, "regions: out of memory");
          break;
        }
      }
      id = ncomp++;
      jnd_region *c = &comp[id];
      memset(c, 0, sizeof *c);
      c->first = i;
      c->x0 = c->x1 = (int)(i % (size_t)w);
      c->y0 = c->y1 = (int)(i / (size_t)w);
      seeded[id] = 0;
    } else {
      id = labels[r];
    }
    labels[i] = id;
    jnd_region *c = &comp[id];
    int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
    c->pixels++;
    c->sum_pow += (double)jnd_fast_pow(v, e);
    if (v > c->max) c->max = v;
    if (x < c->x0) c->x0 = x;
    if (x > c->x1) c->x1 = x;
    c->y1 = y; /* rows come in order */
    if (!seed || seed[i]) seeded[id] = 1;
  }
  free(parent);
  if (st != JND_OK) {
    free(comp);
    free(seeded);
    return st;
  }
  /* keep the seeded components, renumbered in the same order */
  int *remap = jnd_alloc((size_t)ncomp + 1, sizeof *remap);
  if (!remap) {
    free(comp);
    free(seeded);
    return JND_ERR_NOMEM;
  }
  int nkeep = 0;
  for (int k = 0; k < ncomp; k++) {
    remap[k] = seeded[k] ? nkeep : -1;
    if (seeded[k]) comp[nkeep++] = comp[k];
  }
  free(seeded);
  const ptrdiff_t nn = (ptrdiff_t)n;
#pragma omp parallel for num_threads(jnd_threads(threads)) schedule(static)
  for (ptrdiff_t i = 0; i < nn; i++)
    if (labels[i] >= 0) labels[i] = remap[labels[i]];
  free(remap);
  if (nkeep == 0) {
    free(comp);
    comp = NULL;
  }
  *out = comp;
  *nout = nkeep;
  return JND_OK;
}
