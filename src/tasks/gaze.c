/* 002's two gaze-contingent models (Surace et al., EGSR 2023), on images.
 * docs/gaze.md writes each equation down; 002's equations are images the
 * notes do not carry, so the forms below are our reading of its words.
 *
 * Spatial model, for the reference R0 and level Ri seen at a fixation point:
 *  1. Silhouettes S0, Si: the renderer's coverage masks.
 *  2. Geometric term (002 eq. 1): Σ_{p ∈ S0 ⊕ Si} w(ecc_p) A_p / perimeter(S0),
 *     in degrees.  jnd_gaze_geometric_term()
 *  3. Weight (002 eq. 2): w(e) = α softplus_β(s − e) + b.  jnd_gaze_weight()
 *  4. Shading term (002 §"shading", FovVideoVDP in 002): both images over the
 *     background grey, the XOR region grey in both, through the display and
 *     jnd's vision model with the fixation point (each pixel at its own
 *     eccentricity): the judge's pair of frames (jnd_pair_judge_compare),
 *     pooled over S0 ∪ Si.  gaze_pooled_jnd()
 *  5. Magnitude and probability (002 eqs. 3–4): D = ((w_g G)^k + (w_vdp V)^k)^(1/k),
 *     P = ½ + ½ / (1 + D^−γ).  jnd_gaze_spatial_probability()
 * Temporal model (002 eq. 5, after Tursun & Didyk 2022): the switch Ri → Ri+1
 * as a sudden change: both levels over the grey, judged as a pair through
 * the vision model's temporal (flicker) sensitivity at switch_hz and the
 * fixation point, pooled
 * over the object, P = ½ + ½ / (1 + (w_t T)^−γ_t).
 *   jnd_gaze_switch()
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "jnd.h"
#include "tasks/tasks.h"

void jnd_gaze_model_defaults(jnd_gaze_model *m) {
  /* docs/gaze.md "Defaults": fitted by scripts/fit-gaze-defaults.sh to
   * synthetic observers answering from jnd's own vision model (the result is
   * scripts/gaze-defaults.json; tests/e2e/gaze_defaults.sh holds the two equal) */
  m->w_g = 1;
  m->b = 2;
  m->alpha = 5.806;
  m->beta = 0.04357;
  m->s_deg = 0;
  m->w_vdp = 1.04;
  m->k_s = 3.023;
  m->gamma = 6.531;
  m->w_t = 1.036;
  m->gamma_t = 6.124;
}

void jnd_gaze_measure_defaults(jnd_gaze_measure_params *p) {
  memset(p, 0, sizeof *p);
  jnd_model_defaults(&p->model);
  p->pool.kind = JND_POOL_PERCENTILE;
  p->pool.percentile = 93;   /* 000 §6, as the judge pools */
  p->background = 0.18;
  /* docs/gaze.md "The temporal model": a step's amplitude spectrum falls as
   * 1/f, so every octave of temporal frequency carries the same amplitude and
   * the octave seen is where the CSF peaks; 3 Hz is within 16% of the peak
   * of Kelly's surface (as fitted) in every band from 0.5 to 16 cpd */
  p->switch_hz = 3.0;
}

/* the switch's frequency: a display refreshing at fps shows nothing above fps/2 */
static double switch_frequency(const jnd_gaze_measure_params *mp) {
  double f = mp->switch_hz > 0 ? mp->switch_hz : 3.0;
  return mp->model.fps > 0 ? fmin(f, 0.5 * mp->model.fps) : f;
}

/* log(1 + e^x) without overflow */
static double softplus(double x) { return x > 0 ? x + log1p(exp(-x)) : log1p(exp(x)); }

double jnd_gaze_weight(const jnd_gaze_model *m, double ecc_deg) {
  /* 002 eq. 2: "inspired by softplus": linear for e well below s, an
   * exponential tail beyond it, never below the floor b */
  return m->alpha * softplus(m->beta * (m->s_deg - ecc_deg)) / m->beta + m->b;
}

