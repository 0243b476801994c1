/* Pictures a person reads (issue 14 item 5): the heatmap's log scale keeps
 * structure above 1 JND apart, leaves invisible differences alone and
 * magnifies small images; texres's matrix picture outlines the choice; pca's
 * contribution picture names the channels; texres's worst view shows the
 * chosen sizes whether or not the matrices ran. */
#include "test.h"

#include "io/draw.h"
#include "jnd.h"

static void px(const jnd_image *img, int x, int y, float rgb[3]) {
  for (int c = 0; c < 3; c++) rgb[c] = jnd_image_plane(img, c)[(size_t)y * img->w + x];
}

static double dist(const float a[3], const float b[3]) {
  return fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]);
}

/* a grey reference and a map of four vertical bands: 0.05, 2, 6, 40 JND */
static void bands(jnd_image *ref, jnd_image *map) {
  CHECK_OK(jnd_image_alloc(ref, 256, 64, 3));
  CHECK_OK(jnd_image_alloc(map, 256, 64, 1));
  for (size_t i = 0; i < (size_t)256 * 64 * 3; i++) ref->data[i] = 0.5f;
  const float v[4] = {0.05f, 2, 6, 40};
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 256; x++) map->data[y * 256 + x] = v[x / 64];
}

TEST(the_heatmap_keeps_differences_above_one_jnd_apart) {
  jnd_image ref, map, out;
  bands(&ref, &map);
  jnd_heatmap_params p;
  jnd_heatmap_defaults(&p);
  p.min_side = 1; /* no magnification: image pixel = picture pixel, offset by the margin */
  CHECK_OK(jnd_heatmap_draw(&p, &ref, &map, &out));
  int x0 = 10, y0 = 10; /* the margin of heatmap.c */
  float a[3], b[3], c[3], d[3];
  px(&out, x0 + 32, y0 + 32, a);
  px(&out, x0 + 96, y0 + 32, b);
  px(&out, x0 + 160, y0 + 32, c);
  px(&out, x0 + 224, y0 + 32, d);
  /* 2, 6 and 40 JND are three different colours (a 0..1 scale made them one) */
  CHECK(dist(b, c) > 0.15 && dist(c, d) > 0.15 && dist(b, d) > 0.3);
  /* 0.05 JND is below the scale: the dimmed grey backdrop, untouched */
  float grey = (float)(0.15 + 0.45 * 0.5);
  CHECK(fabs(a[0] - grey) < 1e-3 && fabs(a[1] - grey) < 1e-3 && fabs(a[2] - grey) < 1e-3);
  /* the auto scale reaches the 99.9th percentile rounded up: 40 → 50, so
   * 40 JND is not the top colour, which a fixed top of 40 gives */
  jnd_image out2;
  p.max_jnd = 40;
  CHECK_OK(jnd_heatmap_draw(&p, &ref, &map, &out2));
  float d2[3];
  px(&out2, x0 + 224, y0 + 32, d2);
  CHECK(dist(d, d2) > 0.01);
  jnd_image_free(&out2);
  /* the colour bar is right of the picture: the canvas is wider than the image */
  CHECK(out.w > 256 + 100 && out.h >= 64);
  jnd_image_free(&out);
  jnd_image_free(&ref);
  jnd_image_free(&map);
}

TEST(a_small_heatmap_is_magnified_to_a_readable_size) {
  jnd_image ref, map, out;
  CHECK_OK(jnd_image_alloc(&ref, 40, 30, 3));
  CHECK_OK(jnd_image_alloc(&map, 40, 30, 1));
  for (int i = 0; i < 40 * 30; i++) map.data[i] = (float)(i % 40) / 10;
  CHECK_OK(jnd_heatmap(&ref, &map, 0, &out));
  /* shorter side 30 → a whole factor of 9 reaches 256 */
  CHECK(out.h >= 270 && out.w >= 360);
  /* nearest-pixel magnification: a 9 × 9 block of one colour */
  float a[3], b[3];
  px(&out, 10 + 9 * 5, 10 + 9 * 3, a);
  px(&out, 10 + 9 * 5 + 8, 10 + 9 * 3 + 8, b);
  CHECK(dist(a, b) < 1e-6);
  jnd_image_free(&out);
  /* beside: the reference and the heatmap side by side */
  jnd_heatmap_params p;
  jnd_heatmap_defaults(&p);
  p.beside = 1;
  p.title = "worst view";
  CHECK_OK(jnd_heatmap_draw(&p, &ref, &map, &out));
  CHECK(out.w >= 2 * 360);
  jnd_image_free(&out);
  jnd_image small;
  CHECK_OK(jnd_image_alloc(&small, 8, 8, 1));
  CHECK_STATUS(jnd_heatmap(&ref, &small, 0, &out), JND_ERR_ARG);
  jnd_image_free(&small);
  jnd_image_free(&ref);
  jnd_image_free(&map);
}

