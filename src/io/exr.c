/* OpenEXR in and out through the OpenEXR core C API (libOpenEXRCore).
 *
 * Reading works over memory: the library reads through mem_read/mem_size, so
 * a file is loaded once (jnd_read_file) and the fuzz targets can feed bytes
 * directly. The image is the first part's data window; channels are ordered
 * R, G, B, A (or Y, A) when present, else alphabetically. The library's own
 * messages go to the context's record, never to stderr.
 *
 * Writing builds the whole file in memory through mem_write and hands it to
 * jnd_write_file_atomic, so a file is never half-written. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>
#include <openexr.h>

#include "core/core.h"
#include "io/io.h"

/* What a context reads from (or writes to) and the first message the library
 * reported; the context's user data. */
typedef struct {
  const unsigned char *in;
  size_t n;
  unsigned char *out; /* writing: grows to cap; len is the furthest byte written */
  size_t len, cap;
  int out_failed;
  char msg[256];
} exr_stream;

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  void *ud = NULL;
  if (exr_get_user_data(ctxt, &ud) != EXR_ERR_SUCCESS || !ud) return;
  exr_stream *s = ud;
  if (!s->msg[0]) snprintf(s->msg, sizeof s->msg, "%s", msg ? msg : exr_get_default_error_message(code));
}

static int64_t mem_read(exr_const_context_t ctxt, void *ud, void *buffer, uint64_t sz,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  const exr_stream *s = ud;
  if (offset >= s->n) return 0;
  uint64_t k = s->n - offset < sz ? s->n - offset : sz;
  memcpy(buffer, s->in + offset, (size_t)k);
  return (int64_t)k;
}

static int64_t mem_size(exr_const_context_t ctxt, void *ud) {
  const exr_stream *s = ud;
  return (int64_t)s->n;
}

static int64_t mem_write(exr_const_context_t ctxt, void *ud, const void *buffer, uint64_t sz,
                         uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  exr_stream *s = ud;
  if (offset > SIZE_MAX - sz) {
    s->out_failed = 1;
    return -1;
  }
  size_t end = (size_t)(offset + sz);
  if (end > s->cap) {
    size_t cap = s->cap ? s->cap : 1 << 16;
    while (cap < end) cap = cap > SIZE_MAX / 2 ? end : cap * 2;
    unsigned char *p = realloc(s->out, cap);
    if (!p) {
      s->out_failed = 1;
      return -1;
    }
    if (cap > s->cap) memset(p + s->cap, 0, cap - s->cap);
    s->out = p;
    s->cap = cap;
  }
  memcpy(s->out + offset, buffer, (size_t)sz);
  if (end > s->len) s->len = end;
  return (int64_t)sz;
}

/* The library's message when it gave one, else the generic one for the code. */
static const char *exr_message(const exr_stream *s, exr_result_t rv) {
  return s->msg[0] ? s->msg : exr_get_default_error_message(rv);
}

/* ---- reading ---- */

/* Output bytes per file byte a compression can plausibly reach: decoders refuse
 * headers that claim more than that, so a tiny file cannot make us allocate
 * gigabytes. deflate tops out near 1032:1; RLE at 64:1 (128 bytes from 2);
 * B44A stores a flat 4×4 block of halves in 3 bytes; DWA codes a flat 8×8
 * block as one deflated DC value. Outputs are float, so twice the half size. */
static double max_expansion(exr_compression_t c) {
  switch (c) {
    case EXR_COMPRESSION_NONE: return 2.0;
    case EXR_COMPRESSION_RLE: return 2.0 * 64;
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A: return 2.0 * 11;
    case EXR_COMPRESSION_DWAA:
    case EXR_COMPRESSION_DWAB: return 2.0 * 64 * 1040;
    default: return 2.0 * 1040; /* ZIP, ZIPS, PIZ, PXR24 */
  }
}

#define EXR_PARSE_MAX_SIDE (1 << 20)

/* Images up to this many output bytes are never refused for their ratio. */
#define EXR_SMALL_BYTES ((double)(64u << 20))

