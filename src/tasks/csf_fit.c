/* `jnd csf`: the model's constants fitted to human contrast thresholds, and
 * the model's accuracy on data sets it was not fitted on (issue 10).
 *
 *  1. Rows: every row the data can predict (jnd_csf_row.use). Fits search on
 *     every N-th row of each data set (search_every); every reported figure
 *     uses all rows.
 *  2. Fit: maximum a posteriori over the chosen constants θ, in natural-log
 *     units: minimise  Σ_rows e_i² + Σ_k (w·(θ_k − ln prior_k) / sd_k)²,
 *     e_i = 20·log10(S_predicted / S_measured) in dB (the field's error), w
 *     = prior_weight_db / √search_every (each search row stands for the
 *     search_every rows it was picked from, so the priors weigh the same
 *     against the data whatever the subsample), priors from
 *     jnd_model_constants(). Levenberg–
 *     Marquardt on the linear surrogate of each threshold (one model run a
 *     row, jnd_csf_context_set_linear); the Jacobian comes from forward
 *     differences and is kept current between refreshes by Broyden's
 *     rank-one updates, so a step costs one pass over the rows.
 *  3. Prediction: every used row with the constants, each threshold searched
 *     to 0.02 dB: the training figure.
 *  4. Leave-one-data-set-out: for each data set, step 2 on the other data
 *     sets' search rows from the priors (the literature's values of
 *     jnd_model_constants(), which no row chose; not the defaults, which were
 *     fitted on every data set), with forward-difference Jacobians and the
 *     same refreshes as step 2, then step 3 for the left-out rows with those
 *     constants. The left-out rows are never searched and the constants
 *     given (base) never reach a fold: the procedure is the same whatever
 *     figure it gives. A constant only the left-out set measures stays near
 *     its prior. o->folds may name the folds to compute (a quick look at
 *     one set); each is the same fold, and the pooled figure covers those
 *     sets only. The first Jacobian is computed once at the priors over
 *     every search row and each fold takes its own rows of it: a row's
 *     residual and Jacobian row depend only on that row and the constants.
 *  5. Uncertainty: the posterior covariance s²·(JᵀJ)⁻¹ at the fit (J with
 *     the prior rows, s² the residual variance of the rows), and the spread
 *     of each constant across the folds. */
#include <lapacke.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "tasks/tasks.h"

#define FD_STEP 0.02      /* forward-difference step, natural-log units */
#define MAX_STEP 1.0      /* largest change of one ln(constant) in a step */
#define STOP_GAIN 1e-4    /* a fit stops when a step gains less than this fraction of the objective */
#define MAX_REJECTS 8     /* or when this many steps in a row, each damped 4× more, do not lower it */
#define FIT_REFRESHES 3   /* forward-difference Jacobians a fit may compute after its first */
/* the priors' weight against every row of the data: the defaults were
 * fitted with 4 dB against every second row, which is this against all */
#define PRIOR_WEIGHT_DB (4.0 * M_SQRT2)

void jnd_csf_options_defaults(jnd_csf_options *o) {
  memset(o, 0, sizeof *o);
  o->search_every = 1;
  o->max_iterations = 40;
  o->prior_weight_db = PRIOR_WEIGHT_DB;
}

typedef struct {
  const jnd_csf_data *d;
  const jnd_csf_options *o;
  jnd_model_params base;
  int threads;
  int K;                            /* fitted constants */
  int idx[JND_MAX_CONSTANTS];       /* their indices in jnd_model_constants() */
  double mu[JND_MAX_CONSTANTS];     /* ln prior */
  double sd[JND_MAX_CONSTANTS];     /* prior width */
  double lo[JND_MAX_CONSTANTS], hi[JND_MAX_CONSTANTS]; /* ln bounds */
  int passes;
} fit_ctx;

static void params_at(const fit_ctx *f, const double *theta, jnd_model_params *p) {
  *p = f->base;
  for (int k = 0; k < f->K; k++) jnd_model_constant_set(p, f->idx[k], exp(theta[k]));
}

/* Predicted sensitivities of rows[0..n) with constants p: the linear
 * surrogate or the searched threshold. Rows are independent and each thread
 * keeps its own models, so the values do not depend on the thread count. */
