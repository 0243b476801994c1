/* Fitting 002's models to observers' answers (002 "Calibrating the models").
 *
 * Procedure:
 *  1. Data: one row per trial, the stimulus's precomputed terms and the
 *     answer (seen 0/1). Spatial rows: xor_deg (the silhouette XOR's area over
 *     S0's perimeter, degrees, unweighted), v_jnd, eccentricity_deg; temporal
 *     rows: t_jnd. Rows with the same terms (or the same `stimulus`) are one
 *     stimulus.  jnd_gaze_data_parse()
 *  2. The free parameters by maximum likelihood over the Bernoulli answers
 *     (002's argmin of the negative log-likelihood): Nelder–Mead in a
 *     transformed space (logs of the positive parameters, log(k_s − 1),
 *     the logit of s/90°),
 *     restarted from its best point until it stops improving.  fit_ml()
 *     In the fit, every XOR pixel of a stimulus is at the object's
 *     eccentricity: G = w(ecc) · xor_deg (docs/gaze.md says why).
 *  3. Standard errors from the observed information: the inverse of the
 *     numerical Hessian of the negative log-likelihood at the optimum, in
 *     the transformed space (a parameter's 95% interval is the transform of
 *     value ± z SE, z the normal quantile of the confidence).  hessian_se()
 *  4. k-fold cross-validation over stimuli (seeded assignment): fitted on
 *     k − 1 folds, the predicted P of the held-out stimuli against their
 *     observed proportion seen: Pearson r and mean absolute error per fold,
 *     their mean and standard deviation; and on all data (002 reports both).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "jnd.h"

enum { NS = 6, NT = 2, NMAX = 7 };
#define S_MAX_DEG 90.0   /* the knee s is fitted within the visual field, (0, 90)° */
/* b, the weight's far floor, is kept at the start's value: docs/gaze.md "Fitting" */
static const char *const spatial_names[NS] = {"alpha", "beta", "s_deg", "w_vdp", "k_s", "gamma"};
static const char *const temporal_names[NT] = {"w_t", "gamma_t"};

void jnd_gaze_data_free(jnd_gaze_data *d) {
  if (!d) return;
  free(d->trials);
  memset(d, 0, sizeof *d);
}

/* qsort has no context argument: the trials being sorted (one parse at a time per thread) */
static _Thread_local const jnd_gaze_trial *sort_base;

static int cmp_terms(const void *pa, const void *pb) {
  const jnd_gaze_trial *a = &sort_base[*(const int *)pa], *b = &sort_base[*(const int *)pb];
  const double x[4] = {a->xor_deg, a->v_jnd, a->ecc_deg, a->t_jnd}, y[4] = {b->xor_deg, b->v_jnd, b->ecc_deg, b->t_jnd};
  for (int k = 0; k < 4; k++)
    if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
  return 0;
}