static int find_channel(const exr_attr_chlist_t *cl, const char *name) {
  for (int i = 0; i < cl->num_channels; i++)
    if (strcmp(cl->entries[i].name.str, name) == 0) return i;
  return -1;
}

/* Picks the file channels that become image channels, in image order:
 * R, G, B[, A] when R, G and B are present (other channels are left out);
 * Y[, A] when those are the only channels; else every channel alphabetically
 * (the order the library lists them in). Returns the count, or -1 for more
 * than 64 channels without R, G, B. */
static int choose_channels(const exr_attr_chlist_t *cl, int *pick, int *has_alpha) {
  int r = find_channel(cl, "R"), g = find_channel(cl, "G"), b = find_channel(cl, "B");
  int a = find_channel(cl, "A"), y = find_channel(cl, "Y");
  int c = 0;
  *has_alpha = 0;
  if (r >= 0 && g >= 0 && b >= 0) {
    pick[c++] = r;
    pick[c++] = g;
    pick[c++] = b;
  } else if (y >= 0 && cl->num_channels == 1 + (a >= 0)) {
    pick[c++] = y;
  } else {
    if (cl->num_channels > 64) return -1;
    for (int i = 0; i < cl->num_channels; i++) pick[c++] = i;
    return c;
  }
  if (a >= 0) {
    pick[c++] = a;
    *has_alpha = 1;
  }
  return c;
}

/* Decodes one chunk (a band of scanlines or a tile) whose top-left pixel is
 * (x0, y0) in image coordinates. pick maps image channels to file channels. */
static exr_result_t decode_chunk(exr_context_t ctx, const exr_chunk_info_t *ci, int first,
                                 exr_decode_pipeline_t *dec, jnd_image *img, const int *pick,
                                 const exr_attr_chlist_t *cl, int x0, int y0) {
  exr_result_t rv = first ? exr_decoding_initialize(ctx, 0, ci, dec) : exr_decoding_update(ctx, 0, ci, dec);
  if (rv != EXR_ERR_SUCCESS) return rv;
  if (x0 < 0 || y0 < 0 || x0 + ci->width > img->w || y0 + ci->height > img->h) return EXR_ERR_BAD_CHUNK_LEADER;
  for (int i = 0; i < dec->channel_count; i++) {
    exr_coding_channel_info_t *ch = &dec->channels[i];
    ch->decode_to_ptr = NULL;
    for (int k = 0; k < img->c; k++) {
      if (strcmp(ch->channel_name, cl->entries[pick[k]].name.str) != 0) continue;
      float *dst = jnd_image_plane(img, k) + (size_t)y0 * img->w + x0;
      ch->decode_to_ptr = (uint8_t *)dst;
      ch->user_pixel_stride = 4;
      ch->user_line_stride = 4 * img->w;
      ch->user_bytes_per_element = 4;
      /* UINT samples land as uint32 and are converted to float afterwards */
      ch->user_data_type = ch->data_type == EXR_PIXEL_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
    }
  }
  rv = exr_decoding_choose_default_routines(ctx, 0, dec);
  if (rv != EXR_ERR_SUCCESS) return rv;
  return exr_decoding_run(ctx, 0, dec);
}

/* Where the chunks are: scanline chunks of `lines` rows from the data
 * window's top, or tiles of tw × th in rows of nx (the first level). */
typedef struct {
  int tiled, lines, nx, tw, th;
  const exr_attr_box2i_t *dw;
} chunk_grid;

