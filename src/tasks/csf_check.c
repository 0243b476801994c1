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

/* The background kept around a stimulus, degrees beyond its half-extent:
 * enough that the image's borders, where the pyramid mirrors the image, do
 * not change the threshold by more than a few tenths of a dB — eight periods
 * of a grating's frequency (thresholds of small patches were 10 dB off with
 * a quarter of the stimulus's size, the old margin), and the radius of a
 * disc, whose coarse bands and baseband reach far (docs/csf.md). */
static double margin_deg(const jnd_csf_stimulus *s, double half) {
  return s->s_frequency > 0 ? fmax(0.25 * half, 8.0 / s->s_frequency) : half;
}

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
   * than 2.5 samples a cycle. Discs without a carrier: 16 ppd, 8 for discs
   * of more than 2° radius (thresholds within 0.3 dB of 16 and 25 ppd). */
  double p = f > 0 ? jnd_clampd(4.0 * M_SQRT2 * f, 8.0, 256.0) : half > 2.0 ? 8.0 : 16.0;
  double ext = half + margin_deg(s, half);
  if (2 * ext * p > MAX_SIDE_PX) p = fmax(f > 0 ? fmax(2.5 * f, 8.0) : 8.0, MAX_SIDE_PX / (2 * ext));
  *ppd = p;
  *half_deg = half;
  *taper_deg = taper;
}

/* a raised-cosine edge: 1 inside `inner`, 0 beyond inner + width */
static double soft_edge(double d, double inner, double width) {
  if (d <= inner) return 1;
  if (d >= inner + width) return 0;
  return 0.5 + 0.5 * cos(M_PI * (d - inner) / width);
}

/* The stimulus's spatial profile, in [-1, 1], on a side × side grid of
 * pixels (x + 0.5)/ppd − crop degrees from its centre: carrier times
 * envelope, faded out over the crop's outer 15% when the crop is smaller
 * than the stimulus. The carrier cos(2πf(x cos θ + y sin θ)) is expanded
 * into per-column and per-row cosines and sines; square apertures and the
 * crop fade depend on max(|x|, |y|) through a decreasing edge, so they are
 * the minimum of a column and a row factor. */
static void synthesise(const jnd_csf_stimulus *s, int side, double ppd, double half, double taper, double crop,
                       float *g) {
  double *t = malloc(sizeof(double) * (size_t)side * 8);
  if (!t) {
    memset(g, 0, sizeof(float) * (size_t)side * side);
    return;
  }
  double *cx = t, *sx = t + side, *cy = t + 2 * side, *sy = t + 3 * side, *ex = t + 4 * side, *ey = t + 5 * side,
         *fx = t + 6 * side, *pos = t + 7 * side;
  const double th = s->orientation * M_PI / 180.0, w = 2 * M_PI * s->s_frequency;
  for (int i = 0; i < side; i++) {
    double u = (i + 0.5) / ppd - crop;
    pos[i] = u;
    cx[i] = cos(w * u * cos(th));
    sx[i] = sin(w * u * cos(th));
    cy[i] = cos(w * u * sin(th));
    sy[i] = sin(w * u * sin(th));
    if (s->kind == JND_STIM_GABOR)
      ex[i] = exp(-u * u / (2 * s->ge_sigma * s->ge_sigma));
    else
      ex[i] = soft_edge(fabs(u), half - taper, taper); /* square aperture (gratings) */
    fx[i] = soft_edge(fabs(u), 0.85 * crop, 0.15 * crop);
  }
  memcpy(ey, ex, sizeof(double) * (size_t)side);
  for (int y = 0; y < side; y++)
    for (int x = 0; x < side; x++) {
      double carrier = s->s_frequency > 0 ? cx[x] * cy[y] - sx[x] * sy[y] : 1.0;
      double env;
      if (s->kind == JND_STIM_GABOR)
        env = ex[x] * ey[y];
      else if (s->kind == JND_STIM_DISK)
        env = soft_edge(sqrt(pos[x] * pos[x] + pos[y] * pos[y]), half - taper, taper);
      else
        env = fmin(ex[x], ey[y]);
      g[(size_t)y * side + x] = (float)(carrier * env * fmin(fx[x], fx[y]));
    }
  free(t);
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
  int linear; /* 1: one model run at a small probe contrast (csf_fit.c) */
  int n;
  double key[CACHE_MODELS]; /* ppd */
  jnd_model *model[CACHE_MODELS];
};

void jnd_csf_context_set_linear(jnd_csf_context *ctx, int linear) { ctx->linear = linear; }

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

/* a model for these parameters: from the cache, or built (and cached, oldest
 * out); models differ only in their sampling density, the fixation point is
 * set on the one found */