static void fake_matrix(jnd_texres_result *r, jnd_texres_map maps[2], jnd_texres_matrix *mx, double *p, double *stat,
                        int chosen_a, int chosen_b) {
  memset(r, 0, sizeof *r);
  memset(maps, 0, 2 * sizeof *maps);
  memset(mx, 0, sizeof *mx);
  snprintf(maps[0].name, sizeof maps[0].name, "body/baseColor");
  snprintf(maps[1].name, sizeof maps[1].name, "body/normal");
  maps[0].chosen[0] = maps[0].chosen[1] = chosen_a;
  maps[1].chosen[0] = maps[1].chosen[1] = chosen_b;
  mx->map_a = 0, mx->map_b = 1, mx->na = 3, mx->nb = 3, mx->nviews = 2;
  for (int k = 0; k < 3; k++) mx->size_a[k] = mx->size_b[k] = 512 >> k;
  for (int i = 0; i < 18; i++) p[i] = (i % 9) / 8.0;
  for (int i = 0; i < 9; i++) stat[i] = i / 8.0;
  mx->p = p;
  mx->stat = stat;
  r->nmaps = 2, r->maps = maps, r->nmatrix = 1, r->matrix = mx;
}

TEST(the_texres_matrix_picture_outlines_the_chosen_pair) {
  jnd_texres_result r;
  jnd_texres_map maps[2];
  jnd_texres_matrix mx;
  double p[18], stat[9];
  jnd_image a, b;
  fake_matrix(&r, maps, &mx, p, stat, 512, 512);
  CHECK_OK(jnd_texres_matrix_figure(&r, 0, &a));
  fake_matrix(&r, maps, &mx, p, stat, 256, 128);
  CHECK_OK(jnd_texres_matrix_figure(&r, 0, &b));
  CHECK(a.w == b.w && a.h == b.h && a.w > 300 && a.h > 300);
  size_t differ = 0;
  for (size_t i = 0; a.w == b.w && a.h == b.h && i < (size_t)a.w * a.h * 3; i++) differ += a.data[i] != b.data[i];
  CHECK(differ > 100); /* the outline moved, in the large panel and in each view's */
  jnd_image_free(&a);
  jnd_image_free(&b);
  CHECK_STATUS(jnd_texres_matrix_figure(&r, 1, &a), JND_ERR_ARG);
}

TEST(the_contribution_picture_names_channels_and_has_a_legend) {
  jnd_pca pca;
  memset(&pca, 0, sizeof pca);
  pca.c = 3;
  double e[3] = {0.5, 0.3, 0.2};
  for (int k = 0; k < 3; k++) {
    pca.energy[k] = e[k];
    pca.basis[k * 3 + k] = 1;
  }
  jnd_texset set;
  memset(&set, 0, sizeof set);
  set.c = 3;
  snprintf(set.names[0], sizeof set.names[0], "albedo.r");
  snprintf(set.names[1], sizeof set.names[1], "metallicRoughness.g");
  snprintf(set.names[2], sizeof set.names[2], "occlusion");
  jnd_image named, plain;
  CHECK_OK(jnd_pca_contribution_plot(&pca, &set, &named));
  CHECK_OK(jnd_pca_contribution_plot(&pca, NULL, &plain));
  /* the longer channel names need a wider margin: the names are drawn */
  CHECK(named.w > plain.w);
  /* grid plus colour bar: far more than one cell per entry */
  CHECK(named.w > 3 * 64 + 100 && named.h > 3 * 64);
  jnd_image_free(&named);
  jnd_image_free(&plain);
}

static int renderer_available(void) {
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = rp.height = 16;
  jnd_renderer *r;
  if (jnd_renderer_create(&rp, &r) != JND_OK) return 0;
  jnd_renderer_free(r);
  return 1;
}

TEST(the_worst_view_shows_the_chosen_sizes_whether_or_not_the_matrices_ran) {
  if (!renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 64;
  jnd_texres_result with = {0}, without = {0};
  for (int m = 0; m < 2; m++) {
    jnd_scene *s;
    CHECK_OK(jnd_scene_builtin(&bp, &s));
    jnd_texres_params p;
    jnd_texres_defaults(&p);
    p.judge.views.sampling.count = 2;
    p.judge.views.render.width = p.judge.views.render.height = 64;
    p.judge.views.render.samples = 1;
    p.judge.views.render.anisotropy = 1;
    p.confirm_rounds = 0;
    p.matrix = m ? 2 : 0;
    CHECK_OK(jnd_texres_run(s, &p, m ? &with : &without));
    jnd_scene_free(s);
  }
  int same_choice = with.nmaps == without.nmaps;
  for (int i = 0; same_choice && i < with.nmaps; i++)
    same_choice = memcmp(with.maps[i].chosen, without.maps[i].chosen, sizeof with.maps[i].chosen) == 0;
  CHECK(same_choice && with.nmatrix == 1);
  const jnd_image *a = &with.worst_heatmap, *b = &without.worst_heatmap;
  CHECK(a->w == b->w && a->h == b->h && a->data && b->data);
  if (same_choice && a->w == b->w && a->h == b->h && a->data && b->data)
    CHECK(memcmp(a->data, b->data, (size_t)a->w * a->h * 3 * sizeof(float)) == 0);
  jnd_texres_result_free(&with);
  jnd_texres_result_free(&without);
}

RUN_TESTS(the_heatmap_keeps_differences_above_one_jnd_apart, a_small_heatmap_is_magnified_to_a_readable_size,
          the_texres_matrix_picture_outlines_the_chosen_pair, the_contribution_picture_names_channels_and_has_a_legend,
          the_worst_view_shows_the_chosen_sizes_whether_or_not_the_matrices_ran)
