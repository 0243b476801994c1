/* io: image files in and out, and CSV. Every fixture is made here, in the
 * test's scratch folder: nothing is read from outside. */
#include <dirent.h>
#include <omp.h>
#include <stdint.h>

#include <OpenEXR/openexr.h>
#include <stb_image_write.h>
#include <zlib.h>

#include "test.h"
#include "core/core.h"
#include "io/io.h"
#include "vision/vision.h"
#include "jnd.h"

/* ---- helpers ---- */

static const char *tmp_file(const char *name) {
  static char paths[8][1200];
  static int next;
  char *p = paths[next++ % 8];
  snprintf(p, sizeof paths[0], "%s/%s", test_tmp_dir(), name);
  return p;
}

static int write_bytes(const char *path, const void *buf, size_t n) {
  FILE *f = fopen(path, "wb");
  if (!f) return 0;
  size_t put = n ? fwrite(buf, 1, n, f) : 0;
  return (fclose(f) == 0) & (put == n);
}

static unsigned char *read_bytes(const char *path, size_t *n) {
  unsigned char *buf = NULL;
  if (jnd_read_file(path, (size_t)1 << 30, &buf, n) != JND_OK) return NULL;
  return buf;
}

/* A deterministic image with values spread over [lo, hi). */
static jnd_image pattern(int w, int h, int c, double lo, double hi, uint64_t seed) {
  jnd_image img;
  jnd_image_alloc(&img, w, h, c);
  jnd_rng r;
  jnd_rng_seed(&r, seed);
  for (size_t i = 0; i < (size_t)w * h * c; i++) img.data[i] = (float)(lo + (hi - lo) * jnd_rng_uniform(&r));
  return img;
}

static double max_abs_diff(const jnd_image *a, const jnd_image *b) {
  double m = 0;
  for (size_t i = 0; i < (size_t)a->w * a->h * a->c; i++) {
    double d = fabs((double)a->data[i] - b->data[i]);
    if (d > m) m = d;
  }
  return m;
}

static int same_shape(const jnd_image *a, const jnd_image *b) {
  return a->w == b->w && a->h == b->h && a->c == b->c;
}

static unsigned char *find_bytes(unsigned char *buf, size_t n, const void *what, size_t k) {
  for (size_t i = 0; i + k <= n; i++)
    if (memcmp(buf + i, what, k) == 0) return buf + i;
  return NULL;
}

static void put_le32(unsigned char *p, uint32_t v) {
  for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (8 * i));
}

static void put_be32(unsigned char *p, uint32_t v) {
  for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (24 - 8 * i));
}

/* An EXR written straight through the core API, for layouts jnd never writes:
 * tiles, UINT channels, data windows away from the origin. data is planar
 * float (UINT channels take the value's integer part). */
typedef struct {
  exr_storage_t storage;
  exr_compression_t compression;
  int x0, y0, w, h, c;
  const char *names[72];
  exr_pixel_type_t types[72];
} exr_layout;

/* data: c planes of w × h floats */
static int write_core_exr(const char *path, const exr_layout *L, const float *data) {
  exr_context_t ctx;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  if (exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init) != EXR_ERR_SUCCESS) return 0;
  int part, ok = 1;
  exr_attr_box2i_t dw;
  dw.min.x = L->x0;
  dw.min.y = L->y0;
  dw.max.x = L->x0 + L->w - 1;
  dw.max.y = L->y0 + L->h - 1;
  exr_attr_v2f_t centre;
  centre.x = centre.y = 0.f;
  ok &= exr_add_part(ctx, NULL, L->storage, &part) == EXR_ERR_SUCCESS;
  ok &= exr_initialize_required_attr(ctx, part, &dw, &dw, 1.f, &centre, 1.f, EXR_LINEORDER_INCREASING_Y,
                                     L->compression) == EXR_ERR_SUCCESS;
  for (int k = 0; k < L->c; k++)
    ok &= exr_add_channel(ctx, part, L->names[k], L->types[k], EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1) == EXR_ERR_SUCCESS;
  if (L->storage == EXR_STORAGE_TILED)
    ok &= exr_set_tile_descriptor(ctx, part, 16, 8, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN) == EXR_ERR_SUCCESS;
  ok &= exr_write_header(ctx) == EXR_ERR_SUCCESS;
  uint32_t *u = calloc((size_t)L->w * L->h * L->c, sizeof *u);
  for (size_t i = 0; i < (size_t)L->w * L->h * L->c; i++) u[i] = (uint32_t)data[i];
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int first = 1, lines = 16;
  if (L->storage == EXR_STORAGE_SCANLINE) exr_get_scanlines_per_chunk(ctx, part, &lines);
  int tw = L->storage == EXR_STORAGE_TILED ? 16 : L->w, th = L->storage == EXR_STORAGE_TILED ? 8 : lines;
  for (int ty = 0; ok && ty * th < L->h; ty++) {
    for (int tx = 0; ok && tx * tw < L->w; tx++) {
      exr_chunk_info_t ci;
      if (L->storage == EXR_STORAGE_TILED)
        ok &= exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &ci) == EXR_ERR_SUCCESS;
      else
        ok &= exr_write_scanline_chunk_info(ctx, part, L->y0 + ty * th, &ci) == EXR_ERR_SUCCESS;
      if (!ok) break;
      ok &= (first ? exr_encoding_initialize(ctx, part, &ci, &enc) : exr_encoding_update(ctx, part, &ci, &enc)) ==
            EXR_ERR_SUCCESS;
      first = 0;
      for (int i = 0; ok && i < enc.channel_count; i++) {
        exr_coding_channel_info_t *ch = &enc.channels[i];
        int k = 0;
        while (strcmp(L->names[k], ch->channel_name) != 0) k++;
        size_t at = ((size_t)k * L->h + (size_t)ty * th) * L->w + (size_t)tx * tw;
        int is_uint = L->types[k] == EXR_PIXEL_UINT;
        ch->encode_from_ptr = is_uint ? (const uint8_t *)(u + at) : (const uint8_t *)(data + at);
        ch->user_pixel_stride = 4;
        ch->user_line_stride = 4 * L->w;
        ch->user_bytes_per_element = 4;
        ch->user_data_type = is_uint ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
      }
      ok &= exr_encoding_choose_default_routines(ctx, part, &enc) == EXR_ERR_SUCCESS;
      ok &= exr_encoding_run(ctx, part, &enc) == EXR_ERR_SUCCESS;
    }
  }
  if (!first) exr_encoding_destroy(ctx, &enc);
  free(u);
  ok &= exr_finish(&ctx) == EXR_ERR_SUCCESS;
  return ok;
}

/* ---- OpenEXR ---- */

TEST(exr_float_round_trips_exactly) {
  const char *path = tmp_file("float.exr");
  jnd_image img = pattern(37, 29, 3, -5.0, 1e6, 1), back;
  jnd_image_info info;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(same_shape(&img, &back));
  if (same_shape(&img, &back)) CHECK(max_abs_diff(&img, &back) == 0);
  CHECK(info.encoding == JND_ENCODING_LINEAR && info.bits == 32 && info.channels == 3 && !info.has_alpha);
  CHECK(strcmp(info.format, "exr") == 0);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_half_round_trips_within_half_precision) {
  const char *path = tmp_file("half.exr");
  jnd_image img = pattern(64, 33, 4, 0.0, 1000.0, 2), back;
  jnd_image_info info;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 1));
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(same_shape(&img, &back));
  for (size_t i = 0; same_shape(&img, &back) && i < (size_t)64 * 33 * 4; i++)
    if (fabs(back.data[i] - img.data[i]) > img.data[i] / 1024.0 + 1e-7) {
      CHECK_NEAR(back.data[i], img.data[i], img.data[i] / 1024.0);
      break;
    }
  CHECK(info.bits == 16 && info.channels == 4 && info.has_alpha);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_half_write_clamps_to_the_half_range_instead_of_infinity) {
  const char *path = tmp_file("half_big.exr");
  jnd_image img, back;
  jnd_image_alloc(&img, 4, 1, 1);
  img.data[0] = 1e9f;
  img.data[1] = -1e9f;
  img.data[2] = 0.5f;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 1));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  if (back.data) {
    CHECK(back.data[0] == 65504.0f && back.data[1] == -65504.0f && back.data[2] == 0.5f);
  }
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_default_names_give_back_the_same_channel_order) {
  for (int c = 1; c <= 4; c++) {
    const char *path = tmp_file("defaults.exr");
    jnd_image img = pattern(5, 3, c, 0.0, 1.0, 10 + c), back;
    jnd_image_info info;
    CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
    CHECK_OK(jnd_image_read(path, &back, &info));
    CHECK(same_shape(&img, &back));
    if (same_shape(&img, &back)) CHECK(max_abs_diff(&img, &back) == 0);
    CHECK(info.has_alpha == (c == 4));
    jnd_image_free(&img);
    jnd_image_free(&back);
  }
}

