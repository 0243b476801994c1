/* Colour stages of 004 §3.1: linear RGB → CIE XYZ → Hunt–Pointer–Estévez LMS. */
#include <stddef.h>

#include "core/core.h"
#include "vision/vision.h"

/* linear sRGB (Rec.709 primaries, D65 white) to XYZ, IEC 61966-2-1 */
static const double RGB2XYZ[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                     {0.2126729, 0.7151522, 0.0721750},
                                     {0.0193339, 0.1191920, 0.9503041}};

/* 004 §3.1: Hunt–Pointer–Estévez cone fundamentals (Fairchild 2004) */
static const double XYZ2LMS[3][3] = {{0.40024, 0.70760, -0.08081},
                                     {-0.22630, 1.16532, 0.04570},
                                     {0.0, 0.0, 0.91822}};

/* a span of pixels through the matrix a, in place */
JND_HOT static void apply3_span(float *restrict p0, float *restrict p1, float *restrict p2, size_t n,
                                const float a[9]) {
  for (size_t i = 0; i < n; i++) {
    float x = p0[i], y = p1[i], z = p2[i];
    p0[i] = a[0] * x + a[1] * y + a[2] * z;
    p1[i] = a[3] * x + a[4] * y + a[5] * z;
    p2[i] = a[6] * x + a[7] * y + a[8] * z;
  }
}

static void apply3(jnd_image *img, const double m[3][3]) {
  size_t n = (size_t)img->w * img->h;
  float *p0 = jnd_image_plane(img, 0), *p1 = jnd_image_plane(img, 1), *p2 = jnd_image_plane(img, 2);
  float a[9];
  for (int i = 0; i < 9; i++) a[i] = (float)m[i / 3][i % 3];
  const size_t span = 16384;
  const ptrdiff_t nspan = (ptrdiff_t)((n + span - 1) / span);
#pragma omp parallel for schedule(static)
  for (ptrdiff_t k = 0; k < nspan; k++) {
    const size_t i = (size_t)k * span;
    apply3_span(p0 + i, p1 + i, p2 + i, n - i < span ? n - i : span, a);
  }
}

void jnd_rgb_to_xyz(jnd_image *img) { apply3(img, RGB2XYZ); }
void jnd_xyz_to_lms(jnd_image *img) { apply3(img, XYZ2LMS); }

/* the product matrix of the two above */
static void rgb_to_lms_matrix(double m[3][3]) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      m[i][j] = XYZ2LMS[i][0] * RGB2XYZ[0][j] + XYZ2LMS[i][1] * RGB2XYZ[1][j] + XYZ2LMS[i][2] * RGB2XYZ[2][j];
}

/* both at once: one pass over the image with the product matrix */
void jnd_rgb_to_lms(jnd_image *img) {
  double m[3][3];
  rgb_to_lms_matrix(m);
  apply3(img, m);
}

/* the codes' values, a table look-up a sample: JND_HOT_AVX2, as GCC's
 * AVX-512 version of such a loop is twice as slow (core.h) */
JND_HOT_AVX2 static void codes_to_rows(const unsigned char *restrict px, const float *restrict value,
                                       float *restrict r, float *restrict g, float *restrict b, size_t w) {
  for (size_t x = 0; x < w; x++) {
    r[x] = value[px[3 * x]];
    g[x] = value[px[3 * x + 1]];
    b[x] = value[px[3 * x + 2]];
  }
}

void jnd_rgb8_lms_row(const unsigned char *px, const float value[256], const float a[9], float *const out[3],
                      size_t w) {
  codes_to_rows(px, value, out[0], out[1], out[2], w);
  apply3_span(out[0], out[1], out[2], w, a);
}

void jnd_rgb_to_lms_weights(float a[9]) {
  double m[3][3];
  rgb_to_lms_matrix(m);
  for (int i = 0; i < 9; i++) a[i] = (float)m[i / 3][i % 3];
}

void jnd_lms_luminance_weights(double w[3]) {
  /* Y row of the inverse of XYZ2LMS, by cofactors */
  const double(*m)[3] = XYZ2LMS;
  double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  w[0] = -(m[1][0] * m[2][2] - m[1][2] * m[2][0]) / det;
  w[1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
  w[2] = -(m[0][0] * m[1][2] - m[0][2] * m[1][0]) / det;
}

/* One colour from HPE LMS back to XYZ: the inverse of XYZ2LMS by cofactors */
void jnd_lms_to_xyz_one(const double lms[3], double xyz[3]) {
  const double(*m)[3] = XYZ2LMS;
  double inv[3][3];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      inv[i][j] = m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    }
  const double det = m[0][0] * inv[0][0] + m[0][1] * inv[1][0] + m[0][2] * inv[2][0];
  for (int i = 0; i < 3; i++) xyz[i] = (inv[i][0] * lms[0] + inv[i][1] * lms[1] + inv[i][2] * lms[2]) / det;
}
