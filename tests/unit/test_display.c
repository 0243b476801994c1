/* The display presets and the display model's constants (004 §3.1, first
 * stage; docs/model.md "Display model"), recomputed here from the physical
 * description docs/model.md gives of each preset, so that a slip in one of
 * its constants (a size, a resolution, a distance, a luminance) changes a
 * number a check compares with a value computed without the code. Every
 * decision of jnd depends on the ppd a preset gives. */
#include <math.h>
#include <stddef.h>

#include "jnd.h"
#include "test.h"

/* docs/model.md: the presets as physical screens */
static const struct {
  const char *name;
  double diagonal_in;
  int w, h;
  double distance_m, peak;
} presets[] = {
    {"standard-fhd", 24, 1920, 1080, 0.60, 200},
    {"standard-4k", 27, 3840, 2160, 0.60, 200},
    {"phone", 6.1, 2532, 1170, 0.30, 500},
    {"laptop", 14, 2560, 1600, 0.50, 300},
};

/* Pixels per degree at the screen centre, by another route than the code's
 * (which takes the angle of one pixel): the number of pixels one degree
 * centred on the line of sight covers, 2·d·tan(½°) / pitch, with the pixel
 * pitch from the diagonal in inches (25.4 mm) over the diagonal in pixels.
 * The two agree to a few parts in 10⁵ (the tangent's curvature over one
 * pixel against over one degree). */
static double ppd_by_hand(double diagonal_in, int w, int h, double distance_m) {
  double pitch_m = diagonal_in * 25.4e-3 / hypot(w, h);
  return 2 * distance_m * tan(0.5 * M_PI / 180) / pitch_m;
}

TEST(each_preset_ppd_is_recomputed_from_its_size_resolution_and_distance) {
  for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++) {
    jnd_display d;
    CHECK_OK(jnd_display_preset(presets[i].name, &d));
    double want = ppd_by_hand(presets[i].diagonal_in, presets[i].w, presets[i].h, presets[i].distance_m);
    fprintf(stderr, "%s: ppd %.4f, by hand %.4f\n", presets[i].name, d.ppd, want);
    CHECK(fabs(d.ppd / want - 1) < 1e-4);
    /* the geometry it reports is the preset's */
    CHECK(d.width_px == presets[i].w && d.height_px == presets[i].h);
    CHECK_NEAR(d.diagonal_in, presets[i].diagonal_in, 1e-12);
    CHECK_NEAR(d.distance_m, presets[i].distance_m, 1e-12);
    CHECK_NEAR(d.peak_cdm2, presets[i].peak, 1e-12);
    CHECK(strcmp(d.name, presets[i].name) == 0);
    /* and the public formula is the same route */
    CHECK_NEAR(jnd_ppd_from_geometry(presets[i].diagonal_in, presets[i].w, presets[i].h, presets[i].distance_m),
               d.ppd, 1e-12);
  }
  /* docs/model.md's round number for the default (its 67.4 for
   * standard-4k is 67.28 by either route) */
  jnd_display d;
  CHECK_OK(jnd_display_preset("standard-fhd", &d));
  CHECK_NEAR(d.ppd, 37.8, 0.05);
  /* vr is given as 20 ppd, 100 cd/m², no geometry */
  CHECK_OK(jnd_display_preset("vr", &d));
  CHECK_NEAR(d.ppd, 20, 0);
  CHECK_NEAR(d.peak_cdm2, 100, 0);
  CHECK(d.diagonal_in == 0 && d.width_px == 0);
}

/* ppd is linear in the distance when the angle is small, and grows with the
 * resolution at a fixed size: the laws a viewing condition follows */
TEST(ppd_grows_with_distance_and_resolution_and_falls_with_size) {
  double a = jnd_ppd_from_geometry(24, 1920, 1080, 0.6), b = jnd_ppd_from_geometry(24, 1920, 1080, 1.2);
  CHECK(fabs(b / a - 2) < 1e-4);
  CHECK(jnd_ppd_from_geometry(24, 3840, 2160, 0.6) > 1.99 * a);
  CHECK(jnd_ppd_from_geometry(48, 1920, 1080, 0.6) < 0.51 * a);
  /* a portrait screen is the same screen */
  CHECK_NEAR(jnd_ppd_from_geometry(6.1, 1170, 2532, 0.3), jnd_ppd_from_geometry(6.1, 2532, 1170, 0.3), 1e-12);
}

