/* The drawing layer of report pictures: shapes land where they are asked to,
 * text is drawn and measured consistently, plots map data to the right
 * pixels, and grids colour each cell by its value. */
#include "test.h"

#include "jnd.h"
#include "io/draw.h"

static const jnd_rgb WHITE = {1, 1, 1}, RED = {1, 0, 0};

static int is_red(const jnd_image *img, int x, int y) {
  size_t i = (size_t)y * img->w + x;
  return jnd_image_plane(img, 0)[i] > 0.9f && jnd_image_plane(img, 1)[i] < 0.1f && jnd_image_plane(img, 2)[i] < 0.1f;
}

/* bounding box of pixels that differ from white */
static void ink_box(const jnd_image *img, int box[4]) {
  box[0] = img->w, box[1] = img->h, box[2] = -1, box[3] = -1;
  for (int y = 0; y < img->h; y++)
    for (int x = 0; x < img->w; x++) {
      size_t i = (size_t)y * img->w + x;
      if (jnd_image_plane(img, 0)[i] < 0.95f || jnd_image_plane(img, 1)[i] < 0.95f || jnd_image_plane(img, 2)[i] < 0.95f) {
        if (x < box[0]) box[0] = x;
        if (y < box[1]) box[1] = y;
        if (x > box[2]) box[2] = x;
        if (y > box[3]) box[3] = y;
      }
    }
}

TEST(a_thick_line_covers_its_path_and_nothing_far_from_it) {
  jnd_image img;
  CHECK_OK(jnd_canvas_new(&img, 64, 64, WHITE));
  jnd_draw_line(&img, 8, 32, 56, 32, 4, RED);
  CHECK(is_red(&img, 8, 31) && is_red(&img, 32, 32) && is_red(&img, 55, 33));
  int box[4];
  ink_box(&img, box);
  CHECK(box[0] >= 5 && box[2] <= 58 && box[1] >= 29 && box[3] <= 35);
  jnd_image_free(&img);
}

TEST(text_is_drawn_within_its_measured_width) {
  jnd_image img;
  CHECK_OK(jnd_canvas_new(&img, 300, 60, WHITE));
  double w = jnd_text_width("Triangles (thousands)", 16);
  CHECK(w > 100 && w < 250);
  CHECK(jnd_text_width("ab", 16) < jnd_text_width("abab", 16));
  CHECK_NEAR(jnd_text_width("abab", 32), 2 * jnd_text_width("abab", 16), 1.0);
  jnd_draw_text(&img, 20, 40, "Triangles (thousands)", 16, (jnd_rgb){0, 0, 0}, JND_ALIGN_LEFT, 0);
  int box[4];
  ink_box(&img, box);
  CHECK(box[0] >= 18 && box[0] <= 24);
  CHECK_NEAR(box[2] - box[0], w, 4);
  CHECK(box[1] >= 40 - 16 && box[3] <= 40 + 6); /* ascender above, descender just below the baseline */
  /* the ink lies in the box jnd_text_box gives, for each alignment */
  for (int al = 0; al < 3; al++) {
    jnd_image t;
    CHECK_OK(jnd_canvas_new(&t, 300, 60, WHITE));
    jnd_draw_text(&t, 150, 40, "Tg (jy) 10\u2075", 16, (jnd_rgb){0, 0, 0}, (jnd_align)al, 0);
    jnd_box tb = jnd_text_box(150, 40, "Tg (jy) 10\u2075", 16, (jnd_align)al, 0);
    ink_box(&t, box);
    CHECK(box[0] >= tb.x0 && box[2] < tb.x1 && box[1] >= tb.y0 && box[3] < tb.y1);
    CHECK(tb.x1 - tb.x0 < jnd_text_width("Tg (jy) 10\u2075", 16) + 8);
    jnd_image_free(&t);
  }
  jnd_image_free(&img);
  /* vertical text runs upwards from its anchor */
  CHECK_OK(jnd_canvas_new(&img, 60, 300, WHITE));
  jnd_draw_text(&img, 30, 260, "P(detect)", 16, (jnd_rgb){0, 0, 0}, JND_ALIGN_LEFT, 1);
  ink_box(&img, box);
  CHECK(box[3] <= 262 && box[1] < 260 - 50 && box[2] - box[0] < 22);
  jnd_box vb = jnd_text_box(30, 260, "P(detect)", 16, JND_ALIGN_LEFT, 1);
  CHECK(box[0] >= vb.x0 && box[2] < vb.x1 && box[1] >= vb.y0 && box[3] < vb.y1);
  jnd_image_free(&img);
}

