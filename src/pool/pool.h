/* Internal helpers of the pool layer. */
#ifndef JND_POOL_H
#define JND_POOL_H
#include <stddef.h>
#include "jnd.h"

/* Sorts n floats ascending in place (radix sort when all are >= 0). */
jnd_status jnd_sort_floats(float *v, size_t n);
/* p-th percentile (0..100) of already sorted values, linear interpolation. */
double jnd_percentile_sorted(const float *sorted, size_t n, double p);
#endif
