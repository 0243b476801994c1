/* The spatio-velocity colour vision model of 004 §3.1 and the difference map
 * of 004 §3.2, stage by stage:
 *
 *   display → XYZ → LMS (HPE) → Gaussian pyramid → contrast pyramid
 *   (G_i − G_{i+1}) / G_{i+2} → opponent A, a, b → CSF normalisation at each
 *   band's measured peak frequency (velocity, adaptation luminance,
 *   eccentricity) → masking transducer T → |T(test) − T(ref)|^2.4 summed over
 *   channels → collapse across bands → ^(1/2.4) → JND map.
 *
 * diff_lms calls them in that order, from LMS on: gaussian_pyramids,
 * adaptation_luminance and csf_velocity (what the CSF is evaluated at),
 * band_differences (contrast, opponent channels, CSF, masking and the
 * difference summed over the channels, band by band: band_difference,
 * baseband_difference), collapse_bands, jnd_map_of.
 *
 * Memory: the two Gaussian pyramids (3 × 4/3 floats a pixel each) are the
 * bulk. Contrast bands are never stored: each band's difference is computed
 * row by row from the Gaussian levels, expanding the coarser levels on the
 * fly, so the peak stays near 40 bytes a pixel. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "core/core.h"
#include "vision/vision.h"

#define MAX_BANDS 16
#define NCH 3                 /* A, a, b */
#define LUT_LOGL0 (-5.0)      /* adaptation luminance 1e-5 .. 1e5 cd/m² */
#define LUT_NL 201
#define LUT_DLOGL 0.05
#define LUT_LOGV0 (-1.0)      /* retinal velocity 0.1 .. 316 deg/s */
#define LUT_NV 71
#define LUT_DLOGV 0.05
#define CONTRAST_FLOOR 1e-4f  /* cd/m²-scale floor of the contrast denominator */
#define BOX_COLS 64           /* columns per block of the vertical box passes */

struct jnd_model {
  jnd_model_params p;
  int nbands;
  double band_cpp[MAX_BANDS];  /* peak frequency, cycles per full-resolution pixel; entry nbands: the baseband */
  double band_amp[MAX_BANDS];  /* peak amplitude of the band's filter */
  double band_cpd[MAX_BANDS];
  int adapt_level;             /* Gaussian level where a pixel is about one degree */
  double lum_w[3];             /* Y from LMS */
  float *lut;                  /* [band][iv][iL][ch, -]: CSF · sensitivity / amplitude, the
                                  channels side by side (one load reads a corner's three), filled
                                  by luminance column on first use (lut_fill) */
  unsigned char lut_done[LUT_NL];
  double c0[LUT_NL], c1[LUT_NL]; /* 004 §3.1's adaptation of the achromatic CSF, per column */
  double lumf[2][LUT_NL];      /* the chromatic CSFs' luminance factors, per column */
  double vgrid[LUT_NV];
};

/* ---- psychometric function (000 eq. 4) ---- */

double jnd_probability(double jnd, double beta) {
  if (!(jnd > 0)) return 0.0;
  return jnd_prob_of_jnd((float)jnd, (float)beta);
}

double jnd_probability_inverse(double p, double beta) {
  if (!(p > 0)) return 0.0;
  if (p >= 1) return INFINITY;
  return pow(log(1.0 - p) / log(0.5), 1.0 / beta);
}

/* ---- model construction ---- */

void jnd_model_defaults(jnd_model_params *p) {
  memset(p, 0, sizeof *p);
  jnd_display_defaults(&p->display);
  p->minkowski = 2.4; /* 004 §3.2 */
  p->masking_slope = 0.6; /* Legge 1981, as 004 §3.1 cites (docs/model.md) */
  p->masking_cross = 1.0; /* one normalisation pool over the three channels (docs/model.md "Masking") */
  p->masking_band_oct = 1.0; /* masking tuned to about ±1 octave (Legge & Foley 1980; docs/model.md "Masking") */
  p->beta = 3.5;      /* 000 eq. 4 */
  p->fps = 60;
  /* Fitted on ../shared/data/csf/csf_train.csv (785 rows, nine data sets)
   * by jnd csf --fit (scripts/fit-model.sh): maximum a posteriori with the
   * priors of constants.c; the comment is one posterior standard deviation.
   * docs/model.md has the procedure and the errors. */
  p->sensitivity = 0.624072; /* ±8% */
  p->sens_rg = 907.842; /* ±22% */
  p->sens_yv = 803.104; /* ±25% */
  p->rg_cutoff_cpd = 1.01758; /* ±44% */
  p->yv_cutoff_cpd = 0.471771; /* ±44% */
  p->chroma_tail = 0.495567; /* ±13% */
  p->chroma_sat_td = 100; /* held at its prior (constants.c): not fitted */
  p->chroma_temporal_hz = 8.92361; /* ±5% */
  p->kelly_c2 = 0.840116; /* ±3% */
  p->flicker_gain = 0.762525; /* ±8% */
  p->eye_velocity_dps = 74.4514; /* ±86% */
  p->summation_area_deg2 = 381.784; /* ±59% */
  p->summation_f0_cpd = 1.25523; /* ±58% */
  p->summation_beta = 3.12089; /* ±8% */
  p->summation_chroma_f0_cpd = 0.0670529; /* ±43% */
  p->summation_chroma_beta = 3.27922; /* ±28% */
  p->ecc_e2_deg = 8.27192; /* ±42% */
  p->ecc_achromatic = 0.285979; /* ±42% */
  p->ecc_rg = 1.46145; /* ±22% */
  p->ecc_yv = 0.791331; /* ±33% */
  p->ecc_freq = 0.056308; /* ±10% */
  p->min_band_cpd = 0.125; /* chosen, not fitted: the lowest frequency in the data */
  p->side_by_side_de00 = 1.0; /* CIE 142-2001: ΔE00 ≈ 1 at the large-field threshold (docs/model.md "Viewing task") */
}

const jnd_model_params *jnd_model_get_params(const jnd_model *m) { return &m->p; }

void jnd_model_set_gaze(jnd_model *m, int has_gaze, double gaze_x, double gaze_y) {
  m->p.has_gaze = has_gaze;
  m->p.gaze_x = gaze_x;
  m->p.gaze_y = gaze_y;
}

int jnd_model_band_peaks(const jnd_model *m, double *cpd, int max) {
  int n = m->nbands < max ? m->nbands : max;
  for (int i = 0; i < n; i++) cpd[i] = m->band_cpd[i];
  return m->nbands;
}

/* LUT_SLOT floats a table entry: the NCH channels and one unused */
#define LUT_SLOT 4
#define LUT_IX(iv, il) (((size_t)(iv) * LUT_NL + (size_t)(il)) * LUT_SLOT)

static float *lut_band(const jnd_model *m, int band) {
  return m->lut + (size_t)band * LUT_NV * LUT_NL * LUT_SLOT;
}

jnd_status jnd_model_create(const jnd_model_params *p, jnd_model **out) {
  *out = NULL;
  jnd_status ds = jnd_display_check(&p->display);
  if (ds != JND_OK) return ds;
  if (!(p->sensitivity > 0) || !(p->sens_rg >= 0) || !(p->sens_yv >= 0))
    return jnd_fail(JND_ERR_ARG, "model: sensitivities must be positive");
  if (!(p->min_band_cpd > 0.01)) return jnd_fail(JND_ERR_ARG, "model: min_band_cpd must be > 0.01");
  if (!(p->summation_area_deg2 >= 0) || !(p->summation_f0_cpd > 0) || !(p->summation_beta >= 1) ||
      !(p->eye_velocity_dps >= 0) || !(p->chroma_sat_td >= 0) || !(p->rg_cutoff_cpd > 0) || !(p->yv_cutoff_cpd > 0) || !(p->chroma_tail > 0) ||
      !(p->chroma_temporal_hz > 0) || !(p->kelly_c2 > 0) || !(p->flicker_gain > 0))
    return jnd_fail(JND_ERR_ARG, "model: summation, eye velocity, saturation, cut-offs and chroma_tail must be positive");
  if (!(p->summation_chroma_f0_cpd >= 0) || !(p->summation_chroma_beta == 0 || p->summation_chroma_beta >= 1))
    return jnd_fail(JND_ERR_ARG, "model: summation_chroma_f0_cpd must be >= 0 and summation_chroma_beta 0 or >= 1");
  if (!(p->ecc_e2_deg > 0) || !(p->ecc_achromatic >= 0) || !(p->ecc_rg >= 0) || !(p->ecc_yv >= 0) ||
      !(p->ecc_freq >= 0))
    return jnd_fail(JND_ERR_ARG, "model: eccentricity constants must be positive");
  if (!(p->masking_slope >= 0 && p->masking_slope < 1))
    return jnd_fail(JND_ERR_ARG, "model: masking_slope must be in [0, 1)");
  if (!(p->masking_cross >= 0 && p->masking_cross <= 1))
    return jnd_fail(JND_ERR_ARG, "model: masking_cross must be in [0, 1]");
  if (!(p->masking_band_oct >= 0 && p->masking_band_oct <= 8))
    return jnd_fail(JND_ERR_ARG, "model: masking_band_oct must be in [0, 8]");
  if (!(p->side_by_side_de00 > 0))
    return jnd_fail(JND_ERR_ARG, "model: side_by_side_de00 must be positive");
  if (!(p->minkowski >= 1) || !(p->beta > 0))
    return jnd_fail(JND_ERR_ARG, "model: Minkowski exponent must be >= 1 and beta > 0");
  jnd_model *m = jnd_calloc(1, sizeof *m);
  if (!m) return JND_ERR_NOMEM;
  m->p = *p;
  double ppd = p->display.ppd;

  /* 004 §3.1: as many bands as keep the coarsest band's peak at >= 0.5 cpd,
   * with each band's actual peak frequency and amplitude taken from the
   * filters (the finest peaks near Nyquist, ~4× the next). Bands from the
   * sixth on are self-similar: each halves the previous one's frequency. */
  int n = 0;
  for (int i = 0; i < MAX_BANDS - 1; i++) {
    if (i <= 5) {
      m->band_cpp[i] = jnd_band_table[i][0];
      m->band_amp[i] = jnd_band_table[i][1];
    } else {
      m->band_cpp[i] = m->band_cpp[i - 1] / 2;
      m->band_amp[i] = m->band_amp[i - 1];
    }
    m->band_cpd[i] = m->band_cpp[i] * ppd;
    if (m->band_cpd[i] < p->min_band_cpd) break;
    n = i + 1;
  }
  if (n == 0) {
    jnd_model_free(m);
    return jnd_fail(JND_ERR_ARG, "model: %g pixels per degree resolves no band above 0.5 cpd", ppd);
  }
  m->nbands = n;
  /* the baseband (docs/model.md) is table entry n: its CSF is taken an
   * octave below the coarsest band's peak; the Gaussian level passes the
   * mean with gain 1 */
  m->band_cpp[n] = m->band_cpp[n - 1] / 2;
  m->band_cpd[n] = m->band_cpp[n] * ppd;
  m->band_amp[n] = 1.0;
  /* 004 §3.1: adaptation from the Gaussian level where one pixel is about one degree */
  m->adapt_level = (int)lround(log2(ppd));
  if (m->adapt_level < 0) m->adapt_level = 0;
  jnd_lms_luminance_weights(m->lum_w);

  /* malloc, not jnd_alloc: lut_fill writes only the columns of the
   * luminances a comparison meets (a few of the 201), in a parallel loop,
   * so the table's 1.6 MB are not populated here — as the first block of a
   * diff that also started the thread team, and the files were read only
   * after it: 20 interleaved runs of the 1080p pair, both images decoded
   * 40.5 ms into the run instead of 44.3, the run 147.4 ms instead of 154.1
   * (medians; docs/speed.md "Eleventh pass") */
  m->lut = malloc(sizeof(float) * (size_t)(n + 1) * LUT_NV * LUT_NL * LUT_SLOT);
  if (!m->lut) {
    jnd_model_free(m);
    return jnd_fail(JND_ERR_NOMEM, "model: out of memory");
  }
  for (int iv = 0; iv < LUT_NV; iv++) m->vgrid[iv] = pow(10.0, LUT_LOGV0 + iv * LUT_DLOGV);
  *out = m;
  return JND_OK;
}

/* Chromatic channel ch's sensitivity (0 red–green, 1 yellow–violet) at
 * spatial frequency rho and temporal frequency omega, before the luminance
 * factor: the channel's scale times Kelly's chromatic CSF with its cut-off */
static double chromatic_sensitivity(const jnd_model_params *p, int ch, double rho, double omega) {
  return (ch ? p->sens_yv : p->sens_rg) *
         jnd_csf_chromatic(rho, omega, ch, ch ? p->yv_cutoff_cpd : p->rg_cutoff_cpd, p->chroma_tail, p->chroma_temporal_hz);
}

/* The CSF tables of luminance columns [il0, il1], those not filled yet: the
 * achromatic CSF from c0(L), c1(L) (Barten-adapted, 004 §3.1), the chromatic
 * CSFs as a spatio-temporal shape (temporal frequency ω = ρ·v) times their
 * luminance factor, each divided by the band's amplitude. A model fills the
 * columns an image's adaptation luminances need, so that making a model
 * costs nothing per luminance it never sees. */
