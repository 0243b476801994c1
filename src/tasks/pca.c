/* Texture sets in fewer channels (Wronski, 001): a material's maps packed as
 * a (w·h) × C matrix, mean-centred and weighted, decorrelated by PCA; the
 * first K components kept, each at its own resolution and bit depth; the
 * reconstruction a (C × (K+1)) homogeneous matrix; quality as PSNR per
 * channel, with and without GPU block compression; an automatic choice of
 * the smallest encoding meeting a PSNR floor; and rendered visibility: the
 * material re-rendered with the reconstructed maps from sampled views,
 * compared with the original by the vision model, P pooled per view, and
 * the cheapest encoding whose views pass (docs/pca.md).
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

#define MAXC JND_PCA_MAX_CHANNELS

/* ------------------------------------------------------------------------ */
/* Resampling: the scene layer's (jnd_resample_plane, jnd_box_down_plane)    */
/* ------------------------------------------------------------------------ */

static int coarse_side(int n, int s) { return (n + (1 << s) - 1) >> s; }

/* a plane made by jnd_box_down_plane(src, w, h, s, ...) back to w × h with
 * Lanczos-3, the coarse samples sitting at the centres of their boxes */
static jnd_status upsample(const float *coarse, int w, int h, int s, float *dst) {
  if (s == 0) {
    memcpy(dst, coarse, (size_t)w * h * sizeof *dst);
    return JND_OK;
  }
  double r = 1.0 / (1 << s);
  return jnd_resample_plane(coarse, coarse_side(w, s), coarse_side(h, s), dst, w, h, r, r, 0, 0);
}

/* ------------------------------------------------------------------------ */
/* Texture sets                                                             */
/* ------------------------------------------------------------------------ */

static const char letters[] = "rgba";

void jnd_texset_free(jnd_texset *set) {
  if (!set) return;
  free(set->data);
  memset(set, 0, sizeof *set);
}

static int plane_constant(const float *p, size_t n) {
  for (size_t i = 1; i < n; i++)
    if (p[i] != p[0]) return 0;
  return 1;
}

static int planes_equal(const float *a, const float *b, size_t n) { return memcmp(a, b, n * sizeof *a) == 0; }

/* "normal=rg,metalRoughness=gb" → picks[map] = letters string; -1 for unknown map */
static jnd_status parse_picks(const char *spec, const char *const *names, int n, char picks[][8]) {
  for (int i = 0; i < n; i++) picks[i][0] = 0;
  if (!spec || !*spec) return JND_OK;
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", spec);
  char *save = NULL;
  for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    char *eq = strchr(tok, '=');
    if (!eq) return jnd_fail(JND_ERR_ARG, "--channels: '%s' is not MAP=LETTERS (e.g. normal=rg)", tok);
    *eq = 0;
    int m = -1;
    for (int i = 0; i < n; i++)
      if (strcmp(names[i], tok) == 0) m = i;
    if (m < 0) return jnd_fail(JND_ERR_ARG, "--channels: no map named '%s'", tok);
    const char *l = eq + 1;
    size_t len = strlen(l);
    if (len == 0 || len > 4) return jnd_fail(JND_ERR_ARG, "--channels: '%s' needs 1 to 4 of r, g, b, a", tok);
    for (size_t k = 0; k < len; k++)
      if (!strchr(letters, tolower((unsigned char)l[k])))
        return jnd_fail(JND_ERR_ARG, "--channels: '%c' is not one of r, g, b, a", l[k]);
    for (size_t k = 0; k < len; k++) picks[m][k] = (char)tolower((unsigned char)l[k]);
    picks[m][len] = 0;
  }
  return JND_OK;
}

