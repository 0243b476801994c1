/* The picture of a calibration that a person reads (drawn with io/draw.h):
 * 000 Fig. 9/11, the histogram of the held-out errors of the predicted
 * threshold resolution. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/draw.h"

#define BIN_PX 32.0 /* 000 Fig. 9's bins */
#define HALF 16     /* bins each side of 0: ±512 pixels, the end bins open */

jnd_status jnd_calibrate_histogram(const jnd_calibrate_result *r, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (r->nscenes < 1 || !r->errors_px) return jnd_fail(JND_ERR_ARG, "calibrate: no held-out errors to draw");
  double x[2 * HALF + 1], count[2 * HALF + 1];
  int widest = 1, used = 0;
  for (int b = 0; b <= 2 * HALF; b++) x[b] = (b - HALF) * BIN_PX, count[b] = 0;
  for (int i = 0; i < r->nscenes; i++) {
    if (!isfinite(r->errors_px[i])) continue;
    int b = (int)floor(r->errors_px[i] / BIN_PX + 0.5);
    b = b < -HALF ? -HALF : b > HALF ? HALF : b;
    count[b + HALF]++;
    used++;
    if (abs(b) + 1 > widest) widest = abs(b) + 1;
  }
  /* empty bins are no bar */
  for (int b = 0; b <= 2 * HALF; b++)
    if (!count[b]) count[b] = NAN;
  char title[160];
  snprintf(title, sizeof title, "Held-out errors of %d scene%s (000 Fig. 9): mean absolute %.1f px", used,
           used == 1 ? "" : "s", r->cv_mae_px);
  jnd_plot_series s = {.x = x, .y = count, .n = 2 * HALF + 1, .label = NULL, .colour = jnd_palette(0),
                       .bar_width = 0.8 * BIN_PX};
  jnd_plot_axes ax = {.title = title,
                      .xlabel = "predicted − measured threshold (pixels; bins of 32, the end bins ±512 and beyond)",
                      .ylabel = "scenes",
                      .xmin = -(widest + 0.5) * BIN_PX, .xmax = (widest + 0.5) * BIN_PX,
                      .ymin = 0, .ymax = NAN, .width = 720, .height = 380, .integer_y = 1};
  return jnd_plot_lines(&ax, &s, 1, out);
}