static void lut_fill(jnd_model *m, int il0, int il1) {
  const jnd_model_params *p = &m->p;
  il0 = jnd_clampi(il0, 0, LUT_NL - 1);
  il1 = jnd_clampi(il1, 0, LUT_NL - 1);
  int todo[LUT_NL], nt = 0;
  for (int il = il0; il <= il1; il++)
    if (!m->lut_done[il]) todo[nt++] = il;
  if (nt == 0) return;
  const int n = m->nbands + 1; /* the bands and the baseband */
  const int threads = jnd_threads(p->threads);
  for (int k = 0; k < nt; k++) {
    int il = todo[k];
    double L = pow(10.0, LUT_LOGL0 + il * LUT_DLOGL);
    jnd_csf_adaptation(L, &m->c0[il], &m->c1[il]);
    for (int ch = 0; ch < 2; ch++) m->lumf[ch][il] = jnd_csf_chromatic_luminance(L, p->chroma_sat_td);
  }
  /* the sweep of fixational eye movements from velocity index iv reaches
   * index jmax[iv] (nondecreasing in iv), so each column's window maxima
   * come from one monotone deque */
  int jmax[LUT_NV];
  for (int iv = 0; iv < LUT_NV; iv++) {
    double vmax = m->vgrid[iv] + p->eye_velocity_dps;
    int j = iv;
    while (j + 1 < LUT_NV && m->vgrid[j + 1] <= vmax * 1.0001) j++;
    jmax[iv] = j;
  }
#pragma omp parallel for collapse(2) num_threads(threads) schedule(static)
  for (int b = 0; b < n; b++) {
    for (int k = 0; k < nt; k++) {
      const int il = todo[k];
      const double rho = m->band_cpd[b], amp = m->band_amp[b];
      float col[NCH][LUT_NV];
      for (int iv = 0; iv < LUT_NV; iv++) {
        double v = m->vgrid[iv];
        col[0][iv] = (float)(p->sensitivity * jnd_csf_achromatic(rho, v, m->c0[il], m->c1[il], p->kelly_c2) / amp);
        for (int ch = 0; ch < 2; ch++)
          col[1 + ch][iv] = (float)(chromatic_sensitivity(p, ch, rho, rho * v) * m->lumf[ch][il] / amp);
      }
      /* Fixational eye movements (our extension, docs/model.md): drift and
       * microsaccades sweep the retinal velocity from v up to v + eye_velocity,
       * and a pattern is seen at the most favourable velocity of that sweep.
       * Kelly's surface is measured on stabilised images, whose low
       * frequencies fade; this restores natural viewing's low-frequency
       * sensitivity while high frequencies, best seen at low velocity, keep
       * 004's values. */
      for (int ch = 0; ch < NCH; ch++) {
        float *t = lut_band(m, b) + ch;
        if (p->eye_velocity_dps <= 0) {
          for (int iv = 0; iv < LUT_NV; iv++) t[LUT_IX(iv, il)] = col[ch][iv];
          continue;
        }
        int dq[LUT_NV], head = 0, tail = 0, next = 0; /* dq[head, tail): indices, values decreasing */
        for (int iv = 0; iv < LUT_NV; iv++) {
          for (; next <= jmax[iv]; next++) {
            while (tail > head && col[ch][dq[tail - 1]] <= col[ch][next]) tail--;
            dq[tail++] = next;
          }
          while (dq[head] < iv) head++;
          /* the sweep's end v + eye_velocity lies between grid points: the
           * CSF there, interpolated in log velocity, is a candidate too (so
           * that the table changes smoothly with eye_velocity) */
          float best = col[ch][dq[head]];
          const int j = jmax[iv];
          if (j + 1 < LUT_NV) {
            double f = (log10(m->vgrid[iv] + p->eye_velocity_dps) - (LUT_LOGV0 + j * LUT_DLOGV)) / LUT_DLOGV;
            f = jnd_clampd(f, 0, 1);
            best = jnd_maxf(best, (float)((1 - f) * col[ch][j] + f * col[ch][j + 1]));
          }
          t[LUT_IX(iv, il)] = best;
        }
      }
    }
  }
  for (int k = 0; k < nt; k++) m->lut_done[todo[k]] = 1;
}

void jnd_model_free(jnd_model *m) {
  if (!m) return;
  free(m->lut);
  free(m);
}

/* ---- per-comparison state ---- */

typedef struct {
  jnd_gauss g[2][3]; /* [image][L, M, S] */
  float *adapt[2];   /* luminance at the adaptation level, per image */
  float *adapt_mid;  /* their mean, the baseband's adaptation */
  int aw, ah, alev;
  int uniform[2];    /* 1: the image is one colour, so its contrast bands are exactly 0 */
  jnd_gauss vel[2];  /* retinal velocity pyramid (deg/s) per image, when motion is given */
  int has_vel;
  int vel_shared;    /* 1: both images move alike, vel[1] is vel[0] */
  float uniform_v;   /* retinal velocity when there is no map */
  double temporal_hz; /* > 0: the difference is a temporal modulation at this frequency */
  int il0, il1;      /* the CSF table columns the adaptation luminances need */
  /* An image kept as its 8-bit RGB codes (jnd_model_diff_rgb8), or NULL:
   * its level 0 (g[a][c].plane[0] NULL) is made a row at a time from the
   * codes (rgb8_rows) where REDUCE and the finest band read it, never
   * stored (12 bytes a pixel less) */
  unsigned char *rgb[2];
  float code_lum[2][256]; /* the display's luminance of each code, per image */
  float rgb_lms[9];       /* jnd_rgb_to_lms_weights */
} diff_state;

/* Bilinear sampling of the coarse adaptation map at the centres of a level's
 * pixels: indices and weights per column and per row, computed once. */
typedef struct {
  int *i0, *i1;
  float *t;
  int nrun, *run; /* runs of equal (i0, i1): run[k] .. run[k + 1] − 1 */
} interp_axis;

static int axis_init(interp_axis *a, int n, int coarse_n, double scale) {
  a->i0 = malloc(sizeof(int) * (size_t)n);
  a->i1 = malloc(sizeof(int) * (size_t)n);
  a->t = malloc(sizeof(float) * (size_t)n);
  a->run = malloc(sizeof(int) * ((size_t)n + 1));
  if (!a->i0 || !a->i1 || !a->t || !a->run) return 0;
  a->nrun = 0;
  for (int k = 0; k < n; k++) {
    double f = (k + 0.5) * scale - 0.5;
    int k0 = (int)floor(f);
    a->t[k] = (float)(f - k0);
    a->i0[k] = jnd_clampi(k0, 0, coarse_n - 1);
    a->i1[k] = jnd_clampi(k0 + 1, 0, coarse_n - 1);
    if (k == 0 || a->i0[k] != a->i0[k - 1] || a->i1[k] != a->i1[k - 1]) a->run[a->nrun++] = k;
  }
  a->run[a->nrun] = n;
  return 1;
}

static void axis_free(interp_axis *a) {
  free(a->i0);
  free(a->i1);
  free(a->t);
  free(a->run);
}

/* CSF look-up: bilinear in log luminance and log velocity, the three
 * channels at once (a corner's entries are side by side). */
typedef float lut_v4 __attribute__((vector_size(16)));

static inline lut_v4 lut_lookup(const float *t, float logL, float logv) {
  float fl = (logL - (float)LUT_LOGL0) * (float)(1.0 / LUT_DLOGL);
  float fv = (logv - (float)LUT_LOGV0) * (float)(1.0 / LUT_DLOGV);
  fl = jnd_minf(jnd_maxf(fl, 0), LUT_NL - 1.001f);
  fv = jnd_minf(jnd_maxf(fv, 0), LUT_NV - 1.001f);
  int il = (int)fl, iv = (int)fv;
  float tl = fl - (float)il, tv = fv - (float)iv;
  const float *e = t + LUT_IX(iv, il);
  lut_v4 c00, c01, c10, c11;
  memcpy(&c00, e, sizeof c00);
  memcpy(&c01, e + LUT_SLOT, sizeof c01);
  memcpy(&c10, e + LUT_NL * LUT_SLOT, sizeof c10);
  memcpy(&c11, e + (LUT_NL + 1) * LUT_SLOT, sizeof c11);
  return (1 - tv) * ((1 - tl) * c00 + tl * c01) + tv * ((1 - tl) * c10 + tl * c11);
}

/* What every row of one band reads. */
typedef struct {
  const jnd_model *m;
  const diff_state *st;
  int band, w, h, w1;
  int unmasked;         /* 1: one image is uniform, so the mutual masker is 0 */
  const float *lut;     /* the band's CSF tables over (velocity, luminance), with a motion map */
  float lut1[LUT_NL][4];   /* the tables at the one retinal velocity, without: [iL][A, a, b, -] */
  interp_axis ax, ay;   /* bilinear sampling of the adaptation map */
  double scale;         /* full-resolution pixels per pixel of this level */
  double dist_px;       /* viewing distance in pixels (eccentricity on a flat screen) */
  float *ecc_tab;       /* with a fixation point: [ch][i] the eccentricity factors at i/ECC_STEPS
                           level pixels from it, i < ecc_n */
  int ecc_n;
  float e;              /* Minkowski exponent */
  float e0;             /* the achromatic term's exponent in D: e, or with Dc the summation's beta
                           (summation_levels: D is pooled over its window next, which takes it to
                           beta first) */
  float lum_w[2];       /* Y's weights on L and M (S's, −6e-6, is left out) */
  const float *coarse_mask[NCH]; /* the next coarser band's pooled maskers (at level band + 1), or NULL */
  float coarse_w;       /* their weight in this band's masking pool (band_masking_weight) */
  float *mask_out[NCH]; /* this band's pooled maskers for the next finer band, or NULL */
  float *Dc;            /* the chromatic channels' difference, summed apart from the achromatic
                           one (chroma_summation_apart), or NULL: all three into D */
} band_ctx;

/* One thread's rows: caches of expanded coarse rows and the row stages. */
typedef struct {
  jnd_row_cache cache[2][3][2]; /* [image][cone][G_{i+1}, EXPAND(G_{i+2})] */
  jnd_row_cache g2[2][3]; /* rows of G_{i+2} expanded horizontally to level i+1 */
  float *xrow;            /* a row of EXPAND(G_{i+2}) at level i+1 */
  float *opp[2][3], *logl, *logv, *sens[NCH], *eccf[NCH];
  int *lix;            /* the CSF table column of each pixel (sens_row) */
  float *mask[5][NCH]; /* ring of 5 rows: the mutual masker, pooled along the row */
  float *dif[3][NCH];  /* ring of 3 rows: |n_test − n_ref| per channel */
  float *pooled[NCH];  /* the maskers of the row being finished, pooled in 5 × 5 */
  jnd_row_cache coarse[NCH]; /* rows of the coarser band's maskers, expanded to this level */
  float *ylum[2];      /* the luminance contrast's numerator and denominator (image_row) */
  float *l0[3];        /* a row of level 0's L, M, S, made from an image's codes (rgb8_rows) */
  float *tmp;
  float *mem;
  float dc_max;        /* the largest value written to Dc by these rows (note_dc_max) */
} row_scratch;

static int scratch_init(row_scratch *r, int w) {
  /* 12 caches × 3 rows; 6 caches × 3 rows of G_{i+2} and a row of its EXPAND; opponent values (2 × 3), log adaptation and log velocity (2), sensitivities
   * (3), eccentricity factors (3), masker ring (5 × 3), difference ring (3 × 3), pooled maskers (3),
   * 3 caches × 3 rows of the coarser band's maskers, the CSF table columns, the luminance contrast's
   * two terms, level 0's three cones, one row of scratch */
  _Static_assert(sizeof(int) == sizeof(float), "the column indices share the float scratch");
  r->mem = malloc(sizeof(float) * (size_t)w * (36 + 18 + 1 + 6 + 2 + 3 + 3 + 15 + 9 + 3 + 9 + 1 + 2 + 3 + 1));
  if (!r->mem) return 0;
  float *p = r->mem;
  for (int a = 0; a < 2; a++)
    for (int c = 0; c < 3; c++) {
      r->g2[a][c].buf = p;
      p += (size_t)3 * w;
      r->g2[a][c].row[0] = r->g2[a][c].row[1] = r->g2[a][c].row[2] = -1;
    }
  r->xrow = p, p += w;
  for (int a = 0; a < 2; a++)
    for (int c = 0; c < 3; c++)
      for (int k = 0; k < 2; k++) {
        r->cache[a][c][k].buf = p;
        p += (size_t)3 * w;
        r->cache[a][c][k].row[0] = r->cache[a][c][k].row[1] = r->cache[a][c][k].row[2] = -1;
      }
  for (int a = 0; a < 2; a++)
    for (int c = 0; c < 3; c++) r->opp[a][c] = p, p += w;
  r->logl = p, p += w;
  r->logv = p, p += w;
  for (int c = 0; c < NCH; c++) r->sens[c] = p, p += w;
  for (int c = 0; c < NCH; c++) r->eccf[c] = p, p += w;
  for (int k = 0; k < 5; k++)
    for (int c = 0; c < NCH; c++) r->mask[k][c] = p, p += w;
  for (int k = 0; k < 3; k++)
    for (int c = 0; c < NCH; c++) r->dif[k][c] = p, p += w;
  for (int c = 0; c < NCH; c++) r->pooled[c] = p, p += w;
  for (int c = 0; c < NCH; c++) {
    r->coarse[c].buf = p;
    p += (size_t)3 * w;
    r->coarse[c].row[0] = r->coarse[c].row[1] = r->coarse[c].row[2] = -1;
  }
  r->lix = (int *)(void *)p, p += w;
  r->ylum[0] = p, p += w;
  r->ylum[1] = p, p += w;
  for (int c = 0; c < 3; c++) r->l0[c] = p, p += w;
  r->tmp = p;
  return 1;
}