/* labels name the inputs in errors (paths for files) */
static jnd_status texset_build(const jnd_image *maps, const char *const *names, const char *const *labels, int n,
                               const char *channels, jnd_texset *out) {
  memset(out, 0, sizeof *out);
  if (n <= 0) return jnd_fail(JND_ERR_ARG, "a texture set needs at least one map");
  if (n > JND_PCA_MAX_MAPS) return jnd_fail(JND_ERR_LIMIT, "%d maps is over the limit of %d", n, JND_PCA_MAX_MAPS);
  int W = 0, H = 0;
  for (int i = 0; i < n; i++) {
    if (!maps[i].data || maps[i].c < 1 || maps[i].c > 4)
      return jnd_fail(JND_ERR_FORMAT, "%s: needs 1 to 4 channels (has %d)", labels[i], maps[i].c);
    if ((size_t)maps[i].w * maps[i].h > (size_t)W * H) {
      W = maps[i].w;
      H = maps[i].h;
    }
  }
  for (int i = 0; i < n; i++)
    if ((long long)maps[i].w * H != (long long)maps[i].h * W)
      return jnd_fail(JND_ERR_ARG, "%s: %d × %d does not have the shape of the set's largest map (%d × %d)",
                      labels[i], maps[i].w, maps[i].h, W, H);
  char picks[JND_PCA_MAX_MAPS][8];
  jnd_status s = parse_picks(channels, names, n, picks);
  if (s != JND_OK) return s;
  size_t np = (size_t)W * H;
  /* choose channels */
  int total = 0;
  for (int i = 0; i < n; i++) {
    jnd_texset_map *m = &out->maps[i];
    snprintf(m->name, sizeof m->name, "%s", names[i]);
    m->file_w = maps[i].w;
    m->file_h = maps[i].h;
    m->file_channels = maps[i].c;
    m->resampled = maps[i].w != W || maps[i].h != H;
    m->first = total;
    size_t fp = (size_t)maps[i].w * maps[i].h;
    int dup_of[4] = {-1, -1, -1, -1};   /* index into m->src */
    if (picks[i][0]) {
      for (int k = 0; picks[i][k]; k++) {
        int ch = (int)(strchr(letters, picks[i][k]) - letters);
        if (ch >= maps[i].c)
          return jnd_fail(JND_ERR_ARG, "%s: --channels asks for '%c' of a %d-channel map", labels[i], picks[i][k],
                          maps[i].c);
        m->src[m->count++] = ch;
      }
    } else {
      for (int ch = 0; ch < maps[i].c; ch++) {
        const float *p = jnd_image_plane(&maps[i], ch);
        if (plane_constant(p, fp)) {
          m->constants++;
          continue;
        }
        int dup = -1;
        for (int k = 0; k < m->count && dup < 0; k++)
          if (planes_equal(p, jnd_image_plane(&maps[i], m->src[k]), fp)) dup = k;
        if (dup >= 0) {
          m->duplicates++;
          dup_of[ch] = dup;
          continue;
        }
        m->src[m->count++] = ch;
      }
      if (m->count == 0) {   /* a constant map still needs one channel */
        m->src[m->count++] = 0;
        m->constants--;
      }
    }
    for (int ch = 0; ch < 4; ch++) {
      m->from[ch] = -1;
      m->constant[ch] = 0;
      if (ch >= maps[i].c) continue;
      for (int k = 0; k < m->count; k++)
        if (m->src[k] == ch) m->from[ch] = total + k;
      if (dup_of[ch] >= 0) m->from[ch] = total + dup_of[ch];
      if (m->from[ch] < 0 && !picks[i][0]) m->constant[ch] = jnd_image_plane(&maps[i], ch)[0];
    }
    total += m->count;
  }
  if (total > MAXC) return jnd_fail(JND_ERR_LIMIT, "%d channels is over the limit of %d (pick with --channels)", total, MAXC);
  s = jnd_check_size(W, H, total, labels[0]);
  if (s != JND_OK) return s;
  out->data = jnd_alloc(np * (size_t)total, sizeof *out->data);
  if (!out->data) return JND_ERR_NOMEM;
  out->w = W;
  out->h = H;
  out->c = total;
  out->nmaps = n;
  for (int i = 0; i < n; i++) {
    jnd_texset_map *m = &out->maps[i];
    /* a grey file (with or without alpha), or grey stored as RGB(A) */
    /* a grey file (with or without alpha), grey stored as RGB(A), or a
     * constant map (one channel kept for it): named after the map */
    int grey = m->count == 1 && m->src[0] == 0 && !picks[i][0] &&
               (m->file_channels <= 2 || m->duplicates >= 1 || m->constants == m->file_channels - 1);
    for (int k = 0; k < m->count; k++) {
      int c = m->first + k;
      out->map_of[c] = i;
      if (grey)
        snprintf(out->names[c], sizeof out->names[c], "%s", m->name);
      else
        snprintf(out->names[c], sizeof out->names[c], "%s.%c", m->name, letters[m->src[k]]);
      const float *p = jnd_image_plane(&maps[i], m->src[k]);
      float *d = out->data + (size_t)c * np;
      if (m->resampled) {
        s = jnd_resample_plane(p, maps[i].w, maps[i].h, d, W, H, (double)maps[i].w / W, (double)maps[i].h / H, 0, 0);
        if (s != JND_OK) {
          jnd_texset_free(out);
          return s;
        }
      } else {
        memcpy(d, p, np * sizeof *d);
      }
    }
  }
  return JND_OK;
}

jnd_status jnd_texset_from_images(const jnd_image *maps, const char *const *names, int n, const char *channels,
                                  jnd_texset *out) {
  return texset_build(maps, names, names, n, channels, out);
}

/* file stem: after the last '/', before the last '.' */
static void stem(const char *path, char *out, size_t n) {
  const char *b = strrchr(path, '/');
  b = b ? b + 1 : path;
  snprintf(out, n, "%s", b);
  char *dot = strrchr(out, '.');
  if (dot && dot != out) *dot = 0;
}

jnd_status jnd_texset_read(const char *const *paths, int n, const char *channels, jnd_texset *out) {
  memset(out, 0, sizeof *out);
  if (n <= 0) return jnd_fail(JND_ERR_ARG, "a texture set needs at least one map");
  if (n > JND_PCA_MAX_MAPS) return jnd_fail(JND_ERR_LIMIT, "%d maps is over the limit of %d", n, JND_PCA_MAX_MAPS);
  char stems[JND_PCA_MAX_MAPS][64];
  const char *names[JND_PCA_MAX_MAPS];
  for (int i = 0; i < n; i++) stem(paths[i], stems[i], sizeof stems[i]);
  /* drop the prefix every stem shares, up to a separator ("Default_") */
  size_t pre = 0;
  if (n > 1) {
    size_t common = strlen(stems[0]);
    for (int i = 1; i < n; i++) {
      size_t k = 0;
      while (k < common && stems[i][k] == stems[0][k]) k++;
      common = k;
    }
    for (size_t k = 0; k < common; k++)
      if (strchr("_-. ", stems[0][k])) pre = k + 1;
    for (int i = 0; i < n; i++)
      if (!stems[i][pre]) pre = 0;
  }
  for (int i = 0; i < n; i++) {
    names[i] = stems[i] + pre;
    for (int j = 0; j < i; j++)
      if (strcmp(names[i], names[j]) == 0)
        return jnd_fail(JND_ERR_ARG, "%s: a second map named '%s'", paths[i], names[i]);
  }
  jnd_image maps[JND_PCA_MAX_MAPS];
  memset(maps, 0, sizeof maps);
  jnd_status s = JND_OK;
  for (int i = 0; i < n && s == JND_OK; i++) s = jnd_image_read(paths[i], &maps[i], NULL);
  if (s == JND_OK) s = texset_build(maps, names, paths, n, channels, out);
  for (int i = 0; i < n; i++) jnd_image_free(&maps[i]);
  return s;
}

