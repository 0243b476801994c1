/* PNG: chunk validation on read (stb_image skips CRCs) and a writer for 8- and
 * 16-bit images (stb_image_write only writes 8-bit), deflated by zlib. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "core/core.h"
#include "io/io.h"

uint32_t jnd_crc32(const unsigned char *buf, size_t n) {
  return (uint32_t)crc32(crc32(0L, Z_NULL, 0), buf, (uInt)n);
}

static uint32_t be32(const unsigned char *p) {
  return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Refuses sizes over the limits, and images whose filtered rows could not
 * come out of idat_bytes of deflate data (deflate expands at most ~1032:1),
 * so that a few bytes cannot make the decoder allocate gigabytes. */
static jnd_status png_check_size(const char *name, uint32_t w, uint32_t h, unsigned depth,
                                 unsigned colour, size_t idat_bytes) {
  static const unsigned samples[7] = {1, 0, 3, 1, 2, 0, 4};
  if (colour > 6 || !samples[colour] || (depth != 1 && depth != 2 && depth != 4 && depth != 8 && depth != 16))
    return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (colour type %u, bit depth %u)", name, colour, depth);
  if (w > INT32_MAX || h > INT32_MAX) w = h = JND_MAX_SIDE + 1u;
  jnd_status s = jnd_check_size((int)w, (int)h, 1, name);
  if (s != JND_OK) return s;
  double row = 1 + ceil((double)w * samples[colour] * depth / 8);
  if (row * h > 1040.0 * (double)idat_bytes + 1024)
    return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (%u × %u pixels cannot come from %zu bytes of image data)",
                    name, (unsigned)w, (unsigned)h, idat_bytes);
  return JND_OK;
}

jnd_status jnd_png_validate(const char *name, const unsigned char *buf, size_t n) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n < 8 || memcmp(buf, sig, 8) != 0) return jnd_fail(JND_ERR_FORMAT, "%s: not a PNG file", name);
  size_t pos = 8, idat_bytes = 0;
  int chunk = 0, seen_idat = 0;
  uint32_t w = 0, h = 0;
  unsigned depth = 0, colour = 0;
  while (pos < n) {
    if (n - pos < 12) return jnd_fail(JND_ERR_FORMAT, "%s: truncated PNG (chunk header cut off)", name);
    uint32_t len = be32(buf + pos);
    const unsigned char *type = buf + pos + 4;
    if (len > 0x7fffffffu || len > n - pos - 12)
      return jnd_fail(JND_ERR_FORMAT, "%s: truncated PNG (chunk %.4s runs past the end)", name, type);
    uint32_t want = be32(buf + pos + 8 + len);
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION /* lets the fuzzer past the CRCs, into the decoder */
    if (jnd_crc32(type, (size_t)len + 4) != want)
      return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (bad CRC in chunk %.4s)", name, type);
#else
    (void)want;
#endif
    if (chunk == 0 && memcmp(type, "IHDR", 4) != 0)
      return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (first chunk is not IHDR)", name);
    if (chunk == 0) {
      if (len != 13) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (IHDR is %u bytes, not 13)", name, (unsigned)len);
      w = be32(type + 4);
      h = be32(type + 8);
      depth = type[12];
      colour = type[13];
    }
    if (memcmp(type, "IDAT", 4) == 0) {
      seen_idat = 1;
      idat_bytes += len;
    }
    pos += (size_t)len + 12;
    chunk++;
    if (memcmp(type, "IEND", 4) == 0) {
      if (!seen_idat) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (no image data)", name);
      return png_check_size(name, w, h, depth, colour, idat_bytes);
    }
  }
  return jnd_fail(JND_ERR_FORMAT, "%s: truncated PNG (no IEND chunk)", name);
}

static void put32(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)(v >> 24);
  p[1] = (unsigned char)(v >> 16);
  p[2] = (unsigned char)(v >> 8);
  p[3] = (unsigned char)v;
}

/* Appends one chunk (length, type, data, CRC) at out + *pos. */
static void put_chunk(unsigned char *out, size_t *pos, const char *type, const unsigned char *data,
                      uint32_t len) {
  put32(out + *pos, len);
  memcpy(out + *pos + 4, type, 4);
  if (len) memcpy(out + *pos + 8, data, len);
  put32(out + *pos + 8 + len, jnd_crc32(out + *pos + 4, (size_t)len + 4));
  *pos += (size_t)len + 12;
}

jnd_status jnd_image_write_png(const char *path, const jnd_image *img, int bits) {
  if (bits != 8 && bits != 16) return jnd_fail(JND_ERR_ARG, "%s: PNG bit depth must be 8 or 16", path);
  if (img->c < 1 || img->c > 4) return jnd_fail(JND_ERR_ARG, "%s: PNG needs 1–4 channels, not %d", path, img->c);
  jnd_status s = jnd_check_size(img->w, img->h, img->c, path);
  if (s != JND_OK) return s;
  size_t bpp = (size_t)img->c * (bits / 8), row = 1 + (size_t)img->w * bpp;
  size_t raw_n = row * img->h;
  unsigned char *raw = jnd_alloc(raw_n, 1);
  if (!raw) return JND_ERR_NOMEM;
  for (int y = 0; y < img->h; y++) {
    unsigned char *r = raw + row * y;
    r[0] = 0; /* filter: none */
    for (int x = 0; x < img->w; x++) {
      for (int ch = 0; ch < img->c; ch++) {
        double v = jnd_clampd(jnd_image_plane(img, ch)[(size_t)y * img->w + x], 0.0, 1.0);
        if (bits == 8) {
          r[1 + (size_t)x * bpp + ch] = (unsigned char)(v * 255.0 + 0.5);
        } else {
          unsigned q = (unsigned)(v * 65535.0 + 0.5);
          r[1 + (size_t)x * bpp + 2 * ch] = (unsigned char)(q >> 8);
          r[1 + (size_t)x * bpp + 2 * ch + 1] = (unsigned char)q;
        }
      }
    }
  }
  uLongf zn = compressBound((uLong)raw_n);
  unsigned char *z = jnd_alloc(zn, 1);
  if (!z) {
    free(raw);
    return JND_ERR_NOMEM;
  }
  if (compress2(z, &zn, raw, (uLong)raw_n, 6) != Z_OK) {
    free(raw);
    free(z);
    return jnd_fail(JND_ERR_INTERNAL, "%s: zlib failed", path);
  }
  free(raw);
  size_t total = 8 + 25 + 12 + zn + 12;
  unsigned char *out = jnd_alloc(total, 1);
  if (!out) {
    free(z);
    return JND_ERR_NOMEM;
  }
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static const unsigned char colour_type[5] = {0, 0, 4, 2, 6};
  memcpy(out, sig, 8);
  size_t pos = 8;
  unsigned char ihdr[13];
  put32(ihdr, (uint32_t)img->w);
  put32(ihdr + 4, (uint32_t)img->h);
  ihdr[8] = (unsigned char)bits;
  ihdr[9] = colour_type[img->c];
  ihdr[10] = ihdr[11] = ihdr[12] = 0;
  put_chunk(out, &pos, "IHDR", ihdr, 13);
  put_chunk(out, &pos, "IDAT", z, (uint32_t)zn);
  put_chunk(out, &pos, "IEND", NULL, 0);
  free(z);
  s = jnd_write_file_atomic(path, out, pos);
  free(out);
  return s;
}
