/* GPU block compression, encoder and decoder, written from the format
 * definitions (D3D BC1/BC4/BC5, a.k.a. DXT1/ATI1/ATI2), for 001 "Caveats":
 * how much a decorrelated texture set loses under block compression.
 *
 * BC1 block (8 bytes): two RGB565 endpoints c0, c1 (little-endian), then
 * 16 two-bit indices, texel i (row-major in the 4 × 4 block) at bits 2i.
 * With c0 > c1 the palette is c0, c1, (2c0 + c1)/3, (c0 + 2c1)/3; we only
 * produce that four-colour mode (a flat block has c0 = c1 and index 0).
 * BC4 block (8 bytes): two 8-bit endpoints r0, r1, then 16 three-bit
 * indices at bits 3i of the next 48 bits. With r0 > r1 index k ≥ 2 is
 * ((8 − k)·r0 + (k − 1)·r1)/7; with r0 ≤ r1 indices 2..5 interpolate in
 * fifths and 6, 7 are 0 and 255. BC5 is two BC4 blocks (R then G).
 *
 * Encoders: BC4 starts from the block's min and max and refines the
 * endpoints by least squares over the chosen indices; BC1 takes the block's
 * principal axis (power iteration on the 3 × 3 covariance), puts the
 * endpoints at the extreme projections, then alternates index assignment
 * and a least-squares endpoint fit, keeping the best quantised result.
 * Partial blocks at the image edge replicate the last row/column.
 * Decoders round interpolated values to nearest. */
#include <math.h>
#include <string.h>

#include "core/core.h"

size_t jnd_bc_size(jnd_bc_format f, int w, int h) {
  size_t blocks = (size_t)((w + 3) / 4) * (size_t)((h + 3) / 4);
  return blocks * (f == JND_BC5 ? 16 : 8);
}

static int to8(float v) {
  double d = v * 255.0;
  return d <= 0 ? 0 : d >= 255 ? 255 : (int)lrint(d);
}

/* the 16 texels of block (bx, by) of channel ch as 0..255 */
static void gather(const jnd_image *img, int ch, int bx, int by, float *t) {
  const float *p = jnd_image_plane(img, ch);
  for (int y = 0; y < 4; y++) {
    int yy = by * 4 + y < img->h ? by * 4 + y : img->h - 1;
    for (int x = 0; x < 4; x++) {
      int xx = bx * 4 + x < img->w ? bx * 4 + x : img->w - 1;
      t[y * 4 + x] = (float)to8(p[(size_t)yy * img->w + xx]);
    }
  }
}

/* ---- BC4 ---- */

static void bc4_palette(int r0, int r1, int *pal) {
  pal[0] = r0;
  pal[1] = r1;
  if (r0 > r1) {
    for (int k = 2; k < 8; k++) pal[k] = ((8 - k) * r0 + (k - 1) * r1 + 3) / 7;
  } else {
    for (int k = 2; k < 6; k++) pal[k] = ((6 - k) * r0 + (k - 1) * r1 + 2) / 5;
    pal[6] = 0;
    pal[7] = 255;
  }
}

/* nearest palette entries; returns the squared error */
static double bc4_assign(const float *t, const int *pal, int *idx) {
  double err = 0;
  for (int i = 0; i < 16; i++) {
    int best = 0;
    double bd = 1e30;
    for (int k = 0; k < 8; k++) {
      double d = (t[i] - pal[k]) * (t[i] - pal[k]);
      if (d < bd) {
        bd = d;
        best = k;
      }
    }
    idx[i] = best;
    err += bd;
  }
  return err;
}

