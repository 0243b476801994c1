/* Pooling a map into one number (000 §6): percentiles (P93 by default: the
 * value below which 93% of the map lies, which best predicted the measured
 * thresholds in 000 §6), maximum, mean and Minkowski mean. */
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "pool/pool.h"

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

jnd_status jnd_sort_floats(float *v, size_t n) {
  int nonneg = 1;
  for (size_t i = 0; i < n; i++)
    if (!(v[i] >= 0)) { nonneg = 0; break; }
  if (!nonneg || n < 4096) {
    qsort(v, n, sizeof *v, cmp_float);
    return JND_OK;
  }
  /* non-negative IEEE floats order like their bit patterns: LSD radix, 4 × 8 bits */
  uint32_t *a = (uint32_t *)(void *)v;
  uint32_t *b = jnd_alloc(n, sizeof *b);
  if (!b) return JND_ERR_NOMEM;
  for (int pass = 0; pass < 4; pass++) {
    size_t count[257] = {0};
    int sh = pass * 8;
    for (size_t i = 0; i < n; i++) count[((a[i] >> sh) & 0xff) + 1]++;
    for (int k = 0; k < 256; k++) count[k + 1] += count[k];
    for (size_t i = 0; i < n; i++) b[count[(a[i] >> sh) & 0xff]++] = a[i];
    uint32_t *t = a;
    a = b;
    b = t;
  }
  /* after 4 passes the data is back in the caller's buffer */
  free(b);
  return JND_OK;
}

/* ---- order statistics without a full sort (radix select) ---- */

/* a float's bits as an unsigned key that orders like the float (not NaN) */
static uint32_t order_key(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  return (u & 0x80000000u) ? ~u : u | 0x80000000u;
}

enum { NBIN = JND_ORDER_BINS, FINE = 8 };

/* Adds range [i0, i1) of v to h4's four interleaved counts (4 × NBIN bins
 * of key bits [shift, shift + 12)), so that neighbouring values in one bin
 * (most of a smooth map) do not each wait for the previous one's
 * increment; jnd_order_fold sums them */
static void count_range(const float *v, size_t i0, size_t i1, int shift, size_t *h4) {
  size_t i = i0;
  for (; i + 4 <= i1; i += 4)
    for (int q = 0; q < 4; q++) h4[(size_t)q * NBIN + (order_key(v[i + q]) >> shift & (NBIN - 1))]++;
  for (; i < i1; i++) h4[order_key(v[i]) >> shift & (NBIN - 1)]++;
}

void jnd_order_fold(const size_t *h4, size_t *h) {
  for (int b = 0; b < NBIN; b++) h[b] = h4[b] + h4[NBIN + b] + h4[2 * NBIN + b] + h4[3 * NBIN + b];
}

/* the first level's counts: key bits [20, 32) */
void jnd_order_count(const float *v, size_t n, size_t *h4) { count_range(v, 0, n, 20, h4); }

/* Which of the 8 values at v fall in one of the wanted bins (key bits
 * [shift, shift + 12) equal to one of want[0..nw)), as bit q for value q:
 * compares of the 8 keys with each, no branch per value; most groups of a
 * map hold none, and the others few */
static inline unsigned group_wanted(const float *v, int shift, const uint32_t *want, int nw) {
  unsigned hit = 0;
  for (int w = 0; w < nw; w++)
    for (int q = 0; q < 8; q++) hit |= (unsigned)((order_key(v[q]) >> shift & (NBIN - 1)) == want[w]) << q;
  return hit;
}

static jnd_status order_stats_level(const float *v, size_t n, const size_t *ks, int nk, float *out, int shift,
                                    int nt);

/* Ranks ks (ascending) of v[0, n), whose keys all agree above bit shift + 12
 * (shift 20: any values), from the counts per bin of key bits [shift, shift
 * + 12) of nt ranges of v, [bound[t], bound[t + 1]) counted into row t of
 * hist (rows NBIN apart): the bins holding the wanted ranks are
 * gathered in a pass, and each is searched one level finer (shift 8) or, at
 * that level, sorted. Exact, O(n), and v is unchanged. Range t's values go
 * after the earlier ranges' in each gathered bin, so the result depends on
 * neither timing nor team size (and an order statistic, on no order at
 * all). */