/* Decodes chunks [k0, k1) in order with one pipeline. */
static exr_result_t decode_range(exr_context_t ctx, const chunk_grid *g, int k0, int k1, jnd_image *img,
                                 const int *pick, const exr_attr_chlist_t *cl) {
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  exr_result_t rv = EXR_ERR_SUCCESS;
  int first = 1;
  for (int k = k0; k < k1 && rv == EXR_ERR_SUCCESS; k++) {
    exr_chunk_info_t ci;
    int x0, y0;
    if (g->tiled) {
      int tx = k % g->nx, ty = k / g->nx;
      rv = exr_read_tile_chunk_info(ctx, 0, tx, ty, 0, 0, &ci);
      x0 = (int)((int64_t)tx * g->tw);
      y0 = (int)((int64_t)ty * g->th);
    } else {
      rv = exr_read_scanline_chunk_info(ctx, 0, (int)(g->dw->min.y + (int64_t)k * g->lines), &ci);
      x0 = ci.start_x - g->dw->min.x;
      y0 = ci.start_y - g->dw->min.y;
    }
    if (rv != EXR_ERR_SUCCESS) break;
    rv = decode_chunk(ctx, &ci, first, &dec, img, pick, cl, x0, y0);
    first = 0;
  }
  if (!first) exr_decoding_destroy(ctx, &dec);
  return rv;
}

enum { CHUNK_GROUPS = 32 }; /* pieces a decode is split into for the threads */

/* Group q of ng of the nchunks chunks (consecutive ones, sizes within one). */
static exr_result_t decode_group(exr_context_t ctx, const chunk_grid *g, int q, int ng, int nchunks, jnd_image *img,
                                 const int *pick, const exr_attr_chlist_t *cl) {
  return decode_range(ctx, g, (int)((int64_t)q * nchunks / ng), (int)((int64_t)(q + 1) * nchunks / ng), img, pick,
                      cl);
}

/* Decodes every chunk. OpenEXR's core decodes chunks of one context
 * concurrently, so groups of chunks go to the threads: as tasks of the
 * caller's team inside a parallel region (a file read beside others), in a
 * team of their own outside one. Should any group fail, the whole is
 * decoded again in order, so that the error reported is the file's first,
 * whatever the threads did. */
static exr_result_t decode_all(exr_context_t ctx, exr_stream *st, const chunk_grid *g, int nchunks, jnd_image *img,
                               const int *pick, const exr_attr_chlist_t *cl) {
  const int ng = nchunks < CHUNK_GROUPS ? nchunks : CHUNK_GROUPS;
  exr_chunk_info_t ci; /* the chunk table is read here, once, before the threads share it */
  exr_result_t rv = g->tiled ? exr_read_tile_chunk_info(ctx, 0, 0, 0, 0, 0, &ci)
                             : exr_read_scanline_chunk_info(ctx, 0, g->dw->min.y, &ci);
  if (rv == EXR_ERR_SUCCESS && ng > 1) {
    int failed = 0;
    if (omp_in_parallel()) {
      const unsigned ngu = (unsigned)ng; /* clang's taskloop compares its unsigned count with the bound */
#pragma omp taskloop grainsize(1) shared(failed)
      for (unsigned q = 0; q < ngu; q++)
        if (decode_group(ctx, g, (int)q, ng, nchunks, img, pick, cl) != EXR_ERR_SUCCESS) {
#pragma omp atomic write
          failed = 1;
        }
    } else {
#pragma omp parallel for schedule(dynamic, 1)
      for (int q = 0; q < ng; q++)
        if (decode_group(ctx, g, q, ng, nchunks, img, pick, cl) != EXR_ERR_SUCCESS) {
#pragma omp atomic write
          failed = 1;
        }
    }
    if (!failed) return EXR_ERR_SUCCESS;
  }
  st->msg[0] = 0;
  return decode_range(ctx, g, 0, nchunks, img, pick, cl);
}

