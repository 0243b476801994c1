/* The engine's side of 002's table L(distance, eccentricity): loaded once
 * (from jnd gaze's gaze.csv or a table in memory), looked up per object per
 * frame without allocating. Three ways between grid points: the nearest
 * point, bilinear (a fractional level, for blending), and the floor corner
 * (the finest of the neighbours, as the table is monotone: never a level
 * coarser than the table allows). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "jnd.h"

#define GAZE_MAX_AXIS 256   /* as gaze_table.c */

void jnd_gaze_lookup_free(jnd_gaze_lookup *lut) {
  if (!lut) return;
  free(lut->distances_m);
  free(lut->eccentricities_deg);
  free(lut->level);
  memset(lut, 0, sizeof *lut);
}

static jnd_status lookup_alloc(jnd_gaze_lookup *out, int nd, int ne) {
  out->nd = nd, out->ne = ne;
  out->distances_m = jnd_alloc((size_t)nd, sizeof(double));
  out->eccentricities_deg = jnd_alloc((size_t)ne, sizeof(double));
  out->level = jnd_alloc((size_t)nd * ne, sizeof(float));
  if (out->distances_m && out->eccentricities_deg && out->level) return JND_OK;
  jnd_gaze_lookup_free(out);
  return JND_ERR_NOMEM;
}

