/* castleCSF-format threshold data (`jnd csf`): the rows of a data set with
 * their colour directions and backgrounds resolved into stimuli.
 *
 * Every row names a colour direction (col_dir_id) and a background (bkg_id)
 * that the two companion files list. Two data sets of the collection define
 * their directions in their publications instead of listing them, and the
 * directions are derived here from those definitions (docs/csf.md):
 *   kong2018   — each background has four modulations at constant luminance
 *                along the angles 0°, 45°, 90°, 135° of the CIE 1976 u′v′
 *                chromaticity diagram (ids 55–90, four per background 50–58);
 *   hansen2009 — C1, C2, C3 (ids 114–116) are the DKL cardinal directions at
 *                D65 (achromatic, L−M, S), which castleCSF expresses by the
 *                same vectors as colorfest's cardinal stimuli (ids 2–4).
 * Any other direction missing from the file is an error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"

/* castleCSF's CIE 2006 LMS → XYZ matrix (derived for LED-LCD spectra); the
 * same one turns every stimulus into XYZ (csf_check.c) */
const double jnd_csf_lms2006_xyz[3][3] = {{2.629129278399650, -3.780202391780134, 10.294956387893450},
                                          {0.865649062438827, 1.215555811642301, -0.984175688105352},
                                          {-0.008886561474676, 0.081612628990755, 51.371024830897888}};

static void mat3_apply(const double m[3][3], const double v[3], double out[3]) {
  for (int r = 0; r < 3; r++) out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
}

void jnd_csf_lms_to_xyz(const double lms[3], double xyz[3]) { mat3_apply(jnd_csf_lms2006_xyz, lms, xyz); }

static void mat3_inverse(const double m[3][3], double inv[3][3]) {
  double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      /* cofactor of (c, r), transposed */
      int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
      inv[r][c] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
    }
}

void jnd_csf_uv_direction(const double bkg_lms[3], double angle_deg, double dir_lms[3]) {
  double xyz[3];
  jnd_csf_lms_to_xyz(bkg_lms, xyz);
  const double X = xyz[0], Y = xyz[1], Z = xyz[2], den = X + 15 * Y + 3 * Z;
  const double u = 4 * X / den, v = 9 * Y / den;
  /* at fixed Y: X = Y·9u′/(4v′), Z = Y·(12 − 3u′ − 20v′)/(4v′); their
   * derivatives along (cos θ, sin θ) in u′v′ */
  const double th = angle_deg * M_PI / 180.0, du = cos(th), dv = sin(th);
  double dxyz[3];
  dxyz[0] = 9 * Y / (4 * v) * du - 9 * Y * u / (4 * v * v) * dv;
  dxyz[1] = 0;
  dxyz[2] = -3 * Y / (4 * v) * du + Y * (3 * u - 12) / (4 * v * v) * dv;
  double inv[3][3];
  mat3_inverse(jnd_csf_lms2006_xyz, inv);
  mat3_apply(inv, dxyz, dir_lms);
  double n = sqrt(dir_lms[0] * dir_lms[0] + dir_lms[1] * dir_lms[1] + dir_lms[2] * dir_lms[2]);
  for (int i = 0; i < 3; i++) dir_lms[i] /= n;
}

/* finds id in a lookup table (first column) and reads columns a, b, c */
static int lookup3(const jnd_csv *t, double id, const int col[3], double out[3]) {
  for (int r = 0; r < t->nrows; r++) {
    double v;
    if (jnd_csv_number(t->cells[r][0], &v) && v == id)
      return jnd_csv_number(t->cells[r][col[0]], &out[0]) && jnd_csv_number(t->cells[r][col[1]], &out[1]) &&
             jnd_csv_number(t->cells[r][col[2]], &out[2]);
  }
  return 0;
}

#define KONG_FIRST_DIR 55
#define KONG_FIRST_BKG 50
#define KONG_BKGS 9

/* The direction a data set defines in its publication, for ids the colour
 * file does not list: 1 and dir_lms filled, 0 when the id is not one of them
 * (msg then says why, if the id is close to one). */
