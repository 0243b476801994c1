/* Internal helpers of the tasks layer, shared by the task files. Each part
 * is a delimited block owned by the file that implements it. */
#ifndef JND_TASKS_H
#define JND_TASKS_H

#include <stddef.h>
#include "jnd.h"

/* ---- linalg.c: small dense linear algebra for pca.c (begin) ---- */

/* Means of n channels: planes[ch] points at count floats. Double
 * accumulation in fixed-size chunks summed in order (thread-independent). */
void linalg_channel_means(const float *const *planes, int n, size_t count, double *mean);

/* The n × n covariance (1/count) Σ (w_i(x_i − m_i))(w_j(x_j − m_j)) of n
 * planes; cov is row-major, symmetric, filled in full. Deterministic. */
jnd_status linalg_weighted_covariance(const float *const *planes, int n, size_t count,
                                      const double *mean, const double *weight, double *cov);

/* Eigen-decomposition of a symmetric n × n matrix (row-major, not
 * modified): eigenvalues descending, vectors as columns of vec (row-major
 * n × n, vec[i·n + k] = component i of vector k), each with its
 * largest-magnitude entry positive. LAPACKE dsyev. */
jnd_status linalg_symmetric_eigen(const double *a, int n, double *eigval, double *vec);

/* Index of the knee of a descending sequence's cumulative curve: the point
 * farthest from the chord from (0, 0) to (n, total); returns a count 1..n. */
int linalg_knee(const double *values, int n);

/* ---- linalg.c (end) ---- */

/* ---- pca.c: resampling of single planes (begin) ---- */

/* Resamples a w × h plane to dw × dh with a separable Lanczos-3 filter,
 * widened by the scale factor when shrinking; edges are clamped. */
jnd_status pca_resample_lanczos3(const float *src, int w, int h, float *dst, int dw, int dh);

/* Averages 2^s × 2^s boxes (partial boxes at the edge average what they
 * cover): the coarse plane is ceil(w/2^s) × ceil(h/2^s). */
void pca_box_down(const float *src, int w, int h, int s, float *dst);

/* Upsamples a plane made by pca_box_down(src, w, h, s, ...) back to w × h
 * with Lanczos-3, the coarse samples sitting at the centres of their boxes. */
jnd_status pca_upsample(const float *coarse, int w, int h, int s, float *dst);

/* Rendered visibility hook: see jnd_pca_rendered_visibility (jnd.h). */
jnd_status pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc,
                                   const char *model_path, const char *material, double *p_detect);

/* ---- pca.c (end) ---- */

/* ---- texres_figures.c: pictures of a texres result (begin) ---- */

/* The worst view's figure: the object as rendered (ref_srgb, display
 * signal) beside its heatmap, magnified to a readable size, titled with the
 * view and its pooled P. */
jnd_status texres_worst_view_figure(const jnd_image *ref_srgb, const jnd_image *map, int view, int nviews, double p,
                                    jnd_image *out);

/* ---- texres_figures.c (end) ---- */

#endif
