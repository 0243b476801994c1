/* Pictures the HTML report draws from a command's JSON report (PNG), with
 * the plots of io/draw.h. Each returns 1 when it wrote path, 0 when the
 * report holds nothing to draw, -1 on an error (jnd_last_error()). */
#ifndef JND_BATCH_PLOTS_H
#define JND_BATCH_PLOTS_H

#include <cjson/cJSON.h>

#include "io/draw.h"

/* texres: the criterion statistic of each map alone against its candidate
 * sizes (log axis): the values judged on every view on a line, those whose
 * judging stopped once they failed (series_decided_early) as lower bounds
 * off it, and the threshold p (parameters.criterion.p) dashed across */
int jnd_plot_texres_series(const cJSON *report, const char *path);
/* pca: each component's share of the energy and the cumulative share, with
 * the number of components kept marked (and the share they hold) */
int jnd_plot_pca_energy(const cJSON *report, const char *path);

/* The same pictures into img (the caller frees it), with their layout
 * (jnd_plot_lines_layout) when layout is not NULL; 1, 0 or -1 as above. */
int jnd_plot_texres_series_image(const cJSON *report, jnd_image *img, jnd_plot_layout *layout);
int jnd_plot_pca_energy_image(const cJSON *report, jnd_image *img, jnd_plot_layout *layout);

#endif
