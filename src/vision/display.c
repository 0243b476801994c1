/* Display model (004 §3.1, first stage): from the file's signal to absolute
 * linear RGB in cd/m², with the display's peak, black level and the ambient
 * light it reflects; and the viewing geometry as pixels per degree. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "vision/vision.h"

static const char *const preset_names[] = {"standard-fhd", "standard-4k", "phone", "laptop", "vr", NULL};

const char *const *jnd_display_preset_names(void) { return preset_names; }

double jnd_ppd_from_geometry(double diagonal_in, int width_px, int height_px, double distance_m) {
  double diag_px = sqrt((double)width_px * width_px + (double)height_px * height_px);
  double pitch_m = diagonal_in * 0.0254 / diag_px;
  /* one pixel at the centre of the screen subtends 2·atan(p / 2d) */
  double deg_per_px = 2.0 * atan(pitch_m / (2.0 * distance_m)) * 180.0 / M_PI;
  return 1.0 / deg_per_px;
}

static void set_geometry(jnd_display *d, const char *name, double diag, int w, int h, double dist,
                         double peak) {
  memset(d, 0, sizeof *d);
  snprintf(d->name, sizeof d->name, "%s", name);
  d->diagonal_in = diag;
  d->width_px = w;
  d->height_px = h;
  d->distance_m = dist;
  d->ppd = diag > 0 ? jnd_ppd_from_geometry(diag, w, h, dist) : 0;
  d->peak_cdm2 = peak;
  d->black_cdm2 = peak / 1000.0; /* a 1000:1 panel */
  d->ambient_lux = 0.0;          /* a dark room, as in the experiments behind the CSFs */
  d->reflectivity = 0.005;       /* a matte screen */
  d->exr_scale = 1.0;
  d->task = JND_TASK_SIDE_BY_SIDE; /* what a user of a gate or a pipeline means (docs/model.md "Viewing task") */
}

const char *jnd_viewing_task_name(jnd_viewing_task t) { return t == JND_TASK_FLICKER ? "flicker" : "side-by-side"; }

jnd_status jnd_viewing_task_parse(const char *s, jnd_viewing_task *t) {
  if (strcmp(s, "side-by-side") == 0) {
    *t = JND_TASK_SIDE_BY_SIDE;
  } else if (strcmp(s, "flicker") == 0) {
    *t = JND_TASK_FLICKER;
  } else {
    return jnd_fail(JND_ERR_ARG, "unknown viewing task '%s' (side-by-side or flicker)", s);
  }
  return JND_OK;
}

void jnd_display_defaults(jnd_display *d) { set_geometry(d, "standard-fhd", 24, 1920, 1080, 0.60, 200); }

jnd_status jnd_display_preset(const char *name, jnd_display *d) {
  if (strcmp(name, "standard-fhd") == 0) {
    set_geometry(d, name, 24, 1920, 1080, 0.60, 200);
  } else if (strcmp(name, "standard-4k") == 0) {
    set_geometry(d, name, 27, 3840, 2160, 0.60, 200);
  } else if (strcmp(name, "phone") == 0) {
    set_geometry(d, name, 6.1, 2532, 1170, 0.30, 500);
  } else if (strcmp(name, "laptop") == 0) {
    set_geometry(d, name, 14, 2560, 1600, 0.50, 300);
  } else if (strcmp(name, "vr") == 0) {
    /* a current headset: about 20 pixels per degree, 100 cd/m² */
    set_geometry(d, name, 0, 0, 0, 0, 100);
    d->ppd = 20;
  } else {
    return jnd_fail(JND_ERR_ARG,
                    "unknown display '%s' (one of standard-fhd, standard-4k, phone, laptop, vr)", name);
  }
  return JND_OK;
}

/* The name a display's messages give: "display NAME: ..." ("display: ..."
 * where it has none or it is not a terminated string). */
static const char *label(const jnd_display *d, char buf[40]) {
  if (memchr(d->name, 0, sizeof d->name) && d->name[0])
    snprintf(buf, 40, "display %s", d->name);
  else
    snprintf(buf, 40, "display");
  return buf;
}

static int within(double x, double lo, double hi) { return x >= lo && x <= hi; } /* NaN: no */

