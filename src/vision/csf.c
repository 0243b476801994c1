/* Contrast sensitivity functions of 004 §3.1. */
#include <math.h>

#include "core/core.h"
#include "vision/vision.h"

/* 004 §3.1: Barten's (2003) spatial CSF, used only to adapt the achromatic
 * CSF to the luminance level. */
double jnd_csf_barten(double rho, double L) {
  double r2 = rho * rho;
  double num = 5200.0 * exp(-0.0016 * r2 * pow(1.0 + 100.0 / L, 0.08));
  double den = sqrt((2.0 + 0.64 * r2) * (63.0 / pow(L, 0.83) + 1.0 / (1.0 - exp(-0.02 * r2))));
  return num / den;
}

/* The maximum of csf_B over frequency at luminance L, and where it is:
 * golden-section search in log frequency (csf_B is unimodal in ρ). */
static void barten_peak(double L, double *peak, double *argmax) {
  double lo = log(0.01), hi = log(100.0);
  const double gr = 0.6180339887498949;
  double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
  double f1 = jnd_csf_barten(exp(x1), L), f2 = jnd_csf_barten(exp(x2), L);
  while (hi - lo > 1e-7) {
    if (f1 > f2) {
      hi = x2; x2 = x1; f2 = f1;
      x1 = hi - gr * (hi - lo); f1 = jnd_csf_barten(exp(x1), L);
    } else {
      lo = x1; x1 = x2; f1 = f2;
      x2 = lo + gr * (hi - lo); f2 = jnd_csf_barten(exp(x2), L);
    }
  }
  *argmax = exp(0.5 * (lo + hi));
  *peak = jnd_csf_barten(*argmax, L);
}

/* 004 §3.1: c0(L) = 1.14 · max csf_B(·, L) / max csf_B(·, 100),
 *           c1(L) = 0.67 · argmax csf_B(·, 100) / argmax csf_B(·, L). */
void jnd_csf_adaptation(double L, double *c0, double *c1) {
  double p100, a100, pL, aL;
  barten_peak(100.0, &p100, &a100);
  barten_peak(L, &pL, &aL);
  *c0 = 1.14 * pL / p100;
  *c1 = 0.67 * a100 / aL;
}

/* 004 §3.1: Daly's (1998) refinement of Kelly's (1979) spatio-velocity CSF,
 *   csf_A(ρ, v) = (6.1 + 7.3 |log10(c2 v / 3)|³) c0 c2 v (2π c1 ρ)² exp(−4π c1 ρ (c2 v + 2) / 45.9)
 * with c0, c1 adapted to the luminance (jnd_csf_adaptation). c2 scales the
 * velocity axis: 004 prints Daly's 1.7; Kelly's own surface has 1, and it is
 * a fitted constant here (kelly_c2, docs/model.md), because the temporal
 * fall-off above 10 Hz that 1.7 implies is far steeper than flicker data. */
double jnd_csf_achromatic(double rho, double v, double c0, double c1, double c2) {
  double lv = fabs(log10(c2 * v / 3.0));
  double k = 6.1 + 7.3 * lv * lv * lv;
  double a = 2.0 * M_PI * c1 * rho;
  return k * c0 * c2 * v * a * a * exp(-4.0 * M_PI * c1 * rho * (c2 * v + 2.0) / 45.9);
}

/* 004 §3.1: Le Grand's pupil diameter, d(L) = 5 − 3 tanh(0.4 log10 L), mm. */
double jnd_pupil_diameter_mm(double L) { return 5.0 - 3.0 * tanh(0.4 * log10(L)); }

/* Kelly's (1983) chromatic spatio-temporal CSF as 004 §3.1 describes it: a
 * linear combination of two space–time-separable low-pass functions, a
 * centre and a surround. 004 does not print Kelly's constants; the form and
 * the constants below are our choice, documented in docs/model.md: each
 * component is a low-pass in spatial frequency times a
 * low-pass in temporal frequency; the surround is broader in space and
 * slower, so motion or flicker removes it first and the peak sensitivity
 * rises with velocity while the curve stays low-pass. The centre's temporal
 * low-pass is of second order, 1 / (1 + (ω/ω_c)²), ω_c = temporal_hz fitted
 * (docs/model.md): chromatic flicker sensitivity is flat at low frequencies
 * and falls by about a decade from 10 to 25 Hz, faster than a first-order
 * filter allows. The centre's spatial low-pass is a stretched exponential,
 * exp(−(ρ/ρ_c)^q), q = tail fitted (docs/model.md): the exponential (q = 1)
 * falls far faster above a few cpd than red–green and S-cone thresholds do;
 * the surround keeps the exponential. */
