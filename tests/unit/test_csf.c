/* `jnd csf`'s data: castleCSF-format rows, their colour directions and backgrounds. */
#include "test.h"
#include "core/core.h"
#include "jnd.h"
#include "tasks/tasks.h"

/* CIE 1976 u′v′ and Y of a CIE 2006 LMS colour */
static void uvY(const double lms[3], double *u, double *v, double *Y) {
  double xyz[3];
  jnd_csf_lms_to_xyz(lms, xyz);
  double d = xyz[0] + 15 * xyz[1] + 3 * xyz[2];
  *u = 4 * xyz[0] / d;
  *v = 9 * xyz[1] / d;
  *Y = xyz[1];
}

/* kong2018's background BC2 (castleCSF backgrounds.csv, bkg_id 51) */
static const double BC2[3] = {29.3697577136479, 14.4939157378042, 8.17137309386128};

/* the CIE 2006 LMS -> XYZ matrix against castleCSF's own data: its D65
 * background of 50 cd/m² (backgrounds.csv, bkg_id 1: LMS 36.737, 15.814,
 * 1.041) is CIE D65's white point (95.047, 100, 108.883) at Y = 50 */
TEST(castlecsf_d65_background_is_d65_white_at_its_luminance) {
  const double d65[3] = {36.7372648518233, 15.8141236515338, 1.04100192534928};
  double xyz[3];
  jnd_csf_lms_to_xyz(d65, xyz);
  CHECK_NEAR(xyz[0], 0.5 * 95.047, 0.01);
  CHECK_NEAR(xyz[1], 50.0, 0.01);
  CHECK_NEAR(xyz[2], 0.5 * 108.883, 0.01);
}

TEST(uv_directions_are_unit_vectors_at_constant_luminance) {
  for (int k = 0; k < 4; k++) {
    double d[3];
    jnd_csf_uv_direction(BC2, 45.0 * k, d);
    CHECK_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-12);
    double xyz[3];
    jnd_csf_lms_to_xyz(d, xyz);
    CHECK_NEAR(xyz[1], 0.0, 1e-12); /* no change of luminance Y */
  }
}

TEST(uv_directions_move_the_chromaticity_along_their_angle_45_degrees_apart) {
  double u0, v0, Y0;
  uvY(BC2, &u0, &v0, &Y0);
  double prev = 0;
  for (int k = 0; k < 4; k++) {
    double d[3], p[3], u, v, Y;
    jnd_csf_uv_direction(BC2, 45.0 * k, d);
    for (int i = 0; i < 3; i++) p[i] = BC2[i] + 1e-4 * d[i];
    uvY(p, &u, &v, &Y);
    /* a symmetric modulation has no sign: the angle is taken modulo 180° */
    double a = fmod(atan2(v - v0, u - u0) * 180 / M_PI + 360.0, 180.0);
    if (a > 179.9) a -= 180;
    CHECK_NEAR(a, 45.0 * k, 1e-3);
    if (k > 0) CHECK_NEAR(a - prev, 45.0, 1e-3);
    prev = a;
    CHECK_NEAR(Y, Y0, 1e-9 * Y0);
  }
}

TEST(uv_0_is_the_same_cone_direction_on_every_background) {
  /* moving along u′ at constant v′ and Y keeps X/Z-independent ratios: the
   * data's authors list (0.8044, −0.5935, −0.0255) for uv_0 on all nine */
  const double other[3] = {33.8088386942858, 4.99952850800758, 0.349323251314877};
  double a[3], b[3];
  jnd_csf_uv_direction(BC2, 0, a);
  jnd_csf_uv_direction(other, 0, b);
  for (int i = 0; i < 3; i++) CHECK_NEAR(fabs(a[i]), fabs(b[i]), 1e-9);
  CHECK_NEAR(fabs(a[0]), 0.8044, 1e-4);
  CHECK_NEAR(fabs(a[1]), 0.5935, 1e-4);
  CHECK_NEAR(fabs(a[2]), 0.0255, 1e-4);
}

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

static const char *COLORS = "col_dir_id,L_delta,M_delta,S_delta,dataset\n"
                            "1,0.918203011274591,0.395254682570263,0.0260185701481506,x\n"
                            "2,0.904788433511642,0.419896446537257,0.0710272114680906,colorfest\n"
                            "3,0.762860488743917,-0.646494144848117,-0.00944433112997181,colorfest\n"
                            "4,0.450449715432406,0.274890824273731,0.84942927227461,colorfest\n";
