/* Internal pieces of the vision model (004 §3.1), one stage per function. */
#ifndef JND_VISION_H
#define JND_VISION_H

#include <math.h>
#include "core/fastmath.h"
#include "jnd.h"

/* ---- colour (colour.c) ---- */
/* linear Rec.709/sRGB (D65) → CIE XYZ, in place on a 3-channel planar image */
void jnd_rgb_to_xyz(jnd_image *img);
/* CIE XYZ → Hunt–Pointer–Estévez LMS (004 §3.1, matrix from Fairchild 2004), in place */
void jnd_xyz_to_lms(jnd_image *img);
void jnd_rgb_to_lms(jnd_image *img); /* the two above in one pass */
/* the float weights jnd_rgb_to_lms applies, row by row (L = a[0]·R + a[1]·G
 * + a[2]·B, summed in that order; then M, S): for computing the same LMS
 * values from other storage (jnd_model_diff_rgb8) */
void jnd_rgb_to_lms_weights(float a[9]);
/* w pixels of 8-bit R, G, B codes (3 bytes a pixel) to L, M, S rows:
 * each code's value (value[code], the display's luminance), then the
 * weights a of jnd_rgb_to_lms_weights — bit for bit jnd_rgb_to_lms of an
 * image holding value[code] */
void jnd_rgb8_lms_row(const unsigned char *px, const float value[256], const float a[9], float *const out[3],
                      size_t w);

/* jnd_model_diff_consume (include/jnd.h) for two 8-bit RGB images kept as
 * their codes: w × h pixels of R, G, B bytes, row-major, taken over (freed),
 * and lum[v] the display's luminance of code v (jnd_display_code_luminances).
 * The same map, bit for bit, as planes of lum[code] through
 * jnd_model_diff_consume, without the images' float planes (12 bytes a
 * pixel each, 50 MB at 1920 × 1080): the finest level is made from the
 * codes a row at a time where REDUCE and the finest band read it. Where
 * level 0 is read whole (no band, or the adaptation level at level 0: a
 * display of under about 2 pixels a degree) the planes are made first. */
jnd_status jnd_model_diff_rgb8(jnd_model *m, unsigned char *ref, unsigned char *test, int w, int h,
                               const float lum[256], const jnd_diff_inputs *in, jnd_image *jnd_out);
/* jnd_model_diff_rgb8 in two steps, so that each image's pyramids can be
 * made as soon as it is decoded, beside the other's decoding (jnd diff: a
 * thread a file): jnd_model_image_rgb8 takes an image's codes over and
 * makes its pyramids (with `threads` threads; 1 inside a parallel
 * section), jnd_model_diff_images takes two such images over and compares
 * them — the same map, bit for bit. */
typedef struct jnd_model_image jnd_model_image;
jnd_status jnd_model_image_rgb8(const jnd_model *m, unsigned char *rgb, int w, int h, const float lum[256],
                                int threads, jnd_model_image **out);
jnd_status jnd_model_diff_images(jnd_model *m, jnd_model_image *ref, jnd_model_image *test,
                                 const jnd_diff_inputs *in, jnd_image *jnd_out);
/* an image's codes back (the image freed): for a pair whose other image is not 8-bit RGB */
unsigned char *jnd_model_image_codes(jnd_model_image *im);
void jnd_model_image_free(jnd_model_image *im);
/* luminance Y from HPE LMS (the second row of the inverse matrix) */
void jnd_lms_luminance_weights(double w[3]);
/* one colour from HPE LMS back to CIE XYZ (the inverse of the matrix above) */
void jnd_lms_to_xyz_one(const double lms[3], double xyz[3]);
/* The two colour-opponent channels a (red–green) and b (yellow–violet)
 * from LMS contrasts: Hunt's rows (004 §3.1). The achromatic channel is
 * not Hunt's A but the luminance contrast, computed from the cones' terms
 * where they are at hand (model.c image_row; docs/model.md "Channels"). */
static inline void jnd_opponent_colour(float cl, float cm, float cs, float *a, float *b) {
  *a = cl - (12.0f / 11.0f) * cm + (1.0f / 11.0f) * cs;
  *b = (cl + cm - 2.0f * cs) * (1.0f / 9.0f);
}

/* ---- the psychometric function (000 eq. 4), the one definition ---- */
/* P = 1 − exp(ln 0.5 · jnd^β) = 1 − 2^(−jnd^β), with the fast pow so that
 * per-pixel loops vectorise; jnd_probability and every pooling call it. */
