/* Internal helpers of the pool layer. */
#ifndef JND_POOL_H
#define JND_POOL_H
#include <stddef.h>
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
double jnd_ranks_percentile(const jnd_ranks *r, double p, double (*f)(double, const void *), const void *ctx);
/* np percentiles p[] of n values at once (np <= 32) into out[] */
jnd_status jnd_percentiles(const float *v, size_t n, const double *p, int np, double *out);
#endif
