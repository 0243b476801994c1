/* Thread count policy. Work is split over rows with OpenMP; every reduction
 * is done afterwards in a fixed order, so results do not depend on threads. */
#include <omp.h>

#include "core/core.h"

int jnd_threads(int requested) {
  if (requested > 0) return requested;
  int n = omp_get_max_threads();
  return n > 0 ? n : 1;
}

int jnd_threads_enter(int n) {
  if (n <= 0) return 0;
  int previous = omp_get_max_threads();
  omp_set_num_threads(n);
  return previous;
}

void jnd_threads_leave(int previous) {
  if (previous > 0) omp_set_num_threads(previous);
}