static jnd_status order_select(const float *v, int nt, const size_t *bound, const size_t *hist,
                               const size_t *ks, int nk, float *out, int shift) {
  size_t *start = jnd_calloc(NBIN + 1, sizeof *start);
  int *slot = malloc(sizeof(int) * NBIN);
  if (!start || !slot) {
    free(start);
    free(slot);
    return JND_ERR_NOMEM;
  }
  for (int t = 0; t < nt; t++)
    for (int b = 0; b < NBIN; b++) start[b + 1] += hist[(size_t)t * NBIN + b];
  for (int b = 0; b < NBIN; b++) start[b + 1] += start[b];
  /* the bin of each wanted rank, and a gather buffer per distinct bin */
  int bin_of[JND_RANKS_MAX], nbins = 0, bins[JND_RANKS_MAX];
  uint32_t want[JND_RANKS_MAX];
  size_t off[JND_RANKS_MAX + 1] = {0};
  for (int b = 0; b < NBIN; b++) slot[b] = -1;
  for (int i = 0; i < nk; i++) {
    int lo = 0, hi = NBIN - 1; /* the bin b with start[b] <= k < start[b + 1] */
    while (lo < hi) {
      int mid = (lo + hi + 1) / 2;
      if (start[mid] <= ks[i]) lo = mid; else hi = mid - 1;
    }
    if (slot[lo] < 0) {
      slot[lo] = nbins;
      bins[nbins] = lo;
      want[nbins] = (uint32_t)lo;
      off[nbins + 1] = off[nbins] + (start[lo + 1] - start[lo]);
      nbins++;
    }
    bin_of[i] = lo;
  }
  float *buf = jnd_alloc(off[nbins] ? off[nbins] : 1, sizeof *buf);
  jnd_status s = buf ? JND_OK : JND_ERR_NOMEM;
  if (s == JND_OK) {
#pragma omp parallel for num_threads(nt) schedule(static)
    for (int t = 0; t < nt; t++) {
      const size_t i0 = bound[t], i1 = bound[t + 1];
      /* this range's place in each gathered bin: after the earlier ranges' values */
      size_t fill[JND_RANKS_MAX];
      for (int j = 0; j < nbins; j++) {
        fill[j] = off[j];
        for (int u = 0; u < t; u++) fill[j] += hist[(size_t)u * NBIN + bins[j]];
      }
      size_t i = i0;
      for (; i + 8 <= i1; i += 8)
        for (unsigned hit = group_wanted(v + i, shift, want, nbins); hit; hit &= hit - 1) {
          const float x = v[i + (size_t)__builtin_ctz(hit)];
          buf[fill[slot[order_key(x) >> shift & (NBIN - 1)]]++] = x;
        }
      for (; i < i1; i++) {
        int sl = slot[order_key(v[i]) >> shift & (NBIN - 1)];
        if (sl >= 0) buf[fill[sl]++] = v[i];
      }
    }
  }
  /* each gathered bin: its ranks (consecutive in ks, as the bins ascend) */
  for (int i = 0; i < nk && s == JND_OK;) {
    const int j = slot[bin_of[i]];
    const size_t m = off[j + 1] - off[j];
    float *b = buf + off[j];
    size_t local[JND_RANKS_MAX];
    int e = i;
    for (; e < nk && bin_of[e] == bin_of[i]; e++) local[e - i] = ks[e] - start[bin_of[i]];
    if (shift > FINE && m > 4096) {
      s = order_stats_level(b, m, local, e - i, out + i, FINE, 1);
    } else {
      s = jnd_sort_floats(b, m);
      for (int q = i; q < e && s == JND_OK; q++) out[q] = b[local[q - i]];
    }
    i = e;
  }
  free(buf);
  free(start);
  free(slot);
  return s;
}

/* order_select after a counting pass: v split into nt equal ranges, each
 * counted by a thread */
