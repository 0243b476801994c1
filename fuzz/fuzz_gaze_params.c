/* libFuzzer target: jnd gaze --params (a jnd gaze fit report or the combined
 * defaults file). A refusal leaves the parameters as they were; an accepted
 * file gives finite parameters in their ranges. */
#include <math.h>
#include <string.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_gaze_model m, before;
  jnd_gaze_model_defaults(&m);
  before = m;
  jnd_status s = jnd_gaze_model_parse("fuzz.json", (const char *)data, size, &m);
  if (s != JND_OK) {
    if (memcmp(&m, &before, sizeof m) != 0) abort();
    return 0;
  }
  const double v[10] = {m.alpha, m.beta, m.s_deg, m.b, m.w_g, m.w_vdp, m.k_s, m.gamma, m.w_t, m.gamma_t};
  for (int i = 0; i < 10; i++)
    if (!isfinite(v[i])) abort();
  if (!(m.alpha > 0 && m.beta > 0 && m.k_s >= 1 && m.gamma > 0 && m.gamma_t > 0 && m.b >= 0 && m.w_g > 0)) abort();
  return 0;
}
