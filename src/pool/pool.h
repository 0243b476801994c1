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
/* p-th percentile (0..100) of already sorted values, linear interpolation. */
double jnd_percentile_sorted(const float *sorted, size_t n, double p);
#endif