static void bc4_block(const float *t, uint8_t *out) {
  float lo = t[0], hi = t[0];
  for (int i = 1; i < 16; i++) {
    lo = t[i] < lo ? t[i] : lo;
    hi = t[i] > hi ? t[i] : hi;
  }
  int r0 = (int)hi, r1 = (int)lo, pal[8], idx[16], best_idx[16];
  int best0 = r0, best1 = r1;
  if (r0 == r1) {
    memset(best_idx, 0, sizeof best_idx);
  } else {
    bc4_palette(r0, r1, pal);
    double best = bc4_assign(t, pal, best_idx);
    memcpy(idx, best_idx, sizeof idx);
    for (int it = 0; it < 3 && best > 0; it++) {
      /* least squares: t_i ≈ a_i r0 + (1 − a_i) r1 with a from the indices */
      double saa = 0, sab = 0, sbb = 0, sat = 0, sbt = 0;
      for (int i = 0; i < 16; i++) {
        double a = idx[i] == 0 ? 1 : idx[i] == 1 ? 0 : (8 - idx[i]) / 7.0, b = 1 - a;
        saa += a * a;
        sab += a * b;
        sbb += b * b;
        sat += a * t[i];
        sbt += b * t[i];
      }
      double det = saa * sbb - sab * sab;
      if (fabs(det) < 1e-9) break;
      int n0 = jnd_clampi((int)lrint((sat * sbb - sbt * sab) / det), 0, 255);
      int n1 = jnd_clampi((int)lrint((sbt * saa - sat * sab) / det), 0, 255);
      if (n0 < n1) {
        int tmp = n0;
        n0 = n1;
        n1 = tmp;
      }
      if (n0 == n1) break;
      bc4_palette(n0, n1, pal);
      double e = bc4_assign(t, pal, idx);
      if (e < best) {
        best = e;
        best0 = n0;
        best1 = n1;
        memcpy(best_idx, idx, sizeof idx);
      } else {
        break;
      }
    }
  }
  out[0] = (uint8_t)best0;
  out[1] = (uint8_t)best1;
  uint64_t bits = 0;
  for (int i = 0; i < 16; i++) bits |= (uint64_t)best_idx[i] << (3 * i);
  for (int b = 0; b < 6; b++) out[2 + b] = (uint8_t)(bits >> (8 * b));
}

static void bc4_decode_block(const uint8_t *in, float *t) {
  int pal[8];
  bc4_palette(in[0], in[1], pal);
  uint64_t bits = 0;
  for (int b = 0; b < 6; b++) bits |= (uint64_t)in[2 + b] << (8 * b);
  for (int i = 0; i < 16; i++) t[i] = (float)pal[(bits >> (3 * i)) & 7];
}

/* ---- BC1 ---- */

static int pack565(const double *c) {
  int r = jnd_clampi((int)lrint(c[0] * 31 / 255.0), 0, 31);
  int g = jnd_clampi((int)lrint(c[1] * 63 / 255.0), 0, 63);
  int b = jnd_clampi((int)lrint(c[2] * 31 / 255.0), 0, 31);
  return (r << 11) | (g << 5) | b;
}

static void unpack565(int v, int *c) {
  int r = (v >> 11) & 31, g = (v >> 5) & 63, b = v & 31;
  c[0] = (r << 3) | (r >> 2);
  c[1] = (g << 2) | (g >> 4);
  c[2] = (b << 3) | (b >> 2);
}

static void bc1_palette(int c0, int c1, int pal[4][3]) {
  unpack565(c0, pal[0]);
  unpack565(c1, pal[1]);
  for (int ch = 0; ch < 3; ch++) {
    if (c0 > c1) {
      pal[2][ch] = (2 * pal[0][ch] + pal[1][ch] + 1) / 3;
      pal[3][ch] = (pal[0][ch] + 2 * pal[1][ch] + 1) / 3;
    } else {
      pal[2][ch] = (pal[0][ch] + pal[1][ch] + 1) / 2;
      pal[3][ch] = 0;
    }
  }
}

static double bc1_assign(const float t[16][3], int pal[4][3], int ncol, int *idx) {
  double err = 0;
  for (int i = 0; i < 16; i++) {
    int best = 0;
    double bd = 1e30;
    for (int k = 0; k < ncol; k++) {
      double d = 0;
      for (int ch = 0; ch < 3; ch++) d += (t[i][ch] - pal[k][ch]) * (t[i][ch] - pal[k][ch]);
      if (d < bd) {
        bd = d;
        best = k;
      }
    }
    idx[i] = best;
    err += bd;
  }
  return err;
}

