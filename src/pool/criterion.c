/* The view criterion of 000 §9: "at most a fraction q of the sampled views
 * above P = p", the verdict every decision of jnd rests on. One
 * implementation, used by every task, so that texres, pca and the rest mean
 * the same thing by "passes".
 *
 * The statistic is the (⌊q·n⌋ + 1)-th largest P: at most ⌊q·n⌋ views lie
 * above p exactly when it is ≤ p, so a search can compare one number with p,
 * and its distance from p says how close a candidate is to the edge.
 *
 * With a handful of views the observed fraction is a noisy estimate of the
 * fraction over all views a player could see; the Clopper–Pearson upper bound
 * says how large that fraction could still be. */
#include <math.h>
#include <stdlib.h>

#include "core/core.h"
#include "jnd.h"

/* 000 §9: "at most 10% of the sampled views have the probability of
 * detection greater than 0.2". The confidence of the upper bound is ours. */
#define CRITERION_P 0.2
#define CRITERION_Q 0.1
#define CRITERION_CONFIDENCE 0.9

void jnd_criterion_defaults(jnd_criterion *c) {
  c->p = CRITERION_P;
  c->q = CRITERION_Q;
  c->confidence = CRITERION_CONFIDENCE;
}

/* P(X <= k) for X ~ Binomial(n, u), summed in log space */
static double binomial_cdf(int k, int n, double u) {
  if (u <= 0) return 1;
  if (u >= 1) return k >= n ? 1 : 0;
  double lu = log(u), lv = log1p(-u), sum = 0;
  for (int i = 0; i <= k; i++)
    sum += exp(lgamma(n + 1.0) - lgamma(i + 1.0) - lgamma(n - i + 1.0) + i * lu + (n - i) * lv);
  return sum;
}

double jnd_binomial_upper(int k, int n, double confidence) {
  if (n <= 0 || k < 0 || !(confidence > 0 && confidence < 1)) return NAN;
  if (k >= n) return 1;
  double alpha = 1 - confidence, lo = (double)k / n, hi = 1;
  /* the CDF falls as u grows: bisect for CDF(u) = alpha */
  for (int it = 0; it < 100; it++) {
    double mid = 0.5 * (lo + hi);
    if (binomial_cdf(k, n, mid) > alpha) lo = mid;
    else hi = mid;
  }
  return hi;
}

jnd_status jnd_criterion_eval(const double *p_views, int n, double p, double q, double confidence,
                              jnd_criterion_result *out) {
  if (n < 1 || !p_views) return jnd_fail(JND_ERR_ARG, "criterion: no views");
  if (!(p >= 0 && p <= 1)) return jnd_fail(JND_ERR_ARG, "criterion: P threshold %g is outside 0..1", p);
  if (!(q >= 0 && q < 1)) return jnd_fail(JND_ERR_ARG, "criterion: fraction of views %g is outside 0..1 (1 excluded)", q);
  if (!(confidence > 0 && confidence < 1))
    return jnd_fail(JND_ERR_ARG, "criterion: confidence %g is outside 0..1 (both excluded)", confidence);
  for (int i = 0; i < n; i++)
    if (!(p_views[i] >= 0 && p_views[i] <= 1)) return jnd_fail(JND_ERR_ARG, "criterion: view %d has P = %g", i, p_views[i]);
  out->views = n;
  /* the small tolerance keeps q·n integral when q is given in decimal (0.1 · 10 = 1) */
  out->allowed = (int)floor(q * n + 1e-9);
  if (out->allowed > n - 1) out->allowed = n - 1;
  out->above = 0;
  out->worst_view = 0;
  for (int i = 0; i < n; i++) {
    out->above += p_views[i] > p;
    if (p_views[i] > p_views[out->worst_view]) out->worst_view = i;
  }
  /* the (allowed + 1)-th largest: count, for each value, how many are larger
   * (n is a few dozen views at most; no allocation) */
  out->statistic = 0;
  for (int i = 0; i < n; i++) {
    int larger = 0, equal_before = 0;
    for (int j = 0; j < n; j++) {
      larger += p_views[j] > p_views[i];
      equal_before += j < i && p_views[j] == p_views[i];
    }
    if (larger + equal_before == out->allowed) {
      out->statistic = p_views[i];
      break;
    }
  }
  out->pass = out->above <= out->allowed;
  out->fraction_above = (double)out->above / n;
  out->fraction_upper = jnd_binomial_upper(out->above, n, confidence);
  return JND_OK;
}