static jnd_status data_from_csv(const char *name, jnd_csv *csv, jnd_gaze_data *out) {
  int cx = jnd_csv_column(csv, "xor_deg"), cv = jnd_csv_column(csv, "v_jnd"), ce = jnd_csv_column(csv, "eccentricity_deg"),
      ct = jnd_csv_column(csv, "t_jnd"), cs = jnd_csv_column(csv, "seen"), cid = jnd_csv_column(csv, "stimulus");
  if (cs < 0) return jnd_fail(JND_ERR_FORMAT, "%s: no column 'seen' (the observer's answer, 0 or 1)", name);
  int temporal = cx < 0 && cv < 0 && ce < 0;
  if (temporal && ct < 0)
    return jnd_fail(JND_ERR_FORMAT, "%s: give the spatial terms (xor_deg, v_jnd, eccentricity_deg) or the temporal t_jnd", name);
  if (!temporal && (cx < 0 || cv < 0 || ce < 0))
    return jnd_fail(JND_ERR_FORMAT, "%s: missing column '%s' (spatial rows need xor_deg, v_jnd, eccentricity_deg)", name,
                    cx < 0 ? "xor_deg" : cv < 0 ? "v_jnd" : "eccentricity_deg");
  if (csv->nrows < 1) return jnd_fail(JND_ERR_FORMAT, "%s: no trials", name);
  out->trials = jnd_calloc((size_t)csv->nrows, sizeof *out->trials);
  if (!out->trials) return JND_ERR_NOMEM;
  out->n = csv->nrows;
  out->temporal = temporal;
  for (int i = 0; i < csv->nrows; i++) {
    jnd_gaze_trial *t = &out->trials[i];
    char **row = csv->cells[i];
    double seen;
    if (!jnd_csv_number(row[cs], &seen) || !(seen == 0 || seen == 1))
      return jnd_fail(JND_ERR_FORMAT, "%s: row %d: seen '%s' is not 0 or 1", name, i + 2, row[cs]);
    t->seen = (int)seen;
    if (temporal) {
      if (!jnd_csv_number(row[ct], &t->t_jnd) || !(t->t_jnd >= 0) || !isfinite(t->t_jnd))
        return jnd_fail(JND_ERR_FORMAT, "%s: row %d: t_jnd '%s' is not a number >= 0", name, i + 2, row[ct]);
    } else {
      if (!jnd_csv_number(row[cx], &t->xor_deg) || !(t->xor_deg >= 0) || !isfinite(t->xor_deg))
        return jnd_fail(JND_ERR_FORMAT, "%s: row %d: xor_deg '%s' is not a number >= 0", name, i + 2, row[cx]);
      if (!jnd_csv_number(row[cv], &t->v_jnd) || !(t->v_jnd >= 0) || !isfinite(t->v_jnd))
        return jnd_fail(JND_ERR_FORMAT, "%s: row %d: v_jnd '%s' is not a number >= 0", name, i + 2, row[cv]);
      if (!jnd_csv_number(row[ce], &t->ecc_deg) || !(t->ecc_deg >= 0 && t->ecc_deg <= 90))
        return jnd_fail(JND_ERR_FORMAT, "%s: row %d: eccentricity_deg '%s' is outside 0..90", name, i + 2, row[ce]);
    }
    t->stimulus = -1;
    if (cid >= 0) {
      double id;
      if (!jnd_csv_number(row[cid], &id) || !(id >= 0 && id < csv->nrows) || id != floor(id))
        return jnd_fail(JND_ERR_FORMAT, "%s: row %d: stimulus '%s' is not a whole number 0..%d (ids number the stimuli)",
                        name, i + 2, row[cid], csv->nrows - 1);
      t->stimulus = (int)id;
    }
  }
  /* stimuli: the given ids, or one per distinct set of terms (numbered in
   * order of first appearance; found by sorting, not pairwise) */
  int next = 0;
  if (cid >= 0) {
    for (int i = 0; i < out->n; i++) next = out->trials[i].stimulus + 1 > next ? out->trials[i].stimulus + 1 : next;
  } else {
    int *idx = jnd_alloc((size_t)out->n, sizeof *idx);
    if (!idx) return JND_ERR_NOMEM;
    for (int i = 0; i < out->n; i++) idx[i] = i;
    sort_base = out->trials;
    qsort(idx, (size_t)out->n, sizeof *idx, cmp_terms);
    /* each run of equal terms gets the id of its first row: ids by first appearance */
    for (int a = 0, b; a < out->n; a = b) {
      int first = idx[a];
      for (b = a + 1; b < out->n && cmp_terms(&idx[a], &idx[b]) == 0; b++)
        if (idx[b] < first) first = idx[b];
      for (int k = a; k < b; k++) out->trials[idx[k]].stimulus = first;   /* provisional: a row index */
    }
    free(idx);
    int *id = jnd_alloc((size_t)out->n, sizeof *id);
    if (!id) return JND_ERR_NOMEM;
    for (int i = 0; i < out->n; i++) id[i] = -1;
    for (int i = 0; i < out->n; i++) {
      int f = out->trials[i].stimulus;
      if (id[f] < 0) id[f] = next++;
      out->trials[i].stimulus = id[f];
    }
    free(id);
  }
  out->stimuli = next;
  return JND_OK;
}

