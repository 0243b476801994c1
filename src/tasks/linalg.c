/* Small dense linear algebra for the texture-set PCA (001): channel means,
 * the weighted covariance of a (w·h) × C matrix, a symmetric
 * eigen-decomposition (LAPACK).
 * Sums run over fixed chunks of pixels and are added in chunk order, so
 * results are the same for every thread count. */
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"

enum { CHUNK = 1 << 15 };

static size_t chunk_count(size_t count) { return (count + CHUNK - 1) / CHUNK; }

void linalg_channel_means(const float *const *planes, int n, size_t count, double *mean) {
  size_t nch = chunk_count(count);
  for (int c = 0; c < n; c++) {
    double total = 0;
    /* chunks summed in order; each chunk's sum in double */
    for (size_t k = 0; k < nch; k++) {
      size_t a = k * CHUNK, b = a + CHUNK < count ? a + CHUNK : count;
      double s = 0;
      for (size_t i = a; i < b; i++) s += planes[c][i];
      total += s;
    }
    mean[c] = count ? total / (double)count : 0;
  }
}

jnd_status linalg_weighted_covariance(const float *const *planes, int n, size_t count,
                                      const double *mean, const double *weight, double *cov) {
  if (n <= 0 || n > JND_PCA_MAX_CHANNELS || count == 0)
    return jnd_fail(JND_ERR_ARG, "covariance of %d channels × %zu samples", n, count);
  size_t nch = chunk_count(count), tri = (size_t)n * n;
  double *part = jnd_calloc(nch * tri, sizeof *part);
  if (!part) return JND_ERR_NOMEM;
  /* Each chunk writes its own block of part: no shared accumulators. */
#pragma omp parallel for schedule(dynamic, 1)
  for (size_t k = 0; k < nch; k++) {
    size_t a = k * CHUNK, b = a + CHUNK < count ? a + CHUNK : count;
    double *acc = part + k * tri;
    double v[JND_PCA_MAX_CHANNELS];
    for (size_t i = a; i < b; i++) {
      for (int c = 0; c < n; c++) v[c] = weight[c] * ((double)planes[c][i] - mean[c]);
      for (int r = 0; r < n; r++) {
        double vr = v[r];
        double *row = acc + (size_t)r * n;
#pragma omp simd
        for (int c = r; c < n; c++) row[c] += vr * v[c];
      }
    }
  }
  memset(cov, 0, tri * sizeof *cov);
  for (size_t k = 0; k < nch; k++)
    for (size_t i = 0; i < tri; i++) cov[i] += part[k * tri + i];
  for (int r = 0; r < n; r++)
    for (int c = r; c < n; c++) {
      cov[r * n + c] /= (double)count;
      cov[c * n + r] = cov[r * n + c];
    }
  free(part);
  return JND_OK;
}

jnd_status linalg_symmetric_eigen(const double *a, int n, double *eigval, double *vec) {
  double work[JND_PCA_MAX_CHANNELS * JND_PCA_MAX_CHANNELS], w[JND_PCA_MAX_CHANNELS];
  if (n <= 0 || n > JND_PCA_MAX_CHANNELS) return jnd_fail(JND_ERR_ARG, "eigen: %d × %d matrix", n, n);
  memcpy(work, a, (size_t)n * n * sizeof *work);
  lapack_int info = LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'V', 'U', n, work, n, w);
  if (info != 0) return jnd_fail(JND_ERR_INTERNAL, "eigen-decomposition failed (dsyev info %d)", (int)info);
  /* dsyev gives ascending eigenvalues; we want descending. */
  for (int k = 0; k < n; k++) {
    int src = n - 1 - k;
    eigval[k] = w[src];
    int big = 0;
    for (int i = 1; i < n; i++)
      if (fabs(work[i * n + src]) > fabs(work[big * n + src]) + 1e-12) big = i;
    double sign = work[big * n + src] < 0 ? -1.0 : 1.0;
    for (int i = 0; i < n; i++) vec[i * n + k] = sign * work[i * n + src];
  }
  return JND_OK;
}
