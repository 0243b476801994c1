/* Image-based lighting from an equirectangular environment, prepared once at
 * load: diffuse irradiance as 9 spherical-harmonic coefficients (Ramamoorthi
 * & Hanrahan 2001), specular prefiltered with the GGX lobe per roughness
 * level (filtered importance sampling, GPU Gems 3 ch. 20), and the split-sum
 * scale/bias table of the specular BRDF. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "render/render.h"

/* Equirectangular mapping shared with the shaders (pbr_frag.glsl):
 * u = atan2(x, −z) / 2π + ½, v = acos(y) / π (v = 0 at the zenith, +Y up). */
static void dir_of(double u, double v, double d[3]) {
  double ph = (u - 0.5) * 2 * M_PI, th = v * M_PI;
  d[0] = sin(th) * sin(ph);
  d[1] = cos(th);
  d[2] = -sin(th) * cos(ph);
}
static void uv_of(const double d[3], double *u, double *v) {
  *u = atan2(d[0], -d[2]) / (2 * M_PI) + 0.5;
  *v = acos(jnd_clampd(d[1], -1, 1)) / M_PI;
}

static double smooth_box(double x, double lo, double hi, double soft) {
  double a = jnd_clampd((x - lo) / soft + 0.5, 0, 1), b = jnd_clampd((hi - x) / soft + 0.5, 0, 1);
  a = a * a * (3 - 2 * a);
  b = b * b * (3 - 2 * b);
  return a * b;
}

jnd_status jnd_env_studio(jnd_image *out) {
  const int W = 512, H = 256;
  jnd_status st = jnd_image_alloc(out, W, H, 3);
  if (st) return st;
  /* soft boxes: azimuth centre, elevation centre, half-sizes (degrees), radiance */
  static const double box[3][5] = {{-45, 40, 18, 12, 6.0}, {75, 25, 20, 14, 2.5}, {170, 55, 25, 10, 4.0}};
  size_t P = (size_t)W * H;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double u = (x + 0.5) / W, v = (y + 0.5) / H;
      double elev = 90 - v * 180, az = (u - 0.5) * 360;
      double L;
      if (elev >= 0)
        L = 0.55 + 0.25 * sin(elev * M_PI / 180);          /* dome, brighter overhead */
      else
        L = 0.18 + 0.12 * exp(elev / 8.0);                 /* floor, lit near the horizon */
      for (int b = 0; b < 3; b++) {
        double da = fmod(az - box[b][0] + 540.0, 360.0) - 180;
        L += box[b][4] * smooth_box(da, -box[b][2], box[b][2], 6) *
             smooth_box(elev, box[b][1] - box[b][3], box[b][1] + box[b][3], 6);
      }
      for (int k = 0; k < 3; k++) out->data[k * P + (size_t)y * W + x] = (float)L;
    }
  return JND_OK;
}

/* ---- a mip pyramid of the source, sampled bilinearly with wrap in u ---- */
typedef struct {
  float *img[16];   /* RGB interleaved */
  int w[16], h[16], n;
} pyramid;

static void pyr_free(pyramid *p) {
  for (int i = 0; i < p->n; i++) free(p->img[i]);
}

