/* The knee of a curve: the point farthest from the chord between its first
 * and last points, with both axes scaled to 0..1 over the curve (the
 * "maximum distance to the chord" rule, Kneedle's difference curve). One
 * rule for every task that turns a trade-off curve into a choice: pca's
 * cumulative energy against components (001, a curve above its chord) and
 * lod's error against level of detail (003 §3, Hypothesis 1: the Point of
 * Imperceptibility is the knee of the Pareto curve, a curve below its chord).
 *
 * Scaling both axes to 0..1 makes the rule independent of the units of x and
 * y (003's error has none; triangles and components have others). The
 * distance to the chord is then (chord(x) − y)·cos θ for a fixed θ, so the
 * farthest point is the one with the largest vertical gap.
 *
 * A sampled curve's knee is only known to its sampling: points whose gaps
 * differ by a rounding's worth are a tie. With tie > 0 the first point whose
 * gap is within that fraction of the largest is the knee (the first: for an
 * error curve against a falling level of detail, the finer level — the
 * conservative side of "imperceptible"). */
#include <math.h>

#include "jnd.h"

int jnd_knee(const double *x, const double *y, int n, jnd_knee_side side, double tie) {
  if (n < 1) return -1;
  if (n < 3) return 0;
  for (int i = 0; i < n; i++)
    if (!isfinite(x[i]) || !isfinite(y[i])) return -1;
  double x0 = x[0], x1 = x[n - 1], y0 = y[0], y1 = y[n - 1];
  double xs = x1 - x0, ys = y1 - y0;
  if (xs == 0) return 0;
  /* a flat curve (y1 == y0) keeps y unscaled: the gap is then y's own */
  double yscale = ys != 0 ? fabs(ys) : 1;
  double best_gap = 0;
  for (int pass = 0; pass < 2; pass++)
    for (int i = 1; i < n - 1; i++) {
      double t = (x[i] - x0) / xs;                       /* 0..1 along the chord */
      double chord = t * (ys / yscale), v = (y[i] - y0) / yscale;
      double gap = side == JND_KNEE_BELOW ? chord - v : v - chord;
      if (pass == 0) {
        if (gap > best_gap) best_gap = gap;
      } else if (best_gap > 0 && gap > 0 && gap >= best_gap * (1 - tie) - 1e-12) {
        /* the first point within the tolerance of the farthest (1e-12: rounding of the scaling) */
        return i;
      }
    }
  return 0;
}