/* ½ + ½ · x^γ / (1 + x^γ): a logistic in log x, 0.75 at x = 1 */
static double two_afc(double x, double gamma) {
  if (!(x > 0)) return 0.5;
  return 0.5 + 0.5 / (1.0 + pow(x, -gamma));
}

double jnd_gaze_spatial_probability(const jnd_gaze_model *m, double g_deg, double v_jnd) {
  double k = m->k_s >= 1 ? m->k_s : 1;
  double a = fmax(m->w_g * g_deg, 0), c = fmax(m->w_vdp * v_jnd, 0);
  double d = pow(pow(a, k) + pow(c, k), 1.0 / k);   /* 002 eq. 3 */
  return two_afc(d, m->gamma);                      /* 002 eq. 4 */
}

double jnd_gaze_switch_probability(const jnd_gaze_model *m, double t_jnd) {
  return two_afc(m->w_t * t_jnd, m->gamma_t);        /* 002 eq. 5 */
}

/* degrees between the fixation point and pixel (x, y) on a flat screen,
 * as the vision model measures it (model.c: distance 1 / tan(1°/ppd) px) */
static double pixel_ecc(double x, double y, double gx, double gy, double dist_px) {
  double dx = x - gx, dy = y - gy;
  return atan(sqrt(dx * dx + dy * dy) / dist_px) * 180.0 / M_PI;
}

jnd_status jnd_gaze_geometric_term(const jnd_gaze_model *m, const jnd_image *mask0, const jnd_image *mask_i,
                                   double ppd, double gaze_x, double gaze_y, double *g_deg) {
  *g_deg = 0;
  if (!mask0 || !mask_i || mask0->w != mask_i->w || mask0->h != mask_i->h || mask0->c < 1 || mask_i->c < 1)
    return jnd_fail(JND_ERR_ARG, "gaze: the two silhouettes differ in size");
  if (!(ppd > 0)) return jnd_fail(JND_ERR_ARG, "gaze: pixels per degree must be > 0");
  const int w = mask0->w, h = mask0->h;
  const float *a = mask0->data, *b = mask_i->data;
  const double dist_px = 1.0 / tan(M_PI / 180.0 / ppd);
  double area = 0;   /* Σ w(ecc_p) · A_p over the XOR, A_p in deg² */
  long edges = 0;    /* 4-neighbour edges between S0 and its outside */
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t q = (size_t)y * w + x;
      /* the fraction of the pixel inside exactly one silhouette: with
       * multisampled coverage, |c0 − ci| (a sub-pixel shift of an edge counts) */
      double xor_frac = fabs((double)a[q] - (double)b[q]);
      if (xor_frac > 0) area += xor_frac * jnd_gaze_weight(m, pixel_ecc(x, y, gaze_x, gaze_y, dist_px));
      int in = a[q] > 0.5f;
      int right = x + 1 < w ? a[q + 1] > 0.5f : 0, down = y + 1 < h ? a[q + (size_t)w] > 0.5f : 0;
      if (x == 0) edges += in;
      if (y == 0) edges += in;
      edges += (in != right) + (in != down);
    }
  if (edges == 0) return JND_OK;
  /* the 4-neighbour edge count measures a curve's length in the L1 metric:
   * π/4 of it is the Euclidean length on average over orientations
   * (Cauchy–Crofton), so the perimeter does not depend on how S0 is turned */
  double perimeter_deg = edges * (M_PI / 4.0) / ppd;
  *g_deg = area / (ppd * ppd) / perimeter_deg;
  return JND_OK;
}

/* The pooled JND of two renderings seen with the fixation point at (gx, gy),
 * over the pixels of either silhouette; grey_xor: the XOR region grey in both;
 * temporal_hz > 0: the change seen as a modulation at that frequency. The
 * judge shows both over the background and compares them (mp->judge, or
 * one made for this call). */