/* The CSF value of every pixel of row y of this band, per channel, into
 * r->sens: the adaptation luminance (log10) sampled bilinearly from the
 * level where a pixel is about one degree (004 §3.1), the tables at the
 * band's peak frequency (at image vimg's retinal velocity with a motion
 * map), and the eccentricity factors of r->eccf when there is a fixation
 * point. */
JND_HOT static void sens_row(const band_ctx *k, row_scratch *r, const float *adapt, int vimg, int y) {
  const diff_state *st = k->st;
  const int w = k->w, band = k->band;
  float *ll = r->logl;
  const float *ar0 = adapt + (size_t)k->ay.i0[y] * st->aw, *ar1 = adapt + (size_t)k->ay.i1[y] * st->aw;
  const float ty = k->ay.t[y];
  const float *t = k->ax.t;
  /* along runs of pixels between the same two coarse columns, so that the
   * inner loop has no indexed loads */
  for (int q = 0; q < k->ax.nrun; q++) {
    const int xa = k->ax.run[q], xb = k->ax.run[q + 1], j0 = k->ax.i0[xa], j1 = k->ax.i1[xa];
    const float a00 = ar0[j0], a01 = ar0[j1], a10 = ar1[j0], a11 = ar1[j1];
#pragma omp simd
    for (int x = xa; x < xb; x++) {
      float tx = t[x];
      ll[x] = (1 - ty) * ((1 - tx) * a00 + tx * a01) + ty * ((1 - tx) * a10 + tx * a11);
    }
  }
#pragma omp simd
  for (int x = 0; x < w; x++) ll[x] = jnd_fast_log2(jnd_maxf(ll[x], 1e-6f)) * 0.30103f;
  /* CSF normalisation at the band's peak frequency (004 §3.1) */
  float *s0 = r->sens[0], *s1 = r->sens[1], *s2 = r->sens[2];
  if (st->has_vel) {
    const float *vr = st->vel[vimg].plane[band] + (size_t)y * w;
    float *lv = r->logv;
#pragma omp simd
    for (int x = 0; x < w; x++) lv[x] = jnd_fast_log2(jnd_maxf(vr[x], 1e-3f)) * 0.30103f;
    for (int x = 0; x < w; x++) {
      lut_v4 v = lut_lookup(k->lut, ll[x], lv[x]);
      s0[x] = v[0];
      s1[x] = v[1];
      s2[x] = v[2];
    }
  } else {
    /* Linear in log luminance: each pixel's column and weight in a
     * vectorised pass (the weights in logv's row, unused without a motion
     * map), then the interpolation */
    int *ix = r->lix;
    float *tl = r->logv;
#pragma omp simd
    for (int x = 0; x < w; x++) {
      float fl = (ll[x] - (float)LUT_LOGL0) * (float)(1.0 / LUT_DLOGL);
      fl = jnd_minf(jnd_maxf(fl, 0), LUT_NL - 1.001f);
      /* floorf, not (int) then back: GCC turns that pair into a branch that
       * stops the loop vectorising (the same values: fl >= 0) */
      const float f = floorf(fl);
      ix[x] = (int)f;
      tl[x] = fl - f;
    }
    /* The adaptation map is coarse, so neighbouring pixels mostly share a
     * column: along each run of one column its entries are held and the run
     * interpolated in a vectorised loop (the same arithmetic, pixel by
     * pixel, as one look-up each). */
    const float(*l)[4] = k->lut1; /* the three channels' entries side by side */
    for (int x0 = 0, x1; x0 < w; x0 = x1) {
      const int i = ix[x0];
      for (x1 = x0 + 1; x1 < w && ix[x1] == i; x1++) {}
      const float e0 = l[i][0], e1 = l[i][1], e2 = l[i][2];
      const float d0 = l[i + 1][0] - e0, d1 = l[i + 1][1] - e1, d2 = l[i + 1][2] - e2;
#pragma omp simd
      for (int x = x0; x < x1; x++) {
        s0[x] = e0 + tl[x] * d0;
        s1[x] = e1 + tl[x] * d1;
        s2[x] = e2 + tl[x] * d2;
      }
    }
  }
  if (k->m->p.has_gaze)
    for (int c = 0; c < NCH; c++) {
      float *sc = r->sens[c];
      const float *ef = r->eccf[c];
#pragma omp simd
      for (int x = 0; x < w; x++) sc[x] *= ef[x];
    }
}

#define ECC_STEPS 4 /* table entries per pixel of distance */

/* The eccentricity factors of a band (jnd_eccentricity_factor) as a table
 * over the distance from the fixation point in this level's pixels, a
 * quarter pixel apart: eccentricity on a flat screen seen from the distance
 * the ppd implies, the factors as exponentials of log M(0)/M(e) and of e.
 * Rows then interpolate it (ecc_row), not an atan, a log and three exps a
 * pixel. */
static jnd_status ecc_table(band_ctx *k) {
  const jnd_model_params *p = &k->m->p;
  const double rho = k->m->band_cpd[k->band];
  /* the farthest corner of the level from the fixation point */
  double gx = (p->gaze_x + 0.5) / k->scale - 0.5, gy = (p->gaze_y + 0.5) / k->scale - 0.5;
  double dx = fmax(fabs(gx), fabs(k->w - 1 - gx)), dy = fmax(fabs(gy), fabs(k->h - 1 - gy));
  k->ecc_n = (int)ceil(sqrt(dx * dx + dy * dy) * ECC_STEPS) + 2;
  k->ecc_tab = malloc(sizeof(float) * 3 * (size_t)k->ecc_n);
  if (!k->ecc_tab) return jnd_fail(JND_ERR_NOMEM, "model: out of memory");
  for (int i = 0; i < k->ecc_n; i++) {
    double d = (double)i / ECC_STEPS * k->scale; /* full-resolution pixels */
    double ecc = atan(d / k->dist_px) * 180.0 / M_PI;
    double lm = log(jnd_cortical_magnification(ecc, p->ecc_e2_deg)), f = -p->ecc_freq * rho * ecc;
    k->ecc_tab[i] = (float)exp(f - p->ecc_achromatic * lm);
    k->ecc_tab[k->ecc_n + i] = (float)exp(f - p->ecc_rg * lm);
    k->ecc_tab[2 * k->ecc_n + i] = (float)exp(f - p->ecc_yv * lm);
  }
  return JND_OK;
}

/* The eccentricity factors of row y into r->eccf, from the band's table:
 * the distances in a vectorised pass (into eccf[0]), the table look-ups in
 * a scalar one */
JND_HOT static void ecc_row(const band_ctx *k, row_scratch *r, int y) {
  const jnd_model_params *p = &k->m->p;
  const float gx = (float)((p->gaze_x + 0.5) / k->scale - 0.5), fy = (float)(y - ((p->gaze_y + 0.5) / k->scale - 0.5));
  const float lim = (float)(k->ecc_n - 2) + 0.999f;
  float *u = r->eccf[0];
#pragma omp simd
  for (int x = 0; x < k->w; x++) {
    float fx = (float)x - gx;
    u[x] = jnd_minf(sqrtf(fx * fx + fy * fy) * ECC_STEPS, lim);
  }
  const float *t0 = k->ecc_tab, *t1 = t0 + k->ecc_n, *t2 = t1 + k->ecc_n;
  for (int x = 0; x < k->w; x++) {
    int i = (int)u[x];
    float t = u[x] - (float)i;
    r->eccf[0][x] = t0[i] + t * (t0[i + 1] - t0[i]);
    r->eccf[1][x] = t1[i] + t * (t1[i + 1] - t1[i]);
    r->eccf[2][x] = t2[i] + t * (t2[i + 1] - t2[i]);
  }
}

/* Row crow of EXPAND(G_{i+2}) at level i+1 expanded once more to level i,
 * from the row cache: EXPAND(G_{i+2}) is made a row at a time as the rows
 * ask for it (jnd_pyr_expanded_row), never as a plane — the same values as
 * the six planes of level i+1 it used to be (12 MB at the finest band). */
static const float *expanded_row(const band_ctx *k, row_scratch *r, int a, int c, int crow) {
  jnd_row_cache *q = &r->cache[a][c][1];
  const int slot = crow % 3;
  float *dst = q->buf + (size_t)slot * k->w;
  if (q->row[slot] != crow) {
    const jnd_gauss *g = &k->st->g[a][c];
    const int b2 = k->band + 2;
    jnd_pyr_expanded_row(&r->g2[a][c], g->plane[b2], g->w[b2], g->h[b2], crow, r->xrow, k->w1);
    jnd_pyr_expand_row(r->xrow, k->w1, dst, k->w);
    q->row[slot] = crow;
  }
  return dst;
}

/* How many rows ahead local summation's column blocks ask for their rows'
 * cache lines (prefetch_span): a row of a block is 4 lines, its work about
 * a hundred cycles, a line from memory several hundred (docs/speed.md,
 * "Ninth pass") */
#define PREFETCH_ROWS 8

/* asks for the cache lines of n floats at p (for writing: write) */
static inline void prefetch_span(const float *p, size_t n, int write) {
  for (size_t i = 0; i < n; i += 16) {
    if (write)
      __builtin_prefetch(p + i, 1, 3);
    else
      __builtin_prefetch(p + i, 0, 3);
  }
}

/* row y of image a's level 0 (L, M, S) from its codes */
static void rgb8_rows(const diff_state *st, int a, int y, float *const out[3]) {
  const size_t w = (size_t)st->g[a][0].w[0];
  jnd_rgb8_lms_row(st->rgb[a] + (size_t)y * 3 * w, st->code_lum[a], st->rgb_lms, out, w);
}

/* one image's CSF-normalised contrasts on row y: opp[a][A, a, b] */
JND_HOT static void image_row(const band_ctx *k, row_scratch *r, int a, int y, const int rows[3], const float wts[3]) {
  const diff_state *st = k->st;
  const int w = k->w, w1 = k->w1, band = k->band;
  /* the achromatic channel's band-limited luminance contrast: numerator
   * and denominator summed from the L and M cones' terms with Y's weights
   * (docs/model.md "Channels") */
  float *yn = r->ylum[0], *yd = r->ylum[1];
  /* level 0 of an image kept as codes: its three cones' row made here */
  const int from_codes = !st->g[a][0].plane[band];
  if (from_codes) rgb8_rows(st, a, y, r->l0);
  /* 004 §3.1: band-limited contrast (G_i − G_{i+1}) / G_{i+2} (Lubin 1995), per cone */
  for (int c = 0; c < 3; c++) {
    const float *g0 = from_codes ? r->l0[c] : st->g[a][c].plane[band] + (size_t)y * w;
    const float *p0 = jnd_pyr_cached_row(&r->cache[a][c][0], st->g[a][c].plane[band + 1], w1, rows[0], w);
    const float *p1 = jnd_pyr_cached_row(&r->cache[a][c][0], st->g[a][c].plane[band + 1], w1, rows[1], w);
    const float *p2 = jnd_pyr_cached_row(&r->cache[a][c][0], st->g[a][c].plane[band + 1], w1, rows[2], w);
    const float *q0 = expanded_row(k, r, a, c, rows[0]);
    const float *q1 = expanded_row(k, r, a, c, rows[1]);
    const float *q2 = expanded_row(k, r, a, c, rows[2]);
    float *o = r->opp[a][c];
    const float w0 = wts[0], w1_ = wts[1], w2 = wts[2];
    const float wc = c < 2 ? k->lum_w[c] : 0.0f; /* S's weight in Y is left out */
#pragma omp simd
    for (int x = 0; x < w; x++) {
      float s1 = w0 * p0[x] + w1_ * p1[x] + w2 * p2[x];
      float s2 = w0 * q0[x] + w1_ * q1[x] + w2 * q2[x];
      o[x] = (g0[x] - s1) / jnd_maxf(s2, CONTRAST_FLOOR);
      yn[x] = (c ? yn[x] : 0.0f) + wc * (g0[x] - s1);
      yd[x] = (c ? yd[x] : 0.0f) + wc * s2;
    }
  }
  /* the opponent channels (docs/model.md "Channels"), each normalised by
   * its CSF (one pass for both) */
  sens_row(k, r, st->adapt[a], a, y);
  float *o0 = r->opp[a][0], *o1 = r->opp[a][1], *o2 = r->opp[a][2];
  const float *s0 = r->sens[0], *s1 = r->sens[1], *s2 = r->sens[2];
#pragma omp simd
  for (int x = 0; x < w; x++) {
    float ca, cb;
    jnd_opponent_colour(o0[x], o1[x], o2[x], &ca, &cb);
    o0[x] = yn[x] / jnd_maxf(yd[x], CONTRAST_FLOOR) * s0[x];
    o1[x] = ca * s1[x];
    o2[x] = cb * s2[x];
  }
}