/* Reads the first part of an open context into out. */
static jnd_status read_part(const char *name, exr_context_t ctx, exr_stream *st, size_t n,
                            jnd_image *out, jnd_image_info *info) {
  exr_storage_t storage;
  exr_attr_box2i_t dw;
  exr_compression_t comp;
  const exr_attr_chlist_t *cl = NULL;
  exr_result_t rv = exr_get_storage(ctx, 0, &storage);
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_data_window(ctx, 0, &dw);
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_compression(ctx, 0, &comp);
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_channels(ctx, 0, &cl);
  if (rv != EXR_ERR_SUCCESS || !cl)
    return jnd_fail(JND_ERR_FORMAT, "%s: corrupt OpenEXR header: %s", name, exr_message(st, rv));
  if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
    return jnd_fail(JND_ERR_FORMAT, "%s: deep OpenEXR images are not supported", name);
  if (cl->num_channels < 1) return jnd_fail(JND_ERR_FORMAT, "%s: OpenEXR file has no channels", name);
  int64_t w64 = (int64_t)dw.max.x - dw.min.x + 1, h64 = (int64_t)dw.max.y - dw.min.y + 1;
  if (w64 <= 0 || h64 <= 0) return jnd_fail(JND_ERR_FORMAT, "%s: empty OpenEXR data window", name);
  if (w64 > JND_MAX_SIDE || h64 > JND_MAX_SIDE) w64 = h64 = JND_MAX_SIDE + 1; /* refused below */
  jnd_status s = jnd_check_size((int)w64, (int)h64, 1, name);
  if (s != JND_OK) return s;
  int w = (int)w64, h = (int)h64;

  for (int i = 0; i < cl->num_channels; i++) {
    const exr_attr_chlist_entry_t *e = &cl->entries[i];
    if (e->x_sampling != 1 || e->y_sampling != 1)
      return jnd_fail(JND_ERR_FORMAT, "%s: channel %s is subsampled (%d × %d); only full-resolution channels are supported",
                      name, e->name.str, e->x_sampling, e->y_sampling);
    if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT && e->pixel_type != EXR_PIXEL_UINT)
      return jnd_fail(JND_ERR_FORMAT, "%s: channel %s has an unknown sample type", name, e->name.str);
  }
  int pick[64], has_alpha;
  int c = choose_channels(cl, pick, &has_alpha);
  if (c < 0)
    return jnd_fail(JND_ERR_LIMIT, "%s: %d channels without R, G, B is over the limit of 64", name, cl->num_channels);
  int bits = 16;
  for (int k = 0; k < c; k++)
    if (cl->entries[pick[k]].pixel_type != EXR_PIXEL_HALF) bits = 32;

  double out_bytes = (double)w * h * c * sizeof(float);
  if (out_bytes > EXR_SMALL_BYTES && out_bytes > (double)n * max_expansion(comp))
    return jnd_fail(JND_ERR_FORMAT, "%s: header claims %d × %d × %d samples, more than a %zu-byte file can hold",
                    name, w, h, c, n);

  /* the chunk offset table (8 bytes a chunk) must fit in the file */
  int32_t chunks = 0;
  rv = exr_get_chunk_count(ctx, 0, &chunks);
  if (rv != EXR_ERR_SUCCESS || chunks < 1 || (uint64_t)chunks > n / 8)
    return jnd_fail(JND_ERR_FORMAT, "%s: corrupt OpenEXR header: %d chunks in a %zu-byte file", name, (int)chunks, n);

  if ((s = jnd_image_alloc(out, w, h, c)) != JND_OK) {
    if (s == JND_ERR_NOMEM) return jnd_fail(s, "%s: out of memory for %d × %d × %d", name, w, h, c);
    return s;
  }
  chunk_grid g = {.tiled = storage == EXR_STORAGE_TILED, .dw = &dw};
  if (g.tiled) {
    int32_t lw = 0, lh = 0;
    rv = exr_get_tile_sizes(ctx, 0, 0, 0, &g.tw, &g.th);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_level_sizes(ctx, 0, 0, 0, &lw, &lh);
    if (rv == EXR_ERR_SUCCESS && (g.tw < 1 || g.th < 1 || lw != w || lh != h)) rv = EXR_ERR_INVALID_ATTR;
    if (rv == EXR_ERR_SUCCESS) {
      g.nx = (int)(((int64_t)lw + g.tw - 1) / g.tw);
      int64_t nt = (int64_t)g.nx * (((int64_t)lh + g.th - 1) / g.th);
      if (nt > chunks) rv = EXR_ERR_INVALID_ATTR; /* more tiles than the offset table lists */
      else rv = decode_all(ctx, st, &g, (int)nt, out, pick, cl);
    }
  } else {
    rv = exr_get_scanlines_per_chunk(ctx, 0, &g.lines);
    if (rv == EXR_ERR_SUCCESS && g.lines < 1) rv = EXR_ERR_INVALID_ATTR;
    if (rv == EXR_ERR_SUCCESS) rv = decode_all(ctx, st, &g, (int)((h + (int64_t)g.lines - 1) / g.lines), out, pick, cl);
  }
  if (rv != EXR_ERR_SUCCESS) {
    jnd_image_free(out);
    if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED)
      return jnd_fail(JND_ERR_FORMAT, "%s: unsupported OpenEXR compression: %s", name, exr_message(st, rv));
    return jnd_fail(JND_ERR_FORMAT, "%s: corrupt OpenEXR pixel data: %s", name, exr_message(st, rv));
  }
  size_t plane = (size_t)w * h;
  for (int k = 0; k < c; k++) {
    if (cl->entries[pick[k]].pixel_type != EXR_PIXEL_UINT) continue;
    float *p = jnd_image_plane(out, k);
    for (size_t i = 0; i < plane; i++) {
      uint32_t u;
      memcpy(&u, &p[i], sizeof u);
      p[i] = (float)u;
    }
  }
  if ((s = jnd_image_check_finite(name, out)) != JND_OK) {
    jnd_image_free(out);
    return s;
  }
  jnd_image_info_set(info, "exr", JND_ENCODING_LINEAR, bits, c, has_alpha);
  return JND_OK;
}