jnd_status jnd_texset_map_image(const jnd_texset *set, const jnd_image *channels, int map, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (map < 0 || map >= set->nmaps) return jnd_fail(JND_ERR_ARG, "map %d of a set of %d", map, set->nmaps);
  if (channels->w != set->w || channels->h != set->h || channels->c != set->c)
    return jnd_fail(JND_ERR_ARG, "map image: channels are %d × %d × %d, the set %d × %d × %d", channels->w,
                    channels->h, channels->c, set->w, set->h, set->c);
  const jnd_texset_map *m = &set->maps[map];
  jnd_status s = jnd_image_alloc(out, set->w, set->h, m->file_channels);
  if (s != JND_OK) return s;
  size_t np = (size_t)set->w * set->h;
  for (int ch = 0; ch < m->file_channels; ch++) {
    float *d = jnd_image_plane(out, ch);
    if (m->from[ch] >= 0)
      memcpy(d, jnd_image_plane(channels, m->from[ch]), np * sizeof *d);
    else
      for (size_t i = 0; i < np; i++) d[i] = m->constant[ch];
  }
  return JND_OK;
}

jnd_status jnd_texset_parse_weights(const jnd_texset *set, const char *spec, double *weights) {
  for (int c = 0; c < set->c; c++) weights[c] = 1.0;
  if (!spec || !*spec) return JND_OK;
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", spec);
  char *save = NULL;
  for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    char *eq = strchr(tok, '=');
    if (!eq) return jnd_fail(JND_ERR_ARG, "--weight: '%s' is not NAME=WEIGHT (e.g. albedo=2)", tok);
    *eq = 0;
    char *end;
    double w = strtod(eq + 1, &end);
    if (end == eq + 1 || *end || !(w > 0) || !isfinite(w))
      return jnd_fail(JND_ERR_ARG, "--weight: %s: '%s' is not a positive number", tok, eq + 1);
    int hit = 0;
    for (int c = 0; c < set->c; c++)
      if (strcmp(set->names[c], tok) == 0 || strcmp(set->maps[set->map_of[c]].name, tok) == 0) {
        weights[c] = w;
        hit = 1;
      }
    if (!hit) return jnd_fail(JND_ERR_ARG, "--weight: no map or channel named '%s'", tok);
  }
  return JND_OK;
}