/* the pyramid's binomial kernel (1 4 6 4 1)/16 along a row, mirrored ends */
JND_HOT static void binomial_row(const float *s, float *d, int w) {
  if (w < 5) {
    for (int x = 0; x < w; x++)
      d[x] = (s[jnd_mirror(x - 2, w)] + 4 * s[jnd_mirror(x - 1, w)] + 6 * s[x] + 4 * s[jnd_mirror(x + 1, w)] +
              s[jnd_mirror(x + 2, w)]) * (1.0f / 16);
    return;
  }
  d[0] = (6 * s[0] + 8 * s[1] + 2 * s[2]) * (1.0f / 16);
  d[1] = (4 * s[0] + 7 * s[1] + 4 * s[2] + s[3]) * (1.0f / 16);
#pragma omp simd
  for (int x = 2; x < w - 2; x++) d[x] = (s[x - 2] + 4 * s[x - 1] + 6 * s[x] + 4 * s[x + 1] + s[x + 2]) * (1.0f / 16);
  d[w - 2] = (s[w - 4] + 4 * s[w - 3] + 7 * s[w - 2] + 4 * s[w - 1]) * (1.0f / 16);
  d[w - 1] = (2 * s[w - 3] + 8 * s[w - 2] + 6 * s[w - 1]) * (1.0f / 16);
}

/* Both images' normalised contrasts on row y, then per channel the
 * difference |n_test − n_ref| into dif and, where mask is given, the mutual
 * masker min(|n_test|, |n_ref|) pooled along the row into mask. */
JND_HOT static void response_row(const band_ctx *k, row_scratch *r, int y, float *const dif[NCH], float *const mask[NCH]) {
  const diff_state *st = k->st;
  const int w = k->w, h1 = st->g[0][0].h[k->band + 1];
  int rows[3];
  float wts[3] = {0, 0, 0};
  int nr = jnd_pyr_expand_rows(y, h1, rows, wts);
  if (nr == 2) rows[2] = rows[1]; /* weight 0: any valid row */
  if (k->m->p.has_gaze) ecc_row(k, r, y);
  for (int a = 0; a < 2; a++) {
    if (st->uniform[a]) {
      /* a uniform image has no contrast: its response is 0 */
      for (int c = 0; c < 3; c++) memset(r->opp[a][c], 0, sizeof(float) * (size_t)w);
      continue;
    }
    image_row(k, r, a, y, rows, wts);
  }
  for (int c = 0; c < NCH; c++) {
    const float *nr_ = r->opp[0][c], *nt = r->opp[1][c];
    float *d = dif[c];
#pragma omp simd
    for (int x = 0; x < w; x++) d[x] = fabsf(nt[x] - nr_[x]);
    if (!mask) continue;
    float *m = r->tmp;
#pragma omp simd
    for (int x = 0; x < w; x++) m[x] = jnd_minf(fabsf(nt[x]), fabsf(nr_[x]));
    binomial_row(m, mask[c], w);
  }
}

/* Adds the next coarser band's pooled maskers, expanded to row y of this
 * band's level and weighted by k->coarse_w, to the row's own (r->pooled):
 * the masking pool spans neighbouring frequencies (docs/model.md
 * "Masking"). */
JND_HOT static void add_coarse_maskers(const band_ctx *k, row_scratch *r, int y, const float *const own[NCH]) {
  const diff_state *st = k->st;
  const int w = k->w, w1 = k->w1, h1 = st->g[0][0].h[k->band + 1];
  int rows[3];
  float wts[3] = {0, 0, 0};
  int nr = jnd_pyr_expand_rows(y, h1, rows, wts);
  if (nr == 2) rows[2] = rows[1]; /* weight 0: any valid row */
  for (int c = 0; c < NCH; c++) {
    const float *c0 = jnd_pyr_cached_row(&r->coarse[c], k->coarse_mask[c], w1, rows[0], w);
    const float *c1 = jnd_pyr_cached_row(&r->coarse[c], k->coarse_mask[c], w1, rows[1], w);
    const float *c2 = jnd_pyr_cached_row(&r->coarse[c], k->coarse_mask[c], w1, rows[2], w);
    const float a0 = k->coarse_w * wts[0], a1 = k->coarse_w * wts[1], a2 = k->coarse_w * wts[2];
    const float *o = own[c];
    float *mp = r->pooled[c];
#pragma omp simd
    for (int x = 0; x < w; x++) mp[x] = o[x] + (a0 * c0[x] + a1 * c1[x] + a2 * c2[x]);
  }
}

/* Row crow of Dc, just written, into the rows' largest value: what
 * local_summation's test for a negligible chromatic level reads, found
 * while the row is in cache rather than in a pass over the plane (the
 * same comparison, so the same value) */
static void note_dc_max(row_scratch *r, const float *crow, int w) {
  float mx = r->dc_max;
#pragma omp simd reduction(max : mx)
  for (int x = 0; x < w; x++) mx = crow[x] > mx ? crow[x] : mx;
  r->dc_max = mx;
}

/* A pixel's three channels' terms into D, or the achromatic one into D and
 * the chromatic ones into Dc when they are summed apart (crow non-NULL) */
static inline void put_channels(float *drow, float *crow, int x, float p0, float p1, float p2) {
  if (crow) {
    drow[x] = p0;
    crow[x] = p1 + p2;
  } else {
    drow[x] = p0 + p1 + p2;
  }
}

/* Rows [y0, y1) of band i's difference, summed over channels:
 *   D_i = Σ_ch (|n_test − n_ref| · T′(m))^e
 * with n the CSF-normalised contrasts and m the mutual masker
 * min(|n_test|, |n_ref|) pooled with the pyramid's 5 × 5 binomial kernel,
 * plus the next coarser band's (004's transducer T, taken as its
 * incremental gain at the masker: see jnd_masking_gain). Rows are computed in order with rings of the last five
 * maskers and three differences, so that a row's vertical pooling reads
 * rows computed just before; a chunk recomputes the two rows either side of
 * it, and a row's value does not depend on the chunking. */
JND_HOT static void band_rows(const band_ctx *k, row_scratch *r, int y0, int y1, float *D) {
  const int w = k->w, h = k->h;
  const float e = k->e;
  if (k->unmasked) {
    /* one image is uniform: its contrast, and so the mutual masker, is 0 */
    for (int y = y0; y < y1; y++) {
      response_row(k, r, y, r->dif[0], NULL);
      float *drow = D + (size_t)y * w;
      const float *d0 = r->dif[0][0], *d1 = r->dif[0][1], *d2 = r->dif[0][2];
      if (k->Dc) {
        float *crow = k->Dc + (size_t)y * w;
#pragma omp simd
        for (int x = 0; x < w; x++) {
          drow[x] = jnd_fast_pow(d0[x], k->e0);
          crow[x] = jnd_fast_pow(d1[x], e) + jnd_fast_pow(d2[x], e);
        }
        note_dc_max(r, crow, w);
      } else {
#pragma omp simd
        for (int x = 0; x < w; x++) drow[x] = jnd_fast_pow(d0[x], e) + jnd_fast_pow(d1[x], e) + jnd_fast_pow(d2[x], e);
      }
    }
    return;
  }
  const float slope = (float)k->m->p.masking_slope, cross = (float)k->m->p.masking_cross, e0 = k->e0;
  for (int q = y0 - 2; q <= y1 + 1; q++) {
    response_row(k, r, jnd_mirror(q, h), r->dif[(q + 6) % 3], r->mask[(q + 10) % 5]);
    const int y = q - 2;
    if (y < y0) continue;
    /* each channel's mutual masker, pooled with the 5 × 5 binomial kernel,
     * straight into the row kept for the next finer band when there is one
     * (not copied there: a copy was 3% of a diff) */
    const float *own[NCH];
    for (int c = 0; c < NCH; c++) {
      const float *m0 = r->mask[(y + 8) % 5][c], *m1 = r->mask[(y + 9) % 5][c], *m2 = r->mask[(y + 10) % 5][c],
                  *m3 = r->mask[(y + 11) % 5][c], *m4 = r->mask[(y + 12) % 5][c];
      float *mp = k->mask_out[c] ? k->mask_out[c] + (size_t)y * w : r->pooled[c];
#pragma omp simd
      for (int x = 0; x < w; x++) mp[x] = (m0[x] + 4 * m1[x] + 6 * m2[x] + 4 * m3[x] + m4[x]) * (1.0f / 16);
      own[c] = mp;
    }
    /* the masking pool: these plus the coarser band's, into r->pooled */
    if (k->coarse_mask[0]) {
      add_coarse_maskers(k, r, y, own);
      for (int c = 0; c < NCH; c++) own[c] = r->pooled[c];
    }
    /* 004 §3.2: difference of the responses, Minkowski over channels; each
     * channel is masked by its own masker plus `cross` times the other
     * channels' (cross-channel masking, docs/model.md "Masking"); with
     * cross = 1 (the default) the three channels share one masker, whose
     * terms are computed once (jnd_masked_pow) */
    float *drow = D + (size_t)y * w, *crow = k->Dc ? k->Dc + (size_t)y * w : NULL;
    const float *d0 = r->dif[(y + 6) % 3][0], *d1 = r->dif[(y + 6) % 3][1], *d2 = r->dif[(y + 6) % 3][2];
    const float *w0 = own[0], *w1 = own[1], *w2 = own[2];
    if (cross == 1.0f) {
#pragma omp simd
      for (int x = 0; x < w; x++) {
        float a, l;
        jnd_masker_terms(w0[x] + (w1[x] + w2[x]), slope, &a, &l);
        const float p0 = jnd_masked_pow(d0[x], a, l, slope, e0), p1 = jnd_masked_pow(d1[x], a, l, slope, e),
                    p2 = jnd_masked_pow(d2[x], a, l, slope, e);
        put_channels(drow, crow, x, p0, p1, p2);
      }
    } else {
#pragma omp simd
      for (int x = 0; x < w; x++) {
        float a0, l0, a1, l1, a2, l2;
        jnd_masker_terms(w0[x] + cross * (w1[x] + w2[x]), slope, &a0, &l0);
        jnd_masker_terms(w1[x] + cross * (w2[x] + w0[x]), slope, &a1, &l1);
        jnd_masker_terms(w2[x] + cross * (w0[x] + w1[x]), slope, &a2, &l2);
        const float p0 = jnd_masked_pow(d0[x], a0, l0, slope, e0), p1 = jnd_masked_pow(d1[x], a1, l1, slope, e),
                    p2 = jnd_masked_pow(d2[x], a2, l2, slope, e);
        put_channels(drow, crow, x, p0, p1, p2);
      }
    }
    if (crow) note_dc_max(r, crow, w);
  }
}

static void band_free(band_ctx *k) {
  axis_free(&k->ax);
  axis_free(&k->ay);
  free(k->ecc_tab);
}

/* What every row of band `band` reads (the baseband is band nbands): the
 * CSF tables for the comparison's temporal condition, and the sampling of
 * the adaptation map. */
static jnd_status band_setup(const jnd_model *m, const diff_state *st, int band, band_ctx *k) {
  memset(k, 0, sizeof *k);
  k->m = m;
  k->st = st;
  k->band = band;
  k->w = st->g[0][0].w[band];
  k->w1 = st->g[0][0].w[band + 1];
  k->h = st->g[0][0].h[band];
  k->unmasked = st->uniform[0] || st->uniform[1];
  k->e = (float)m->p.minkowski;
  k->e0 = k->e;
  k->lum_w[0] = (float)m->lum_w[0];
  k->lum_w[1] = (float)m->lum_w[1];
  k->lut = lut_band(m, band);
  if (st->temporal_hz > 0) {
    /* a temporal modulation at ω under fixation (docs/model.md, "Time"):
     * Kelly's spatio-temporal surface at the band's peak, ω = ρ·v, with no
     * sweep of eye movements (the stimulus itself sets the temporal
     * frequency) */
    const jnd_model_params *p = &m->p;
    const double rho = m->band_cpd[band], amp = m->band_amp[band] / p->flicker_gain, om = st->temporal_hz;
    for (int il = st->il0; il <= st->il1; il++) {
      k->lut1[il][0] =
          (float)(p->sensitivity * jnd_csf_achromatic(rho, om / rho, m->c0[il], m->c1[il], p->kelly_c2) / amp);
      for (int ch = 0; ch < 2; ch++)
        k->lut1[il][1 + ch] = (float)(chromatic_sensitivity(p, ch, rho, om) * m->lumf[ch][il] / amp);
    }
  } else if (!st->has_vel) {
    /* without a motion map every pixel has the same retinal velocity: the
     * CSF tables reduce to one dimension (adaptation luminance) */
    float fv = (log10f(st->uniform_v) - (float)LUT_LOGV0) * (float)(1.0 / LUT_DLOGV);
    fv = fv < 0 ? 0 : fv > LUT_NV - 1.001f ? LUT_NV - 1.001f : fv;
    int iv = (int)fv;
    float tv = fv - iv;
    for (int c = 0; c < NCH; c++)
      for (int il = st->il0; il <= st->il1; il++)
        k->lut1[il][c] =
            (1 - tv) * k->lut[LUT_IX(iv, il) + c] + tv * k->lut[LUT_IX(iv + 1, il) + c];
  }
  k->scale = ldexp(1.0, band);
  k->dist_px = 1.0 / tan(M_PI / 180.0 / m->p.display.ppd);
  if (m->p.has_gaze && ecc_table(k) != JND_OK) return JND_ERR_NOMEM;
  if (!axis_init(&k->ax, k->w, st->aw, ldexp(1.0, band - st->alev)) ||
      !axis_init(&k->ay, k->h, st->ah, ldexp(1.0, band - st->alev))) {
    band_free(k);
    return jnd_fail(JND_ERR_NOMEM, "model: out of memory");
  }
  return JND_OK;
}

