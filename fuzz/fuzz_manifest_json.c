/* libFuzzer target: the JSON manifest parser of `jnd batch` on arbitrary
 * bytes (options as a string or a list of words). */
#include "manifest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_batch_manifest m;
  fuzz_check_manifest(jnd_batch_manifest_parse_json("fuzz.json", (const char *)data, size, &m), &m, "fuzz.json");
  return 0;
}
