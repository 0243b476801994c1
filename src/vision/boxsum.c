/* The box passes of local summation (model.c local_summation; docs/model.md
 * "Area summation"): three passes along each axis make its Gaussian window.
 *
 * A pass gives each output the sum of the 2r + 1 samples centred on it plus
 * a times the two at r + 1, over the weights' sum 2r + 1 + 2a. The window's
 * sum is not a running sum (add the sample entering, subtract the one
 * leaving): in float that subtraction cancels, and after a large difference
 * has left the window its rounding stays behind in the sum of the small ones
 * (j^beta spans ten orders between an edge and its surround). It is instead
 * van Herk's and Gil & Werman's split of the samples into blocks of the
 * window's length L = 2r + 1, from the first window's start: a window
 * starting at p in block [p0, p0 + L) is the block's suffix from p plus the
 * next block's prefix up to p + L − 1, both sums of non-negative terms
 * restarted at every block, so the rounding of any output is that of at
 * most L additions of its own window's samples (relative error below L·2^−24,
 * about 5e-6 at the finest band's r ≈ 38), whatever lies beyond it. The
 * blocks start at the pass's own first window, not a thread's, so the
 * outputs are the same at any thread count. (Until the eighth pass these
 * were running sums in double: docs/speed.md "Eighth pass".) */
#include <limits.h>
#include <stddef.h>
#include <string.h>

#include "core/core.h"
#include "vision/vision.h"

/* row j of the pass's input, or zeros outside [n0, n1) */
static inline const float *box_src(const float *s, ptrdiff_t ss, int n0, int n1, int j) {
  static const float zeros[JND_BOX_LANES_MAX];
  return j >= n0 && j < n1 ? s + ss * j : zeros;
}

/* suf[t] = the samples from p0 + t to p0 + L − 1, t from L − 1 down to t1:
 * the suffixes of block p0, one chain of additions */
static inline __attribute__((always_inline)) void box_suffix(const float *s, ptrdiff_t ss, int n0, int n1, int p0,
                                                             int L, int V, float *suf) {
  const float *sj = box_src(s, ss, n0, n1, p0 + L - 1);
  float *u = suf + (size_t)(L - 1) * V;
#pragma omp simd
  for (int k = 0; k < V; k++) u[k] = sj[k];
  for (int t = L - 2; t >= 0; t--) {
    sj = box_src(s, ss, n0, n1, p0 + t);
    u = suf + (size_t)t * V;
    const float *u1 = u + V;
#pragma omp simd
    for (int k = 0; k < V; k++) u[k] = u1[k] + sj[k];
  }
}

/* the pass on V lanes (V a constant where it is inlined, so that the lane
 * loops vectorise without a remainder). Each block's windows walk its
 * successor forwards (the prefix) while the successor's suffixes are made
 * backwards in the same loop: two independent chains of additions in
 * flight, not one after the other (with 8 lanes, one vector, each chain is
 * bound by the adds' latency). The suffixes are the same additions in the
 * same order as box_suffix's. */
static inline __attribute__((always_inline)) void box_pass(const float *s, ptrdiff_t ss, int n0, int n1, float *d,
                                                           ptrdiff_t ds, int from, int m, int V, int r, float a,
                                                           float *suf) {
  const int L = 2 * r + 1, last = from + m - 1 - r; /* the last window's start */
  const float inv = (float)(1.0 / (2.0 * r + 1.0 + 2.0 * a));
  float pre[JND_BOX_LANES_MAX];
  float *cur = suf, *nxt = suf + (size_t)L * V;
  if (from - r <= last) box_suffix(s, ss, n0, n1, from - r, L, V, cur);
  for (int p0 = from - r; p0 <= last; p0 += L) {
    const int nt = last - p0 + 1 < L ? last - p0 + 1 : L;
    const int more = p0 + L <= last; /* a next block, whose suffixes are made here (then nt = L) */
    for (int k = 0; k < V; k++) pre[k] = 0;
    for (int t = 0; t < nt; t++) {
      const int c = p0 + t + r;
      const float *lo = box_src(s, ss, n0, n1, c - r - 1), *hi = box_src(s, ss, n0, n1, c + r + 1);
      const float *u = cur + (size_t)t * V;
      float *o = d + ds * (c - from);
#pragma omp simd
      for (int k = 0; k < V; k++) o[k] = ((u[k] + pre[k]) + a * (lo[k] + hi[k])) * inv;
      if (t + 1 < nt) {
        const float *nx = box_src(s, ss, n0, n1, p0 + L + t);
#pragma omp simd
        for (int k = 0; k < V; k++) pre[k] += nx[k];
      }
      if (more) {
        const int q = L - 1 - t; /* the next block's suffix from p0 + L + q */
        const float *sq = box_src(s, ss, n0, n1, p0 + L + q);
        float *v = nxt + (size_t)q * V;
        if (q == L - 1) {
#pragma omp simd
          for (int k = 0; k < V; k++) v[k] = sq[k];
        } else {
          const float *v1 = v + V;
#pragma omp simd
          for (int k = 0; k < V; k++) v[k] = v1[k] + sq[k];
        }
      }
    }
    float *sw = cur;
    cur = nxt;
    nxt = sw;
  }
}