static jnd_status order_stats_level(const float *v, size_t n, const size_t *ks, int nk, float *out, int shift,
                                    int nt) {
  /* [thread][4][bin]: four counts a range (count_range), folded into the
   * range's row of counts (hist) */
  size_t *h4 = jnd_calloc((size_t)nt * 4 * NBIN, sizeof *h4);
  size_t *hist = jnd_alloc((size_t)nt * NBIN, sizeof *hist);
  size_t bound[JND_ORDER_RANGES_MAX + 1];
  if (!h4 || !hist || nt > JND_ORDER_RANGES_MAX) {
    free(h4);
    free(hist);
    return JND_ERR_NOMEM;
  }
  for (int t = 0; t <= nt; t++) bound[t] = n * (size_t)t / (size_t)nt;
#pragma omp parallel for num_threads(nt) schedule(static)
  for (int t = 0; t < nt; t++) {
    count_range(v, bound[t], bound[t + 1], shift, h4 + (size_t)t * 4 * NBIN);
    jnd_order_fold(h4 + (size_t)t * 4 * NBIN, hist + (size_t)t * NBIN);
  }
  free(h4);
  jnd_status s = order_select(v, nt, bound, hist, ks, nk, out, shift);
  free(hist);
  return s;
}

static jnd_status ranks_check(const size_t *ks, int nk, size_t n) {
  if (nk > JND_RANKS_MAX) return jnd_fail(JND_ERR_INTERNAL, "order statistics: at most %d ranks", JND_RANKS_MAX);
  for (int i = 0; i < nk; i++)
    if (ks[i] >= n || (i > 0 && ks[i] < ks[i - 1])) return jnd_fail(JND_ERR_INTERNAL, "order statistics: bad index");
  return JND_OK;
}

jnd_status jnd_order_stats(const float *v, size_t n, const size_t *ks, int nk, float *out) {
  jnd_status s = ranks_check(ks, nk, n);
  if (s != JND_OK) return s;
  int nt = omp_get_max_threads() > 0 ? omp_get_max_threads() : 1;
  if (nt > JND_ORDER_RANGES_MAX) nt = JND_ORDER_RANGES_MAX;
  return order_stats_level(v, n, ks, nk, out, 20, nt);
}

jnd_status jnd_ranks_select_counted(jnd_ranks *r, const float *v, int nt, const size_t *bound, const size_t *hist) {
  jnd_status s = ranks_check(r->k, r->nk, r->n);
  if (s != JND_OK) return s;
  if (nt < 1 || nt > JND_ORDER_RANGES_MAX || bound[0] != 0 || bound[nt] != r->n)
    return jnd_fail(JND_ERR_INTERNAL, "order statistics: bad ranges");
  return order_select(v, nt, bound, hist, r->k, r->nk, r->v, 20);
}

/* ---- percentiles from order statistics ---- */

/* where the p-th percentile lies: between order statistics k and k + 1, at
 * weight t of k + 1 (linear interpolation; k = n − 1, t = 0 at the top) */
static size_t percentile_rank(size_t n, double p, double *t) {
  double pos = jnd_clampd(p, 0, 100) / 100.0 * (double)(n - 1);
  size_t k = (size_t)floor(pos);
  if (k >= n - 1) {
    *t = 0;
    return n - 1;
  }
  *t = pos - (double)k;
  return k;
}

void jnd_ranks_init(jnd_ranks *r, size_t n) {
  memset(r, 0, sizeof *r);
  r->n = n;
}

/* adds rank k, keeping r->k ascending and unique */
static void ranks_add(jnd_ranks *r, size_t k) {
  int i = r->nk;
  while (i > 0 && r->k[i - 1] > k) i--;
  if (i > 0 && r->k[i - 1] == k) return;
  memmove(r->k + i + 1, r->k + i, sizeof r->k[0] * (size_t)(r->nk - i));
  r->k[i] = k;
  r->nk++;
}

jnd_status jnd_ranks_want(jnd_ranks *r, double p) {
  if (r->n == 0) return jnd_fail(JND_ERR_ARG, "percentile of no values");
  if (r->nk + 2 > JND_RANKS_MAX) return jnd_fail(JND_ERR_INTERNAL, "too many percentiles at once");
  double t;
  size_t k = percentile_rank(r->n, p, &t);
  ranks_add(r, k);
  if (k + 1 < r->n) ranks_add(r, k + 1);
  return JND_OK;
}

