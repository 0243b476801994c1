/* libFuzzer target: jnd gaze's table (gaze.csv) as an engine loads it. A
 * parsed table is a complete grid, ascending on both axes, of whole levels;
 * a lookup anywhere returns one of its levels or a value between them; a
 * refusal leaves the table empty. */
#include <math.h>
#include <string.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_gaze_lookup lut;
  jnd_status s = jnd_gaze_lookup_parse("fuzz.csv", (const char *)data, size, &lut);
  if (s != JND_OK) {
    if (lut.level || lut.distances_m || lut.eccentricities_deg || lut.nd || lut.ne) abort();
    return 0;
  }
  if (lut.nd < 1 || lut.ne < 1) abort();
  float lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < lut.nd; i++)
    if (!(lut.distances_m[i] > 0) || (i && !(lut.distances_m[i] > lut.distances_m[i - 1]))) abort();
  for (int j = 0; j < lut.ne; j++)
    if (!(lut.eccentricities_deg[j] >= 0 && lut.eccentricities_deg[j] <= 90) ||
        (j && !(lut.eccentricities_deg[j] > lut.eccentricities_deg[j - 1])))
      abort();
  for (int q = 0; q < lut.nd * lut.ne; q++) {
    if (!(lut.level[q] >= 0) || lut.level[q] != floorf(lut.level[q])) abort();
    lo = fminf(lo, lut.level[q]), hi = fmaxf(hi, lut.level[q]);
  }
  const double probes[][2] = {{0, 0}, {1e9, 90}, {1, 45}, {lut.distances_m[0], lut.eccentricities_deg[lut.ne - 1]}};
  for (size_t i = 0; i < sizeof probes / sizeof *probes; i++)
    for (int mode = 0; mode < 3; mode++) {
      double l = jnd_gaze_lookup_level(&lut, probes[i][0], probes[i][1], (jnd_gaze_lookup_mode)mode);
      if (!(l >= lo - 1e-4 && l <= hi + 1e-4)) abort();
    }
  jnd_gaze_lookup_free(&lut);
  return 0;
}
