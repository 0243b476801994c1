/* `jnd diff`: two images as a viewer sees them on a display → JND map →
 * probability map (000 eq. 4) → pooled probability of detection (000 §6). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "pool/pool.h"
#include "tasks/tasks.h"
#include "vision/vision.h"


/* P of a JND, for percentiles of P: P is monotonic in JND, so the p-th
 * percentile of P interpolates P of the JND map's order statistics */
static double prob_of(double j, const void *beta) { return jnd_prob_of_jnd((float)j, *(const float *)beta); }

enum { SUM_BLOCK = 4096 };

/* one block's Σ j, Σ j^2.4, Σ P and (for Minkowski pooling) Σ P^2.4: the
 * values in vectorisable loops, a loop a step (a value's whole chain, its
 * log2 and three exp2s one after the other, in one loop was bound by their
 * latency: docs/speed.md "Eleventh pass"), then summed in order. j^2.4 and P share j's
 * log2 (the same floats as jnd_fast_pow and jnd_prob_of_jnd); without
 * Minkowski pooling Σ P^2.4 is 0 and not computed. */
JND_HOT static void block_sums(const float *j, size_t m, float beta, int minkowski, double out[4]) {
  float a[SUM_BLOCK], b[SUM_BLOCK], l[SUM_BLOCK];
#pragma omp simd
  for (size_t i = 0; i < m; i++) l[i] = jnd_fast_log2_of(j[i]);
#pragma omp simd
  for (size_t i = 0; i < m; i++) a[i] = j[i] > 0.0f ? jnd_fast_exp2(2.4f * l[i]) : 0.0f;
#pragma omp simd
  for (size_t i = 0; i < m; i++) b[i] = jnd_prob_power(l[i], beta);
#pragma omp simd
  for (size_t i = 0; i < m; i++) b[i] = jnd_prob_of_power(j[i], b[i]);
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  if (minkowski) {
    float c[SUM_BLOCK];
#pragma omp simd
    for (size_t i = 0; i < m; i++) c[i] = jnd_fast_pow(b[i], 2.4f);
    for (size_t i = 0; i < m; i++) {
      s0 += j[i];
      s1 += a[i];
      s2 += b[i];
      s3 += c[i];
    }
  } else {
    for (size_t i = 0; i < m; i++) {
      s0 += j[i];
      s1 += a[i];
      s2 += b[i];
    }
  }
  out[0] = s0;
  out[1] = s1;
  out[2] = s2;
  out[3] = s3;
}

jnd_status jnd_diff_summarise(const jnd_image *map, double beta, const jnd_pooling *pool,
                              jnd_diff_stats *st) {
  memset(st, 0, sizeof *st);
  size_t n = (size_t)map->w * map->h;
  if (n == 0) return jnd_fail(JND_ERR_ARG, "summary of an empty map");
  jnd_calibration cal;   /* the default pooling is the calibration's (P93, 000 §6) */
  jnd_calibration_defaults(&cal);
  jnd_pooling dflt = {JND_POOL_PERCENTILE, cal.percentile};
  if (!pool) pool = &dflt;
  const float fb = (float)beta;
  const int minkowski = pool->kind == JND_POOL_MINKOWSKI;
  /* sums in fixed blocks (the same order whatever the thread count), and
   * the values' bins for the percentiles counted as each block is read
   * (jnd_order_count: one pass over the map, not two); thread t takes
   * blocks [nblocks·t/nt, nblocks·(t+1)/nt), its counts row t */
  const size_t nblocks = (n + SUM_BLOCK - 1) / SUM_BLOCK;
  int nt = omp_get_max_threads();
  nt = nt < 1 ? 1 : nt > JND_ORDER_RANGES_MAX ? JND_ORDER_RANGES_MAX : nt;
  double *part = jnd_calloc(nblocks * 4, sizeof *part);
  size_t *h4 = jnd_alloc((size_t)nt * 4 * JND_ORDER_BINS, sizeof *h4);
  size_t *hist = jnd_alloc((size_t)nt * JND_ORDER_BINS, sizeof *hist);
  size_t bound[JND_ORDER_RANGES_MAX + 1];
  int team = 1;
  if (!part || !h4 || !hist) {
    free(part);
    free(h4);
    free(hist);
    return JND_ERR_NOMEM;
  }
#pragma omp parallel num_threads(nt)
  {
    const int tn = omp_get_num_threads(), t = omp_get_thread_num();
    const size_t b0 = nblocks * (size_t)t / (size_t)tn, b1 = nblocks * (size_t)(t + 1) / (size_t)tn;
    size_t *c4 = h4 + (size_t)t * 4 * JND_ORDER_BINS;
    memset(c4, 0, sizeof *c4 * 4 * JND_ORDER_BINS);
    for (size_t bk = b0; bk < b1; bk++) {
      size_t i0 = bk * SUM_BLOCK, m = n - i0 < SUM_BLOCK ? n - i0 : SUM_BLOCK;
      block_sums(map->data + i0, m, fb, minkowski, part + bk * 4);
      jnd_order_count(map->data + i0, m, c4);
    }
    jnd_order_fold(c4, hist + (size_t)t * JND_ORDER_BINS);
    bound[t] = b0 * SUM_BLOCK < n ? b0 * SUM_BLOCK : n;
    if (t == tn - 1) {
      bound[tn] = n;
      team = tn;
    }
  }
  free(h4);
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
  jnd_ranks r;
  jnd_ranks_init(&r, n);
  const double pcts[] = {93, 50, 99, 100, pool->kind == JND_POOL_PERCENTILE ? pool->percentile : 93};   /* p_p93 etc. are named statistics */
  jnd_status s = JND_OK;
  for (size_t i = 0; i < sizeof pcts / sizeof pcts[0] && s == JND_OK; i++) s = jnd_ranks_want(&r, pcts[i]);
  if (s == JND_OK) s = jnd_ranks_select_counted(&r, map->data, team, bound, hist);
  free(hist);
  if (s != JND_OK) return s;
  st->jnd_p93 = jnd_ranks_percentile(&r, 93, NULL, NULL);
  st->jnd_max = jnd_ranks_percentile(&r, 100, NULL, NULL);
  st->p_p50 = jnd_ranks_percentile(&r, 50, prob_of, &fb);
  st->p_p93 = jnd_ranks_percentile(&r, 93, prob_of, &fb);
  st->p_p99 = jnd_ranks_percentile(&r, 99, prob_of, &fb);
  st->p_max = jnd_ranks_percentile(&r, 100, prob_of, &fb);
  switch (pool->kind) {
  case JND_POOL_MAX: st->p_detect = st->p_max; break;
  case JND_POOL_MEAN: st->p_detect = st->p_mean; break;
  case JND_POOL_MINKOWSKI: st->p_detect = pow(sp24 / (double)n, 1.0 / 2.4); break;
  default: st->p_detect = jnd_ranks_percentile(&r, pool->percentile, prob_of, &fb); break;
  }
  return JND_OK;
}

jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ri, jnd_image *test,
                          const jnd_image_info *ti, const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats) {
  jnd_model_image *none[2] = {NULL, NULL};
  return diff_files_codes(m, ref, ri, test, ti, none, NULL, in, pool, jnd_out, stats);
}

/* an image kept as codes to planes of their luminances, into img (which
 * holds its size); rgb freed */
static jnd_status codes_to_planes(unsigned char *rgb, const float lum[256], jnd_image *img) {
  const int w = img->w, h = img->h;
  jnd_status s = jnd_image_alloc(img, w, h, 3);
  const size_t npx = (size_t)w * h;
  for (size_t i = 0; s == JND_OK && i < npx; i++)
    for (int c = 0; c < 3; c++) img->data[c * npx + i] = lum[rgb[3 * i + c]];
  free(rgb);
  return s;
}

jnd_status diff_files_codes(jnd_model *m, jnd_image *ref, const jnd_image_info *ri, jnd_image *test,
                            const jnd_image_info *ti, jnd_model_image *prep[2], const float lum[256],
                            const jnd_diff_inputs *in, const jnd_pooling *pool, jnd_image *jnd_out,
                            jnd_diff_stats *stats) {
  const jnd_model_params *p = jnd_model_get_params(m);
  jnd_image map = {0};
  jnd_status s = JND_OK;
  if (ref->w != test->w || ref->h != test->h) {
    s = jnd_fail(JND_ERR_ARG, "image sizes differ: %d × %d vs %d × %d", ref->w, ref->h, test->w, test->h);
    goto fail;
  }
  if (prep[0] && prep[1]) {
    memset(ref, 0, sizeof *ref);
    memset(test, 0, sizeof *test);
    s = jnd_model_diff_images(m, prep[0], prep[1], in, &map);
    prep[0] = prep[1] = NULL;
    if (s != JND_OK) return s;
  } else {
    jnd_image *img[2] = {ref, test};
    const jnd_image_info *info[2] = {ri, ti};
    for (int a = 0; a < 2; a++) {
      /* codes beside a decoded image: its luminances as planes */
      if (prep[a]) {
        s = codes_to_planes(jnd_model_image_codes(prep[a]), lum, img[a]);
        prep[a] = NULL;
      } else {
        s = jnd_display_apply(&p->display, img[a], info[a]->encoding, info[a]->has_alpha, img[a]);
      }
      if (s != JND_OK) goto fail;
    }
    if ((s = jnd_model_diff_consume(m, ref, test, in, &map)) != JND_OK) return s;
  }
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
  for (int a = 0; a < 2; a++) {
    jnd_model_image_free(prep[a]);
    prep[a] = NULL;
  }
  jnd_image_free(ref);
  jnd_image_free(test);
  return s;
}