/* Runs rows(k, scratch, y0, y1, D) on one contiguous chunk of the band's
 * rows per thread (the masker rings of band_rows run down a chunk; a row's
 * value does not depend on the chunking); *dc_max: the largest value of
 * k->Dc (0 without it, or where none is above 0). */
static jnd_status band_parallel(const band_ctx *k, float *D,
                                void (*rows)(const band_ctx *, row_scratch *, int, int, float *), float *dc_max) {
  const int threads = jnd_threads(k->m->p.threads), h = k->h;
  int fail = 0;
  float mx = 0;
#pragma omp parallel num_threads(threads) reduction(max : mx)
  {
    row_scratch r = {0};
    if (!scratch_init(&r, k->w)) {
#pragma omp atomic write
      fail = 1;
    }
    const int nt = omp_get_num_threads(), t = omp_get_thread_num();
    const int y0 = (int)((long long)h * t / nt), y1 = (int)((long long)h * (t + 1) / nt);
    if (r.mem && y1 > y0) rows(k, &r, y0, y1, D);
    mx = r.dc_max;
    free(r.mem);
  }
  *dc_max = mx;
  return fail ? jnd_fail(JND_ERR_NOMEM, "model: out of memory") : JND_OK;
}

/* The weight of the next coarser band's masker in band `band`'s masking
 * pool: a Gaussian in log frequency, 2^−(d/h)², d the octaves between the
 * two bands' peaks and h = masking_band_oct the tuning's half-width at half
 * height (docs/model.md "Masking"); 0 without inter-band masking. */
static float band_masking_weight(const jnd_model *m, int band) {
  const double h = m->p.masking_band_oct;
  if (!(h > 0) || band + 1 >= m->nbands) return 0;
  const double d = log2(m->band_cpd[band] / m->band_cpd[band + 1]) / h;
  return (float)exp2(-d * d);
}

/* Difference of band i, summed over channels (band_rows). coarse: the next
 * coarser band's pooled maskers (NULL: none); mask_out: where this band's
 * go (NULL: not needed). */
static jnd_status band_difference(const jnd_model *m, diff_state *st, int band, float *D, float *Dc,
                                  float *const coarse[NCH], float *const mask_out[NCH], float *dc_max) {
  band_ctx k;
  jnd_status s = band_setup(m, st, band, &k);
  if (s != JND_OK) return s;
  k.Dc = Dc;
  if (Dc) k.e0 = (float)m->p.summation_beta; /* summation_levels' first pass, done here */
  for (int c = 0; c < NCH; c++) {
    k.coarse_mask[c] = coarse ? coarse[c] : NULL;
    k.mask_out[c] = mask_out ? mask_out[c] : NULL;
  }
  k.coarse_w = coarse ? band_masking_weight(m, band) : 0;
  s = band_parallel(&k, D, band_rows, dc_max);
  band_free(&k);
  return s;
}

/* The baseband (our extension of 004, docs/model.md "Baseband"): the
 * Gaussian level G_n below the coarsest band keeps each image's mean
 * luminance and colour over areas larger than that band's period, which
 * the contrast bands cannot see (a frame that turns black has no contrast).
 * Per cone, the difference of the two images' baselines relative to their
 * mean, (G_test − G_ref) / ((G_test + G_ref) / 2), goes through the
 * opponent transform and the CSF at the baseband's nominal frequency (half
 * the coarsest band's peak) and adaptation, and is summed over channels like
 * a band: D_n = Σ_ch |S·Δc|^e. No masking: the baseband has no pattern. */
static void baseband_rows(const band_ctx *k, row_scratch *r, int y0, int y1, float *D) {
  const diff_state *st = k->st;
  const int nb = k->band;
  for (int y = y0; y < y1; y++) {
    if (k->m->p.has_gaze) ecc_row(k, r, y);
    sens_row(k, r, st->adapt_mid, 0, y); /* the reference's velocity */
    float *drow = D + (size_t)y * k->w;
    for (int x = 0; x < k->w; x++) {
      float dc[3], yn = 0, yd = 0;
      for (int c = 0; c < 3; c++) {
        float gr = st->g[0][c].plane[nb][(size_t)y * k->w + x], gt = st->g[1][c].plane[nb][(size_t)y * k->w + x];
        dc[c] = (gt - gr) / jnd_maxf(0.5f * (gt + gr), CONTRAST_FLOOR);
        if (c < 2) {
          yn += k->lum_w[c] * (gt - gr);
          yd += k->lum_w[c] * 0.5f * (gt + gr);
        }
      }
      float o[3];
      o[0] = yn / jnd_maxf(yd, CONTRAST_FLOOR);
      jnd_opponent_colour(dc[0], dc[1], dc[2], &o[1], &o[2]);
      float d[NCH];
      for (int c = 0; c < NCH; c++) d[c] = jnd_fast_pow(fabsf(o[c] * r->sens[c][x]), c ? k->e : k->e0);
      if (k->Dc) {
        drow[x] = d[0];
        k->Dc[(size_t)y * k->w + x] = d[1] + d[2];
      } else {
        drow[x] = d[0] + d[1] + d[2];
      }
    }
    if (k->Dc) note_dc_max(r, k->Dc + (size_t)y * k->w, k->w);
  }
}

static jnd_status baseband_difference(const jnd_model *m, diff_state *st, float *D, float *Dc, float *dc_max) {
  band_ctx k;
  jnd_status s = band_setup(m, st, m->nbands, &k);
  if (s != JND_OK) return s;
  k.Dc = Dc;
  if (Dc) k.e0 = (float)m->p.summation_beta; /* as band_difference's */
  s = band_parallel(&k, D, baseband_rows, dc_max);
  band_free(&k);
  return s;
}

/* The side-by-side task (docs/model.md "Viewing task"). Two images side by
 * side are compared across space and time, not at one retinal place: a
 * change of the mean luminance and colour over large areas, which in the
 * flicker task is a transient the CSF sees, is then seen only by comparing
 * the two fields' colours, and colorimetry measures that task directly: two
 * large uniform fields side by side are just distinguishable at about
 * ΔE00 = 1 (CIE 142-2001). Each baseband pixel's difference, summed over
 * its area as in the flicker task, is therefore capped at the CIEDE2000
 * difference of the two images' baselines (their Gaussian level G_n, a mean
 * over areas of several degrees) in units of side_by_side_de00: the task is
 * never easier than flickering the same two images, which shows the same
 * fields and the transient besides. D holds JND^e; the bands are
 * untouched (a pattern is seen within either image alone). */
static void side_by_side_baseband(const jnd_model *m, const diff_state *st, float *D) {
  const int nb = m->nbands;
  const size_t n = (size_t)st->g[0][0].w[nb] * st->g[0][0].h[nb];
  const double e = m->p.minkowski, unit = m->p.side_by_side_de00;
  for (size_t i = 0; i < n; i++) {
    double lab[2][3];
    for (int a = 0; a < 2; a++) {
      double lms[3], xyz[3];
      for (int c = 0; c < 3; c++) lms[c] = st->g[a][c].plane[nb][i];
      jnd_lms_to_xyz_one(lms, xyz);
      jnd_lab_of_xyz(&m->p.display, xyz, lab[a]);
    }
    D[i] = jnd_minf(D[i], (float)pow(jnd_delta_e00(lab[0], lab[1]) / unit, e));
  }
}

/* The box passes (jnd_box_pass, boxsum.c): weight 1 on the 2r+1 samples
 * within r of the centre and a on the two at r+1, the weights normalised to
 * sum 1. The horizontal passes run on BOX_ROWS rows interleaved (sample j
 * of row k at s[BOX_ROWS·j + k], and so d), one vector a sample; their input
 * is padded with the zeros beyond the image's ends, so they have no bounds
 * to check. The end weight a ∈ [0, 1] makes the box's variance a continuous
 * function of its length (box_radius): whole-sample radii alone gave a
 * window that moved in steps as σ moved, and the fit's objective was a
 * staircase (docs/model.md "Area summation"). Each pass's output runs past
 * the image's ends by as far as the passes after it reach, so three passes
 * are one window over the image's samples, each sample counted however near
 * the border it lies. Zero, not mirrored: the viewer sees nothing past the
 * image's border, so a difference near it is summed over fewer detectors
 * (mirroring would add reflected copies of it, and make a small stimulus in
 * a small image look like a large one). */
#define BOX_ROWS 8 /* one vector of eight floats a sample */
_Static_assert(BOX_COLS <= JND_BOX_LANES_MAX, "a column block is one box pass");

/* Eight rows into the passes' interleaved layout (sample x of row k at
 * d[BOX_ROWS·x + k]), and back out, eight streams in one loop that the
 * compiler turns into shuffles: a row at a time, the strided scalar moves
 * were 2.5 % of the run's samples (docs/speed.md "Twelfth pass") */
_Static_assert(BOX_ROWS == 8, "interleave8 and deinterleave8 move eight rows");
JND_HOT static void interleave8_rows(float *restrict d, int w, const float *restrict s0, const float *restrict s1,
                                     const float *restrict s2, const float *restrict s3, const float *restrict s4,
                                     const float *restrict s5, const float *restrict s6, const float *restrict s7) {
  for (int x = 0; x < w; x++) {
    float *p = d + (size_t)BOX_ROWS * x;
    p[0] = s0[x], p[1] = s1[x], p[2] = s2[x], p[3] = s3[x];
    p[4] = s4[x], p[5] = s5[x], p[6] = s6[x], p[7] = s7[x];
  }
}

JND_HOT static void deinterleave8_rows(const float *restrict s, int w, float *restrict d0, float *restrict d1,
                                       float *restrict d2, float *restrict d3, float *restrict d4, float *restrict d5,
                                       float *restrict d6, float *restrict d7) {
  for (int x = 0; x < w; x++) {
    const float *p = s + (size_t)BOX_ROWS * x;
    d0[x] = p[0], d1[x] = p[1], d2[x] = p[2], d3[x] = p[3];
    d4[x] = p[4], d5[x] = p[5], d6[x] = p[6], d7[x] = p[7];
  }
}

static void interleave8(const float *const s[BOX_ROWS], float *d, int w) {
  interleave8_rows(d, w, s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]);
}

static void deinterleave8(const float *s, float *const d[BOX_ROWS], int w) {
  deinterleave8_rows(s, w, d[0], d[1], d[2], d[3], d[4], d[5], d[6], d[7]);
}

JND_HOT static void pow_span(const float *src, float *dst, size_t n, float e) {
#pragma omp simd
  for (size_t i = 0; i < n; i++) dst[i] = jnd_fast_pow(src[i], e);
}

/* pooled = (gain · sum)^down, at most bound × the pixel's own value d,
 * into d, or added to acc where acc is given */
JND_HOT static void pool_cap_span(const float *sum, float *d, float *acc, size_t n, float gain, float down,
                                  float bound) {
  if (acc) {
#pragma omp simd
    for (size_t i = 0; i < n; i++) acc[i] += jnd_pooled_capped(sum[i], d[i], gain, down, bound);
    return;
  }
#pragma omp simd
  for (size_t i = 0; i < n; i++) d[i] = jnd_pooled_capped(sum[i], d[i], gain, down, bound);
}

/* pool_cap_span for a level whose d holds j^beta (the difference to the
 * summation's exponent, not to e: band_difference's e0): the cap
 * bound · j^e = (gain · j^beta)^down, so the pooled value is
 * (gain · min(sum, j^beta))^down, one pow where the other pays two
 * (pow_span's and this one) */
JND_HOT static void pool_min_span(const float *sum, float *d, size_t n, float gain, float down) {
#pragma omp simd
  for (size_t i = 0; i < n; i++) d[i] = jnd_pooled_min(sum[i], d[i], gain, down);
}

/* The box of jnd_box_pass whose variance is v (samples²): whole radius r and
 * end weight a ∈ [0, 1). Weights 1 on |j| ≤ r and a on |j| = r + 1, over
 * their sum 2r + 1 + 2a, have variance
 *   (r (r+1) (2r+1) / 3 + 2 a (r+1)²) / (2r + 1 + 2a),
 * which rises with a from r (r+1) / 3 (the box of width 2r + 1) to
 * (r+1) (r+2) / 3 (the next one) — continuous in v, where whole radii alone
 * move in steps. Returns the variance the box has (v, to rounding). */