static void pyr_fetch(const pyramid *p, int l, double u, double v, double out[3]) {
  int w = p->w[l], h = p->h[l];
  double x = u * w - 0.5, y = jnd_clampd(v * h - 0.5, 0, h - 1);
  int x0 = (int)floor(x), y0 = (int)floor(y);
  double fx = x - x0, fy = y - y0;
  int y1 = y0 + 1 < h ? y0 + 1 : h - 1;
  int xa = ((x0 % w) + w) % w, xb = (xa + 1) % w;
  const float *im = p->img[l];
  for (int k = 0; k < 3; k++) {
    double a = im[((size_t)y0 * w + xa) * 3 + k], b = im[((size_t)y0 * w + xb) * 3 + k];
    double c = im[((size_t)y1 * w + xa) * 3 + k], d = im[((size_t)y1 * w + xb) * 3 + k];
    out[k] = (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy;
  }
}

static void pyr_sample(const pyramid *p, double lod, const double d[3], double out[3]) {
  double u, v;
  uv_of(d, &u, &v);
  lod = jnd_clampd(lod, 0, p->n - 1);
  int l0 = (int)floor(lod), l1 = l0 + 1 < p->n ? l0 + 1 : l0;
  double f = lod - l0, a[3], b[3];
  pyr_fetch(p, l0, u, v, a);
  pyr_fetch(p, l1, u, v, b);
  for (int k = 0; k < 3; k++) out[k] = a[k] + (b[k] - a[k]) * f;
}

static jnd_status pyr_build(const jnd_image *src, pyramid *p) {
  memset(p, 0, sizeof *p);
  /* level 0: the source box-filtered to at most 1024 × 512 */
  int w = src->w, h = src->h, step = 1;
  while (w / step > 1024 || h / step > 512) step *= 2;
  w = src->w / step > 0 ? src->w / step : 1;
  h = src->h / step > 0 ? src->h / step : 1;
  size_t P = (size_t)src->w * src->h;
  p->img[0] = jnd_alloc((size_t)w * h * 3, sizeof(float));
  if (!p->img[0]) return JND_ERR_NOMEM;
  p->w[0] = w;
  p->h[0] = h;
  p->n = 1;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      for (int k = 0; k < 3; k++) {
        double acc = 0;
        for (int j = 0; j < step; j++)
          for (int i = 0; i < step; i++) {
            int sx = jnd_clampi(x * step + i, 0, src->w - 1), sy = jnd_clampi(y * step + j, 0, src->h - 1);
            int ch = src->c >= 3 ? k : 0;
            acc += src->data[ch * P + (size_t)sy * src->w + sx];
          }
        p->img[0][((size_t)y * w + x) * 3 + k] = (float)(acc / (step * step));
      }
  while (p->n < 16 && (p->w[p->n - 1] > 1 || p->h[p->n - 1] > 1)) {
    int pw = p->w[p->n - 1], ph = p->h[p->n - 1];
    int nw = pw > 1 ? pw / 2 : 1, nh = ph > 1 ? ph / 2 : 1;
    float *n = jnd_alloc((size_t)nw * nh * 3, sizeof(float));
    if (!n) return JND_ERR_NOMEM;
    const float *o = p->img[p->n - 1];
    for (int y = 0; y < nh; y++)
      for (int x = 0; x < nw; x++)
        for (int k = 0; k < 3; k++) {
          int x0 = jnd_clampi(2 * x, 0, pw - 1), x1 = jnd_clampi(2 * x + 1, 0, pw - 1);
          int y0 = jnd_clampi(2 * y, 0, ph - 1), y1 = jnd_clampi(2 * y + 1, 0, ph - 1);
          n[((size_t)y * nw + x) * 3 + k] =
              0.25f * (o[((size_t)y0 * pw + x0) * 3 + k] + o[((size_t)y0 * pw + x1) * 3 + k] +
                       o[((size_t)y1 * pw + x0) * 3 + k] + o[((size_t)y1 * pw + x1) * 3 + k]);
        }
    p->img[p->n] = n;
    p->w[p->n] = nw;
    p->h[p->n] = nh;
    p->n++;
  }
  return JND_OK;
}

static void hammersley(int i, int n, double *a, double *b) {
  uint32_t bits = (uint32_t)i;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  *a = (double)i / n;
  *b = bits * 2.3283064365386963e-10;
}

/* A GGX half vector around +Z for roughness α (the NDF squared-roughness). */
static void ggx_half(double a2, double e1, double e2, double h[3]) {
  double cos_t = sqrt((1 - e2) / (1 + (a2 - 1) * e2)), sin_t = sqrt(1 - cos_t * cos_t);
  double ph = 2 * M_PI * e1;
  h[0] = sin_t * cos(ph);
  h[1] = sin_t * sin(ph);
  h[2] = cos_t;
}

static void basis(const double n[3], double t[3], double b[3]) {
  double up[3] = {fabs(n[1]) < 0.999 ? 0 : 1, fabs(n[1]) < 0.999 ? 1 : 0, 0};
  t[0] = up[1] * n[2] - up[2] * n[1];
  t[1] = up[2] * n[0] - up[0] * n[2];
  t[2] = up[0] * n[1] - up[1] * n[0];
  double l = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  for (int k = 0; k < 3; k++) t[k] /= l;
  b[0] = n[1] * t[2] - n[2] * t[1];
  b[1] = n[2] * t[0] - n[0] * t[2];
  b[2] = n[0] * t[1] - n[1] * t[0];
}

static void prefilter_level(const pyramid *p, double rough, int w, int h, float *out) {
  const int M = 128;
  double a = rough * rough, a2 = a * a;
  double texel_sa = 4 * M_PI / ((double)p->w[0] * p->h[0]);
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      double n[3], t[3], b[3], acc[3] = {0, 0, 0}, wsum = 0;
      dir_of((x + 0.5) / w, (y + 0.5) / h, n);
      basis(n, t, b);
      for (int i = 0; i < M; i++) {
        double e1, e2, hl[3], hv[3], l[3], c[3];
        hammersley(i, M, &e1, &e2);
        ggx_half(a2, e1, e2, hl);
        for (int k = 0; k < 3; k++) hv[k] = hl[0] * t[k] + hl[1] * b[k] + hl[2] * n[k];
        double nh = hl[2];
        for (int k = 0; k < 3; k++) l[k] = 2 * nh * hv[k] - n[k];   /* V = N */
        double nl = l[0] * n[0] + l[1] * n[1] + l[2] * n[2];
        if (nl <= 0) continue;
        double dd = nh * nh * (a2 - 1) + 1, D = a2 / (M_PI * dd * dd);
        double pdf = D / 4;   /* D·(N·H) / (4 V·H) with V = N */
        double lod = 0.5 * log2(1.0 / (M * pdf + 1e-9) / texel_sa) + 1;
        pyr_sample(p, lod, l, c);
        for (int k = 0; k < 3; k++) acc[k] += c[k] * nl;
        wsum += nl;
      }
      for (int k = 0; k < 3; k++) out[((size_t)y * w + x) * 3 + k] = (float)(wsum > 0 ? acc[k] / wsum : 0);
    }
}