jnd_status jnd_ranks_select(jnd_ranks *r, const float *v) { return jnd_order_stats(v, r->n, r->k, r->nk, r->v); }

static double rank_value(const jnd_ranks *r, size_t k, double (*f)(double, const void *), const void *ctx) {
  for (int i = 0; i < r->nk; i++)
    if (r->k[i] == k) return f ? f(r->v[i], ctx) : r->v[i];
  return NAN; /* a rank jnd_ranks_want was not given */
}

double jnd_ranks_percentile(const jnd_ranks *r, double p, double (*f)(double, const void *), const void *ctx) {
  double t;
  size_t k = percentile_rank(r->n, p, &t);
  double a = rank_value(r, k, f, ctx);
  if (k + 1 >= r->n) return a;
  double b = rank_value(r, k + 1, f, ctx);
  return a + t * (b - a);
}

jnd_status jnd_percentiles(const float *v, size_t n, const double *p, int np, double *out) {
  jnd_ranks r;
  jnd_ranks_init(&r, n);
  jnd_status s = JND_OK;
  for (int i = 0; i < np && s == JND_OK; i++) s = jnd_ranks_want(&r, p[i]);
  if (s == JND_OK) s = jnd_ranks_select(&r, v);
  for (int i = 0; i < np; i++) out[i] = s == JND_OK ? jnd_ranks_percentile(&r, p[i], NULL, NULL) : NAN;
  return s;
}

double jnd_percentile(const float *values, size_t n, double p) {
  double r;
  return jnd_percentiles(values, n, &p, 1, &r) == JND_OK ? r : NAN;
}

double jnd_pool(const float *values, size_t n, const jnd_pooling *pool, double e) {
  if (n == 0) return NAN;
  switch (pool->kind) {
  case JND_POOL_MAX: {
    float m = values[0];
    for (size_t i = 1; i < n; i++) m = values[i] > m ? values[i] : m;
    return m;
  }
  case JND_POOL_MEAN: {
    double s = 0;
    for (size_t i = 0; i < n; i++) s += values[i];
    return s / (double)n;
  }
  case JND_POOL_MINKOWSKI: {
    double s = 0;
    for (size_t i = 0; i < n; i++) s += pow(fabs(values[i]), e);
    return pow(s / (double)n, 1.0 / e);
  }
  case JND_POOL_PERCENTILE:
  default:
    return jnd_percentile(values, n, pool->percentile);
  }
}

jnd_status jnd_pooling_parse(const char *s, jnd_pooling *out) {
  memset(out, 0, sizeof *out);
  if (strcmp(s, "max") == 0) {
    out->kind = JND_POOL_MAX;
  } else if (strcmp(s, "mean") == 0) {
    out->kind = JND_POOL_MEAN;
  } else if (strcmp(s, "minkowski") == 0) {
    out->kind = JND_POOL_MINKOWSKI;
  } else if (s[0] == 'p' && s[1]) {
    char *end;
    double p = strtod(s + 1, &end);
    if (*end || !(p >= 0 && p <= 100))
      return jnd_fail(JND_ERR_ARG, "pooling '%s': a percentile is p0..p100, like p93", s);
    out->kind = JND_POOL_PERCENTILE;
    out->percentile = p;
  } else {
    return jnd_fail(JND_ERR_ARG, "pooling '%s': one of p93 (or any pNN), max, mean, minkowski", s);
  }
  return JND_OK;
}

const char *jnd_pooling_name(const jnd_pooling *p, char *buf, size_t n) {
  switch (p->kind) {
  case JND_POOL_MAX: snprintf(buf, n, "max"); break;
  case JND_POOL_MEAN: snprintf(buf, n, "mean"); break;
  case JND_POOL_MINKOWSKI: snprintf(buf, n, "minkowski"); break;
  default: snprintf(buf, n, "p%g", p->percentile); break;
  }
  return buf;
}
