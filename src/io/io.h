/* Internal helpers of the io layer. */
#ifndef JND_IO_H
#define JND_IO_H

#include <stddef.h>
#include <stdint.h>
#include "jnd.h"

/* Reads a whole file (at most max_bytes) into a malloc'd buffer. */
jnd_status jnd_read_file(const char *path, size_t max_bytes, unsigned char **data, size_t *size);

/* One CSV record (RFC 4180) of t[0..n) starting at *pos, which moves past it
 * and its line break: fields (malloc'd, each malloc'd) and their count.
 * Returns 0 at the end of input, 1 for a record, -1 for a malformed one (a
 * quote not closed, a NUL byte). */
int jnd_csv_record(const char *t, size_t n, size_t *pos, char ***fields, int *count);

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

/* Whether a PNG that jnd_png_validate has passed is one jnd_png_decode reads:
 * bit depth 8 or 16, grey, grey + alpha, RGB or RGBA, not interlaced, no
 * tRNS chunk and no unknown critical chunk. The rest (palettes, depths 1–4,
 * Adam7, transparency keys) is left to stb_image. */
int jnd_png_plain(const unsigned char *buf, size_t n);

/* Decodes a PNG for which jnd_png_plain holds: zlib inflates the IDAT chunks
 * in place, a block of rows at a time (memory besides the image: about
 * 64 KiB, or two rows where a row is longer), the rows are unfiltered and
 * written to out as planar floats, sample / 255 or / 65535, bit for bit as
 * the stb_image path gives them. *bits gets 8 or 16. A corrupt or short
 * stream, or a filter type over 4, is JND_ERR_FORMAT naming the file; data
 * after the last row is ignored (its Adler-32 is not checked: the chunks'
 * CRCs are). out is empty on failure. */
jnd_status jnd_png_decode(const char *name, const unsigned char *buf, size_t n, jnd_image *out, int *bits);
/* Whether a PNG that jnd_png_validate has passed is an 8-bit RGB one that
 * jnd_png_decode reads (jnd_png_plain). */
int jnd_png_is_rgb8(const unsigned char *buf, size_t n);
/* jnd_png_decode of an 8-bit RGB file (jnd_png_is_rgb8), its samples kept
 * as they are: *rgb gets w × h pixels of R, G, B bytes, row-major (free()),
 * a quarter of the planes' memory. Another layout is JND_ERR_FORMAT. */
jnd_status jnd_png_decode_rgb8(const char *name, const unsigned char *buf, size_t n, unsigned char **rgb, int *w,
                               int *h);
/* jnd_image_read, where the file is an 8-bit RGB PNG that jnd_png_decode
 * reads, with its samples kept as bytes (jnd_png_decode_rgb8): *rgb gets
 * them, and out the size with no data; any other file as jnd_image_read
 * gives it (*rgb NULL). */
jnd_status jnd_image_read_rgb8(const char *path, jnd_image *out, jnd_image_info *info, unsigned char **rgb);

/* jnd_decode_png through stb_image alone (the path for every other PNG),
 * for comparing the two decoders in tests and the fuzzer. */
jnd_status jnd_decode_png_stb(const char *name, const unsigned char *buf, size_t n,
                              jnd_image *out, jnd_image_info *info);

/* Fills *info (when not NULL) for a decoded image: every decoder's summary. */
void jnd_image_info_set(jnd_image_info *info, const char *format, jnd_encoding enc, int bits, int channels,
                        int has_alpha);

uint32_t jnd_crc32(const unsigned char *buf, size_t n);

/* Refuses NaN and Inf samples. */
jnd_status jnd_image_check_finite(const char *name, const jnd_image *img);

/* ---- a growable byte buffer and the binary glTF container (glb.c) ---- */
typedef struct {
  unsigned char *p;
  size_t n, cap;
  int failed;          /* an allocation failed: later puts do nothing */
} jnd_buf;
void jnd_buf_put(jnd_buf *b, const void *data, size_t n);
void jnd_buf_pad4(jnd_buf *b, unsigned char fill);
void jnd_buf_free(jnd_buf *b);
/* An image (0..1, 1 to 4 channels) as 8-bit PNG (jpeg 0) or JPEG (quality
 * 95; 1 or 3 channels) appended to out: the codes jnd_image_write_png
 * writes, for the textures a written model embeds. */
jnd_status jnd_image_encode_8bit(const jnd_image *img, int jpeg, jnd_buf *out);
/* Splits a file into its glTF JSON and binary chunk: 1 for a GLB (json and
 * bin point into file; bin NULL when it has no BIN chunk), 0 for plain JSON
 * (json is the whole file), −1 for a malformed GLB header or JSON chunk. */
int jnd_glb_split(const unsigned char *file, size_t n, const unsigned char **json, size_t *json_n,
                  const unsigned char **bin, size_t *bin_n);
/* Builds a GLB (version 2) from JSON text and a binary chunk (bin_n 0:
 * none), each padded to 4 bytes (JSON with spaces, BIN with zeros). */
jnd_status jnd_glb_join(const char *json, size_t json_n, const unsigned char *bin, size_t bin_n, jnd_buf *out);

#endif