static double box_radius(double v, int *r, float *a) {
  if (!(v > 0)) v = 0;
  int k = (int)floor((sqrt(12.0 * v + 1.0) - 1.0) / 2.0);
  if (k < 0) k = 0;
  while ((double)(k + 1) * (k + 2) / 3.0 <= v) k++;
  while (k > 0 && (double)k * (k + 1) / 3.0 > v) k--;
  const double m2 = (double)k * (k + 1) * (2 * k + 1) / 3.0, r1 = (double)(k + 1) * (k + 1);
  double al = (v * (2 * k + 1) - m2) / (2.0 * (r1 - v));
  if (al < 0) al = 0;
  if (al > 1) al = 1;
  *r = k;
  *a = (float)al;
  return (m2 + 2.0 * (double)*a * r1) / (2.0 * k + 1.0 + 2.0 * (double)*a);
}

/* The Gaussian window of local summation for a band of peak frequency ρ, as
 * σ in cycles of the band: its area 2πσ² (deg², at ρ cycles a degree) is
 * Rovamo, Luntinen & Näsänen's (1993) critical area A_c = A0 / (1 + (ρ/f0)²),
 * the area up to which sensitivity grows with stimulus area. */
static double summation_sigma_cycles(const jnd_model_params *p, double rho, double f0) {
  double ac = p->summation_area_deg2 / (1.0 + (rho / f0) * (rho / f0));
  return sqrt(ac / (2.0 * M_PI)) * rho;
}

/* Whether the chromatic channels are summed over their own window
 * (docs/model.md "Area summation"): a chromatic f0 or exponent of its own.
 * Chromatic gratings, too, grow more visible with their number of cycles
 * (Lucassen et al. 2018, experiment 2), but over a critical area of their
 * own: castleCSF (Ashraf et al. 2024) gives each colour mechanism its own
 * A0 / (1 + (rho/f0)^2). We share A0 (the saturation at the lowest
 * frequencies) and give the two chromatic channels their own f0 and
 * exponent; 0 keeps the one window of the three channels. */
static int chroma_summation_apart(const jnd_model_params *p) {
  return p->summation_area_deg2 > 0 &&
         ((p->summation_chroma_f0_cpd > 0 && p->summation_chroma_f0_cpd != p->summation_f0_cpd) ||
          (p->summation_chroma_beta > 0 && p->summation_chroma_beta != p->summation_beta));
}

/* j^e (JND to the Minkowski exponent) below which a level's pooled
 * chromatic difference is left out of the map (local_summation) */
#define SUMMATION_NEGLIGIBLE 1e-9f

/* Local probability summation (our extension of 004, docs/model.md): a band's
 * detectors near a pixel all have a chance to see the difference, so the
 * per-band JND j is pooled over a Gaussian window of the critical area
 * (summation_sigma_cycles, three box passes) with exponent summation_beta:
 *   j'(x) = (Σ_y g(x − y) j(y)^beta)^(1/beta),  g's area counted in cycles²,
 * which makes large stimuli more visible than small ones of equal contrast
 * (area summation, Rovamo et al. 1993). D holds j^e and is updated, or,
 * with acc, the pooled values are added to acc. The three horizontal passes
 * run on BOX_ROWS rows at a time and the three vertical ones on one block
 * of columns at a time, in cache; the first two passes keep what they
 * spread beyond the image's border, so that the window over the image's
 * samples is the same however far the border is (the box passes above). f0 and beta: the channels' own critical
 * area and exponent (summation_levels). P: room for the windowed sums, w × h floats. */
static jnd_status local_summation(const jnd_model *m, int band, float *D, float *acc, float *P, int w, int h,
                                  double f0, double beta, int d_beta, float d_max) {
  const double e = m->p.minkowski;
  /* samples of this level per cycle of the band's peak frequency */
  const double spc = 1.0 / (m->band_cpp[band] * ldexp(1.0, band));
  const double sigma = summation_sigma_cycles(&m->p, m->band_cpd[band], f0) * spc;
  /* three equal boxes of variance σ²/3 each (box_radius) */
  int r;
  float endw;
  const double sig_eff = sqrt(3.0 * box_radius(sigma * sigma / 3.0, &r, &endw));
  /* the window's weights sum to its area in cycles²: 2π σ² / spc² */
  const float gain = (float)(2.0 * M_PI * sig_eff * sig_eff / (spc * spc));
  const float up = (float)(beta / e), down = (float)(e / beta);
  /* a pixel's pooled value is at most the whole window's gain times its own:
   * where this band has no difference, pooling must not bring in its
   * neighbours' (it would smear low-frequency differences over degrees).
   * At a local maximum — where thresholds are read — the bound never acts. */
  const float bound = jnd_fast_pow(gain, down);
  /* how far past each end the first and the second pass keep their output:
   * as far as the passes after them reach (the box passes above) */
  const int spill1 = 2 * (r + 1), spill2 = r + 1;
  const int threads = jnd_threads(m->p.threads);
  /* What a level added to acc adds is at most bound × its largest value
   * anywhere (d_max, found as band_rows wrote D: note_dc_max). Where that
   * is negligible — a pair without colour differences at this band's
   * frequencies — the level is left out: the map changes by less than
   * SUMMATION_NEGLIGIBLE (a JND of 2e-4 on its own). (With chroma_tail's
   * slower fall the bench pair's chromatic difference at 18 cpd is bounded
   * at 0.08 JND, no longer 1e-12: it is summed; docs/model.md "Speed".) */
  if (acc && bound * d_max <= SUMMATION_NEGLIGIBLE) return JND_OK;
  int fail = 0;
#pragma omp parallel num_threads(threads)
  {
    /* scratch for the horizontal passes, BOX_ROWS rows interleaved: the
     * first pass's input, padded with the zeros it reads beyond the image's
     * ends, and the first and the second pass's outputs; then two column
     * blocks, each long enough for what the first pass spreads beyond the
     * ends */
    const int pad = spill1 + r + 1;
    const size_t w0 = (size_t)w + 2 * (size_t)pad, w1 = (size_t)w + 2 * (size_t)spill1,
                 w2 = (size_t)w + 2 * (size_t)spill2, hp = (size_t)h + 2 * (size_t)spill1;
    const size_t rows = BOX_ROWS * (w0 + w1 + w2), cols = 2 * BOX_COLS * hp;
    float *a = calloc(rows > cols ? rows : cols, sizeof(float));
    float *suf = malloc(sizeof(float) * 2 * (size_t)(2 * r + 1) * BOX_COLS); /* jnd_box_pass's block suffixes */
    if (!a || !suf) {
#pragma omp atomic write
      fail = 1;
    }
    /* each buffer addressed by image position (0 .. w − 1 the image's) */
    float *t0 = NULL, *o1 = NULL, *o2 = NULL;
    if (a) {
      t0 = a + (size_t)BOX_ROWS * pad;
      o1 = a + (size_t)BOX_ROWS * (w0 + spill1);
      o2 = a + (size_t)BOX_ROWS * (w0 + w1 + spill2);
    }
    const int ngroups = (h + BOX_ROWS - 1) / BOX_ROWS;
    /* groups and blocks handed out as threads come free: a thread held up
     * (this machine's host takes a vCPU away for milliseconds at a time)
     * no longer leaves the other waiting at the loop's end with its share
     * undone (docs/speed.md "Eleventh pass"); each is computed alone, so
     * the values are the same */
#pragma omp for schedule(dynamic, 1)
    for (int g = 0; g < ngroups; g++) {
      if (!a || !suf) continue;
      /* the rows to the exponent, through o2's space, interleaved into t0;
       * past the level's last row (its last group) rows of zeros, whose
       * sums are not kept */
      const int y0 = g * BOX_ROWS, nk = h - y0 < BOX_ROWS ? h - y0 : BOX_ROWS;
      float *staged = o2 - (size_t)BOX_ROWS * spill2; /* room for BOX_ROWS rows */
      const float *src[BOX_ROWS];
      for (int k = 0; k < BOX_ROWS; k++) {
        /* D's row to beta/e, or D's own holding j^beta already */
        float *row = staged + (size_t)k * w;
        src[k] = row;
        if (k < nk && d_beta)
          src[k] = D + (size_t)(y0 + k) * w;
        else if (k < nk)
          pow_span(D + (size_t)(y0 + k) * w, row, (size_t)w, up);
        else
          memset(row, 0, sizeof(float) * (size_t)w);
      }
      interleave8(src, t0, w);
      jnd_box_pass(t0, BOX_ROWS, INT_MIN, INT_MAX, o1 - (size_t)BOX_ROWS * spill1, BOX_ROWS, -spill1, w + 2 * spill1,
                   BOX_ROWS, r, endw, suf);
      jnd_box_pass(o1, BOX_ROWS, INT_MIN, INT_MAX, o2 - (size_t)BOX_ROWS * spill2, BOX_ROWS, -spill2, w + 2 * spill2,
                   BOX_ROWS, r, endw, suf);
      float *o3 = a + (size_t)BOX_ROWS * w0; /* o1's space, free again */
      jnd_box_pass(o2, BOX_ROWS, INT_MIN, INT_MAX, o3, BOX_ROWS, 0, w, BOX_ROWS, r, endw, suf);
      /* the rows past the level's end go to t0's space, free again */
      float *out[BOX_ROWS];
      for (int k = 0; k < BOX_ROWS; k++) out[k] = k < nk ? P + (size_t)(y0 + k) * w : t0 + (size_t)k * w;
      deinterleave8(o3, out, w);
    }
    const int nblocks = (w + BOX_COLS - 1) / BOX_COLS;
#pragma omp for schedule(dynamic, 1)
    for (int bk = 0; bk < nblocks; bk++) {
      if (!a || !suf) continue;
      int x0 = bk * BOX_COLS, cw = w - x0 < BOX_COLS ? w - x0 : BOX_COLS;
      float *b0 = a, *b1 = a + BOX_COLS * hp; /* row stride BOX_COLS */
      /* The block's columns of P, of D and of acc are rows w floats apart,
       * which the hardware's prefetchers do not follow (a stride of pages):
       * each row's lines are asked for PREFETCH_ROWS rows ahead. P's
       * block is first gathered into b1 so, the passes' reads then
       * contiguous: the same values in the same order. */
      for (int y = 0; y < h; y++) {
        if (y + PREFETCH_ROWS < h) prefetch_span(P + (size_t)(y + PREFETCH_ROWS) * w + x0, (size_t)cw, 0);
        memcpy(b1 + (size_t)y * BOX_COLS, P + (size_t)y * w + x0, sizeof(float) * (size_t)cw);
      }
      jnd_box_pass(b1, BOX_COLS, 0, h, b0, BOX_COLS, -spill1, h + 2 * spill1, cw, r, endw, suf);
      jnd_box_pass(b0, BOX_COLS, 0, h + 2 * spill1, b1, BOX_COLS, r + 1, h + 2 * spill2, cw, r, endw, suf);
      jnd_box_pass(b1, BOX_COLS, 0, h + 2 * spill2, b0, BOX_COLS, spill2, h, cw, r, endw, suf);
      for (int y = 0; y < h; y++) {
        if (y + PREFETCH_ROWS < h) {
          prefetch_span(D + (size_t)(y + PREFETCH_ROWS) * w + x0, (size_t)cw, 1);
          if (acc) prefetch_span(acc + (size_t)(y + PREFETCH_ROWS) * w + x0, (size_t)cw, 1);
        }
        if (d_beta)
          pool_min_span(b0 + (size_t)y * BOX_COLS, D + (size_t)y * w + x0, (size_t)cw, gain, down);
        else
          pool_cap_span(b0 + (size_t)y * BOX_COLS, D + (size_t)y * w + x0, acc ? acc + (size_t)y * w + x0 : NULL,
                        (size_t)cw, gain, down, bound);
      }
    }
    free(a);
    free(suf);
  }
  return fail ? jnd_fail(JND_ERR_NOMEM, "model: out of memory") : JND_OK;
}

/* Local summation of one level's difference: D holds all three channels,
 * or, with Dc, the achromatic one while Dc holds the two chromatic ones,
 * each summed over its own window and the two then added (Minkowski over
 * the channels, as before summation). */
static jnd_status summation_levels(const jnd_model *m, int band, float *D, float *Dc, int w, int h, float dc_max) {
  const jnd_model_params *p = &m->p;
  if (!(p->summation_area_deg2 > 0)) return JND_OK;
  /* the windowed sums' plane, one for both passes: the second takes the
   * first's pages, not fresh ones the kernel zeroes again (8 MB at 1080p) */
  float *P = jnd_alloc((size_t)w * h, sizeof(float));
  if (!P) return JND_ERR_NOMEM;
  /* with Dc, D holds the achromatic term to summation_beta (band_difference's e0) */
  jnd_status s = local_summation(m, band, D, NULL, P, w, h, p->summation_f0_cpd, p->summation_beta, Dc != NULL, 0);
  if (s == JND_OK && Dc) {
    const double f0 = p->summation_chroma_f0_cpd > 0 ? p->summation_chroma_f0_cpd : p->summation_f0_cpd;
    const double beta = p->summation_chroma_beta > 0 ? p->summation_chroma_beta : p->summation_beta;
    s = local_summation(m, band, Dc, D, P, w, h, f0, beta, 0, dc_max); /* pooled into D */
  }
  free(P);
  return s;
}

