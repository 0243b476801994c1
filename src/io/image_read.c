/* Image files in: the format is told by the file's first bytes, not its name.
 * PNG goes through png.c's decoder (zlib) where it can, else, like JPEG and
 * Radiance HDR, through stb_image; OpenEXR through the OpenEXR core C API
 * (exr.c). Every decoder refuses sizes over the limits and non-finite
 * samples, and names the file in its one-line error. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "core/core.h"
#include "io/io.h"

#define MAX_FILE_BYTES ((size_t)2 << 30)

jnd_status jnd_image_check_finite(const char *name, const jnd_image *img) {
  size_t n = (size_t)img->w * img->h * img->c;
  size_t i = jnd_first_outside(img->data, n, -FLT_MAX, FLT_MAX);
  if (i < n) {
    size_t px = i % ((size_t)img->w * img->h);
    return jnd_fail(JND_ERR_FORMAT, "%s: pixel (%zu, %zu) channel %zu is %s", name, px % img->w, px / img->w,
                    i / ((size_t)img->w * img->h), isnan(img->data[i]) ? "NaN" : "infinite");
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

/* ---- checks stb_image (v2.27) leaves to the caller ---- */

/* stb_image decodes with Huffman and quantisation tables that were never
 * defined (uninitialised memory; an assertion aborts the process), so every
 * table a frame or scan uses must have been defined before it. Walks the
 * markers up to the end of the image. */
static jnd_status jpeg_check_tables(const char *name, const unsigned char *buf, size_t n) {
  int dqt = 0, dc = 0, ac = 0, progressive = 0, frame = 0, quant_used = 0;
  unsigned char comp_id[4];
  int ncomp = 0;
  size_t p = 2;
  for (;;) {
    while (p < n && buf[p] != 0xFF) p++; /* entropy-coded data between markers */
    while (p < n && buf[p] == 0xFF) p++;
    if (p >= n) return jnd_fail(JND_ERR_FORMAT, "%s: truncated JPEG", name);
    unsigned m = buf[p++];
    if (m == 0x00 || (m >= 0xD0 && m <= 0xD7) || m == 0x01) continue; /* stuffing, RSTn, TEM */
    if (m == 0xD9) return frame ? JND_OK : jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (no frame header)", name);
    if (m == 0xD8) continue;
    if (n - p < 2) return jnd_fail(JND_ERR_FORMAT, "%s: truncated JPEG", name);
    size_t len = (size_t)buf[p] << 8 | buf[p + 1];
    if (len < 2 || len > n - p) return jnd_fail(JND_ERR_FORMAT, "%s: truncated JPEG (segment runs past the end)", name);
    const unsigned char *seg = buf + p + 2, *end = buf + p + len;
    if (m == 0xDB) {
      while (seg < end) {
        int tq = seg[0] & 15, bytes = (seg[0] >> 4) ? 128 : 64;
        if (tq > 3 || end - seg < 1 + bytes) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad quantisation table)", name);
        dqt |= 1 << tq;
        seg += 1 + bytes;
      }
    } else if (m == 0xC4) {
      while (seg < end) {
        int tc = seg[0] >> 4, th = seg[0] & 15, count = 0;
        if (tc > 1 || th > 3 || end - seg < 17) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad Huffman table)", name);
        for (int i = 1; i <= 16; i++) count += seg[i];
        if (count > 256 || end - seg < 17 + count)
          return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad Huffman table)", name);
        if (tc) ac |= 1 << th;
        else dc |= 1 << th;
        seg += 17 + count;
      }
    } else if (m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC) {
      if (frame) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (two frame headers)", name);
      frame = 1;
      progressive = m == 0xC2;
      if (len < 8) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (short frame header)", name);
      ncomp = seg[5];
      if ((ncomp != 1 && ncomp != 3 && ncomp != 4) || len < 8 + 3 * (size_t)ncomp)
        return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad frame header)", name);
      for (int i = 0; i < ncomp; i++) {
        comp_id[i] = seg[6 + 3 * i];
        quant_used |= 1 << (seg[6 + 3 * i + 2] & 3);
        if (seg[6 + 3 * i + 2] > 3) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad frame header)", name);
      }
    } else if (m == 0xDA) {
      if (!frame) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (scan before the frame header)", name);
      if ((quant_used & dqt) != quant_used)
        return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (quantisation table used but not defined)", name);
      int ns = len >= 3 ? seg[0] : 0;
      if (ns < 1 || ns > 4 || len < 6 + 2 * (size_t)ns) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad scan header)", name);
      int ss = seg[1 + 2 * ns];
      for (int i = 0; i < ns; i++) {
        int id = seg[1 + 2 * i], td = seg[2 + 2 * i] >> 4, ta = seg[2 + 2 * i] & 15, known = 0;
        for (int k = 0; k < ncomp; k++) known |= comp_id[k] == id;
        if (!known || td > 3 || ta > 3) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (bad scan header)", name);
        int need_dc = !progressive || ss == 0, need_ac = !progressive || ss != 0;
        if ((need_dc && !(dc >> td & 1)) || (need_ac && !(ac >> ta & 1)))
          return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG (Huffman table used but not defined)", name);
      }
    }
    p += len;
  }
}

