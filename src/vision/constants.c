/* The model's fitted constants: which fields of jnd_model_params the human
 * threshold data may set (`jnd csf --fit`), and the prior each fit starts
 * from. A prior is a published or physiological value with a width: fits
 * are maximum a posteriori, so a constant that a fit's data do not constrain
 * (in cross-validation, when the only data set that measures it is left
 * out) returns to the literature, not to a value fitted on the left-out
 * data. docs/model.md lists them with their fitted values. */
#include <stddef.h>
#include <string.h>

#include "core/core.h"
#include "vision/vision.h"

#define LN10 2.302585092994046

static const struct {
  jnd_model_constant c;
  size_t offset;
} CONSTANTS[] = {
    {{"sensitivity", "multiplier on the achromatic CSF (004's Daly/Kelly form as printed: 1)", 1.0, LN10, 0.01, 100,
      "004 §3.1", 0},
     offsetof(jnd_model_params, sensitivity)},
    {{"sens_rg", "peak scale of the red–green CSF", 300, LN10, 1, 1e5,
      "Mullen 1985: isoluminant red–green thresholds of a few 0.1% cone contrast", 0},
     offsetof(jnd_model_params, sens_rg)},
    {{"sens_yv", "peak scale of the yellow–violet CSF", 200, LN10, 1, 1e5,
      "Mullen 1985, as sens_rg", 0},
     offsetof(jnd_model_params, sens_yv)},
    {{"rg_cutoff_cpd", "red–green CSF centre cut-off, cycles/degree", 2.0, 0.7, 0.2, 20,
      "Mullen 1985: the red–green CSF is low-pass and 10× down near 5 cpd", 0},
     offsetof(jnd_model_params, rg_cutoff_cpd)},
    {{"yv_cutoff_cpd", "yellow–violet CSF centre cut-off, cycles/degree", 1.5, 0.7, 0.2, 20,
      "Mullen 1985: S-cone gratings fade at lower frequencies than red–green", 0},
     offsetof(jnd_model_params, yv_cutoff_cpd)},
    {{"chroma_tail", "exponent q of the chromatic CSFs' centre, exp(-(rho/cutoff)^q)", 1.0, 0.5, 0.1, 4,
      "q = 1, an exponential low-pass, was this model's form of Kelly's 1983 centre (004 §3.1 does not print it; docs/model.md)", 0},
     offsetof(jnd_model_params, chroma_tail)},
    {{"chroma_sat_td", "trolands where the chromatic square-root law turns into Weber's law", 100, LN10, 1, 1e6,
      "van der Horst & Bouman 1969: square-root law at low, Weber at high retinal illuminance", 1},
     offsetof(jnd_model_params, chroma_sat_td)},
    {{"chroma_temporal_hz", "temporal cut-off of the chromatic CSFs' centre, Hz", 7, 0.5, 1, 60,
      "Kelly 1983: chromatic flicker sensitivity falls off above 5-10 Hz", 0},
     offsetof(jnd_model_params, chroma_temporal_hz)},
    {{"kelly_c2", "velocity scale c2 of the achromatic spatio-velocity CSF", 1.7, 0.5, 0.2, 10,
      "004 §3.1 (Daly 1998); Kelly 1979 has 1", 0},
     offsetof(jnd_model_params, kelly_c2)},
    {{"flicker_gain", "sensitivity to a flicker's amplitude relative to a travelling wave's", 0.71, 0.5, 0.05, 5,
      "Kelly 1979: a counterphase grating is two travelling ones of half its contrast", 0},
     offsetof(jnd_model_params, flicker_gain)},
    {{"eye_velocity_dps", "sweep of retinal velocity by fixational eye movements, deg/s", 10, 1.0, 0.5, 200,
      "Martinez-Conde et al. 2004: drift and microsaccades, ~0.5 to ~30 deg/s", 0},
     offsetof(jnd_model_params, eye_velocity_dps)},
    {{"summation_area_deg2", "A0 of the critical summation area A0 / (1 + (rho/f0)^2), deg²", 270, 0.7, 1, 1e5,
      "Rovamo, Luntinen & Näsänen 1993", 0},
     offsetof(jnd_model_params, summation_area_deg2)},
    {{"summation_f0_cpd", "f0 of the critical summation area, cycles/degree", 0.65, 0.7, 0.02, 20,
      "Rovamo, Luntinen & Näsänen 1993", 0},
     offsetof(jnd_model_params, summation_f0_cpd)},
    {{"summation_beta", "exponent of local probability summation", 2.0, 0.3, 1, 8,
      "Rovamo et al. 1993: sensitivity grows as the square root of area", 0},
     offsetof(jnd_model_params, summation_beta)},
    {{"summation_chroma_f0_cpd", "f0 of the chromatic channels' critical summation area, cycles/degree", 0.65, 0.7,
      0.005, 20, "Rovamo et al. 1993's achromatic f0, no chromatic value assumed; castleCSF (Ashraf et al. 2024): one critical area per colour mechanism", 0},
     offsetof(jnd_model_params, summation_chroma_f0_cpd)},
    {{"summation_chroma_beta", "exponent of the chromatic channels' local probability summation", 2.0, 0.3, 1, 8,
      "Rovamo et al. 1993, as summation_beta", 0},
     offsetof(jnd_model_params, summation_chroma_beta)},
    {{"ecc_e2_deg", "eccentricity where cortical magnification has halved, degrees", 3.0, 0.5, 0.3, 30,
      "Rovamo & Virsu 1979: M(0)/M(e) = 1 + 0.33 e", 0},
     offsetof(jnd_model_params, ecc_e2_deg)},
    {{"ecc_achromatic", "exponent of M(0)/M(e) in achromatic sensitivity", 1.0, 0.5, 0.01, 5,
      "Rovamo & Virsu 1979: M-scaled stimuli are equally visible; square-root summation", 0},
     offsetof(jnd_model_params, ecc_achromatic)},
    {{"ecc_rg", "exponent of M(0)/M(e) in red–green sensitivity", 1.5, 0.7, 0.01, 8,
      "Mullen & Kingdom 2002: red–green sensitivity falls faster than luminance's", 0},
     offsetof(jnd_model_params, ecc_rg)},
    {{"ecc_yv", "exponent of M(0)/M(e) in yellow–violet sensitivity", 1.0, 0.7, 0.01, 8,
      "Mullen & Kingdom 2002: S-cone sensitivity falls about as luminance's", 0},
     offsetof(jnd_model_params, ecc_yv)},
    {{"ecc_freq", "frequency-dependent loss with eccentricity, per cpd·degree", 0.046, 0.7, 1e-4, 1,
      "Geisler & Perry 1998: 0.106 / 2.3", 0},
     offsetof(jnd_model_params, ecc_freq)},
};

