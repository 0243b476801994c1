/* pca's automatic choice by PSNR (docs/pca.md): the cheapest encoding —
 * components, each at its own scale and bit depth — whose reconstruction
 * meets a PSNR floor on every channel. */
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
/* Automatic choice by PSNR                                                 */
/* ------------------------------------------------------------------------ */

/* Options for one component, most expensive first: (scale, bits), then
 * dropped. Costs in bits per full-size pixel strictly decrease. */
typedef struct {
  int scale, bits;
  double cost;
} option;

typedef struct pca_search {
  int C, K, nopt;
  option opt[2 * (JND_PCA_MAX_SCALE + 1) + 1];
  double dist[MAXC][2 * (JND_PCA_MAX_SCALE + 1) + 1];  /* E[(û_k − u_k)²] */
  double t2[MAXC][MAXC];       /* basis[c][k]² / weight_c² */
  double budget[MAXC];         /* per-channel MSE allowed */
  double fixed_bytes;          /* per channel per component of the matrix */
  double px;                   /* pixels */
  int cur[MAXC], best[MAXC];
  double best_cost;
} search;

static void search_rec(search *S, int k, int min_opt, double cost, const double *err) {
  if (cost >= S->best_cost) return;
  if (k == S->C) {
    S->best_cost = cost;
    memcpy(S->best, S->cur, sizeof S->cur);
    return;
  }
  for (int o = min_opt; o < S->nopt; o++) {
    int drop = o == S->nopt - 1;
    double e2[MAXC];
    int ok = 1;
    for (int c = 0; c < S->C && ok; c++) {
      e2[c] = err[c] + S->t2[c][k] * S->dist[k][o];
      ok = e2[c] <= S->budget[c];
    }
    if (!ok) continue;   /* a cheaper option only adds error */
    S->cur[k] = o;
    if (drop) {
      /* the rest are dropped too: check them all */
      for (int j = k + 1; j < S->C && ok; j++)
        for (int c = 0; c < S->C && ok; c++) {
          e2[c] += S->t2[c][j] * S->dist[j][o];
          ok = e2[c] <= S->budget[c];
        }
      if (ok && cost < S->best_cost) {
        for (int j = k + 1; j < S->C; j++) S->cur[j] = o;
        S->best_cost = cost;
        memcpy(S->best, S->cur, sizeof S->cur);
      }
      continue;
    }
    search_rec(S, k + 1, o, cost + S->opt[o].cost * S->px / 8 + S->fixed_bytes, e2);
  }
}

/* distortion of each component under each option, measured at full size */
static jnd_status measure_options(const jnd_texset *set, const jnd_pca *pca, const float *proj, search *S) {
  int w = set->w, h = set->h;
  size_t np = (size_t)w * h;
  float *up = jnd_alloc(np, sizeof *up);
  double *rows = jnd_alloc((size_t)h, sizeof *rows);
  if (!up || !rows) {
    free(up);
    free(rows);
    return JND_ERR_NOMEM;
  }
  jnd_status s = JND_OK;
  for (int k = 0; k < S->C && s == JND_OK; k++) {
    const float *u = proj + (size_t)k * np;
    for (int o = 0; o < S->nopt && s == JND_OK; o++) {
      if (o == S->nopt - 1) {
        S->dist[k][o] = pca->energy[k];
        continue;
      }
      jnd_image img = {0};
      double scale, offset;
      s = pca_store_component(u, w, h, S->opt[o].scale, S->opt[o].bits, &img, &scale, &offset);
      if (s == JND_OK) s = pca_upsample(img.data, w, h, S->opt[o].scale, up);
      if (s == JND_OK) {
        /* per-row sums added in row order: the same on any thread count */
#pragma omp parallel for schedule(static)
        for (int y = 0; y < h; y++) {
          double r = 0;
          for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            double d = offset + scale * up[i] - u[i];
            r += d * d;
          }
          rows[y] = r;
        }
        double acc = 0;
        for (int y = 0; y < h; y++) acc += rows[y];
        S->dist[k][o] = acc / (double)np;
      }
      jnd_image_free(&img);
    }
  }
  free(up);
  free(rows);
  return s;
}

/* The PSNR search set up once (pca_stages.h). */
void pca_chooser_free(psnr_chooser *ch) {
  free(ch->S);
  free(ch->proj);
  ch->S = NULL;
  ch->proj = NULL;
}