/* endpoints e0, e1 → ordered 565 pair, indices, error */
static double bc1_try(const float t[16][3], const double *e0, const double *e1, int *c0, int *c1, int *idx) {
  int a = pack565(e0), b = pack565(e1);
  if (a < b) {
    int tmp = a;
    a = b;
    b = tmp;
  }
  int pal[4][3];
  *c0 = a;
  *c1 = b;
  if (a == b) {
    bc1_palette(a, b, pal);
    for (int i = 0; i < 16; i++) idx[i] = 0;
    double err = 0;
    for (int i = 0; i < 16; i++)
      for (int ch = 0; ch < 3; ch++) err += (t[i][ch] - pal[0][ch]) * (t[i][ch] - pal[0][ch]);
    return err;
  }
  bc1_palette(a, b, pal);
  return bc1_assign(t, pal, 4, idx);
}

static void bc1_block(const float t[16][3], uint8_t *out) {
  double mean[3] = {0, 0, 0}, cov[3][3] = {{0}};
  for (int i = 0; i < 16; i++)
    for (int ch = 0; ch < 3; ch++) mean[ch] += t[i][ch] / 16.0;
  for (int i = 0; i < 16; i++)
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) cov[r][c] += (t[i][r] - mean[r]) * (t[i][c] - mean[c]);
  /* principal axis by power iteration, started on the widest channel */
  double axis[3] = {0, 0, 0};
  int wide = cov[1][1] > cov[0][0] ? 1 : 0;
  wide = cov[2][2] > cov[wide][wide] ? 2 : wide;
  axis[wide] = 1;
  for (int it = 0; it < 8; it++) {
    double nx[3];
    for (int r = 0; r < 3; r++) nx[r] = cov[r][0] * axis[0] + cov[r][1] * axis[1] + cov[r][2] * axis[2];
    double len = sqrt(nx[0] * nx[0] + nx[1] * nx[1] + nx[2] * nx[2]);
    if (len < 1e-12) break;
    for (int r = 0; r < 3; r++) axis[r] = nx[r] / len;
  }
  double lo = 1e30, hi = -1e30;
  for (int i = 0; i < 16; i++) {
    double p = 0;
    for (int ch = 0; ch < 3; ch++) p += (t[i][ch] - mean[ch]) * axis[ch];
    lo = p < lo ? p : lo;
    hi = p > hi ? p : hi;
  }
  double e0[3], e1[3];
  for (int ch = 0; ch < 3; ch++) {
    e0[ch] = jnd_clampd(mean[ch] + axis[ch] * hi, 0, 255);
    e1[ch] = jnd_clampd(mean[ch] + axis[ch] * lo, 0, 255);
  }
  int c0, c1, idx[16], bc0, bc1, bidx[16];
  double best = bc1_try(t, e0, e1, &bc0, &bc1, bidx);
  memcpy(idx, bidx, sizeof idx);
  c0 = bc0;
  c1 = bc1;
  for (int it = 0; it < 4 && best > 0 && c0 != c1; it++) {
    /* least squares fit of the endpoints to the assigned palette weights */
    static const double wt[4] = {1, 0, 2.0 / 3.0, 1.0 / 3.0};
    double saa = 0, sab = 0, sbb = 0, sat[3] = {0}, sbt[3] = {0};
    for (int i = 0; i < 16; i++) {
      double a = wt[idx[i]], b = 1 - a;
      saa += a * a;
      sab += a * b;
      sbb += b * b;
      for (int ch = 0; ch < 3; ch++) {
        sat[ch] += a * t[i][ch];
        sbt[ch] += b * t[i][ch];
      }
    }
    double det = saa * sbb - sab * sab;
    if (fabs(det) < 1e-9) break;
    for (int ch = 0; ch < 3; ch++) {
      e0[ch] = jnd_clampd((sat[ch] * sbb - sbt[ch] * sab) / det, 0, 255);
      e1[ch] = jnd_clampd((sbt[ch] * saa - sat[ch] * sab) / det, 0, 255);
    }
    double e = bc1_try(t, e0, e1, &c0, &c1, idx);
    if (e < best) {
      best = e;
      bc0 = c0;
      bc1 = c1;
      memcpy(bidx, idx, sizeof idx);
    } else {
      break;
    }
  }
  out[0] = (uint8_t)(bc0 & 255);
  out[1] = (uint8_t)(bc0 >> 8);
  out[2] = (uint8_t)(bc1 & 255);
  out[3] = (uint8_t)(bc1 >> 8);
  uint32_t bits = 0;
  for (int i = 0; i < 16; i++) bits |= (uint32_t)bidx[i] << (2 * i);
  for (int b = 0; b < 4; b++) out[4 + b] = (uint8_t)(bits >> (8 * b));
}

