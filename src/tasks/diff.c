/* `jnd diff`: two images as a viewer sees them on a display → JND map →
 * probability map (000 eq. 4) → pooled probability of detection (000 §6). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "pool/pool.h"

jnd_status jnd_diff_summarise(const jnd_image *map, double beta, const jnd_pooling *pool,
                              jnd_diff_stats *st) {
  memset(st, 0, sizeof *st);
  size_t n = (size_t)map->w * map->h;
  if (n == 0) return jnd_fail(JND_ERR_ARG, "summary of an empty map");
  jnd_pooling p93 = {JND_POOL_PERCENTILE, 93.0};
  if (!pool) pool = &p93;
  float *v = jnd_alloc(n, sizeof *v);
  if (!v) return JND_ERR_NOMEM;
  /* P = 1 − exp(ln 0.5 · jnd^beta) = 1 − 2^(−jnd^beta) (000 eq. 4) */
  double sj = 0, sj24 = 0, sp = 0;
  const float fb = (float)beta;
  for (size_t i = 0; i < n; i++) {
    float j = map->data[i];
    sj += j;
    sj24 += jnd_fast_pow(j, 2.4f);
    v[i] = j > 0 ? 1.0f - jnd_fast_exp2(-jnd_fast_pow(j, fb)) : 0.0f;
    sp += v[i];
  }
  st->jnd_mean = sj / (double)n;
  st->jnd_minkowski = pow(sj24 / (double)n, 1.0 / 2.4);
  st->p_mean = sp / (double)n;
  jnd_status s = jnd_sort_floats(v, n);
  if (s != JND_OK) {
    free(v);
    return s;
  }
  st->p_p50 = jnd_percentile_sorted(v, n, 50);
  st->p_p93 = jnd_percentile_sorted(v, n, 93);
  st->p_p99 = jnd_percentile_sorted(v, n, 99);
  st->p_max = v[n - 1];
  switch (pool->kind) {
  case JND_POOL_MAX: st->p_detect = st->p_max; break;
  case JND_POOL_MEAN: st->p_detect = st->p_mean; break;
  case JND_POOL_MINKOWSKI: {
    double s24 = 0;
    for (size_t i = 0; i < n; i++) s24 += pow(v[i], 2.4);
    st->p_detect = pow(s24 / (double)n, 1.0 / 2.4);
    break;
  }
  default: st->p_detect = jnd_percentile_sorted(v, n, pool->percentile); break;
  }
  /* JND order statistics: reuse the buffer */
  memcpy(v, map->data, n * sizeof *v);
  if ((s = jnd_sort_floats(v, n)) == JND_OK) {
    st->jnd_p93 = jnd_percentile_sorted(v, n, 93);
    st->jnd_max = v[n - 1];
  }
  free(v);
  return s;
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
