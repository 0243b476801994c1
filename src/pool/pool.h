/* Internal helpers of the pool layer. */
#ifndef JND_POOL_H
#define JND_POOL_H
#include <stddef.h>
#include <stdint.h>
#include "jnd.h"

/* Sorts n floats ascending in place (radix sort when all are >= 0). */
jnd_status jnd_sort_floats(float *v, size_t n);
/* The order statistics for the ascending indices ks[0..nk), nk <= 64: what
 * v[ks[i]] would be after sorting v ascending. O(n); v is not changed. */
jnd_status jnd_order_stats(const float *v, size_t n, const size_t *ks, int nk, float *out);
/* Percentiles (0..100, linear interpolation between order statistics) of
 * unsorted values, by selection: say which percentiles are wanted, select
 * once, then read them, through a monotone map f (NULL: the values
 * themselves) where the percentile of f(values) is wanted. */
enum { JND_RANKS_MAX = 64 };
typedef struct {
  size_t n;
  int nk;
  size_t k[JND_RANKS_MAX]; /* the order statistics wanted, ascending, unique */
  float v[JND_RANKS_MAX];  /* their values, after jnd_ranks_select */
} jnd_ranks;
void jnd_ranks_init(jnd_ranks *r, size_t n);
jnd_status jnd_ranks_want(jnd_ranks *r, double p);
jnd_status jnd_ranks_select(jnd_ranks *r, const float *v);
/* Counting and selecting apart, for a caller that reads the values anyway
 * (jnd_diff_summarise): jnd_order_count adds the n values to h4's four
 * interleaved counts per bin (4 × JND_ORDER_BINS, zeroed first by the
 * caller), jnd_order_fold sums those into h (JND_ORDER_BINS); then
 * jnd_ranks_select_counted selects as jnd_ranks_select does, v being nt
 * ranges [bound[t], bound[t + 1]) (bound[0] = 0, bound[nt] = n,
 * nt <= JND_ORDER_RANGES_MAX) whose counts are row t of hist
 * (JND_ORDER_BINS apart). The same values as jnd_ranks_select, whatever the
 * ranges. */
enum { JND_ORDER_BINS = 4096, JND_ORDER_RANGES_MAX = 64 };
void jnd_order_count(const float *v, size_t n, size_t *h4);
void jnd_order_fold(const size_t *h4, size_t *h);
jnd_status jnd_ranks_select_counted(jnd_ranks *r, const float *v, int nt, const size_t *bound, const size_t *hist);
double jnd_ranks_percentile(const jnd_ranks *r, double p, double (*f)(double, const void *), const void *ctx);
/* np percentiles p[] of n values at once (np <= 32) into out[] */
jnd_status jnd_percentiles(const float *v, size_t n, const double *p, int np, double *out);

/* ---- regions.c: connected regions (004 §3.2) ---- */
typedef struct {
  size_t pixels;
  double sum_pow;          /* Σ value^exponent over the region's pixels (raster order, double) */
  float max;               /* its largest value */
  int x0, y0, x1, y1;      /* bounding box, inclusive, pixels */
  size_t first;            /* raster index (y·w + x) of its first pixel */
} jnd_region;
/* The 8-connected components of {map >= threshold} of a w × h map that
 * contain at least one seed (seed[i] != 0; seed NULL: every pixel), in the
 * raster order of their first pixels (004 §3.2: seeds grown over the eight
 * neighbours while the value stays >= threshold). labels (w × h, caller's)
 * receives each pixel's region index or −1. *out is allocated (NULL when
 * none; free()). The same bits whatever `threads` (regions.c says how). */
jnd_status jnd_regions_find(const float *map, const uint8_t *seed, int w, int h, float threshold, double exponent,
                            int threads, int32_t *labels, jnd_region **out, int *nout);
#endif