TEST(exr_channels_are_read_as_r_g_b_a_whatever_their_order) {
  const char *path = tmp_file("bgra.exr");
  jnd_image img, back;
  jnd_image_alloc(&img, 2, 2, 4);
  const char *names[] = {"B", "A", "R", "G"};
  const float value[] = {3, 4, 1, 2}; /* so R = 1, G = 2, B = 3, A = 4 */
  for (int k = 0; k < 4; k++)
    for (int i = 0; i < 4; i++) jnd_image_plane(&img, k)[i] = value[k];
  CHECK_OK(jnd_image_write_exr(path, &img, names, 0));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  CHECK(back.c == 4);
  for (int k = 0; k < back.c; k++) CHECK(jnd_image_plane(&back, k)[3] == (float)(k + 1));
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_without_colour_channels_is_read_alphabetically) {
  const char *path = tmp_file("abc.exr");
  jnd_image img, back;
  jnd_image_alloc(&img, 3, 1, 3);
  const char *names[] = {"zeta", "alpha", "mu"};
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < 3; i++) jnd_image_plane(&img, k)[i] = (float)k;
  CHECK_OK(jnd_image_write_exr(path, &img, names, 0));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  CHECK(back.c == 3);
  if (back.c == 3) {
    CHECK(jnd_image_plane(&back, 0)[0] == 1.0f); /* alpha */
    CHECK(jnd_image_plane(&back, 1)[0] == 2.0f); /* mu */
    CHECK(jnd_image_plane(&back, 2)[0] == 0.0f); /* zeta */
  }
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_luminance_with_alpha_is_y_then_a) {
  const char *path = tmp_file("ya.exr");
  jnd_image img, back;
  jnd_image_info info;
  jnd_image_alloc(&img, 2, 1, 2);
  const char *names[] = {"A", "Y"};
  img.data[0] = img.data[1] = 0.25f; /* A */
  img.data[2] = img.data[3] = 7.0f;  /* Y */
  CHECK_OK(jnd_image_write_exr(path, &img, names, 0));
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(back.c == 2 && info.has_alpha);
  if (back.c == 2) CHECK(back.data[0] == 7.0f && back.data[2] == 0.25f);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_with_many_layers_reads_its_rgb_and_over_64_plain_channels_is_refused) {
  const char *path = tmp_file("layers.exr");
  enum { C = 70 };
  exr_layout L = {EXR_STORAGE_SCANLINE, EXR_COMPRESSION_ZIP, 0, 0, 2, 2, C, {0}, {0}};
  char storage[C][8];
  float data[C * 4];
  for (int k = 0; k < C; k++) {
    snprintf(storage[k], sizeof storage[k], "c%02d", k);
    L.names[k] = storage[k];
    L.types[k] = EXR_PIXEL_FLOAT;
    for (int i = 0; i < 4; i++) data[k * 4 + i] = (float)(k * 4 + i);
  }
  jnd_image back;
  CHECK(write_core_exr(path, &L, data));
  CHECK_STATUS(jnd_image_read(path, &back, NULL), JND_ERR_LIMIT);
  L.names[7] = "R";
  L.names[8] = "G";
  L.names[9] = "B";
  CHECK(write_core_exr(path, &L, data));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  CHECK(back.c == 3);
  if (back.c == 3) CHECK(memcmp(back.data, data + 7 * 4, 3 * 4 * sizeof(float)) == 0);
  jnd_image_free(&back);
}

TEST(exr_writer_refuses_duplicate_channel_names) {
  jnd_image img = pattern(2, 2, 2, 0, 1, 3);
  const char *names[] = {"Y", "Y"};
  CHECK_STATUS(jnd_image_write_exr(tmp_file("dup.exr"), &img, names, 0), JND_ERR_ARG);
  jnd_image_free(&img);
}

TEST(exr_tiled_file_reads_like_the_pixels_it_holds) {
  const char *path = tmp_file("tiled.exr");
  exr_layout L = {EXR_STORAGE_TILED, EXR_COMPRESSION_ZIP, 0, 0, 37, 21, 3, {"B", "G", "R"},
                  {EXR_PIXEL_FLOAT, EXR_PIXEL_FLOAT, EXR_PIXEL_FLOAT}};
  jnd_image img = pattern(37, 21, 3, -1, 1, 4), back;
  CHECK(write_core_exr(path, &L, img.data));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  CHECK(same_shape(&img, &back));
  if (same_shape(&img, &back)) { /* the file's B, G, R come back as R, G, B */
    size_t plane = (size_t)37 * 21;
    CHECK(memcmp(back.data, img.data + 2 * plane, plane * 4) == 0);
    CHECK(memcmp(back.data + plane, img.data + plane, plane * 4) == 0);
    CHECK(memcmp(back.data + 2 * plane, img.data, plane * 4) == 0);
  }
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_data_window_away_from_the_origin_is_the_image) {
  const char *path = tmp_file("window.exr");
  exr_layout L = {EXR_STORAGE_SCANLINE, EXR_COMPRESSION_PIZ, -7, 100, 19, 35, 1, {"Y"}, {EXR_PIXEL_HALF}};
  jnd_image img = pattern(19, 35, 1, 0, 1, 5), back;
  for (size_t i = 0; i < (size_t)19 * 35; i++) img.data[i] = (float)(i % 64) / 64; /* exact in half */
  CHECK(write_core_exr(path, &L, img.data));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  CHECK(same_shape(&img, &back));
  if (same_shape(&img, &back)) CHECK(max_abs_diff(&img, &back) == 0);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_every_compression_reads_back) {
  const exr_compression_t lossless[] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE, EXR_COMPRESSION_ZIPS,
                                        EXR_COMPRESSION_ZIP, EXR_COMPRESSION_PIZ};
  for (size_t t = 0; t < sizeof lossless / sizeof lossless[0]; t++) {
    const char *path = tmp_file("comp.exr");
    exr_layout L = {EXR_STORAGE_SCANLINE, lossless[t], 0, 0, 40, 40, 3, {"R", "G", "B"},
                    {EXR_PIXEL_FLOAT, EXR_PIXEL_HALF, EXR_PIXEL_FLOAT}};
    jnd_image img = pattern(40, 40, 3, 0, 4, 6), back;
    for (size_t i = 0; i < (size_t)40 * 40 * 3; i++) img.data[i] = floorf(img.data[i] * 256) / 256;
    CHECK(write_core_exr(path, &L, img.data));
    CHECK_OK(jnd_image_read(path, &back, NULL));
    CHECK(same_shape(&img, &back));
    if (same_shape(&img, &back)) CHECK(max_abs_diff(&img, &back) == 0);
    jnd_image_free(&img);
    jnd_image_free(&back);
  }
  /* DWAA and DWAB: OpenEXRCore 3.1 implements neither (docs/formats.md) */
  const exr_compression_t lossy[] = {EXR_COMPRESSION_PXR24, EXR_COMPRESSION_B44, EXR_COMPRESSION_B44A};
  for (size_t t = 0; t < sizeof lossy / sizeof lossy[0]; t++) {
    const char *path = tmp_file("lossy.exr");
    exr_layout L = {EXR_STORAGE_SCANLINE, lossy[t], 0, 0, 40, 40, 3, {"R", "G", "B"},
                    {EXR_PIXEL_HALF, EXR_PIXEL_HALF, EXR_PIXEL_HALF}};
    jnd_image img = pattern(40, 40, 3, 0.2, 0.3, 7), back;
    CHECK(write_core_exr(path, &L, img.data));
    CHECK_OK(jnd_image_read(path, &back, NULL));
    CHECK(same_shape(&img, &back));
    if (same_shape(&img, &back)) CHECK_LT(max_abs_diff(&img, &back), 0.05);
    jnd_image_free(&img);
    jnd_image_free(&back);
  }
}

TEST(exr_uint_channel_reads_as_float_counts) {
  const char *path = tmp_file("uint.exr");
  exr_layout L = {EXR_STORAGE_SCANLINE, EXR_COMPRESSION_ZIP, 0, 0, 9, 4, 1, {"id"}, {EXR_PIXEL_UINT}};
  jnd_image img, back;
  jnd_image_info info;
  jnd_image_alloc(&img, 9, 4, 1);
  for (int i = 0; i < 36; i++) img.data[i] = (float)(i * 1000);
  CHECK(write_core_exr(path, &L, img.data));
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(same_shape(&img, &back) && info.bits == 32);
  if (same_shape(&img, &back)) CHECK(max_abs_diff(&img, &back) == 0);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(exr_with_nan_is_refused) {
  const char *path = tmp_file("nan.exr");
  jnd_image img = pattern(8, 8, 3, 0, 1, 8), back;
  img.data[8 * 8 + 3 * 8 + 5] = NAN;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  CHECK_STATUS(jnd_image_read(path, &back, NULL), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "nan.exr") && strstr(jnd_last_error(), "NaN") &&
        strstr(jnd_last_error(), "(5, 3) channel 1"));
  CHECK(back.data == NULL);
  jnd_image_free(&img);
}