jnd_status jnd_decode_exr(const char *name, const unsigned char *buf, size_t n, jnd_image *out,
                          jnd_image_info *info) {
  memset(out, 0, sizeof *out);
  if (n > INT64_MAX) return jnd_fail(JND_ERR_LIMIT, "%s: file too large", name);
  exr_stream st = {.in = buf, .n = n};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = on_exr_error;
  init.user_data = &st;
  init.read_fn = mem_read;
  init.size_fn = mem_size;
  /* far above JND_MAX_SIDE, so that read_part refuses oversized images with
   * JND_ERR_LIMIT, but low enough to keep the library's own arithmetic safe */
  init.max_image_width = EXR_PARSE_MAX_SIDE;
  init.max_image_height = EXR_PARSE_MAX_SIDE;
  init.max_tile_width = EXR_PARSE_MAX_SIDE;
  init.max_tile_height = EXR_PARSE_MAX_SIDE;
  /* a damaged offset table is an error, not a cue to search the file */
  init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_read(&ctx, name, &init);
  if (rv != EXR_ERR_SUCCESS) {
    exr_finish(&ctx);
    return jnd_fail(JND_ERR_FORMAT, "%s: not a readable OpenEXR file: %s", name, exr_message(&st, rv));
  }
  jnd_status s = read_part(name, ctx, &st, n, out, info);
  exr_finish(&ctx);
  return s;
}

/* ---- writing ---- */

#define HALF_MAX 65504.0f

/* Encodes rows [y, y + ci->height) of img; half output goes through a
 * clamped copy so values beyond the half range become ±65504, not infinity. */
static exr_result_t encode_chunk(exr_context_t ctx, int part, const exr_chunk_info_t *ci, int first,
                                 exr_encode_pipeline_t *enc, const jnd_image *img,
                                 const char *const *names, float *scratch) {
  exr_result_t rv = first ? exr_encoding_initialize(ctx, part, ci, enc) : exr_encoding_update(ctx, part, ci, enc);
  if (rv != EXR_ERR_SUCCESS) return rv;
  size_t band = (size_t)img->w * ci->height;
  int y0 = ci->start_y;
  for (int i = 0; i < enc->channel_count; i++) {
    exr_coding_channel_info_t *ch = &enc->channels[i];
    int k = 0;
    while (k < img->c && strcmp(names[k], ch->channel_name) != 0) k++;
    if (k == img->c) return EXR_ERR_INVALID_ARGUMENT;
    const float *src = jnd_image_plane(img, k) + (size_t)y0 * img->w;
    if (scratch) {
      float *dst = scratch + (size_t)k * band;
      for (size_t j = 0; j < band; j++) {
        float v = src[j];
        dst[j] = v > HALF_MAX ? HALF_MAX : v < -HALF_MAX ? -HALF_MAX : v;
      }
      src = dst;
    }
    ch->encode_from_ptr = (const uint8_t *)src;
    ch->user_pixel_stride = 4;
    ch->user_line_stride = 4 * img->w;
    ch->user_bytes_per_element = 4;
    ch->user_data_type = EXR_PIXEL_FLOAT;
  }
  rv = exr_encoding_choose_default_routines(ctx, part, enc);
  if (rv != EXR_ERR_SUCCESS) return rv;
  return exr_encoding_run(ctx, part, enc);
}

