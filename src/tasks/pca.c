/* Texture sets in fewer channels (Wronski, 001): a material's maps packed as
 * a (w·h) × C matrix, mean-centred and weighted, decorrelated by PCA; the
 * first K components kept, each at its own resolution and bit depth; the
 * reconstruction a (C × (K+1)) homogeneous matrix; quality as PSNR per
 * channel. This file holds the decomposition and the encoding; the texture
 * sets are pca_texset.c, the automatic choice by PSNR pca_psnr.c, the
 * rendered choice (the material re-rendered with the reconstructed maps and
 * judged, the cheapest encoding whose views pass) pca_render.c, and GPU
 * block compression pca_bc.c; pca_stages.h is what they share
 * (docs/pca.md).
 *
 * Resampling (the scene layer's): components are shrunk by averaging
 * 2^s × 2^s boxes (as mip levels are made) and enlarged with Lanczos-3; maps
 * of different sizes are brought to the largest with Lanczos-3 (widened when
 * shrinking). 001 used a box filter with nearest-neighbour enlargement and
 * notes that a better filter would do better. */
#include <ctype.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"
#include "tasks/tasks.h"
#include "tasks/pca_stages.h"

#define MAXC JND_PCA_MAX_CHANNELS

/* ------------------------------------------------------------------------ */
/* Resampling: the scene layer's (jnd_resample_plane, jnd_box_down_plane)    */
/* ------------------------------------------------------------------------ */

int pca_coarse_side(int n, int s) { return (n + (1 << s) - 1) >> s; }

/* a plane made by jnd_box_down_plane(src, w, h, s, ...) back to w × h with
 * Lanczos-3, the coarse samples sitting at the centres of their boxes */
jnd_status pca_upsample(const float *coarse, int w, int h, int s, float *dst) {
  if (s == 0) {
    memcpy(dst, coarse, (size_t)w * h * sizeof *dst);
    return JND_OK;
  }
  double r = 1.0 / (1 << s);
  return jnd_resample_plane(coarse, pca_coarse_side(w, s), pca_coarse_side(h, s), dst, w, h, r, r, 0, 0);
}

/* ------------------------------------------------------------------------ */
/* Decomposition                                                            */
/* ------------------------------------------------------------------------ */

jnd_status jnd_pca_analyse(const jnd_texset *set, const double *weights, jnd_pca *out) {
  memset(out, 0, sizeof *out);
  if (!set || !set->data || set->c < 1 || set->c > MAXC) return jnd_fail(JND_ERR_ARG, "pca: empty texture set");
  int C = set->c;
  size_t np = (size_t)set->w * set->h;
  const float *planes[MAXC];
  pca_set_planes(set, planes);
  out->c = C;
  for (int c = 0; c < C; c++) {
    out->weight[c] = weights ? weights[c] : 1.0;
    if (!(out->weight[c] > 0)) return jnd_fail(JND_ERR_ARG, "pca: weight of %s must be > 0", set->names[c]);
  }
  linalg_channel_means(planes, C, np, out->mean);
  double cov[MAXC * MAXC];
  jnd_status s = linalg_weighted_covariance(planes, C, np, out->mean, out->weight, cov);
  if (s != JND_OK) return s;
  out->total_variance = 0;
  for (int c = 0; c < C; c++) out->total_variance += cov[c * C + c];
  s = linalg_symmetric_eigen(cov, C, out->energy, out->basis);
  if (s != JND_OK) return s;
  /* round-off can leave tiny negative eigenvalues of a semi-definite matrix */
  for (int k = 0; k < C; k++)
    if (out->energy[k] < 0) out->energy[k] = 0;
  out->knee = pca_energy_knee(out->energy, C);
  return JND_OK;
}