static inline float jnd_prob_of_jnd_log2(float j, float l, float beta);
/* ... in two steps, for loops that run each over a block (one pixel's
 * chain of exp2s in one loop is latency-bound: docs/speed.md "Eleventh
 * pass"): jnd^β from the log2, then P from it */
static inline float jnd_prob_power(float l, float beta) { return jnd_fast_exp2(beta * l); }
static inline float jnd_prob_of_power(float j, float jb) { return j > 0 ? 1.0f - jnd_fast_exp2(-jb) : 0.0f; }
static inline float jnd_prob_of_jnd_log2(float j, float l, float beta) {
  return jnd_prob_of_power(j, jnd_prob_power(l, beta));
}
/* the same from j alone; jnd_prob_of_jnd_log2 above takes l =
 * jnd_fast_log2_of(j), for loops that raise j to other powers too
 * (jnd_fast_pow(j, β) is exp2(β · l) where j > 0): the same floats */
static inline float jnd_prob_of_jnd(float j, float beta) { return jnd_prob_of_jnd_log2(j, jnd_fast_log2_of(j), beta); }

/* ---- pyramids (pyramid.c) ---- */
typedef struct {
  int levels;
  int w[24], h[24];
  float *plane[24]; /* level 0 may be borrowed from the caller */
  int own0;
} jnd_gauss;

/* Gaussian pyramid (Burt & Adelson 1983, 5×5 binomial kernel) of one plane,
 * with `levels` levels; level 0 is the plane itself (borrowed). */
jnd_status jnd_gauss_build(jnd_gauss *g, float *plane0, int w, int h, int levels, int threads);
void jnd_gauss_free(jnd_gauss *g);
/* Rows of three planes made on demand: row y of each into out[0..2]. */
typedef void (*jnd_rows3_fn)(void *ctx, int y, float *const out[3]);
/* The pyramids of three w × h planes that are not stored, whose rows
 * row(ctx, …) makes (each row once a thread for all three): level 0 is
 * left NULL, levels 1… are bit for bit jnd_gauss_build's of the planes.
 * constant[c]: plane c holds one value, value[c] (jnd_gauss_build's test). */
jnd_status jnd_gauss_build3_rows(jnd_gauss g[3], jnd_rows3_fn row, void *ctx, int w, int h, int levels,
                                 const int constant[3], const float value[3], int threads);
/* jnd_pyr_reduce of three planes given by their rows */
int jnd_pyr_reduce3_rows(jnd_rows3_fn row, void *ctx, int w, int h, float *const dst[3], int dw, int dh,
                         int threads); /* 0: out of memory */
/* one REDUCE step: blur with the binomial kernel and keep even samples */
int jnd_pyr_reduce(const float *src, int w, int h, float *dst, int dw, int dh, int threads); /* 0: out of memory */
/* one EXPAND step: to (dw, dh) from (w, h), interpolating with 2× the kernel */
int jnd_pyr_expand(const float *src, int w, int h, float *dst, int dw, int dh, int threads); /* 0: out of memory */
/* dst += max(EXPAND(src), 0), pixel by pixel the same as jnd_pyr_expand into a
 * temporary and adding, without the temporary (collapsing a pyramid) */
int jnd_pyr_expand_add(const float *src, int w, int h, float *dst, int dw, int dh, int threads); /* 0: out of memory */
/* the same, then each pixel of dst raised to p (jnd_fast_pow) as its row is
 * done: bit for bit jnd_pyr_expand_add followed by a pass of jnd_fast_pow
 * (the collapse's last level and the map's ^(1/e) without a second pass
 * over the full-resolution plane) */
int jnd_pyr_expand_add_pow(const float *src, int w, int h, float *dst, int dw, int dh, float p, int threads);
/* horizontally expands one coarse row of width cw to width fw */
void jnd_pyr_expand_row(const float *src, int cw, float *dst, int fw);
/* weights and rows of the vertical EXPAND for fine row y: n (2 or 3) rows */
int jnd_pyr_expand_rows(int y, int ch, int rows[3], float wts[3]);
/* The last three coarse rows expanded horizontally (EXPAND's vertical step
 * reads rows c−1, c, c+1, and a row's neighbours share two of them): buf is
 * 3 × the fine width, row[] the coarse row each slot holds (−1: none). */
typedef struct {
  float *buf;
  int row[3];
} jnd_row_cache;
/* coarse row crow of src (cw wide) expanded to width fw, from the cache */
const float *jnd_pyr_cached_row(jnd_row_cache *c, const float *src, int cw, int crow, int fw);
/* Row y of EXPAND(src) (src cw × ch, the expanded image fw wide) into out,
 * src's rows expanded horizontally through the cache c: bit for bit row y
 * of jnd_pyr_expand, without the expanded image. */