static const struct {
  double k_s, rho_s, omega_s;
} CHROM[2] = {
    {0.25, 0.25, 2.0}, /* red–green (a) */
    {0.25, 0.20, 2.0}, /* yellow–violet (b) */
};
#define CHROM_REF_LUM 35.0 /* 004 §3.1: the chromatic CSF's reference luminance */

static double retinal_illuminance(double L) {
  double d = jnd_pupil_diameter_mm(L);
  return L * M_PI * d * d / 4.0; /* trolands */
}

double jnd_csf_chromatic_luminance(double L, double sat_td) {
  /* 004 §3.1 (van der Horst & Bouman 1969): sensitivity scales with the square
   * root of retinal illuminance, relative to the reference luminance. The
   * square-root law holds at low illuminance; above sat_td trolands
   * sensitivity approaches Weber's law (constant), as the csf_train data
   * show (docs/model.md): I / (1 + I / sat) in place of I. */
  double i = retinal_illuminance(L), r = retinal_illuminance(CHROM_REF_LUM);
  if (sat_td > 0) {
    i = i / (1.0 + i / sat_td);
    r = r / (1.0 + r / sat_td);
  }
  return sqrt(i / r);
}

double jnd_csf_chromatic(double rho, double omega, int ch, double cutoff, double tail, double temporal_hz) {
  double tc = 1.0 / (1.0 + (omega / temporal_hz) * (omega / temporal_hz));
  double ts = 1.0 / sqrt(1.0 + (omega / CHROM[ch].omega_s) * (omega / CHROM[ch].omega_s));
  double s = exp(-pow(rho / cutoff, tail)) * tc - CHROM[ch].k_s * exp(-rho / CHROM[ch].rho_s) * ts;
  return fmax(s, 0.0);
}

/* 004 §3.1: Daly's (1998) model of unconstrained eye movements,
 *   v = |v_s − min(0.82 v_s + 0.15, 80)| deg/s:
 * smooth pursuit tracks 82% of the image velocity up to 80 deg/s, and drift
 * leaves 0.15 deg/s on the retina even for a static image. */
double jnd_retinal_velocity(double vs) {
  vs = fabs(vs);
  return fabs(vs - fmin(0.82 * vs + JND_DRIFT_DPS, 80.0));
}

/* Cortical magnification (Rovamo & Virsu 1979, in the one-term form of
 * Levi, Klein & Aitsebaomo 1985): M(0)/M(e) = 1 + e/e2. M² is proportional to
 * the density of retinal ganglion cells, so the number of detectors under a
 * patch of the visual field falls as (1 + e/e2)^−2. */
double jnd_cortical_magnification(double ecc, double e2) { return 1.0 + ecc / e2; }

/* Sensitivity at eccentricity e relative to the fovea, for a band of peak
 * frequency ρ in channel ch (0 achromatic, 1 red–green, 2 yellow–violet):
 *   (M(0)/M(e))^−γ_ch · exp(−α ρ e).
 * The first factor is the loss of detectors (Rovamo & Virsu: sensitivity to
 * a stimulus of fixed size falls with M, exponent γ ≈ 1 for luminance under
 * square-root summation); chromatic channels fall faster than luminance in
 * the periphery (Mullen & Kingdom 2002), hence one exponent per channel. The
 * second is Geisler & Perry's (1998) frequency-dependent loss, the decline of
 * acuity. All four are fitted (docs/model.md). */
double jnd_eccentricity_factor(const jnd_model_params *p, int ch, double rho, double ecc) {
  const double gamma = ch == 0 ? p->ecc_achromatic : ch == 1 ? p->ecc_rg : p->ecc_yv;
  return pow(jnd_cortical_magnification(ecc, p->ecc_e2_deg), -gamma) * exp(-p->ecc_freq * rho * ecc);
}