static void sh_project(const pyramid *p, float sh[9][3]) {
  int l = 0;
  while (l + 1 < p->n && p->w[l] > 128) l++;
  int w = p->w[l], h = p->h[l];
  double c[9][3] = {{0}};
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      double d[3], v = (y + 0.5) / h;
      dir_of((x + 0.5) / w, v, d);
      double dw = (2 * M_PI / w) * (M_PI / h) * sin(v * M_PI);
      double Y[9] = {0.282095, 0.488603 * d[1], 0.488603 * d[2], 0.488603 * d[0],
                     1.092548 * d[0] * d[1], 1.092548 * d[1] * d[2], 0.315392 * (3 * d[2] * d[2] - 1),
                     1.092548 * d[0] * d[2], 0.546274 * (d[0] * d[0] - d[1] * d[1])};
      const float *px = p->img[l] + ((size_t)y * w + x) * 3;
      for (int i = 0; i < 9; i++)
        for (int k = 0; k < 3; k++) c[i][k] += px[k] * Y[i] * dw;
    }
  /* cosine-lobe convolution A_l = π, 2π/3, π/4, divided by π so that the
   * shader's sum is the radiance a white Lambertian surface reflects */
  static const double A[9] = {1, 2.0 / 3, 2.0 / 3, 2.0 / 3, 0.25, 0.25, 0.25, 0.25, 0.25};
  for (int i = 0; i < 9; i++)
    for (int k = 0; k < 3; k++) sh[i][k] = (float)(c[i][k] * A[i]);
}