static int is_ink(const jnd_image *img, int x, int y, jnd_rgb c) {
  size_t i = (size_t)y * img->w + x;
  return fabsf(jnd_image_plane(img, 0)[i] - c.r) < 0.15f && fabsf(jnd_image_plane(img, 1)[i] - c.g) < 0.15f &&
         fabsf(jnd_image_plane(img, 2)[i] - c.b) < 0.15f;
}

/* any pixel of colour c within r pixels of (x, y) */
static int ink_near(const jnd_image *img, double x, double y, int r, jnd_rgb c) {
  for (int dy = -r; dy <= r; dy++)
    for (int dx = -r; dx <= r; dx++) {
      int px = (int)floor(x) + dx, py = (int)floor(y) + dy;
      if (px >= 0 && py >= 0 && px < img->w && py < img->h && is_ink(img, px, py, c)) return 1;
    }
  return 0;
}

static double to_px(const jnd_plot_layout *L, int axis, double v, double lo, double hi) {
  double t = (v - lo) / (hi - lo);
  return axis == 0 ? L->plot.x0 + t * (L->plot.x1 - L->plot.x0) : L->plot.y1 - t * (L->plot.y1 - L->plot.y0);
}

TEST(a_line_plot_maps_its_data_range_onto_the_plot_area) {
  double x[2] = {0, 10}, y[2] = {0, 10};
  jnd_plot_series s = {.x = x, .y = y, .n = 2, .label = "series", .colour = RED, .line = 1, .width = 3};
  jnd_plot_axes ax = {0};
  ax.title = "t";
  ax.xlabel = "x";
  ax.ylabel = "y";
  ax.xmin = ax.ymin = 0;
  ax.xmax = ax.ymax = 10;
  ax.width = 400;
  ax.height = 300;
  jnd_image img;
  jnd_plot_layout L;
  CHECK_OK(jnd_plot_lines_layout(&ax, &s, 1, &L));
  CHECK_OK(jnd_plot_lines(&ax, &s, 1, &img));
  CHECK(img.w == 400 && img.h == 300 && L.width == 400 && L.height == 300);
  /* the diagonal runs from the bottom-left corner of the plot area to its top-right */
  int minx = img.w, maxx = -1, miny = img.h, maxy = -1;
  for (int py = 0; py < (int)L.plot.y1 + 3; py++)
    for (int px = 0; px < img.w; px++)
      if (is_red(&img, px, py)) {
        if (px < minx) minx = px;
        if (px > maxx) maxx = px;
        if (py < miny) miny = py;
        if (py > maxy) maxy = py;
      }
  CHECK_NEAR(minx, L.plot.x0, 2);
  CHECK_NEAR(maxx, L.plot.x1, 2);
  CHECK_NEAR(miny, L.plot.y0, 2);
  CHECK_NEAR(maxy, L.plot.y1, 2);
  /* the line is straight: half-way across it is half-way up */
  CHECK(ink_near(&img, 0.5 * (L.plot.x0 + L.plot.x1), 0.5 * (L.plot.y0 + L.plot.y1), 2, RED));
  jnd_image_free(&img);
  CHECK_STATUS(jnd_plot_lines(&(jnd_plot_axes){.width = 50, .height = 50}, &s, 1, &img), JND_ERR_ARG);
}

static int all_contain(char (*label)[32], int n, const char *what) {
  for (int i = 0; i < n; i++)
    if (label[i][0] && !strstr(label[i], what)) return 0;
  return 1;
}
static int none_contain(char (*label)[32], int n, const char *what) {
  for (int i = 0; i < n; i++)
    if (strstr(label[i], what)) return 0;
  return 1;
}

