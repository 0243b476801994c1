/* `jnd csf`: the vision model against human contrast-detection thresholds.
 *
 * Each row of castleCSF-format data describes a stimulus — a Gabor, a
 * grating or a disc of a colour direction on a uniform background — and the
 * contrast at which people detect it. We synthesise the stimulus as an XYZ
 * image pair (background alone vs background + stimulus), and find, in log
 * contrast, the contrast at which the model's max-pooled probability is 0.5
 * (JND = 1). The predicted sensitivity is 1 / that contrast.
 *
 * Colour: backgrounds and directions are CIE 2006 LMS (castleCSF's scaling,
 * luminance = L + M). They are taken to XYZ with the LMS2006→XYZ matrix of
 * castleCSF's colour utilities (derived for LED-LCD spectra), then scaled so
 * that the background's Y equals the row's luminance. Contrast is RMS cone
 * contrast: sqrt(mean((ΔL/L)², (ΔM/M)², (ΔS/S)²)), equal to Michelson
 * contrast for a luminance modulation. Geometry and sampling: docs/csf.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"
#include "vision/vision.h"

#define MAX_SIDE_PX 512

void jnd_csf_sampling(const jnd_csf_stimulus *s, double *ppd, double *half_deg, double *taper_deg) {
  double f = s->s_frequency;
  double half;
  if (s->kind == JND_STIM_GABOR) {
    half = 3.0 * s->ge_sigma;
  } else {
    half = 0.5 * sqrt(s->area);
    if (s->kind == JND_STIM_DISK) half = sqrt(s->area / M_PI);
  }
  /* a soft edge for apertures: half a period, at least 0.05° */
  double taper = s->kind == JND_STIM_GABOR ? 0 : fmax(0.05, f > 0 ? 0.5 / f : 0.1);
  half += taper;
  /* 4√2 samples a cycle where the size allows: the stimulus then lies half
   * an octave from the Nyquist frequency of every pyramid level (at exactly
   * 4 or 8 samples a cycle it would sit on a level's Nyquist frequency, where
   * the response depends on the grating's phase); 8..256 ppd, never fewer
   * than 2.5 samples a cycle */
  double p = f > 0 ? jnd_clampd(4.0 * M_SQRT2 * f, 8.0, 256.0) : 16.0;
  double margin = 1.25;
  if (2 * half * margin * p > MAX_SIDE_PX && f > 0) p = fmax(fmax(2.5 * f, 8.0), MAX_SIDE_PX / (2 * half * margin));
  *ppd = p;
  *half_deg = half;
  *taper_deg = taper;
}

/* the stimulus's spatial profile at (x, y) degrees from its centre, in [-1, 1] */
static double profile(const jnd_csf_stimulus *s, double x, double y, double half, double taper, double crop) {
  double th = s->orientation * M_PI / 180.0;
  double xr = x * cos(th) + y * sin(th);
  double carrier = s->s_frequency > 0 ? cos(2 * M_PI * s->s_frequency * xr) : 1.0;
  double env;
  if (s->kind == JND_STIM_GABOR) {
    env = exp(-(x * x + y * y) / (2 * s->ge_sigma * s->ge_sigma));
  } else {
    /* a square (gratings) or round (discs) aperture with a raised-cosine edge */
    double inner = half - taper;
    double d = s->kind == JND_STIM_DISK ? sqrt(x * x + y * y) : fmax(fabs(x), fabs(y));
    if (d <= inner)
      env = 1;
    else if (d >= half)
      env = 0;
    else
      env = 0.5 + 0.5 * cos(M_PI * (d - inner) / taper);
  }
  /* a crop smaller than the stimulus fades it out over the crop's outer 15% */
  double dc = fmax(fabs(x), fabs(y));
  if (dc > 0.85 * crop) env *= dc >= crop ? 0 : 0.5 + 0.5 * cos(M_PI * (dc - 0.85 * crop) / (0.15 * crop));
  return carrier * env;
}

typedef struct {
  jnd_model *model;
  jnd_image bg, stim; /* XYZ: background, and the unit-contrast modulation */
  jnd_diff_inputs in;
} stim_ctx;