TEST(exr_with_infinity_is_refused) {
  const char *path = tmp_file("inf.exr");
  jnd_image img = pattern(8, 8, 1, 0, 1, 9), back;
  img.data[0] = INFINITY;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  CHECK_STATUS(jnd_image_read(path, &back, NULL), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "infinite") != NULL);
  jnd_image_free(&img);
}

TEST(every_truncation_of_an_exr_is_refused) {
  const char *path = tmp_file("whole.exr");
  jnd_image img = pattern(20, 40, 3, 0, 1, 10), back;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 1));
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  CHECK(buf != NULL);
  int accepted = 0;
  for (size_t k = 0; buf && k < n; k++) {
    if (jnd_decode_exr("cut.exr", buf, k, &back, NULL) == JND_OK) accepted++;
    CHECK(back.data == NULL);
    jnd_image_free(&back);
  }
  CHECK(accepted == 0);
  CHECK_OK(jnd_decode_exr("whole.exr", buf, n, &back, NULL));
  free(buf);
  jnd_image_free(&back);
  jnd_image_free(&img);
}

/* The file offset and size of the packed data of the scanline chunk that
 * holds row y, through OpenEXR's own reader. */
static int exr_chunk_bytes(const char *path, int y, uint64_t *off, uint64_t *size) {
  exr_context_t ctx = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  exr_chunk_info_t ci;
  int ok = exr_start_read(&ctx, path, &init) == EXR_ERR_SUCCESS &&
           exr_read_scanline_chunk_info(ctx, 0, y, &ci) == EXR_ERR_SUCCESS;
  if (ok) {
    *off = ci.data_offset;
    *size = ci.packed_size;
  }
  exr_finish(&ctx);
  return ok;
}

/* reads path on n threads (0: from inside a parallel region of two, as a
 * file read beside others is); the status, and the message into msg */
static jnd_status read_on(const char *path, int n, jnd_image *out, char *msg, size_t len) {
  jnd_status s = JND_OK;
  int prev = jnd_threads_enter(n ? n : 2);
  if (n) {
    s = jnd_image_read(path, out, NULL);
    snprintf(msg, len, "%s", s ? jnd_last_error() : "");
  } else {
#pragma omp parallel
#pragma omp single
    {
      s = jnd_image_read(path, out, NULL);
      snprintf(msg, len, "%s", s ? jnd_last_error() : "");
    }
  }
  jnd_threads_leave(prev);
  return s;
}

TEST(exr_of_many_chunks_reads_the_same_on_any_threads_and_reports_its_first_bad_chunk) {
  /* 48 × 1000, ZIP: 63 chunks of 16 rows, decoded in groups by the threads */
  const char *path = tmp_file("chunks.exr"), *bad = tmp_file("chunks_bad.exr");
  jnd_image img = pattern(48, 1000, 2, -3, 3, 21), back[3];
  for (size_t i = 0; i < (size_t)48 * 1000 * 2; i++) img.data[i] = (float)(i % 97) / 8; /* deflates: not stored raw */
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  char msg[3][600];
  for (int t = 0; t < 3; t++) {
    CHECK_OK(read_on(path, (int[]){1, 2, 0}[t], &back[t], msg[t], sizeof msg[t]));
    CHECK(same_shape(&img, &back[t]) && memcmp(back[t].data, img.data, (size_t)48 * 1000 * 2 * 4) == 0);
    jnd_image_free(&back[t]);
  }
  /* garbage in the deflate data of the chunks holding rows 500 and 900 (one
   * alone, then both): the message is the one of the first in the file,
   * whatever the threads did */
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  uint64_t off[2], size[2];
  CHECK(buf && exr_chunk_bytes(path, 500, &off[0], &size[0]) && exr_chunk_bytes(path, 900, &off[1], &size[1]));
  char first[600] = "", later[600] = "";
  for (int c = 1; buf && c >= 0; c--) { /* the later chunk alone, then both */
    for (uint64_t i = size[c] / 4; i < size[c] / 2; i++) buf[off[c] + i] ^= 0x5a;
    CHECK(write_bytes(bad, buf, n));
    for (int t = 0; t < 3; t++) {
      CHECK_STATUS(read_on(bad, (int[]){1, 2, 0}[t], &back[t], msg[t], sizeof msg[t]), JND_ERR_FORMAT);
      CHECK(back[t].data == NULL);
      CHECK(strstr(msg[t], "chunks_bad.exr") && strchr(msg[t], '\n') == NULL);
      CHECK(strcmp(msg[t], msg[0]) == 0);
    }
    snprintf(c ? later : first, sizeof first, "%s", msg[0]);
  }
  /* the library's message gives the chunk's packed size (481 and 479
   * bytes here): with both chunks bad, it is the earlier one's */
  CHECK(first[0] && later[0] && strcmp(first, later) != 0);
  free(buf);
  jnd_image_free(&img);
}

TEST(exr_errors_name_the_file_on_one_line) {
  static const unsigned char junk[] = {0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0, 'x', 'y'};
  jnd_image back;
  CHECK_STATUS(jnd_decode_exr("junk.exr", junk, sizeof junk, &back, NULL), JND_ERR_FORMAT);
  CHECK(strncmp(jnd_last_error(), "junk.exr: ", 10) == 0);
  CHECK(strchr(jnd_last_error(), '\n') == NULL);
}

TEST(exr_claiming_more_than_the_size_limit_is_refused) {
  const char *path = tmp_file("huge.exr");
  jnd_image img = pattern(16, 16, 1, 0, 1, 11), back;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  unsigned char *dwa = buf ? find_bytes(buf, n, "dataWindow\0box2i\0", 17) : NULL;
  CHECK(dwa != NULL);
  if (dwa) {
    put_le32(dwa + 17 + 4 + 8, 40000); /* max.x */
    CHECK_STATUS(jnd_decode_exr("huge.exr", buf, n, &back, NULL), JND_ERR_LIMIT);
    CHECK(strstr(jnd_last_error(), "limit") != NULL);
    put_le32(dwa + 17 + 4 + 8, 10000); /* within the limits, but 10001² pixels from a few hundred bytes */
    put_le32(dwa + 17 + 4 + 12, 10000);
    CHECK_STATUS(jnd_decode_exr("huge.exr", buf, n, &back, NULL), JND_ERR_FORMAT);
  }
  free(buf);
  jnd_image_free(&img);
}

TEST(exr_with_subsampled_channels_is_refused) {
  const char *path = tmp_file("sub.exr");
  jnd_image img = pattern(8, 8, 1, 0, 1, 12), back;
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  unsigned char *cl = buf ? find_bytes(buf, n, "channels\0chlist\0", 16) : NULL;
  CHECK(cl != NULL);
  if (cl) {
    put_le32(cl + 16 + 4 + 2 + 8, 2); /* after the size, "Y\0", type, pLinear + reserved: xSampling */
    CHECK_STATUS(jnd_decode_exr("sub.exr", buf, n, &back, NULL), JND_ERR_FORMAT);
    CHECK(strstr(jnd_last_error(), "sub.exr") != NULL);
    CHECK(back.data == NULL);
  }
  free(buf);
  jnd_image_free(&img);
}

TEST(exr_write_is_atomic_and_leaves_no_temporary_file) {
  const char *path = tmp_file("atomic.exr");
  jnd_image img = pattern(8, 8, 3, 0, 1, 13);
  CHECK_OK(jnd_image_write_exr(path, &img, NULL, 0));
  char cmd[1400];
  snprintf(cmd, sizeof cmd, "ls '%s' | grep -q 'atomic.exr.tmp'", test_tmp_dir());
  CHECK(system(cmd) != 0);
  /* a folder that does not exist: an error, nothing written */
  CHECK_STATUS(jnd_image_write_exr("/nonexistent-folder/x.exr", &img, NULL, 0), JND_ERR_IO);
  jnd_image_free(&img);
}

/* ---- PNG ---- */

TEST(png_8_bit_round_trips_for_1_to_4_channels) {
  for (int c = 1; c <= 4; c++) {
    const char *path = tmp_file("rt8.png");
    jnd_image img = pattern(17, 9, c, 0, 1, 20 + c), back;
    jnd_image_info info;
    for (size_t i = 0; i < (size_t)17 * 9 * c; i++) img.data[i] = roundf(img.data[i] * 255) / 255;
    CHECK_OK(jnd_image_write_png(path, &img, 8));
    CHECK_OK(jnd_image_read(path, &back, &info));
    CHECK(same_shape(&img, &back));
    if (same_shape(&img, &back)) CHECK_LT(max_abs_diff(&img, &back), 1e-6);
    CHECK(info.bits == 8 && info.channels == c && info.has_alpha == (c == 2 || c == 4));
    CHECK(info.encoding == JND_ENCODING_SRGB && strcmp(info.format, "png") == 0);
    jnd_image_free(&img);
    jnd_image_free(&back);
  }
}