jnd_status jnd_gaze_data_parse(const char *name, const char *text, size_t n, jnd_gaze_data *out) {
  memset(out, 0, sizeof *out);
  jnd_csv csv;
  jnd_status st = jnd_csv_parse(name, text, n, &csv);
  if (st != JND_OK) return st;
  st = data_from_csv(name, &csv, out);
  jnd_csv_free(&csv);
  if (st != JND_OK) jnd_gaze_data_free(out);
  return st;
}

jnd_status jnd_gaze_data_read(const char *path, jnd_gaze_data *out) {
  memset(out, 0, sizeof *out);
  jnd_csv csv;
  jnd_status st = jnd_csv_read(path, &csv);
  if (st != JND_OK) return st;
  st = data_from_csv(path, &csv, out);
  jnd_csv_free(&csv);
  if (st != JND_OK) jnd_gaze_data_free(out);
  return st;
}

void jnd_gaze_fit_defaults(jnd_gaze_fit_params *p) {
  memset(p, 0, sizeof *p);
  p->folds = 4;   /* 002: 4-fold cross-validation */
  p->seed = 1;
  p->confidence = 0.95;
  /* a fixed start, not jnd_gaze_model_defaults: the defaults are fitted
   * from here (scripts/fit-gaze-defaults.sh), and a start that moved with
   * them would make the fit depend on its own previous result. The values
   * are the hand-chosen constants of docs/gaze.md "Defaults" (the 1-arcmin
   * silhouette and the 1-JND midpoint) */
  jnd_gaze_model_defaults(&p->start);
  p->start.alpha = 2.0, p->start.beta = 0.1, p->start.s_deg = 30.0, p->start.b = 2.0;
  p->start.w_g = 1.0, p->start.w_vdp = 1.0, p->start.k_s = 2.0, p->start.gamma = 4.85;
  p->start.w_t = 1.0, p->start.gamma_t = 4.85;
}

/* ---- the parameters in the optimiser's space ---- */

static void to_x(const jnd_gaze_model *m, int temporal, double *x) {
  if (temporal) {
    x[0] = log(m->w_t), x[1] = log(m->gamma_t);
    return;
  }
  /* s in the visual field, (0, 90)°, as a logit: below 0 the softplus is a
   * pure exponential in which α and s trade off exactly (only α e^{βs}/β is
   * identified) and an unbounded fit runs α to its limit */
  double u = fmin(fmax(m->s_deg / S_MAX_DEG, 1e-9), 1 - 1e-9);
  x[0] = log(m->alpha), x[1] = log(m->beta), x[2] = log(u / (1 - u));
  x[3] = log(m->w_vdp), x[4] = log(fmax(m->k_s - 1, 1e-3)), x[5] = log(m->gamma);
}

static void from_x(const double *x, int temporal, jnd_gaze_model *m) {
  if (temporal) {
    m->w_t = exp(x[0]), m->gamma_t = exp(x[1]);
    return;
  }
  m->alpha = exp(x[0]), m->beta = exp(x[1]), m->s_deg = S_MAX_DEG / (1 + exp(-x[2]));
  m->w_g = 1;   /* w_g scales alpha and b alike: only their products are identifiable */
  m->w_vdp = exp(x[3]), m->k_s = 1 + exp(x[4]), m->gamma = exp(x[5]);
}

static double predict(const jnd_gaze_model *m, int temporal, const jnd_gaze_trial *t) {
  if (temporal) return jnd_gaze_switch_probability(m, t->t_jnd);
  return jnd_gaze_spatial_probability(m, jnd_gaze_weight(m, t->ecc_deg) * t->xor_deg, t->v_jnd);
}

/* the answers summed per stimulus: the likelihood of k seen in n trials is
 * that of the n Bernoulli answers up to a constant, and costs one
 * prediction per stimulus */