/* The difference planes of level b: D, and with apart Dc for the chromatic
 * channels (summation_levels); on failure *Dc is NULL and *D is freed by
 * the caller with the other levels */
static jnd_status level_planes(const diff_state *st, int b, int apart, float **D, float **Dc) {
  const size_t n = (size_t)st->g[0][0].w[b] * st->g[0][0].h[b];
  *D = jnd_alloc(n, sizeof(float));
  if (!*D) return JND_ERR_NOMEM;
  if (apart && !(*Dc = jnd_alloc(n, sizeof(float)))) return JND_ERR_NOMEM;
  return JND_OK;
}

static void state_free(diff_state *st) {
  for (int a = 0; a < 2; a++) {
    for (int c = 0; c < 3; c++) jnd_gauss_free(&st->g[a][c]);
    free(st->adapt[a]);
  }
  free(st->adapt_mid);
  for (int a = 0; a < 2; a++) free(st->rgb[a]);
  if (st->has_vel) jnd_gauss_free(&st->vel[0]);
  if (st->has_vel && !st->vel_shared) jnd_gauss_free(&st->vel[1]);
}

/* Retinal velocity per full-resolution pixel from the displacement map
 * (pixels per frame → deg/s through fps and ppd → Daly's eye-movement model);
 * motion NULL is a static image. */
static jnd_status velocity_map(const jnd_model *m, const jnd_image *motion, int w, int h, float **out) {
  *out = NULL;
  if (!motion) {
    float *v = jnd_alloc((size_t)w * h, sizeof(float));
    if (!v) return JND_ERR_NOMEM;
    const float v0 = (float)jnd_retinal_velocity(0);
    for (size_t i = 0; i < (size_t)w * h; i++) v[i] = v0;
    *out = v;
    return JND_OK;
  }
  if (motion->w != w || motion->h != h || motion->c < 2)
    return jnd_fail(JND_ERR_ARG, "motion map: %d × %d × %d does not match the %d × %d images (2 channels needed)",
                    motion->w, motion->h, motion->c, w, h);
  if (!(m->p.fps > 0)) return jnd_fail(JND_ERR_ARG, "motion map: frames per second must be positive");
  float *v = jnd_alloc((size_t)w * h, sizeof(float));
  if (!v) return JND_ERR_NOMEM;
  const float *dx = jnd_image_plane(motion, 0), *dy = jnd_image_plane(motion, 1);
  double k = m->p.fps / m->p.display.ppd;
  for (size_t i = 0; i < (size_t)w * h; i++) {
    double vs = sqrt((double)dx[i] * dx[i] + (double)dy[i] * dy[i]) * k;
    v[i] = (float)jnd_retinal_velocity(vs);
  }
  *out = v;
  return JND_OK;
}

/* ---- diff_lms's stages, in 004 §3.1's order (the list at the top) ---- */

/* rgb8_rows for jnd_gauss_build3_rows: ctx is {state, image} */
typedef struct {
  const diff_state *st;
  int a;
} rgb8_src;

static void rgb8_rows_of(void *ctx, int y, float *const out[3]) {
  const rgb8_src *q = ctx;
  rgb8_rows(q->st, q->a, y, out);
}

/* Which of an image's L, M, S planes kept as codes hold one value each
 * (value[c] then): its pixels whose codes differ from the first pixel's,
 * through the same arithmetic as its rows, until every plane has differed
 * (at the first such pixel, but for codes whose L, M or S round alike) */
static void rgb8_constant(const diff_state *st, int a, size_t npx, int constant[3], float value[3]) {
  const unsigned char *px = st->rgb[a];
  float one[3], *o[3] = {&one[0], &one[1], &one[2]}, *v[3] = {&value[0], &value[1], &value[2]};
  jnd_rgb8_lms_row(px, st->code_lum[a], st->rgb_lms, v, 1);
  int left = 3;
  for (int c = 0; c < 3; c++) constant[c] = 1;
  for (size_t i = 1; i < npx && left; i++) {
    const unsigned char *q = px + 3 * i;
    if (q[0] == px[0] && q[1] == px[1] && q[2] == px[2]) continue;
    jnd_rgb8_lms_row(q, st->code_lum[a], st->rgb_lms, o, 1);
    for (int c = 0; c < 3; c++)
      if (constant[c] && one[c] != value[c]) {
        constant[c] = 0;
        left--;
      }
  }
}

/* Gaussian pyramids of image a's L, M, S planes (lms is taken over: plane
 * 0 of channel L owns it, freed here on failure; an image kept as codes,
 * st->rgb[a], has lms NULL), and whether the image is uniform (a
 * psychophysical background needs no contrast bands). */
static jnd_status image_pyramids(diff_state *st, int a, float *lms, int w, int h, int levels, int threads) {
  jnd_status s = JND_OK;
  size_t npx = (size_t)w * h;
  if (st->rgb[a]) {
    int constant[3];
    float value[3];
    rgb8_constant(st, a, npx, constant, value);
    rgb8_src src = {st, a};
    s = jnd_gauss_build3_rows(st->g[a], rgb8_rows_of, &src, w, h, levels, constant, value, threads);
    st->uniform[a] = constant[0] && constant[1] && constant[2];
    return s;
  }
  for (int c = 0; c < 3 && s == JND_OK; c++) {
    s = jnd_gauss_build(&st->g[a][c], lms + (size_t)c * npx, w, h, levels, threads);
    if (s == JND_OK && c == 0) st->g[a][c].own0 = 1; /* plane 0 of channel L owns the buffer */
  }
  if (s != JND_OK) {
    if (!st->g[a][0].own0) free(lms);
    return s;
  }
  st->uniform[a] = 1;
  for (int c = 0; c < 3 && st->uniform[a]; c++) {
    const float *p = lms + (size_t)c * npx;
    for (size_t i = 1; i < npx; i++)
      if (p[i] != p[0]) {
        st->uniform[a] = 0;
        break;
      }
  }
  return JND_OK;
}

/* both images' planes' (image_pyramids); lms[a] taken over */
static jnd_status gaussian_pyramids(diff_state *st, float *lms[2], int w, int h, int levels, int threads) {
  jnd_status s = image_pyramids(st, 0, lms[0], w, h, levels, threads);
  if (s != JND_OK) {
    free(lms[1]);
    return s;
  }
  return image_pyramids(st, 1, lms[1], w, h, levels, threads);
}

/* The adaptation luminance of the CSF: Y at the level where a pixel is
 * about one degree, of each image and their mean, and the CSF table's
 * columns it needs. */
static jnd_status adaptation_luminance(jnd_model *m, diff_state *st, int levels) {
  st->alev = m->adapt_level < levels ? m->adapt_level : levels - 1;
  st->aw = st->g[0][0].w[st->alev];
  st->ah = st->g[0][0].h[st->alev];
  for (int a = 0; a < 2; a++) {
    st->adapt[a] = jnd_alloc((size_t)st->aw * st->ah, sizeof(float));
    if (!st->adapt[a]) return JND_ERR_NOMEM;
    for (size_t i = 0; i < (size_t)st->aw * st->ah; i++) {
      double y = 0;
      for (int c = 0; c < 3; c++) y += m->lum_w[c] * st->g[a][c].plane[st->alev][i];
      st->adapt[a][i] = (float)fmax(y, 1e-6);
    }
  }
  st->adapt_mid = jnd_alloc((size_t)st->aw * st->ah, sizeof(float));
  if (!st->adapt_mid) return JND_ERR_NOMEM;
  for (size_t i = 0; i < (size_t)st->aw * st->ah; i++) st->adapt_mid[i] = 0.5f * (st->adapt[0][i] + st->adapt[1][i]);
  /* the CSF table columns these adaptation luminances need (one more either
   * side for the interpolation) */
  float lo = st->adapt[0][0], hi = lo;
  for (int a = 0; a < 2; a++)
    for (size_t i = 0; i < (size_t)st->aw * st->ah; i++) {
      lo = jnd_minf(lo, st->adapt[a][i]);
      hi = jnd_maxf(hi, st->adapt[a][i]);
    }
  st->il0 = jnd_clampi((int)floor((log10(lo) - LUT_LOGL0) / LUT_DLOGL) - 1, 0, LUT_NL - 1);
  st->il1 = jnd_clampi((int)ceil((log10(hi) - LUT_LOGL0) / LUT_DLOGL) + 1, 0, LUT_NL - 1);
  lut_fill(m, st->il0, st->il1);
  return JND_OK;
}

/* The CSF's velocity: the retinal velocity of each pixel (pyramids of the
 * motion maps), a uniform one, or a temporal modulation. */
static jnd_status csf_velocity(jnd_model *m, diff_state *st, const jnd_diff_inputs *in, int w, int h, int threads) {
  const int nb = m->nbands;
  float *vel0 = NULL;
  jnd_status s = JND_OK;
  st->uniform_v = JND_DRIFT_DPS; /* 004 §3.1: static images keep the drift minimum */
  if (in && in->temporal_hz > 0) {
    st->temporal_hz = in->temporal_hz;
  } else if (in && in->retinal_dps > 0) {
    st->uniform_v = (float)in->retinal_dps;
  } else if (in && (in->motion || in->motion_test)) {
    /* 004 §3: each frame's own displacement; one pyramid when they are the same */
    st->vel_shared = !in->motion_test || in->motion_test == in->motion;
    for (int a = 0; a < (st->vel_shared ? 1 : 2); a++) {
      const jnd_image *mo = a == 0 ? in->motion : in->motion_test;
      if ((s = velocity_map(m, mo, w, h, &vel0)) != JND_OK) break;
      if ((s = jnd_gauss_build(&st->vel[a], vel0, w, h, nb + 1, threads)) != JND_OK) break;
      st->vel[a].own0 = 1;
      vel0 = NULL;
      st->has_vel = 1;
    }
    if (s == JND_OK && st->vel_shared) st->vel[1] = st->vel[0];
  }
  free(vel0);
  return s;
}

/* Each band's difference, contrast pyramid → opponent channels → CSF
 * normalisation → masking transducer → |T(test) − T(ref)|^β summed over
 * the channels, into Dlev[b] (b = 0..nb, nb the baseband). */
static jnd_status band_differences(jnd_model *m, diff_state *st, float **Dlev, int threads) {
  const int nb = m->nbands;
  jnd_status s = JND_OK;
  /* from the coarsest band to the finest, so that each band's masking pool
   * can take in the next coarser band's pooled maskers (kept at that
   * band's level: 3/4 of a float a pixel at most) */
  const int xband = m->p.masking_band_oct > 0 && !st->uniform[0] && !st->uniform[1];
  const int apart = chroma_summation_apart(&m->p);
  float *mk_coarse[NCH] = {0}, *mk_this[NCH] = {0};
  for (int b = nb - 1; b >= 0 && s == JND_OK; b--) {
    if (xband && b > 0)
      for (int c = 0; c < NCH && s == JND_OK; c++) {
        mk_this[c] = jnd_alloc((size_t)st->g[0][0].w[b] * st->g[0][0].h[b], sizeof(float));
        if (!mk_this[c]) s = jnd_fail(JND_ERR_NOMEM, "model: out of memory");
      }
    float *Dc = NULL, dc_max = 0;
    if (s == JND_OK) s = level_planes(st, b, apart, &Dlev[b], &Dc);
    if (s == JND_OK)
      s = band_difference(m, st, b, Dlev[b], Dc, xband && mk_coarse[0] ? mk_coarse : NULL,
                          xband && b > 0 ? mk_this : NULL, &dc_max);
    for (int c = 0; c < NCH; c++) {
      free(mk_coarse[c]);
      mk_coarse[c] = mk_this[c];
      mk_this[c] = NULL;
    }
    /* the finest band was the last to read level 0 of the images' pyramids
     * (the images themselves, 50 MB at 1920×1080): freed before its
     * summation, the peak of a diff's memory */
    if (b == 0)
      for (int a = 0; a < 2; a++) {
        if (st->g[a][0].own0) free(st->g[a][0].plane[0]);
        st->g[a][0].own0 = 0;
        for (int c = 0; c < 3; c++) st->g[a][c].plane[0] = NULL;
        free(st->rgb[a]);
        st->rgb[a] = NULL;
      }
    if (s == JND_OK) s = summation_levels(m, b, Dlev[b], Dc, st->g[0][0].w[b], st->g[0][0].h[b], dc_max);
    free(Dc);
  }
  for (int c = 0; c < NCH; c++) free(mk_coarse[c]);
  /* the baseband, as one more level below the coarsest band */
  if (s == JND_OK) {
    float *Dc = NULL, dc_max = 0;
    s = level_planes(st, nb, apart, &Dlev[nb], &Dc);
    if (s == JND_OK) s = baseband_difference(m, st, Dlev[nb], Dc, &dc_max);
    if (s == JND_OK) s = summation_levels(m, nb, Dlev[nb], Dc, st->g[0][0].w[nb], st->g[0][0].h[nb], dc_max);
    /* a temporal modulation is a flicker whatever the display's task */
    if (s == JND_OK && m->p.display.task == JND_TASK_SIDE_BY_SIDE && !(st->temporal_hz > 0))
      side_by_side_baseband(m, st, Dlev[nb]);
    free(Dc);
  }
  return s;
}