TEST(png_16_bit_round_trips_to_within_one_code) {
  const char *path = tmp_file("rt16.png");
  jnd_image img = pattern(31, 7, 3, 0, 1, 30), back;
  jnd_image_info info;
  CHECK_OK(jnd_image_write_png(path, &img, 16));
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(same_shape(&img, &back) && info.bits == 16);
  if (same_shape(&img, &back)) CHECK_LT(max_abs_diff(&img, &back), 0.5 / 65535 + 1e-7);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

TEST(png_written_in_many_pieces_reads_back_through_both_decoders_and_is_the_same_bytes_for_any_thread_count) {
  /* 1.2 MB of 8-bit samples and 1.8 MB of 16-bit ones: several deflate
   * pieces of ~256 KB; smooth ramps, noise and flat areas so that rows pick
   * different filters */
  for (int bits = 8; bits <= 16; bits += 8) {
    const int w = 640, h = bits == 8 ? 640 : 240, c = bits == 8 ? 3 : 4;
    jnd_image img = pattern(w, h, c, 0, 1, 77 + bits), back;
    for (int ch = 0; ch < c; ch++)
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
          float *v = &jnd_image_plane(&img, ch)[(size_t)y * w + x];
          if (y < h / 3) *v = (float)((x + ch * 7) % 256) / 255; /* ramps: Sub */
          else if (y < h / 2) *v = 64.0f / 255;                  /* flat: None or Up */
          else if (bits == 8) *v = roundf(*v * 255) / 255;      /* noise */
        }
    const char *p1 = tmp_file("pieces1.png"), *p4 = tmp_file("pieces4.png");
    omp_set_num_threads(1);
    CHECK_OK(jnd_image_write_png(p1, &img, bits));
    omp_set_num_threads(4);
    CHECK_OK(jnd_image_write_png(p4, &img, bits));
    size_t n1 = 0, n4 = 0;
    unsigned char *b1 = read_bytes(p1, &n1), *b4 = read_bytes(p4, &n4);
    CHECK(b1 && b4 && n1 == n4 && memcmp(b1, b4, n1) == 0);
    CHECK(n1 > 0 && n1 < (size_t)w * h * c * (bits / 8)); /* it compresses */
    /* one zlib stream whose Adler-32 holds (our decoders do not check it; zlib's uncompress does) */
    if (b1 && n1 > 8 + 25 + 8) {
      size_t idat = (size_t)b1[33] << 24 | (size_t)b1[34] << 16 | (size_t)b1[35] << 8 | b1[36];
      CHECK(memcmp(b1 + 37, "IDAT", 4) == 0 && 41 + idat + 4 <= n1);
      uLongf rn = (uLongf)((size_t)(1 + w * c * (bits / 8)) * h);
      unsigned char *rows = malloc(rn);
      CHECK(rows && uncompress(rows, &rn, b1 + 41, (uLong)idat) == Z_OK);
      CHECK(rn == (uLongf)((size_t)(1 + w * c * (bits / 8)) * h));
      free(rows);
    }
    CHECK_OK(jnd_decode_png("pieces.png", b1, n1, &back, NULL));
    CHECK(same_shape(&img, &back));
    if (same_shape(&img, &back)) CHECK_LT(max_abs_diff(&img, &back), bits == 8 ? 1e-6 : 0.5 / 65535 + 1e-7);
    jnd_image_free(&back);
    CHECK_OK(jnd_decode_png_stb("pieces.png", b1, n1, &back, NULL));
    if (same_shape(&img, &back)) CHECK_LT(max_abs_diff(&img, &back), bits == 8 ? 1e-6 : 0.5 / 65535 + 1e-7);
    jnd_image_free(&back);
    free(b1);
    free(b4);
    jnd_image_free(&img);
  }
  omp_set_num_threads(omp_get_num_procs());
}

TEST(png_8_bit_codes_are_the_values_rounded_in_double) {
  /* the writer's quantisation: code = floor(v · 255 + 0.5) in double for v
   * clamped to 0..1 (float arithmetic rounds some values near half a code
   * the other way) */
  const int w = 1000, h = 100;
  jnd_image img = pattern(w, h, 1, -0.05, 1.05, 91), back;
  for (int i = 0; i < 2000; i++) img.data[i] = (float)((i % 256 + 0.5) / 255.0); /* half codes */
  const char *path = tmp_file("codes.png");
  CHECK_OK(jnd_image_write_png(path, &img, 8));
  CHECK_OK(jnd_image_read(path, &back, NULL));
  int wrong = 0;
  for (int i = 0; i < w * h; i++) {
    double v = img.data[i] < 0 ? 0 : img.data[i] > 1 ? 1 : img.data[i];
    int want = (int)(v * 255.0 + 0.5), got = (int)lround(back.data[i] * 255.0);
    wrong += want != got;
  }
  CHECK(wrong == 0);
  jnd_image_free(&img);
  jnd_image_free(&back);
}

static unsigned char *small_png(size_t *n) {
  jnd_image img = pattern(6, 5, 3, 0, 1, 31);
  const char *path = tmp_file("small.png");
  jnd_image_write_png(path, &img, 8);
  jnd_image_free(&img);
  return read_bytes(path, n);
}

TEST(png_with_bad_crc_is_refused) {
  size_t n;
  unsigned char *buf = small_png(&n);
  jnd_image back;
  CHECK(buf != NULL);
  if (!buf) return;
  buf[8 + 8 + 13] ^= 1; /* IHDR's CRC */
  CHECK_STATUS(jnd_decode_png("bad.png", buf, n, &back, NULL), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "bad.png") && strstr(jnd_last_error(), "CRC"));
  buf[8 + 8 + 13] ^= 1;
  buf[8 + 25 + 8 + 2] ^= 0x40; /* a byte inside IDAT */
  CHECK_STATUS(jnd_decode_png("bad.png", buf, n, &back, NULL), JND_ERR_FORMAT);
  free(buf);
}

TEST(every_truncation_of_a_png_is_refused) {
  size_t n;
  unsigned char *buf = small_png(&n);
  jnd_image back;
  int accepted = 0;
  for (size_t k = 0; buf && k < n; k++) {
    if (jnd_decode_png("cut.png", buf, k, &back, NULL) == JND_OK) accepted++;
    jnd_image_free(&back);
  }
  CHECK(buf && accepted == 0);
  free(buf);
}

TEST(png_without_iend_is_refused) {
  size_t n;
  unsigned char *buf = small_png(&n);
  jnd_image back;
  CHECK(buf != NULL);
  if (!buf) return;
  CHECK_STATUS(jnd_decode_png("noend.png", buf, n - 12, &back, NULL), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "IEND") != NULL);
  free(buf);
}

TEST(png_claiming_more_than_the_size_limit_is_refused) {
  size_t n;
  unsigned char *buf = small_png(&n);
  jnd_image back;
  CHECK(buf != NULL);
  if (!buf) return;
  put_be32(buf + 16, 40000); /* IHDR width, then a valid CRC */
  put_be32(buf + 8 + 8 + 13, jnd_crc32(buf + 12, 17));
  CHECK_STATUS(jnd_decode_png("wide.png", buf, n, &back, NULL), JND_ERR_LIMIT);
  put_be32(buf + 16, 10000); /* within the limits, but far more than the data holds */
  put_be32(buf + 20, 10000);
  put_be32(buf + 8 + 8 + 13, jnd_crc32(buf + 12, 17));
  CHECK_STATUS(jnd_decode_png("wide.png", buf, n, &back, NULL), JND_ERR_FORMAT);
  CHECK(back.data == NULL);
  free(buf);
}

/* ---- PNG: the zlib path against stb_image ---- */

/* PNG files written here byte by byte (PNG spec §5, §9–§11), for layouts
 * jnd_image_write_png never writes: every filter type, 16-bit alpha,
 * palettes, 1-bit grey, Adam7. */
typedef struct {
  int w, h, colour, depth, interlace;
  const unsigned char *plte; /* colour type 3: plte_n bytes */
  size_t plte_n;
} png_layout;

static size_t png_samples(int colour) { return colour == 2 ? 3 : colour == 4 ? 2 : colour == 6 ? 4 : 1; }

static size_t png_row_bytes(const png_layout *L, int w) {
  return ((size_t)w * png_samples(L->colour) * L->depth + 7) / 8;
}