static exr_result_t encode_image(exr_context_t ctx, const jnd_image *img, const char *const *names,
                                 int half) {
  int part = 0;
  exr_result_t rv = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctx, part, img->w, img->h, EXR_COMPRESSION_ZIP);
  for (int k = 0; k < img->c && rv == EXR_ERR_SUCCESS; k++)
    rv = exr_add_channel(ctx, part, names[k], half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
  int32_t lines = 0;
  if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
  if (rv != EXR_ERR_SUCCESS) return rv;
  if (lines < 1) return EXR_ERR_INVALID_ATTR;
  float *scratch = NULL;
  if (half) {
    scratch = malloc((size_t)img->w * lines * img->c * sizeof *scratch);
    if (!scratch) return EXR_ERR_OUT_OF_MEMORY;
  }
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int first = 1;
  for (int y = 0; y < img->h && rv == EXR_ERR_SUCCESS; y += lines) {
    exr_chunk_info_t ci;
    rv = exr_write_scanline_chunk_info(ctx, part, y, &ci);
    if (rv != EXR_ERR_SUCCESS) break;
    rv = encode_chunk(ctx, part, &ci, first, &enc, img, names, scratch);
    first = 0;
  }
  if (!first) exr_encoding_destroy(ctx, &enc);
  free(scratch);
  return rv;
}

jnd_status jnd_image_write_exr(const char *path, const jnd_image *img, const char *const *names, int half) {
  jnd_status s = jnd_check_size(img->w, img->h, img->c, path);
  if (s != JND_OK) return s;
  static const char *const one[] = {"Y"}, *const two[] = {"X", "Y"};
  static const char *const rgba[] = {"R", "G", "B", "A"};
  if (!names) {
    if (img->c > 4) return jnd_fail(JND_ERR_ARG, "%s: %d channels need explicit OpenEXR channel names", path, img->c);
    names = img->c == 1 ? one : img->c == 2 ? two : rgba;
  }
  for (int k = 0; k < img->c; k++) {
    if (!names[k] || !names[k][0] || strlen(names[k]) > 255)
      return jnd_fail(JND_ERR_ARG, "%s: OpenEXR channel %d needs a name of 1–255 bytes", path, k);
    for (int j = 0; j < k; j++)
      if (strcmp(names[j], names[k]) == 0)
        return jnd_fail(JND_ERR_ARG, "%s: OpenEXR channel name %s is used twice", path, names[k]);
  }
  exr_stream st = {0};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = on_exr_error;
  init.user_data = &st;
  init.write_fn = mem_write;
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv == EXR_ERR_SUCCESS) rv = encode_image(ctx, img, names, half);
  exr_result_t fin = exr_finish(&ctx);
  if (rv == EXR_ERR_SUCCESS) rv = fin;
  if (rv != EXR_ERR_SUCCESS || st.out_failed) {
    free(st.out);
    if (rv == EXR_ERR_OUT_OF_MEMORY || st.out_failed) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
    return jnd_fail(JND_ERR_INTERNAL, "%s: OpenEXR encoding failed: %s", path, exr_message(&st, rv));
  }
  s = jnd_write_file_atomic(path, st.out, st.len);
  free(st.out);
  return s;
}