/* stb_image loops for ever on a run-length scanline whose data ends early
 * (and on a zero-length literal run), so the runs are walked here first: the
 * data must hold every pixel the header promises. */
static jnd_status hdr_check_runs(const char *name, const unsigned char *buf, size_t n, int w, int h) {
  /* header: the magic line, lines up to an empty one (for stb, one that is
   * empty or starts with a NUL), then the resolution line */
  size_t p = 0, line_start = 0;
  int seen_empty = 0;
  for (;;) {
    if (p >= n) return jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR header", name);
    if (buf[p++] != '\n') continue;
    if (seen_empty) break; /* the end of the resolution line */
    if (line_start > 0 && (p - 1 == line_start || buf[line_start] == 0)) seen_empty = 1;
    line_start = p;
  }
  size_t left = n - p, need = (size_t)w * h * 4;
  const unsigned char *d = buf + p;
  if (w < 8 || w >= 32768) /* flat pixels */
    return left >= need ? JND_OK : jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR", name);
  size_t q = 0;
  for (int y = 0; y < h; y++) {
    if (left - q < 4) return jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR", name);
    if (d[q] != 2 || d[q + 1] != 2 || (d[q + 2] & 0x80)) /* flat from here on, restarting at pixel 0 */
      return left - q >= need ? JND_OK : jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR", name);
    if (((int)d[q + 2] << 8 | d[q + 3]) != w) return JND_OK; /* stb refuses it */
    q += 4;
    for (int k = 0; k < 4; k++) {
      for (int x = 0; x < w;) {
        if (q >= left) return jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR", name);
        int count = d[q++];
        if (count > 128) {
          if (q >= left) return jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR", name);
          q++;
          count -= 128;
        } else {
          if (count == 0) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt Radiance HDR (empty run)", name);
          if ((size_t)count > left - q) return jnd_fail(JND_ERR_FORMAT, "%s: truncated Radiance HDR", name);
          q += (size_t)count;
        }
        if (count > w - x) return JND_OK; /* stb refuses it */
        x += count;
      }
    }
  }
  return JND_OK;
}

void jnd_image_info_set(jnd_image_info *info, const char *format, jnd_encoding enc, int bits, int channels,
                        int has_alpha) {
  if (!info) return;
  memset(info, 0, sizeof *info);
  info->encoding = enc;
  info->bits = bits;
  info->channels = channels;
  info->has_alpha = has_alpha;
  snprintf(info->format, sizeof info->format, "%s", format);
}

static void png_info(jnd_image_info *info, int bits, int c) {
  jnd_image_info_set(info, "png", JND_ENCODING_SRGB, bits, c, c == 2 || c == 4);
}

/* A PNG that jnd_png_validate has passed, through stb_image. */
static jnd_status png_decode_stb(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                                 jnd_image_info *info) {
  int w, h, c;
  /* jnd_png_validate has bounded the size by the compressed data */
  jnd_status s = stb_header(name, buf, n, 1e12, &w, &h, &c);
  if (s != JND_OK) return s;
  int bits = stbi_is_16_bit_from_memory(buf, (int)n) ? 16 : 8;
  void *px = bits == 16 ? (void *)stbi_load_16_from_memory(buf, (int)n, &w, &h, &c, 0)
                        : (void *)stbi_load_from_memory(buf, (int)n, &w, &h, &c, 0);
  if (!px) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG: %s", name, stbi_failure_reason());
  s = planar_from_interleaved(name, px, bits, w, h, c, bits == 16 ? 1.0 / 65535 : 1.0 / 255, out);
  stbi_image_free(px);
  if (s != JND_OK) return s;
  png_info(info, bits, c);
  return JND_OK;
}

jnd_status jnd_decode_png_stb(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                              jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  jnd_status s = jnd_png_validate(name, buf, n);
  return s != JND_OK ? s : png_decode_stb(name, buf, n, out, info);
}

