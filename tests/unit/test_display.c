/* The display presets and the display model's constants (004 §3.1, first
 * stage; docs/model.md "Display model"), recomputed here from the physical
 * description docs/model.md gives of each preset, so that a slip in one of
 * its constants (a size, a resolution, a distance, a luminance) changes a
 * number a check compares with a value computed without the code. Every
 * decision of jnd depends on the ppd a preset gives. */
#include <math.h>

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

RUN_TESTS(each_preset_ppd_is_recomputed_from_its_size_resolution_and_distance,
          ppd_grows_with_distance_and_resolution_and_falls_with_size,
          every_preset_is_a_1000_to_1_matte_panel_in_a_dark_room, display_model_follows_its_formula_on_every_preset)
