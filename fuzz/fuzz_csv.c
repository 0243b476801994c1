/* libFuzzer target: the CSV parser on arbitrary bytes. A parsed table must be
 * rectangular with every cell a string; a refusal must leave it empty. */
#include <string.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_csv csv;
  jnd_status s = jnd_csv_parse("fuzz.csv", (const char *)data, size, &csv);
  if (s != JND_OK) {
    if (csv.header || csv.cells || csv.ncols || csv.nrows) abort();
    return 0;
  }
  if (csv.ncols < 1 || !csv.header) abort();
  size_t total = 0;
  for (int i = 0; i < csv.ncols; i++) total += strlen(csv.header[i]);
  for (int r = 0; r < csv.nrows; r++)
    for (int i = 0; i < csv.ncols; i++) total += strlen(csv.cells[r][i]);
  if (total > size) abort(); /* cells are pieces of the input */
  jnd_csv_free(&csv);
  return 0;
}
