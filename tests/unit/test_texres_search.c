/* texres's search (000 §4–§9, docs/texres.md), by properties whose
 * expected values come from outside the code: the candidates from the
 * halving series written out here, the held-out views compared with the
 * views the choice was made on, the reported bounds recomputed from the
 * reported counts, and the chosen sizes' order in the threshold p. The
 * builtin asset is rendered at 96² from 3 views, so each run takes a
 * second. */
#include <math.h>

#include "jnd.h"
#include "test.h"

static int longer(const int *wh) { return wh[0] > wh[1] ? wh[0] : wh[1]; }

/* the builtin asset with maps of map_size², or NULL (and a skip) where no
 * OpenGL context can be had */
static jnd_scene *builtin(int map_size) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return NULL;
  }
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = map_size;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  return s;
}

static void small_params(jnd_texres_params *p) {
  jnd_texres_defaults(p);
  p->judge.views.sampling.count = 3;
  p->judge.views.render.width = p->judge.views.render.height = 96;
  p->judge.views.sampling.coverage = 0.9;
  p->judge.views.render.anisotropy = 1;
  p->judge.views.render.samples = 1;
  p->confirm_rounds = 0;
}

/* Clopper–Pearson's upper bound of k of n at confidence c by bisection of
 * the binomial CDF written as a sum of products */
static double cp_upper(int k, int n, double c) {
  if (k >= n) return 1;
  double lo = 0, hi = 1;
  for (int it = 0; it < 200; it++) {
    double u = 0.5 * (lo + hi), sum = 0;
    for (int i = 0; i <= k; i++) {
      double t = 1;
      for (int j = 0; j < i; j++) t *= (double)(n - j) / (j + 1) * u;
      for (int j = 0; j < n - i; j++) t *= 1 - u;
      sum += t;
    }
    if (sum > 1 - c) lo = u;
    else hi = u;
  }
  return 0.5 * (lo + hi);
}

/* the criterion a result reports, recomputed from its P per view */
static void check_reported_criterion(const double *P, int n, const jnd_criterion_result *r, double p, double q,
                                     double confidence) {
  int above = 0;
  for (int v = 0; v < n; v++) above += P[v] > p;
  CHECK(r->views == n && r->above == above);
  CHECK(r->allowed == (int)floor(q * n + 1e-9));
  CHECK(r->pass == (above <= r->allowed));
  CHECK_NEAR(r->fraction_above, (double)above / n, 1e-12);
  CHECK_NEAR(r->fraction_upper, cp_upper(above, n, confidence), 1e-7);
}

/* The verification views are views the choice was not made on (docs/
 * texres.md "Held-out views"): other cameras and lights, so the same
 * combination gives other P there. Their P is compared with every set of
 * the choice's views (the first set and the confirmation set that joined);
 * with p near 1 every map goes down to its smallest candidate, so every
 * view sees a difference (no P is 0 because nothing changed). */
TEST(held_out_views_are_not_the_views_the_choice_was_made_on) {
  jnd_scene *s = builtin(128);
  if (!s) return;
  jnd_texres_params p;
  small_params(&p);
  p.judge.criterion.p = 0.99;
  p.margin = 0;
  p.verify_views = 3;
  p.confirm_rounds = 1;
  jnd_texres_result r = {0};
  double held[3] = {0};
  CHECK_OK(jnd_texres_search(s, &p, &r));
  CHECK(r.verify_views == 3 && r.verify_p != NULL);
  if (r.verify_p) memcpy(held, r.verify_p, sizeof held);
  CHECK(r.nviews >= 3 && r.nviews % 3 == 0);
  if (r.verify_p && r.view_p) {
    for (int v = 0; v < 3; v++) CHECK(r.verify_p[v] > 0);
    for (int v = 0; v < r.nviews; v++) CHECK(r.view_p[v] > 0);
    /* no held-out view's P is any choice view's P: other cameras */
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < r.nviews; b++) {
        if (r.verify_p[a] == r.view_p[b]) fprintf(stderr, "held-out view %d has choice view %d's P %.9g\n", a, b, r.view_p[b]);
        CHECK(r.verify_p[a] != r.view_p[b]);
      }
    check_reported_criterion(r.verify_p, 3, &r.verify, 0.99, p.judge.criterion.q, p.judge.criterion.confidence);
    check_reported_criterion(r.view_p, r.nviews, &r.views, 0.99, p.judge.criterion.q, p.judge.criterion.confidence);
  }
  jnd_texres_result_clear(&r);
  /* the held-out views depend on the seed of the views, as the choice's do:
   * another seed, other held-out views */
  jnd_texres_result r2 = {0};
  p.judge.views.sampling.seed += 1;
  CHECK_OK(jnd_texres_search(s, &p, &r2));
  if (r2.verify_p)
    for (int a = 0; a < 3; a++) CHECK(r2.verify_p[a] != held[a]);
  jnd_texres_result_clear(&r2);
  jnd_scene_free(s);
}

