/* Thread count policy. Work is split over rows with OpenMP; every reduction
 * is done afterwards in a fixed order, so results do not depend on threads. */
#include <omp.h>

#include "core/core.h"

int jnd_threads(int requested) {
  if (requested > 0) return requested;
  int n = omp_get_max_threads();
  return n > 0 ? n : 1;
}