typedef struct {
  jnd_gaze_trial terms;   /* the stimulus's terms */
  double seen, count;
} stimulus_sum;

typedef struct {
  const jnd_gaze_data *d;
  const stimulus_sum *sum; /* per stimulus */
  const jnd_gaze_model *base;
  const unsigned char *use;   /* per stimulus: in the fit (NULL: all) */
} objective;

/* negative log-likelihood of the answers (002's argmin) */
static double nll(const objective *o, const double *x) {
  jnd_gaze_model m = *o->base;
  from_x(x, o->d->temporal, &m);
  if (!(m.alpha < 1e6 && m.beta < 1e3 && fabs(m.s_deg) < 1e3 && m.b < 1e6 && m.w_vdp < 1e6 && m.k_s < 1e3 &&
        m.gamma < 1e3 && m.w_t < 1e6 && m.gamma_t < 1e3))
    return INFINITY;
  double s = 0;
  for (int i = 0; i < o->d->stimuli; i++) {
    const stimulus_sum *t = &o->sum[i];
    if ((o->use && !o->use[i]) || t->count == 0) continue;
    double p = predict(&m, o->d->temporal, &t->terms);
    p = fmin(fmax(p, 1e-12), 1 - 1e-12);
    s -= t->seen * log(p) + (t->count - t->seen) * log1p(-p);
  }
  return s;
}

/* Nelder–Mead in n dimensions from x with initial steps step; x gets the best point. */
static double nelder_mead(const objective *o, int n, double *x, double step) {
  double v[NMAX + 1][NMAX], f[NMAX + 1];
  for (int k = 0; k <= n; k++) {
    memcpy(v[k], x, (size_t)n * sizeof *x);
    if (k) v[k][k - 1] += step;
    f[k] = nll(o, v[k]);
  }
  for (int it = 0; it < 4000; it++) {
    /* sort: best first (insertion sort, stable) */
    for (int a = 1; a <= n; a++)
      for (int b = a; b > 0 && f[b] < f[b - 1]; b--) {
        double t = f[b];
        f[b] = f[b - 1], f[b - 1] = t;
        for (int c = 0; c < n; c++) t = v[b][c], v[b][c] = v[b - 1][c], v[b - 1][c] = t;
      }
    double spread = 0;
    for (int k = 1; k <= n; k++)
      for (int c = 0; c < n; c++) spread = fmax(spread, fabs(v[k][c] - v[0][c]));
    if (fabs(f[n] - f[0]) < 1e-10 * (1 + fabs(f[0])) && spread < 1e-6) break;
    double c[NMAX] = {0}, r[NMAX], e[NMAX], q[NMAX];
    for (int k = 0; k < n; k++)
      for (int j = 0; j < n; j++) c[j] += v[k][j] / n;
    for (int j = 0; j < n; j++) r[j] = 2 * c[j] - v[n][j];
    double fr = nll(o, r);
    if (fr < f[0]) {
      for (int j = 0; j < n; j++) e[j] = 3 * c[j] - 2 * v[n][j];
      double fe = nll(o, e);
      memcpy(v[n], fe < fr ? e : r, (size_t)n * sizeof(double));
      f[n] = fe < fr ? fe : fr;
    } else if (fr < f[n - 1]) {
      memcpy(v[n], r, (size_t)n * sizeof(double));
      f[n] = fr;
    } else {
      for (int j = 0; j < n; j++) q[j] = (c[j] + v[n][j]) / 2;
      double fq = nll(o, q);
      if (fq < f[n]) {
        memcpy(v[n], q, (size_t)n * sizeof(double));
        f[n] = fq;
      } else {
        for (int k = 1; k <= n; k++) {
          for (int j = 0; j < n; j++) v[k][j] = (v[k][j] + v[0][j]) / 2;
          f[k] = nll(o, v[k]);
        }
      }
    }
  }
  int best = 0;
  for (int k = 1; k <= n; k++)
    if (f[k] < f[best]) best = k;
  memcpy(x, v[best], (size_t)n * sizeof *x);
  return f[best];
}