TEST(the_tick_labels_of_an_axis_share_one_number_format) {
  char l[8][32];
  /* a log axis of triangles from 100 to a million: plain numbers, no "1e+06" */
  double tri[5] = {100, 1000, 10000, 100000, 1000000};
  jnd_plot_tick_labels(tri, 5, 1, l);
  CHECK(strcmp(l[3], "100000") == 0 && strcmp(l[4], "1000000") == 0);
  CHECK(none_contain(l, 5, "e") && none_contain(l, 5, "\u00d7"));
  /* past 7 digits every tick is a power of ten, the small ones too */
  double big[4] = {1000, 1e5, 1e7, 1e9};
  jnd_plot_tick_labels(big, 4, 1, l);
  CHECK(strcmp(l[0], "10\u00b3") == 0 && strcmp(l[3], "10\u2079") == 0);
  CHECK(all_contain(l, 4, "10") && none_contain(l, 4, "e"));
  /* a linear axis: the same decimals on every tick */
  double lin[6] = {0, 0.2, 0.4, 0.6, 0.8, 1};
  jnd_plot_tick_labels(lin, 6, 0, l);
  CHECK(strcmp(l[0], "0.0") == 0 && strcmp(l[1], "0.2") == 0 && strcmp(l[5], "1.0") == 0);
  double mix[3] = {0, 2.5e6, 5e6};
  jnd_plot_tick_labels(mix, 3, 0, l);
  CHECK(strcmp(l[1], "2500000") == 0 && strcmp(l[2], "5000000") == 0);
  double tiny[3] = {0, 5e-5, 1e-4};
  jnd_plot_tick_labels(tiny, 3, 0, l);
  CHECK(strcmp(l[0], "0") == 0 && strcmp(l[1], "5\u00d710\u207b\u2075") == 0 && strcmp(l[2], "1\u00d710\u207b\u2074") == 0);
  /* a plot's own axes, 100 to 2e6 triangles: one format on each */
  double x[3] = {150, 40000, 2e6}, y[3] = {1, 0.5, 0};
  jnd_plot_series s = {.x = x, .y = y, .n = 3, .label = "unlit", .colour = RED, .line = 1};
  jnd_plot_axes ax = {.log_x = 1, .xmin = NAN, .xmax = NAN, .ymin = 0, .ymax = 1};
  jnd_plot_layout L;
  CHECK_OK(jnd_plot_lines_layout(&ax, &s, 1, &L));
  CHECK(L.nticks[0] >= 4 && L.nticks[1] >= 3);
  for (int a = 0; a < 2; a++) {
    int plain = 0, sci = 0;
    for (int i = 0; i < L.nticks[a]; i++) {
      if (!L.tick_label[a][i][0]) continue;
      CHECK(!strstr(L.tick_label[a][i], "e+"));
      if (strstr(L.tick_label[a][i], "10\u2070") || strstr(L.tick_label[a][i], "\u00d7")) sci++;
      else plain++;
    }
    CHECK(plain == 0 || sci == 0);
  }
}

