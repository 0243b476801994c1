/* PNG: chunk validation on read (stb_image skips CRCs), a decoder for the
 * common layouts that inflates the image data with libdeflate in one call
 * (twice zlib's speed; stb_image's own inflate takes four times as long),
 * with zlib's streaming inflate for the files that are not exactly their
 * rows (data past the last row, a short or corrupt stream: it decodes or
 * reports them), straight into planar floats, and a writer for 8- and
 * 16-bit images (stb_image_write only writes 8-bit), filtered and deflated by
 * zlib in parallel pieces. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <libdeflate.h>
#include <stb/stb_image_write.h>
#include <zlib.h>

#include "core/core.h"
#include "io/io.h"

/* PNG's CRC-32 (ISO 3309, the one zlib and gzip use) by libdeflate, which
 * folds with carry-less multiplies: zlib 1.2.13's table-driven one was 1.7%
 * of a 1080p diff's time for the chunks' checks */
uint32_t jnd_crc32(const unsigned char *buf, size_t n) { return libdeflate_crc32(0, buf, n); }

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

/* ---- decoding (PNG spec §7–§10), for the layouts jnd_png_plain accepts ---- */

/* One chunk (PNG spec §5.3: length, type, data, CRC) of a file that
 * jnd_png_validate has passed. */
typedef struct {
  uint32_t len;
  const unsigned char *type, *data;
} png_chunk;

/* The chunk at *pos, moving *pos past it; 0 at IEND or where none fits. */
static int png_next_chunk(const unsigned char *buf, size_t n, size_t *pos, png_chunk *c) {
  if (*pos > n || n - *pos < 12) return 0;
  uint32_t len = be32(buf + *pos);
  if (len > n - *pos - 12) return 0;
  c->len = len;
  c->type = buf + *pos + 4;
  c->data = buf + *pos + 8;
  *pos += (size_t)len + 12;
  return memcmp(c->type, "IEND", 4) != 0;
}

static int png_chunk_is(const png_chunk *c, const char *type) { return memcmp(c->type, type, 4) == 0; }

/* Samples per pixel of colour types 0 (grey), 2 (RGB), 4 (grey + alpha) and
 * 6 (RGBA); 0 for the rest (PNG spec §11.2.2, Table 11.1). */
static unsigned png_plain_channels(unsigned colour) {
  static const unsigned channels[7] = {1, 0, 3, 0, 2, 0, 4};
  return colour <= 6 ? channels[colour] : 0;
}

/* The samples per pixel of an IHDR's data (§11.2.2) that png_decode reads:
 * bit depth 8 or 16, colour type 0, 2, 4 or 6, compression, filter and
 * interlace methods 0; 0 for any other layout. */
static unsigned png_plain_layout(const unsigned char *ihdr) {
  unsigned depth = ihdr[8];
  if ((depth != 8 && depth != 16) || ihdr[10] || ihdr[11] || ihdr[12]) return 0;
  return png_plain_channels(ihdr[9]);
}

int jnd_png_plain(const unsigned char *buf, size_t n) {
  size_t pos = 8;
  png_chunk c;
  int ihdr = 0;
  while (png_next_chunk(buf, n, &pos, &c)) {
    if (png_chunk_is(&c, "IHDR")) {
      if (ihdr++ || c.len != 13 || !png_plain_layout(c.data)) return 0;
    } else if (png_chunk_is(&c, "PLTE")) {
      if (c.len % 3 || c.len > 3 * 256) return 0; /* stb_image refuses it */
    } else if (png_chunk_is(&c, "tRNS")) {
      return 0; /* stb_image adds an alpha channel from the key colour */
    } else if (!png_chunk_is(&c, "IDAT") && !(c.type[0] & 0x20)) {
      return 0; /* an unknown critical chunk (§5.4), Apple's CgBI among them */
    }
  }
  return ihdr;
}

/* x · y, or 0 when it overflows size_t. */
static int png_mul(size_t x, size_t y, size_t *r) {
  if (y && x > SIZE_MAX / y) return 0;
  *r = x * y;
  return 1;
}

/* The Paeth predictor of PNG spec §9.4: whichever of left (a), up (b) and
 * up-left (c) is closest to a + b − c, ties going to a, then b. */