/* docs/model.md: every preset is a 1000:1 panel, in a dark room, with a
 * matte reflectivity of 0.005, and EXR values are cd/m² */
TEST(every_preset_is_a_1000_to_1_matte_panel_in_a_dark_room) {
  const char *const *names = jnd_display_preset_names();
  int n = 0;
  for (; names[n]; n++) {
    jnd_display d;
    CHECK_OK(jnd_display_preset(names[n], &d));
    CHECK_NEAR(d.black_cdm2, d.peak_cdm2 / 1000, 1e-12);
    CHECK(d.ambient_lux == 0);
    CHECK_NEAR(d.reflectivity, 0.005, 0);
    CHECK_NEAR(d.exr_scale, 1, 0);
    CHECK(d.ppd > 0);
  }
  CHECK(n == 5);
  /* the default display is standard-fhd */
  jnd_display def, fhd;
  jnd_display_defaults(&def);
  CHECK_OK(jnd_display_preset("standard-fhd", &fhd));
  CHECK(strcmp(def.name, "standard-fhd") == 0);
  CHECK_NEAR(def.ppd, fhd.ppd, 0);
  CHECK_NEAR(def.peak_cdm2, fhd.peak_cdm2, 0);
  CHECK_NEAR(def.black_cdm2, fhd.black_cdm2, 0);
  CHECK_STATUS(jnd_display_preset("standard", &def), JND_ERR_ARG);
}

/* 004 §3.1: L = (peak − black)·EOTF(V) + black, recomputed with the sRGB
 * curve written out here, for each preset's luminances and for signals
 * between the 8-bit codes (the formula path) as well as on them (the table) */
TEST(display_model_follows_its_formula_on_every_preset) {
  const char *const *names = jnd_display_preset_names();
  for (int i = 0; names[i]; i++) {
    jnd_display d;
    CHECK_OK(jnd_display_preset(names[i], &d));
    d.ambient_lux = 100;
    static const float sig[] = {0, 0.02f, 0.5f, 128 / 255.0f, 0.7071f, 1};
    enum { N = sizeof sig / sizeof sig[0] };
    for (int path = 0; path < 2; path++) {
      jnd_image in, out;
      CHECK_OK(jnd_image_alloc(&in, N, 1, 1));
      /* path 0: one of them is not a code, so the formula runs for all;
       * path 1: all codes (the table) */
      for (int k = 0; k < N; k++) in.data[k] = path ? roundf(sig[k] * 255) / 255 : sig[k];
      CHECK_OK(jnd_display_apply(&d, &in, JND_ENCODING_SRGB, 0, &out));
      for (int k = 0; k < N; k++) {
        double v = in.data[k], lin = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
        double want = (d.peak_cdm2 - d.black_cdm2) * lin + d.black_cdm2 + 0.005 * 100 / M_PI;
        for (int ch = 0; ch < 3; ch++) CHECK(fabs(jnd_image_plane(&out, ch)[k] / want - 1) < 2e-4);
      }
      jnd_image_free(&in);
      jnd_image_free(&out);
    }
  }
}

/* A display is checked where it is accepted (jnd_display_check; the model
 * and the display's transform): every quantity NaN, infinite, negative or
 * out of its range is JND_ERR_ARG with one line naming the display and the
 * quantity, never a model or an image made of it */