static int derived_direction(const char *dataset, double id, double bkg_id, const double bkg_lms[3],
                             const jnd_csv *colors, const int col[3], double dir_lms[3], char *msg, size_t nmsg) {
  msg[0] = 0;
  if (strcmp(dataset, "kong2018") == 0 && id == floor(id) && id >= KONG_FIRST_DIR &&
      id < KONG_FIRST_DIR + 4 * KONG_BKGS) {
    int k = (int)id - KONG_FIRST_DIR;
    int want_bkg = KONG_FIRST_BKG + k / 4;
    if (bkg_id != want_bkg) {
      snprintf(msg, nmsg, "kong2018 direction %g belongs to background %d, not %g", id, want_bkg, bkg_id);
      return 0;
    }
    jnd_csf_uv_direction(bkg_lms, 45.0 * (k % 4), dir_lms);
    return 1;
  }
  if (strcmp(dataset, "hansen2009") == 0 && id >= 114 && id <= 116 && id == floor(id)) {
    /* the DKL cardinal directions at D65 as castleCSF writes them: colorfest's ids 2, 3, 4 */
    double cf = id - 112;
    if (!lookup3(colors, cf, col, dir_lms)) {
      snprintf(msg, nmsg, "hansen2009 direction %g is defined as colorfest's direction %g, which is not listed", id,
               cf);
      return 0;
    }
    return 1;
  }
  return 0;
}

static jnd_stim_kind stimulus_kind(const char *s) {
  if (strcmp(s, "gabor") == 0) return JND_STIM_GABOR;
  if (strcmp(s, "grating") == 0) return JND_STIM_GRATING;
  if (strcmp(s, "disk") == 0 || strcmp(s, "disc") == 0) return JND_STIM_DISK;
  return (jnd_stim_kind)-1;
}

void jnd_csf_data_free(jnd_csf_data *d) {
  if (!d) return;
  free(d->rows);
  for (int i = 0; i < d->ndatasets; i++) free(d->datasets[i]);
  free(d->datasets);
  jnd_csv_free(&d->table);
  memset(d, 0, sizeof *d);
}

