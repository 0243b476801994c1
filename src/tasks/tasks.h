/* Internal helpers of the tasks layer, shared by the task files. Each part
 * is a delimited block owned by the file that implements it. */
#ifndef JND_TASKS_H
#define JND_TASKS_H

#include <stddef.h>
#include <stdint.h>
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

/* ---- linalg.c (end) ---- */

/* ---- pca.c (begin) ---- */

/* The knee of the cumulative energy of n descending values (001): the
 * component count 1..n where the curve from (0, 0) to (n, total) lies
 * farthest above its chord (jnd_knee). */
int pca_energy_knee(const double *energy, int n);

/* Rendered visibility hook: see jnd_pca_rendered_visibility (jnd.h). */
jnd_status pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc,
                                   const char *model_path, const char *material, double *p_detect);

/* ---- pca.c (end) ---- */

/* ---- lod.c: 003's screen-space and perceptual terms, for tests (begin) ---- */

/* E_p² · W2·H2 (003 eq. 2 before its normalisation): test, mw × mh 8-bit
 * codes (c planes, the M2 screen), against ref, w × h codes (M1), blocks by
 * area. */
double poi_ep_sum_codes(const uint8_t *ref, int w, int h, const uint8_t *test, int mw, int mh, int c);

/* M_p · N (003 eq. 4 before its normalisation) of two w × h luma planes on a
 * display of ppd pixels per degree. */
double poi_mp_sum(const float *y1, const float *y2, int w, int h, double ppd);

/* ---- lod.c (end) ---- */

#endif