static const float *const *set_planes(const jnd_texset *set, const float **planes) {
  for (int c = 0; c < set->c; c++) planes[c] = set->data + (size_t)c * set->w * set->h;
  return planes;
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
  set_planes(set, planes);
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

static size_t comp_pixels(int w, int h, int s) { return (size_t)coarse_side(w, s) * coarse_side(h, s); }

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
static void project(const jnd_texset *set, const jnd_pca *pca, int K, float *proj) {
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
static jnd_status store_component(const float *u, int w, int h, int s, int bits, jnd_image *img, double *scale,
                                  double *offset) {
  int cw = coarse_side(w, s), ch = coarse_side(h, s);
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
    if (comp[k].w != coarse_side(w, sc) || comp[k].h != coarse_side(h, sc) || comp[k].c < 1)
      s = jnd_fail(JND_ERR_ARG, "reconstruct: component %d is %d × %d, wanted %d × %d", k, comp[k].w, comp[k].h,
                   coarse_side(w, sc), coarse_side(h, sc));
    else
      s = upsample(comp[k].data, w, h, sc, up + (size_t)k * np);
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
static jnd_status encode_from(const jnd_texset *set, const jnd_pca *pca, const float *proj,
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
    s = store_component(proj + (size_t)k * np, set->w, set->h, e->scale[k], e->bits[k], &out->comp[k],
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
  project(set, pca, K, proj);
  s = encode_from(set, pca, proj, e, out);
  free(proj);
  return s;
}

/* ------------------------------------------------------------------------ */
/* Automatic choice by PSNR                                                 */
/* ------------------------------------------------------------------------ */

/* Options for one component, most expensive first: (scale, bits), then
 * dropped. Costs in bits per full-size pixel strictly decrease. */
typedef struct {
  int scale, bits;
  double cost;
} option;

typedef struct {
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
      s = store_component(u, w, h, S->opt[o].scale, S->opt[o].bits, &img, &scale, &offset);
      if (s == JND_OK) s = upsample(img.data, w, h, S->opt[o].scale, up);
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

/* The PSNR search set up once (projections, per-option distortions) for
 * any number of targets: the rendered search asks for many. */
typedef struct {
  search *S;
  float *proj;   /* all C component planes at full size */
} psnr_chooser;

static void chooser_free(psnr_chooser *ch) {
  free(ch->S);
  free(ch->proj);
  ch->S = NULL;
  ch->proj = NULL;
}

static jnd_status chooser_init(const jnd_texset *set, const jnd_pca *pca, int max_scale, psnr_chooser *ch) {
  memset(ch, 0, sizeof *ch);
  if (!set || !pca || pca->c != set->c) return jnd_fail(JND_ERR_ARG, "pca: set and analysis differ");
  max_scale = jnd_clampi(max_scale, 0, JND_PCA_MAX_SCALE);
  int C = set->c;
  size_t np = (size_t)set->w * set->h;
  ch->proj = jnd_alloc(np * (size_t)C, sizeof *ch->proj);
  ch->S = jnd_calloc(1, sizeof *ch->S);
  if (!ch->proj || !ch->S) {
    chooser_free(ch);
    return JND_ERR_NOMEM;
  }
  project(set, pca, C, ch->proj);
  search *S = ch->S;
  S->C = C;
  for (int sc = 0; sc <= max_scale; sc++)
    for (int b = 16; b >= 8; b -= 8) S->opt[S->nopt++] = (option){sc, b, (double)b / (1 << (2 * sc))};
  S->opt[S->nopt++] = (option){0, 0, 0};
  /* costs must strictly decrease for the monotone enumeration */
  for (int o = 1; o < S->nopt; o++)
    if (!(S->opt[o].cost < S->opt[o - 1].cost)) {
      chooser_free(ch);
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
  if (s != JND_OK) chooser_free(ch);
  return s;
}

static jnd_status chooser_run(psnr_chooser *ch, const jnd_texset *set, const jnd_pca *pca, double min_psnr_db,
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
    s = encode_from(set, pca, ch->proj, &e, &enc);
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
  jnd_status s = chooser_init(set, pca, max_scale, &ch);
  if (s == JND_OK) s = chooser_run(&ch, set, pca, min_psnr_db, out);
  chooser_free(&ch);
  return s;
}

/* ------------------------------------------------------------------------ */
/* Rendered visibility (the renderer's part)                                */
/* ------------------------------------------------------------------------ */

/* The loop of DESIGN.md for a texture set, asked of the judge: the
 * material rendered with its maps rebuilt from a candidate, against the
 * rendering of the set itself (the judge's reference), P per view pooled
 * over the object as every task pools it (judge.c). */
struct jnd_pca_render {
  char path[1024];
  jnd_pca_render_params p;
  jnd_scene *scene;
  jnd_judge *judge;                        /* made when a set is bound: its state is the reference */
  int material;
  const jnd_texset *set;                   /* bound set (the caller's) */
  int nbound;
  int scene_map[JND_PCA_MAX_MAPS];         /* scene map of each set map */
  jnd_map_slot slot[JND_PCA_MAX_MAPS];
};

void jnd_pca_render_defaults(jnd_pca_render_params *p) {
  memset(p, 0, sizeof *p);
  jnd_judge_defaults(&p->judge);
  p->builtin_map_size = 2048;
}

void jnd_pca_render_free(jnd_pca_render *r) {
  if (!r) return;
  jnd_judge_free(r->judge);
  jnd_scene_free(r->scene);
  free(r);
}

const char *jnd_pca_render_description(const jnd_pca_render *r) {
  return r && r->judge ? jnd_judge_renderer(r->judge) : "";
}

static int render_views(const jnd_pca_render_params *p) {
  return p->judge.views.cameras ? p->judge.views.ncameras : p->judge.views.sampling.count;
}

jnd_status jnd_pca_render_open(const char *model_path, const char *material, const jnd_pca_render_params *p,
                               jnd_pca_render **out) {
  *out = NULL;
  if (!model_path || !material) return jnd_fail(JND_ERR_ARG, "rendered visibility needs a model and a material");
  int nv = render_views(p);
  if (nv < 1 || nv > JND_PCA_MAX_VIEWS)
    return jnd_fail(JND_ERR_ARG, "%s: %d views (1 to %d)", model_path, nv, JND_PCA_MAX_VIEWS);
  jnd_pca_render *r = jnd_calloc(1, sizeof *r);
  if (!r) return JND_ERR_NOMEM;
  snprintf(r->path, sizeof r->path, "%s", model_path);
  r->p = *p;
  jnd_status s = jnd_scene_open(model_path, p->builtin_map_size, &r->scene);
  if (s != JND_OK) goto fail;
  r->material = -1;
  int nm = jnd_scene_material_count(r->scene);
  for (int i = 0; i < nm && r->material < 0; i++)
    if (strcmp(jnd_scene_material_name(r->scene, i), material) == 0) r->material = i;
  if (r->material < 0) {
    char list[512] = "";
    for (int i = 0; i < nm; i++) {
      size_t n = strlen(list);
      snprintf(list + n, sizeof list - n, "%s'%s'", i ? ", " : "", jnd_scene_material_name(r->scene, i));
    }
    s = jnd_fail(JND_ERR_ARG, "%s: no material '%s' (it has %s)", model_path, material, nm ? list : "none");
    goto fail;
  }
  *out = r;
  return JND_OK;
fail:
  jnd_pca_render_free(r);
  return s;
}

int jnd_pca_slot_guess(const char *name, jnd_map_slot *slot) {
  char low[128];
  size_t n = 0;
  for (; name[n] && n + 1 < sizeof low; n++) low[n] = (char)tolower((unsigned char)name[n]);
  low[n] = 0;
  for (int i = 0; i < JND_MAP_SLOTS; i++) {
    char sn[32];
    const char *t = jnd_map_slot_name((jnd_map_slot)i);
    size_t k = 0;
    for (; t[k] && k + 1 < sizeof sn; k++) sn[k] = (char)tolower((unsigned char)t[k]);
    sn[k] = 0;
    if (strcmp(low, sn) == 0) {
      *slot = (jnd_map_slot)i;
      return 1;
    }
  }
  /* "ao" as a whole word: the name itself or delimited by _ - . space */
  int ao = 0;
  for (const char *q = strstr(low, "ao"); q && !ao; q = strstr(q + 1, "ao"))
    ao = (q == low || strchr("_-. ", q[-1])) && (!q[2] || strchr("_-. ", q[2]));
  struct {
    const char *word;
    jnd_map_slot slot;
  } const rules[] = {{"emissive", JND_MAP_EMISSIVE},         {"emission", JND_MAP_EMISSIVE},
                     {"normal", JND_MAP_NORMAL},             {"metal", JND_MAP_METALLIC_ROUGHNESS},
                     {"rough", JND_MAP_METALLIC_ROUGHNESS},  {"orm", JND_MAP_METALLIC_ROUGHNESS},
                     {"occlusion", JND_MAP_OCCLUSION},       {"basecolor", JND_MAP_BASE_COLOR},
                     {"base_color", JND_MAP_BASE_COLOR},     {"albedo", JND_MAP_BASE_COLOR},
                     {"diffuse", JND_MAP_BASE_COLOR},        {"color", JND_MAP_BASE_COLOR},
                     {"colour", JND_MAP_BASE_COLOR}};
  for (size_t i = 0; i < sizeof rules / sizeof rules[0]; i++) {
    if (rules[i].slot == JND_MAP_OCCLUSION && ao) break;
    if (strstr(low, rules[i].word)) {
      *slot = rules[i].slot;
      return 1;
    }
  }
  if (ao) {
    *slot = JND_MAP_OCCLUSION;
    return 1;
  }
  return 0;
}

jnd_status jnd_pca_render_material_set(const jnd_pca_render *r, const char *channels, jnd_texset *set,
                                       jnd_map_slot *slots, size_t *orig_bytes) {
  memset(set, 0, sizeof *set);
  if (orig_bytes) *orig_bytes = 0;
  jnd_image maps[JND_MAP_SLOTS];
  memset(maps, 0, sizeof maps);
  const char *names[JND_MAP_SLOTS];
  int image[JND_MAP_SLOTS];   /* the file's image each sampled (jnd_map_info.image) */
  char picks[256] = "";
  int n = 0;
  jnd_status s = JND_OK;
  const char *mname = jnd_scene_material_name(r->scene, r->material);
  for (int slot = 0; slot < JND_MAP_SLOTS && s == JND_OK; slot++) {
    char full[256];
    snprintf(full, sizeof full, "%s/%s", mname, jnd_map_slot_name((jnd_map_slot)slot));
    int idx = jnd_scene_map_find(r->scene, full);
    if (idx < 0) continue;
    jnd_map_info mi;
    if ((s = jnd_scene_map_info(r->scene, idx, &mi)) != JND_OK) break;
    if ((s = jnd_scene_map_get(r->scene, idx, 1, &maps[n])) != JND_OK) break;
    image[n] = mi.image;
    names[n] = jnd_map_slot_name((jnd_map_slot)slot);
    slots[n] = (jnd_map_slot)slot;
    /* the channels the shader reads (docs/render.md "Materials") */
    const char *use = slot == JND_MAP_METALLIC_ROUGHNESS && maps[n].c >= 3 ? "gb"
                      : slot == JND_MAP_OCCLUSION && maps[n].c >= 2       ? "r"
                                                                          : NULL;
    int given = 0;   /* an explicit pick for this slot wins */
    if (channels && *channels) {
      size_t ln = strlen(names[n]);
      for (const char *q = strstr(channels, names[n]); q && !given; q = strstr(q + 1, names[n]))
        given = (q == channels || q[-1] == ',') && q[ln] == '=';
    }
    if (use && !given) {
      size_t k = strlen(picks);
      snprintf(picks + k, sizeof picks - k, "%s%s=%s", k ? "," : "", names[n], use);
    }
    int shared = 0;   /* one image of the file bound to two slots (packed occlusion): counted once */
    for (int j = 0; j < n && !shared; j++) shared = image[j] == image[n];
    if (orig_bytes && !shared) *orig_bytes += (size_t)maps[n].w * maps[n].h * maps[n].c;
    n++;
  }
  if (s == JND_OK && n == 0)
    s = jnd_fail(JND_ERR_ARG, "%s: material '%s' has no texture maps", r->path, mname);
  if (s == JND_OK && channels && *channels) {
    size_t k = strlen(picks);
    snprintf(picks + k, sizeof picks - k, "%s%s", k ? "," : "", channels);
  }
  if (s == JND_OK) s = jnd_texset_from_images(maps, names, n, picks, set);
  for (int i = 0; i < n; i++) jnd_image_free(&maps[i]);
  return s;
}

int pca_render_slot_image(const jnd_pca_render *r, jnd_map_slot slot) {
  char full[256];
  snprintf(full, sizeof full, "%s/%s", jnd_scene_material_name(r->scene, r->material), jnd_map_slot_name(slot));
  int idx = jnd_scene_map_find(r->scene, full);
  jnd_map_info mi;
  if (idx < 0 || jnd_scene_map_info(r->scene, idx, &mi) != JND_OK) return -1;
  return mi.image;
}

/* puts map i of the set, rebuilt from channels, into its slot */
static jnd_status set_map(jnd_pca_render *r, const jnd_image *channels, int i) {
  const jnd_texset_map *m = &r->set->maps[i];
  jnd_image img = {0}, back = {0};
  jnd_status s = jnd_texset_map_image(r->set, channels, i, &img);
  if (s == JND_OK && m->resampled) {
    s = jnd_resample_map(&img, m->file_w, m->file_h, jnd_map_slot_kind(r->slot[i]), 0, &back);
    jnd_image_free(&img);
    img = back;
  }
  if (s == JND_OK) s = jnd_scene_map_set(r->scene, r->scene_map[i], &img);
  jnd_image_free(&img);
  return s;
}

jnd_status jnd_pca_render_bind(jnd_pca_render *r, const jnd_texset *set, const jnd_map_slot *slots) {
  if (!set || !set->data || set->nmaps < 1) return jnd_fail(JND_ERR_ARG, "%s: no texture set to bind", r->path);
  const char *mname = jnd_scene_material_name(r->scene, r->material);
  for (int i = 0; i < r->nbound; i++) jnd_scene_map_restore(r->scene, r->scene_map[i]);
  r->nbound = 0;
  r->set = set;
  for (int i = 0; i < set->nmaps; i++) {
    if ((int)slots[i] < 0 || slots[i] >= JND_MAP_SLOTS)
      return jnd_fail(JND_ERR_ARG, "%s: map '%s' has no slot", r->path, set->maps[i].name);
    for (int j = 0; j < i; j++)
      if (slots[j] == slots[i])
        return jnd_fail(JND_ERR_ARG, "%s: maps '%s' and '%s' both go to slot %s", r->path, set->maps[j].name,
                        set->maps[i].name, jnd_map_slot_name(slots[i]));
    char full[256];
    snprintf(full, sizeof full, "%s/%s", mname, jnd_map_slot_name(slots[i]));
    r->scene_map[i] = jnd_scene_map_find(r->scene, full);
    r->slot[i] = slots[i];
    if (r->scene_map[i] < 0)
      return jnd_fail(JND_ERR_ARG, "%s: material '%s' has no %s texture to replace with '%s'", r->path, mname,
                      jnd_map_slot_name(slots[i]), set->maps[i].name);
  }
  r->nbound = set->nmaps;
  jnd_image own = {set->w, set->h, set->c, set->data};
  jnd_status s = JND_OK;
  for (int i = 0; i < r->nbound && s == JND_OK; i++) s = set_map(r, &own, i);
  /* the set itself in its slots is the reference */
  if (s == JND_OK) s = r->judge ? jnd_judge_set_reference(r->judge) : jnd_judge_create(r->scene, &r->p.judge, &r->judge);
  return s;
}

jnd_status jnd_pca_render_measure(jnd_pca_render *r, const jnd_image *channels, jnd_pca_visibility *out) {
  memset(out, 0, sizeof *out);
  if (!r->set || !r->nbound || !r->judge) return jnd_fail(JND_ERR_ARG, "%s: no texture set bound", r->path);
  jnd_status s = JND_OK;
  for (int i = 0; i < r->nbound && s == JND_OK; i++) s = set_map(r, channels, i);
  int n = jnd_judge_view_count(r->judge);
  jnd_judgement j;
  if (s == JND_OK) s = jnd_judge_eval(r->judge, 0, n, 0, out->p, &j);
  if (s != JND_OK) return s;
  out->views = n;
  out->allowed = j.criterion.allowed;
  out->above = j.criterion.above;
  out->p_criterion = j.criterion.statistic;
  out->pass = j.criterion.pass;
  return JND_OK;
}

/* encodes e, reconstructs and measures */
static jnd_status measure_encoding(jnd_pca_render *r, const jnd_texset *set, const jnd_pca *pca, const float *proj,
                                   const jnd_pca_encoding *e, jnd_pca_visibility *vis, size_t *bytes) {
  jnd_pca_encoded enc;
  jnd_status s = encode_from(set, pca, proj, e, &enc);
  if (s != JND_OK) return s;
  jnd_image rec = {0};
  s = jnd_pca_reconstruct(&enc, NULL, &rec);
  if (s == JND_OK) s = jnd_pca_render_measure(r, &rec, vis);
  *bytes = enc.storage_bytes;
  jnd_image_free(&rec);
  jnd_pca_encoded_free(&enc);
  return s;
}

static void search_log_add(jnd_pca_search_log *log, const jnd_pca_encoding *e, size_t bytes, double floor_db,
                           const jnd_pca_visibility *v) {
  if (!log || log->tried >= JND_PCA_MAX_TRIED) return;
  int t = log->tried++;
  log->enc[t] = *e;
  log->storage_bytes[t] = bytes;
  log->psnr_target_db[t] = floor_db;
  log->vis[t] = *v;
}

static int same_encoding(const jnd_pca_encoding *a, const jnd_pca_encoding *b) {
  if (a->components != b->components) return 0;
  for (int k = 0; k < a->components; k++)
    if (a->scale[k] != b->scale[k] || a->bits[k] != b->bits[k]) return 0;
  return 1;
}

jnd_status jnd_pca_choose_rendered(jnd_pca_render *r, const jnd_texset *set, const jnd_pca *pca, int max_scale,
                                   jnd_pca_encoding *out, jnd_pca_visibility *vis, jnd_pca_search_log *log) {
  enum { FAMILY = 26 };   /* 24 PSNR floors and the lossless candidate */
  memset(out, 0, sizeof *out);
  if (vis) memset(vis, 0, sizeof *vis);
  if (log) {
    memset(log, 0, sizeof *log);
    log->chosen = -1;
  }
  if (r->set != set) return jnd_fail(JND_ERR_ARG, "%s: the set is not the one bound", r->path);
  psnr_chooser ch;
  jnd_status s = chooser_init(set, pca, max_scale, &ch);
  if (s != JND_OK) return s;
  jnd_pca_encoding fam[FAMILY];
  double floor_db[FAMILY];
  size_t bytes[FAMILY];
  int n = 0;
  /* the family: the cheapest encoding for each PSNR floor (001's measure,
   * fast to search), then all components at 16 bits */
  for (int db = 14; db <= 60 && s == JND_OK; db += 2) {
    jnd_pca_encoding e;
    s = chooser_run(&ch, set, pca, db, &e);
    if (s == JND_ERR_ARG) {   /* unreachable floor: the higher ones are too */
      s = JND_OK;
      break;
    }
    if (s != JND_OK) break;
    fam[n] = e;
    floor_db[n++] = db;
  }
  if (s == JND_OK) {
    jnd_pca_encoding e;
    jnd_pca_encoding_default(pca, &e);
    for (int k = 0; k < set->c; k++) e.bits[k] = 16;
    fam[n] = e;
    floor_db[n++] = 0;
  }
  /* deduplicate, sort by storage (stable: insertion) */
  int m = 0;
  for (int i = 0; i < n; i++) {
    int dup = 0;
    for (int j = 0; j < m && !dup; j++) dup = same_encoding(&fam[j], &fam[i]);
    if (dup) continue;
    fam[m] = fam[i];
    floor_db[m] = floor_db[i];
    bytes[m] = jnd_pca_storage_bytes(&fam[m], set->c, set->w, set->h);
    for (int j = m; j > 0 && bytes[j] < bytes[j - 1]; j--) {
      jnd_pca_encoding te = fam[j];
      fam[j] = fam[j - 1];
      fam[j - 1] = te;
      double td = floor_db[j];
      floor_db[j] = floor_db[j - 1];
      floor_db[j - 1] = td;
      size_t tb = bytes[j];
      bytes[j] = bytes[j - 1];
      bytes[j - 1] = tb;
    }
    m++;
  }
  if (log) log->candidates = m;
  /* bisection for the first candidate that passes */
  int lo = 0, hi = m, best = -1;
  jnd_pca_encoding best_enc;
  jnd_pca_visibility best_vis;
  size_t best_bytes = 0;
  memset(&best_enc, 0, sizeof best_enc);
  memset(&best_vis, 0, sizeof best_vis);
  while (lo < hi && s == JND_OK) {
    int mid = lo + (hi - lo) / 2;
    jnd_pca_visibility v;
    size_t b = 0;
    s = measure_encoding(r, set, pca, ch.proj, &fam[mid], &v, &b);
    if (s != JND_OK) break;
    search_log_add(log, &fam[mid], b, floor_db[mid], &v);
    if (v.pass) {
      hi = mid;
      best = mid;
      best_enc = fam[mid];
      best_vis = v;
      best_bytes = b;
    } else {
      lo = mid + 1;
    }
  }
  /* The floors are 2 dB apart, and one step can double the storage (a
   * component going from 8 to 16 bits): bisect the floor between the
   * candidate below, which failed (lo only moves past failures), and the
   * chosen one. */
  if (s == JND_OK && best > 0 && floor_db[best] > 0 && floor_db[best - 1] > 0) {
    double f_lo = floor_db[best - 1], f_hi = floor_db[best];
    for (int it = 0; it < 3 && s == JND_OK; it++) {
      double f = 0.5 * (f_lo + f_hi);
      jnd_pca_encoding e;
      s = chooser_run(&ch, set, pca, f, &e);
      if (s != JND_OK) break;
      size_t b = jnd_pca_storage_bytes(&e, set->c, set->w, set->h);
      if (b >= best_bytes) {   /* nothing cheaper above f */
        f_hi = f;
        continue;
      }
      if (same_encoding(&e, &fam[best - 1])) {   /* known to fail */
        f_lo = f;
        continue;
      }
      jnd_pca_visibility v;
      s = measure_encoding(r, set, pca, ch.proj, &e, &v, &b);
      if (s != JND_OK) break;
      search_log_add(log, &e, b, f, &v);
      if (v.pass) {
        best_enc = e;
        best_vis = v;
        best_bytes = b;
        f_hi = f;
      } else {
        f_lo = f;
      }
    }
  }
  chooser_free(&ch);
  if (s != JND_OK) return s;
  if (best < 0)
    return jnd_fail(JND_ERR_ARG, "%s: no encoding keeps P <= %g in all but %g of the views, not even all components at 16 bits",
                    r->path, r->p.judge.criterion.p, r->p.judge.criterion.q);
  if (log)
    for (int t = 0; t < log->tried; t++)
      if (same_encoding(&log->enc[t], &best_enc)) log->chosen = t;
  *out = best_enc;
  if (vis) *vis = best_vis;
  return JND_OK;
}

/* The hook of tasks.h: the simple call. */
jnd_status pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc, const char *model_path,
                                   const char *material, double *p_detect) {
  if (p_detect) *p_detect = NAN;
  if (!set || !enc) return jnd_fail(JND_ERR_ARG, "%s: rendered visibility needs a set and an encoding",
                                    model_path ? model_path : "--model");
  jnd_map_slot slots[JND_PCA_MAX_MAPS];
  for (int i = 0; i < set->nmaps; i++)
    if (!jnd_pca_slot_guess(set->maps[i].name, &slots[i]))
      return jnd_fail(JND_ERR_ARG, "%s: no material slot fits the map name '%s'", model_path ? model_path : "--model",
                      set->maps[i].name);
  jnd_pca_render_params p;
  jnd_pca_render_defaults(&p);
  jnd_pca_render *r = NULL;
  jnd_status s = jnd_pca_render_open(model_path, material, &p, &r);
  if (s == JND_OK) s = jnd_pca_render_bind(r, set, slots);
  jnd_image rec = {0};
  jnd_pca_visibility v;
  if (s == JND_OK) s = jnd_pca_reconstruct(enc, NULL, &rec);
  if (s == JND_OK) s = jnd_pca_render_measure(r, &rec, &v);
  if (s == JND_OK && p_detect) *p_detect = v.p_criterion;
  jnd_image_free(&rec);
  jnd_pca_render_free(r);
  return s;
}

jnd_status jnd_pca_rendered_visibility(const jnd_texset *set, const jnd_pca_encoded *enc, const char *model_path,
                                       const char *material, double *p_detect) {
  return pca_rendered_visibility(set, enc, model_path, material, p_detect);
}

/* ------------------------------------------------------------------------ */
/* Block compression of the components and of the maps (001 "Caveats")     */
/* ------------------------------------------------------------------------ */

/* Compresses channels [first, first+n) of img with f and decodes them back
 * in place; returns the bytes it took. */
static jnd_status bc_roundtrip(jnd_bc_format f, jnd_image *img, int first, size_t *bytes) {
  size_t n = jnd_bc_size(f, img->w, img->h);
  uint8_t *blocks = jnd_alloc(n, 1);
  if (!blocks) return JND_ERR_NOMEM;
  jnd_status s = jnd_bc_encode(f, img, first, blocks);
  if (s == JND_OK) s = jnd_bc_decode(f, blocks, img, first);
  free(blocks);
  *bytes += n;
  return s;
}

/* components grouped (by threes of one size when bc1, else pairs),
 * block-compressed and reconstructed into rec (w × h × C, allocated) */
static jnd_status bc_components(const jnd_pca_encoded *enc, int bc1, jnd_image *rec, size_t *bytes) {
  int K = enc->enc.components;
  jnd_image comp[MAXC];
  memset(comp, 0, sizeof comp);
  jnd_status s = JND_OK;
  *bytes = 0;
  int done[MAXC] = {0};
  for (int k = 0; k < K && s == JND_OK; k++) {
    if (done[k]) continue;
    int group[3] = {k, -1, -1}, n = 1, want = bc1 ? 3 : 2;
    for (int j = k + 1; j < K && n < want; j++)
      if (!done[j] && enc->enc.scale[j] == enc->enc.scale[k]) group[n++] = j;
    const jnd_image *src = &enc->comp[k];
    jnd_image packed = {0};
    s = jnd_image_alloc(&packed, src->w, src->h, n);
    for (int g = 0; g < n && s == JND_OK; g++) {
      memcpy(jnd_image_plane(&packed, g), enc->comp[group[g]].data, (size_t)src->w * src->h * sizeof(float));
      done[group[g]] = 1;
    }
    if (s == JND_OK) s = bc_roundtrip(n == 3 ? JND_BC1 : n == 2 ? JND_BC5 : JND_BC4, &packed, 0, bytes);
    for (int g = 0; g < n && s == JND_OK; g++) {
      s = jnd_image_alloc(&comp[group[g]], src->w, src->h, 1);
      if (s == JND_OK)
        memcpy(comp[group[g]].data, jnd_image_plane(&packed, g), (size_t)src->w * src->h * sizeof(float));
    }
    jnd_image_free(&packed);
  }
  if (s == JND_OK) s = jnd_pca_reconstruct(enc, comp, rec);
  for (int k = 0; k < K; k++) jnd_image_free(&comp[k]);
  return s;
}

/* the maps themselves, each in the format its channel count calls for */
static jnd_status bc_plain(const jnd_texset *set, jnd_image *rec, size_t *bytes) {
  *bytes = 0;
  jnd_status s = jnd_image_alloc(rec, set->w, set->h, set->c);
  if (s == JND_OK) memcpy(rec->data, set->data, (size_t)set->w * set->h * set->c * sizeof(float));
  for (int i = 0; i < set->nmaps && s == JND_OK; i++) {
    const jnd_texset_map *m = &set->maps[i];
    jnd_image view = {set->w, set->h, m->count, jnd_image_plane(rec, m->first)};
    switch (m->count) {
    case 1: s = bc_roundtrip(JND_BC4, &view, 0, bytes); break;
    case 2: s = bc_roundtrip(JND_BC5, &view, 0, bytes); break;
    case 3: s = bc_roundtrip(JND_BC1, &view, 0, bytes); break;
    default:
      s = bc_roundtrip(JND_BC1, &view, 0, bytes);
      if (s == JND_OK) s = bc_roundtrip(JND_BC4, &view, 3, bytes);
      break;
    }
  }
  if (s != JND_OK) jnd_image_free(rec);
  return s;
}

jnd_status jnd_pca_block_compressed(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_variant v,
                                    jnd_image *out, size_t *bytes) {
  memset(out, 0, sizeof *out);
  size_t b = 0;
  if (!set || !set->data) return jnd_fail(JND_ERR_ARG, "block compression: no set");
  if (v != JND_PCA_BC_PLAIN && (!enc || enc->c != set->c || enc->w != set->w || enc->h != set->h))
    return jnd_fail(JND_ERR_ARG, "block compression: set and encoding differ");
  jnd_status s;
  switch (v) {
  case JND_PCA_BC_PCA_BC4: s = bc_components(enc, 0, out, &b); break;
  case JND_PCA_BC_PCA_BC1: s = bc_components(enc, 1, out, &b); break;
  case JND_PCA_BC_PLAIN: s = bc_plain(set, out, &b); break;
  default: return jnd_fail(JND_ERR_ARG, "block compression: variant %d", (int)v);
  }
  if (bytes) *bytes = b;
  return s;
}

jnd_status jnd_pca_block_compression(const jnd_texset *set, const jnd_pca_encoded *enc, jnd_pca_bc_report *out) {
  memset(out, 0, sizeof *out);
  if (!set || !enc || enc->c != set->c || enc->w != set->w || enc->h != set->h)
    return jnd_fail(JND_ERR_ARG, "block compression: set and encoding differ");
  double *psnr[3] = {out->psnr_pca_bc4_db, out->psnr_pca_bc1_db, out->psnr_plain_db};
  size_t *bytes[3] = {&out->bytes_pca_bc4, &out->bytes_pca_bc1, &out->bytes_plain};
  jnd_status s = JND_OK;
  for (int v = 0; v < 3 && s == JND_OK; v++) {
    jnd_image rec = {0};
    s = jnd_pca_block_compressed(set, enc, (jnd_pca_bc_variant)v, &rec, bytes[v]);
    if (s == JND_OK) s = jnd_texset_psnr(set, &rec, psnr[v], NULL);
    jnd_image_free(&rec);
  }
  return s;
}