/* step 2: Nelder–Mead from several starts (the given one, and the weight's
 * knee and the summation exponent moved: the likelihood has ridges where
 * the weight's parameters trade off), each restarted from its best point
 * until it stops improving; the best wins */
static double fit_ml(const objective *o, int n, double *x) {
  double best[NMAX], fbest = INFINITY;
  const int starts = o->d->temporal ? 1 : 5;
  static const double ds[5] = {0, -1.5, 1.5, 0, 0}, dk[5] = {0, 0, 0, -1.5, 1.5};   /* s: in logit units */
  for (int k = 0; k < starts; k++) {
    double y[NMAX];
    memcpy(y, x, (size_t)n * sizeof *x);
    if (!o->d->temporal) y[2] += ds[k], y[4] += dk[k];
    double f = nll(o, y);
    for (int round = 0; round < 5; round++) {
      double g = nelder_mead(o, n, y, round == 0 ? 0.5 : 0.1);
      int done = f - g < 1e-6;
      f = g;
      if (done && round >= 1) break;
    }
    if (f < fbest) fbest = f, memcpy(best, y, (size_t)n * sizeof *y);
  }
  memcpy(x, best, (size_t)n * sizeof *x);
  return fbest;
}

/* In-place inverse of an n × n symmetric positive-definite matrix
 * (Gauss–Jordan with partial pivoting); 0 if singular. */
static int invert(double *a, int n) {
  double inv[NMAX * NMAX] = {0};
  for (int i = 0; i < n; i++) inv[i * n + i] = 1;
  for (int c = 0; c < n; c++) {
    int p = c;
    for (int r = c + 1; r < n; r++)
      if (fabs(a[r * n + c]) > fabs(a[p * n + c])) p = r;
    if (!(fabs(a[p * n + c]) > 1e-300)) return 0;
    for (int k = 0; k < n; k++) {
      double t = a[c * n + k];
      a[c * n + k] = a[p * n + k], a[p * n + k] = t;
      t = inv[c * n + k];
      inv[c * n + k] = inv[p * n + k], inv[p * n + k] = t;
    }
    double d = a[c * n + c];
    for (int k = 0; k < n; k++) a[c * n + k] /= d, inv[c * n + k] /= d;
    for (int r = 0; r < n; r++) {
      if (r == c) continue;
      double m = a[r * n + c];
      for (int k = 0; k < n; k++) a[r * n + k] -= m * a[c * n + k], inv[r * n + k] -= m * inv[c * n + k];
    }
  }
  memcpy(a, inv, sizeof(double) * (size_t)n * n);
  return 1;
}

/* step 3: SE of each transformed parameter from the numerical Hessian (NaN where undetermined) */
static void hessian_se(const objective *o, int n, const double *x, double *se) {
  double h[NMAX * NMAX], xx[NMAX];
  const double eps = 1e-3;
  double f0 = nll(o, x);
  for (int i = 0; i < n; i++)
    for (int j = i; j < n; j++) {
      double s[4];
      for (int k = 0; k < 4; k++) {
        memcpy(xx, x, (size_t)n * sizeof *x);
        xx[i] += (k & 1 ? -eps : eps);
        xx[j] += (k & 2 ? -eps : eps);
        s[k] = nll(o, xx);
      }
      h[i * n + j] = h[j * n + i] = (s[0] - s[1] - s[2] + s[3]) / (4 * eps * eps);
    }
  (void)f0;
  /* a flat direction (a parameter run off to a bound of its transform, such
   * as b → 0) has no curvature: it is left out and reported undetermined,
   * and the others' errors come from the rest of the matrix */
  double hmax = 0;
  for (int i = 0; i < n; i++) hmax = fmax(hmax, fabs(h[i * n + i]));
  int keep[NMAX], m = 0;
  for (int i = 0; i < n; i++)
    if (h[i * n + i] > 1e-6 * hmax) keep[m++] = i;
  double sub[NMAX * NMAX];
  for (int a = 0; a < m; a++)
    for (int b = 0; b < m; b++) sub[a * m + b] = h[keep[a] * n + keep[b]];
  int ok = m > 0 && invert(sub, m);
  for (int i = 0; i < n; i++) se[i] = NAN;
  for (int a = 0; a < m && ok; a++) se[keep[a]] = sub[a * m + a] > 0 ? sqrt(sub[a * m + a]) : NAN;
}

