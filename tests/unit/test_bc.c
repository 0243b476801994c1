/* Block compression (BC1, BC4, BC5): the decoder follows the format, the
 * encoders are exact where the format can be and close where it cannot. */
#include "jnd.h"
#include "test.h"
#include "core/core.h"

static double psnr(const jnd_image *a, const jnd_image *b, int ch) {
  const float *x = jnd_image_plane(a, ch), *y = jnd_image_plane(b, ch);
  double s = 0;
  size_t n = (size_t)a->w * a->h;
  for (size_t i = 0; i < n; i++) s += ((double)x[i] - y[i]) * ((double)x[i] - y[i]);
  s /= (double)n;
  return s > 0 ? 10 * log10(1 / s) : 999;
}

static void roundtrip(jnd_bc_format f, const jnd_image *in, jnd_image *out) {
  uint8_t *blocks = malloc(jnd_bc_size(f, in->w, in->h));
  jnd_image_alloc(out, in->w, in->h, in->c);
  CHECK_OK(jnd_bc_encode(f, in, 0, blocks));
  CHECK_OK(jnd_bc_decode(f, blocks, out, 0));
  free(blocks);
}

TEST(sizes_count_partial_blocks) {
  CHECK(jnd_bc_size(JND_BC1, 4, 4) == 8);
  CHECK(jnd_bc_size(JND_BC4, 5, 7) == 4 * 8);
  CHECK(jnd_bc_size(JND_BC5, 8, 8) == 4 * 16);
  CHECK(jnd_bc_size(JND_BC1, 2048, 2048) == 2048u * 2048u / 2);
}

TEST(bc1_decoder_follows_the_format) {
  /* c0 = pure red 0xF800 > c1 = pure blue 0x001F: four-colour mode */
  uint8_t block[8] = {0x00, 0xF8, 0x1F, 0x00, 0, 0, 0, 0};
  /* texel 0 index 0, texel 1 index 1, texel 2 index 2, texel 3 index 3 */
  block[4] = 0 | (1 << 2) | (2 << 4) | (3 << 6);
  jnd_image img;
  jnd_image_alloc(&img, 4, 4, 3);
  CHECK_OK(jnd_bc_decode(JND_BC1, block, &img, 0));
  float *r = jnd_image_plane(&img, 0), *g = jnd_image_plane(&img, 1), *b = jnd_image_plane(&img, 2);
  CHECK_NEAR(r[0] * 255, 255, 1e-3);
  CHECK_NEAR(b[0] * 255, 0, 1e-3);
  CHECK_NEAR(r[1] * 255, 0, 1e-3);
  CHECK_NEAR(b[1] * 255, 255, 1e-3);
  CHECK_NEAR(r[2] * 255, 170, 1e-3);   /* (2·255 + 0)/3 */
  CHECK_NEAR(b[2] * 255, 85, 1e-3);
  CHECK_NEAR(r[3] * 255, 85, 1e-3);
  CHECK_NEAR(g[3] * 255, 0, 1e-3);
  jnd_image_free(&img);
}

TEST(bc4_decoder_follows_the_format) {
  /* r0 = 200 > r1 = 100: eight values; texel 0 index 2, texel 1 index 7 */
  uint8_t block[8] = {200, 100, 0, 0, 0, 0, 0, 0};
  uint64_t bits = 2 | (7 << 3);
  for (int i = 0; i < 6; i++) block[2 + i] = (uint8_t)(bits >> (8 * i));
  jnd_image img;
  jnd_image_alloc(&img, 4, 4, 1);
  CHECK_OK(jnd_bc_decode(JND_BC4, block, &img, 0));
  CHECK_NEAR(img.data[0] * 255, 186, 1e-3);   /* (6·200 + 100)/7 = 185.7 */
  CHECK_NEAR(img.data[1] * 255, 114, 1e-3);   /* (200 + 6·100)/7 = 114.3 */
  CHECK_NEAR(img.data[2] * 255, 200, 1e-3);   /* index 0 */
  /* r0 <= r1: six values, then 0 and 255 */
  uint8_t six[8] = {100, 200, 0, 0, 0, 0, 0, 0};
  bits = 6 | (7 << 3);
  for (int i = 0; i < 6; i++) six[2 + i] = (uint8_t)(bits >> (8 * i));
  CHECK_OK(jnd_bc_decode(JND_BC4, six, &img, 0));
  CHECK_NEAR(img.data[0], 0, 1e-6);
  CHECK_NEAR(img.data[1], 1, 1e-6);
  jnd_image_free(&img);
}

