/* Internal helpers of the io layer. */
#ifndef JND_IO_H
#define JND_IO_H

#include <stddef.h>
#include <stdint.h>
#include "jnd.h"

/* Reads a whole file (at most max_bytes) into a malloc'd buffer. */
jnd_status jnd_read_file(const char *path, size_t max_bytes, unsigned char **data, size_t *size);

/* Decoders over memory, used by jnd_image_read and by the fuzz targets.
 * name is the file name used in error messages. */
jnd_status jnd_decode_png(const char *name, const unsigned char *buf, size_t n,
                          jnd_image *out, jnd_image_info *info);
jnd_status jnd_decode_jpeg(const char *name, const unsigned char *buf, size_t n,
                           jnd_image *out, jnd_image_info *info);
jnd_status jnd_decode_hdr(const char *name, const unsigned char *buf, size_t n,
                          jnd_image *out, jnd_image_info *info);
jnd_status jnd_decode_exr(const char *name, const unsigned char *buf, size_t n,
                          jnd_image *out, jnd_image_info *info);

/* Checks a PNG's signature, chunk lengths and CRCs, and that IHDR comes first
 * and IEND last (stb_image does not check CRCs). */
jnd_status jnd_png_validate(const char *name, const unsigned char *buf, size_t n);

uint32_t jnd_crc32(const unsigned char *buf, size_t n);

/* Refuses NaN and Inf samples. */
jnd_status jnd_image_check_finite(const char *name, const jnd_image *img);

/* ---- CSV ---- */
typedef struct {
  int ncols, nrows;
  char **header;   /* ncols names */
  char ***cells;   /* nrows × ncols strings ("" for empty) */
} jnd_csv;

/* Reads a comma-separated file with a header row; quoted fields ("a,b",
 * "say ""hi""") are supported. Rows must have the header's column count. */
jnd_status jnd_csv_read(const char *path, jnd_csv *out);
jnd_status jnd_csv_parse(const char *name, const char *text, size_t n, jnd_csv *out);
void jnd_csv_free(jnd_csv *csv);
/* Index of a column by name, or -1. */
int jnd_csv_column(const jnd_csv *csv, const char *name);
/* Parses a cell as a number; NaN for "NaN"/"NA"/"". Returns 0 if not a number. */
int jnd_csv_number(const char *cell, double *out);

#endif