/* max JND over the image at RMS cone contrast c */
static jnd_status max_jnd(stim_ctx *ctx, double c, double *out) {
  jnd_image test = {0}, map = {0};
  jnd_status s = jnd_image_alloc(&test, ctx->bg.w, ctx->bg.h, 3);
  if (s != JND_OK) return s;
  size_t n = (size_t)ctx->bg.w * ctx->bg.h * 3;
  for (size_t i = 0; i < n; i++) test.data[i] = ctx->bg.data[i] + (float)c * ctx->stim.data[i];
  s = jnd_model_diff_xyz(ctx->model, &ctx->bg, &test, &ctx->in, &map);
  jnd_image_free(&test);
  if (s != JND_OK) return s;
  float mx = 0;
  for (size_t i = 0; i < (size_t)map.w * map.h; i++) mx = map.data[i] > mx ? map.data[i] : mx;
  jnd_image_free(&map);
  *out = mx;
  return JND_OK;
}

#define CACHE_MODELS 48

struct jnd_csf_context {
  jnd_model_params base;
  int n;
  jnd_model_params key[CACHE_MODELS];
  jnd_model *model[CACHE_MODELS];
};

jnd_status jnd_csf_context_create(const jnd_model_params *base, jnd_csf_context **out) {
  *out = jnd_calloc(1, sizeof **out);
  if (!*out) return JND_ERR_NOMEM;
  (*out)->base = *base;
  return JND_OK;
}

void jnd_csf_context_free(jnd_csf_context *ctx) {
  if (!ctx) return;
  for (int i = 0; i < ctx->n; i++) jnd_model_free(ctx->model[i]);
  free(ctx);
}

/* a model for these parameters: from the cache, or built (and cached, oldest out) */
static jnd_status context_model(jnd_csf_context *ctx, const jnd_model_params *p, jnd_model **m) {
  for (int i = 0; i < ctx->n; i++)
    if (ctx->key[i].display.ppd == p->display.ppd && ctx->key[i].has_gaze == p->has_gaze &&
        ctx->key[i].gaze_x == p->gaze_x && ctx->key[i].gaze_y == p->gaze_y) {
      *m = ctx->model[i];
      return JND_OK;
    }
  jnd_status s = jnd_model_create(p, m);
  if (s != JND_OK) return s;
  if (ctx->n == CACHE_MODELS) {
    jnd_model_free(ctx->model[0]);
    memmove(ctx->model, ctx->model + 1, sizeof ctx->model[0] * (CACHE_MODELS - 1));
    memmove(ctx->key, ctx->key + 1, sizeof ctx->key[0] * (CACHE_MODELS - 1));
    ctx->n--;
  }
  ctx->key[ctx->n] = *p;
  ctx->model[ctx->n++] = *m;
  return JND_OK;
}