/* The candidates of a map are its original and its halvings down to
 * min_size, min_size included when a halving lands on it (docs/texres.md);
 * with p near 1 everything passes and every map goes to the smallest. */
TEST(the_smallest_allowed_size_is_a_candidate_and_is_chosen_when_everything_passes) {
  jnd_scene *s = builtin(128);
  if (!s) return;
  static const int floors[] = {16, 64};
  for (size_t f = 0; f < sizeof floors / sizeof floors[0]; f++) {
    jnd_texres_params p;
    small_params(&p);
    p.judge.criterion.p = 0.99;
    p.margin = 0;
    p.min_size = floors[f];
    p.judge.views.sampling.coverage = 0.3;   /* a small object: even 32² maps pass */
    jnd_texres_result r = {0};
    CHECK_OK(jnd_texres_search(s, &p, &r));
    /* the halvings of 128 that are >= the floor, by hand */
    int want[8], nw = 0;
    for (int side = 128; side >= floors[f]; side /= 2) want[nw++] = side;
    for (int i = 0; i < r.nmaps; i++) {
      const jnd_texres_map *m = &r.maps[i];
      CHECK(longer(m->orig) == 128);
      fprintf(stderr, "%s: floor %d, mip bound %d, %d candidates down to %d, chosen %d\n", m->name, floors[f],
              longer(m->mip_bound), m->ncand, longer(m->cand[m->ncand - 1]), longer(m->chosen));
      /* every halving is a candidate, and none below the floor (the mip
       * bound may add one, never below the floor's halving series' end) */
      for (int w = 0; w < nw; w++) {
        int found = 0;
        for (int k = 0; k < m->ncand; k++) found |= longer(m->cand[k]) == want[w];
        if (!found) fprintf(stderr, "%s: min size %d: no candidate %d\n", m->name, floors[f], want[w]);
        CHECK(found);
      }
      /* the smallest candidate: the floor's, or the mip-usage bound where
       * that lies below the floor (docs/texres.md: the bound is always a
       * candidate) */
      int smallest = want[nw - 1] < longer(m->mip_bound) ? want[nw - 1] : longer(m->mip_bound);
      CHECK(longer(m->cand[m->ncand - 1]) == smallest);
      /* everything passes: the smallest candidate */
      if (longer(m->chosen) != smallest) {
        fprintf(stderr, "%s floor %d chosen %d; series:", m->name, floors[f], longer(m->chosen));
        for (int k = 0; k < m->ncand; k++) fprintf(stderr, " %d:%g", longer(m->cand[k]), m->series[k]);
        fprintf(stderr, "\n");
      }
      CHECK(longer(m->chosen) == smallest);
    }
    jnd_texres_result_clear(&r);
  }
  jnd_scene_free(s);
}

/* A larger threshold p never asks for larger maps: the chosen size is
 * monotone in p, and at p near 0 no map goes below its mip-usage bound */
TEST(chosen_sizes_never_grow_as_the_threshold_rises) {
  jnd_scene *s = builtin(128);
  if (!s) return;
  static const double ps[] = {0.02, 0.2, 0.99};
  int prev[16] = {0}, n = 0;
  for (size_t t = 0; t < sizeof ps / sizeof ps[0]; t++) {
    jnd_texres_params p;
    small_params(&p);
    p.judge.criterion.p = ps[t];
    jnd_texres_result r = {0};
    CHECK_OK(jnd_texres_search(s, &p, &r));
    CHECK_NEAR(r.choice_p, ps[t] * (1 - p.margin), 1e-15);
    for (int i = 0; i < r.nmaps && i < 16; i++) {
      int L = longer(r.maps[i].chosen);
      CHECK(L <= longer(r.maps[i].mip_bound));
      if (t) CHECK(L <= prev[i]);
      prev[i] = L;
    }
    n = r.nmaps;
    jnd_texres_result_clear(&r);
  }
  CHECK(n == 4);
  jnd_scene_free(s);
}

RUN_TESTS(held_out_views_are_not_the_views_the_choice_was_made_on,
          the_smallest_allowed_size_is_a_candidate_and_is_chosen_when_everything_passes,
          chosen_sizes_never_grow_as_the_threshold_rises)