int pca_energy_knee(const double *energy, int n) {
  double x[MAXC + 1], y[MAXC + 1];
  if (n < 1) return 0;
  if (n > MAXC) n = MAXC;
  x[0] = y[0] = 0;
  for (int k = 1; k <= n; k++) {
    x[k] = k;
    y[k] = y[k - 1] + energy[k - 1];
  }
  int knee = jnd_knee(x, y, n + 1, JND_KNEE_ABOVE, 0);
  return knee < 1 ? 1 : knee;
}

void jnd_pca_contribution(const jnd_pca *pca, double *out) {
  int C = pca->c;
  for (int k = 0; k < C; k++)
    for (int c = 0; c < C; c++) out[k * C + c] = sqrt(pca->energy[k]) * fabs(pca->basis[c * C + k]);
}

/* ------------------------------------------------------------------------ */
/* Encoding                                                                 */
/* ------------------------------------------------------------------------ */

void jnd_pca_encoding_default(const jnd_pca *pca, jnd_pca_encoding *e) {
  memset(e, 0, sizeof *e);
  e->components = pca->c;
  for (int k = 0; k < MAXC; k++) e->bits[k] = 8;
}

static size_t comp_pixels(int w, int h, int s) { return (size_t)pca_coarse_side(w, s) * pca_coarse_side(h, s); }

size_t jnd_pca_storage_bytes(const jnd_pca_encoding *e, int c, int w, int h) {
  size_t bits = 0;
  for (int k = 0; k < e->components; k++)
    bits += comp_pixels(w, h, e->scale[k]) * (size_t)(e->bits[k] ? e->bits[k] : 32);
  return (bits + 7) / 8 + (size_t)c * (e->components + 1) * sizeof(float);
}

void jnd_pca_encoded_free(jnd_pca_encoded *enc) {
  if (!enc) return;
  for (int k = 0; k < MAXC; k++) jnd_image_free(&enc->comp[k]);
  memset(enc, 0, sizeof *enc);
}

/* The K component planes u_k = Σ_c basis[c][k]·w_c·(x_c − mean_c) at full
 * size, into proj (K planes of w·h, caller's). */
void pca_project(const jnd_texset *set, const jnd_pca *pca, int K, float *proj) {
  int C = set->c;
  size_t np = (size_t)set->w * set->h;
  double m[MAXC * MAXC], off[MAXC];
  for (int k = 0; k < K; k++) {
    off[k] = 0;
    for (int c = 0; c < C; c++) {
      m[k * C + c] = pca->basis[c * C + k] * pca->weight[c];
      off[k] -= m[k * C + c] * pca->mean[c];
    }
  }
  float mf[MAXC * MAXC], of[MAXC];
  for (int i = 0; i < K * C; i++) mf[i] = (float)m[i];
  for (int k = 0; k < K; k++) of[k] = (float)off[k];
  /* row by row, one multiply-add sweep per (component, channel): vectorises */
#pragma omp parallel for schedule(static)
  for (int y = 0; y < set->h; y++) {
    size_t base = (size_t)y * set->w;
    for (int k = 0; k < K; k++) {
      float *out = proj + (size_t)k * np + base;
      for (int x = 0; x < set->w; x++) out[x] = of[k];
      for (int c = 0; c < C; c++) {
        const float *in = set->data + (size_t)c * np + base;
        float mk = mf[k * C + c];
        #pragma omp simd
        for (int x = 0; x < set->w; x++) out[x] += mk * in[x];
      }
    }
  }
}

/* A component plane → its stored image: box down to scale s, range to 0..1,
 * quantised to bits (0: not quantised). */
