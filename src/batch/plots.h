/* Pictures the HTML report draws from a command's JSON report (PNG), with
 * the plots of io/draw.h. Each returns 1 when it wrote path, 0 when the
 * report holds nothing to draw, -1 on an error (jnd_last_error()). */
#ifndef JND_BATCH_PLOTS_H
#define JND_BATCH_PLOTS_H

#include <cjson/cJSON.h>

/* texres: the criterion statistic of each map alone against its candidate
 * sizes (log axis), with the threshold p */
int jnd_plot_texres_series(const cJSON *report, const char *path);
/* pca: each component's share of the energy and the cumulative share, with
 * the number of components kept marked */
int jnd_plot_pca_energy(const cJSON *report, const char *path);

#endif