static jnd_status predict(fit_ctx *f, const jnd_model_params *p, const int *rows, int n, int linear, double *out,
                          const char *stage) {
  jnd_model_params one = *p;
  one.threads = 1;
  int failed_row = -1, done = 0;
  char msg[512] = "";
  jnd_status fail = JND_OK;
  f->passes++;
#pragma omp parallel num_threads(f->threads)
  {
    jnd_csf_context *cx = NULL;
    jnd_status s = jnd_csf_context_create(&one, &cx);
    if (s == JND_OK) jnd_csf_context_set_linear(cx, linear);
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i < n; i++) {
      double sens = NAN;
      jnd_status si = s == JND_OK ? jnd_csf_threshold(cx, &f->d->rows[rows[i]].st, &sens, NULL) : s;
      out[i] = sens;
#pragma omp critical
      {
        if (si != JND_OK && (failed_row < 0 || i < failed_row)) {
          failed_row = i;
          fail = si;
          snprintf(msg, sizeof msg, "%s", jnd_last_error());
        }
        done++;
        if (stage && f->o->progress) f->o->progress(f->o->user, stage, done, n);
      }
    }
    jnd_csf_context_free(cx);
  }
  if (fail != JND_OK)
    return jnd_fail(fail, "csf: line %d: %s", f->d->rows[rows[failed_row]].line, msg[0] ? msg : "failed");
  return JND_OK;
}

/* residuals at theta: n rows' errors in dB, then the K prior terms */
static jnd_status residuals(fit_ctx *f, const double *theta, const int *rows, int n, double *r) {
  jnd_model_params p;
  params_at(f, theta, &p);
  jnd_status s = predict(f, &p, rows, n, 1, r, NULL);
  if (s != JND_OK) return s;
  for (int i = 0; i < n; i++) r[i] = 20.0 * log10(fmax(r[i], 1e-9) / f->d->rows[rows[i]].measured);
  /* each search row stands for the search_every rows of its data set it
   * was picked from: the objective is the one over every row, whatever
   * the subsample, so a fit on fewer rows is not pulled harder to the priors */
  const double w = f->o->prior_weight_db / sqrt(f->o->search_every);
  for (int k = 0; k < f->K; k++) r[n + k] = w * (theta[k] - f->mu[k]) / f->sd[k];
  return JND_OK;
}

static double sumsq(const double *r, int n) {
  double s = 0;
  for (int i = 0; i < n; i++) s += r[i] * r[i];
  return s;
}

/* J (n + K rows × K, row-major) by forward differences; the prior rows are exact */
static jnd_status jacobian(fit_ctx *f, const double *theta, const int *rows, int n, const double *r, double *J) {
  const int K = f->K;
  double *rk = jnd_alloc((size_t)(n + K), sizeof *rk), th[JND_MAX_CONSTANTS];
  if (!rk) return JND_ERR_NOMEM;
  jnd_status s = JND_OK;
  for (int k = 0; k < K && s == JND_OK; k++) {
    memcpy(th, theta, sizeof(double) * K);
    double h = th[k] + FD_STEP <= f->hi[k] ? FD_STEP : -FD_STEP;
    th[k] += h;
    s = residuals(f, th, rows, n, rk);
    for (int i = 0; i < n + K && s == JND_OK; i++) J[(size_t)i * K + k] = (rk[i] - r[i]) / h;
    if (f->o->progress) f->o->progress(f->o->user, "jacobian", k + 1, K);
  }
  free(rk);
  return s;
}

/* Solves (A + λ·diag(A)) x = b for symmetric positive A (K × K), by Cholesky */
static int solve_damped(const double *A, double lambda, const double *b, double *x, int K) {
  double M[JND_MAX_CONSTANTS * JND_MAX_CONSTANTS];
  for (int i = 0; i < K; i++)
    for (int j = 0; j < K; j++) M[i * K + j] = A[i * K + j] + (i == j ? lambda * fmax(A[i * K + i], 1e-9) : 0);
  memcpy(x, b, sizeof(double) * K);
  return LAPACKE_dposv(LAPACK_ROW_MAJOR, 'U', K, 1, M, K, x, 1) == 0;
}