jnd_status pca_chooser_init(const jnd_texset *set, const jnd_pca *pca, int max_scale, psnr_chooser *ch) {
  memset(ch, 0, sizeof *ch);
  if (!set || !pca || pca->c != set->c) return jnd_fail(JND_ERR_ARG, "pca: set and analysis differ");
  max_scale = jnd_clampi(max_scale, 0, JND_PCA_MAX_SCALE);
  int C = set->c;
  size_t np = (size_t)set->w * set->h;
  ch->proj = jnd_alloc(np * (size_t)C, sizeof *ch->proj);
  ch->S = jnd_calloc(1, sizeof *ch->S);
  if (!ch->proj || !ch->S) {
    pca_chooser_free(ch);
    return JND_ERR_NOMEM;
  }
  pca_project(set, pca, C, ch->proj);
  search *S = ch->S;
  S->C = C;
  for (int sc = 0; sc <= max_scale; sc++)
    for (int b = 16; b >= 8; b -= 8) S->opt[S->nopt++] = (option){sc, b, (double)b / (1 << (2 * sc))};
  S->opt[S->nopt++] = (option){0, 0, 0};
  /* costs must strictly decrease for the monotone enumeration */
  for (int o = 1; o < S->nopt; o++)
    if (!(S->opt[o].cost < S->opt[o - 1].cost)) {
      pca_chooser_free(ch);
      return jnd_fail(JND_ERR_INTERNAL, "pca: options not ordered by cost");
    }
  S->px = (double)np;
  S->fixed_bytes = (double)C * sizeof(float);
  for (int c = 0; c < C; c++)
    for (int k = 0; k < C; k++) {
      double t = pca->basis[c * C + k] / pca->weight[c];
      S->t2[c][k] = t * t;
    }
  jnd_status s = measure_options(set, pca, ch->proj, S);
  if (s != JND_OK) pca_chooser_free(ch);
  return s;
}

jnd_status pca_chooser_run(psnr_chooser *ch, const jnd_texset *set, const jnd_pca *pca, double min_psnr_db,
                              jnd_pca_encoding *out) {
  memset(out, 0, sizeof *out);
  search *S = ch->S;
  int C = set->c;
  jnd_status s = JND_OK;
  double target = pow(10.0, -min_psnr_db / 10.0);
  for (int c = 0; c < C; c++) S->budget[c] = target;
  int found = 0;
  /* The additive model ignores the small correlations between the errors
   * of different components; check for real and tighten where it missed. */
  for (int round = 0; round < 8 && s == JND_OK && !found; round++) {
    double zero[MAXC] = {0};
    S->best_cost = INFINITY;
    search_rec(S, 0, 0, (double)C * sizeof(float), zero);
    if (!isfinite(S->best_cost)) break;
    jnd_pca_encoding e = {0};
    for (int k = 0; k < C; k++) {
      if (S->best[k] == S->nopt - 1) break;
      e.scale[k] = S->opt[S->best[k]].scale;
      e.bits[k] = S->opt[S->best[k]].bits;
      e.components = k + 1;
    }
    jnd_pca_encoded enc;
    s = pca_encode_from(set, pca, ch->proj, &e, &enc);
    if (s != JND_OK) break;
    found = 1;
    for (int c = 0; c < C; c++)
      if (enc.mse[c] > target) {
        /* scale the model's prediction for this channel by how far it was
         * off, so that this candidate (and its like) no longer passes */
        double model = 0;
        for (int k = 0; k < C; k++) model += S->t2[c][k] * S->dist[k][S->best[k]];
        double b = 0.99 * model * target / enc.mse[c];
        S->budget[c] = b < S->budget[c] ? b : S->budget[c];
        found = 0;
      }
    jnd_pca_encoded_free(&enc);
    if (found) *out = e;
  }
  if (s == JND_OK && !found)
    s = jnd_fail(JND_ERR_ARG, "pca: no encoding reaches %g dB in every channel (try a lower --psnr)", min_psnr_db);
  return s;
}

jnd_status jnd_pca_choose_psnr(const jnd_texset *set, const jnd_pca *pca, double min_psnr_db, int max_scale,
                               jnd_pca_encoding *out) {
  memset(out, 0, sizeof *out);
  if (!set || !pca || pca->c != set->c) return jnd_fail(JND_ERR_ARG, "pca: set and analysis differ");
  if (!(min_psnr_db > 0 && min_psnr_db < 200)) return jnd_fail(JND_ERR_ARG, "pca: PSNR target %g dB", min_psnr_db);
  psnr_chooser ch;
  jnd_status s = pca_chooser_init(set, pca, max_scale, &ch);
  if (s == JND_OK) s = pca_chooser_run(&ch, set, pca, min_psnr_db, out);
  pca_chooser_free(&ch);
  return s;
}