/* The quantities the display's transform uses: luminances, the room's light, the EXR scale. */
static jnd_status check_light(const jnd_display *d) {
  char who[40];
  if (!within(d->peak_cdm2, 0.01, 100000))
    return jnd_fail(JND_ERR_ARG, "%s: peak %g cd/m² is outside [0.01, 100000]", label(d, who), d->peak_cdm2);
  if (!(d->black_cdm2 >= 0 && d->black_cdm2 < d->peak_cdm2))
    return jnd_fail(JND_ERR_ARG, "%s: need 0 <= black (%g) < peak (%g) cd/m²", label(d, who), d->black_cdm2,
                    d->peak_cdm2);
  if (!within(d->ambient_lux, 0, 200000))
    return jnd_fail(JND_ERR_ARG, "%s: ambient %g lux is outside [0, 200000]", label(d, who), d->ambient_lux);
  if (!within(d->reflectivity, 0, 1))
    return jnd_fail(JND_ERR_ARG, "%s: reflectivity %g is outside [0, 1]", label(d, who), d->reflectivity);
  if (!within(d->exr_scale, 1e-9, 1e9))
    return jnd_fail(JND_ERR_ARG, "%s: exr_scale %g is outside [1e-09, 1e+09] cd/m² per unit", label(d, who),
                    d->exr_scale);
  return JND_OK;
}

jnd_status jnd_display_check(const jnd_display *d) {
  char who[40];
  if (!memchr(d->name, 0, sizeof d->name))
    return jnd_fail(JND_ERR_ARG, "display: its name is not a string of under %d bytes", (int)sizeof d->name);
  if (!within(d->ppd, 1, 1000))
    return jnd_fail(JND_ERR_ARG, "%s: pixels per degree must be in [1, 1000], not %g", label(d, who), d->ppd);
  jnd_status s = check_light(d);
  if (s != JND_OK) return s;
  /* the geometry the ppd came from: none (0, a ppd given directly), a
   * resolution alone (a screen's pixels) or a whole screen */
  if (!within(d->diagonal_in, 0, 1e6) || !within(d->distance_m, 0, 1e6) || d->width_px < 0 || d->height_px < 0)
    return jnd_fail(JND_ERR_ARG, "%s: diagonal (%g in), distance (%g m) and resolution (%dx%d) must be finite, not negative",
                    label(d, who), d->diagonal_in, d->distance_m, d->width_px, d->height_px);
  if ((d->diagonal_in > 0 || d->distance_m > 0) &&
      !(d->diagonal_in > 0 && d->distance_m > 0 && d->width_px > 0 && d->height_px > 0))
    return jnd_fail(JND_ERR_ARG, "%s: a screen's geometry needs a diagonal (%g in), a distance (%g m) and a resolution (%dx%d)",
                    label(d, who), d->diagonal_in, d->distance_m, d->width_px, d->height_px);
  if (d->task != JND_TASK_SIDE_BY_SIDE && d->task != JND_TASK_FLICKER)
    return jnd_fail(JND_ERR_ARG, "%s: unknown viewing task %d (side-by-side or flicker)", label(d, who), (int)d->task);
  return JND_OK;
}

enum { SPAN = 8192 };

/* One span of sRGB signal → cd/m². A span of 8-bit codes (most inputs) goes
 * through a table of the 256 luminances: the codes in a vectorised loop, the
 * look-ups in a scalar one (GCC emits no gathers for generic x86). Other
 * signals take the EOTF with the fast pow (within 1e-5 of libm's). Alpha
 * composites the linear signal over the display's black. */
JND_HOT static void srgb_span(const float *src, const float *alpha, const float lum[256], float range,
                              float black, float refl, float *dst, size_t n) {
  int code[SPAN];
  float worst = 0.0f; /* the largest distance of a signal from its nearest code */
#pragma omp simd reduction(max : worst)
  for (size_t i = 0; i < n; i++) {
    float v = src[i];
    float q = (v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v) * 255.0f;
    /* the nearest code by adding and subtracting 1.5·2^23: GCC turns
     * (float)(int)(q + 0.5f) into a rounding call that stops vectorisation
     * in the AVX2 version */
    float k = (q + 12582912.0f) - 12582912.0f;
    code[i] = (int)k;
    worst = jnd_maxf(worst, fabsf(q - k));
  }
  if (worst < 1e-3f && !alpha) {
    for (size_t i = 0; i < n; i++) dst[i] = lum[code[i]];
    return;
  }
  /* separate loops, not a conditional load of alpha in one: masked loads
   * through a null pointer are very slow on some CPUs */
  if (!alpha) {
#pragma omp simd
    for (size_t i = 0; i < n; i++) {
      dst[i] = range * jnd_srgb_decode(src[i]) + black + refl;
    }
    return;
  }
#pragma omp simd
  for (size_t i = 0; i < n; i++) {
    float lin = jnd_srgb_decode(src[i]);
    float a = alpha[i] < 0.0f ? 0.0f : alpha[i] > 1.0f ? 1.0f : alpha[i];
    dst[i] = range * lin * a + black + refl;
  }
}