static void normal_equations(const double *J, const double *r, int m, int K, double *A, double *g) {
  for (int a = 0; a < K; a++) {
    g[a] = 0;
    for (int b = 0; b < K; b++) A[a * K + b] = 0;
  }
  for (int i = 0; i < m; i++) {
    const double *Ji = J + (size_t)i * K;
    for (int a = 0; a < K; a++) {
      g[a] += Ji[a] * r[i];
      for (int b = 0; b < K; b++) A[a * K + b] += Ji[a] * Ji[b];
    }
  }
}

/* Levenberg–Marquardt from theta over rows[0..n); J and r hold the Jacobian
 * and residuals at theta on entry and on return. fd_refreshes: how many
 * forward-difference Jacobians the fit may compute when Broyden's stalls. */
static jnd_status lm_fit(fit_ctx *f, const int *rows, int n, double *theta, double *J, double *r, int fd_refreshes) {
  const int K = f->K, m = n + K;
  double *r2 = jnd_alloc((size_t)m, sizeof *r2);
  if (!r2) return JND_ERR_NOMEM;
  double A[JND_MAX_CONSTANTS * JND_MAX_CONSTANTS], g[JND_MAX_CONSTANTS], step[JND_MAX_CONSTANTS],
      th2[JND_MAX_CONSTANTS];
  double lambda = 1e-3, sse = sumsq(r, m);
  int rejects = 0, fresh = 1; /* fresh: J is a forward-difference Jacobian at theta */
  jnd_status s = JND_OK;
  for (int it = 0; it < f->o->max_iterations; it++) {
    normal_equations(J, r, m, K, A, g);
    for (int k = 0; k < K; k++) g[k] = -g[k];
    if (!solve_damped(A, lambda, g, step, K)) {
      lambda *= 10;
      continue;
    }
    double big = 0;
    for (int k = 0; k < K; k++) big = fmax(big, fabs(step[k]));
    if (big > MAX_STEP)
      for (int k = 0; k < K; k++) step[k] *= MAX_STEP / big;
    double dd = 0;
    for (int k = 0; k < K; k++) {
      th2[k] = jnd_clampd(theta[k] + step[k], f->lo[k], f->hi[k]);
      step[k] = th2[k] - theta[k];
      dd += step[k] * step[k];
    }
    if (dd < 1e-16) break;
    if ((s = residuals(f, th2, rows, n, r2)) != JND_OK) break;
    double sse2 = sumsq(r2, m);
    /* Broyden's update of the rows' part (the prior rows are linear and exact) */
    for (int i = 0; i < n; i++) {
      double *Ji = J + (size_t)i * K, pred = 0;
      for (int k = 0; k < K; k++) pred += Ji[k] * step[k];
      double c = (r2[i] - r[i] - pred) / dd;
      for (int k = 0; k < K; k++) Ji[k] += c * step[k];
    }
    if (sse2 < sse) {
      double gain = (sse - sse2) / sse;
      memcpy(theta, th2, sizeof(double) * K);
      memcpy(r, r2, sizeof(double) * m);
      sse = sse2;
      lambda = fmax(lambda / 3, 1e-7);
      rejects = 0;
      fresh = 0;
      if (f->o->progress) f->o->progress(f->o->user, "fit", it + 1, f->o->max_iterations);
      if (gain < STOP_GAIN) {
        if (fd_refreshes <= 0) break;
        /* converged on Broyden's Jacobian: confirm on a fresh one */
        if ((s = jacobian(f, theta, rows, n, r, J)) != JND_OK) break;
        fd_refreshes--;
        fresh = 1;
        lambda = 1e-3;
      }
    } else {
      lambda *= 4;
      ++rejects;
      if (rejects >= 3 && !fresh && fd_refreshes > 0) {
        /* Broyden's Jacobian has gone stale: a fresh one */
        if ((s = jacobian(f, theta, rows, n, r, J)) != JND_OK) break;
        fd_refreshes--;
        fresh = 1;
        rejects = 0;
        lambda = 1e-3;
      } else if (rejects >= MAX_REJECTS) {
        /* the damping has made the step a short one down the gradient,
         * and it still does not lower the cost: a minimum */
        break;
      }
    }
  }
  free(r2);
  return s;
}

