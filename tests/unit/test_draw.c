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
  jnd_image_free(&img);
  /* vertical text runs upwards from its anchor */
  CHECK_OK(jnd_canvas_new(&img, 60, 300, WHITE));
  jnd_draw_text(&img, 30, 260, "P(detect)", 16, (jnd_rgb){0, 0, 0}, JND_ALIGN_LEFT, 1);
  ink_box(&img, box);
  CHECK(box[3] <= 262 && box[1] < 260 - 50 && box[2] - box[0] < 22);
  jnd_image_free(&img);
}

TEST(a_line_plot_maps_its_data_range_onto_the_plot_area) {
  double x[2] = {0, 10}, y[2] = {0, 10};
  jnd_plot_series s = {x, y, 2, "series", RED, 1, 0, 3};
  jnd_plot_axes ax = {0};
  ax.title = "t";
  ax.xlabel = "x";
  ax.ylabel = "y";
  ax.xmin = ax.ymin = 0;
  ax.xmax = ax.ymax = 10;
  ax.width = 400;
  ax.height = 300;
  jnd_image img;
  CHECK_OK(jnd_plot_lines(&ax, &s, 1, &img));
  CHECK(img.w == 400 && img.h == 300);
  /* the diagonal runs from the bottom-left corner of the plot area to its top-right */
  int minx = img.w, maxx = -1, miny = img.h, maxy = -1;
  for (int py = 0; py < img.h; py++)
    for (int px = 0; px < 330; px++) /* left of the legend */
      if (is_red(&img, px, py)) {
        if (px < minx) minx = px;
        if (px > maxx) maxx = px;
        if (py < miny) miny = py;
        if (py > maxy) maxy = py;
      }
  CHECK(minx >= 82 && minx <= 86);       /* plot area starts at x = 84 */
  CHECK(maxy >= 236 && maxy <= 240);     /* and ends at y = H − 62 = 238 */
  /* the line is straight: at x = 84 + 0.5·(376 − 84) it is half-way up */
  int mid = 84 + (376 - 84) / 2, found = 0;
  for (int py = 0; py < img.h; py++) found |= is_red(&img, mid, py) && abs(py - (238 + 44) / 2) <= 3;
  CHECK(found);
  jnd_image_free(&img);
  CHECK_STATUS(jnd_plot_lines(&(jnd_plot_axes){.width = 50, .height = 50}, &s, 1, &img), JND_ERR_ARG);
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

RUN_TESTS(a_thick_line_covers_its_path_and_nothing_far_from_it, text_is_drawn_within_its_measured_width,
          a_line_plot_maps_its_data_range_onto_the_plot_area, grid_cells_take_the_colour_of_their_value,
          colour_scale_rises_in_lightness)
