/* The cross-population psychometric function of 000 eq. 1 and its fit:
 * P_det(r) = 1 − Θ(x; µ, σ), Θ the cumulative normal, x the texture
 * resolution r in pixels (as 000) or log2 r. 000 §6 fits it to pooled
 * probabilities over a scene's resolution series "to regularize the
 * predictions across the resolution levels" and reads the resolution at
 * P = 0.2 from it. The fit is least squares on probability, started from a
 * probit analysis (and a coarse grid over (µ, log σ), so that the start is
 * never in a wrong basin), then Nelder–Mead. */
#include <math.h>
#include <stddef.h>

#include "core/core.h"

static double to_domain(int log2_domain, double r) { return log2_domain ? log2(r) : r; }
static double from_domain(int log2_domain, double x) { return log2_domain ? exp2(x) : x; }

/* 000 eq. 1 */
static double pdet(double x, double mu, double sigma) {
  return 1.0 - 0.5 * (1.0 + erf((x - mu) / (sigma * M_SQRT2)));
}

double jnd_psychometric_eval(const jnd_psychometric *f, double r) {
  return pdet(to_domain(f->log2_domain, r), f->mu, f->sigma);
}

/* Θ⁻¹(q): Newton's method on Θ from the logistic approximation
 * Θ(x) ≈ 1/(1 + e^(−1.702 x)), with a bisection bracket kept so that a
 * step never leaves it; |error| < 1e-12. */
static double normal_quantile(double q) {
  if (q <= 0) return -40;
  if (q >= 1) return 40;
  double lo = -40, hi = 40, x = jnd_clampd(log(q / (1 - q)) / 1.702, -38, 38);
  for (int i = 0; i < 100; i++) {
    double f = 0.5 * erfc(-x / M_SQRT2) - q;
    if (f < 0) lo = x;
    else hi = x;
    double d = exp(-0.5 * x * x) / sqrt(2 * M_PI);
    double nx = d > 1e-300 ? x - f / d : 0.5 * (lo + hi);
    if (!(nx > lo && nx < hi)) nx = 0.5 * (lo + hi);
    if (fabs(nx - x) < 1e-12 * (1 + fabs(x))) return nx;
    x = nx;
  }
  return x;
}

double jnd_psychometric_resolution(const jnd_psychometric *f, double p) {
  /* P = 1 − Θ(x) = p  ⇔  x = µ + σ Θ⁻¹(1 − p) */
  double x = f->mu + f->sigma * normal_quantile(1.0 - jnd_clampd(p, 1e-12, 1 - 1e-12));
  return from_domain(f->log2_domain, x);
}

typedef struct {
  const double *x, *p;
  int n;
} fit_data;

static double sse(const fit_data *d, double mu, double log_sigma) {
  double sigma = exp(log_sigma), s = 0;
  for (int i = 0; i < d->n; i++) {
    double e = pdet(d->x[i], mu, sigma) - d->p[i];
    s += e * e;
  }
  return s;
}

/* Nelder–Mead over (µ, log σ) from a start point with steps dmu, dls. */
static void nelder_mead(const fit_data *d, double *mu, double *ls, double dmu, double dls, double ls_min,
                        double ls_max) {
  double v[3][2] = {{*mu, *ls}, {*mu + dmu, *ls}, {*mu, *ls + dls}}, f[3];
  for (int k = 0; k < 3; k++) f[k] = sse(d, v[k][0], jnd_clampd(v[k][1], ls_min, ls_max));
  for (int it = 0; it < 400; it++) {
    /* order: best 0, worst 2 */
    for (int a = 0; a < 2; a++)
      for (int b = a + 1; b < 3; b++)
        if (f[b] < f[a]) {
          double t = f[a];
          f[a] = f[b];
          f[b] = t;
          for (int c = 0; c < 2; c++) {
            t = v[a][c];
            v[a][c] = v[b][c];
            v[b][c] = t;
          }
        }
    if (fabs(f[2] - f[0]) < 1e-13 * (1 + f[0]) && fabs(v[2][0] - v[0][0]) + fabs(v[2][1] - v[0][1]) < 1e-7 * (1 + fabs(v[0][0])))
      break;
    double c[2] = {(v[0][0] + v[1][0]) / 2, (v[0][1] + v[1][1]) / 2};
    double r[2] = {2 * c[0] - v[2][0], 2 * c[1] - v[2][1]};
    r[1] = jnd_clampd(r[1], ls_min, ls_max);
    double fr = sse(d, r[0], r[1]);
    if (fr < f[0]) {
      double e[2] = {3 * c[0] - 2 * v[2][0], jnd_clampd(3 * c[1] - 2 * v[2][1], ls_min, ls_max)};
      double fe = sse(d, e[0], e[1]);
      if (fe < fr) {
        v[2][0] = e[0], v[2][1] = e[1], f[2] = fe;
      } else {
        v[2][0] = r[0], v[2][1] = r[1], f[2] = fr;
      }
    } else if (fr < f[1]) {
      v[2][0] = r[0], v[2][1] = r[1], f[2] = fr;
    } else {
      double k[2] = {(c[0] + v[2][0]) / 2, (c[1] + v[2][1]) / 2};
      double fk = sse(d, k[0], k[1]);
      if (fk < f[2]) {
        v[2][0] = k[0], v[2][1] = k[1], f[2] = fk;
      } else {
        for (int j = 1; j < 3; j++) {
          v[j][0] = (v[j][0] + v[0][0]) / 2;
          v[j][1] = (v[j][1] + v[0][1]) / 2;
          f[j] = sse(d, v[j][0], v[j][1]);
        }
      }
    }
  }
  int best = 0;
  for (int k = 1; k < 3; k++)
    if (f[k] < f[best]) best = k;
  *mu = v[best][0];
  *ls = v[best][1];
}

