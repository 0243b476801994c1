/* Image files in: the format is told by the file's first bytes, not its name.
 * PNG, JPEG and Radiance HDR go through stb_image; OpenEXR through the
 * OpenEXR core C API (exr.c). Every decoder refuses sizes over the limits and
 * non-finite samples, and names the file in its one-line error. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "core/core.h"
#include "io/io.h"

#define MAX_FILE_BYTES ((size_t)2 << 30)

jnd_status jnd_image_check_finite(const char *name, const jnd_image *img) {
  size_t n = (size_t)img->w * img->h * img->c;
  for (size_t i = 0; i < n; i++) {
    if (!isfinite(img->data[i])) {
      size_t px = i % ((size_t)img->w * img->h);
      return jnd_fail(JND_ERR_FORMAT, "%s: pixel (%zu, %zu) channel %zu is %s", name,
                      px % img->w, px / img->w, i / ((size_t)img->w * img->h),
                      isnan(img->data[i]) ? "NaN" : "infinite");
    }
  }
  return JND_OK;
}

/* stb gives interleaved samples; jnd images are planar. */
static jnd_status planar_from_interleaved(const char *name, const void *px, int bits, int w, int h,
                                          int c, double scale, jnd_image *out) {
  jnd_status s = jnd_image_alloc(out, w, h, c);
  if (s != JND_OK) return jnd_fail(s, "%s: out of memory for %d × %d × %d", name, w, h, c);
  size_t n = (size_t)w * h;
  for (int ch = 0; ch < c; ch++) {
    float *dst = jnd_image_plane(out, ch);
    if (bits == 8) {
      const unsigned char *src = px;
      for (size_t i = 0; i < n; i++) dst[i] = (float)(src[i * c + ch] * scale);
    } else if (bits == 16) {
      const unsigned short *src = px;
      for (size_t i = 0; i < n; i++) dst[i] = (float)(src[i * c + ch] * scale);
    } else {
      const float *src = px;
      for (size_t i = 0; i < n; i++) dst[i] = src[i * c + ch];
    }
  }
  return JND_OK;
}

/* Headers may claim up to this many samples whatever the file's size. */
#define SMALL_SAMPLES ((double)(1u << 22))

/* Reads the size from the header and refuses sizes over the limits, or more
 * samples than max_per_byte per byte of the file could encode, so that a few
 * bytes cannot make the decoder allocate gigabytes. */
static jnd_status stb_header(const char *name, const unsigned char *buf, size_t n, double max_per_byte,
                             int *w, int *h, int *c) {
  if (n > INT32_MAX) return jnd_fail(JND_ERR_LIMIT, "%s: file too large", name);
  if (!stbi_info_from_memory(buf, (int)n, w, h, c))
    return jnd_fail(JND_ERR_FORMAT, "%s: cannot read the header: %s", name, stbi_failure_reason());
  jnd_status s = jnd_check_size(*w, *h, *c, name);
  if (s != JND_OK) return s;
  double samples = (double)*w * *h * *c;
  if (samples > SMALL_SAMPLES && samples > max_per_byte * (double)n)
    return jnd_fail(JND_ERR_FORMAT, "%s: header claims %d × %d × %d samples, more than a %zu-byte file can hold",
                    name, *w, *h, *c, n);
  return JND_OK;
}

jnd_status jnd_decode_png(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                          jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  jnd_status s = jnd_png_validate(name, buf, n);
  if (s != JND_OK) return s;
  int w, h, c;
  /* jnd_png_validate has bounded the size by the compressed data */
  if ((s = stb_header(name, buf, n, 1e12, &w, &h, &c)) != JND_OK) return s;
  int bits = stbi_is_16_bit_from_memory(buf, (int)n) ? 16 : 8;
  void *px = bits == 16 ? (void *)stbi_load_16_from_memory(buf, (int)n, &w, &h, &c, 0)
                        : (void *)stbi_load_from_memory(buf, (int)n, &w, &h, &c, 0);
  if (!px) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG: %s", name, stbi_failure_reason());
  s = planar_from_interleaved(name, px, bits, w, h, c, bits == 16 ? 1.0 / 65535 : 1.0 / 255, out);
  stbi_image_free(px);
  if (s != JND_OK) return s;
  if (info) {
    memset(info, 0, sizeof *info);
    info->encoding = JND_ENCODING_SRGB;
    info->bits = bits;
    info->channels = c;
    info->has_alpha = c == 2 || c == 4;
    strcpy(info->format, "png");
  }
  return JND_OK;
}