TEST(flat_and_two_level_blocks_survive_bc4_exactly) {
  jnd_image in, out;
  jnd_image_alloc(&in, 8, 8, 1);
  for (int y = 0; y < 8; y++)
    for (int x = 0; x < 8; x++) in.data[y * 8 + x] = x < 4 ? 77 / 255.0f : ((x + y) & 1 ? 20 : 230) / 255.0f;
  roundtrip(JND_BC4, &in, &out);
  for (int i = 0; i < 64; i++) CHECK_NEAR(out.data[i], in.data[i], 1e-6);
  jnd_image_free(&in);
  jnd_image_free(&out);
}

TEST(bc4_is_close_on_smooth_and_noisy_content) {
  jnd_image in, out;
  jnd_image_alloc(&in, 61, 37, 1);   /* partial blocks on both edges */
  jnd_rng r;
  jnd_rng_seed(&r, 1);
  for (int y = 0; y < 37; y++)
    for (int x = 0; x < 61; x++) in.data[y * 61 + x] = (float)(0.5 + 0.4 * sin(x * 0.2 + y * 0.1));
  roundtrip(JND_BC4, &in, &out);
  CHECK_LT(38.0, psnr(&in, &out, 0));   /* steep: 8 levels a block */
  for (int i = 0; i < 61 * 37; i++) in.data[i] = (float)jnd_rng_uniform(&r);
  jnd_image_free(&out);
  roundtrip(JND_BC4, &in, &out);
  CHECK_LT(25.0, psnr(&in, &out, 0));   /* 8 levels per block of uniform noise: ~1/14 steps */
  jnd_image_free(&in);
  jnd_image_free(&out);
}

TEST(bc1_is_close_on_correlated_colour_and_exact_on_565_colours) {
  jnd_image in, out;
  jnd_image_alloc(&in, 32, 32, 3);
  for (int y = 0; y < 32; y++)
    for (int x = 0; x < 32; x++) {
      double t = 0.5 + 0.45 * sin(x * 0.3) * cos(y * 0.2);
      jnd_image_plane(&in, 0)[y * 32 + x] = (float)t;
      jnd_image_plane(&in, 1)[y * 32 + x] = (float)(0.8 * t + 0.1);
      jnd_image_plane(&in, 2)[y * 32 + x] = (float)(1 - t);
    }
  roundtrip(JND_BC1, &in, &out);
  for (int c = 0; c < 3; c++) CHECK_LT(32.0, psnr(&in, &out, c));
  jnd_image_free(&out);
  /* a flat colour on the 565 grid comes back exactly */
  for (int c = 0; c < 3; c++)
    for (int i = 0; i < 32 * 32; i++) jnd_image_plane(&in, c)[i] = (c == 1 ? 134 : 66) / 255.0f;   /* g6 = 33, r5 = b5 = 8 */
  roundtrip(JND_BC1, &in, &out);
  for (int c = 0; c < 3; c++) CHECK(psnr(&in, &out, c) == 999);
  jnd_image_free(&in);
  jnd_image_free(&out);
}

TEST(bc5_encodes_two_channels_independently) {
  jnd_image in, out, one, one_out;
  jnd_image_alloc(&in, 16, 16, 2);
  jnd_image_alloc(&one, 16, 16, 1);
  for (int i = 0; i < 256; i++) {
    jnd_image_plane(&in, 0)[i] = (float)((i * 37 % 256) / 255.0);
    jnd_image_plane(&in, 1)[i] = (float)((i % 16) / 15.0);
    one.data[i] = jnd_image_plane(&in, 1)[i];
  }
  roundtrip(JND_BC5, &in, &out);
  roundtrip(JND_BC4, &one, &one_out);
  for (int i = 0; i < 256; i++) CHECK(jnd_image_plane(&out, 1)[i] == one_out.data[i]);
  jnd_image_free(&in);
  jnd_image_free(&out);
  jnd_image_free(&one);
  jnd_image_free(&one_out);
}

TEST(wrong_channel_counts_are_refused) {
  jnd_image img;
  jnd_image_alloc(&img, 4, 4, 2);
  uint8_t blocks[16];
  CHECK_STATUS(jnd_bc_encode(JND_BC1, &img, 0, blocks), JND_ERR_ARG);
  CHECK_STATUS(jnd_bc_encode(JND_BC5, &img, 1, blocks), JND_ERR_ARG);
  CHECK_STATUS(jnd_bc_encode((jnd_bc_format)2, &img, 0, blocks), JND_ERR_ARG);
  jnd_image_free(&img);
}

RUN_TESTS(sizes_count_partial_blocks, bc1_decoder_follows_the_format, bc4_decoder_follows_the_format,
          flat_and_two_level_blocks_survive_bc4_exactly, bc4_is_close_on_smooth_and_noisy_content,
          bc1_is_close_on_correlated_colour_and_exact_on_565_colours, bc5_encodes_two_channels_independently,
          wrong_channel_counts_are_refused)