static int predict_paeth(int a, int b, int c) {
  int pa = abs(b - c), pb = abs(a - c), pc = abs(a + b - 2 * c); /* |p − a|, |p − b|, |p − c| */
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* h rows of row bytes, row y filtered with type (first + y) % 5 (PNG spec
 * §9.2): h × (1 + row) bytes. */
static unsigned char *filter_rows(const unsigned char *raw, size_t row, int h, size_t bpp, int first) {
  unsigned char *out = malloc((1 + row) * h);
  for (int y = 0; y < h; y++) {
    const unsigned char *x = raw + row * y, *b = y ? x - row : NULL;
    unsigned char *f = out + (1 + row) * y;
    f[0] = (unsigned char)((first + y) % 5);
    for (size_t i = 0; i < row; i++) {
      int a = i >= bpp ? x[i - bpp] : 0, up = b ? b[i] : 0, c = b && i >= bpp ? b[i - bpp] : 0;
      int pred[5] = {0, a, up, (a + up) / 2, predict_paeth(a, up, c)};
      f[1 + i] = (unsigned char)(x[i] - pred[f[0]]);
    }
  }
  return out;
}

/* The file: signature, IHDR, PLTE if any, a tEXt, the zlib stream spread
 * over IDAT chunks of 1 byte, half the rest, nothing, and the rest, then IEND. */
static unsigned char *png_wrap(const png_layout *L, const unsigned char *z, size_t zn, size_t *n) {
  unsigned char *out = malloc(8 + 25 + (12 + L->plte_n) + (12 + 11) + (4 * 12 + zn) + 12), ihdr[13];
  size_t pos = 8, cut[5] = {0, zn ? 1 : 0, 0, 0, zn};
  cut[2] = cut[3] = cut[1] + (zn - cut[1]) / 2;
  memcpy(out, "\x89PNG\r\n\x1a\n", 8);
  put_be32(ihdr, (uint32_t)L->w);
  put_be32(ihdr + 4, (uint32_t)L->h);
  ihdr[8] = (unsigned char)L->depth;
  ihdr[9] = (unsigned char)L->colour;
  ihdr[10] = ihdr[11] = 0;
  ihdr[12] = (unsigned char)L->interlace;
  const struct { const char *type; const unsigned char *data; size_t len; } chunks[] = {
      {"IHDR", ihdr, 13},
      {L->plte ? "PLTE" : NULL, L->plte, L->plte_n},
      {"tEXt", (const unsigned char *)"Comment\0jnd", 11},
      {"IDAT", z, cut[1]},
      {"IDAT", z + cut[1], cut[2] - cut[1]},
      {"IDAT", z + cut[2], 0},
      {"IDAT", z + cut[3], cut[4] - cut[3]},
      {"IEND", NULL, 0},
  };
  for (size_t k = 0; k < sizeof chunks / sizeof chunks[0]; k++) {
    if (!chunks[k].type) continue;
    put_be32(out + pos, (uint32_t)chunks[k].len);
    memcpy(out + pos + 4, chunks[k].type, 4);
    if (chunks[k].len) memcpy(out + pos + 8, chunks[k].data, chunks[k].len);
    put_be32(out + pos + 8 + chunks[k].len, jnd_crc32(out + pos + 4, chunks[k].len + 4));
    pos += chunks[k].len + 12;
  }
  *n = pos;
  return out;
}

/* The file for the image data (filtered rows) data, deflated by zlib. */
static unsigned char *png_from_image_data(const png_layout *L, const unsigned char *data, size_t len, size_t *n) {
  uLongf zn = compressBound((uLong)len);
  unsigned char *z = malloc(zn);
  compress2(z, &zn, data, (uLong)len, 9);
  unsigned char *file = png_wrap(L, z, zn, n);
  free(z);
  return file;
}

/* Random samples for a plain layout (8 or 16 bits), filtered from type first. */
static unsigned char *plain_png(const png_layout *L, uint64_t seed, int first, unsigned char **raw, size_t *n) {
  size_t row = png_row_bytes(L, L->w);
  jnd_rng r;
  jnd_rng_seed(&r, seed);
  *raw = malloc(row * L->h);
  for (size_t i = 0; i < row * L->h; i++) (*raw)[i] = (unsigned char)jnd_rng_next(&r);
  unsigned char *data = filter_rows(*raw, row, L->h, png_samples(L->colour) * L->depth / 8, first);
  unsigned char *file = png_from_image_data(L, data, (1 + row) * L->h, n);
  free(data);
  return file;
}

/* Both paths decode buf to the same floats, bit for bit, and the same info;
 * and an 8-bit RGB file kept as its codes (jnd_png_decode_rgb8) has the
 * codes of those floats (code / 255), any other is refused by it. */
static int png_paths_agree(const char *name, const unsigned char *buf, size_t n) {
  jnd_image a, b;
  jnd_image_info ia, ib;
  jnd_status sa = jnd_decode_png(name, buf, n, &a, &ia), sb = jnd_decode_png_stb(name, buf, n, &b, &ib);
  int same = sa == JND_OK && sb == JND_OK && same_shape(&a, &b) &&
             memcmp(a.data, b.data, sizeof(float) * a.w * a.h * a.c) == 0 && memcmp(&ia, &ib, sizeof ia) == 0;
  if (!same) fprintf(stderr, "%s: the zlib path (%d) and stb_image (%d) differ: %s\n", name, sa, sb, jnd_last_error());
  unsigned char *rgb = NULL;
  int w = -1, h = -1;
  const int is_rgb8 = sb == JND_OK && b.c == 3 && ib.bits == 8;
  if (same && jnd_png_is_rgb8(buf, n) != is_rgb8) {
    fprintf(stderr, "%s: jnd_png_is_rgb8 says %d\n", name, !is_rgb8);
    same = 0;
  }
  jnd_status sc = jnd_png_decode_rgb8(name, buf, n, &rgb, &w, &h);
  if (same && is_rgb8) {
    const size_t npx = (size_t)b.w * b.h;
    size_t bad = sc != JND_OK || w != b.w || h != b.h;
    for (size_t i = 0; !bad && i < npx * 3; i++)
      bad += jnd_image_plane(&b, (int)(i % 3))[i / 3] != (float)(rgb[i] * (1.0 / 255));
    if (bad) fprintf(stderr, "%s: its codes are not its samples (%d)\n", name, sc);
    same = !bad;
  } else if (same && (sc != JND_ERR_FORMAT || rgb)) {
    fprintf(stderr, "%s: kept as codes though not 8-bit RGB\n", name);
    same = 0;
  }
  free(rgb);
  jnd_image_free(&a);
  jnd_image_free(&b);
  return same;
}

TEST(png_zlib_path_matches_stb_for_every_plain_layout_filter_and_odd_width) {
  static const int colours[4] = {0, 2, 4, 6}, widths[3] = {1, 3, 17};
  for (int k = 0; k < 4 * 2 * 3 * 5; k++) {
    png_layout L = {widths[k / 5 % 3], 7, colours[k / 30], k / 15 % 2 ? 16 : 8, 0, NULL, 0};
    unsigned char *raw;
    size_t n;
    unsigned char *buf = plain_png(&L, 100 + k, k % 5, &raw, &n);
    char name[64];
    snprintf(name, sizeof name, "c%d_d%d_w%d_f%d.png", L.colour, L.depth, L.w, k % 5);
    CHECK(jnd_png_plain(buf, n));
    CHECK(png_paths_agree(name, buf, n));
    /* and the samples themselves, not only stb's reading of them */
    jnd_image img;
    jnd_image_info info;
    CHECK_OK(jnd_decode_png(name, buf, n, &img, &info));
    size_t c = png_samples(L.colour), bad = 0;
    for (size_t i = 0; img.data && i < (size_t)L.w * L.h * c; i++) {
      size_t px = i / c, ch = i % c;
      unsigned v = L.depth == 8 ? raw[i] : (unsigned)(raw[2 * i] << 8 | raw[2 * i + 1]);
      bad += jnd_image_plane(&img, (int)ch)[px] != (float)(v * (1.0 / (L.depth == 8 ? 255 : 65535)));
    }
    CHECK(img.data && bad == 0 && info.bits == L.depth && info.channels == (int)c);
    jnd_image_free(&img);
    free(raw);
    free(buf);
  }
}

/* Rows of 3- and 4-byte pixels are unfiltered four at a time, each row two
 * pixels behind the one above (png.c, png_unfilter_wave), and rows of up to
 * 3 bytes a pixel inflated into the end of the image's own memory where a
 * row is short enough (png_in_place: RGB from 18 pixels wide, grey from
 * 6): every height (whole and short groups), widths shorter and longer than
 * the wave's start and either side of the in-place bound, every mix of
 * filter types in a group, on both decoding paths — libdeflate's whole
 * stream, and zlib's blocks when data follows the rows — give stb_image's
 * floats and the samples themselves. */
TEST(png_rows_unfiltered_in_groups_and_in_place_match_stb_for_every_height_width_and_filter_mix) {
  static const int layouts[4][2] = {{2, 8}, {6, 8}, {4, 16}, {0, 8}}, widths[8] = {1, 2, 5, 6, 7, 17, 18, 41};
  int bad = 0, n_files = 0;
  for (int k = 0; k < 4 * 8 * 11 * 5; k++) {
    const int lay = k / 440, width = widths[k / 55 % 8], h = 1 + k / 5 % 11, first = k % 5;
    png_layout L = {width, h, layouts[lay][0], layouts[lay][1], 0, NULL, 0};
    size_t row = png_row_bytes(&L, L.w), c = png_samples(L.colour);
    jnd_rng r;
    jnd_rng_seed(&r, 7000 + (uint64_t)k);
    unsigned char *raw = malloc(row * h);
    for (size_t i = 0; i < row * h; i++) raw[i] = (unsigned char)jnd_rng_next(&r);
    unsigned char *data = filter_rows(raw, row, h, c * L.depth / 8, first);
    for (int extra = 0; extra < 2; extra++) { /* extra: bytes after the rows, zlib's path */
      size_t len = (1 + row) * h, n;
      unsigned char *more = calloc(len + 9, 1);
      memcpy(more, data, len);
      unsigned char *buf = png_from_image_data(&L, more, len + (extra ? 9 : 0), &n);
      char name[64];
      snprintf(name, sizeof name, "c%d_d%d_w%d_h%d_f%d_x%d.png", L.colour, L.depth, L.w, h, first, extra);
      jnd_image img;
      int same = png_paths_agree(name, buf, n) && jnd_decode_png(name, buf, n, &img, NULL) == JND_OK;
      for (size_t i = 0; same && i < (size_t)L.w * h * c; i++) {
        unsigned v = L.depth == 8 ? raw[i] : (unsigned)(raw[2 * i] << 8 | raw[2 * i + 1]);
        same = jnd_image_plane(&img, (int)(i % c))[i / c] == (float)(v * (1.0 / (L.depth == 8 ? 255 : 65535)));
      }
      if (same) jnd_image_free(&img);
      else fprintf(stderr, "%s: decoded wrong\n", name);
      bad += !same;
      n_files++;
      free(buf);
      free(more);
    }
    free(data);
    free(raw);
  }
  CHECK(bad == 0 && n_files == 2 * 1760);
}

TEST(png_zlib_path_matches_stb_on_the_kodak_photographs) {
  const char *data = test_shared_data();
  if (!data) {
    TEST_SKIP("no shared data");
    return;
  }
  char dir[1100];
  snprintf(dir, sizeof dir, "%s/kodak", data);
  DIR *d = opendir(dir);
  CHECK(d != NULL); /* the shared data has the Kodak set */
  if (!d) return;
  int seen = 0;
  struct dirent *e;
  while ((e = readdir(d))) {
    size_t len = strlen(e->d_name), n;
    if (len < 4 || strcmp(e->d_name + len - 4, ".png") != 0) continue;
    char path[1400];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    unsigned char *buf = read_bytes(path, &n);
    CHECK(buf && jnd_png_plain(buf, n));
    CHECK(buf && png_paths_agree(path, buf, n));
    free(buf);
    seen++;
  }
  closedir(d);
  CHECK(seen > 0);
}

TEST(png_with_data_after_the_last_row_decodes) {
  png_layout L = {5, 3, 2, 8, 0, NULL, 0};
  unsigned char data[3 * 16 + 40] = {0};
  for (size_t i = 0; i < sizeof data; i++) data[i] = i % 16 ? (unsigned char)(7 * i) : 0; /* filter None */
  size_t n;
  unsigned char *buf = png_from_image_data(&L, data, sizeof data, &n);
  CHECK(png_paths_agree("extra.png", buf, n));
  free(buf);
}

/* The filtered rows of a 9 × 4 RGB image. */
static unsigned char *rgb_image_data(size_t *len) {
  png_layout L = {9, 4, 2, 8, 0, NULL, 0};
  unsigned char raw[27 * 4];
  for (size_t i = 0; i < sizeof raw; i++) raw[i] = (unsigned char)(i * 37);
  *len = (1 + 27) * 4;
  return filter_rows(raw, png_row_bytes(&L, L.w), L.h, 3, 0);
}

TEST(png_with_a_truncated_deflate_stream_is_refused_naming_the_file) {
  png_layout L = {9, 4, 2, 8, 0, NULL, 0};
  size_t len, n;
  unsigned char *data = rgb_image_data(&len);
  for (size_t cut = 1; cut < len; cut += 7) { /* the rows cut short, each stream complete */
    unsigned char *buf = png_from_image_data(&L, data, cut, &n);
    jnd_image img;
    CHECK_STATUS(jnd_decode_png("short.png", buf, n, &img, NULL), JND_ERR_FORMAT);
    CHECK(img.data == NULL && strstr(jnd_last_error(), "short.png: truncated PNG ("));
    free(buf);
  }
  uLongf zn = compressBound((uLong)len);
  unsigned char *z = malloc(zn);
  compress2(z, &zn, data, (uLong)len, 9);
  unsigned char *rows = malloc(len);
  for (size_t keep = 0; keep < zn; keep++) { /* the stream cut short, the CRCs valid */
    uLongf got = len;
    uLong used = keep;
    uncompress2(rows, &got, z, &used);
    unsigned char *buf = png_wrap(&L, z, keep, &n);
    jnd_image img;
    if (got == len) { /* only the end-of-stream marks are gone: every row is there */
      CHECK_OK(jnd_decode_png("cut.png", buf, n, &img, NULL));
    } else {
      CHECK_STATUS(jnd_decode_png("cut.png", buf, n, &img, NULL), JND_ERR_FORMAT);
      CHECK(img.data == NULL && strstr(jnd_last_error(), "cut.png: ") && strstr(jnd_last_error(), " PNG ("));
    }
    jnd_image_free(&img);
    free(buf);
  }
  free(rows);
  free(z);
  free(data);
}

TEST(png_row_with_filter_type_5_is_refused_naming_the_file) {
  png_layout L = {9, 4, 2, 8, 0, NULL, 0};
  size_t len, n;
  unsigned char *data = rgb_image_data(&len);
  data[2 * 28] = 5; /* the third row's filter type */
  unsigned char *buf = png_from_image_data(&L, data, len, &n);
  jnd_image img;
  CHECK_STATUS(jnd_decode_png("filter5.png", buf, n, &img, NULL), JND_ERR_FORMAT);
  CHECK(img.data == NULL && strstr(jnd_last_error(), "filter5.png: corrupt PNG (row 3 has filter type 5"));
  free(buf);
  free(data);
}

TEST(png_with_garbage_deflate_data_is_refused_naming_the_file) {
  png_layout L = {9, 4, 2, 8, 0, NULL, 0};
  unsigned char z[64];
  memset(z, 0xFF, sizeof z); /* after a valid zlib header, a block of the reserved type 3 */
  z[0] = 0x78;
  z[1] = 0xDA;
  size_t n;
  unsigned char *buf = png_wrap(&L, z, sizeof z, &n);
  jnd_image img;
  CHECK_STATUS(jnd_decode_png("garbage.png", buf, n, &img, NULL), JND_ERR_FORMAT);
  CHECK(img.data == NULL && strstr(jnd_last_error(), "garbage.png: corrupt PNG ("));
  free(buf);
  jnd_rng r; /* nor any random bytes */
  jnd_rng_seed(&r, 7);
  for (int k = 0; k < 200; k++) {
    for (size_t i = 0; i < sizeof z; i++) z[i] = (unsigned char)jnd_rng_next(&r);
    buf = png_wrap(&L, z, sizeof z, &n);
    CHECK_STATUS(jnd_decode_png("noise.png", buf, n, &img, NULL), JND_ERR_FORMAT);
    CHECK(img.data == NULL && strstr(jnd_last_error(), "noise.png: "));
    free(buf);
  }
}

TEST(palette_1_bit_and_interlaced_pngs_still_decode_through_stb) {
  jnd_image img;
  jnd_image_info info;
  size_t n;
  /* palette: 3 × 2 indices into 3 colours */
  static const unsigned char plte[9] = {255, 0, 0, 0, 128, 0, 10, 20, 30};
  png_layout P = {3, 2, 3, 8, 0, plte, 9};
  static const unsigned char pdata[8] = {0, 0, 1, 2, 0, 2, 2, 1};
  unsigned char *buf = png_from_image_data(&P, pdata, sizeof pdata, &n);
  CHECK(!jnd_png_plain(buf, n));
  CHECK_OK(jnd_decode_png("palette.png", buf, n, &img, &info));
  CHECK(img.c == 3 && info.bits == 8);
  if (img.data) CHECK(jnd_image_plane(&img, 1)[4] == (float)(20 * (1.0 / 255))); /* pixel (1, 1): colour 2 */
  jnd_image_free(&img);
  free(buf);
  /* 1-bit grey: 10 × 1, 1 0 1 1 0 0 0 0 1 0 */
  png_layout B = {10, 1, 0, 1, 0, NULL, 0};
  static const unsigned char bdata[3] = {0, 0xB0, 0x80};
  buf = png_from_image_data(&B, bdata, sizeof bdata, &n);
  CHECK(!jnd_png_plain(buf, n));
  CHECK_OK(jnd_decode_png("bits.png", buf, n, &img, &info));
  if (img.data) CHECK(img.data[0] == 1 && img.data[1] == 0 && img.data[3] == 1 && img.data[8] == 1 && img.data[9] == 0);
  jnd_image_free(&img);
  free(buf);
  /* Adam7 (PNG spec §8.2): 5 × 5 RGB, each pass's rows unfiltered */
  static const int x0[7] = {0, 4, 0, 2, 0, 1, 0}, y0[7] = {0, 0, 4, 0, 2, 0, 1};
  static const int dx[7] = {8, 8, 4, 4, 2, 2, 1}, dy[7] = {8, 8, 8, 4, 4, 2, 2};
  png_layout A = {5, 5, 2, 8, 1, NULL, 0};
  unsigned char adata[200];
  size_t len = 0;
  for (int p = 0; p < 7; p++)
    for (int y = y0[p]; x0[p] < A.w && y < A.h; y += dy[p]) {
      adata[len++] = 0;
      for (int x = x0[p]; x < A.w; x += dx[p])
        for (int ch = 0; ch < 3; ch++) adata[len++] = (unsigned char)(10 * (y * A.w + x) + ch);
    }
  buf = png_from_image_data(&A, adata, len, &n);
  CHECK(!jnd_png_plain(buf, n));
  CHECK_OK(jnd_decode_png("adam7.png", buf, n, &img, &info));
  int bad = !img.data;
  for (int i = 0; img.data && i < 25; i++)
    for (int ch = 0; ch < 3; ch++) bad += jnd_image_plane(&img, ch)[i] != (float)((10 * i + ch) * (1.0 / 255));
  CHECK(bad == 0);
  jnd_image_free(&img);
  free(buf);
}

/* ---- any image ---- */

TEST(empty_file_is_refused) {
  const char *path = tmp_file("empty.png");
  jnd_image back;
  CHECK(write_bytes(path, "", 0));
  CHECK_STATUS(jnd_image_read(path, &back, NULL), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "empty") != NULL);
}