TEST(a_display_with_a_nan_inf_or_negative_quantity_is_refused_in_one_line) {
  const double nan = NAN, inf = INFINITY;
  static const struct {
    size_t off;
    double lo_bad, hi_bad; /* just outside the range, below and above (0: none) */
    const char *word;
  } q[] = {
      {offsetof(jnd_display, ppd), 0.99, 1000.5, "pixels per degree"},
      {offsetof(jnd_display, peak_cdm2), 0.009, 100001, "peak"},
      {offsetof(jnd_display, black_cdm2), -1e-9, 0, "black"},
      {offsetof(jnd_display, ambient_lux), -1e-9, 200001, "ambient"},
      {offsetof(jnd_display, reflectivity), -1e-9, 1.000001, "reflectivity"},
      {offsetof(jnd_display, exr_scale), 1e-10, 2e9, "exr_scale"},
      {offsetof(jnd_display, diagonal_in), -1, 0, "diagonal"},
      {offsetof(jnd_display, distance_m), -1, 0, "distance"},
  };
  jnd_image in;
  CHECK_OK(jnd_image_alloc(&in, 4, 4, 3));
  for (size_t i = 0; i < 48; i++) in.data[i] = 0.5f;
  jnd_display good;
  CHECK_OK(jnd_display_preset("phone", &good));
  CHECK_OK(jnd_display_check(&good));
  for (size_t k = 0; k < sizeof q / sizeof q[0]; k++) {
    const double bad[] = {nan, inf, -inf, -1, q[k].lo_bad, q[k].hi_bad};
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
      if (bad[b] == 0 && b >= 4) continue; /* no bound on that side */
      jnd_display d = good;
      *(double *)((char *)&d + q[k].off) = bad[b];
      CHECK_STATUS(jnd_display_check(&d), JND_ERR_ARG);
      const char *e = jnd_last_error();
      fprintf(stderr, "  %s = %g: %s\n", q[k].word, bad[b], e);
      CHECK(strncmp(e, "display phone: ", 15) == 0 && strstr(e, q[k].word) && !strchr(e, '\n'));
      /* the model refuses it with the same line */
      jnd_model_params mp;
      jnd_model_defaults(&mp);
      mp.display = d;
      jnd_model *m = (jnd_model *)&mp; /* not NULL: the call must set it */
      CHECK_STATUS(jnd_model_create(&mp, &m), JND_ERR_ARG);
      CHECK(m == NULL && strstr(jnd_last_error(), q[k].word));
      /* the transform refuses the quantities it uses and makes no image */
      if (k >= 1 && k <= 5) {
        jnd_image out = {0};
        CHECK_STATUS(jnd_display_apply(&d, &in, JND_ENCODING_LINEAR, 0, &out), JND_ERR_ARG);
        CHECK(out.data == NULL && strstr(jnd_last_error(), q[k].word));
      }
    }
  }
  /* black must stay below peak; the black a preset gives is inside */
  jnd_display d = good;
  d.black_cdm2 = d.peak_cdm2;
  CHECK_STATUS(jnd_display_check(&d), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "need 0 <= black (500) < peak (500)") != NULL);
  /* the geometry: a diagonal without a distance or a resolution is no screen;
   * a resolution alone (a screen's pixels, ppd given) and none at all are */
  d = good;
  d.distance_m = 0;
  CHECK_STATUS(jnd_display_check(&d), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "geometry") != NULL);
  d = good;
  d.width_px = -1;
  CHECK_STATUS(jnd_display_check(&d), JND_ERR_ARG);
  d = good;
  d.diagonal_in = d.distance_m = 0;
  CHECK_OK(jnd_display_check(&d));
  d.width_px = d.height_px = 0;
  CHECK_OK(jnd_display_check(&d));
  /* a task outside the enum, a name without its end */
  d = good;
  d.task = (jnd_viewing_task)7;
  CHECK_STATUS(jnd_display_check(&d), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "task") != NULL);
  d = good;
  memset(d.name, 'x', sizeof d.name);
  CHECK_STATUS(jnd_display_check(&d), JND_ERR_ARG);
  CHECK(strncmp(jnd_last_error(), "display: ", 9) == 0);
  /* every preset and the edges of each range pass */
  const char *const *names = jnd_display_preset_names();
  for (int i = 0; names[i]; i++) {
    CHECK_OK(jnd_display_preset(names[i], &d));
    CHECK_OK(jnd_display_check(&d));
  }
  d = good;
  d.ppd = 1;
  d.peak_cdm2 = 0.01;
  d.black_cdm2 = 0;
  d.ambient_lux = 200000;
  d.reflectivity = 1;
  d.exr_scale = 1e9;
  CHECK_OK(jnd_display_check(&d));
  d.ppd = 1000;
  d.exr_scale = 1e-9;
  d.peak_cdm2 = 100000;
  CHECK_OK(jnd_display_check(&d));
  jnd_image_free(&in);
}

RUN_TESTS(each_preset_ppd_is_recomputed_from_its_size_resolution_and_distance,
          ppd_grows_with_distance_and_resolution_and_falls_with_size,
          every_preset_is_a_1000_to_1_matte_panel_in_a_dark_room, display_model_follows_its_formula_on_every_preset,
          a_display_with_a_nan_inf_or_negative_quantity_is_refused_in_one_line)