/* a PNG that jnd_png_validate has passed */
static jnd_status decode_valid_png(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                                   jnd_image_info *info) {
  /* zlib's inflate where it can: a 1920 × 1080 RGB file in 39 ms instead of 62 */
  if (!jnd_png_plain(buf, n)) return png_decode_stb(name, buf, n, out, info);
  int bits;
  jnd_status s;
  if ((s = jnd_png_decode(name, buf, n, out, &bits)) != JND_OK) return s;
  png_info(info, bits, out->c);
  return JND_OK;
}

static jnd_status decode_png(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                             jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  jnd_status s = jnd_png_validate(name, buf, n);
  return s != JND_OK ? s : decode_valid_png(name, buf, n, out, info);
}

jnd_status jnd_decode_png(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                          jnd_image_info *info) {
  return decode_png(name, buf, n, out, info);
}

jnd_status jnd_decode_jpeg(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                           jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  /* stb_image guesses the format; only a JPEG may reach its decoder from here */
  if (n < 3 || buf[0] != 0xFF || buf[1] != 0xD8 || buf[2] != 0xFF)
    return jnd_fail(JND_ERR_FORMAT, "%s: not a JPEG file", name);
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
  if ((s = jpeg_check_tables(name, buf, n)) != JND_OK) return s;
  unsigned char *px = stbi_load_from_memory(buf, (int)n, &w, &h, &c, 0);
  if (!px) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt JPEG: %s", name, stbi_failure_reason());
  s = planar_from_interleaved(name, px, 8, w, h, c, 1.0 / 255, out);
  stbi_image_free(px);
  if (s != JND_OK) return s;
  jnd_image_info_set(info, "jpeg", JND_ENCODING_SRGB, 8, c, 0);
  return JND_OK;
}

jnd_status jnd_decode_hdr(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                          jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  /* stb_image guesses the format (a "#?" file could pass for a TGA); only a
   * Radiance file may reach its decoder from here */
  if (!(n >= 11 && memcmp(buf, "#?RADIANCE\n", 11) == 0) && !(n >= 7 && memcmp(buf, "#?RGBE\n", 7) == 0))
    return jnd_fail(JND_ERR_FORMAT, "%s: not a Radiance HDR file", name);
  int w, h, c;
  /* run-length scanlines spend at least 2 bytes on 127 values of a component */
  jnd_status s = stb_header(name, buf, n, 64, &w, &h, &c);
  if (s != JND_OK) return s;
  if ((s = hdr_check_runs(name, buf, n, w, h)) != JND_OK) return s;
  float *px = stbi_loadf_from_memory(buf, (int)n, &w, &h, &c, 3);
  if (!px) return jnd_fail(JND_ERR_FORMAT, "%s: corrupt Radiance HDR: %s", name, stbi_failure_reason());
  s = planar_from_interleaved(name, px, 32, w, h, 3, 1.0, out);
  stbi_image_free(px);
  if (s != JND_OK) return s;
  if ((s = jnd_image_check_finite(name, out)) != JND_OK) {
    jnd_image_free(out);
    return s;
  }
  jnd_image_info_set(info, "hdr", JND_ENCODING_LINEAR, 32, 3, 0);
  return JND_OK;
}

static jnd_status image_read(const char *path, jnd_image *out, jnd_image_info *info, unsigned char **rgb) {
  memset(out, 0, sizeof *out);
  if (rgb) *rgb = NULL;
  unsigned char *buf;
  size_t n;
  jnd_status s = jnd_read_file(path, MAX_FILE_BYTES, &buf, &n);
  if (s != JND_OK) return s;
  static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n == 0) {
    s = jnd_fail(JND_ERR_FORMAT, "%s: empty file", path);
  } else if (n >= 8 && memcmp(buf, png_sig, 8) == 0) {
    /* validated once, whichever decoder then reads it */
    s = jnd_png_validate(path, buf, n);
    if (s == JND_OK && rgb && jnd_png_is_rgb8(buf, n)) {
      int w, h;
      if ((s = jnd_png_decode_rgb8(path, buf, n, rgb, &w, &h)) == JND_OK) {
        out->w = w;
        out->h = h;
        out->c = 3;
        png_info(info, 8, 3);
      }
    } else if (s == JND_OK) {
      s = decode_valid_png(path, buf, n, out, info);
    }
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

jnd_status jnd_image_read(const char *path, jnd_image *out, jnd_image_info *info) {
  return image_read(path, out, info, NULL);
}

jnd_status jnd_image_read_rgb8(const char *path, jnd_image *out, jnd_image_info *info, unsigned char **rgb) {
  return image_read(path, out, info, rgb);
}