TEST(non_image_file_is_refused_naming_it) {
  const char *path = tmp_file("notes.png");
  jnd_image back;
  CHECK(write_bytes(path, "hello, world\n", 13));
  CHECK_STATUS(jnd_image_read(path, &back, NULL), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "notes.png") != NULL);
  CHECK_STATUS(jnd_image_read(tmp_file("missing.png"), &back, NULL), JND_ERR_IO);
  CHECK_STATUS(jnd_image_read(test_tmp_dir(), &back, NULL), JND_ERR_IO);
}

TEST(jpeg_reads_as_srgb_8_bit) {
  const char *path = tmp_file("grey.jpg");
  unsigned char px[16 * 16 * 3];
  for (int i = 0; i < 16 * 16 * 3; i++) px[i] = 128;
  CHECK(stbi_write_jpg(path, 16, 16, 3, px, 95));
  jnd_image back;
  jnd_image_info info;
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(back.w == 16 && back.h == 16 && back.c == 3);
  CHECK(info.encoding == JND_ENCODING_SRGB && info.bits == 8 && strcmp(info.format, "jpeg") == 0);
  if (back.data) CHECK_NEAR(back.data[100], 128.0 / 255, 2.0 / 255);
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  jnd_image cut;
  if (buf) CHECK_STATUS(jnd_decode_jpeg("cut.jpg", buf, n / 2, &cut, NULL), JND_ERR_FORMAT);
  free(buf);
  jnd_image_free(&back);
}