jnd_status jnd_gaze_lookup_from_table(const jnd_gaze_table *t, jnd_gaze_lookup *out) {
  memset(out, 0, sizeof *out);
  jnd_status st = lookup_alloc(out, t->nd, t->ne);
  if (st != JND_OK) return st;
  memcpy(out->distances_m, t->distances_m, (size_t)t->nd * sizeof(double));
  memcpy(out->eccentricities_deg, t->eccentricities_deg, (size_t)t->ne * sizeof(double));
  for (int i = 0; i < t->nd * t->ne; i++) out->level[i] = (float)t->level[i];
  return JND_OK;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* sorted distinct values of v (n) into v; returns the count */
static int distinct(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  int k = 0;
  for (int i = 0; i < n; i++)
    if (k == 0 || v[i] != v[k - 1]) v[k++] = v[i];
  return k;
}

static int index_of(const double *v, int n, double x) {
  for (int i = 0; i < n; i++)
    if (v[i] == x) return i;
  return -1;
}

/* the grid from a parsed table (csv is freed) */
static jnd_status lookup_from_csv(const char *name, jnd_csv csv, jnd_gaze_lookup *out) {
  jnd_status st = JND_OK;
  int cd = jnd_csv_column(&csv, "distance_m"), ce = jnd_csv_column(&csv, "eccentricity_deg"),
      cl = jnd_csv_column(&csv, "level");
  double *ds = NULL, *es = NULL, *lv = NULL;
  if (cd < 0 || ce < 0 || cl < 0) {
    st = jnd_fail(JND_ERR_FORMAT, "%s: a gaze table needs the columns distance_m, eccentricity_deg and level", name);
    goto done;
  }
  if (csv.nrows < 1 || csv.nrows > GAZE_MAX_AXIS * GAZE_MAX_AXIS) {
    st = jnd_fail(JND_ERR_FORMAT, "%s: a gaze table has 1 to %d rows, not %d", name, GAZE_MAX_AXIS * GAZE_MAX_AXIS,
                  csv.nrows);
    goto done;
  }
  int nr = csv.nrows;
  ds = jnd_alloc((size_t)nr, sizeof *ds), es = jnd_alloc((size_t)nr, sizeof *es), lv = jnd_alloc((size_t)nr, sizeof *lv);
  if (!ds || !es || !lv) {
    st = JND_ERR_NOMEM;
    goto done;
  }
  for (int i = 0; i < nr; i++) {
    double d, e, l;
    if (!jnd_csv_number(csv.cells[i][cd], &d) || !(d > 0) || !isfinite(d)) {
      st = jnd_fail(JND_ERR_FORMAT, "%s: row %d: distance_m '%s' is not a distance > 0", name, i + 2, csv.cells[i][cd]);
      goto done;
    }
    if (!jnd_csv_number(csv.cells[i][ce], &e) || !(e >= 0 && e <= 90)) {
      st = jnd_fail(JND_ERR_FORMAT, "%s: row %d: eccentricity_deg '%s' is outside 0..90", name, i + 2, csv.cells[i][ce]);
      goto done;
    }
    if (!jnd_csv_number(csv.cells[i][cl], &l) || !(l >= 0 && l <= 1000) || l != floor(l)) {
      st = jnd_fail(JND_ERR_FORMAT, "%s: row %d: level '%s' is not a whole number 0..1000", name, i + 2, csv.cells[i][cl]);
      goto done;
    }
    ds[i] = d, es[i] = e, lv[i] = l;
  }
  {
    double *ud = jnd_alloc((size_t)nr, sizeof *ud), *ue = jnd_alloc((size_t)nr, sizeof *ue);
    if (!ud || !ue) {
      free(ud), free(ue);
      st = JND_ERR_NOMEM;
      goto done;
    }
    memcpy(ud, ds, (size_t)nr * sizeof *ud);
    memcpy(ue, es, (size_t)nr * sizeof *ue);
    int nd = distinct(ud, nr), ne = distinct(ue, nr);
    if (nd > GAZE_MAX_AXIS || ne > GAZE_MAX_AXIS || (long)nd * ne != nr) {
      free(ud), free(ue);
      st = jnd_fail(JND_ERR_FORMAT, "%s: %d rows do not make a complete grid of distances × eccentricities", name, nr);
      goto done;
    }
    if ((st = lookup_alloc(out, nd, ne)) != JND_OK) {
      free(ud), free(ue);
      goto done;
    }
    memcpy(out->distances_m, ud, (size_t)nd * sizeof *ud);
    memcpy(out->eccentricities_deg, ue, (size_t)ne * sizeof *ue);
    free(ud), free(ue);
    for (int i = 0; i < nd * ne; i++) out->level[i] = -1;
    for (int i = 0; i < nr; i++) {
      size_t q = (size_t)index_of(out->distances_m, nd, ds[i]) * ne + index_of(out->eccentricities_deg, ne, es[i]);
      if (out->level[q] >= 0) {
        st = jnd_fail(JND_ERR_FORMAT, "%s: row %d repeats distance %g, eccentricity %g", name, i + 2, ds[i], es[i]);
        jnd_gaze_lookup_free(out);
        goto done;
      }
      out->level[q] = (float)lv[i];
    }
  }
done:
  free(ds), free(es), free(lv);
  jnd_csv_free(&csv);
  return st;
}

jnd_status jnd_gaze_lookup_parse(const char *name, const char *text, size_t n, jnd_gaze_lookup *out) {
  memset(out, 0, sizeof *out);
  jnd_csv csv;
  jnd_status st = jnd_csv_parse(name, text, n, &csv);
  return st == JND_OK ? lookup_from_csv(name, csv, out) : st;
}

jnd_status jnd_gaze_lookup_load(const char *path, jnd_gaze_lookup *out) {
  memset(out, 0, sizeof *out);
  jnd_csv csv;
  jnd_status st = jnd_csv_read(path, &csv);
  return st == JND_OK ? lookup_from_csv(path, csv, out) : st;
}

/* the grid cell of x on axis v (n): lower index and fraction, clamped */
static void locate(const double *v, int n, double x, int *i, double *t) {
  if (n == 1 || !(x > v[0])) {
    *i = 0, *t = 0;
    return;
  }
  if (x >= v[n - 1]) {
    *i = n - 2, *t = 1;
    return;
  }
  int k = 0;
  while (k + 2 < n && x >= v[k + 1]) k++;
  *i = k;
  *t = (x - v[k]) / (v[k + 1] - v[k]);
}

double jnd_gaze_lookup_level(const jnd_gaze_lookup *lut, double dist_m, double ecc_deg, jnd_gaze_lookup_mode mode) {
  int i, j;
  double s, t;
  locate(lut->distances_m, lut->nd, dist_m, &i, &s);
  locate(lut->eccentricities_deg, lut->ne, ecc_deg, &j, &t);
  int i1 = lut->nd > 1 ? i + 1 : i, j1 = lut->ne > 1 ? j + 1 : j;
  const float *L = lut->level;
  const int ne = lut->ne;
  switch (mode) {
  case JND_GAZE_BILINEAR:
    return (1 - s) * ((1 - t) * L[i * ne + j] + t * L[i * ne + j1]) + s * ((1 - t) * L[i1 * ne + j] + t * L[i1 * ne + j1]);
  case JND_GAZE_FLOOR:
    return L[(s >= 1 ? i1 : i) * ne + (t >= 1 ? j1 : j)];
  default:
    return L[(s > 0.5 ? i1 : i) * ne + (t > 0.5 ? j1 : j)];
  }
}
