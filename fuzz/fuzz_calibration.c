/* libFuzzer target: the calibration file reader (jnd_calibration_load, what
 * --calibration of jnd diff and jnd texres reads) on arbitrary bytes. A
 * loaded calibration must be in range; a refusal must say why. */
#include <stdio.h>
#include <unistd.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static char path[64];
  if (!path[0]) snprintf(path, sizeof path, "/tmp/jnd-fuzz-calibration-%d.json", (int)getpid());
  FILE *f = fopen(path, "wb");
  if (!f) abort();
  if (size && fwrite(data, size, 1, f) != 1) abort();
  fclose(f);
  jnd_calibration c;
  jnd_status s = jnd_calibration_load(path, &c);
  if (s != JND_OK) {
    if (!jnd_last_error()[0]) abort();
    return 0;
  }
  if (!(c.percentile >= 0 && c.percentile <= 100) || !(c.scale > 0) || !(c.beta > 0) ||
      !(c.threshold_p > 0 && c.threshold_p < 1) || !isfinite(c.bias))
    abort();
  return 0;
}