/* ln-unit posterior standard deviations: s²·(JᵀJ)⁻¹, s² the rows' residual variance */
static void posterior_sd(const fit_ctx *f, const double *J, const double *r, int n, double *sd) {
  const int K = f->K;
  double A[JND_MAX_CONSTANTS * JND_MAX_CONSTANTS], g[JND_MAX_CONSTANTS];
  normal_equations(J, r, n + K, K, A, g);
  double s2 = n > K ? sumsq(r, n) / (n - K) : NAN;
  if (LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'U', K, A, K) != 0 || LAPACKE_dpotri(LAPACK_ROW_MAJOR, 'U', K, A, K) != 0) {
    for (int k = 0; k < K; k++) sd[k] = NAN;
    return;
  }
  /* f's priors are in J's rows, scaled to dB like the rows' residuals */
  for (int k = 0; k < K; k++) sd[k] = sqrt(s2 * A[k * K + k]);
}

static double rms_of(const double *e, int n) { return n ? sqrt(sumsq(e, n) / n) : NAN; }

/* per data set and pooled RMS of the errors of pred (NaN: not predicted) */
static void score(const jnd_csf_data *d, const double *pred, int cv, jnd_csf_result *r) {
  int nsets = d->ndatasets;
  for (int ds = -1; ds < nsets; ds++) {
    double sa = 0, ss = 0, se = 0;
    int na = 0, ns = 0;
    for (int i = 0; i < d->nrows; i++) {
      const jnd_csf_row *row = &d->rows[i];
      if (!row->use || isnan(pred[i]) || (ds >= 0 && row->dataset != ds)) continue;
      double e = 20 * log10(pred[i] / row->measured);
      sa += e * e;
      se += e;
      na++;
      if (row->st.t_frequency <= 0) {
        ss += e * e;
        ns++;
      }
    }
    jnd_csf_score *sc = ds < 0 ? &r->pooled : &r->dataset[ds];
    double all = na ? sqrt(sa / na) : NAN, st = ns ? sqrt(ss / ns) : NAN, bias = na ? se / na : NAN;
    if (cv) {
      sc->cv_rmse_db = all;
      sc->cv_rmse_db_static = st;
      sc->cv_bias_db = bias;
    } else {
      sc->rows = na;
      sc->static_rows = ns;
      sc->rmse_db = all;
      sc->rmse_db_static = st;
      sc->bias_db = bias;
    }
  }
}

void jnd_csf_result_free(jnd_csf_result *r) {
  if (!r) return;
  free(r->predicted);
  free(r->predicted_cv);
  free(r->dataset);
  free(r->fold_value);
  memset(r, 0, sizeof *r);
}

/* the data set called name, or -1 */
static int fold_index(const jnd_csf_data *d, const char *name) {
  for (int ds = 0; ds < d->ndatasets; ds++)
    if (strcmp(d->datasets[ds], name) == 0) return ds;
  return -1;
}

/* whether the cross-validation computes data set ds's fold (o->folds) */
static int fold_wanted(const jnd_csf_data *d, const jnd_csf_options *o, int ds) {
  if (o->nfolds <= 0) return 1;
  for (int q = 0; q < o->nfolds; q++)
    if (fold_index(d, o->folds[q]) == ds) return 1;
  return 0;
}