static int overlap(const jnd_box *a, const jnd_box *b) {
  return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

TEST(every_text_of_a_plot_is_inside_the_picture_and_none_covers_another_or_the_data) {
  /* lod's Pareto plot as it was: five markers, two of them at the right
   * edge, long legend entries, a threshold; the legend and the markers'
   * labels used to cover the data and each other, "perceptual" was clipped */
  double x[4] = {200, 3000, 40000, 120000}, y1[4] = {1, 0.4, 0.1, 0}, y2[4] = {1, 0.6, 0.05, 0};
  jnd_plot_series s[2] = {
      {.x = x, .y = y1, .n = 4, .label = "unlit, eq. 1 (largest 0.0123)", .colour = RED, .line = 1, .markers = 1},
      {.x = x, .y = y2, .n = 4, .label = "lit, eq. 3 (largest 0.000456)", .colour = {0, 0, 1}, .line = 1, .markers = 1}};
  jnd_plot_mark m[5] = {{3000, "003 lit 3000", RED}, {3000, "003 unlit 3000", RED}, {120000, "meshopt 120000", RED},
                        {40000, "px rule 40000", RED}, {120000, "perceptual 120000", RED}};
  jnd_plot_hline h = {0.25, "threshold p = 0.25", {0.4f, 0.4f, 0.4f}};
  jnd_plot_axes ax = {.title = "003 Pareto curves: desktop (1920 x 1080, 40 px/deg)", .xlabel = "triangles",
                      .ylabel = "error / its largest value", .log_x = 1, .xmin = NAN, .xmax = NAN, .ymin = 0,
                      .ymax = 1, .width = 640, .height = 420, .marks = m, .nmarks = 5, .hlines = &h, .nhlines = 1};
  jnd_plot_layout L;
  CHECK_OK(jnd_plot_lines_layout(&ax, s, 2, &L));
  int marks = 0, legend = 0;
  for (int i = 0; i < L.ntexts; i++) {
    const jnd_box *b = &L.text_box[i];
    CHECK(b->x0 >= 0 && b->y0 >= 0 && b->x1 <= L.width && b->y1 <= L.height);
    for (int j = 0; j < i; j++)
      if (overlap(b, &L.text_box[j])) fprintf(stderr, "overlap: \"%s\" and \"%s\"\n", L.text[i], L.text[j]);
    for (int j = 0; j < i; j++) CHECK(!overlap(b, &L.text_box[j]));
    /* nothing but the tick labels next to it touches the data area */
    if (L.text_kind[i] != 'X' && L.text_kind[i] != 'Y') CHECK(!overlap(b, &L.plot));
    marks += L.text_kind[i] == 'm';
    legend += L.text_kind[i] == 'l';
    if (L.text_kind[i] == 'l') CHECK(b->y0 >= L.plot.y1); /* legends below the data */
  }
  CHECK(marks == 5 && legend == 3);
  CHECK(!overlap(&L.legend, &L.plot) && L.legend.x1 > L.legend.x0);
  /* the "perceptual" marker's label is all there: its box is as wide as the text */
  for (int i = 0; i < L.ntexts; i++)
    if (L.text_kind[i] == 'm' && strncmp(L.text[i], "perceptual", 10) == 0)
      CHECK(L.text_box[i].x1 - L.text_box[i].x0 >= jnd_text_width(L.text[i], 13));
  /* the title and the axis labels shrink to fit a narrow picture rather than being cut */
  ax.xlabel = "predicted − measured threshold resolution (pixels; bins of 32, the ends ±512 and beyond)";
  ax.width = 420;
  CHECK_OK(jnd_plot_lines_layout(&ax, s, 2, &L));
  for (int i = 0; i < L.ntexts; i++) CHECK(L.text_box[i].x0 >= 0 && L.text_box[i].x1 <= L.width);
}

TEST(a_bound_is_drawn_off_the_line_with_an_arrow_and_a_threshold_across_the_plot) {
  /* texres's series: 1 and 3 measured, 2 judged until it failed (a lower
   * bound), the threshold at 0.5 */
  double x[3] = {1, 2, 3}, y[3] = {0.2, 0.9, 0.4};
  signed char bound[3] = {0, 1, 0};
  jnd_rgb blue = {0, 0, 1}, grey = {0.4f, 0.4f, 0.4f};
  jnd_plot_series s = {.x = x, .y = y, .n = 3, .label = "normal", .colour = blue, .line = 1, .markers = 1,
                       .bound = bound};
  jnd_plot_hline h = {0.5, "threshold p = 0.5", grey};
  jnd_plot_axes ax = {.xmin = 0.5, .xmax = 3.5, .ymin = 0, .ymax = 1, .width = 500, .height = 400, .hlines = &h,
                      .nhlines = 1, .bound_label = "lower bound (stopped once it failed)"};
  jnd_plot_layout L;
  jnd_image img;
  CHECK_OK(jnd_plot_lines_layout(&ax, &s, 1, &L));
  CHECK_OK(jnd_plot_lines(&ax, &s, 1, &img));
  double px[3], py[3];
  for (int i = 0; i < 3; i++) px[i] = to_px(&L, 0, x[i], 0.5, 3.5), py[i] = to_px(&L, 1, y[i], 0, 1);
  /* the line runs from point 1 to point 3 past the bound ... */
  CHECK(ink_near(&img, 0.5 * (px[0] + px[2]), 0.5 * (py[0] + py[2]), 1, blue));
  /* ... not through it: half-way from point 1 to the bound there is no line */
  CHECK(!ink_near(&img, 0.5 * (px[0] + px[1]), 0.5 * (py[0] + py[1]), 2, blue));
  /* the bound's marker and its arrow above it */
  CHECK(ink_near(&img, px[1], py[1], 5, blue));
  CHECK(ink_near(&img, px[1], py[1] - 15, 1, blue));
  CHECK(!ink_near(&img, px[1], py[1] + 15, 1, blue));
  /* the threshold: dashed across the whole plot area at y = 0.5 */
  double ty = to_px(&L, 1, 0.5, 0, 1);
  int drawn = 0, n = 0;
  for (double xx = L.plot.x0 + 4; xx < L.plot.x1 - 4; xx += 1, n++) drawn += ink_near(&img, xx, ty, 0, grey);
  CHECK(drawn > n / 2);
  /* the legend names the series, the threshold and the bound */
  int named = 0;
  for (int i = 0; i < L.ntexts; i++)
    if (L.text_kind[i] == 'l')
      named |= (strcmp(L.text[i], "normal") == 0) | (strstr(L.text[i], "threshold") ? 2 : 0) |
               (strstr(L.text[i], "lower bound") ? 4 : 0);
  CHECK(named == 7);
  jnd_image_free(&img);
}

TEST(two_markers_on_one_place_both_show) {
  /* lod's pixel rule and perceptual choice on the same level: one dashed
   * line used to hide the other */
  double x[2] = {1, 10}, y[2] = {0, 1};
  jnd_rgb green = {0, 0.6f, 0}, blue = {0, 0, 1};
  jnd_plot_series s = {.x = x, .y = y, .n = 2, .colour = RED, .line = 1};
  jnd_plot_mark m[2] = {{5, "px rule 5", green}, {5, "perceptual 5", blue}};
  jnd_plot_axes ax = {.xmin = 0, .xmax = 10, .ymin = 0, .ymax = 1, .width = 400, .height = 300, .marks = m, .nmarks = 2};
  jnd_plot_layout L;
  jnd_image img;
  CHECK_OK(jnd_plot_lines_layout(&ax, &s, 1, &L));
  CHECK_OK(jnd_plot_lines(&ax, &s, 1, &img));
  double px = jnd_plot_layout_map(&L, 0, 5);
  int g = 0, b = 0;
  for (double yy = L.plot.y0 + 2; yy < L.plot.y1 - 2; yy++) g += ink_near(&img, px, yy, 0, green), b += ink_near(&img, px, yy, 0, blue);
  CHECK(g > 20 && b > 20);
  jnd_image_free(&img);
}

TEST(grid_cells_take_the_colour_of_their_value) {
  double v[4] = {0, 1, 2, NAN};
  const char *rows[2] = {"2048", "1024"}, *cols[2] = {"512", "256"};
  jnd_plot_grid_spec g = {0};
  g.rows = g.cols = 2;
  g.value = v;
  g.row_labels = rows;
  g.col_labels = cols;
  g.title = "matrix";
  g.row_title = "albedo";
  g.col_title = "normal";
  g.vmin = 0;
  g.vmax = 2;
  g.cell_px = 40;
  jnd_image img;
  CHECK_OK(jnd_plot_grid(&g, &img));
  /* find the first cell: the top-left pixel of the grid has the scale's bottom colour */
  jnd_rgb c0 = jnd_colour_scale(0), c1 = jnd_colour_scale(1);
  int found0 = 0, found1 = 0;
  for (int y = 0; y < img.h; y++)
    for (int x = 0; x < img.w; x++) {
      size_t i = (size_t)y * img.w + x;
      float r = jnd_image_plane(&img, 0)[i], gg = jnd_image_plane(&img, 1)[i], b = jnd_image_plane(&img, 2)[i];
      found0 += fabsf(r - c0.r) < 1e-3f && fabsf(gg - c0.g) < 1e-3f && fabsf(b - c0.b) < 1e-3f;
      found1 += fabsf(r - c1.r) < 1e-3f && fabsf(gg - c1.g) < 1e-3f && fabsf(b - c1.b) < 1e-3f;
    }
  /* most of a 40 × 40 cell (less its text); the bar holds a few rows of each too */
  CHECK(found0 > 900 && found1 > 900);
  jnd_image_free(&img);
}

TEST(colour_scale_rises_in_lightness) {
  double prev = -1;
  for (int i = 0; i <= 100; i++) {
    jnd_rgb c = jnd_colour_scale(i / 100.0);
    double l = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    CHECK(l > prev);
    prev = l;
  }
  jnd_rgb a = jnd_palette(0), b = jnd_palette(1);
  CHECK(a.r != b.r || a.g != b.g || a.b != b.b);
}

/* Numbers printed beside an axis's values (lod's Pareto legend: "largest
 * 5.02e-05" beside "largest 0.0778") take the tick labels' format: plain
 * decimals, or m×10ⁿ for all of them, never printf's e-notation; each
 * reads back as its value to the digits asked for. */
static double read_label(const char *s) {
  const char *x = strstr(s, "\u00d710");
  if (!x) return strtod(s, NULL);
  static const char *const digit[10] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                        "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  const char *p = x + strlen("\u00d710");
  int sign = 1, e = 0;
  if (strncmp(p, "\u207b", strlen("\u207b")) == 0) sign = -1, p += strlen("\u207b");
  for (;;) {
    int d = -1;
    for (int k = 0; k < 10 && d < 0; k++)
      if (strncmp(p, digit[k], strlen(digit[k])) == 0) d = k;
    if (d < 0) break;
    e = 10 * e + d;
    p += strlen(digit[d]);
  }
  return strtod(s, NULL) * pow(10, sign * e);
}

TEST(numbers_beside_an_axis_share_its_format_and_read_back) {
  char l[4][32];
  const double plain[3] = {0.0778, 1234, 12.5};
  jnd_plot_number_labels(plain, 3, 3, l);
  CHECK(strcmp(l[0], "0.0778") == 0);
  CHECK(strcmp(l[1], "1230") == 0);
  CHECK(strcmp(l[2], "12.5") == 0);
  /* each its own decimals, as on a logarithmic axis: 4, not 4.00 */
  const double dist_m[4] = {4, 22, 0.25, 96};
  jnd_plot_number_labels(dist_m, 4, 3, l);
  CHECK(strcmp(l[0], "4") == 0 && strcmp(l[1], "22") == 0 && strcmp(l[2], "0.25") == 0 && strcmp(l[3], "96") == 0);
  /* one of them needs a power of ten: all take it */
  const double mixed[2] = {0.0778, 5.02e-5};
  jnd_plot_number_labels(mixed, 2, 3, l);
  CHECK(strcmp(l[0], "7.78\u00d710\u207b\u00b2") == 0);
  CHECK(strcmp(l[1], "5.02\u00d710\u207b\u2075") == 0);
  /* rounding that carries into the next power, large values, zero */
  const double more[4] = {9.996, 2.5e9, 0, -0.031};
  jnd_plot_number_labels(more, 4, 3, l);
  CHECK(strcmp(l[2], "0") == 0);
  for (int i = 0; i < 4; i++) {
    CHECK(!strchr(l[i], 'e'));
    if (more[i] != 0) CHECK_NEAR(read_label(l[i]) / more[i], 1, 0.005);
  }
  CHECK(strcmp(l[0], "1.0\u00d710\u00b9") == 0); /* the mantissas share one decimal (2.5, -3.1) */
  /* a sweep: every positive value reads back within half a unit of its third digit */
  for (double v = 1.234e-6; v < 1e9; v *= 3.7) {
    const double one[1] = {v};
    jnd_plot_number_labels(one, 1, 3, l);
    CHECK(!strchr(l[0], 'e'));
    CHECK_NEAR(read_label(l[0]) / v, 1, 0.0051);
  }
}

RUN_TESTS(a_thick_line_covers_its_path_and_nothing_far_from_it, text_is_drawn_within_its_measured_width,
          a_line_plot_maps_its_data_range_onto_the_plot_area, the_tick_labels_of_an_axis_share_one_number_format,
          every_text_of_a_plot_is_inside_the_picture_and_none_covers_another_or_the_data,
          a_bound_is_drawn_off_the_line_with_an_arrow_and_a_threshold_across_the_plot, two_markers_on_one_place_both_show,
          grid_cells_take_the_colour_of_their_value,
          colour_scale_rises_in_lightness, numbers_beside_an_axis_share_its_format_and_read_back)