/* 004 §3.2: the bands collapsed into Dlev[0] (full resolution), the
 * coarser levels freed; with nb > 0 Dlev[0] is then raised to p as its
 * rows are made (jnd_map_of's first step, done here: *powed = 1). */
static jnd_status collapse_bands(float **Dlev, int nb, int w, int h, float p, int *powed, int threads) {
  *powed = 0;
  /* 004 §3.2: collapse the difference pyramid (Minkowski sum across bands):
   * acc_i = D_i + EXPAND(acc_{i+1}), from the baseband to the finest band */
  for (int b = nb; b > 0; b--) {
    int cw = w, ch = h, fw = w, fh = h;
    for (int k = 0; k < b; k++) { cw = (cw + 1) / 2; ch = (ch + 1) / 2; }
    for (int k = 0; k < b - 1; k++) { fw = (fw + 1) / 2; fh = (fh + 1) / 2; }
    /* acc_{b-1} += max(EXPAND(acc_b), 0), a row at a time */
    if (!(b == 1 ? jnd_pyr_expand_add_pow(Dlev[b], cw, ch, Dlev[b - 1], fw, fh, p, threads)
                 : jnd_pyr_expand_add(Dlev[b], cw, ch, Dlev[b - 1], fw, fh, threads)))
      return jnd_fail(JND_ERR_NOMEM, "model: out of memory");
    *powed = b == 1;
    free(Dlev[b]);
    Dlev[b] = NULL;
  }
  return JND_OK;
}

/* the collapsed sum's exponent to the map: 1/β (Minkowski) */
static float map_power(const jnd_model *m) { return (float)(1.0 / m->p.minkowski); }

/* ^(1/β) of the collapsed sum (unless powed: collapse_bands did it), and
 * the caller's weights: the JND map, in place. */
static void jnd_map_of(const jnd_model *m, const jnd_diff_inputs *in, float *o, size_t npx, int powed, int threads) {
  const float inv = map_power(m);
  const float *wt = in && in->weights ? in->weights->data : NULL;
  /* two loops, not one with a branch, so that both vectorise */
  const size_t span = 16384;
  if (!powed) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (size_t i = 0; i < npx; i += span) pow_span(o + i, o + i, npx - i < span ? npx - i : span, inv);
  }
  /* 004 §3.2: weights scale down the difference map */
  if (wt) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (size_t i = 0; i < npx; i++) o[i] *= jnd_maxf(wt[i], 0.0f);
  }
}

/* Gaussian levels: bands need G_{i+2}; the adaptation level must exist too */
static int gauss_level_count(const jnd_model *m) {
  int levels = m->nbands + 2;
  if (m->adapt_level + 1 > levels) levels = m->adapt_level + 1;
  return levels;
}

/* The model from the images' pyramids on (st, taken over) to the map */
static jnd_status diff_levels(jnd_model *m, diff_state *st, int w, int h, const jnd_diff_inputs *in,
                              jnd_image *jnd_out) {
  const int threads = jnd_threads(m->p.threads);
  const int nb = m->nbands;
  float *Dlev[MAX_BANDS] = {0};
  jnd_status s = adaptation_luminance(m, st, gauss_level_count(m));
  if (s == JND_OK) s = csf_velocity(m, st, in, w, h, threads);
  if (s == JND_OK) s = band_differences(m, st, Dlev, threads);
  state_free(st);
  int powed = 0;
  if (s == JND_OK) s = collapse_bands(Dlev, nb, w, h, map_power(m), &powed, threads);
  if (s != JND_OK) {
    for (int b = 0; b < MAX_BANDS; b++) free(Dlev[b]);
    return s;
  }
  jnd_map_of(m, in, Dlev[0], (size_t)w * h, powed, threads);
  jnd_image out = {0};
  out.w = w;
  out.h = h;
  out.c = 1;
  out.data = Dlev[0];
  *jnd_out = out;
  return JND_OK;
}

/* The model on two LMS images (planar, 3 channels) whose buffers it takes
 * over. */
static jnd_status diff_lms(jnd_model *m, float *lms[2], int w, int h, const jnd_diff_inputs *in,
                           jnd_image *jnd_out) {
  diff_state st;
  memset(&st, 0, sizeof st);
  jnd_status s = gaussian_pyramids(&st, lms, w, h, gauss_level_count(m), jnd_threads(m->p.threads));
  if (s != JND_OK) {
    state_free(&st);
    return s;
  }
  return diff_levels(m, &st, w, h, in, jnd_out);
}

static jnd_status check_pair(const jnd_image *a, const jnd_image *b, const jnd_diff_inputs *in) {
  if (a->c != 3 || b->c != 3)
    return jnd_fail(JND_ERR_ARG, "model: images need 3 channels (got %d and %d)", a->c, b->c);
  if (a->w != b->w || a->h != b->h)
    return jnd_fail(JND_ERR_ARG, "image sizes differ: %d × %d vs %d × %d", a->w, a->h, b->w, b->h);
  jnd_status s = jnd_check_size(a->w, a->h, a->c, "model");
  if (s != JND_OK) return s;
  if (in && in->weights && (in->weights->w != a->w || in->weights->h != a->h))
    return jnd_fail(JND_ERR_ARG, "weight map: %d × %d does not match the %d × %d images", in->weights->w,
                    in->weights->h, a->w, a->h);
  return JND_OK;
}

/* converts a 3-channel image (RGB or XYZ) in place to HPE LMS */
static jnd_status to_lms(jnd_image *img, int is_xyz) {
  if (is_xyz)
    jnd_xyz_to_lms(img);
  else
    jnd_rgb_to_lms(img);
  return JND_OK;
}

static jnd_status diff_copy(jnd_model *m, const jnd_image *ref, const jnd_image *test, const jnd_diff_inputs *in,
                            jnd_image *jnd_out, int is_xyz) {
  memset(jnd_out, 0, sizeof *jnd_out);
  jnd_status s = check_pair(ref, test, in);
  if (s != JND_OK) return s;
  size_t n = (size_t)ref->w * ref->h * 3;
  jnd_image c[2] = {{ref->w, ref->h, 3, jnd_alloc(n, sizeof(float))}, {ref->w, ref->h, 3, jnd_alloc(n, sizeof(float))}};
  if (!c[0].data || !c[1].data) {
    free(c[0].data);
    free(c[1].data);
    return JND_ERR_NOMEM;
  }
  memcpy(c[0].data, ref->data, n * sizeof(float));
  memcpy(c[1].data, test->data, n * sizeof(float));
  to_lms(&c[0], is_xyz);
  to_lms(&c[1], is_xyz);
  float *lms[2] = {c[0].data, c[1].data};
  return diff_lms(m, lms, ref->w, ref->h, in, jnd_out);
}

jnd_status jnd_model_diff(jnd_model *m, const jnd_image *ref, const jnd_image *test, const jnd_diff_inputs *in,
                          jnd_image *jnd_out) {
  return diff_copy(m, ref, test, in, jnd_out, 0);
}

jnd_status jnd_model_diff_xyz(jnd_model *m, const jnd_image *ref, const jnd_image *test,
                              const jnd_diff_inputs *in, jnd_image *jnd_out) {
  return diff_copy(m, ref, test, in, jnd_out, 1);
}

jnd_status jnd_model_diff_consume(jnd_model *m, jnd_image *ref, jnd_image *test, const jnd_diff_inputs *in,
                                  jnd_image *jnd_out) {
  memset(jnd_out, 0, sizeof *jnd_out);
  jnd_status s = check_pair(ref, test, in);
  if (s != JND_OK) {
    jnd_image_free(ref);
    jnd_image_free(test);
    return s;
  }
  to_lms(ref, 0);
  to_lms(test, 0);
  float *lms[2] = {ref->data, test->data};
  int w = ref->w, h = ref->h;
  memset(ref, 0, sizeof *ref);
  memset(test, 0, sizeof *test);
  return diff_lms(m, lms, w, h, in, jnd_out);
}

/* One image of a pair, its pyramids made on its own (jnd_model_image_rgb8):
 * a diff_state's half */
struct jnd_model_image {
  jnd_gauss g[3];
  unsigned char *rgb; /* its codes: level 0 is made from them, or g[0] owns its LMS planes (made
                         from them where level 0 is read whole) */
  float code_lum[256];
  int uniform;
  int w, h;
};

void jnd_model_image_free(jnd_model_image *im) {
  if (!im) return;
  for (int c = 0; c < 3; c++) jnd_gauss_free(&im->g[c]);
  free(im->rgb);
  free(im);
}

unsigned char *jnd_model_image_codes(jnd_model_image *im) {
  unsigned char *rgb = im->rgb;
  im->rgb = NULL;
  jnd_model_image_free(im);
  return rgb;
}

jnd_status jnd_model_image_rgb8(const jnd_model *m, unsigned char *rgb, int w, int h, const float lum[256],
                                int threads, jnd_model_image **out) {
  *out = NULL;
  jnd_status s = jnd_check_size(w, h, 3, "model");
  jnd_model_image *im = s == JND_OK ? calloc(1, sizeof *im) : NULL;
  if (!im) {
    free(rgb);
    return s != JND_OK ? s : jnd_fail(JND_ERR_NOMEM, "model: out of memory");
  }
  diff_state st;
  memset(&st, 0, sizeof st);
  jnd_rgb_to_lms_weights(st.rgb_lms);
  const int levels = gauss_level_count(m);
  const int alev = m->adapt_level < levels ? m->adapt_level : levels - 1;
  float *lms = NULL;
  if (m->nbands < 1 || alev < 1) {
    /* level 0 is then read whole (as the adaptation level, or the
     * baseband's): the image as planes, made from the codes */
    const size_t npx = (size_t)w * h;
    lms = jnd_alloc(npx * 3, sizeof(float));
    for (int y = 0; y < h && lms; y++) {
      float *row[3] = {lms + (size_t)y * w, lms + npx + (size_t)y * w, lms + 2 * npx + (size_t)y * w};
      jnd_rgb8_lms_row(rgb + (size_t)y * 3 * w, lum, st.rgb_lms, row, (size_t)w);
    }
    if (!lms) {
      free(rgb);
      free(im);
      return JND_ERR_NOMEM;
    }
  } else {
    st.rgb[0] = rgb;
    memcpy(st.code_lum[0], lum, sizeof st.code_lum[0]);
  }
  s = image_pyramids(&st, 0, lms, w, h, levels, threads);
  memcpy(im->g, st.g[0], sizeof im->g);
  /* kept with the planes too, for jnd_model_image_codes (the planes are read) */
  im->rgb = rgb;
  memcpy(im->code_lum, st.code_lum[0], sizeof im->code_lum);
  im->uniform = st.uniform[0];
  im->w = w;
  im->h = h;
  if (s != JND_OK) {
    jnd_model_image_free(im);
    return s;
  }
  *out = im;
  return JND_OK;
}

jnd_status jnd_model_diff_images(jnd_model *m, jnd_model_image *ref, jnd_model_image *test,
                                 const jnd_diff_inputs *in, jnd_image *jnd_out) {
  memset(jnd_out, 0, sizeof *jnd_out);
  const jnd_image a = {ref->w, ref->h, 3, NULL}, b = {test->w, test->h, 3, NULL};
  jnd_status s = check_pair(&a, &b, in);
  if (s != JND_OK) {
    jnd_model_image_free(ref);
    jnd_model_image_free(test);
    return s;
  }
  diff_state st;
  memset(&st, 0, sizeof st);
  jnd_rgb_to_lms_weights(st.rgb_lms);
  jnd_model_image *im[2] = {ref, test};
  for (int i = 0; i < 2; i++) {
    memcpy(st.g[i], im[i]->g, sizeof st.g[i]);
    st.rgb[i] = im[i]->rgb; /* (with planes too: unread, freed with them) */
    memcpy(st.code_lum[i], im[i]->code_lum, sizeof st.code_lum[i]);
    st.uniform[i] = im[i]->uniform;
    free(im[i]); /* its contents now st's */
  }
  return diff_levels(m, &st, a.w, a.h, in, jnd_out);
}

jnd_status jnd_model_diff_rgb8(jnd_model *m, unsigned char *ref, unsigned char *test, int w, int h,
                               const float lum[256], const jnd_diff_inputs *in, jnd_image *jnd_out) {
  memset(jnd_out, 0, sizeof *jnd_out);
  const int threads = jnd_threads(m->p.threads);
  jnd_model_image *a = NULL, *b = NULL;
  jnd_status s = jnd_model_image_rgb8(m, ref, w, h, lum, threads, &a);
  if (s != JND_OK) {
    free(test);
    return s;
  }
  if ((s = jnd_model_image_rgb8(m, test, w, h, lum, threads, &b)) != JND_OK) {
    jnd_model_image_free(a);
    return s;
  }
  return jnd_model_diff_images(m, a, b, in, jnd_out);
}
