/* libFuzzer target: the CSV manifest parser of `jnd batch` (rows, their
 * checks, the shell words of each row's options) on arbitrary bytes. */
#include "manifest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_batch_manifest m;
  fuzz_check_manifest(jnd_batch_manifest_parse_csv("fuzz.csv", (const char *)data, size, &m), &m, "fuzz.csv");
  return 0;
}