static unsigned png_paeth(unsigned a, unsigned b, unsigned c) {
  int p = (int)(a + b) - (int)c;
  unsigned pa = (unsigned)abs(p - (int)a), pb = (unsigned)abs(p - (int)b), pc = (unsigned)abs(p - (int)c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* Rows whose pixels are 3 or 4 bytes (8-bit RGB and RGBA, 16-bit grey and
 * alpha) are unfiltered PNG_WAVE at a time, as a wavefront. Each row's
 * pixels wait on each other (Sub, Average and Paeth predict from the pixel
 * to the left), so a row at a time goes at the pace of one pixel's
 * arithmetic; the group's rows share that pace: the lanes of one vector of
 * shorts hold a pixel's bytes of each row (4 × 4), and each row's filter
 * type selects its predictor by masks. At step s, row g undoes its pixel
 * s − PNG_LAG·g: its left neighbour is its own pixel of the step before,
 * its upper and upper-left ones row g − 1's of PNG_LAG and PNG_LAG + 1
 * steps before (row 0's: the row above the group). With a lag of 2, moving
 * the upper neighbours across the vector is off the chain of steps, which
 * runs through the left neighbour alone. Loads and stores move 4 bytes, so
 * rows are read and written with PNG_SLACK bytes after them. */
enum { PNG_WAVE = 4, PNG_LAG = 2, PNG_SLACK = 16 };
typedef short png_w16 __attribute__((vector_size(32)));       /* shorts: 4 rows × 4 bytes */
typedef unsigned char png_wb __attribute__((vector_size(16))); /* the same bytes */
typedef uint32_t png_w32 __attribute__((vector_size(16)));      /* the same, a row's pixel a lane */

/* (32-byte vectors go to the helpers by address: passed by value they
 * would change the baseline clone's calling convention, GCC's -Wpsabi) */
typedef struct {
  const unsigned char *in[PNG_WAVE], *above; /* filtered rows; the unfiltered row above in[0] */
  unsigned char *out[PNG_WAVE];              /* unfiltered rows */
  size_t w, bpp;
  png_w16 m[5];        /* m[t]: the lanes of the rows of filter type t */
  png_w16 all;         /* 0xff in every byte of the group's rows, 0 in the rest */
  png_w16 r[PNG_LAG];  /* each row's pixels of the last PNG_LAG steps, r[0] the last */
  png_w16 up;          /* the upper neighbours of the last step */
} png_wave;

/* |x| of every lane (none is −32768) */
#define PNG_WAVE_ABS(x) (((x) ^ ((x) >> 15)) - ((x) >> 15))

/* The predictor of each lane's row (PNG spec §9.2) from the unfiltered
 * neighbours a (left), up and c (upper left). Paeth (§9.4) as
 * pa = |up − c|, pb = |a − c|, pc = |a + up − 2c|: left (a) on ties, then
 * up; with no pixel to the left (a = c = 0) it predicts up. */
static inline __attribute__((always_inline)) void png_wave_predict(const png_wave *W, const png_w16 *upper,
                                                                   png_w16 *pred) {
  const png_w16 a = W->r[0], up = *upper, c = W->up;
  png_w16 da = up - c, db = a - c, dc = da + db;
  png_w16 pa = PNG_WAVE_ABS(da), pb = PNG_WAVE_ABS(db), pc = PNG_WAVE_ABS(dc);
  png_w16 ma = (pa <= pb) & (pa <= pc), mb = pb <= pc; /* lanes of all ones where true */
  png_w16 paeth = (a & ma) | (((up & mb) | (c & ~mb)) & ~ma);
  *pred = (a & W->m[1]) | (up & W->m[2]) | (((a + up) >> 1) & W->m[3]) | (paeth & W->m[4]);
}

/* Step s: each row g whose bit is set in `act` undoes its pixel
 * s − PNG_LAG·g; lanes: 0xff in the bytes of those pixels, 0 elsewhere (a
 * row not yet begun holds zeros, its pixel −1's neighbours). */
static inline __attribute__((always_inline)) void png_wave_step(png_wave *W, const png_w16 *lanes, unsigned act,
                                                                size_t s) {
  uint32_t x[PNG_WAVE] = {0}, u = 0;
  for (size_t g = 0; g < PNG_WAVE; g++)
    if (act >> g & 1) memcpy(&x[g], W->in[g] + (s - PNG_LAG * g) * W->bpp, 4);
  if (act & 1) memcpy(&u, W->above + s * W->bpp, 4);
  png_w32 xv = {x[0], x[1], x[2], x[3]}, uv = {u, 0, 0, 0};
  png_w16 v = __builtin_convertvector((png_wb)xv, png_w16), ua = __builtin_convertvector((png_wb)uv, png_w16);
  /* row g's upper neighbour: row g − 1's pixel of PNG_LAG steps before */
  png_w16 up = __builtin_shufflevector(W->r[PNG_LAG - 1], ua, 16, 17, 18, 19, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11),
          pred;
  png_wave_predict(W, &up, &pred);
  for (int k = PNG_LAG - 1; k > 0; k--) W->r[k] = W->r[k - 1];
  W->r[0] = (v + pred) & *lanes;
  W->up = up;
  png_wb rb = __builtin_convertvector(W->r[0], png_wb);
  uint32_t y[PNG_WAVE];
  memcpy(y, &rb, sizeof y);
  for (size_t g = 0; g < PNG_WAVE; g++)
    if (act >> g & 1) memcpy(W->out[g] + (s - PNG_LAG * g) * W->bpp, &y[g], 4);
}

/* A step where some rows have not begun or have ended. */
static inline __attribute__((always_inline)) void png_wave_edge(png_wave *W, size_t s) {
  unsigned act = 0;
  png_w16 lanes = W->all;
  for (size_t g = 0; g < PNG_WAVE; g++) {
    const short on = s >= PNG_LAG * g && s - PNG_LAG * g < W->w;
    act |= (unsigned)on << g;
    for (size_t l = 4 * g; l < 4 * g + 4; l++) lanes[l] &= (short)-on;
  }
  png_wave_step(W, &lanes, act, s);
}

/* PNG_WAVE rows of w pixels of bpp (3 or 4) bytes: in[g] filtered with
 * filter[g] (0–4), unfiltered into out[g]; above: the unfiltered row above
 * in[0] (zeros above the first). A group with fewer rows left in the image
 * passes keep[g] = 0 for the others, and any row of PNG_SLACK readable bytes
 * beyond w · bpp as their in[g] and out[g]: they come out zeros. */
JND_HOT static void png_unfilter_wave(const unsigned char *const in[PNG_WAVE], unsigned char *const out[PNG_WAVE],
                                      const unsigned char *above, const unsigned filter[PNG_WAVE],
                                      const int keep[PNG_WAVE], size_t w, size_t bpp) {
  /* the rows' addresses in a local where no store through them can reach:
   * the compiler would reload them after each store otherwise */
  png_wave W;
  memset(&W, 0, sizeof W);
  memcpy(W.in, in, sizeof W.in);
  memcpy(W.out, out, sizeof W.out);
  W.above = above;
  W.w = w;
  W.bpp = bpp;
  for (int l = 0; l < 4 * PNG_WAVE; l++) {
    const int g = l / 4, byte = (size_t)(l % 4) < bpp && keep[g];
    for (unsigned t = 0; t < 5; t++) W.m[t][l] = (short)(byte && filter[g] == t ? -1 : 0);
    W.all[l] = (short)(byte ? 0xff : 0);
  }
  const size_t lead = PNG_LAG * (PNG_WAVE - 1); /* the steps of the last row's start */
  size_t s = 0;
  for (; s < lead; s++) png_wave_edge(&W, s);
  for (; s < w; s++) png_wave_step(&W, &W.all, (1u << PNG_WAVE) - 1, s);
  for (; s < w + lead; s++) png_wave_edge(&W, s);
}

/* Undoes one row's filter in place (PNG spec §9.2, filter method 0): x is
 * the row, b the row above once unfiltered (zeros above the first row), bpp
 * the bytes of a complete pixel, the distance to the byte "to the left". */
JND_HOT static void png_unfilter(unsigned filter, unsigned char *x, const unsigned char *b, size_t len, size_t bpp) {
  size_t i;
  switch (filter) {
  case 1: /* Sub */
    for (i = bpp; i < len; i++) x[i] = (unsigned char)(x[i] + x[i - bpp]);
    break;
  case 2: /* Up */
    for (i = 0; i < len; i++) x[i] = (unsigned char)(x[i] + b[i]);
    break;
  case 3: /* Average, of left and up without overflow (§9.3) */
    for (i = 0; i < bpp; i++) x[i] = (unsigned char)(x[i] + (b[i] >> 1));
    for (; i < len; i++) x[i] = (unsigned char)(x[i] + ((x[i - bpp] + b[i]) >> 1));
    break;
  case 4: /* Paeth; with no pixel to the left it predicts up */
    for (i = 0; i < bpp; i++) x[i] = (unsigned char)(x[i] + b[i]);
    for (; i < len; i++) x[i] = (unsigned char)(x[i] + png_paeth(x[i - bpp], b[i], b[i - bpp]));
    break;
  default: /* None */
    break;
  }
}

/* Rows inflate this many bytes at a time (at least a row): zlib's fast loop
 * stops 258 bytes short of the end of its output, so one row at a time costs
 * about a tenth more, and a block this size still sits in the cache. */
#define PNG_BLOCK_BYTES ((size_t)64 << 10)

/* The decoder's state: the zlib stream, the IDAT chunk it reads, a block
 * of rows inflated but not yet used, and the unfiltered rows. */
typedef struct {
  const char *name;
  const unsigned char *buf;
  size_t n, pos; /* pos: the chunk after the one zlib reads */
  z_stream z;
  unsigned depth;
  size_t bpp, row, stride; /* stride = 1 + row: the filter type byte first */
  unsigned char *rows;     /* block × stride, and PNG_SLACK */
  size_t block;
  /* PNG_WAVE + 2 rows of pitch bytes: the last row unfiltered (zeros above
   * the first, PNG spec §9.2), a group's rows, a row for a short group's
   * missing ones */
  unsigned char *bank;
  size_t pitch;
  float to_float[256]; /* 8-bit samples as floats */
  unsigned char *codes; /* jnd_png_decode_rgb8: the unfiltered rows go here, row bytes apart, not to
                           planes (out has no data) */
} png_decoder;

/* Row y of interleaved samples (16-bit ones big-endian, PNG spec §7.1) into
 * the planes of out, scaled as image_read.c scales stb_image's samples, so
 * that both paths give the same floats. */
static inline __attribute__((always_inline)) void png_bytes_to_planes(const float to_float[256],
                                                                      const unsigned char *row, float *const dst[4],
                                                                      size_t w, size_t c) {
  for (size_t x = 0; x < w; x++)
    for (size_t ch = 0; ch < c; ch++) dst[ch][x] = to_float[row[x * c + ch]];
}

/* RGB: no plane overlaps the row or the table (restrict), so the row's
 * bytes need not be read again after each store */
JND_HOT_AVX2 static void png_rgb_to_planes(const float *restrict to_float, const unsigned char *restrict row,
                                      float *restrict r, float *restrict g, float *restrict b, size_t w) {
  for (size_t x = 0; x < w; x++) {
    r[x] = to_float[row[3 * x]];
    g[x] = to_float[row[3 * x + 1]];
    b[x] = to_float[row[3 * x + 2]];
  }
}

static void png_row_to_planes(const png_decoder *d, const unsigned char *row, size_t y, jnd_image *out) {
  size_t w = (size_t)out->w, c = (size_t)out->c;
  if (d->codes) {
    memcpy(d->codes + y * d->row, row, d->row); /* row: the bank's, never the codes' */
    return;
  }
  if (d->depth == 8) {
    /* one pass along the row writing every plane, with the channel count a
     * constant for RGB and RGBA (a pass per plane, or a loop over the
     * channels of each pixel, costs a fifth more) */
    float *dst[4];
    for (size_t ch = 0; ch < c; ch++) dst[ch] = jnd_image_plane(out, (int)ch) + y * w;
    if (c == 3)
      png_rgb_to_planes(d->to_float, row, dst[0], dst[1], dst[2], w);
    else if (c == 4)
      png_bytes_to_planes(d->to_float, row, dst, w, 4);
    else
      png_bytes_to_planes(d->to_float, row, dst, w, c);
    return;
  }
  const double scale = 1.0 / 65535;
  for (size_t ch = 0; ch < c; ch++) {
    float *dst = jnd_image_plane(out, (int)ch) + y * w;
    for (size_t x = 0; x < w; x++) {
      const unsigned char *p = row + 2 * (x * c + ch);
      dst[x] = (float)((p[0] << 8 | p[1]) * scale);
    }
  }
}

/* The n (1 to PNG_WAVE) rows at filtered, stride bytes apart (each its
 * filter type, then its bytes; PNG_SLACK readable bytes after the last),
 * rows y… of the image: unfiltered against the bank's last row into the
 * bank (PNG spec §7.3, §9), written out, the last of them kept as the next
 * group's row above. 0, or the row (from 1) of the first unknown filter
 * type. */
static size_t png_unfilter_group(png_decoder *d, const unsigned char *filtered, size_t stride, size_t n, size_t y,
                                 jnd_image *out) {
  for (size_t g = 0; g < n; g++)
    if (filtered[g * stride] > 4) return y + g + 1;
  unsigned char *above = d->bank, *spare = d->bank + (PNG_WAVE + 1) * d->pitch;
  if (d->bpp == 3 || d->bpp == 4) {
    const unsigned char *in[PNG_WAVE];
    unsigned char *rows[PNG_WAVE];
    unsigned filter[PNG_WAVE];
    int keep[PNG_WAVE];
    for (size_t g = 0; g < PNG_WAVE; g++) {
      keep[g] = g < n;
      in[g] = keep[g] ? filtered + g * stride + 1 : spare;
      rows[g] = keep[g] ? d->bank + (g + 1) * d->pitch : spare;
      filter[g] = keep[g] ? filtered[g * stride] : 0;
    }
    png_unfilter_wave(in, rows, above, filter, keep, (size_t)out->w, d->bpp);
  } else {
    for (size_t g = 0; g < n; g++) {
      unsigned char *x = d->bank + (g + 1) * d->pitch;
      memcpy(x, filtered + g * stride + 1, d->row);
      png_unfilter(filtered[g * stride], x, x - d->pitch, d->row, d->bpp);
    }
  }
  for (size_t g = 0; g < n; g++) png_row_to_planes(d, d->bank + (g + 1) * d->pitch, y + g, out);
  memcpy(above, d->bank + n * d->pitch, d->row);
  return 0;
}

/* Inflates the next len bytes of the image data into out (PNG spec §10: the
 * zlib stream is the IDAT chunks' data joined in order), fetching IDAT
 * chunks as the stream needs them; y, h: the rows, for the messages. */
static jnd_status png_inflate(png_decoder *d, unsigned char *out, size_t len, size_t y, size_t h) {
  z_stream *z = &d->z;
  z->next_out = out;
  z->avail_out = (uInt)len;
  while (z->avail_out) {
    size_t at = y + 1 + (len - z->avail_out) / d->stride;
    if (!z->avail_in) {
      png_chunk c;
      int more;
      while ((more = png_next_chunk(d->buf, d->n, &d->pos, &c)) && !png_chunk_is(&c, "IDAT")) {}
      if (!more)
        return jnd_fail(JND_ERR_FORMAT, "%s: truncated PNG (image data ends in row %zu of %zu)", d->name, at, h);
      z->next_in = (unsigned char *)c.data; /* zlib's API is not const; it only reads */
      z->avail_in = c.len;
      continue;
    }
    int r = inflate(z, Z_NO_FLUSH);
    if (r == Z_STREAM_END && z->avail_out)
      return jnd_fail(JND_ERR_FORMAT, "%s: truncated PNG (deflate stream ends in row %zu of %zu)", d->name, at, h);
    if (r == Z_MEM_ERROR) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory for zlib", d->name);
    if (r == Z_NEED_DICT) /* PNG spec §10.1 forbids a preset dictionary */
      return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (deflate stream asks for a preset dictionary)", d->name);
    if (r != Z_OK && r != Z_STREAM_END)
      return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (%s in row %zu)", d->name,
                      z->msg ? z->msg : "bad deflate data", at);
  }
  return JND_OK;
}

/* A bad filter type's message: row counts from 1. */
static jnd_status png_bad_filter(const png_decoder *d, size_t row, unsigned type) {
  return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (row %zu has filter type %u, not 0–4)", d->name, row, type);
}

/* The rows, a block at a time: inflated, then unfiltered and written out a
 * group at a time. */
static jnd_status png_decode_rows(png_decoder *d, jnd_image *out) {
  size_t h = (size_t)out->h;
  for (size_t y = 0; y < h; y += d->block) {
    size_t k = h - y < d->block ? h - y : d->block;
    jnd_status s = png_inflate(d, d->rows, k * d->stride, y, h);
    if (s != JND_OK) return s;
    for (size_t i = 0; i < k; i += PNG_WAVE) {
      size_t bad = png_unfilter_group(d, d->rows + i * d->stride, d->stride, k - i < PNG_WAVE ? k - i : PNG_WAVE,
                                      y + i, out);
      if (bad) return png_bad_filter(d, bad, d->rows[(bad - 1 - y) * d->stride]);
    }
  }
  return JND_OK; /* what the stream holds after the last row is not read */
}

/* Reads IHDR (PNG spec §11.2.2) into d: the layout, the sizes of a row and
 * of a block of rows; *w, *h, *channels: the image's. */
static jnd_status png_read_header(png_decoder *d, uint32_t *w, uint32_t *h, unsigned *channels) {
  png_chunk c;
  if (!png_next_chunk(d->buf, d->n, &d->pos, &c) || !png_chunk_is(&c, "IHDR") || c.len != 13)
    return jnd_fail(JND_ERR_FORMAT, "%s: corrupt PNG (no IHDR)", d->name);
  *w = be32(c.data);
  *h = be32(c.data + 4);
  *channels = png_plain_layout(c.data);
  d->depth = c.data[8];
  if (!*channels)
    return jnd_fail(JND_ERR_FORMAT, "%s: PNG layout not read here (bit depth %u, colour type %u, interlace %u)",
                    d->name, d->depth, c.data[9], c.data[12]);
  d->bpp = *channels * (d->depth / 8);
  /* a block goes to zlib in one piece, so it must fit in a uInt */
  if (*w > INT_MAX || *h > INT_MAX || !png_mul(*w, d->bpp, &d->row) || d->row >= UINT_MAX - PNG_BLOCK_BYTES)
    return jnd_fail(JND_ERR_LIMIT, "%s: PNG too large (%u × %u)", d->name, (unsigned)*w, (unsigned)*h);
  d->stride = d->row + 1;
  d->block = d->stride >= PNG_BLOCK_BYTES ? 1 : PNG_BLOCK_BYTES / d->stride;
  if (d->block > PNG_WAVE) d->block -= d->block % PNG_WAVE; /* whole groups */
  if (d->block > *h) d->block = *h;
  d->pitch = (d->row + PNG_SLACK + 63) & ~(size_t)63;
  return JND_OK;
}

/* The whole image data in one call: the IDAT chunks' data (joined when
 * there are several), their deflate stream inflated by libdeflate into
 * every filtered row at once, then the rows unfiltered and written out a
 * group at a time. 1 when that decoded the image; 0 when the stream is not
 * exactly the rows (shorter or longer, corrupt, a preset dictionary) or a
 * row has an unknown filter: the streaming decoder then decodes what it can
 * and reports the rest in its words. NOMEM: -1.
 *
 * Where a filtered row is shorter than a row of a plane by more than
 * PNG_SLACK bytes (up to 3 bytes a pixel: 8-bit grey, grey and alpha, RGB;
 * 16-bit grey), the filtered rows are inflated into the end of the image's
 * own memory instead of a buffer of their own (6 MB of fresh pages at
 * 1920 × 1080 RGB): writing out rows y… of the last plane, at 4 · w bytes a
 * row, stays behind the filtered rows still to read, which start
 * stride ≤ 4 · w − PNG_SLACK − 1 bytes a row later (png_in_place). */
static int png_in_place(const png_decoder *d, const jnd_image *out) {
  return d->stride + PNG_SLACK < (size_t)out->w * sizeof(float);
}

static int png_decode_whole(png_decoder *d, jnd_image *out) {
  const size_t h = (size_t)out->h;
  size_t raw_n, zn = 0, pos = d->pos, chunks = 0;
  png_chunk c;
  const unsigned char *z = NULL;
  if (!png_mul(h, d->stride, &raw_n) || raw_n > SIZE_MAX - PNG_SLACK) return 0;
  while (png_next_chunk(d->buf, d->n, &pos, &c))
    if (png_chunk_is(&c, "IDAT")) {
      zn += c.len;
      chunks++;
      z = c.data;
    }
  if (zn < 2) return 0;
  unsigned char *joined = chunks > 1 ? jnd_alloc(zn, 1) : NULL, *raw;
  const int in_place = d->codes || png_in_place(d, out);
  if (d->codes) /* rows written out at y · row, behind the filtered ones at y · stride */
    raw = d->codes;
  else if (in_place) /* the image's memory ends PNG_SLACK bytes after the rows */
    raw = (unsigned char *)(out->data + (size_t)out->w * out->h * out->c) - raw_n - PNG_SLACK;
  else
    raw = jnd_alloc(raw_n + PNG_SLACK, 1);
  struct libdeflate_decompressor *dd = libdeflate_alloc_decompressor();
  int ok = -1;
  if ((chunks == 1 || joined) && raw && dd) {
    memset(raw + raw_n, 0, PNG_SLACK);
    if (joined) {
      zn = 0;
      pos = d->pos;
      while (png_next_chunk(d->buf, d->n, &pos, &c))
        if (png_chunk_is(&c, "IDAT")) {
          memcpy(joined + zn, c.data, c.len);
          zn += c.len;
        }
      z = joined;
    }
    /* the zlib header (RFC 1950): deflate, a valid check, no dictionary;
     * the Adler-32 after the rows is not read, as the streaming path */
    size_t got = 0;
    ok = (z[0] & 0x0f) == 8 && (z[0] >> 4) <= 7 && ((unsigned)z[0] << 8 | z[1]) % 31 == 0 && !(z[1] & 0x20) &&
         libdeflate_deflate_decompress_ex(dd, z + 2, zn - 2, raw, raw_n, NULL, &got) == LIBDEFLATE_SUCCESS &&
         got == raw_n;
    for (size_t y = 0; ok == 1 && y < h; y += PNG_WAVE)
      if (png_unfilter_group(d, raw + y * d->stride, d->stride, h - y < PNG_WAVE ? h - y : PNG_WAVE, y, out))
        ok = 0;
  }
  libdeflate_free_decompressor(dd);
  free(joined);
  if (!in_place) free(raw);
  return ok;
}

/* The image data into out (its planes, or with d->codes the rows' bytes),
 * out's size set: libdeflate's whole stream where it can, else zlib's
 * blocks. d->bank is freed; out is left to the caller. */
static jnd_status png_decode_data(png_decoder *d, jnd_image *out, const char *name) {
  d->bank = jnd_calloc(PNG_WAVE + 2, d->pitch);
  int whole = d->bank ? png_decode_whole(d, out) : -1;
  if (whole) {
    free(d->bank);
    if (whole < 0)
      return jnd_fail(JND_ERR_NOMEM, "%s: out of memory for %d × %d × %d", name, out->w, out->h, out->c);
    return JND_OK;
  }
  memset(d->bank, 0, d->pitch); /* the row above the first is zeros (§9.2) */
  d->rows = d->block * d->stride <= SIZE_MAX - PNG_SLACK ? jnd_alloc(d->block * d->stride + PNG_SLACK, 1) : NULL;
  if (d->rows) memset(d->rows + d->block * d->stride, 0, PNG_SLACK);
  if (!d->rows || inflateInit(&d->z) != Z_OK) {
    free(d->rows);
    free(d->bank);
    return jnd_fail(JND_ERR_NOMEM, "%s: out of memory for zlib", name);
  }
#if ZLIB_VERNUM >= 0x1290
  inflateValidate(&d->z, 0); /* the Adler-32 after the rows is not read: data past them is ignored */
#endif
  jnd_status s = png_decode_rows(d, out);
  inflateEnd(&d->z);
  free(d->rows);
  free(d->bank);
  return s;
}

/* A decoder on buf, its header read (png_read_header) */
static jnd_status png_start(png_decoder *d, const char *name, const unsigned char *buf, size_t n, uint32_t *w,
                            uint32_t *h, unsigned *channels) {
  memset(d, 0, sizeof *d);
  d->name = name;
  d->buf = buf;
  d->n = n;
  d->pos = 8;
  *w = *h = 0;
  *channels = 0;
  return png_read_header(d, w, h, channels);
}

jnd_status jnd_png_decode(const char *name, const unsigned char *buf, size_t n, jnd_image *out, int *bits) {
  memset(out, 0, sizeof *out);
  png_decoder d;
  uint32_t w, h;
  unsigned channels;
  jnd_status s = png_start(&d, name, buf, n, &w, &h, &channels);
  if (s != JND_OK) return s;
  if ((s = jnd_image_alloc(out, (int)w, (int)h, (int)channels)) != JND_OK)
    return jnd_fail(s, "%s: out of memory for %u × %u × %u", name, (unsigned)w, (unsigned)h, channels);
  for (int v = 0; v < 256; v++) d.to_float[v] = (float)(v * (1.0 / 255));
  if ((s = png_decode_data(&d, out, name)) != JND_OK) {
    jnd_image_free(out);
    return s;
  }
  *bits = (int)d.depth;
  return JND_OK;
}

int jnd_png_is_rgb8(const unsigned char *buf, size_t n) {
  /* IHDR is the first chunk (jnd_png_validate): bit depth at byte 24, colour type at 25 */
  return jnd_png_plain(buf, n) && n > 25 && buf[24] == 8 && buf[25] == 2;
}

jnd_status jnd_png_decode_rgb8(const char *name, const unsigned char *buf, size_t n, unsigned char **rgb, int *w,
                               int *h) {
  *rgb = NULL;
  *w = *h = 0;
  png_decoder d;
  uint32_t pw, ph;
  unsigned channels;
  jnd_status s = png_start(&d, name, buf, n, &pw, &ph, &channels);
  if (s != JND_OK) return s;
  if (d.depth != 8 || channels != 3)
    return jnd_fail(JND_ERR_FORMAT, "%s: not an 8-bit RGB PNG (bit depth %u, %u channels)", name, d.depth, channels);
  if ((s = jnd_check_size((int)pw, (int)ph, 3, name)) != JND_OK) return s;
  /* the filtered rows are inflated here, and the rows written out over
   * them (png_decode_whole) */
  size_t bytes;
  if (!png_mul(ph, d.stride, &bytes) || bytes > SIZE_MAX - PNG_SLACK || !(d.codes = jnd_alloc(bytes + PNG_SLACK, 1)))
    return jnd_fail(JND_ERR_NOMEM, "%s: out of memory for %u × %u × 3", name, (unsigned)pw, (unsigned)ph);
  jnd_image out = {(int)pw, (int)ph, 3, NULL};
  if ((s = png_decode_data(&d, &out, name)) != JND_OK) {
    free(d.codes);
    return s;
  }
  *rgb = d.codes;
  *w = (int)pw;
  *h = (int)ph;
  return JND_OK;
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

/* The writer: rows quantised, each row filtered with the PNG filter (None,
 * Sub, Up, Paeth) whose output has the smallest sum of absolute values as
 * signed bytes (libpng's heuristic), and deflated at level 1 in pieces that
 * are compressed in parallel and joined into one zlib stream (each piece a
 * raw deflate, the Adler-32 sums combined in order), as pigz does. The last
 * LAST_SHARE of the rows is one piece deflated by libdeflate, which ends the
 * stream (its last block is final) and is started first; the rows before it
 * are zlib pieces of about PIECE_BYTES, each ending on a byte boundary
 * (Z_SYNC_FLUSH), so that the next piece can follow. libdeflate takes less
 * than half of zlib's time (a 1080p picture: 44 against 98 ms), so with the
 * split at about that ratio the two halves of the work end together on two
 * threads. Pieces are fixed by the image, not by the thread count: the file
 * is the same bytes for any number of threads. Level 1 with filtering is
 * 4–6× faster than level 6 unfiltered and, on rendered and synthetic
 * images, about as small or smaller. */
enum { PIECE_BYTES = 1 << 18 };
#define LAST_SHARE 0.7

static void quantise_row(const jnd_image *img, int y, int bits, unsigned char *r) {
  const size_t bpp = (size_t)img->c * (bits / 8);
  for (int ch = 0; ch < img->c; ch++) {
    const float *p = jnd_image_plane(img, ch) + (size_t)y * img->w;
    for (int x = 0; x < img->w; x++) {
      /* in double, as the writer always quantised: the same codes as before */
      double v = jnd_clampd(p[x], 0.0, 1.0);
      if (bits == 8) {
        r[(size_t)x * bpp + ch] = (unsigned char)(v * 255.0 + 0.5);
      } else {
        unsigned q = (unsigned)(v * 65535.0 + 0.5);
        r[(size_t)x * bpp + 2 * ch] = (unsigned char)(q >> 8);
        r[(size_t)x * bpp + 2 * ch + 1] = (unsigned char)q;
      }
    }
  }
}

/* the four filters of one row into f[0..3] (n bytes each), and the sum of
 * each one's absolute values as signed bytes; up is the row above (zeros
 * above the first row). One plain loop per filter, so that each vectorises. */
JND_HOT static void filter_candidates(const unsigned char *cur, const unsigned char *up, size_t n, size_t bpp,
                                      unsigned char *f, long sum[4]) {
  unsigned char *none = f, *sub = f + n, *upf = f + 2 * n, *pae = f + 3 * n;
  long s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  for (size_t i = 0; i < bpp && i < n; i++) { /* the first pixel: no left neighbour */
    none[i] = cur[i];
    sub[i] = cur[i];
    upf[i] = (unsigned char)(cur[i] - up[i]);
    pae[i] = (unsigned char)(cur[i] - up[i]); /* Paeth of (0, b, 0) is b */
  }
#pragma omp simd
  for (size_t i = bpp; i < n; i++) {
    int a = cur[i - bpp], b = up[i], c = up[i - bpp];
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    int pr = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
    none[i] = cur[i];
    sub[i] = (unsigned char)(cur[i] - a);
    upf[i] = (unsigned char)(cur[i] - b);
    pae[i] = (unsigned char)(cur[i] - pr);
  }
#pragma omp simd reduction(+ : s0, s1, s2, s3)
  for (size_t i = 0; i < n; i++) {
    s0 += none[i] < 128 ? none[i] : 256 - none[i];
    s1 += sub[i] < 128 ? sub[i] : 256 - sub[i];
    s2 += upf[i] < 128 ? upf[i] : 256 - upf[i];
    s3 += pae[i] < 128 ? pae[i] : 256 - pae[i];
  }
  sum[0] = s0;
  sum[1] = s1;
  sum[2] = s2;
  sum[3] = s3;
}

/* row cur (n bytes; up the row above, zeros above the first) filtered into
 * out (type byte + n bytes) with the filter of the smallest sum; try holds
 * 4 × n bytes of scratch */
static void filter_row(const unsigned char *cur, const unsigned char *up, size_t n, size_t bpp, unsigned char *try,
                       unsigned char *out) {
  long sum[4];
  filter_candidates(cur, up, n, bpp, try, sum);
  int pick = 0;
  for (int t = 1; t < 4; t++)
    if (sum[t] < sum[pick]) pick = t;
  static const unsigned char type[4] = {0, 1, 2, 4}; /* None, Sub, Up, Paeth */
  out[0] = type[pick];
  memcpy(out + 1, try + (size_t)pick * n, n);
}

typedef struct {
  unsigned char *z;
  size_t zn;
  uLong adler;
  size_t len; /* filtered bytes */
} png_piece;

jnd_status jnd_image_write_png(const char *path, const jnd_image *img, int bits) {
  if (bits != 8 && bits != 16) return jnd_fail(JND_ERR_ARG, "%s: PNG bit depth must be 8 or 16", path);
  if (img->c < 1 || img->c > 4) return jnd_fail(JND_ERR_ARG, "%s: PNG needs 1–4 channels, not %d", path, img->c);
  jnd_status s = jnd_check_size(img->w, img->h, img->c, path);
  if (s != JND_OK) return s;
  const size_t bpp = (size_t)img->c * (bits / 8), n = (size_t)img->w * bpp, row = 1 + n;
  unsigned char *raw = jnd_alloc(n * img->h, 1);
  if (!raw) return JND_ERR_NOMEM;
  const int h = img->h;
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++) quantise_row(img, y, bits, raw + n * y);
  /* rows [0, split) in zlib pieces of rows_per rows, [split, h) the last piece */
  const int split = (int)(h * (1 - LAST_SHARE));
  const int rows_per = row >= PIECE_BYTES ? 1 : (int)(PIECE_BYTES / row);
  const int npieces = (split + rows_per - 1) / rows_per + 1;
  png_piece *pc = jnd_calloc((size_t)npieces, sizeof *pc);
  if (!pc) {
    free(raw);
    return JND_ERR_NOMEM;
  }
  int fail = 0;
#pragma omp parallel
  {
    unsigned char *buf = malloc(row * rows_per + 5 * n); /* a zlib piece's filtered rows, 4 candidates, zeros */
#pragma omp for schedule(dynamic, 1)
    for (int t = 0; t < npieces; t++) {
      const int k = t == 0 ? npieces - 1 : t - 1; /* the last, largest piece first */
      const int last = k == npieces - 1;
      const int y0 = last ? split : k * rows_per, y1 = last ? h : y0 + rows_per < split ? y0 + rows_per : split;
      png_piece *q = &pc[k];
      q->len = row * (size_t)(y1 - y0);
      /* the last piece's rows in a buffer of their own, the thread's for the others */
      unsigned char *rows = last && buf ? malloc(q->len) : buf;
      if (!rows) {
#pragma omp atomic write
        fail = 1;
        continue;
      }
      unsigned char *try = buf + row * rows_per, *zeros = try + 4 * n;
      memset(zeros, 0, n);
      for (int y = y0; y < y1; y++)
        filter_row(raw + n * y, y ? raw + n * (y - 1) : zeros, n, bpp, try, rows + row * (y - y0));
      q->adler = adler32(adler32(0L, Z_NULL, 0), rows, (uInt)q->len);
      int ok = 0;
      if (last) { /* libdeflate: a raw deflate stream whose last block is final */
        struct libdeflate_compressor *c = libdeflate_alloc_compressor(1);
        size_t bound = c ? libdeflate_deflate_compress_bound(c, q->len) : 0;
        q->z = c ? malloc(bound) : NULL;
        q->zn = q->z ? libdeflate_deflate_compress(c, rows, q->len, q->z, bound) : 0;
        libdeflate_free_compressor(c);
        free(rows);
        ok = q->zn > 0;
      } else { /* zlib: raw deflate ending on a byte boundary, not final */
        z_stream zs;
        memset(&zs, 0, sizeof zs);
        if (deflateInit2(&zs, 1, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) == Z_OK) {
          uLong bound = deflateBound(&zs, (uLong)q->len) + 16;
          q->z = malloc(bound);
          if (q->z) {
            zs.next_in = buf;
            zs.avail_in = (uInt)q->len;
            zs.next_out = q->z;
            zs.avail_out = (uInt)bound;
            ok = deflate(&zs, Z_SYNC_FLUSH) == Z_OK && zs.avail_in == 0;
            q->zn = zs.total_out;
          }
          deflateEnd(&zs);
        }
      }
      if (!ok) {
#pragma omp atomic write
        fail = 1;
      }
    }
    free(buf);
  }
  free(raw);
  size_t zn = 2 + 4;
  for (int k = 0; k < npieces; k++) zn += pc[k].zn;
  unsigned char *z = fail ? NULL : jnd_alloc(zn, 1);
  if (z) {
    /* the zlib stream: header (deflate, 32 KiB window, level "fastest"), the
     * pieces, the Adler-32 of all the filtered bytes */
    z[0] = 0x78;
    z[1] = 0x01;
    size_t at = 2;
    uLong adler = adler32(0L, Z_NULL, 0);
    for (int k = 0; k < npieces; k++) {
      memcpy(z + at, pc[k].z, pc[k].zn);
      at += pc[k].zn;
      adler = adler32_combine(adler, pc[k].adler, (z_off_t)pc[k].len);
    }
    put32(z + at, (uint32_t)adler);
  }
  for (int k = 0; k < npieces; k++) free(pc[k].z);
  free(pc);
  if (!z) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory compressing the PNG", path);
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

/* ---- an image into memory, for a model's embedded textures ---- */

static void put_buf(void *ctx, void *data, int size) { jnd_buf_put(ctx, data, (size_t)size); }

jnd_status jnd_image_encode_8bit(const jnd_image *img, int jpeg, jnd_buf *out) {
  if (img->c < 1 || img->c > 4) return jnd_fail(JND_ERR_ARG, "an image of %d channels cannot be encoded", img->c);
  jnd_status s = jnd_check_size(img->w, img->h, img->c, "texture");
  if (s != JND_OK) return s;
  const size_t n = (size_t)img->w * img->c;
  unsigned char *q = jnd_alloc(n * img->h, 1);
  if (!q) return JND_ERR_NOMEM;
  for (int y = 0; y < img->h; y++) quantise_row(img, y, 8, q + n * y);
  int ok = jpeg ? stbi_write_jpg_to_func(put_buf, out, img->w, img->h, img->c, q, 95)
                : stbi_write_png_to_func(put_buf, out, img->w, img->h, img->c, q, (int)n);
  free(q);
  return ok && !out->failed ? JND_OK : jnd_fail(JND_ERR_NOMEM, "cannot encode a %d x %d map", img->w, img->h);
}