void jnd_pyr_expanded_row(jnd_row_cache *c, const float *src, int cw, int ch, int y, float *out, int fw);
static inline int jnd_mirror(int i, int n) {
  if (n == 1) return 0;
  while (i < 0 || i >= n) {
    if (i < 0) i = -i;
    if (i >= n) i = 2 * n - 2 - i;
  }
  return i;
}
/* Peak frequency (cycles/pixel of the full-resolution image) and peak
 * amplitude of contrast band i = G_i − EXPAND(G_{i+1}), measured by passing
 * sinusoids through the same filters (004 §3.1 "Contrast pyramid levels"). */
void jnd_band_response(int band, double *peak_cpp, double *peak_amp);
/* jnd_band_response for bands 0–5 as a table: {peak cycles/pixel, amplitude} */
extern const double jnd_band_table[6][2];

/* ---- CSFs (csf.c) ---- */
/* Barten's spatial CSF (004 §3.1, Barten 2003) */
double jnd_csf_barten(double rho_cpd, double lum_cdm2);
/* Daly's refinement of Kelly's spatio-velocity CSF (004 §3.1), with c0, c1
 * from jnd_csf_adaptation for the luminance and c2 the velocity scale (004: 1.7) */
double jnd_csf_achromatic(double rho_cpd, double vel_dps, double c0, double c1, double c2);
/* c0(L), c1(L) of 004 §3.1 */
void jnd_csf_adaptation(double lum_cdm2, double *c0, double *c1);
/* The spatio-temporal shape of Kelly's (1983) chromatic CSF, centre +
 * surround, at spatial frequency rho_cpd and temporal frequency omega_hz;
 * channel 0 red–green, 1 yellow–violet; the centre falls as
 * exp(−(rho/cutoff_cpd)^tail), temporal_hz is its temporal cut-off
 * (docs/model.md). Peak ≈ 1. */
double jnd_csf_chromatic(double rho_cpd, double omega_hz, int channel, double cutoff_cpd, double tail, double temporal_hz);
/* The chromatic CSF's luminance factor: the square root of the retinal
 * illuminance relative to 35 cd/m² (004 §3.1), turning into Weber's law
 * above sat_td trolands (0: never) */
double jnd_csf_chromatic_luminance(double lum_cdm2, double sat_td);
/* Le Grand's pupil diameter in mm (004 §3.1) */
double jnd_pupil_diameter_mm(double lum_cdm2);

/* ---- motion and eccentricity ---- */
/* Daly's (1998) eye-movement model: retinal velocity from image velocity (004 §3.1) */
double jnd_retinal_velocity(double image_vel_dps);
#define JND_DRIFT_DPS 0.15
/* M(0)/M(e): the inverse cortical magnification relative to the fovea */
double jnd_cortical_magnification(double ecc_deg, double e2_deg);

/* ---- masking ---- */
/* 004 §3.1's transducer T(c) = sign(c)·|c| / (1 + (|c|^0.3)^10)^0.1 on
 * CSF-normalised contrast, taken as its incremental gain at a masker of
 * normalised contrast m. 004 cites Legge (1981) for its sub-Weber power law,
 * discrimination thresholds growing as the masker's contrast to the 0.6
 * (Legge's exponent), but its printed T grows as |c|^0.7, a slope of only
 * 0.3. We keep T's form, T(c) = c / (1 + |c|³)^(γ/3), with γ = masking_slope
 * (default Legge's 0.6; 0.3 is 004 as printed), whose incremental gain is
 *   T′(m) = (1 + (1 − γ) m³) / (1 + m³)^(1 + γ/3):
 * 1 on a uniform field, (1 − γ) m^−γ on a strong masker. The model evaluates
 * it at the mutual masker min(|n_test|, |n_ref|) pooled over the band's
 * neighbourhood (docs/model.md, "Masking"). */
/* its terms a = 1 + (1 − γ) m³ and l = log2(1 + m³) */
static inline void jnd_masker_terms(float m, float slope, float *a, float *l) {
  float m3 = m * m * m;
  *a = 1.0f + (1.0f - slope) * m3;
  *l = jnd_fast_log2(1.0f + m3);
}
static inline float jnd_masking_gain(float m, float slope) {
  float a, l;
  jnd_masker_terms(m, slope, &a, &l);
  return a * jnd_fast_exp2(-(1.0f + slope * (1.0f / 3)) * l);
}