static void bc1_decode_block(const uint8_t *in, float t[16][3]) {
  int c0 = in[0] | (in[1] << 8), c1 = in[2] | (in[3] << 8), pal[4][3];
  bc1_palette(c0, c1, pal);
  uint32_t bits = (uint32_t)in[4] | ((uint32_t)in[5] << 8) | ((uint32_t)in[6] << 16) | ((uint32_t)in[7] << 24);
  for (int i = 0; i < 16; i++)
    for (int ch = 0; ch < 3; ch++) t[i][ch] = (float)pal[(bits >> (2 * i)) & 3][ch];
}

/* ---- images ---- */

static int format_channels(jnd_bc_format f) { return f == JND_BC1 ? 3 : f == JND_BC4 ? 1 : f == JND_BC5 ? 2 : 0; }

static jnd_status check(jnd_bc_format f, const jnd_image *img, int first) {
  int n = format_channels(f);
  if (!n) return jnd_fail(JND_ERR_ARG, "block compression: unknown format %d", (int)f);
  if (!img || !img->data || first < 0 || first + n > img->c)
    return jnd_fail(JND_ERR_ARG, "block compression: BC%d needs %d channels from %d", (int)f, n, first);
  return JND_OK;
}

jnd_status jnd_bc_encode(jnd_bc_format f, const jnd_image *img, int first, uint8_t *blocks) {
  jnd_status s = check(f, img, first);
  if (s != JND_OK) return s;
  int bw = (img->w + 3) / 4, bh = (img->h + 3) / 4;
  size_t bsize = f == JND_BC5 ? 16 : 8;
#pragma omp parallel for schedule(dynamic, 4)
  for (int by = 0; by < bh; by++) {
    for (int bx = 0; bx < bw; bx++) {
      uint8_t *out = blocks + ((size_t)by * bw + bx) * bsize;
      float t[16], t3[16][3];
      if (f == JND_BC1) {
        for (int ch = 0; ch < 3; ch++) {
          gather(img, first + ch, bx, by, t);
          for (int i = 0; i < 16; i++) t3[i][ch] = t[i];
        }
        bc1_block((const float(*)[3])t3, out);
      } else {
        for (int ch = 0; ch < (f == JND_BC5 ? 2 : 1); ch++) {
          gather(img, first + ch, bx, by, t);
          bc4_block(t, out + 8 * ch);
        }
      }
    }
  }
  return JND_OK;
}

jnd_status jnd_bc_decode(jnd_bc_format f, const uint8_t *blocks, jnd_image *img, int first) {
  jnd_status s = check(f, img, first);
  if (s != JND_OK) return s;
  int bw = (img->w + 3) / 4, bh = (img->h + 3) / 4, n = format_channels(f);
  size_t bsize = f == JND_BC5 ? 16 : 8;
#pragma omp parallel for schedule(static)
  for (int by = 0; by < bh; by++) {
    for (int bx = 0; bx < bw; bx++) {
      const uint8_t *in = blocks + ((size_t)by * bw + bx) * bsize;
      float t3[16][3], t[16];
      if (f == JND_BC1) bc1_decode_block(in, t3);
      for (int ch = 0; ch < n; ch++) {
        if (f == JND_BC1) {
          for (int i = 0; i < 16; i++) t[i] = t3[i][ch];
        } else {
          bc4_decode_block(in + 8 * ch, t);
        }
        float *p = jnd_image_plane(img, first + ch);
        for (int y = 0; y < 4 && by * 4 + y < img->h; y++)
          for (int x = 0; x < 4 && bx * 4 + x < img->w; x++)
            p[(size_t)(by * 4 + y) * img->w + bx * 4 + x] = t[y * 4 + x] / 255.0f;
      }
    }
  }
  return JND_OK;
}