TEST(radiance_hdr_reads_as_linear) {
  const char *path = tmp_file("sky.hdr");
  float px[8 * 4 * 3];
  for (int i = 0; i < 8 * 4 * 3; i++) px[i] = 0.5f * (float)(i % 3 + 1);
  CHECK(stbi_write_hdr(path, 8, 4, 3, px));
  jnd_image back;
  jnd_image_info info;
  CHECK_OK(jnd_image_read(path, &back, &info));
  CHECK(back.w == 8 && back.h == 4 && back.c == 3);
  CHECK(info.encoding == JND_ENCODING_LINEAR && strcmp(info.format, "hdr") == 0);
  if (back.data) {
    CHECK_NEAR(jnd_image_plane(&back, 0)[5], 0.5, 0.01);
    CHECK_NEAR(jnd_image_plane(&back, 2)[5], 1.5, 0.01);
  }
  jnd_image_free(&back);
}

TEST(jpeg_using_an_undefined_huffman_table_is_refused) {
  /* stb_image would decode with uninitialised tables, or abort on an assertion */
  const char *path = tmp_file("grey1.jpg");
  unsigned char px[16 * 16];
  for (int i = 0; i < 256; i++) px[i] = (unsigned char)i;
  CHECK(stbi_write_jpg(path, 16, 16, 1, px, 90));
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  unsigned char *sos = buf ? find_bytes(buf, n, "\xFF\xDA", 2) : NULL;
  CHECK(sos != NULL);
  jnd_image back;
  if (sos) {
    CHECK_OK(jnd_decode_jpeg("grey1.jpg", buf, n, &back, NULL));
    jnd_image_free(&back);
    sos[2 + 2 + 1 + 1] = 0x22; /* the scan's only component now uses DC and AC tables 2 */
    CHECK_STATUS(jnd_decode_jpeg("grey1.jpg", buf, n, &back, NULL), JND_ERR_FORMAT);
    CHECK(strstr(jnd_last_error(), "Huffman") != NULL);
  }
  free(buf);
}

TEST(radiance_hdr_with_truncated_runs_is_refused_not_hung) {
  /* stb_image loops for ever when run-length data ends early */
  const char *path = tmp_file("runs.hdr");
  float px[32 * 4 * 3];
  for (int i = 0; i < 32 * 4 * 3; i++) px[i] = 1.0f + (float)(i % 5);
  CHECK(stbi_write_hdr(path, 32, 4, 3, px)); /* 32 wide: run-length scanlines */
  size_t n;
  unsigned char *buf = read_bytes(path, &n);
  jnd_image back;
  CHECK(buf != NULL);
  for (size_t cut = 1; buf && cut < 40; cut++) {
    CHECK_STATUS(jnd_decode_hdr("runs.hdr", buf, n - cut, &back, NULL), JND_ERR_FORMAT);
    CHECK(back.data == NULL);
  }
  if (buf) CHECK_OK(jnd_decode_hdr("runs.hdr", buf, n, &back, NULL));
  jnd_image_free(&back);
  free(buf);
  /* stb ends the header at a line that starts with a NUL, not only at an empty one */
  static const char nul_line[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\0x\n-Y 2 +X 16\n\2\2\0\20\220\1";
  CHECK_STATUS(jnd_decode_hdr("nul.hdr", (const unsigned char *)nul_line, sizeof nul_line - 1, &back, NULL),
               JND_ERR_FORMAT);
}

TEST(each_decoder_refuses_other_formats) {
  /* stb_image guesses formats; a PNM must not reach it through the HDR decoder */
  static const char pnm[] = "P5\n2 1\n469\n\0\1\0\2";
  jnd_image back;
  CHECK_STATUS(jnd_decode_hdr("x.hdr", (const unsigned char *)pnm, sizeof pnm - 1, &back, NULL), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_decode_jpeg("x.jpg", (const unsigned char *)pnm, sizeof pnm - 1, &back, NULL), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_decode_png("x.png", (const unsigned char *)pnm, sizeof pnm - 1, &back, NULL), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_decode_exr("x.exr", (const unsigned char *)pnm, sizeof pnm - 1, &back, NULL), JND_ERR_FORMAT);
}

/* ---- CSV ---- */

TEST(csv_reads_quoted_fields_with_commas_quotes_and_newlines) {
  const char text[] = "\xEF\xBB\xBFname,value,note\r\n"
                      "\"a,b\",1.5,\"say \"\"hi\"\"\"\r\n"
                      "\n"
                      "c,,\"two\nlines\"\n";
  jnd_csv csv;
  CHECK_OK(jnd_csv_parse("t.csv", text, sizeof text - 1, &csv));
  CHECK(csv.ncols == 3 && csv.nrows == 2);
  if (csv.nrows == 2) {
    CHECK(strcmp(csv.header[0], "name") == 0);
    CHECK(strcmp(csv.cells[0][0], "a,b") == 0);
    CHECK(strcmp(csv.cells[0][2], "say \"hi\"") == 0);
    CHECK(strcmp(csv.cells[1][1], "") == 0);
    CHECK(strcmp(csv.cells[1][2], "two\nlines") == 0);
    CHECK(jnd_csv_column(&csv, "note") == 2 && jnd_csv_column(&csv, "nope") == -1);
  }
  jnd_csv_free(&csv);
}

TEST(csv_row_with_the_wrong_column_count_is_refused_with_its_line) {
  const char text[] = "a,b\n1,2\n3\n";
  jnd_csv csv;
  CHECK_STATUS(jnd_csv_parse("rows.csv", text, sizeof text - 1, &csv), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "rows.csv: line 3") != NULL);
  const char text2[] = "a,b\n1,2,3\n";
  CHECK_STATUS(jnd_csv_parse("rows.csv", text2, sizeof text2 - 1, &csv), JND_ERR_FORMAT);
}

