/* CSV in: a header row, then rows of the same width. RFC 4180 quoting. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"

#define MAX_CSV_BYTES ((size_t)256 << 20)
#define MAX_CSV_COLS 4096

void jnd_csv_free(jnd_csv *csv) {
  if (!csv) return;
  if (csv->header) {
    for (int i = 0; i < csv->ncols; i++) free(csv->header[i]);
    free(csv->header);
  }
  if (csv->cells) {
    for (int r = 0; r < csv->nrows; r++) {
      if (!csv->cells[r]) continue;
      for (int i = 0; i < csv->ncols; i++) free(csv->cells[r][i]);
      free(csv->cells[r]);
    }
    free(csv->cells);
  }
  memset(csv, 0, sizeof *csv);
}

int jnd_csv_record(const char *t, size_t n, size_t *pos, char ***fields, int *count) {
  size_t p = *pos;
  if (p >= n) return 0;
  int cap = 16, nf = 0;
  char **f = malloc(sizeof *f * cap);
  if (!f) return -1;
  for (;;) {
    size_t fcap = 32, fl = 0;
    char *field = malloc(fcap);
    if (!field) goto fail;
    int quoted = p < n && t[p] == '"';
    if (quoted) p++;
    for (;;) {
      if (p >= n) {
        if (quoted) { free(field); goto fail; }
        break;
      }
      char ch = t[p];
      if (quoted) {
        if (ch == '"') {
          if (p + 1 < n && t[p + 1] == '"') { p += 2; ch = '"'; }
          else { p++; quoted = 0; continue; }
        } else {
          p++;
        }
      } else {
        if (ch == ',' || ch == '\n' || ch == '\r') break;
        if (ch == '\0') { free(field); goto fail; }
        p++;
      }
      if (fl + 2 > fcap) {
        fcap *= 2;
        char *nf2 = realloc(field, fcap);
        if (!nf2) { free(field); goto fail; }
        field = nf2;
      }
      field[fl++] = ch;
    }
    field[fl] = 0;
    if (nf == cap) {
      if (cap >= MAX_CSV_COLS) { free(field); goto fail; }
      cap *= 2;
      char **nf3 = realloc(f, sizeof *f * cap);
      if (!nf3) { free(field); goto fail; }
      f = nf3;
    }
    f[nf++] = field;
    if (p < n && t[p] == ',') { p++; continue; }
    if (p < n && t[p] == '\r') p++;
    if (p < n && t[p] == '\n') p++;
    break;
  }
  *pos = p;
  *fields = f;
  *count = nf;
  return 1;
fail:
  for (int i = 0; i < nf; i++) free(f[i]);
  free(f);
  return -1;
}

jnd_status jnd_csv_parse(const char *name, const char *text, size_t n, jnd_csv *out) {
  memset(out, 0, sizeof *out);
  size_t pos = 0;
  if (n >= 3 && (unsigned char)text[0] == 0xEF && (unsigned char)text[1] == 0xBB &&
      (unsigned char)text[2] == 0xBF)
    pos = 3; /* UTF-8 byte-order mark */
  char **fields;
  int count;
  int r = jnd_csv_record(text, n, &pos, &fields, &count);
  if (r <= 0) return jnd_fail(JND_ERR_FORMAT, "%s: %s", name, r == 0 ? "empty CSV file" : "malformed CSV header");
  out->header = fields;
  out->ncols = count;
  int cap = 256, line = 1;
  out->cells = malloc(sizeof *out->cells * cap);
  if (!out->cells) { jnd_csv_free(out); return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", name); }
  for (;;) {
    line++;
    r = jnd_csv_record(text, n, &pos, &fields, &count);
    if (r == 0) break;
    if (r < 0) { jnd_csv_free(out); return jnd_fail(JND_ERR_FORMAT, "%s: line %d: malformed CSV record", name, line); }
    if (count == 1 && fields[0][0] == 0) { /* blank line */
      free(fields[0]);
      free(fields);
      continue;
    }
    if (count != out->ncols) {
      for (int i = 0; i < count; i++) free(fields[i]);
      free(fields);
      jnd_csv_free(out);
      return jnd_fail(JND_ERR_FORMAT, "%s: line %d has %d fields, the header has %d", name, line, count, out->ncols);
    }
    if (out->nrows == cap) {
      cap *= 2;
      char ***nc = realloc(out->cells, sizeof *nc * cap);
      if (!nc) {
        for (int i = 0; i < count; i++) free(fields[i]);
        free(fields);
        jnd_csv_free(out);
        return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", name);
      }
      out->cells = nc;
    }
    out->cells[out->nrows++] = fields;
  }
  return JND_OK;
}

jnd_status jnd_csv_read(const char *path, jnd_csv *out) {
  memset(out, 0, sizeof *out);
  unsigned char *buf;
  size_t n;
  jnd_status s = jnd_read_file(path, MAX_CSV_BYTES, &buf, &n);
  if (s != JND_OK) return s;
  s = jnd_csv_parse(path, (const char *)buf, n, out);
  free(buf);
  return s;
}

int jnd_csv_column(const jnd_csv *csv, const char *name) {
  for (int i = 0; i < csv->ncols; i++)
    if (strcmp(csv->header[i], name) == 0) return i;
  return -1;
}

int jnd_csv_number(const char *cell, double *out) {
  while (*cell == ' ') cell++;
  if (!*cell || strcmp(cell, "NaN") == 0 || strcmp(cell, "NA") == 0 || strcmp(cell, "nan") == 0) {
    *out = NAN;
    return 1;
  }
  char *end;
  errno = 0;
  double v = strtod(cell, &end);
  while (*end == ' ') end++;
  if (*end || errno == ERANGE) return 0;
  *out = v;
  return 1;
}