#define MAX_POINTS 4096

jnd_status jnd_psychometric_fit(const double *r, const double *p, int n, int log2_domain, jnd_psychometric *out) {
  if (n < 2 || n > MAX_POINTS) return jnd_fail(JND_ERR_ARG, "psychometric fit: needs 2..%d points (got %d)", MAX_POINTS, n);
  double x[MAX_POINTS], lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < n; i++) {
    if (!(r[i] > 0) || !isfinite(r[i]) || !(p[i] >= 0 && p[i] <= 1))
      return jnd_fail(JND_ERR_ARG, "psychometric fit: point %d (r %g, p %g) is out of range", i, r[i], p[i]);
    x[i] = to_domain(log2_domain, r[i]);
    if (x[i] < lo) lo = x[i];
    if (x[i] > hi) hi = x[i];
  }
  double span = hi - lo;
  if (!(span > 0)) return jnd_fail(JND_ERR_ARG, "psychometric fit: all points at one resolution");
  fit_data d = {x, p, n};
  /* σ from a thousandth of the data's span (a step) to ten spans (flat) */
  double ls_min = log(span * 1e-3), ls_max = log(span * 10);
  double bmu = 0.5 * (lo + hi), bls = log(span / 4);
  /* start 1: probit analysis, Θ⁻¹(1 − p) = (x − µ)/σ is linear in x;
   * weighted least squares with weights p(1 − p) on the points inside (0, 1) */
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  int inner = 0;
  for (int i = 0; i < n; i++) {
    if (!(p[i] > 0.005 && p[i] < 0.995)) continue;
    inner++;
    double w = p[i] * (1 - p[i]), y = normal_quantile(1 - p[i]);
    sw += w, sx += w * x[i], sy += w * y, sxx += w * x[i] * x[i], sxy += w * x[i] * y;
  }
  double den = sw * sxx - sx * sx;
  if (sw > 0 && den > 1e-12 * sw * sw) {
    double slope = (sw * sxy - sx * sy) / den, icept = (sy - slope * sx) / sw;
    if (slope > 0) {
      bmu = -icept / slope;
      bls = jnd_clampd(log(1 / slope), ls_min, ls_max);
    }
  }
  double best = sse(&d, bmu, bls);
  /* start 2: a coarse grid, so that a poor probit start (few inner points,
   * non-monotone data) never leaves the fit in a wrong basin */
  int good_start = inner >= 3 && best < 0.01 * n;
  for (int i = 0; i <= 20 && !good_start; i++) {
    double mu = lo - span + 3 * span * i / 20.0;
    for (int j = 0; j <= 8; j++) {
      double ls = ls_min + (ls_max - ls_min) * j / 8.0;
      double e = sse(&d, mu, ls);
      if (e < best - 1e-12) {
        best = e;
        bmu = mu;
        bls = ls;
      }
    }
  }
  nelder_mead(&d, &bmu, &bls, span / 20, 0.3, ls_min, ls_max);
  out->mu = bmu;
  out->sigma = exp(bls);
  out->log2_domain = log2_domain;
  out->rmse = sqrt(sse(&d, bmu, bls) / n);
  return JND_OK;
}