jnd_status jnd_decode_jpeg(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                           jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  /* stb_image fills a truncated JPEG with grey; refuse files without the end marker */
  size_t end = n;
  while (end > 2 && buf[end - 1] == 0) end--; /* some writers pad with zeros */
  if (end < 4 || buf[end - 2] != 0xFF || buf[end - 1] != 0xD9)
    return jnd_fail(JND_ERR_FORMAT, "%s: truncated JPEG (no end-of-image marker)", name);
  int w, h, c;
  /* every 8 × 8 block of every component costs at least a bit (its DC code);
   * chroma subsampling spreads a block over up to 4 × 4 more pixels */
  jnd_status s = stb_header(name, buf, n, 2048, &w, &h, &c);
  if (s != JND_OK) return s;
  unsigned char *px = stbi_load_from_memory(buf, (int)n, &w, &h, &c, 0);
  if (!px) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG: %s", name, stbi_failure_reason());
  s = planar_from_interleaved(name, px, 8, w, h, c, 1.0 / 255, out);
  stbi_image_free(px);
  if (s != JND_OK) return s;
  if (info) {
    memset(info, 0, sizeof *info);
    info->encoding = JND_ENCODING_SRGB;
    info->bits = 8;
    info->channels = c;
    strcpy(info->format, "jpeg");
  }
  return JND_OK;
}

jnd_status jnd_decode_hdr(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                          jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  int w, h, c;
  /* run-length scanlines spend at least 2 bytes on 127 values of a component */
  jnd_status s = stb_header(name, buf, n, 64, &w, &h, &c);
  if (s != JND_OK) return s;
  float *px = stbi_loadf_from_memory(buf, (int)n, &w, &h, &c, 3);
  if (!px) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt Radiance HDR: %s", name, stbi_failure_reason());
  s = planar_from_interleaved(name, px, 32, w, h, 3, 1.0, out);
  stbi_image_free(px);
  if (s != JND_OK) return s;
  if ((s = jnd_image_check_finite(name, out)) != JND_OK) {
    jnd_image_free(out);
    return s;
  }
  if (info) {
    memset(info, 0, sizeof *info);
    info->encoding = JND_ENCODING_LINEAR;
    info->bits = 32;
    info->channels = 3;
    strcpy(info->format, "hdr");
  }
  return JND_OK;
}

jnd_status jnd_image_read(const char *path, jnd_image *out, jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  unsigned char *buf;
  size_t n;
  jnd_status s = jnd_read_file(path, MAX_FILE_BYTES, &buf, &n);
  if (s != JND_OK) return s;
  static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n == 0) {
    s = jnd_fail(JND_ERR_FORMAT, "%s: empty file", path);
  } else if (n >= 8 && memcmp(buf, png_sig, 8) == 0) {
    s = jnd_decode_png(path, buf, n, out, info);
  } else if (n >= 3 && buf[0] == 0xFF && buf[1] == 0xD8 && buf[2] == 0xFF) {
    s = jnd_decode_jpeg(path, buf, n, out, info);
  } else if (n >= 2 && buf[0] == '#' && buf[1] == '?') {
    s = jnd_decode_hdr(path, buf, n, out, info);
  } else if (n >= 4 && buf[0] == 0x76 && buf[1] == 0x2f && buf[2] == 0x31 && buf[3] == 0x01) {
    s = jnd_decode_exr(path, buf, n, out, info);
  } else {
    s = jnd_fail(JND_ERR_FORMAT, "%s: not a supported image (PNG, JPEG, Radiance HDR or OpenEXR)", path);
  }
  free(buf);
  return s;
}