/* The masked difference to the Minkowski exponent, (d · T′(m))^e, in one
 * exp2 instead of the two of jnd_fast_pow(d · jnd_masking_gain(m, γ), e):
 *   e · (log2(d · (1 + (1 − γ) m³)) − (1 + γ/3) · log2(1 + m³)),
 * from the masker's terms a = 1 + (1 − γ) m³ and l = log2(1 + m³)
 * (jnd_masker_terms), which channels pooled by the same masker share. The
 * same equation, rounded differently: within 1e-5 of the two-step value
 * relative (unit.test_vision checks it over the range the model sees;
 * docs/speed.md "Fourth pass"). */
static inline float jnd_masked_pow(float d, float a, float l, float slope, float e) {
  float x = d * a;
  float r = jnd_fast_exp2(e * (jnd_fast_log2(x > 1e-30f ? x : 1e-30f) - (1.0f + slope * (1.0f / 3)) * l));
  return x > 0.0f ? r : 0.0f;
}

/* ---- local summation's box passes (boxsum.c) ---- */
#define JND_BOX_LANES_MAX 64 /* the most lanes of one pass (model.c's BOX_COLS) */
/* One box pass on `lanes` (<= JND_BOX_LANES_MAX) columns at once: input row j
 * (j in [n0, n1), zeros elsewhere) at s + ss·j, output i (i < m, centred on
 * input row from + i) at d + ds·i; weight 1 on the 2r + 1 rows within r of
 * the centre and a on the two at r + 1, normalised to sum 1. The window's
 * sums are block suffixes and prefixes in float, never a running sum's
 * subtraction (boxsum.c). suf: scratch of 2·(2r + 1)·lanes floats. Reads
 * rows from − r − 1 .. from + m + r. */
void jnd_box_pass(const float *s, ptrdiff_t ss, int n0, int n1, float *d, ptrdiff_t ds, int from, int m, int lanes,
                  int r, float a, float *suf);

/* ---- local summation's last step (model.c local_summation) ---- */
/* A pixel's pooled difference (gain · sum)^down, sum its window's sum of
 * j^beta and down = e/beta, capped at bound · j^e (bound = gain^down: where
 * the band has no difference of its own, pooling must not bring in its
 * neighbours'), from d = j^e ... */
static inline float jnd_pooled_capped(float sum, float d, float gain, float down, float bound) {
  float pooled = jnd_fast_pow(sum * gain, down), cap = bound * d;
  return pooled < cap ? pooled : cap;
}
/* ... and the same from d = j^beta, where the cap is (gain · j^beta)^down:
 * (gain · min(sum, j^beta))^down, one pow (no j^e → j^beta pass before the
 * window's sums); within 1e-5 relative of the first (unit.test_vision,
 * docs/speed.md "Fourth pass") */
static inline float jnd_pooled_min(float sum, float dbeta, float gain, float down) {
  return jnd_fast_pow(gain * jnd_minf(sum, dbeta), down);
}

/* ---- CSF-weighted Haar bands of 003 §4.2 (haar.c) ---- */
/* The Mannos–Sakrison CSF as 003 writes it, f in cycles per degree. */
double jnd_csf_mannos_sakrison(double f_cpd);
/* C_m of 003 §4.2: the CSF's mean over Haar level m's band (m >= 1),
 * [ppd/2^(m+1), ppd/2^m] cycles per degree on a display of ppd. */
double jnd_haar_band_weight(int m, double ppd);
/* The orthonormal 2D Haar decomposition of a w × h plane, level by level
 * (odd sides padded with zeros) until one pixel is left or max_levels:
 * energy[m − 1] gets the sum of squares of level m's three detail
 * subbands; rest (may be NULL) the energy of what is left. Returns the
 * number of levels, −1 when out of memory. Parseval: the energies add up to
 * the plane's. */
int jnd_haar_band_energy(const float *plane, int w, int h, double *energy, int max_levels, double *rest);

/* ---- CIELAB and ΔE*94 (deltae.c), for the popping predictor ---- */
/* jnd_delta_e94_map computing only the row blocks where `where` (w × h
 * bytes, NULL: all) has a nonzero byte; the others stay 0, which is their
 * value when `where` marks every pixel whose colours differ. */
jnd_status jnd_delta_e94_map_where(const jnd_display *d, const jnd_image *ref, const jnd_image *test,
                                   const uint8_t *where, jnd_image *out, double *max);

/* ---- the display (display.c) ---- */
/* The luminance (cd/m²) jnd_display_apply gives each 8-bit sRGB code
 * without alpha, bit for bit: an 8-bit RGB file's codes looked up in it
 * (jnd_model_diff_rgb8) leave the display nothing to do.
 * Fails as jnd_display_apply does on the display's luminances. */
jnd_status jnd_display_code_luminances(const jnd_display *d, float lum[256]);

#endif
