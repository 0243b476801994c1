/* libFuzzer target: jnd gaze fit's trials (DATA.csv). Parsed trials have
 * answers 0/1, terms >= 0 and stimulus ids below the count; a refusal
 * leaves the data empty. */
#include <math.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_gaze_data d;
  jnd_status s = jnd_gaze_data_parse("fuzz.csv", (const char *)data, size, &d);
  if (s != JND_OK) {
    if (d.trials || d.n || d.stimuli) abort();
    return 0;
  }
  if (d.n < 1 || d.stimuli < 1 || d.stimuli > 1000000000) abort();
  for (int i = 0; i < d.n; i++) {
    const jnd_gaze_trial *t = &d.trials[i];
    if ((t->seen != 0 && t->seen != 1) || t->stimulus < 0 || t->stimulus >= d.stimuli) abort();
    if (!(t->xor_deg >= 0 && t->v_jnd >= 0 && t->t_jnd >= 0 && t->ecc_deg >= 0 && t->ecc_deg <= 90)) abort();
  }
  jnd_gaze_data_free(&d);
  return 0;
}
