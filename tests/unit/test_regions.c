/* Connected regions of the pool layer (004 §3.2's popping regions): seeded
 * 8-connected components of {map >= threshold}, numbered and summed the same
 * way whatever the thread count. */
#include <stdint.h>

#include "test.h"
#include "core/core.h"
#include "jnd.h"
#include "pool/pool.h"

/* a disc of radius r at (cx, cy) set to v; returns its pixel count */
static size_t disc(float *m, int w, int h, double cx, double cy, double r, float v) {
  size_t n = 0;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) {
        m[(size_t)y * w + x] = v;
        n++;
      }
  return n;
}

TEST(a_blob_of_known_size_is_one_region_of_that_pixel_count) {
  const int w = 80, h = 70;
  float *m = calloc((size_t)w * h, sizeof *m);
  size_t n = disc(m, w, h, 40.3, 30.6, 9.2, 3.0f);
  int32_t *lab = malloc(sizeof *lab * (size_t)w * h);
  jnd_region *r = NULL;
  int nr = -1;
  CHECK_OK(jnd_regions_find(m, NULL, w, h, 2.0f, 2.4, 0, lab, &r, &nr));
  CHECK(nr == 1);
  if (nr == 1) {
    CHECK(r[0].pixels == n);
    CHECK_NEAR(r[0].sum_pow, (double)n * pow(3.0, 2.4), 1e-3 * n);
    CHECK(r[0].max == 3.0f);
    CHECK(r[0].x0 == 32 && r[0].x1 == 49 && r[0].y0 == 22 && r[0].y1 == 39);
    size_t labelled = 0;
    for (int i = 0; i < w * h; i++) labelled += lab[i] == 0;
    CHECK(labelled == n);
  }
  free(r);
  free(lab);
  free(m);
}

TEST(growth_stops_below_the_threshold_and_joins_diagonal_neighbours) {
  const int w = 12, h = 6;
  float m[72] = {0};
  /* two pixels touching at a corner: one region (eight neighbours) */
  m[1 * w + 1] = 2.0f;
  m[2 * w + 2] = 5.0f;
  /* just below the threshold: not grown over, so the pixel beyond it is apart */
  m[2 * w + 3] = 1.999f;
  m[2 * w + 4] = 2.5f;
  int32_t lab[72];
  jnd_region *r = NULL;
  int nr = 0;
  CHECK_OK(jnd_regions_find(m, NULL, w, h, 2.0f, 2.4, 1, lab, &r, &nr));
  CHECK(nr == 2);
  if (nr == 2) {
    CHECK(r[0].pixels == 2 && r[1].pixels == 1);
    CHECK(r[0].first == (size_t)(1 * w + 1)); /* numbered by first pixel in raster order */
    CHECK(lab[2 * w + 3] == -1 && lab[2 * w + 4] == 1);
  }
  free(r);
}

TEST(components_without_a_seed_are_not_regions) {
  const int w = 20, h = 10;
  float m[200] = {0};
  uint8_t seed[200] = {0};
  disc(m, w, h, 4, 4, 2.5, 4.0f);
  disc(m, w, h, 14, 4, 2.5, 4.0f);
  seed[4 * w + 14] = 1;   /* only the right blob has a seed */
  seed[9 * w + 0] = 1;    /* a seed below the threshold seeds nothing */
  int32_t lab[200];
  jnd_region *r = NULL;
  int nr = 0;
  CHECK_OK(jnd_regions_find(m, seed, w, h, 2.0f, 2.4, 0, lab, &r, &nr));
  CHECK(nr == 1);
  if (nr == 1) CHECK(r[0].x0 > 10);
  CHECK(lab[4 * w + 4] == -1 && lab[4 * w + 14] == 0 && lab[9 * w] == -1);
  free(r);
}

TEST(regions_are_the_same_for_any_thread_count) {
  /* a map of many irregular components crossing the strip seams (64 rows) */
  const int w = 301, h = 517;
  float *m = malloc(sizeof *m * (size_t)w * h);
  uint8_t *seed = malloc((size_t)w * h);
  jnd_rng g;
  jnd_rng_seed(&g, 7);
  for (int i = 0; i < w * h; i++) {
    m[i] = (float)(3.2 * jnd_rng_uniform(&g));
    seed[i] = jnd_rng_uniform(&g) < 0.01;
  }
  int32_t *lab[3];
  jnd_region *r[3];
  int nr[3];
  const int threads[3] = {1, 2, 4};
  for (int k = 0; k < 3; k++) {
    lab[k] = malloc(sizeof(int32_t) * (size_t)w * h);
    CHECK_OK(jnd_regions_find(m, seed, w, h, 2.0f, 2.4, threads[k], lab[k], &r[k], &nr[k]));
  }
  CHECK(nr[0] > 100);
  for (int k = 1; k < 3; k++) {
    CHECK(nr[k] == nr[0]);
    CHECK(memcmp(lab[k], lab[0], sizeof(int32_t) * (size_t)w * h) == 0);
    if (nr[k] == nr[0]) CHECK(memcmp(r[k], r[0], sizeof(jnd_region) * (size_t)nr[0]) == 0);
  }
  /* one component snaking through every strip is one region */
  for (int i = 0; i < w * h; i++) m[i] = 0;
  for (int y = 0; y < h; y++) m[(size_t)y * w + abs(y % 10 - 5)] = 2.0f; /* a zigzag, one pixel a row */
  jnd_region *one = NULL;
  int n1 = 0;
  CHECK_OK(jnd_regions_find(m, NULL, w, h, 2.0f, 2.4, 4, lab[0], &one, &n1));
  CHECK(n1 == 1);
  if (n1 == 1) CHECK(one[0].pixels == (size_t)h && one[0].y0 == 0 && one[0].y1 == h - 1);
  free(one);
  for (int k = 0; k < 3; k++) {
    free(lab[k]);
    free(r[k]);
  }
  free(m);
  free(seed);
}

TEST(an_empty_map_has_no_region) {
  float m[16] = {0};
  int32_t lab[16];
  jnd_region *r = (jnd_region *)1;
  int nr = 5;
  CHECK_OK(jnd_regions_find(m, NULL, 4, 4, 2.0f, 2.4, 0, lab, &r, &nr));
  CHECK(nr == 0 && r == NULL);
  for (int i = 0; i < 16; i++) CHECK(lab[i] == -1);
  CHECK_STATUS(jnd_regions_find(m, NULL, 4, 4, 0.0f, 2.4, 0, lab, &r, &nr), JND_ERR_ARG);
}

RUN_TESTS(a_blob_of_known_size_is_one_region_of_that_pixel_count,
          growth_stops_below_the_threshold_and_joins_diagonal_neighbours, components_without_a_seed_are_not_regions,
          regions_are_the_same_for_any_thread_count, an_empty_map_has_no_region)