jnd_status jnd_csf_data_from_tables(const char *data, jnd_csv *table, const char *colors, const jnd_csv *tc,
                                    const char *backgrounds, const jnd_csv *tb, jnd_csf_data *out) {
  memset(out, 0, sizeof *out);
  out->table = *table;
  memset(table, 0, sizeof *table);
  jnd_status s;
  const jnd_csv *t = &out->table;
  static const char *need[] = {"luminance", "s_frequency", "t_frequency", "area",     "ge_sigma",    "eccentricity",
                               "orientation", "col_dir_id", "bkg_id",   "stimulus", "sensitivity", "dataset"};
  enum { LUM, SF, TF, AREA, SIGMA, ECC, ORI, DIR, BKG, STIM, SENS, DS, NEED };
  int col[NEED];
  for (int k = 0; k < NEED; k++)
    if ((col[k] = jnd_csv_column(t, need[k])) < 0) {
      s = jnd_fail(JND_ERR_FORMAT, "%s: missing column '%s'", data, need[k]);
      goto fail;
    }
  const int ccol[3] = {jnd_csv_column(tc, "L_delta"), jnd_csv_column(tc, "M_delta"), jnd_csv_column(tc, "S_delta")};
  if (ccol[0] < 0 || ccol[1] < 0 || ccol[2] < 0) {
    s = jnd_fail(JND_ERR_FORMAT, "%s: needs columns L_delta, M_delta, S_delta", colors);
    goto fail;
  }
  const int bcol[3] = {jnd_csv_column(tb, "L"), jnd_csv_column(tb, "M"), jnd_csv_column(tb, "S")};
  if (bcol[0] < 0 || bcol[1] < 0 || bcol[2] < 0) {
    s = jnd_fail(JND_ERR_FORMAT, "%s: needs columns L, M, S", backgrounds);
    goto fail;
  }
  out->rows = jnd_calloc(t->nrows ? (size_t)t->nrows : 1, sizeof *out->rows);
  out->datasets = jnd_calloc(t->nrows ? (size_t)t->nrows : 1, sizeof *out->datasets);
  if (!out->rows || !out->datasets) {
    s = JND_ERR_NOMEM;
    goto fail;
  }
  out->nrows = t->nrows;
  for (int r = 0; r < t->nrows; r++) {
    jnd_csf_row *row = &out->rows[r];
    char **c = t->cells[r];
    double v[NEED];
    for (int k = 0; k < NEED; k++) {
      if (k == STIM || k == DS) continue;
      if (!jnd_csv_number(c[col[k]], &v[k])) {
        s = jnd_fail(JND_ERR_FORMAT, "%s: line %d: column %s: '%s' is not a number", data, r + 2, need[k], c[col[k]]);
        goto fail;
      }
    }
    const char *ds = c[col[DS]];
    int d;
    for (d = 0; d < out->ndatasets; d++)
      if (strcmp(out->datasets[d], ds) == 0) break;
    if (d == out->ndatasets) {
      if (!(out->datasets[d] = strdup(ds))) {
        s = JND_ERR_NOMEM;
        goto fail;
      }
      out->ndatasets++;
    }
    row->dataset = d;
    row->line = r + 2;
    jnd_csf_stimulus *st = &row->st;
    st->kind = stimulus_kind(c[col[STIM]]);
    st->luminance = v[LUM];
    st->s_frequency = v[SF];
    st->t_frequency = isnan(v[TF]) ? 0 : v[TF];
    st->area = v[AREA];
    st->ge_sigma = v[SIGMA];
    st->eccentricity = isnan(v[ECC]) ? 0 : v[ECC];
    st->orientation = isnan(v[ORI]) ? 0 : v[ORI];
    row->measured = v[SENS];
    row->col_dir_id = v[DIR];
    row->bkg_id = v[BKG];
    row->use = 1;
    if (!lookup3(tb, v[BKG], bcol, st->bkg_lms)) {
      s = jnd_fail(JND_ERR_FORMAT, "%s: line %d: background %g is not in %s", data, r + 2, v[BKG], backgrounds);
      goto fail;
    }
    if (!lookup3(tc, v[DIR], ccol, st->dir_lms)) {
      char why[160];
      if (!derived_direction(ds, v[DIR], v[BKG], st->bkg_lms, tc, ccol, st->dir_lms, why, sizeof why)) {
        s = jnd_fail(JND_ERR_FORMAT, "%s: line %d: colour direction %g is not in %s%s%s", data, r + 2, v[DIR], colors,
                     why[0] ? ": " : "", why);
        goto fail;
      }
      row->derived_direction = 1;
    }
    if ((int)st->kind < 0) {
      row->use = 0;
      row->skip = "unknown stimulus type";
    } else if (!(row->measured > 0)) {
      row->use = 0;
      row->skip = "no measured sensitivity";
    } else if (st->kind == JND_STIM_GABOR && !(st->ge_sigma > 0)) {
      row->use = 0;
      row->skip = "Gabor without ge_sigma";
    } else if (st->kind != JND_STIM_GABOR && !(st->area > 0)) {
      row->use = 0;
      row->skip = "no area";
    }
  }
  return JND_OK;
fail:
  jnd_csf_data_free(out);
  return s;
}

jnd_status jnd_csf_data_read(const char *data, const char *colors, const char *backgrounds, jnd_csf_data *out) {
  memset(out, 0, sizeof *out);
  jnd_csv t = {0}, tc = {0}, tb = {0};
  jnd_status s;
  if ((s = jnd_csv_read(data, &t)) == JND_OK && (s = jnd_csv_read(colors, &tc)) == JND_OK &&
      (s = jnd_csv_read(backgrounds, &tb)) == JND_OK)
    s = jnd_csf_data_from_tables(data, &t, colors, &tc, backgrounds, &tb, out);
  jnd_csv_free(&t);
  jnd_csv_free(&tc);
  jnd_csv_free(&tb);
  return s;
}