TEST(csv_unterminated_quote_and_empty_input_are_refused) {
  const char text[] = "a,b\n\"1,2\n";
  jnd_csv csv;
  CHECK_STATUS(jnd_csv_parse("q.csv", text, sizeof text - 1, &csv), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_csv_parse("e.csv", "", 0, &csv), JND_ERR_FORMAT);
  CHECK_STATUS(jnd_csv_read(tmp_file("missing.csv"), &csv), JND_ERR_IO);
}

TEST(csv_numbers_parse_and_missing_values_are_nan) {
  double v;
  CHECK(jnd_csv_number(" 2.5 ", &v) && v == 2.5);
  CHECK(jnd_csv_number("NA", &v) && isnan(v));
  CHECK(jnd_csv_number("", &v) && isnan(v));
  CHECK(!jnd_csv_number("2.5x", &v));
  CHECK(!jnd_csv_number("1e999", &v));
}

/* A model's embedded textures (gltf_write.c, texres_model.c) and a written
 * PNG are one quantisation: the same codes, halfway values rounded up. */
TEST(embedded_texture_has_the_codes_the_png_writer_writes) {
  jnd_image im = {0}, a = {0}, b = {0};
  CHECK_OK(jnd_image_alloc(&im, 37, 11, 3));
  for (size_t i = 0; i < (size_t)37 * 11 * 3; i++) /* ties, values between, and out of range */
    im.data[i] = i % 3 == 0 ? (float)((i % 256) + 0.5) / 255.0f : i % 3 == 1 ? (float)(i % 997) / 996.0f : (float)(i % 7) - 3.0f;
  jnd_buf enc = {0};
  CHECK_OK(jnd_image_encode_8bit(&im, 0, &enc));
  int bits = 0;
  CHECK_OK(jnd_png_decode("embedded", enc.p, enc.n, &a, &bits));
  CHECK(bits == 8);
  const char *path = tmp_file("embedded.png");
  CHECK_OK(jnd_image_write_png(path, &im, 8));
  CHECK_OK(jnd_image_read(path, &b, NULL));
  CHECK(a.w == 37 && a.h == 11 && a.c == 3 && b.w == 37 && b.c == 3);
  size_t same = 0;
  for (size_t i = 0; a.data && b.data && i < (size_t)37 * 11 * 3; i++) same += a.data[i] == b.data[i];
  CHECK(same == (size_t)37 * 11 * 3);
  CHECK(a.data && a.data[0] == 1.0f / 255); /* 0.5/255 rounds up to code 1 */
  jnd_buf jpg = {0};
  CHECK_OK(jnd_image_encode_8bit(&im, 1, &jpg));
  CHECK(jpg.n > 2 && jpg.p[0] == 0xFF && jpg.p[1] == 0xD8);
  jnd_buf_free(&enc);
  jnd_buf_free(&jpg);
  jnd_image_free(&im);
  jnd_image_free(&a);
  jnd_image_free(&b);
}

/* jnd diff keeps an 8-bit RGB PNG as its codes (jnd_image_read_rgb8) and
 * the model looks each up in jnd_display_code_luminances: bit for bit what
 * reading it and jnd_display_apply give, on every code and on a display
 * with ambient light; any other PNG (alpha, grey, 16 bits) is read as
 * jnd_image_read reads it, with no codes. */
TEST(png_kept_as_codes_is_bit_for_bit_the_display_of_the_decoded_png) {
  jnd_display d;
  CHECK_OK(jnd_display_preset("phone", &d));
  d.ambient_lux = 250;
  float lum[256];
  CHECK_OK(jnd_display_code_luminances(&d, lum));
  const int w = 256, h = 3;
  for (int c = 1; c <= 4; c++)
    for (int bits = 8; bits <= 16; bits += 8) {
      jnd_image im = {0}, a = {0}, b = {0};
      jnd_image_info ia, ib;
      CHECK_OK(jnd_image_alloc(&im, w, h, c));
      for (int ch = 0; ch < c; ch++) /* every code in every channel, in a different order per row */
        for (int y = 0; y < h; y++)
          for (int x = 0; x < w; x++)
            jnd_image_plane(&im, ch)[(size_t)y * w + x] = (float)((x * (2 * y + 1) + 37 * ch) % 256) / 255.0f;
      const char *path = tmp_file("codes.png");
      CHECK_OK(jnd_image_write_png(path, &im, bits));
      CHECK_OK(jnd_image_read(path, &a, &ia));
      unsigned char *rgb = (unsigned char *)"";
      CHECK_OK(jnd_image_read_rgb8(path, &b, &ib, &rgb));
      CHECK((rgb != NULL) == (c == 3 && bits == 8));
      CHECK(b.w == w && b.h == h && memcmp(&ia, &ib, sizeof ia) == 0);
      if (rgb) { /* the codes through the table into planes, as the model reads them */
        CHECK(b.data == NULL && b.c == 3);
        CHECK_OK(jnd_image_alloc(&b, w, h, 3));
        for (size_t i = 0; i < (size_t)w * h * 3; i++) jnd_image_plane(&b, (int)(i % 3))[i / 3] = lum[rgb[i]];
        free(rgb);
      } else {
        CHECK_OK(jnd_display_apply(&d, &b, ib.encoding, ib.has_alpha, &b));
      }
      CHECK_OK(jnd_display_apply(&d, &a, ia.encoding, ia.has_alpha, &a));
      size_t same = 0, n = (size_t)w * h * 3;
      CHECK(a.c == 3 && b.c == 3);
      for (size_t i = 0; a.data && b.data && a.c == 3 && b.c == 3 && i < n; i++) same += memcmp(&a.data[i], &b.data[i], 4) == 0;
      CHECK(same == n);
      jnd_image_free(&im);
      jnd_image_free(&a);
      jnd_image_free(&b);
    }
  /* a display whose luminances are refused gives no table */
  d.peak_cdm2 = -1;
  CHECK(jnd_display_code_luminances(&d, lum) != JND_OK);
}

RUN_TESTS(png_kept_as_codes_is_bit_for_bit_the_display_of_the_decoded_png,
          embedded_texture_has_the_codes_the_png_writer_writes, exr_float_round_trips_exactly, exr_half_round_trips_within_half_precision,
          exr_half_write_clamps_to_the_half_range_instead_of_infinity,
          exr_default_names_give_back_the_same_channel_order,
          exr_channels_are_read_as_r_g_b_a_whatever_their_order,
          exr_without_colour_channels_is_read_alphabetically, exr_luminance_with_alpha_is_y_then_a,
          exr_with_many_layers_reads_its_rgb_and_over_64_plain_channels_is_refused,
          exr_writer_refuses_duplicate_channel_names, exr_tiled_file_reads_like_the_pixels_it_holds,
          exr_data_window_away_from_the_origin_is_the_image, exr_every_compression_reads_back,
          exr_uint_channel_reads_as_float_counts, exr_with_nan_is_refused, exr_with_infinity_is_refused,
          every_truncation_of_an_exr_is_refused,
          exr_of_many_chunks_reads_the_same_on_any_threads_and_reports_its_first_bad_chunk,
          exr_errors_name_the_file_on_one_line,
          exr_claiming_more_than_the_size_limit_is_refused, exr_with_subsampled_channels_is_refused,
          exr_write_is_atomic_and_leaves_no_temporary_file, png_8_bit_round_trips_for_1_to_4_channels,
          png_16_bit_round_trips_to_within_one_code,
          png_written_in_many_pieces_reads_back_through_both_decoders_and_is_the_same_bytes_for_any_thread_count,
          png_8_bit_codes_are_the_values_rounded_in_double, png_with_bad_crc_is_refused,
          every_truncation_of_a_png_is_refused, png_without_iend_is_refused,
          png_claiming_more_than_the_size_limit_is_refused,
          png_zlib_path_matches_stb_for_every_plain_layout_filter_and_odd_width,
          png_rows_unfiltered_in_groups_and_in_place_match_stb_for_every_height_width_and_filter_mix,
          png_zlib_path_matches_stb_on_the_kodak_photographs, png_with_data_after_the_last_row_decodes,
          png_with_a_truncated_deflate_stream_is_refused_naming_the_file,
          png_row_with_filter_type_5_is_refused_naming_the_file,
          png_with_garbage_deflate_data_is_refused_naming_the_file,
          palette_1_bit_and_interlaced_pngs_still_decode_through_stb, empty_file_is_refused,
          non_image_file_is_refused_naming_it, jpeg_reads_as_srgb_8_bit, radiance_hdr_reads_as_linear,
          jpeg_using_an_undefined_huffman_table_is_refused,
          radiance_hdr_with_truncated_runs_is_refused_not_hung, each_decoder_refuses_other_formats,
          csv_reads_quoted_fields_with_commas_quotes_and_newlines,
          csv_row_with_the_wrong_column_count_is_refused_with_its_line,
          csv_unterminated_quote_and_empty_input_are_refused, csv_numbers_parse_and_missing_values_are_nan)