/* one channel of the display model: signal → cd/m² */
static void display_channel(const float *src, const float *alpha, jnd_encoding enc, const float lum[256],
                            float range, float black, float scale, float refl, float *dst, ptrdiff_t n) {
  if (enc != JND_ENCODING_SRGB) {
    /* OpenEXR colour is premultiplied by alpha: it already is the composite over black */
#pragma omp parallel for schedule(static)
    for (ptrdiff_t i = 0; i < n; i++) dst[i] = jnd_maxf(src[i], 0.0f) * scale + refl;
    return;
  }
#pragma omp parallel for schedule(static)
  for (ptrdiff_t i = 0; i < n; i += SPAN)
    srgb_span(src + i, alpha ? alpha + i : NULL, lum, range, black, refl, dst + i,
              (size_t)(n - i < SPAN ? n - i : SPAN));
}

/* the display's light: its range above black, its black and the ambient
 * light it reflects, cd/m² */
typedef struct {
  float range, black, refl;
} display_light;

static display_light light_of(const jnd_display *d) {
  display_light l;
  float refl = (float)(d->reflectivity * d->ambient_lux / M_PI); /* Lambertian screen */
  float range = (float)(d->peak_cdm2 - d->black_cdm2), black = (float)d->black_cdm2;
  l.range = range;
  l.black = black;
  l.refl = refl;
  return l;
}

/* the luminance of each 8-bit sRGB code on display d */
static void code_luminances(const jnd_display *d, float lum[256]) {
  const display_light l = light_of(d);
  for (int k = 0; k < 256; k++) lum[k] = l.range * jnd_srgb_decode(k / 255.0f) + l.black + l.refl;
}

jnd_status jnd_display_code_luminances(const jnd_display *d, float lum[256]) {
  jnd_status st = check_light(d);
  if (st == JND_OK) code_luminances(d, lum);
  return st;
}

jnd_status jnd_display_apply(const jnd_display *d, const jnd_image *in, jnd_encoding enc, int has_alpha,
                             jnd_image *out) {
  jnd_status st = check_light(d);
  if (st != JND_OK) return st;
  if (in->c < 1 || in->c > 4) return jnd_fail(JND_ERR_ARG, "display: images need 1–4 channels, not %d", in->c);
  int colour = in->c >= 3;
  int alpha_ch = has_alpha ? (in->c == 2 ? 1 : in->c == 4 ? 3 : -1) : -1;
  const ptrdiff_t n = (ptrdiff_t)in->w * in->h;
  /* In place when the caller passes out == in and the colour planes can stay
   * where they are (RGB, RGBA): the planes are rewritten one by one, alpha
   * last, so no second full-size image is touched. */
  const int in_place = out == in && in->c >= 3;
  jnd_image tmp;
  if (in_place) {
    tmp = *in;
  } else {
    jnd_status s = jnd_image_alloc(&tmp, in->w, in->h, 3);
    if (s != JND_OK) return s;
  }
  const display_light l = light_of(d);
  const float refl = l.refl, range = l.range, black = l.black;
  const float *alpha = alpha_ch >= 0 ? jnd_image_plane(in, alpha_ch) : NULL;
  float lum[256]; /* the luminance of each 8-bit sRGB code */
  code_luminances(d, lum);
  for (int ch = 0; ch < 3; ch++)
    display_channel(jnd_image_plane(in, colour ? ch : 0), alpha, enc, lum, range, black, (float)d->exr_scale,
                    refl, jnd_image_plane(&tmp, ch), n);
  if (in_place) {
    out->c = 3; /* an alpha plane, if any, stays allocated behind the three colour planes */
    return JND_OK;
  }
  if (out == in) jnd_image_free(out);
  *out = tmp;
  return JND_OK;
}