/* Pearson r and MAE of predictions against observed proportions, over the stimuli in `use` */
static void score(const jnd_gaze_data *d, const jnd_gaze_model *m, const unsigned char *use, double *r, double *mae,
                  double *seen, double *count) {
  memset(seen, 0, sizeof(double) * (size_t)d->stimuli);
  memset(count, 0, sizeof(double) * (size_t)d->stimuli);
  double *pred = seen + d->stimuli;   /* the caller gives 3 × stimuli */
  for (int i = 0; i < d->n; i++) {
    const jnd_gaze_trial *t = &d->trials[i];
    if (use && !use[t->stimulus]) continue;
    seen[t->stimulus] += t->seen;
    count[t->stimulus] += 1;
    pred[t->stimulus] = predict(m, d->temporal, t);
  }
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, sa = 0;
  int k = 0;
  for (int s = 0; s < d->stimuli; s++) {
    if (count[s] == 0) continue;
    double y = seen[s] / count[s], x = pred[s];
    sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y, sa += fabs(x - y);
    k++;
  }
  *mae = k ? sa / k : NAN;
  double vx = sxx - sx * sx / k, vy = syy - sy * sy / k;
  *r = k > 1 && vx > 0 && vy > 0 ? (sxy - sx * sy / k) / sqrt(vx * vy) : NAN;
}

static void mean_sd(const double *v, int n, double *mean, double *sd) {
  double s = 0, q = 0;
  for (int i = 0; i < n; i++) s += v[i];
  *mean = s / n;
  for (int i = 0; i < n; i++) q += (v[i] - *mean) * (v[i] - *mean);
  *sd = n > 1 ? sqrt(q / (n - 1)) : 0;
}