jnd_status gaze_pooled_jnd(const jnd_gaze_measure_params *mp, double ppd, double gx, double gy, const jnd_image *a,
                             const jnd_image *ma, const jnd_image *b, const jnd_image *mb, int grey_xor,
                             double temporal_hz, double *out) {
  *out = 0;
  if (a->w != b->w || a->h != b->h || a->c < 3 || b->c < 3 || ma->w != a->w || ma->h != a->h || mb->w != b->w ||
      mb->h != b->h)
    return jnd_fail(JND_ERR_ARG, "gaze: renderings and masks differ in size");
  size_t n = (size_t)a->w * a->h;
  unsigned char *grey = NULL;
  float *vals = jnd_alloc(n, sizeof *vals);
  if (!vals) return JND_ERR_NOMEM;
  if (grey_xor) {
    if (!(grey = jnd_calloc(n, 1))) {
      free(vals);
      return JND_ERR_NOMEM;
    }
    /* 002: the XOR region in the background's grey in both images, so that
     * the shading term sees what the silhouette term does not */
    for (size_t q = 0; q < n; q++) grey[q] = fabsf(ma->data[q] - mb->data[q]) >= 0.25f;
  }
  jnd_pair_judge *own = NULL, *judge = mp->judge;
  jnd_status st = judge ? JND_OK : jnd_pair_judge_create(&mp->model, &own);
  if (!judge) judge = own;
  jnd_pair_view pv = {.ppd = ppd, .has_gaze = 1, .gaze_x = gx, .gaze_y = gy, .temporal_hz = temporal_hz,
                      .background = mp->background, .grey = grey};
  jnd_image jm = {0};
  if (st == JND_OK) st = jnd_pair_judge_compare(judge, a, ma, b, mb, &pv, &jm);
  if (st == JND_OK) {
    size_t k = 0;
    for (size_t q = 0; q < n; q++)
      if (ma->data[q] > 0.5f || mb->data[q] > 0.5f) vals[k++] = jm.data[q];
    *out = k ? jnd_pool(vals, k, &mp->pool, mp->model.minkowski) : 0;
  }
  jnd_image_free(&jm);
  jnd_pair_judge_free(own);
  free(grey);
  free(vals);
  return st;
}

jnd_status jnd_gaze_spatial(const jnd_gaze_model *gm, const jnd_gaze_measure_params *mp, double ppd,
                            double gaze_x, double gaze_y, const jnd_image *ref, const jnd_image *mask0,
                            const jnd_image *lvl, const jnd_image *mask_i, jnd_gaze_terms *out) {
  memset(out, 0, sizeof *out);
  jnd_status st = jnd_gaze_geometric_term(gm, mask0, mask_i, ppd, gaze_x, gaze_y, &out->g_deg);
  if (st == JND_OK) st = gaze_pooled_jnd(mp, ppd, gaze_x, gaze_y, ref, mask0, lvl, mask_i, 1, 0, &out->v_jnd);
  out->p = jnd_gaze_spatial_probability(gm, out->g_deg, out->v_jnd);
  return st;
}

jnd_status jnd_gaze_switch(const jnd_gaze_model *gm, const jnd_gaze_measure_params *mp, double ppd,
                           double gaze_x, double gaze_y, const jnd_image *a, const jnd_image *mask_a,
                           const jnd_image *b, const jnd_image *mask_b, jnd_gaze_terms *out) {
  memset(out, 0, sizeof *out);
  /* 002 eq. 5: the switch is a sudden change, judged by the model's
   * temporal (counterphase) sensitivity, not as a static difference */
  jnd_status st = gaze_pooled_jnd(mp, ppd, gaze_x, gaze_y, a, mask_a, b, mask_b, 0, switch_frequency(mp), &out->t_jnd);
  out->p = jnd_gaze_switch_probability(gm, out->t_jnd);
  return st;
}