static void brdf_lut(float *lut) {
  const int M = 256, N = JND_BRDF_LUT;
#pragma omp parallel for schedule(static)
  for (int j = 0; j < N; j++)
    for (int i = 0; i < N; i++) {
      double nv = (i + 0.5) / N, rough = (j + 0.5) / N, a = rough * rough, a2 = a * a;
      double v[3] = {sqrt(1 - nv * nv), 0, nv}, A = 0, B = 0;
      for (int s = 0; s < M; s++) {
        double e1, e2, hh[3];
        hammersley(s, M, &e1, &e2);
        ggx_half(a2, e1, e2, hh);
        double vh = v[0] * hh[0] + v[1] * hh[1] + v[2] * hh[2];
        double lz = 2 * vh * hh[2] - v[2];
        if (lz <= 0 || vh <= 0) continue;
        double nh = hh[2];
        /* Smith masking-shadowing for GGX, separable form */
        double g1v = 2 * nv / (nv + sqrt(a2 + (1 - a2) * nv * nv));
        double g1l = 2 * lz / (lz + sqrt(a2 + (1 - a2) * lz * lz));
        double gvis = g1v * g1l * vh / (nh * nv);
        double fc = pow(1 - vh, 5);
        A += (1 - fc) * gvis;
        B += fc * gvis;
      }
      lut[((size_t)j * N + i) * 2] = (float)(A / M);
      lut[((size_t)j * N + i) * 2 + 1] = (float)(B / M);
    }
}

jnd_status jnd_env_prepare(const jnd_image *equirect, jnd_environment *env) {
  memset(env, 0, sizeof *env);
  pyramid p;
  jnd_status st = pyr_build(equirect, &p);
  if (st) {
    pyr_free(&p);
    return jnd_fail(st, "environment: out of memory");
  }
  for (int l = 0; l < JND_ENV_LEVELS; l++) {
    int w = JND_ENV_W >> l, h = JND_ENV_H >> l;
    env->lw[l] = w;
    env->lh[l] = h;
    env->level[l] = jnd_alloc((size_t)w * h * 3, sizeof(float));
    if (!env->level[l]) {
      st = JND_ERR_NOMEM;
      break;
    }
    if (l == 0) {
      double lod = log2((double)p.w[0] / w);
      for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
          double d[3], c[3];
          dir_of((x + 0.5) / w, (y + 0.5) / h, d);
          pyr_sample(&p, lod, d, c);
          for (int k = 0; k < 3; k++) env->level[0][((size_t)y * w + x) * 3 + k] = (float)c[k];
        }
    } else {
      prefilter_level(&p, (double)l / (JND_ENV_LEVELS - 1), w, h, env->level[l]);
    }
  }
  if (!st) {
    sh_project(&p, env->sh);
    env->brdf_lut = jnd_alloc((size_t)JND_BRDF_LUT * JND_BRDF_LUT * 2, sizeof(float));
    env->bw = p.w[0];
    env->bh = p.h[0];
    env->background = jnd_alloc((size_t)env->bw * env->bh * 3, sizeof(float));
    if (!env->brdf_lut || !env->background) st = JND_ERR_NOMEM;
  }
  if (!st) {
    brdf_lut(env->brdf_lut);
    memcpy(env->background, p.img[0], (size_t)env->bw * env->bh * 3 * sizeof(float));
  }
  pyr_free(&p);
  if (st) {
    jnd_env_free(env);
    return jnd_fail(st, "environment: out of memory");
  }
  return JND_OK;
}

void jnd_env_free(jnd_environment *env) {
  for (int l = 0; l < JND_ENV_LEVELS; l++) free(env->level[l]);
  free(env->brdf_lut);
  free(env->background);
  memset(env, 0, sizeof *env);
}
