/* `jnd diff`: two images as a viewer sees them on a display → JND map →
 * probability map (000 eq. 4) → pooled probability of detection (000 §6). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "pool/pool.h"

/* P from JND, 000 eq. 4: 1 − exp(ln 0.5 · jnd^beta) = 1 − 2^(−jnd^beta) */
static inline float prob(float j, float beta) {
  return j > 0 ? 1.0f - jnd_fast_exp2(-jnd_fast_pow(j, beta)) : 0.0f;
}

/* p-th percentile of P over a sorted JND array: P is monotonic in JND, so the
 * sorted P values are P of the sorted JND values */
static double p_percentile(const float *sorted_jnd, size_t n, double pct, float beta) {
  double pos = jnd_clampd(pct, 0, 100) / 100.0 * (double)(n - 1);
  size_t k = (size_t)floor(pos);
  if (k >= n - 1) return prob(sorted_jnd[n - 1], beta);
  double t = pos - (double)k, a = prob(sorted_jnd[k], beta), b = prob(sorted_jnd[k + 1], beta);
  return a + t * (b - a);
}

jnd_status jnd_diff_summarise(const jnd_image *map, double beta, const jnd_pooling *pool,
                              jnd_diff_stats *st) {
  memset(st, 0, sizeof *st);
  size_t n = (size_t)map->w * map->h;
  if (n == 0) return jnd_fail(JND_ERR_ARG, "summary of an empty map");
  jnd_pooling p93 = {JND_POOL_PERCENTILE, 93.0};
  if (!pool) pool = &p93;
  const float fb = (float)beta;
  /* sums in fixed blocks (the same order whatever the thread count), each
   * block's values computed in a vectorisable loop */
  enum { BLOCK = 4096 };
  const size_t nblocks = (n + BLOCK - 1) / BLOCK;
  double *part = jnd_calloc(nblocks * 4, sizeof *part);
  if (!part) return JND_ERR_NOMEM;
#pragma omp parallel for schedule(static)
  for (size_t bk = 0; bk < nblocks; bk++) {
    float a[BLOCK], b[BLOCK], c[BLOCK];
    size_t i0 = bk * BLOCK, m = n - i0 < BLOCK ? n - i0 : BLOCK;
    const float *j = map->data + i0;
    for (size_t i = 0; i < m; i++) {
      a[i] = jnd_fast_pow(j[i], 2.4f);
      b[i] = prob(j[i], fb);
      c[i] = jnd_fast_pow(b[i], 2.4f);
    }
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    for (size_t i = 0; i < m; i++) {
      s0 += j[i];
      s1 += a[i];
      s2 += b[i];
      s3 += c[i];
    }
    part[bk * 4] = s0;
    part[bk * 4 + 1] = s1;
    part[bk * 4 + 2] = s2;
    part[bk * 4 + 3] = s3;
  }
  double sj = 0, sj24 = 0, sp = 0, sp24 = 0;
  for (size_t bk = 0; bk < nblocks; bk++) {
    sj += part[bk * 4];
    sj24 += part[bk * 4 + 1];
    sp += part[bk * 4 + 2];
    sp24 += part[bk * 4 + 3];
  }
  free(part);
  st->jnd_mean = sj / (double)n;
  st->jnd_minkowski = pow(sj24 / (double)n, 1.0 / 2.4);
  st->p_mean = sp / (double)n;
  float *v = jnd_alloc(n, sizeof *v);
  if (!v) return JND_ERR_NOMEM;
  memcpy(v, map->data, n * sizeof *v);
  jnd_status s = jnd_sort_floats(v, n);
  if (s != JND_OK) {
    free(v);
    return s;
  }
  st->jnd_p93 = jnd_percentile_sorted(v, n, 93);
  st->jnd_max = v[n - 1];
  st->p_p50 = p_percentile(v, n, 50, fb);
  st->p_p93 = p_percentile(v, n, 93, fb);
  st->p_p99 = p_percentile(v, n, 99, fb);
  st->p_max = prob(v[n - 1], fb);
  switch (pool->kind) {
  case JND_POOL_MAX: st->p_detect = st->p_max; break;
  case JND_POOL_MEAN: st->p_detect = st->p_mean; break;
  case JND_POOL_MINKOWSKI: st->p_detect = pow(sp24 / (double)n, 1.0 / 2.4); break;
  default: st->p_detect = p_percentile(v, n, pool->percentile, fb); break;
  }
  free(v);
  return JND_OK;
}

jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ri, jnd_image *test,
                          const jnd_image_info *ti, const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats) {
  const jnd_model_params *p = jnd_model_get_params(m);
  jnd_image map = {0};
  jnd_status s = JND_OK;
  if (ref->w != test->w || ref->h != test->h) {
    s = jnd_fail(JND_ERR_ARG, "image sizes differ: %d × %d vs %d × %d", ref->w, ref->h, test->w, test->h);
    goto fail;
  }
  if ((s = jnd_display_apply(&p->display, ref, ri->encoding, ri->has_alpha, ref)) != JND_OK) goto fail;
  if ((s = jnd_display_apply(&p->display, test, ti->encoding, ti->has_alpha, test)) != JND_OK) goto fail;
  if ((s = jnd_model_diff_consume(m, ref, test, in, &map)) != JND_OK) return s;
  if (stats && (s = jnd_diff_summarise(&map, p->beta, pool, stats)) != JND_OK) {
    jnd_image_free(&map);
    return s;
  }
  if (jnd_out)
    *jnd_out = map;
  else
    jnd_image_free(&map);
  return JND_OK;
fail:
  jnd_image_free(ref);
  jnd_image_free(test);
  return s;
}