static jnd_status context_model(jnd_csf_context *ctx, const jnd_model_params *p, jnd_model **m) {
  for (int i = 0; i < ctx->n; i++)
    if (ctx->key[i] == p->display.ppd) {
      *m = ctx->model[i];
      jnd_model_set_gaze(*m, p->has_gaze, p->gaze_x, p->gaze_y);
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
  ctx->key[ctx->n] = p->display.ppd;
  ctx->model[ctx->n++] = *m;
  return JND_OK;
}

/* The stimulus as the model sees it, in XYZ (cd/m²): *bg the uniform
 * background at the data's luminance (Y), *stim the modulation at unit RMS
 * cone contrast (the profile of synthesise in the colour direction), on a
 * side × side grid at *ppd pixels per degree. */
jnd_status csf_stimulus_images(const jnd_csf_stimulus *st, double *ppd_out, jnd_image *bg, jnd_image *stim) {
  memset(bg, 0, sizeof *bg);
  memset(stim, 0, sizeof *stim);
  double ppd, half, taper;
  jnd_csf_sampling(st, &ppd, &half, &taper);
  double crop = fmin(half + margin_deg(st, half), MAX_SIDE_PX / (2 * ppd));
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
  jnd_status s;
  if ((s = jnd_image_alloc(bg, side, side, 3)) != JND_OK || (s = jnd_image_alloc(stim, side, side, 3)) != JND_OK) {
    jnd_image_free(bg);
    return s;
  }
  /* the profile into the stimulus's first plane, then scaled into all three */
  synthesise(st, side, ppd, half, taper, crop, jnd_image_plane(stim, 0));
  for (int c = 2; c >= 0; c--) {
    float *bp = jnd_image_plane(bg, c), *sp = jnd_image_plane(stim, c);
    const float *g = jnd_image_plane(stim, 0), b = (float)bxyz[c], d = (float)dxyz[c];
    for (size_t i = 0; i < (size_t)side * side; i++) {
      bp[i] = b;
      sp[i] = d * g[i];
    }
  }
  *ppd_out = ppd;
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
  double ppd;
  stim_ctx ctx;
  memset(&ctx, 0, sizeof ctx);
  jnd_status s = csf_stimulus_images(st, &ppd, &ctx.bg, &ctx.stim);
  if (s != JND_OK) return s;
  int side = ctx.bg.w;
  jnd_model_params p = *base;
  p.display.ppd = ppd;
  /* the observer compares stimulus and blank at the same place (an
   * interval or a flicker): the flicker task (docs/model.md "Viewing task") */
  p.display.task = JND_TASK_FLICKER;
  p.threads = base->threads > 0 ? base->threads : 1;
  /* the observer fixates ecc° to the left of the stimulus centre, on a flat
   * screen — at its centre for a foveal stimulus, whose outer parts then
   * fall on less sensitive retina (a 20° Gabor is not seen foveally) */
  double dist_px = 1.0 / tan(M_PI / 180.0 / ppd);
  p.has_gaze = 1;
  p.gaze_x = side / 2.0 - 0.5 - dist_px * tan(st->eccentricity * M_PI / 180.0);
  p.gaze_y = side / 2.0 - 0.5;
  if ((s = context_model(cx, &p, &ctx.model)) != JND_OK) goto done;
  /* a temporal modulation (flicker, counterphase or drift) at t_frequency
   * under fixation: the model's temporal-frequency sensitivity */
  if (st->t_frequency > 0) ctx.in.temporal_hz = st->t_frequency;

  /* The model is linear in the contrast of a stimulus on a uniform
   * background (the mutual masker is 0 there) except for the few per cent the
   * stimulus adds to the local mean of the contrast denominators: a probe at
   * a small contrast gives the threshold at once, and secant steps in
   * log–log refine it to max JND = 1 (P = 0.5) inside a bracket that falls
   * back to bisection. */
  const double probe = -3.0; /* log10 contrast */
  double lo = log10(1e-6), hi = log10(2.0), jlo = NAN, jhi = NAN, x = probe, jx;
  if ((s = max_jnd(&ctx, pow(10, x), &jx)) != JND_OK) goto done;
  int evals = 1;
  if (cx->linear) {
    /* the fit's surrogate: the threshold the probe implies */
    x = jx > 0 ? fmin(probe - log10(jx), hi) : hi;
    jx = x < hi ? 1 : 0;
  } else {
    for (int it = 0; it < 40; it++) {
      double lj = log10(fmax(jx, 1e-30));
      if (jx >= 1) { hi = x; jhi = lj; } else { lo = x; jlo = lj; }
      if (fabs(lj) < 1e-3 || hi - lo < 1e-5) break;
      double nx;
      if (jx > 0) nx = x - lj; /* slope 1 in log–log */
      else nx = 0.5 * (lo + hi);
      if (!isnan(jlo) && !isnan(jhi) && jhi != jlo) nx = lo + (0 - jlo) * (hi - lo) / (jhi - jlo);
      if (!(nx > lo && nx < hi)) nx = 0.5 * (lo + hi);
      x = nx;
      if ((s = max_jnd(&ctx, pow(10, x), &jx)) != JND_OK) goto done;
      evals++;
    }
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
