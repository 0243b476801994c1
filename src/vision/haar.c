/* Haar wavelet bands weighted by the Mannos–Sakrison CSF: the perceptual
 * term of 003 §4.2 (eqs. 3–4).
 *
 * 003: "by applying H to a discrete input with bandwidth (0, π), a level of
 * coefficients with bandwidth (π/2, π) is acquired. Thus, after m
 * iterations, the weight for level m is C_m = ∫_{F_m} CSF(ω) dω / A(F_m)
 * where F_m is the frequency subband (π/2^m, π/2^(m−1))". A band of ω in
 * radians per pixel is f = ω/(2π) cycles per pixel, f·ppd cycles per degree
 * on a display of ppd pixels per degree, so level m spans
 * [ppd/2^(m+1), ppd/2^m] cycles per degree; C_m is the CSF's mean there. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "vision/vision.h"

/* 003 §4.2, after Mannos & Sakrison (1974): C_s(f) = (0.0499 + 0.2964 f)
 * exp(−(0.114 f)^1.1), f in cycles per degree (peak ≈ 0.98 near 8 cpd). */
double jnd_csf_mannos_sakrison(double f_cpd) {
  if (!(f_cpd > 0)) return 0.0499;
  return (0.0499 + 0.2964 * f_cpd) * exp(-pow(0.114 * f_cpd, 1.1));
}

/* 003 §4.2: C_m, the CSF averaged over level m's band (Simpson's rule, 64
 * intervals: the integrand is smooth). */
double jnd_haar_band_weight(int m, double ppd) {
  if (m < 1 || !(ppd > 0)) return 0;
  double hi = ppd / ldexp(1.0, m), lo = hi / 2;
  const int n = 64;
  double h = (hi - lo) / n, sum = jnd_csf_mannos_sakrison(lo) + jnd_csf_mannos_sakrison(hi);
  for (int i = 1; i < n; i++) sum += (i % 2 ? 4 : 2) * jnd_csf_mannos_sakrison(lo + i * h);
  return sum * h / 3 / (hi - lo);
}

/* One step of the orthonormal 2D Haar transform of a w × h plane (odd sides
 * padded with zeros: the background of a rendering is black): the coarse
 * plane (ceil(w/2) × ceil(h/2), the pairs' sum / 2) into lo, and the energy
 * of the three detail subbands returned. */
static double haar_step(const float *src, int w, int h, float *lo) {
  int cw = (w + 1) / 2, ch = (h + 1) / 2;
  double energy = 0;
  for (int y = 0; y < ch; y++) {
    const float *r0 = src + (size_t)(2 * y) * w, *r1 = 2 * y + 1 < h ? src + (size_t)(2 * y + 1) * w : NULL;
    for (int x = 0; x < cw; x++) {
      double a = r0[2 * x], b = 2 * x + 1 < w ? r0[2 * x + 1] : 0;
      double c = r1 ? r1[2 * x] : 0, d = r1 && 2 * x + 1 < w ? r1[2 * x + 1] : 0;
      double lh = 0.5 * (a - b + c - d), hl = 0.5 * (a + b - c - d), hh = 0.5 * (a - b - c + d);
      energy += lh * lh + hl * hl + hh * hh;
      lo[(size_t)y * cw + x] = (float)(0.5 * (a + b + c + d));
    }
  }
  return energy;
}

int jnd_haar_band_energy(const float *plane, int w, int h, double *energy, int max_levels, double *rest) {
  int levels = 0;
  if (w < 1 || h < 1) return 0;
  size_t n = (size_t)((w + 1) / 2) * ((h + 1) / 2);
  float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
  if (!a || !b) {
    free(a);
    free(b);
    return -1;
  }
  const float *cur = plane;
  int cw = w, chh = h;
  while ((cw > 1 || chh > 1) && levels < max_levels) {
    float *dst = cur == a ? b : a;
    energy[levels++] = haar_step(cur, cw, chh, dst);
    cur = dst;
    cw = (cw + 1) / 2;
    chh = (chh + 1) / 2;
  }
  if (rest) {
    double r = 0;
    for (size_t i = 0; i < (size_t)cw * chh; i++) r += (double)cur[i] * cur[i];
    *rest = r;
  }
  free(a);
  free(b);
  return levels;
}
