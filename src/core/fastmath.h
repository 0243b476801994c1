/* Fast, deterministic log2 / exp2 / pow for float data on the model's hot
 * paths. Pure arithmetic (no tables, no library calls), so the same input
 * gives the same bits on every thread and run. Accuracy: relative error
 * below 1e-5 over the float range (tests/unit/test_core.c checks it against
 * libm), ample for a perceptual model whose constants are fitted to data. */
#ifndef JND_FASTMATH_H
#define JND_FASTMATH_H
#include <math.h>
#include <stdint.h>
#include <string.h>

/* log2(x) for finite x > 0: x = m·2^e with m in [√½, √2), then
 * ln m = 2 atanh(t), t = (m − 1)/(m + 1), by its series to t⁹ */
static inline float jnd_fast_log2(float x) {
  uint32_t b;
  memcpy(&b, &x, 4);
  int e = (int)((b >> 23) & 0xff) - 127;
  b = (b & 0x007fffffu) | 0x3f800000u; /* m in [1, 2) */
  float m;
  memcpy(&m, &b, 4);
  /* branch-free so that loops over arrays vectorise */
  int big = m > 1.41421356f;
  m = big ? m * 0.5f : m;
  e += big;
  float t = (m - 1.0f) / (m + 1.0f), t2 = t * t;
  float s = t * (2.0f + t2 * (2.0f / 3 + t2 * (2.0f / 5 + t2 * (2.0f / 7 + t2 * (2.0f / 9)))));
  return (float)e + s * 1.44269504f;
}

/* 2^y for y in about [-126, 127]: integer part into the exponent, the
 * fraction f in [-0.5, 0.5] by the Taylor series of e^(f ln 2) to degree 6
 * (truncation error below (ln 2 / 2)^7 / 7! = 1.2e-7). The nearest integer
 * comes from adding and subtracting 1.5·2^23, not from a conversion with
 * copysign, which GCC turns into a call, unvectorisable, on some targets. */
static inline float jnd_fast_exp2(float y) {
  float under = y < -126.0f ? 0.0f : 1.0f;
  y = y < -126.0f ? -126.0f : y > 127.0f ? 127.0f : y;
  float k = (y + 12582912.0f) - 12582912.0f; /* nearest integer, ties to even */
  float f = (y - k) * 0.69314718f;
  float p = 1.0f + f * (1.0f + f * (0.5f + f * (1.0f / 6 + f * (1.0f / 24 + f * (1.0f / 120 + f * (1.0f / 720))))));
  uint32_t b = (uint32_t)((int)k + 127) << 23;
  float s;
  memcpy(&s, &b, 4);
  return p * s * under;
}

/* max without fmaxf's NaN rules, so that loops using it vectorise */
static inline float jnd_maxf(float a, float b) { return a > b ? a : b; }
static inline float jnd_minf(float a, float b) { return a < b ? a : b; }

/* jnd_fast_pow's log2 of x (x floored at 1e-30), for loops that raise the
 * same x to several powers: jnd_fast_pow(x, y) is exactly
 * x > 0 ? jnd_fast_exp2(y * jnd_fast_log2_of(x)) : 0 */
static inline float jnd_fast_log2_of(float x) { return jnd_fast_log2(x > 1e-30f ? x : 1e-30f); }

/* x^y for x > 0 (0 for x <= 0) */
static inline float jnd_fast_pow(float x, float y) {
  float r = jnd_fast_exp2(y * jnd_fast_log2_of(x));
  return x > 0.0f ? r : 0.0f;
}
/* The sRGB transfer curves (IEC 61966-2-1), written once for all of jnd:
 * decode (display signal 0..1 → linear light) and encode (linear → signal,
 * clamped to 0..1; NaN gives 0), with the fast pow. */
static inline float jnd_srgb_decode(float v) {
  v = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
  return v <= 0.04045f ? v * (1.0f / 12.92f) : jnd_fast_pow((v + 0.055f) * (1.0f / 1.055f), 2.4f);
}
static inline float jnd_srgb_encode(float v) {
  v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;   /* NaN fails v > 0 */
  return v <= 0.0031308f ? 12.92f * v : 1.055f * jnd_fast_pow(v, 1.0f / 2.4f) - 0.055f;
}
#endif
