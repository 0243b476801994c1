/* libFuzzer target: the castleCSF data reader (jnd csf's rows, colour
 * directions and backgrounds) on arbitrary bytes. The input is three CSV
 * texts separated by form feeds: data, colour directions, backgrounds. A
 * read must give one row per data row, each with a data set index in range,
 * or fail with an empty result and a message. */
#include <string.h>

#include "fuzz.h"
#include "tasks/tasks.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *p = (const char *)data, *end = p + size;
  const char *part[3];
  size_t len[3];
  for (int k = 0; k < 3; k++) {
    const char *ff = k < 2 ? memchr(p, '\f', (size_t)(end - p)) : NULL;
    part[k] = p;
    len[k] = ff ? (size_t)(ff - p) : (size_t)(end - p);
    p = ff ? ff + 1 : end;
  }
  jnd_csv t[3];
  int ok = 1;
  for (int k = 0; k < 3; k++) {
    if (jnd_csv_parse("fuzz.csv", part[k], len[k], &t[k]) != JND_OK) memset(&t[k], 0, sizeof t[k]), ok = 0;
  }
  if (ok) {
    int nrows = t[0].nrows;
    jnd_csf_data d;
    jnd_status s = jnd_csf_data_from_tables("data.csv", &t[0], "colors.csv", &t[1], "backgrounds.csv", &t[2], &d);
    if (s != JND_OK) {
      if (d.rows || d.nrows || d.datasets || !jnd_last_error()[0]) abort();
    } else {
      if (d.nrows != nrows) abort();
      for (int r = 0; r < d.nrows; r++) {
        if (d.rows[r].dataset < 0 || d.rows[r].dataset >= d.ndatasets) abort();
        if (d.rows[r].use && !(d.rows[r].measured > 0)) abort();
      }
      jnd_csf_data_free(&d);
    }
  }
  for (int k = 0; k < 3; k++) jnd_csv_free(&t[k]);
  return 0;
}