static const char *BKGS = "bkg_id,L,M,S\n"
                          "1,36.7372648518233,15.8141236515338,1.04100192534928\n"
                          "50,23.560694445981,12.3175967808694,0.373936701009002\n"
                          "51,29.3697577136479,14.4939157378042,8.17137309386128\n"
                          "121,68.6861910348092,31.3138089651908,2.38787121229485\n";
#define HEAD "luminance,s_frequency,t_frequency,area,ge_sigma,eccentricity,orientation,col_dir_id,bkg_id,stimulus,sensitivity,dataset\n"

static jnd_status read_rows(const char *rows, jnd_csf_data *d) {
  char data[1200], col[1200], bkg[1200];
  snprintf(data, sizeof data, "%s/csf_data.csv", test_tmp_dir());
  snprintf(col, sizeof col, "%s/csf_colors.csv", test_tmp_dir());
  snprintf(bkg, sizeof bkg, "%s/csf_bkgs.csv", test_tmp_dir());
  char text[4096];
  snprintf(text, sizeof text, HEAD "%s", rows);
  write_file(data, text);
  write_file(col, COLORS);
  write_file(bkg, BKGS);
  return jnd_csf_data_read(data, col, bkg, d);
}

TEST(published_directions_are_derived_and_flagged) {
  jnd_csf_data d;
  CHECK_OK(read_rows("35,0,2,78.5,0,0,0,59,51,disk,500,kong2018\n"
                     "35,0,2,78.5,0,0,0,61,51,disk,300,kong2018\n"
                     "100,0,0,50.3,0,10,0,115,121,disk,200,hansen2009\n"
                     "50,2,0,0.785,0.5,0,0,1,1,gabor,200,x\n",
                     &d));
  CHECK(d.nrows == 4 && d.ndatasets == 3);
  if (d.nrows == 4) {
    CHECK(d.rows[0].derived_direction && d.rows[1].derived_direction && d.rows[2].derived_direction);
    CHECK(!d.rows[3].derived_direction);
    double want[3];
    jnd_csf_uv_direction(BC2, 90, want); /* id 61 = 59 + 2: uv_90 on background 51 */
    for (int i = 0; i < 3; i++) CHECK_NEAR(d.rows[1].st.dir_lms[i], want[i], 1e-12);
    CHECK_NEAR(d.rows[2].st.dir_lms[0], 0.762860488743917, 1e-12); /* L−M: colorfest's id 3 */
    CHECK(d.rows[0].st.t_frequency == 2 && d.rows[2].st.eccentricity == 10);
  }
  jnd_csf_data_free(&d);
}

TEST(an_unlisted_direction_is_an_error_naming_the_line) {
  jnd_csf_data d;
  CHECK_STATUS(read_rows("50,2,0,0.785,0.5,0,0,1,1,gabor,200,x\n50,2,0,0.785,0.5,0,0,9,1,gabor,200,x\n", &d),
               JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "line 3") && strstr(jnd_last_error(), "colour direction 9"));
  /* a kong2018 id on another background than the one it belongs to */
  CHECK_STATUS(read_rows("35,0,2,78.5,0,0,0,55,51,disk,500,kong2018\n", &d), JND_ERR_FORMAT);
  CHECK(strstr(jnd_last_error(), "belongs to background 50") != NULL);
  /* the same ids in another data set are not derived */
  CHECK_STATUS(read_rows("35,0,2,78.5,0,0,0,55,50,disk,500,other\n", &d), JND_ERR_FORMAT);
}


/* ---- the stimuli a threshold search synthesises (csf_check.c) ---- */

/* an achromatic stimulus on castleCSF's D65 background at L cd/m² */
static jnd_csf_stimulus achromatic(jnd_stim_kind kind, double L) {
  const double d65[3] = {36.7372648518233, 15.8141236515338, 1.04100192534928}; /* 50 cd/m² */
  jnd_csf_stimulus s;
  memset(&s, 0, sizeof s);
  s.kind = kind;
  s.luminance = L;
  for (int i = 0; i < 3; i++) s.bkg_lms[i] = s.dir_lms[i] = d65[i] * L / 50.0;
  return s;
}

