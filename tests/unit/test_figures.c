/* Pictures a person reads (issue 14 item 5): the heatmap's log scale keeps
 * structure above 1 JND apart, leaves invisible differences alone and
 * magnifies small images; texres's matrix picture outlines the choice; pca's
 * contribution picture names the channels; texres's worst view shows the
 * chosen sizes whether or not the matrices ran; lod's Pareto plot labels
 * each tick with its value in one format and every mark in full. */
#include "test.h"

#include "batch/plots.h"
#include "io/draw.h"
#include "jnd.h"
#include "tasks/tasks.h"

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

static int ink_near(const jnd_image *img, double x, double y, int r, jnd_rgb c) {
  for (int dy = -r; dy <= r; dy++)
    for (int dx = -r; dx <= r; dx++) {
      int X = (int)floor(x) + dx, Y = (int)floor(y) + dy;
      if (X < 0 || Y < 0 || X >= img->w || Y >= img->h) continue;
      float v[3], want[3] = {c.r, c.g, c.b};
      px(img, X, Y, v);
      if (dist(v, want) < 0.3) return 1;
    }
  return 0;
}

static int box_overlap(const jnd_box *a, const jnd_box *b) {
  return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

TEST(texres_series_draws_early_stopped_values_as_bounds_and_the_threshold) {
  /* the zig-zag of issue 25: 256 and 64 were judged until they failed, so
   * 0.357 and 0.97 are lower bounds; 512 and 128 were judged on every view */
  cJSON *r = cJSON_Parse("{\"parameters\": {\"criterion\": {\"p\": 0.25, \"q\": 0.1}, \"choice_p\": 0.125},"
                         "\"result\": {\"maps\": [{"
                         "\"name\": \"body/normal\", \"searched\": true,"
                         "\"candidates\": [[512, 512], [256, 256], [128, 128], [64, 64], [32, 32]],"
                         "\"series\": [0, 0.357, 0.104, 0.97, null],"
                         "\"series_decided_early\": [false, true, false, true, false]}]}}");
  CHECK(r != NULL);
  jnd_image img;
  jnd_plot_layout L;
  CHECK(jnd_plot_texres_series_image(r, &img, &L) == 1);
  jnd_rgb c = jnd_palette(0);
  double x[4] = {512, 256, 128, 64}, y[4] = {0, 0.357, 0.104, 0.97}, X[4], Y[4];
  for (int i = 0; i < 4; i++) X[i] = jnd_plot_layout_map(&L, 0, x[i]), Y[i] = jnd_plot_layout_map(&L, 1, y[i]);
  /* the line joins the measured values 512 and 128 ... */
  CHECK(ink_near(&img, 0.5 * (X[0] + X[2]), 0.5 * (Y[0] + Y[2]), 1, c));
  /* ... and goes neither to 256's bound nor on to 64's */
  CHECK(!ink_near(&img, 0.5 * (X[0] + X[1]), 0.5 * (Y[0] + Y[1]), 2, c));
  CHECK(!ink_near(&img, 0.5 * (X[2] + X[3]), 0.5 * (Y[2] + Y[3]), 2, c));
  /* each bound: its marker, an arrow up, nothing below */
  for (int i = 1; i < 4; i += 2) {
    CHECK(ink_near(&img, X[i], Y[i], 5, c));
    CHECK(ink_near(&img, X[i], Y[i] - 14, 1, c) || Y[i] - 14 < L.plot.y0 + 2);
    CHECK(!ink_near(&img, X[i], Y[i] + 14, 2, c));
  }
  /* the threshold p = 0.25 (parameters.criterion.p) is drawn across */
  double ty = jnd_plot_layout_map(&L, 1, 0.25);
  int drawn = 0, n = 0;
  for (double xx = L.plot.x0 + 4; xx < L.plot.x1 - 4; xx++, n++) drawn += ink_near(&img, xx, ty, 0, (jnd_rgb){0.45f, 0.45f, 0.45f});
  CHECK(drawn > n / 2);
  /* and so is the choice line p(1 - margin) = 0.125 (parameters.choice_p)
   * that texres chooses against: 128's 0.104 passed below it, while a value
   * between it and p fails, which the line p alone would hide */
  double cy = jnd_plot_layout_map(&L, 1, 0.125);
  drawn = n = 0;
  for (double xx = L.plot.x0 + 4; xx < L.plot.x1 - 4; xx++, n++) drawn += ink_near(&img, xx, cy, 0, (jnd_rgb){0.85f, 0.15f, 0.15f});
  CHECK(drawn > n / 2);
  /* the legend, outside the data, names the map, both lines and the bounds */
  int named = 0;
  for (int i = 0; i < L.ntexts; i++) {
    if (L.text_kind[i] != 'l') continue;
    CHECK(!box_overlap(&L.text_box[i], &L.plot));
    named |= (strcmp(L.text[i], "body/normal") == 0) | (strstr(L.text[i], "p = 0.25") ? 2 : 0) |
             (strstr(L.text[i], "lower bound") ? 4 : 0) | (strstr(L.text[i], "choice line") && strstr(L.text[i], "0.125") ? 8 : 0);
  }
  CHECK(named == 15);
  CHECK(!box_overlap(&L.legend, &L.plot));
  jnd_image_free(&img);
  cJSON_Delete(r);
}

/* more maps than the plot tells apart (8 colours × discs or rings): the
 * first 16 are drawn, each labelled, and the title says how many there are
 * (the 6-material bench asset's 24 maps lost 8 unsaid) */
TEST(texres_series_of_many_maps_says_which_it_shows) {
  char json[8192];
  int n = snprintf(json, sizeof json, "{\"parameters\": {\"criterion\": {\"p\": 0.2, \"q\": 0.1}, \"choice_p\": 0.1},"
                                      "\"result\": {\"maps\": [");
  for (int m = 0; m < 20; m++)
    n += snprintf(json + n, sizeof json - (size_t)n,
                  "%s{\"name\": \"part%d/baseColor\", \"searched\": true, \"candidates\": [[64, 64], [32, 32]],"
                  "\"series\": [0, %g], \"series_decided_early\": [false, false]}",
                  m ? "," : "", m, 0.01 * m);
  snprintf(json + n, sizeof json - (size_t)n, "]}}");
  cJSON *r = cJSON_Parse(json);
  CHECK(r != NULL);
  jnd_image img;
  jnd_plot_layout L;
  CHECK(jnd_plot_texres_series_image(r, &img, &L) == 1);
  int title = 0, labelled = 0;
  for (int i = 0; i < L.ntexts; i++) {
    title += L.text_kind[i] == 't' && strstr(L.text[i], "the first 16 of 20 maps") != NULL;
    labelled += L.text_kind[i] == 'l' && strncmp(L.text[i], "part", 4) == 0;
  }
  CHECK(title == 1);
  CHECK(labelled == 16);
  jnd_image_free(&img);
  cJSON_Delete(r);
}

TEST(pca_energy_marks_the_components_kept_with_their_share) {
  cJSON *r = cJSON_Parse("{\"result\": {\"components_kept\": 2, \"energy_fraction\": [0.7, 0.2, 0.06, 0.04],"
                         "\"cumulative_energy\": [0.7, 0.9, 0.96, 1.0]}}");
  jnd_image img;
  jnd_plot_layout L;
  CHECK(jnd_plot_pca_energy_image(r, &img, &L) == 1);
  int mark = 0;
  for (int i = 0; i < L.ntexts; i++)
    if (L.text_kind[i] == 'm') mark += strcmp(L.text[i], "2 kept: 90.0 % of the energy") == 0;
  CHECK(mark == 1);
  /* components are whole numbers: no tick between them */
  for (int i = 0; i < L.nticks[0]; i++) CHECK(L.tick[0][i] == floor(L.tick[0][i]));
  jnd_image_free(&img);
  cJSON_Delete(r);
}

TEST(pop_switch_plot_shows_every_speed_where_they_pop_alike) {
  /* two speeds with the same distances (a static viewer and a slow orbit
   * often are): the first drawn wider beneath the second, both show at
   * every point, a measured one and a bound alike (level 1: popping-free at
   * the nearest distance searched at both speeds, spot.obj's level 1 in
   * issue 25's pictures, where the static speed's bound was hidden) */
  jnd_pop_asset_report r;
  memset(&r, 0, sizeof r);
  r.nlevels = 3;
  r.distance_unit = "object units";
  jnd_pop_switch_row rows[4];
  const double d[2] = {25, 6};
  for (int k = 0; k < 2; k++)
    for (int s = 0; s < 2; s++) {
      jnd_pop_switch_row *w = &rows[k * 2 + s];
      memset(w, 0, sizeof *w);
      w->level = k + 1;
      w->distance_m = d[k];
      w->distance_m_pixel_rule = NAN;
      w->sw.status = k == 0 ? JND_POP_SWITCH_NEAREST : JND_POP_SWITCH_FOUND;
    }
  r.rows = rows;
  r.nrows = 4;
  double speeds[2] = {0, 60};
  jnd_image img;
  jnd_plot_layout L;
  CHECK_OK(pop_switch_plot(&r, speeds, 2, &img, &L));
  for (int k = 0; k < 2; k++) { /* level 1: the bound's triangles, level 2: the markers */
    double x = jnd_plot_layout_map(&L, 0, k + 1), y = jnd_plot_layout_map(&L, 1, d[k]);
    CHECK(ink_near(&img, x, y, 6, jnd_palette(0)));
    CHECK(ink_near(&img, x, y, 6, jnd_palette(1)));
  }
  jnd_image_free(&img);
}

/* pop's regions.png (004 Fig. 4): a region a few pixels across, lost at the
 * frame's own size, is ringed in its rating's colour a few pixels outside
 * its box; the frame elsewhere stays grey */
TEST(pop_regions_picture_rings_a_small_region_in_its_colour) {
  enum { W = 64 };
  jnd_image grey;
  CHECK_OK(jnd_image_alloc(&grey, W, W, 1));
  for (int i = 0; i < W * W; i++) grey.data[i] = 0.4f;
  int32_t labels[W * W];
  for (int i = 0; i < W * W; i++) labels[i] = -1;
  for (int y = 30; y <= 32; y++)
    for (int x = 30; x <= 32; x++) labels[y * W + x] = 0;
  jnd_pop_region reg = {.pixels = 9, .rating = 2, .bbox = {30, 30, 32, 32}};
  jnd_pop_result r;
  memset(&r, 0, sizeof r);
  r.w = r.h = W;
  r.nregions = 1;
  r.regions = &reg;
  r.labels = labels;
  r.max_rating = 2;
  jnd_image img;
  CHECK_OK(pop_picture(&grey, &r, &img));
  jnd_rgb c = jnd_colour_scale(0.5); /* R = 2 on the scale 0..4 */
  CHECK(ink_near(&img, 26, 31, 1, c));  /* the ring's left side, 4 pixels out */
  CHECK(ink_near(&img, 37, 31, 1, c));  /* its right side */
  CHECK(!ink_near(&img, 18, 31, 2, c)); /* grey beyond it */
  jnd_image_free(&img);
  jnd_image_free(&grey);
}

TEST(pop_switch_plot_draws_the_pixel_rule_and_names_the_units_and_a_nearer_level) {
  /* three switches at two speeds; level 3 pops less than level 2 and comes
   * out nearer (as measured); the pixel rule's distances exist for every level */
  jnd_pop_asset_report r;
  memset(&r, 0, sizeof r);
  r.nlevels = 4;
  r.distance_unit = "object units";
  jnd_pop_switch_row rows[6];
  double d[3][2] = {{20, 15}, {60, 40}, {30, 25}}, pix[3] = {2, 5, 12};
  for (int k = 0; k < 3; k++)
    for (int s = 0; s < 2; s++) {
      jnd_pop_switch_row *w = &rows[k * 2 + s];
      memset(w, 0, sizeof *w);
      w->level = k + 1;
      w->distance_m = d[k][s];
      w->distance_m_pixel_rule = pix[k];
    }
  r.rows = rows;
  r.nrows = 6;
  double speeds[2] = {0, 120};
  jnd_image img;
  jnd_plot_layout L;
  CHECK_OK(pop_switch_plot(&r, speeds, 2, &img, &L));
  int ylabel = 0, title = 0, legend = 0;
  for (int i = 0; i < L.ntexts; i++) {
    ylabel += L.text_kind[i] == 'y' && strcmp(L.text[i], "camera distance (object units)") == 0;
    title += L.text_kind[i] == 't' && strstr(L.text[i], "pops less") != NULL;
    legend += L.text_kind[i] == 'l' && strstr(L.text[i], "1-pixel") != NULL;
    CHECK(L.text_box[i].x0 >= 0 && L.text_box[i].x1 <= L.width);
  }
  CHECK(ylabel == 1 && title == 1 && legend == 1);
  /* the pixel rule's points are drawn where their distances are, and the
   * measured distances where theirs are, level 3 below level 2 */
  jnd_rgb grey = {0.4f, 0.4f, 0.4f};
  for (int k = 0; k < 3; k++) {
    CHECK(ink_near(&img, jnd_plot_layout_map(&L, 0, k + 1), jnd_plot_layout_map(&L, 1, pix[k]), 6, grey));
    CHECK(ink_near(&img, jnd_plot_layout_map(&L, 0, k + 1), jnd_plot_layout_map(&L, 1, d[k][0]), 2, jnd_palette(0)));
  }
  CHECK(jnd_plot_layout_map(&L, 1, d[2][0]) > jnd_plot_layout_map(&L, 1, d[1][0]));
  /* levels on whole-number ticks */
  for (int i = 0; i < L.nticks[0]; i++) CHECK(L.tick[0][i] == floor(L.tick[0][i]));
  jnd_image_free(&img);
  /* a glTF's metres; and no "pops less" where every level is farther */
  r.distance_unit = "m";
  d[2][0] = 90, d[2][1] = 80;
  for (int k = 0; k < 3; k++)
    for (int s = 0; s < 2; s++) rows[k * 2 + s].distance_m = d[k][s];
  CHECK_OK(pop_switch_plot(&r, speeds, 2, &img, &L));
  ylabel = title = 0;
  for (int i = 0; i < L.ntexts; i++) {
    ylabel += L.text_kind[i] == 'y' && strcmp(L.text[i], "camera distance (m)") == 0;
    title += L.text_kind[i] == 't' && strstr(L.text[i], "pops less") != NULL;
  }
  CHECK(ylabel == 1 && title == 0);
  jnd_image_free(&img);
  /* popping-free already at the nearest distance searched: an upper bound,
   * an arrow down from it, named in the legend */
  rows[0].sw.status = JND_POP_SWITCH_NEAREST;
  CHECK_OK(pop_switch_plot(&r, speeds, 2, &img, &L));
  int at_most = 0;
  for (int i = 0; i < L.ntexts; i++) at_most += L.text_kind[i] == 'l' && strncmp(L.text[i], "at most", 7) == 0;
  CHECK(at_most == 1);
  double bx = jnd_plot_layout_map(&L, 0, 1), by = jnd_plot_layout_map(&L, 1, d[0][0]);
  CHECK(ink_near(&img, bx, by + 14, 1, jnd_palette(0)) && !ink_near(&img, bx, by - 14, 1, jnd_palette(0)));
  jnd_image_free(&img);
}

/* the value a tick label says: "5000", "0.2", "10⁶" or "2.5×10⁵" (the
 * superscript digits and minus of jnd_plot_tick_labels); NaN if it is none
 * of these */
static double tick_label_value(const char *s) {
  static const char *const sup[10] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                      "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  char *end;
  double m = strtod(s, &end);
  if (end == s) return NAN;
  if (!*end) return m;
  const char *e = end;
  if (strncmp(e, "\u00d7", 2) == 0) e += 2;
  else if (m != 10) return NAN;
  else m = 1, e = end - 2; /* "10ⁿ": the 10 read as the mantissa */
  if (strncmp(e, "10", 2) != 0) return NAN;
  e += 2;
  int neg = 0, x = 0, digits = 0;
  if (strncmp(e, "\u207b", 3) == 0) neg = 1, e += 3;
  while (*e) {
    int d = 0;
    while (d < 10 && strncmp(e, sup[d], strlen(sup[d])) != 0) d++;
    if (d == 10) return NAN;
    e += strlen(sup[d]);
    x = 10 * x + d;
    digits++;
  }
  return digits ? m * pow(10, neg ? -x : x) : NAN;
}

/* a lod result of one screen: levels' triangles (finest first), rising
 * errors, and the four marks' levels */
static void fake_poi(jnd_poi_result *r, jnd_lod_level_info *li, jnd_poi_screen_result *sr, jnd_poi_point *c,
                     const size_t *tri, int n, const int marks[4]) {
  memset(r, 0, sizeof *r);
  memset(sr, 0, sizeof *sr);
  for (int k = 0; k < n; k++) {
    memset(&li[k], 0, sizeof li[k]);
    li[k].triangles = tri[k];
    memset(&c[k], 0, sizeof c[k]);
    c[k].error = 0.004 + 0.07 * k * k / ((n - 1.0) * (n - 1.0));
    c[k].error_lit = 5e-5 * k * k * k / ((n - 1.0) * (n - 1.0) * (n - 1.0));
  }
  CHECK_OK(jnd_poi_screen_parse("800x600@40", &sr->screen));
  sr->nlevels = n;
  sr->curve = c;
  sr->poi_level = marks[0];
  sr->poi_level_unlit = marks[1];
  sr->meshopt_level = marks[2];
  sr->pixel_level = marks[3];
  r->nlevels = n;
  r->levels = li;
  r->nscreens = 1;
  r->screens = sr;
}

TEST(lod_pareto_ticks_labels_and_marks_match_the_data) {
  /* the builtin sphere's chain (its 5000 tick between 3638 and 6101), and a
   * million-triangle chain (its axis once mixed "100000" with "1e+06") */
  static const size_t chains[2][10] = {{9600, 8000, 6500, 6101, 3638, 1500, 811, 456, 262, 180},
                                       {1200000, 640000, 300000, 150000, 90000, 40000, 20000, 9000, 4100, 2000}};
  static const int mk[2][4] = {{7, 6, 4, 3}, {6, 5, 2, 1}};
  for (int ch = 0; ch < 2; ch++) {
    jnd_poi_result r;
    jnd_lod_level_info li[10];
    jnd_poi_screen_result sr;
    jnd_poi_point c[10];
    fake_poi(&r, li, &sr, c, chains[ch], 10, mk[ch]);
    int perceptual = 3;
    jnd_image img;
    jnd_plot_layout L;
    CHECK_OK(lod_pareto_plot(&r, 0, perceptual, &img, &L));
    CHECK(img.w == L.width && img.h == L.height);
    /* the x axis covers the data, every tick inside it */
    CHECK(L.log[0] && L.lo[0] <= (double)chains[ch][9]);
    CHECK(L.hi[0] >= (double)chains[ch][0]);
    int labelled = 0, sci = 0, plain = 0;
    for (int i = 0; i < L.nticks[0]; i++) {
      double t = L.tick[0][i];
      CHECK(t >= L.lo[0] * (1 - 1e-9) && t <= L.hi[0] * (1 + 1e-9));
      double px = jnd_plot_layout_map(&L, 0, t);
      CHECK(px >= L.plot.x0 - 0.5 && px <= L.plot.x1 + 0.5);
      const char *lab = L.tick_label[0][i];
      if (!lab[0]) continue;
      /* the label says its tick's value, in one format for the axis */
      double v = tick_label_value(lab);
      CHECK(fabs(v - t) <= 1e-9 * t);
      if (!(fabs(v - t) <= 1e-9 * t)) fprintf(stderr, "tick %g labelled '%s'\n", t, lab);
      /* m×10ⁿ or 10ⁿ; else plain digits (not %g's 1e+06) */
      if (strstr(lab, "\u00d7") || (strncmp(lab, "10", 2) == 0 && (unsigned char)lab[2] >= 0x80)) {
        sci++;
      } else {
        plain++;
        CHECK(strspn(lab, "0123456789.") == strlen(lab));
      }
      /* the picture's text of that tick sits under it */
      int found = 0;
      for (int k = 0; k < L.ntexts; k++)
        if (L.text_kind[k] == 'X' && strcmp(L.text[k], lab) == 0) {
          found++;
          CHECK(fabs(0.5 * (L.text_box[k].x0 + L.text_box[k].x1) - px) < 2);
          CHECK(L.text_box[k].y0 >= L.plot.y1 && L.text_box[k].x0 >= 0 && L.text_box[k].x1 <= L.width);
        }
      CHECK(found == 1);
      labelled++;
    }
    CHECK(labelled >= 3);
    CHECK(sci == 0 || plain == 0);
    /* the y axis: 0 to 1, the labels their ticks' values */
    CHECK(L.lo[1] == 0 && L.hi[1] == 1);
    for (int i = 0; i < L.nticks[1]; i++)
      if (L.tick_label[1][i][0]) CHECK(fabs(tick_label_value(L.tick_label[1][i]) - L.tick[1][i]) < 1e-9);
    /* every mark labelled in full, above the data, inside the picture, over
     * its line (or moved in just enough to fit), none over another */
    const int lv[5] = {mk[ch][0], mk[ch][1], mk[ch][2], mk[ch][3], perceptual};
    const char *name[5] = {"003 lit ", "003 unlit ", "meshopt ", "px rule ", "perceptual "};
    for (int m = 0; m < 5; m++) {
      char want[96];
      snprintf(want, sizeof want, "%s%zu", name[m], chains[ch][lv[m]]);
      int found = 0;
      for (int k = 0; k < L.ntexts; k++) {
        if (L.text_kind[k] != 'm' || strcmp(L.text[k], want) != 0) continue;
        found++;
        const jnd_box *b = &L.text_box[k];
        double px = jnd_plot_layout_map(&L, 0, (double)chains[ch][lv[m]]);
        CHECK(b->x0 >= 0 && b->x1 <= L.width && b->y0 >= 0 && b->y1 <= L.plot.y0);
        CHECK((b->x0 <= px && px <= b->x1) || b->x0 < 8 || b->x1 > L.width - 8);
        for (int j = 0; j < L.ntexts; j++)
          if (j != k && (L.text_kind[j] == 'm' || L.text_kind[j] == 't')) CHECK(!box_overlap(b, &L.text_box[j]));
        /* its line is drawn at the level's triangles */
        jnd_rgb col = jnd_palette(m == 0 ? 1 : m == 1 ? 0 : m == 2 ? 2 : m == 3 ? 3 : 4);
        int ink = 0;
        for (double y = L.plot.y0 + 4; y < L.plot.y1 - 4; y += 4) ink += ink_near(&img, px, y, 1, col);
        if (m != 3) CHECK(ink > 0); /* px rule and perceptual share a line here: the later one is on top */
      }
      CHECK(found == 1);
      if (found != 1) fprintf(stderr, "mark '%s' found %d times\n", want, found);
    }
    /* both curves named in a legend outside the data; each level's point
     * drawn where its triangles and error are */
    int legend = 0;
    for (int k = 0; k < L.ntexts; k++) {
      if (L.text_kind[k] != 'l') continue;
      legend += strncmp(L.text[k], "unlit, eq. 1 (largest ", 22) == 0 || strncmp(L.text[k], "lit, eq. 3 (largest ", 20) == 0;
      CHECK(!box_overlap(&L.text_box[k], &L.plot) && L.text_box[k].x1 <= L.width && L.text_box[k].y1 <= L.height);
    }
    CHECK(legend == 2);
    /* (the coarsest level is 1 on both: the lit point drawn over the unlit) */
    double mu = c[9].error;
    for (int k = 0; k < 9; k++)
      CHECK(ink_near(&img, jnd_plot_layout_map(&L, 0, (double)chains[ch][k]), jnd_plot_layout_map(&L, 1, c[k].error / mu),
                     3, jnd_palette(0)));
    jnd_image_free(&img);
  }
}

/* a budget result over n candidates, the chosen and separate indices */
static jnd_budget_result budget_of(jnd_budget_candidate *cand, int n, int chosen, int separate) {
  jnd_budget_result r;
  memset(&r, 0, sizeof r);
  r.ncandidates = n;
  r.candidates = cand;
  r.chosen = chosen;
  r.separate = separate;
  return r;
}

TEST(budget_pareto_draws_every_candidate_the_front_the_choice_and_the_criterion) {
  /* two levels' ladders (memory halving to a quarter, the statistic
   * growing), the front, the separately chosen pair and the choice */
  enum { N = 7 };
  static const double mib[N] = {4.0, 1.0, 0.25, 0.0625, 2.0, 0.5, 0.125};
  static const double stat[N] = {0.01, 0.04, 0.16, 0.72, 0.03, 0.09, 0.45};
  static const int level[N] = {0, 0, 0, 0, 1, 1, 1};
  static const int front[N] = {1, 0, 0, 1, 1, 1, 1};
  jnd_budget_candidate cand[N];
  memset(cand, 0, sizeof cand);
  for (int i = 0; i < N; i++) {
    cand[i].memory_bytes = (size_t)(mib[i] * 1048576.0);
    cand[i].statistic = stat[i];
    cand[i].level = level[i];
    cand[i].triangles = level[i] == 0 ? 4000 : 1200;
    cand[i].pareto = front[i];
  }
  jnd_budget_result r = budget_of(cand, N, 5, 1);
  jnd_criterion c = {.p = 0.25, .q = 0.1};
  jnd_image img;
  jnd_plot_layout L;
  CHECK_OK(budget_pareto_plot(&r, &c, &img, &L));
  CHECK(img.w == L.width && img.h == L.height);
  /* both axes cover every candidate and the criterion */
  CHECK(L.log[0] && L.lo[0] <= 0.0625 && L.hi[0] >= 4.0);
  CHECK(!L.log[1] && L.lo[1] == 0 && L.hi[1] >= 0.72);
  /* each tick inside its axis, labelled with its own value, one format an axis */
  for (int a = 0; a < 2; a++) {
    int labelled = 0, sci = 0, plain = 0;
    for (int i = 0; i < L.nticks[a]; i++) {
      double t = L.tick[a][i];
      CHECK(t >= L.lo[a] - 1e-9 * fabs(L.lo[a]) - 1e-12 && t <= L.hi[a] * (1 + 1e-9));
      const char *lab = L.tick_label[a][i];
      if (!lab[0]) continue;
      labelled++;
      CHECK(fabs(tick_label_value(lab) - t) <= 1e-9 * fmax(fabs(t), 1e-9));
      if (strstr(lab, "\u00d7") || (strncmp(lab, "10", 2) == 0 && (unsigned char)lab[2] >= 0x80)) sci++;
      else plain++;
    }
    CHECK(labelled >= 3);
    CHECK(sci == 0 || plain == 0);
  }
  /* every candidate drawn where its memory and statistic are: a ring in its
   * level's colour, or, on the front, the front's disc over it */
  const jnd_rgb level_ink[2] = {{0.55f, 0.55f, 0.55f}, {0.45f, 0.62f, 0.80f}}, front_ink = {0.13f, 0.13f, 0.13f};
  for (int i = 0; i < N; i++) {
    if (i == r.chosen || i == r.separate) continue;
    double x = jnd_plot_layout_map(&L, 0, mib[i]), y = jnd_plot_layout_map(&L, 1, stat[i]);
    CHECK(ink_near(&img, x, y, 5, front[i] ? front_ink : level_ink[level[i]]));
    if (!ink_near(&img, x, y, 5, front[i] ? front_ink : level_ink[level[i]])) fprintf(stderr, "candidate %d not drawn\n", i);
  }
  /* the choice in red over the separate pair's larger blue disc */
  const jnd_rgb red = {0.85f, 0.15f, 0.15f}, blue = {0.15f, 0.35f, 0.85f};
  double cx = jnd_plot_layout_map(&L, 0, mib[r.chosen]), cy = jnd_plot_layout_map(&L, 1, stat[r.chosen]);
  double sx = jnd_plot_layout_map(&L, 0, mib[r.separate]), sy = jnd_plot_layout_map(&L, 1, stat[r.separate]);
  CHECK(ink_near(&img, cx, cy, 1, red));
  CHECK(ink_near(&img, sx, sy, 1, blue));
  /* the criterion: a dashed red line across the data at p */
  double yp = jnd_plot_layout_map(&L, 1, c.p);
  int dashes = 0, samples = 0;
  for (double x = L.plot.x0 + 4; x < L.plot.x1 - 4; x += 3, samples++) dashes += ink_near(&img, x, yp, 1, red);
  CHECK(dashes > samples / 3);
  /* the legend, outside the data, names each level, the front, both choices and p */
  const char *want[6] = {"level 0 (4000 triangles)", "level 1 (1200 triangles)", "Pareto front (memory, triangles, statistic)",
                         "texres + pca + lod separately (level 0)", "chosen (level 1)", "criterion p"};
  for (int w = 0; w < 6; w++) {
    int found = 0;
    for (int k = 0; k < L.ntexts; k++) {
      if (L.text_kind[k] != 'l' || strcmp(L.text[k], want[w]) != 0) continue;
      found++;
      CHECK(!box_overlap(&L.text_box[k], &L.plot) && L.text_box[k].x0 >= 0 && L.text_box[k].x1 <= L.width &&
            L.text_box[k].y1 <= L.height);
    }
    CHECK(found == 1);
    if (found != 1) fprintf(stderr, "legend '%s' found %d times\n", want[w], found);
  }
  jnd_image_free(&img);
  /* a chosen index outside the candidates is refused, not read */
  r.chosen = N;
  CHECK(budget_pareto_plot(&r, &c, NULL, &L) == JND_ERR_ARG);
}

TEST(budget_pareto_marks_the_joint_choice_the_separate_one_replaced_and_the_dropped_ones) {
  /* step 7 took the separate candidate (index 1) over the joint search's
   * own choice (index 4); step 6 dropped index 2 */
  enum { N = 5 };
  static const double mib[N] = {4.0, 0.5, 0.25, 0.0625, 1.0};
  static const double stat[N] = {0.01, 0.15, 0.08, 0.72, 0.05};
  jnd_budget_candidate cand[N];
  memset(cand, 0, sizeof cand);
  for (int i = 0; i < N; i++) {
    cand[i].memory_bytes = (size_t)(mib[i] * 1048576.0);
    cand[i].cost = (double)cand[i].memory_bytes;
    cand[i].statistic = stat[i];
    cand[i].triangles = 4000;
  }
  cand[2].held_out_fail = 1;
  jnd_budget_result r = budget_of(cand, N, 1, 1);
  r.separate_taken = 1;
  r.joint = 4;
  jnd_criterion c = {.p = 0.2, .q = 0.1};
  jnd_image img;
  jnd_plot_layout L;
  CHECK_OK(budget_pareto_plot(&r, &c, &img, &L));
  const jnd_rgb orange = {0.90f, 0.55f, 0.10f}, purple = {0.55f, 0.20f, 0.60f}, red = {0.85f, 0.15f, 0.15f};
  double jx = jnd_plot_layout_map(&L, 0, mib[4]), jy = jnd_plot_layout_map(&L, 1, stat[4]);
  double cx = jnd_plot_layout_map(&L, 0, mib[1]), cy = jnd_plot_layout_map(&L, 1, stat[1]);
  double dx = jnd_plot_layout_map(&L, 0, mib[2]), dy = jnd_plot_layout_map(&L, 1, stat[2]);
  CHECK(ink_near(&img, jx, jy, 1, orange));
  CHECK(ink_near(&img, cx, cy, 1, red));
  CHECK(ink_near(&img, dx, dy, 13, purple) && !ink_near(&img, dx, dy, 1, purple));   /* a ring around it */
  const char *want[3] = {"chosen: the separate one (level 0)", "the joint search's own, dearer (level 0)",
                         "seen on its held-out views: dropped"};
  for (int w = 0; w < 3; w++) {
    int found = 0;
    for (int k = 0; k < L.ntexts; k++) found += L.text_kind[k] == 'l' && strcmp(L.text[k], want[w]) == 0;
    CHECK(found == 1);
    if (found != 1) fprintf(stderr, "legend '%s' found %d times\n", want[w], found);
  }
  jnd_image_free(&img);
  /* taken over a cheaper joint choice, which its held-out views saw: not called dearer */
  cand[4].cost = cand[1].cost - 1;
  CHECK_OK(budget_pareto_plot(&r, &c, NULL, &L));
  int seen = 0;
  for (int k = 0; k < L.ntexts; k++) {
    seen += strcmp(L.text[k], "the joint search's own, seen on its held-out views (level 0)") == 0;
    CHECK(strcmp(L.text[k], want[1]) != 0);
  }
  CHECK(seen == 1);
  cand[4].cost = (double)cand[4].memory_bytes;
  /* nothing taken, nothing dropped: neither entry */
  r.separate_taken = 0;
  cand[2].held_out_fail = 0;
  CHECK_OK(budget_pareto_plot(&r, &c, NULL, &L));
  for (int k = 0; k < L.ntexts; k++)
    CHECK(strcmp(L.text[k], want[1]) != 0 && strcmp(L.text[k], want[2]) != 0 && strcmp(L.text[k], want[0]) != 0);
  /* a joint index outside the candidates is refused where it is read */
  r.separate_taken = 1;
  r.joint = N;
  CHECK(budget_pareto_plot(&r, &c, NULL, &L) == JND_ERR_ARG);
}

TEST(the_calibration_histogram_has_a_bar_per_bin_as_tall_as_its_count) {
  /* bins of 32 px: −40 → −32, 0 and 10 → 0, 70 → 64, 600 → the open end bin 512 */
  double err[5] = {-40, 0, 10, 70, 600};
  jnd_calibrate_result r;
  memset(&r, 0, sizeof r);
  r.errors_px = err;
  r.nscenes = 5;
  r.cv_mae_px = 144;
  jnd_image img;
  CHECK_OK(jnd_calibrate_histogram(&r, &img));
  jnd_rgb c = jnd_palette(0);
  float want[3] = {c.r, c.g, c.b}, v[3];
  int bottom = -1;
  for (int y = 0; y < img.h; y++)
    for (int x = 0; x < img.w; x++) {
      px(&img, x, y, v);
      if (dist(v, want) < 0.05) bottom = y;
    }
  CHECK(bottom > img.h / 2);
  /* the bars along a row just above the axis, and the height of each */
  int bars = 0, height[8] = {0};
  for (int x = 0, run = 0; x <= img.w; x++) {
    int in = 0;
    if (x < img.w) {
      px(&img, x, bottom - 1, v);
      in = dist(v, want) < 0.05;
    }
    if (in) run++;
    if (!in && run > 3 && bars < 8) {
      int mid = x - run / 2, h = 0;
      for (int y = bottom; y >= 0; y--) {
        px(&img, mid, y, v);
        if (dist(v, want) < 0.05) h++;
      }
      height[bars++] = h;
    }
    if (!in) run = 0;
  }
  CHECK(bars == 4);
  CHECK_NEAR((double)height[1] / height[0], 2, 0.1); /* the 0 bin holds two */
  CHECK_NEAR((double)height[2] / height[0], 1, 0.05);
  CHECK_NEAR((double)height[3] / height[0], 1, 0.05);
  jnd_image_free(&img);
  r.nscenes = 0;
  CHECK_STATUS(jnd_calibrate_histogram(&r, &img), JND_ERR_ARG);
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
    CHECK_OK(jnd_texres_search(s, &p, m ? &with : &without));
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
  jnd_texres_result_clear(&with);
  jnd_texres_result_clear(&without);
}

/* gaze's L(d, ecc) picture (issue 25 item 4): a hand-made table of 4 levels;
 * every level's colour is in the picture as a cell, the coarser level takes
 * more cells at larger distances; JND_FIGURE_DIR=DIR writes it to look at */
TEST(the_gaze_table_picture_colours_each_cell_by_its_level) {
  enum { ND = 6, NE = 5, NL = 4 };
  double dist_m[ND] = {4, 9, 22, 96, 480, 1250}, ecc[NE] = {0, 5, 10, 30, 60};
  int level[ND * NE];
  for (int d = 0; d < ND; d++)
    for (int e = 0; e < NE; e++) level[d * NE + e] = (d + e) / 2 < NL - 1 ? (d + e) / 2 : NL - 1;
  jnd_gaze_table t;
  memset(&t, 0, sizeof t);
  t.nd = ND, t.ne = NE, t.nlevels = NL, t.orientations = 2;
  t.distances_m = dist_m, t.eccentricities_deg = ecc, t.level = level;
  jnd_image fig;
  CHECK_OK(jnd_gaze_table_figure(&t, 0.75, "object units", &fig));
  CHECK(fig.w > NE * 56 && fig.h > ND * 56);
  const char *dir = getenv("JND_FIGURE_DIR");
  if (dir) {
    char path[4096];
    snprintf(path, sizeof path, "%s/gaze_table.png", dir);
    CHECK_OK(jnd_image_write_png(path, &fig, 8));
  }
  /* count, per level, the pixels of exactly its colour: the cells (56 × 56
   * each, less their white borders) dominate the colour bar's one row */
  size_t count[NL] = {0};
  for (int y = 0; y < fig.h; y++)
    for (int x = 0; x < fig.w; x++) {
      float c[3];
      px(&fig, x, y, c);
      for (int l = 0; l < NL; l++) {
        jnd_rgb k = jnd_colour_scale(l / (double)(NL - 1));
        float kc[3] = {k.r, k.g, k.b};
        if (dist(c, kc) < 1e-4) count[l]++;
      }
    }
  size_t cells[NL] = {0};
  for (int i = 0; i < ND * NE; i++) cells[level[i]]++;
  for (int l = 0; l < NL; l++) {
    CHECK(count[l] > cells[l] * 40 * 40);
    CHECK(count[l] < cells[l] * 56 * 56 + 200);
  }
  jnd_image_free(&fig);
  /* a 3 × 3 table (jnd gaze with three distances and eccentricities): its
   * row title is longer than the grid is tall, and stays whole in the
   * picture, below the title: no ink at the picture's edges, none in the
   * row title's column between the title and the grid's top */
  t.nd = t.ne = 3;
  CHECK_OK(jnd_gaze_table_figure(&t, 0.75, "object units", &fig));
  int edge = 0, between = 0;
  for (int y = 0; y < fig.h; y++)
    for (int x = 0; x < fig.w; x++) {
      float c[3];
      px(&fig, x, y, c);
      int ink = c[0] + c[1] + c[2] < 1.5f;
      edge += ink && (x < 3 || y < 3 || x >= fig.w - 3 || y >= fig.h - 3);
      between += ink && x >= 12 && x <= 28 && y >= 35 && y <= 42;
    }
  CHECK(edge == 0);
  CHECK(between == 0);
  if (dir) {
    char path[4096];
    snprintf(path, sizeof path, "%s/gaze_table_3x3.png", dir);
    CHECK_OK(jnd_image_write_png(path, &fig, 8));
  }
  jnd_image_free(&fig);
}

RUN_TESTS(the_heatmap_keeps_differences_above_one_jnd_apart, a_small_heatmap_is_magnified_to_a_readable_size,
          the_texres_matrix_picture_outlines_the_chosen_pair, the_contribution_picture_names_channels_and_has_a_legend,
          texres_series_draws_early_stopped_values_as_bounds_and_the_threshold, texres_series_of_many_maps_says_which_it_shows,
          pca_energy_marks_the_components_kept_with_their_share,
          pop_switch_plot_draws_the_pixel_rule_and_names_the_units_and_a_nearer_level,
          pop_switch_plot_shows_every_speed_where_they_pop_alike, pop_regions_picture_rings_a_small_region_in_its_colour,
          the_calibration_histogram_has_a_bar_per_bin_as_tall_as_its_count,
          the_worst_view_shows_the_chosen_sizes_whether_or_not_the_matrices_ran,
          the_gaze_table_picture_colours_each_cell_by_its_level, lod_pareto_ticks_labels_and_marks_match_the_data,
          budget_pareto_draws_every_candidate_the_front_the_choice_and_the_criterion,
          budget_pareto_marks_the_joint_choice_the_separate_one_replaced_and_the_dropped_ones)