jnd_status jnd_csf_evaluate(const jnd_csf_data *d, const jnd_model_params *base, const jnd_csf_options *opt,
                            jnd_csf_result *r) {
  memset(r, 0, sizeof *r);
  jnd_csf_options od;
  if (!opt) {
    jnd_csf_options_defaults(&od);
    opt = &od;
  }
  if (opt->search_every < 1 || opt->max_iterations < 0 || !(opt->prior_weight_db > 0))
    return jnd_fail(JND_ERR_ARG, "csf: search_every >= 1, max_iterations >= 0 and prior_weight_db > 0 needed");
  for (int q = 0; q < opt->nfolds; q++)
    if (fold_index(d, opt->folds[q]) < 0) return jnd_fail(JND_ERR_ARG, "csf: fold '%s': no data set of that name", opt->folds[q]);
  fit_ctx f;
  memset(&f, 0, sizeof f);
  f.d = d;
  f.o = opt;
  f.base = *base;
  f.threads = jnd_threads(opt->threads);
  const jnd_model_constant *list[JND_MAX_CONSTANTS];
  const int nc = jnd_model_constants(list, JND_MAX_CONSTANTS);
  for (int k = 0; k < nc; k++) {
    if (opt->fit_mask_set ? !(opt->fit_mask >> k & 1) : list[k]->held) continue;
    double v = jnd_model_constant_get(base, k);
    if (!(v > 0)) continue; /* a constant at 0 is switched off, not fitted */
    f.idx[f.K] = k;
    f.mu[f.K] = log(list[k]->prior);
    f.sd[f.K] = list[k]->prior_sd;
    f.lo[f.K] = log(list[k]->lo);
    f.hi[f.K] = log(list[k]->hi);
    f.K++;
  }
  r->nrows = d->nrows;
  r->ndatasets = d->ndatasets;
  r->nconstants = nc;
  r->params = *base;
  r->predicted = jnd_alloc(d->nrows ? (size_t)d->nrows : 1, sizeof(double));
  r->predicted_cv = jnd_alloc(d->nrows ? (size_t)d->nrows : 1, sizeof(double));
  r->dataset = jnd_calloc(d->ndatasets ? (size_t)d->ndatasets : 1, sizeof(jnd_csf_score));
  int *used = jnd_alloc(d->nrows ? (size_t)d->nrows : 1, sizeof(int));
  int *search = jnd_alloc(d->nrows ? (size_t)d->nrows : 1, sizeof(int));
  int *seen = jnd_calloc(d->ndatasets ? (size_t)d->ndatasets : 1, sizeof(int));
  double *pred = jnd_alloc(d->nrows ? (size_t)d->nrows : 1, sizeof(double));
  double *J = NULL, *res = NULL, *Jf = NULL, *rf = NULL;
  jnd_status s = JND_OK;
  if (!r->predicted || !r->predicted_cv || !r->dataset || !used || !search || !seen || !pred) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  int nused = 0, nsearch = 0;
  for (int i = 0; i < d->nrows; i++) {
    r->predicted[i] = r->predicted_cv[i] = NAN;
    if (!d->rows[i].use) continue;
    used[nused++] = i;
    /* every N-th row of each data set */
    if (seen[d->rows[i].dataset]++ % opt->search_every == 0) search[nsearch++] = i;
  }
  if (nused == 0) {
    s = jnd_fail(JND_ERR_ARG, "csf: no rows to predict");
    goto done;
  }
  for (int k = 0; k < nc; k++) r->sd_ln[k] = r->fold_sd_ln[k] = NAN;
  const int K = f.K, fitting = (opt->fit || opt->cross_validate) && K > 0;
  double theta[JND_MAX_CONSTANTS];
  for (int k = 0; k < K; k++) theta[k] = log(jnd_model_constant_get(base, f.idx[k]));
  if (fitting) {
    J = jnd_alloc((size_t)(nsearch + K) * K, sizeof *J);
    res = jnd_alloc((size_t)(nsearch + K), sizeof *res);
    if (!J || !res) {
      s = JND_ERR_NOMEM;
      goto done;
    }
    if ((s = residuals(&f, theta, search, nsearch, res)) != JND_OK) goto done;
    if (opt->fit) {
      if ((s = jacobian(&f, theta, search, nsearch, res, J)) != JND_OK) goto done;
      if ((s = lm_fit(&f, search, nsearch, theta, J, res, FIT_REFRESHES)) != JND_OK) goto done;
      params_at(&f, theta, &r->params);
      double sd[JND_MAX_CONSTANTS];
      posterior_sd(&f, J, res, nsearch, sd);
      for (int k = 0; k < K; k++) {
        r->fitted[f.idx[k]] = 1;
        r->sd_ln[f.idx[k]] = sd[k];
      }
    }
    r->search_rmse_db = rms_of(res, nsearch);
  }
  /* the training figure: every used row, searched */
  if ((s = predict(&f, &r->params, used, nused, 0, pred, "predict")) != JND_OK) goto done;
  for (int i = 0; i < nused; i++) r->predicted[used[i]] = pred[i];
  score(d, r->predicted, 0, r);

  if (opt->cross_validate && fitting) {
    /* the folds start from the priors, which no row chose: J and res at
     * them over every search row (a row's residual and Jacobian row depend
     * on that row and the constants only, so each fold takes its own rows
     * from these as a forward difference of its own would give them) */
    double theta0[JND_MAX_CONSTANTS];
    for (int k = 0; k < K; k++) theta0[k] = jnd_clampd(f.mu[k], f.lo[k], f.hi[k]);
    if ((s = residuals(&f, theta0, search, nsearch, res)) != JND_OK) goto done;
    if ((s = jacobian(&f, theta0, search, nsearch, res, J)) != JND_OK) goto done;
    r->fold_value = jnd_alloc((size_t)d->ndatasets * nc, sizeof(double));
    Jf = jnd_alloc((size_t)(nsearch + K) * K, sizeof *Jf);
    rf = jnd_alloc((size_t)(nsearch + K), sizeof *rf);
    int *rows_f = jnd_alloc((size_t)nsearch, sizeof(int)), *left = jnd_alloc((size_t)nused, sizeof(int));
    if (!r->fold_value || !Jf || !rf || !rows_f || !left) {
      free(rows_f);
      free(left);
      s = JND_ERR_NOMEM;
      goto done;
    }
    double thetaf[JND_MAX_CONSTANTS];
    for (int ds = 0; ds < d->ndatasets && s == JND_OK; ds++) {
      for (int k = 0; k < nc; k++) r->fold_value[(size_t)ds * nc + k] = NAN;
      int nf = 0, nleft = 0;
      /* the other data sets' search rows, with their Jacobian rows and residuals */
      for (int q = 0; q < nsearch; q++) {
        if (d->rows[search[q]].dataset == ds) continue;
        rows_f[nf] = search[q];
        memcpy(Jf + (size_t)nf * K, J + (size_t)q * K, sizeof(double) * K);
        rf[nf] = res[q];
        nf++;
      }
      for (int q = 0; q < nused; q++)
        if (d->rows[used[q]].dataset == ds) left[nleft++] = used[q];
      if (nleft == 0 || nf == 0 || !fold_wanted(d, opt, ds)) continue;
      memcpy(Jf + (size_t)nf * K, J + (size_t)nsearch * K, sizeof(double) * K * K);
      memcpy(thetaf, theta0, sizeof(double) * K);
      for (int k = 0; k < K; k++) rf[nf + k] = res[nsearch + k];
      if (opt->progress) opt->progress(opt->user, d->datasets[ds], 0, 1);
      if ((s = lm_fit(&f, rows_f, nf, thetaf, Jf, rf, FIT_REFRESHES)) != JND_OK) break;
      jnd_model_params pf;
      params_at(&f, thetaf, &pf);
      for (int k = 0; k < nc; k++) r->fold_value[(size_t)ds * nc + k] = jnd_model_constant_get(&pf, k);
      if ((s = predict(&f, &pf, left, nleft, 0, pred, NULL)) != JND_OK) break;
      for (int q = 0; q < nleft; q++) r->predicted_cv[left[q]] = pred[q];
    }
    free(rows_f);
    free(left);
    if (s != JND_OK) goto done;
    score(d, r->predicted_cv, 1, r);
    for (int k = 0; k < K; k++) {
      double m = 0, m2 = 0;
      int n = 0;
      for (int ds = 0; ds < d->ndatasets; ds++) {
        double v = r->fold_value[(size_t)ds * nc + f.idx[k]];
        if (isnan(v)) continue;
        m += log(v);
        m2 += log(v) * log(v);
        n++;
      }
      if (n > 1) r->fold_sd_ln[f.idx[k]] = sqrt(fmax(m2 / n - (m / n) * (m / n), 0) * n / (n - 1));
    }
  } else {
    r->pooled.cv_rmse_db = r->pooled.cv_rmse_db_static = r->pooled.cv_bias_db = NAN;
    for (int ds = 0; ds < d->ndatasets; ds++)
      r->dataset[ds].cv_rmse_db = r->dataset[ds].cv_rmse_db_static = r->dataset[ds].cv_bias_db = NAN;
  }
  r->model_passes = f.passes;
done:
  free(used);
  free(search);
  free(seen);
  free(pred);
  free(J);
  free(res);
  free(Jf);
  free(rf);
  if (s != JND_OK) jnd_csf_result_free(r);
  return s;
}