jnd_status pca_store_component(const float *u, int w, int h, int s, int bits, jnd_image *img, double *scale,
                                  double *offset) {
  int cw = pca_coarse_side(w, s), ch = pca_coarse_side(h, s);
  jnd_status st = jnd_image_alloc(img, cw, ch, 1);
  if (st != JND_OK) return st;
  if (s == 0)
    memcpy(img->data, u, (size_t)w * h * sizeof *u);
  else
    jnd_box_down_plane(u, w, h, s, img->data);
  ptrdiff_t n = (ptrdiff_t)cw * ch;
  float lo = img->data[0], hi = img->data[0];
  float *d = img->data;
#pragma omp parallel for reduction(min : lo) reduction(max : hi) schedule(static)
  for (ptrdiff_t i = 0; i < n; i++) {
    lo = d[i] < lo ? d[i] : lo;
    hi = d[i] > hi ? d[i] : hi;
  }
  *offset = lo;
  *scale = hi > lo ? (double)hi - lo : 0;
  double inv = *scale > 0 ? 1.0 / *scale : 0, levels = bits ? (double)((1u << bits) - 1) : 0;
  double inv_levels = levels > 0 ? 1.0 / levels : 0;
#pragma omp parallel for schedule(static)
  for (ptrdiff_t i = 0; i < n; i++) {
    double q = ((double)d[i] - lo) * inv;
    if (levels > 0) q = floor(q * levels + 0.5) * inv_levels;
    d[i] = (float)q;
  }
  return JND_OK;
}

static void fill_recon(const jnd_pca *pca, jnd_pca_encoded *enc) {
  int C = pca->c, K = enc->enc.components;
  for (int c = 0; c < C; c++) {
    double *row = enc->recon + (size_t)c * (K + 1);
    double cst = pca->mean[c];
    for (int k = 0; k < K; k++) {
      double t = pca->basis[c * C + k] / pca->weight[c];
      row[k] = t * enc->scale[k];
      cst += t * enc->offset[k];
    }
    row[K] = cst;
  }
}

static jnd_status check_encoding(const jnd_pca *pca, const jnd_pca_encoding *e) {
  if (e->components < 0 || e->components > pca->c)
    return jnd_fail(JND_ERR_ARG, "pca: %d components asked of %d", e->components, pca->c);
  for (int k = 0; k < e->components; k++) {
    if (e->scale[k] < 0 || e->scale[k] > JND_PCA_MAX_SCALE)
      return jnd_fail(JND_ERR_ARG, "pca: component %d scale 1/2^%d is outside 0..%d", k, e->scale[k], JND_PCA_MAX_SCALE);
    if (e->bits[k] != 0 && e->bits[k] != 8 && e->bits[k] != 16)
      return jnd_fail(JND_ERR_ARG, "pca: component %d: %d bits (8, 16, or 0 for float)", k, e->bits[k]);
  }
  return JND_OK;
}

jnd_status jnd_texset_psnr(const jnd_texset *set, const jnd_image *recon, double *psnr_db, double *mse) {
  if (recon->w != set->w || recon->h != set->h || recon->c != set->c)
    return jnd_fail(JND_ERR_ARG, "psnr: reconstruction %d × %d × %d for a %d × %d × %d set", recon->w, recon->h,
                    recon->c, set->w, set->h, set->c);
  size_t np = (size_t)set->w * set->h;
  enum { CH = 1 << 16 };
  size_t nch = (np + CH - 1) / CH;
  double *part = jnd_calloc(nch * (size_t)set->c, sizeof *part);
  if (!part) return JND_ERR_NOMEM;
#pragma omp parallel for schedule(static)
  for (size_t k = 0; k < nch; k++) {
    size_t a = k * CH, b = a + CH < np ? a + CH : np;
    for (int c = 0; c < set->c; c++) {
      const float *x = set->data + (size_t)c * np, *r = recon->data + (size_t)c * np;
      double acc = 0;
      for (size_t i = a; i < b; i++) acc += ((double)x[i] - r[i]) * ((double)x[i] - r[i]);
      part[k * set->c + c] = acc;
    }
  }
  for (int c = 0; c < set->c; c++) {
    double acc = 0;
    for (size_t k = 0; k < nch; k++) acc += part[k * set->c + c];
    double m = acc / (double)np;
    if (mse) mse[c] = m;
    psnr_db[c] = m > 0 ? 10.0 * log10(1.0 / m) : INFINITY;
  }
  free(part);
  return JND_OK;
}

