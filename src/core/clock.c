/* The clocks for timings a result reports (never in a decision): one
 * monotonic wall clock and the process's CPU time, for the library, batch
 * and the command-line program alike. */
#include <time.h>

#include "core/core.h"

static double timespec_s(struct timespec t) { return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec; }

double jnd_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return timespec_s(t);
}

double jnd_cpu_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return timespec_s(t);
}
