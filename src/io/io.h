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

#endif