jnd_status jnd_pca_reconstruct(const jnd_pca_encoded *enc, const jnd_image *comp, jnd_image *out) {
  int C = enc->c, K = enc->enc.components, w = enc->w, h = enc->h;
  if (!comp) comp = enc->comp;
  size_t np = (size_t)w * h;
  jnd_status s = jnd_image_alloc(out, w, h, C);
  if (s != JND_OK) return s;
  float *up = NULL;
  if (K > 0 && !(up = jnd_alloc(np * (size_t)K, sizeof *up))) {
    jnd_image_free(out);
    return JND_ERR_NOMEM;
  }
  for (int k = 0; k < K && s == JND_OK; k++) {
    int sc = enc->enc.scale[k];
    if (comp[k].w != pca_coarse_side(w, sc) || comp[k].h != pca_coarse_side(h, sc) || comp[k].c < 1)
      s = jnd_fail(JND_ERR_ARG, "reconstruct: component %d is %d × %d, wanted %d × %d", k, comp[k].w, comp[k].h,
                   pca_coarse_side(w, sc), pca_coarse_side(h, sc));
    else
      s = pca_upsample(comp[k].data, w, h, sc, up + (size_t)k * np);
  }
  if (s != JND_OK) {
    free(up);
    jnd_image_free(out);
    return s;
  }
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++) {
    size_t base = (size_t)y * w;
    for (int c = 0; c < C; c++) {
      const double *row = enc->recon + (size_t)c * (K + 1);
      float *o = out->data + (size_t)c * np + base, cst = (float)row[K];
      for (int x = 0; x < w; x++) o[x] = cst;
      for (int k = 0; k < K; k++) {
        const float *q = up + (size_t)k * np + base;
        float r = (float)row[k];
        #pragma omp simd
        for (int x = 0; x < w; x++) o[x] += r * q[x];
      }
    }
  }
  free(up);
  return JND_OK;
}

/* encode from precomputed projections (at least e->components planes) */
jnd_status pca_encode_from(const jnd_texset *set, const jnd_pca *pca, const float *proj,
                              const jnd_pca_encoding *e, jnd_pca_encoded *out) {
  memset(out, 0, sizeof *out);
  jnd_status s = check_encoding(pca, e);
  if (s != JND_OK) return s;
  out->enc = *e;
  out->c = set->c;
  out->w = set->w;
  out->h = set->h;
  size_t np = (size_t)set->w * set->h;
  for (int k = 0; k < e->components && s == JND_OK; k++)
    s = pca_store_component(proj + (size_t)k * np, set->w, set->h, e->scale[k], e->bits[k], &out->comp[k],
                        &out->scale[k], &out->offset[k]);
  if (s != JND_OK) {
    jnd_pca_encoded_free(out);
    return s;
  }
  fill_recon(pca, out);
  out->storage_bytes = jnd_pca_storage_bytes(e, set->c, set->w, set->h);
  jnd_image rec = {0};
  s = jnd_pca_reconstruct(out, NULL, &rec);
  if (s == JND_OK) s = jnd_texset_psnr(set, &rec, out->psnr_db, out->mse);
  jnd_image_free(&rec);
  if (s != JND_OK) jnd_pca_encoded_free(out);
  return s;
}

jnd_status jnd_pca_encode(const jnd_texset *set, const jnd_pca *pca, const jnd_pca_encoding *e,
                          jnd_pca_encoded *out) {
  memset(out, 0, sizeof *out);
  if (!set || !set->data || !pca || pca->c != set->c) return jnd_fail(JND_ERR_ARG, "pca: set and analysis differ");
  jnd_status s = check_encoding(pca, e);
  if (s != JND_OK) return s;
  size_t np = (size_t)set->w * set->h;
  int K = e->components;
  float *proj = jnd_alloc(np * (size_t)(K > 0 ? K : 1), sizeof *proj);
  if (!proj) return JND_ERR_NOMEM;
  pca_project(set, pca, K, proj);
  s = pca_encode_from(set, pca, proj, e, out);
  free(proj);
  return s;
}