jnd_status jnd_csf_threshold(jnd_csf_context *cx, const jnd_csf_stimulus *st, double *sensitivity,
                             jnd_csf_detail *detail) {
  const jnd_model_params *base = &cx->base;
  *sensitivity = NAN;
  if (!(st->luminance > 0)) return jnd_fail(JND_ERR_ARG, "stimulus: luminance must be positive");
  if (st->kind == JND_STIM_GABOR && !(st->ge_sigma > 0)) return jnd_fail(JND_ERR_ARG, "stimulus: Gabor needs ge_sigma > 0");
  if (st->kind != JND_STIM_GABOR && !(st->area > 0)) return jnd_fail(JND_ERR_ARG, "stimulus: needs area > 0");
  if (!(st->s_frequency >= 0) || st->s_frequency > 64)
    return jnd_fail(JND_ERR_ARG, "stimulus: spatial frequency %g cpd is outside 0..64", st->s_frequency);
  double ppd, half, taper;
  jnd_csf_sampling(st, &ppd, &half, &taper);
  double crop = fmin(half * 1.25, MAX_SIDE_PX / (2 * ppd));
  int side = (int)ceil(2 * crop * ppd);
  if (side < 32) side = 32;
  crop = side / (2.0 * ppd);

  /* colour: background and unit-RMS-contrast modulation in XYZ */
  double bxyz[3], dxyz[3];
  jnd_csf_lms_to_xyz(st->bkg_lms, bxyz);
  double k = st->luminance / bxyz[1];
  double m2 = 0;
  for (int i = 0; i < 3; i++) {
    double r = st->dir_lms[i] / st->bkg_lms[i];
    m2 += r * r / 3.0;
  }
  if (!(m2 > 0)) return jnd_fail(JND_ERR_ARG, "stimulus: zero colour direction");
  double t = 1.0 / sqrt(m2); /* LMS amplitude per unit RMS cone contrast */
  double dl[3] = {st->dir_lms[0] * t, st->dir_lms[1] * t, st->dir_lms[2] * t};
  jnd_csf_lms_to_xyz(dl, dxyz);
  for (int i = 0; i < 3; i++) {
    bxyz[i] *= k;
    dxyz[i] *= k;
  }

  stim_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  jnd_model_params p = *base;
  p.display.ppd = ppd;
  p.threads = base->threads > 0 ? base->threads : 1;
  if (st->eccentricity > 0) {
    /* fixation ecc° to the left of the stimulus centre, on a flat screen */
    double dist_px = 1.0 / tan(M_PI / 180.0 / ppd);
    p.has_gaze = 1;
    p.gaze_x = side / 2.0 - 0.5 - dist_px * tan(st->eccentricity * M_PI / 180.0);
    p.gaze_y = side / 2.0 - 0.5;
  } else {
    p.has_gaze = 0;
  }
  jnd_status s = context_model(cx, &p, &ctx.model);
  if (s != JND_OK) return s;
  if ((s = jnd_image_alloc(&ctx.bg, side, side, 3)) != JND_OK || (s = jnd_image_alloc(&ctx.stim, side, side, 3)) != JND_OK)
    goto done;
  for (int y = 0; y < side; y++)
    for (int x = 0; x < side; x++) {
      double xd = (x + 0.5) / ppd - crop, yd = (y + 0.5) / ppd - crop;
      double g = profile(st, xd, yd, half, taper, crop);
      size_t i = (size_t)y * side + x;
      for (int c = 0; c < 3; c++) {
        jnd_image_plane(&ctx.bg, c)[i] = (float)bxyz[c];
        jnd_image_plane(&ctx.stim, c)[i] = (float)(dxyz[c] * g);
      }
    }
  /* drifting gratings under fixation: retinal velocity = t_freq / s_freq */
  if (st->t_frequency > 0 && st->s_frequency > 0)
    ctx.in.retinal_dps = fmax(st->t_frequency / st->s_frequency, JND_DRIFT_DPS);

  /* bracketed search in log contrast for max JND = 1 (P = 0.5): secant steps
   * in log–log (JND ∝ contrast near threshold), bisection as the fallback */
  double lo = log10(1e-6), hi = log10(2.0), jlo = NAN, jhi = NAN, x = log10(0.01), jx;
  if ((s = max_jnd(&ctx, pow(10, x), &jx)) != JND_OK) goto done;
  int evals = 1;
  for (int it = 0; it < 40; it++) {
    double lj = log10(fmax(jx, 1e-30));
    if (jx >= 1) { hi = x; jhi = lj; } else { lo = x; jlo = lj; }
    if (fabs(lj) < 1e-4 || hi - lo < 1e-5) break;
    double nx;
    if (jx > 0) nx = x - lj; /* slope 1 in log–log */
    else nx = 0.5 * (lo + hi);
    if (!isnan(jlo) && !isnan(jhi) && jhi != jlo) nx = lo + (0 - jlo) * (hi - lo) / (jhi - jlo);
    if (!(nx > lo && nx < hi)) nx = 0.5 * (lo + hi);
    x = nx;
    if ((s = max_jnd(&ctx, pow(10, x), &jx)) != JND_OK) goto done;
    evals++;
  }
  if (jx < 0.999 && x >= log10(2.0) - 1e-6) {
    *sensitivity = 0.5; /* not detected even at contrast 2 */
  } else {
    *sensitivity = pow(10, -x);
  }
  if (detail) {
    detail->ppd = ppd;
    detail->side_px = side;
    detail->evaluations = evals;
  }
done:
  jnd_image_free(&ctx.bg);
  jnd_image_free(&ctx.stim);
  return s;
}