/* box_pass on 8 interleaved lanes (one vector a sample) of an input with no
 * bounds: the same additions in the same order, the two chains (the
 * prefix and the next block's suffixes) held in registers — box_pass's
 * lane arrays go through memory, a store-to-load delay on each chain's
 * every step */
typedef float box_v8 __attribute__((vector_size(32)));
/* (macros, not functions: a 32-byte vector passed by value would change the
 * baseline clone's calling convention, GCC's -Wpsabi; as in io/png.c) */
#define BOX_LD8(p) __extension__({ box_v8 v_; memcpy(&v_, (p), sizeof v_); v_; })
#define BOX_ST8(p, v) __extension__({ box_v8 w_ = (v); memcpy((p), &w_, sizeof w_); })

static inline __attribute__((always_inline)) void box_pass8(const float *s, float *d, int from, int m, int r, float a,
                                                            float *suf) {
  const int L = 2 * r + 1, last = from + m - 1 - r;
  const float inv = (float)(1.0 / (2.0 * r + 1.0 + 2.0 * a));
  const box_v8 av = {a, a, a, a, a, a, a, a}, iv = {inv, inv, inv, inv, inv, inv, inv, inv};
  float *cur = suf, *nxt = suf + (size_t)8 * L;
  if (from - r <= last) box_suffix(s, 8, INT_MIN, INT_MAX, from - r, L, 8, cur);
  for (int p0 = from - r; p0 <= last; p0 += L) {
    const int nt = last - p0 + 1 < L ? last - p0 + 1 : L;
    const int more = p0 + L <= last;
    box_v8 pre = {0}, run = {0};
    for (int t = 0; t < nt; t++) {
      const int c = p0 + t + r;
      const box_v8 o = ((BOX_LD8(cur + (size_t)8 * t) + pre) +
                        av * (BOX_LD8(s + (ptrdiff_t)8 * (c - r - 1)) + BOX_LD8(s + (ptrdiff_t)8 * (c + r + 1)))) *
                       iv;
      BOX_ST8(d + (ptrdiff_t)8 * (c - from), o);
      if (t + 1 < nt) pre = pre + BOX_LD8(s + (ptrdiff_t)8 * (p0 + L + t));
      if (more) {
        const int q = L - 1 - t;
        const box_v8 sq = BOX_LD8(s + (ptrdiff_t)8 * (p0 + L + q));
        run = q == L - 1 ? sq : run + sq;
        BOX_ST8(nxt + (size_t)8 * q, run);
      }
    }
    float *sw = cur;
    cur = nxt;
    nxt = sw;
  }
}

JND_HOT void jnd_box_pass(const float *s, ptrdiff_t ss, int n0, int n1, float *d, ptrdiff_t ds, int from, int m,
                          int lanes, int r, float a, float *suf) {
  if (lanes == 8 && ss == 8 && ds == 8 && n0 == INT_MIN && n1 == INT_MAX)
    box_pass8(s, d, from, m, r, a, suf);
  else if (lanes == 8)
    box_pass(s, ss, n0, n1, d, ds, from, m, 8, r, a, suf);
  else if (lanes == JND_BOX_LANES_MAX)
    box_pass(s, ss, n0, n1, d, ds, from, m, JND_BOX_LANES_MAX, r, a, suf);
  else
    box_pass(s, ss, n0, n1, d, ds, from, m, lanes, r, a, suf);
}