#define NCONST ((int)(sizeof CONSTANTS / sizeof CONSTANTS[0]))

int jnd_model_constants(const jnd_model_constant **list, int max) {
  if (list)
    for (int k = 0; k < NCONST && k < max; k++) list[k] = &CONSTANTS[k].c;
  return NCONST;
}

int jnd_model_constant_find(const char *name) {
  for (int k = 0; k < NCONST; k++)
    if (strcmp(CONSTANTS[k].c.name, name) == 0) return k;
  return -1;
}

double jnd_model_constant_get(const jnd_model_params *p, int k) {
  if (k < 0 || k >= NCONST) return NAN;
  double v;
  memcpy(&v, (const char *)p + CONSTANTS[k].offset, sizeof v);
  return v;
}

jnd_status jnd_model_constant_set(jnd_model_params *p, int k, double v) {
  if (k < 0 || k >= NCONST) return jnd_fail(JND_ERR_ARG, "model: no constant %d", k);
  const jnd_model_constant *c = &CONSTANTS[k].c;
  if (!(v >= c->lo && v <= c->hi))
    return jnd_fail(JND_ERR_ARG, "model: %s must be in [%g, %g], not %g", c->name, c->lo, c->hi, v);
  memcpy((char *)p + CONSTANTS[k].offset, &v, sizeof v);
  return JND_OK;
}
