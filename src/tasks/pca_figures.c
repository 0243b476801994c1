/* The picture of a PCA's contribution matrix (001's |S·Tᵀ|): which input
 * channels feed which component, with names, values and a colour legend,
 * drawn with the shared grid plot (io/draw.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/core.h"
#include "io/draw.h"

jnd_status jnd_pca_contribution_plot(const jnd_pca *pca, const jnd_texset *set, jnd_image *out) {
  enum { MAXC = JND_PCA_MAX_CHANNELS };
  int C = pca->c;
  if (C < 1 || C > MAXC) return jnd_fail(JND_ERR_ARG, "pca: %d channels to draw", C);
  double m[MAXC * MAXC], v[MAXC * MAXC], total = 0;
  jnd_pca_contribution(pca, m);
  for (int k = 0; k < C; k++) total += pca->energy[k];
  /* rows: channels; columns: components (m is [component][channel]) */
  char rl[MAXC][80], cl[MAXC][16], text[MAXC * MAXC][12];
  const char *rows[MAXC], *cols[MAXC], *cells[MAXC * MAXC];
  for (int c = 0; c < C; c++) {
    if (set && set->c == C) snprintf(rl[c], sizeof rl[c], "%s", set->names[c]);
    else snprintf(rl[c], sizeof rl[c], "channel %d", c + 1);
    rows[c] = rl[c];
  }
  for (int k = 0; k < C; k++) {
    snprintf(cl[k], sizeof cl[k], "%d: %.0f%%", k + 1, total > 0 ? 100 * pca->energy[k] / total : 0);
    cols[k] = cl[k];
    for (int c = 0; c < C; c++) {
      v[c * C + k] = m[k * C + c];
      snprintf(text[c * C + k], sizeof text[c * C + k], "%.3f", m[k * C + c]);
      cells[c * C + k] = text[c * C + k];
    }
  }
  jnd_plot_grid_spec g = {.rows = C, .cols = C, .value = v, .cell_text = cells, .row_labels = rows,
                          .col_labels = cols, .title = "How much each channel feeds each component",
                          .row_title = "input channel",
                          .col_title = "component: its share of the energy (cells: sqrt(energy) x abs(basis))",
                          .scale_title = "contribution", .vmin = 0, .vmax = NAN, .cell_px = 64};
  return jnd_plot_grid(&g, out);
}
