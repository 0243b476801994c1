/* Thread count policy. Work is split over rows with OpenMP; every reduction
 * is done afterwards in a fixed order, so results do not depend on threads. */
#include <omp.h>
#include <pthread.h>
#include <sched.h>
#include <stdlib.h>

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

int jnd_threads_pin(int requested) {
#if defined(__linux__) && defined(CPU_SET)
  static const char *const asked[] = {"OMP_PROC_BIND", "OMP_PLACES", "GOMP_CPU_AFFINITY", "KMP_AFFINITY"};
  for (size_t i = 0; i < sizeof asked / sizeof asked[0]; i++)
    if (getenv(asked[i])) return 0;
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return 0;
  const int n = CPU_COUNT(&allowed);
  if (n < 2 || jnd_threads(requested) != n) return 0;
  int cpu_of[CPU_SETSIZE];
  for (int c = 0, k = 0; c < CPU_SETSIZE && k < n; c++)
    if (CPU_ISSET(c, &allowed)) cpu_of[k++] = c;
  int held = 0;
  /* One thread more than CPUs: with more threads than CPUs, libgomp's
   * first thread waits for the threads it starts by sleeping, not spinning.
   * Spinning, it kept them off the CPU the scheduler had queued them on
   * for 1-8 ms (the region took 4.5 ms, this one 0.4). The extra thread
   * leaves when the next team is smaller. */
#pragma omp parallel num_threads(n + 1) reduction(+ : held)
  {
    const int t = omp_get_thread_num();
    if (t < n) {
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpu_of[t], &one);
      held += pthread_setaffinity_np(pthread_self(), sizeof one, &one) == 0;
    }
  }
  return held == n ? n : 0;
#else
  (void)requested;
  return 0;
#endif
}