jnd_status jnd_gaze_fit(const jnd_gaze_data *d, const jnd_gaze_fit_params *p, jnd_gaze_fit_result *out) {
  memset(out, 0, sizeof *out);
  if (!d || d->n < 1 || d->stimuli < 1) return jnd_fail(JND_ERR_ARG, "gaze fit: no trials");
  if (p->folds < 2 || p->folds > JND_GAZE_MAX_FOLDS)
    return jnd_fail(JND_ERR_ARG, "--folds: give 2 to %d", JND_GAZE_MAX_FOLDS);
  if (d->stimuli < p->folds)
    return jnd_fail(JND_ERR_ARG, "gaze fit: %d stimuli cannot make %d folds", d->stimuli, p->folds);
  if (!(p->confidence > 0 && p->confidence < 1)) return jnd_fail(JND_ERR_ARG, "gaze fit: confidence must be in (0, 1)");
  const int n = d->temporal ? NT : NS;
  /* the normal quantile of (1 + confidence) / 2, by bisection */
  double zlo = 0, zhi = 40, z = 1.96;
  for (int it = 0; it < 200; it++) {
    z = 0.5 * (zlo + zhi);
    if (0.5 * erfc(-z / M_SQRT2) < 0.5 * (1 + p->confidence)) zlo = z;
    else zhi = z;
  }
  unsigned char *use = jnd_alloc((size_t)d->stimuli, 1);
  int *fold = jnd_alloc((size_t)d->stimuli, sizeof *fold);
  double *scratch = jnd_alloc((size_t)d->stimuli * 3, sizeof(double));
  if (!use || !fold || !scratch) {
    free(use), free(fold), free(scratch);
    return JND_ERR_NOMEM;
  }
  out->temporal = d->temporal;
  out->nparams = n;
  out->trials = d->n;
  out->stimuli = d->stimuli;
  out->folds = p->folds;
  stimulus_sum *sum = jnd_calloc((size_t)d->stimuli, sizeof *sum);
  if (!sum) {
    free(use), free(fold), free(scratch);
    return JND_ERR_NOMEM;
  }
  for (int i = 0; i < d->n; i++) {
    stimulus_sum *t = &sum[d->trials[i].stimulus];
    t->terms = d->trials[i];
    t->seen += d->trials[i].seen;
    t->count += 1;
  }
  /* all data */
  objective o = {d, sum, &p->start, NULL};
  double x[NMAX], se[NMAX];
  to_x(&p->start, d->temporal, x);
  out->neg_loglik = fit_ml(&o, n, x);
  hessian_se(&o, n, x, se);
  out->model = p->start;
  from_x(x, d->temporal, &out->model);
  for (int i = 0; i < n; i++) {
    out->names[i] = d->temporal ? temporal_names[i] : spatial_names[i];
    jnd_gaze_model lo = out->model, hi = out->model, one = out->model;
    double xl[NMAX], xh[NMAX];
    memcpy(xl, x, sizeof xl), memcpy(xh, x, sizeof xh);
    xl[i] -= z * se[i], xh[i] += z * se[i];
    from_x(xl, d->temporal, &lo), from_x(xh, d->temporal, &hi), from_x(x, d->temporal, &one);
    double *fields[3] = {out->value, out->ci_lo, out->ci_hi};
    const jnd_gaze_model *ms[3] = {&one, &lo, &hi};
    for (int k = 0; k < 3; k++) {
      double v[NMAX];
      if (d->temporal) v[0] = ms[k]->w_t, v[1] = ms[k]->gamma_t;
      else v[0] = ms[k]->alpha, v[1] = ms[k]->beta, v[2] = ms[k]->s_deg, v[3] = ms[k]->w_vdp, v[4] = ms[k]->k_s,
      v[5] = ms[k]->gamma;
      fields[k][i] = isfinite(se[i]) || k == 0 ? v[i] : NAN;
    }
  }
  score(d, &out->model, NULL, &out->r_all, &out->mae_all, scratch, scratch + 2 * d->stimuli);
  /* k-fold over stimuli: a seeded shuffle dealt round-robin */
  int *order = fold;
  for (int s = 0; s < d->stimuli; s++) order[s] = s;
  jnd_rng rng;
  jnd_rng_seed(&rng, p->seed);
  for (int s = d->stimuli - 1; s > 0; s--) {
    int j = (int)(jnd_rng_next(&rng) % (uint64_t)(s + 1)), t = order[s];
    order[s] = order[j], order[j] = t;
  }
  int *which = jnd_alloc((size_t)d->stimuli, sizeof *which);
  if (!which) {
    free(use), free(fold), free(scratch), free(sum);
    return JND_ERR_NOMEM;
  }
  for (int s = 0; s < d->stimuli; s++) which[order[s]] = s % p->folds;
  for (int k = 0; k < p->folds; k++) {
    for (int s = 0; s < d->stimuli; s++) use[s] = which[s] != k;
    objective ok = {d, sum, &p->start, use};
    double xk[NMAX];
    to_x(&p->start, d->temporal, xk);
    fit_ml(&ok, n, xk);
    jnd_gaze_model mk = p->start;
    from_x(xk, d->temporal, &mk);
    for (int s = 0; s < d->stimuli; s++) use[s] = which[s] == k;
    score(d, &mk, use, &out->fold_r[k], &out->fold_mae[k], scratch, scratch + 2 * d->stimuli);
  }
  mean_sd(out->fold_r, p->folds, &out->r_mean, &out->r_sd);
  mean_sd(out->fold_mae, p->folds, &out->mae_mean, &out->mae_sd);
  free(which), free(use), free(fold), free(scratch), free(sum);
  return JND_OK;
}