/* the profile's weight: Σ g / ppd², degrees² (plane Y of the modulation over
 * its value at a full-contrast pixel) */
static double profile_area(const jnd_image *stim, double ppd, double peak, double at_least) {
  const float *y = jnd_image_plane(stim, 1);
  double a = 0;
  for (size_t i = 0; i < (size_t)stim->w * stim->h; i++)
    if (y[i] / peak >= at_least) a += at_least > 0 ? 1 : y[i] / peak;
  return a / (ppd * ppd);
}

TEST(the_background_is_at_the_data_luminance_and_the_modulation_at_unit_rms_cone_contrast) {
  jnd_csf_stimulus s = achromatic(JND_STIM_DISK, 20.0);
  s.area = 1.0;
  double ppd;
  jnd_image bg, stim;
  CHECK_OK(csf_stimulus_images(&s, &ppd, &bg, &stim));
  /* Y is the luminance, cd/m², everywhere on the background */
  CHECK_NEAR(jnd_image_plane(&bg, 1)[0], 20.0, 1e-4);
  CHECK_NEAR(jnd_image_plane(&bg, 1)[(size_t)bg.w * bg.h - 1], 20.0, 1e-4);
  /* an achromatic direction at unit RMS cone contrast: each cone +100%, so
   * the disc's centre is the background's luminance again */
  size_t c = (size_t)(stim.h / 2) * stim.w + stim.w / 2;
  CHECK_NEAR(jnd_image_plane(&stim, 1)[c], 20.0, 1e-3);
  jnd_image_free(&bg);
  jnd_image_free(&stim);
}

TEST(a_disc_covers_its_area_and_a_gabor_its_gaussian_volume) {
  double ppd;
  jnd_image bg, stim;
  /* a disc of 1 deg²: radius sqrt(1/π) at full contrast (a square of side 1
   * would be π/4 of it) */
  jnd_csf_stimulus d = achromatic(JND_STIM_DISK, 50.0);
  d.area = 1.0;
  CHECK_OK(csf_stimulus_images(&d, &ppd, &bg, &stim));
  double full = profile_area(&stim, ppd, 50.0, 0.999);
  CHECK(fabs(full - 1.0) < 0.04);
  jnd_image_free(&bg);
  jnd_image_free(&stim);
  /* a Gabor with sigma 0.5° and no carrier: exp(−r²/2σ²) sums to 2πσ² */
  jnd_csf_stimulus g = achromatic(JND_STIM_GABOR, 50.0);
  g.ge_sigma = 0.5;
  CHECK_OK(csf_stimulus_images(&g, &ppd, &bg, &stim));
  CHECK_NEAR(profile_area(&stim, ppd, 50.0, 0), 2 * M_PI * 0.25, 0.02 * 2 * M_PI * 0.25);
  jnd_image_free(&bg);
  jnd_image_free(&stim);
}

TEST(a_grating_is_sampled_with_at_least_four_samples_a_cycle) {
  /* 4√2 a cycle where the size allows (docs/csf.md): half an octave below
   * every pyramid level's Nyquist frequency, never near aliasing */
  jnd_csf_stimulus s = achromatic(JND_STIM_GRATING, 50.0);
  s.area = 4.0;
  for (double f = 2; f <= 16; f *= 2) {
    s.s_frequency = f;
    double ppd, half, taper;
    jnd_csf_sampling(&s, &ppd, &half, &taper);
    CHECK(ppd / f >= 4.0);
    CHECK_NEAR(ppd, 4 * M_SQRT2 * f, 1e-9);
  }
}

RUN_TESTS(castlecsf_d65_background_is_d65_white_at_its_luminance, uv_directions_are_unit_vectors_at_constant_luminance,
          uv_directions_move_the_chromaticity_along_their_angle_45_degrees_apart,
          uv_0_is_the_same_cone_direction_on_every_background, published_directions_are_derived_and_flagged,
          an_unlisted_direction_is_an_error_naming_the_line,
          the_background_is_at_the_data_luminance_and_the_modulation_at_unit_rms_cone_contrast,
          a_disc_covers_its_area_and_a_gabor_its_gaussian_volume, a_grating_is_sampled_with_at_least_four_samples_a_cycle)
