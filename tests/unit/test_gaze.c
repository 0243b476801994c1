/* 002's gaze-contingent models, the table L(d, ecc) and the engine's lookup. */
#include "jnd.h"
#include "test.h"

/* a disc of radius r pixels centred at (cx, cy), with coverage at its edge
 * (4 × 4 supersampling, as MSAA gives) */
static jnd_image disc(int w, int h, double cx, double cy, double r) {
  jnd_image m = {0};
  CHECK_OK(jnd_image_alloc(&m, w, h, 1));
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      int in = 0;
      for (int sy = 0; sy < 4; sy++)
        for (int sx = 0; sx < 4; sx++) {
          double dx = x + (sx + 0.5) / 4 - 0.5 - cx, dy = y + (sy + 0.5) / 4 - 0.5 - cy;
          in += dx * dx + dy * dy <= r * r;
        }
      m.data[(size_t)y * w + x] = in / 16.0f;
    }
  return m;
}

/* ---- the model's functions ---- */

TEST(weight_falls_with_eccentricity_to_its_floor) {
  jnd_gaze_model m;
  jnd_gaze_model_defaults(&m);
  double prev = INFINITY;
  for (double e = 0; e <= 90; e += 5) {
    double w = jnd_gaze_weight(&m, e);
    CHECK_LT(w, prev);
    CHECK(w > m.b);
    prev = w;
  }
  /* at the edge of the visual field it is near its floor: within 10% of
   * the fovea's excess over it (6% with the defaults fitted to the model
   * with masking over bands, β = 0.035/°; 2% with the one before) */
  CHECK_LT(jnd_gaze_weight(&m, 90) - m.b, 0.1 * (jnd_gaze_weight(&m, 0) - m.b));
}

TEST(no_difference_is_chance_and_unit_magnitude_is_the_midpoint) {
  jnd_gaze_model m;
  jnd_gaze_model_defaults(&m);
  CHECK_NEAR(jnd_gaze_spatial_probability(&m, 0, 0), 0.5, 1e-12);
  CHECK_NEAR(jnd_gaze_switch_probability(&m, 0), 0.5, 1e-12);
  CHECK_NEAR(jnd_gaze_spatial_probability(&m, 0, 1 / m.w_vdp), 0.75, 1e-12);
  CHECK_NEAR(jnd_gaze_spatial_probability(&m, 1 / m.w_g, 0), 0.75, 1e-12);
  CHECK_NEAR(jnd_gaze_switch_probability(&m, 1 / m.w_t), 0.75, 1e-12);
  /* two terms together are seen more than either alone, less than their sum (k_s > 1) */
  double one = jnd_gaze_spatial_probability(&m, 0.5, 0), both = jnd_gaze_spatial_probability(&m, 0.5, 0.5);
  CHECK_LT(one, both);
  CHECK_LT(both, jnd_gaze_spatial_probability(&m, 1.0, 0));
  double prev = 0.5;
  for (double v = 0.1; v < 10; v *= 1.5) {
    double p = jnd_gaze_spatial_probability(&m, 0, v);
    CHECK_LT(prev, p);
    CHECK(p < 1);
    prev = p;
  }
}

TEST(geometric_term_of_a_grown_disc_is_its_weighted_growth_in_degrees) {
  jnd_gaze_model m;
  jnd_gaze_model_defaults(&m);
  const double ppd = 40, r = 30, dr = 2;
  jnd_image a = disc(96, 96, 47.5, 47.5, r), b = disc(96, 96, 47.5, 47.5, r + dr);
  double g = 0;
  /* looking at the centre: every XOR pixel is within 1° of the gaze, so
   * G ≈ w(~0.8°) · (area 2π r dr) / (perimeter 2π r) / ppd */
  CHECK_OK(jnd_gaze_geometric_term(&m, &a, &b, ppd, 47.5, 47.5, &g));
  double want = jnd_gaze_weight(&m, (r + dr / 2) / ppd) * dr / ppd;
  CHECK_NEAR(g, want, 0.08 * want);
  /* the same change 20° away weighs less, by the weight's ratio */
  double g20 = 0, dist_px = 1.0 / tan(M_PI / 180 / ppd);
  CHECK_OK(jnd_gaze_geometric_term(&m, &a, &b, ppd, 47.5 - dist_px * tan(20 * M_PI / 180), 47.5, &g20));
  CHECK_LT(g20, g);
  CHECK_NEAR(g20 / g, jnd_gaze_weight(&m, 20) / jnd_gaze_weight(&m, 0.8), 0.1);
  /* identical silhouettes: nothing */
  double g0 = 1;
  CHECK_OK(jnd_gaze_geometric_term(&m, &a, &a, ppd, 0, 0, &g0));
  CHECK(g0 == 0);
  jnd_image small = disc(32, 32, 15.5, 15.5, 8);
  CHECK_STATUS(jnd_gaze_geometric_term(&m, &a, &small, ppd, 0, 0, &g0), JND_ERR_ARG);
  jnd_image_free(&a), jnd_image_free(&b), jnd_image_free(&small);
}

/* a grey-white disc as the renderer gives it: linear colour over black
 * (premultiplied by coverage) and the coverage */
static void disc_object(int n, double cx, double r, jnd_image *color, jnd_image *mask) {
  *mask = disc(n, n, cx, 0.5 * n - 0.5, r);
  CHECK_OK(jnd_image_alloc(color, n, n, 3));
  for (int ch = 0; ch < 3; ch++)
    for (size_t q = 0; q < (size_t)n * n; q++) color->data[(size_t)ch * n * n + q] = 0.45f * mask->data[q];
}

/* T of the switch from a disc of radius 20 px to one of 20 + dr, looked at
 * ecc degrees to its left, at ppd 30 */
static double switch_t(double dr, double ecc, double hz) {
  const int n = 96;
  const double ppd = 30, dist_px = 1.0 / tan(M_PI / 180 / ppd);
  jnd_image ca, ma, cb, mb;
  disc_object(n, 47.5, 20, &ca, &ma);
  disc_object(n, 47.5, 20 + dr, &cb, &mb);
  jnd_gaze_model gm;
  jnd_gaze_model_defaults(&gm);
  jnd_gaze_measure_params mp;
  jnd_gaze_measure_defaults(&mp);
  mp.switch_hz = hz;
  jnd_gaze_terms t = {0};
  CHECK_OK(jnd_gaze_switch(&gm, &mp, ppd, 47.5 - dist_px * tan(ecc * M_PI / 180), 47.5, &ca, &ma, &cb, &mb, &t));
  CHECK_NEAR(t.p, jnd_gaze_switch_probability(&gm, t.t_jnd), 1e-12);
  jnd_image_free(&ca), jnd_image_free(&ma), jnd_image_free(&cb), jnd_image_free(&mb);
  return t.t_jnd;
}

TEST(switch_is_seen_more_when_larger_and_less_away_from_the_gaze) {
  jnd_gaze_measure_params mp;
  jnd_gaze_measure_defaults(&mp);
  const double hz = mp.switch_hz;
  double t1 = switch_t(1, 0, hz), t3 = switch_t(3, 0, hz), t3_15 = switch_t(3, 15, hz), t3_40 = switch_t(3, 40, hz);
  fprintf(stderr, "switch T: dr 1 px %.3f, 3 px %.3f; at 15 deg %.3f, 40 deg %.3f\n", t1, t3, t3_15, t3_40);
  CHECK(t1 > 0);
  CHECK_LT(t1, t3);          /* a larger change: more seen */
  CHECK_LT(t3_15, t3);       /* away from the gaze: less seen */
  CHECK_LT(t3_40, t3_15);
  /* through the temporal channel: the same step judged at 25 Hz, where
   * Kelly's surface has fallen, is seen far less than at the default */
  double t3_25hz = switch_t(3, 0, 25);
  fprintf(stderr, "at 25 Hz: %.3f\n", t3_25hz);
  CHECK_LT(t3_25hz, 0.5 * t3);
}

/* ---- on renderings of a chain ---- */

static jnd_scene *sphere_chain(void) {
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.shape = 1;
  bp.map_size = 64;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  if (!s) return NULL;
  static const double errors[] = {0.004, 0.02, 0.08};
  jnd_lod_params lp;
  jnd_lod_defaults(&lp);
  lp.errors = errors;
  lp.nerrors = 3;
  CHECK_OK(jnd_scene_lod_build(s, &lp));
  return s;
}

TEST(spatial_p_rises_with_coarseness_and_falls_with_eccentricity) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = sphere_chain();
  if (!s) return;
  int L = jnd_scene_lod_count(s);
  CHECK(L == 4);
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = rp.height = 96;
  jnd_renderer *r = NULL;
  CHECK_OK(jnd_renderer_create(&rp, &r));
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = 1;
  vs.distance = 40;   /* a sphere of 1 m at 40 m: 2.9°, at ~28 pixels per degree */
  vs.fov_y_deg = 2 * asin(1.0 / 40) * 180 / M_PI * 1.2;
  jnd_view v;
  CHECK_OK(jnd_views_sample(s, &vs, &v));
  v.outputs = JND_OUT_COLOR | JND_OUT_MASK;
  jnd_frame f[4];
  for (int k = 0; k < L && r; k++) {
    CHECK_OK(jnd_scene_lod_select(s, k));
    CHECK_OK(jnd_render(r, s, &v, &f[k]));
  }
  jnd_gaze_model gm;
  jnd_gaze_model_defaults(&gm);
  jnd_gaze_measure_params mp;
  jnd_gaze_measure_defaults(&mp);
  double ppd = 96 / vs.fov_y_deg, dist_px = 1.0 / tan(M_PI / 180 / ppd);
  const double ecc[3] = {0, 10, 30};
  double P[3][4], T[3][4];
  for (int e = 0; e < 3 && r; e++) {
    double gx = 47.5 - dist_px * tan(ecc[e] * M_PI / 180);
    for (int k = 1; k < L; k++) {
      jnd_gaze_terms t;
      CHECK_OK(jnd_gaze_spatial(&gm, &mp, ppd, gx, 47.5, &f[0].color, &f[0].mask, &f[k].color, &f[k].mask, &t));
      P[e][k] = t.p;
      CHECK(t.g_deg > 0);
      fprintf(stderr, "ecc %g level %d: G %.4g deg, V %.4g JND", ecc[e], k, t.g_deg, t.v_jnd);
      CHECK_OK(jnd_gaze_switch(&gm, &mp, ppd, gx, 47.5, &f[k - 1].color, &f[k - 1].mask, &f[k].color, &f[k].mask, &t));
      T[e][k] = t.p;
      CHECK(t.t_jnd > 0);
      fprintf(stderr, ", T %.4g JND\n", t.t_jnd);
    }
  }
  if (r) {
    for (int e = 0; e < 3; e++) {
      fprintf(stderr, "ecc %g: P spatial %.3f %.3f %.3f, switch %.3f %.3f %.3f\n", ecc[e], P[e][1], P[e][2], P[e][3],
              T[e][1], T[e][2], T[e][3]);
      for (int k = 2; k < L; k++) CHECK_LT(P[e][k - 1], P[e][k]);   /* coarser: more noticed */
    }
    for (int k = 1; k < L; k++) {
      CHECK_LT(P[1][k], P[0][k]);   /* farther from the gaze: less noticed */
      CHECK_LT(P[2][k], P[1][k]);
      CHECK(T[2][k] <= T[0][k]);
    }
    CHECK_LT(T[1][3], T[0][3]);
    CHECK(P[0][3] > 0.75);   /* the coarsest level looked at is seen */
  }
  for (int k = 0; k < L && r; k++) jnd_frame_free(&f[k]);
  jnd_renderer_free(r);
  jnd_scene_free(s);
}

TEST(table_level_never_gets_finer_with_distance_or_eccentricity) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = sphere_chain();
  if (!s) return;
  static const double dist[] = {20, 40, 80}, ecc[] = {0, 10, 25, 50};
  jnd_gaze_table_params p;
  jnd_gaze_table_defaults(&p);
  CHECK_NEAR(p.threshold, 0.75, 0);   /* 002 "Gaze-contingent LOD prediction": the midpoint, 0.75 */
  p.distances_m = dist, p.ndistances = 3;
  p.eccentricities_deg = ecc, p.neccentricities = 4;
  p.orientations = 2;
  p.min_px = 48, p.max_px = 64;
  p.near_window = 0;   /* one rendering per distance, orientation and level (windows: tests/e2e/gaze.sh) */
  jnd_gaze_table t;
  CHECK_OK(jnd_gaze_table_run(s, &p, &t));
  if (t.level) {
    CHECK(t.renderings == 3 * 2 * 4);
    int any_coarse = 0, any_fine = 0;
    for (int d = 0; d < 3; d++)
      for (int e = 0; e < 4; e++) {
        int l = t.level[d * 4 + e];
        fprintf(stderr, "%d%c", l, e == 3 ? '\n' : ' ');
        if (d + 1 < 3) CHECK(t.level[(d + 1) * 4 + e] >= l);
        if (e + 1 < 4) CHECK(t.level[d * 4 + e + 1] >= l);
        CHECK(l <= t.level_raw[d * 4 + e]);
        /* the chosen level's worst-orientation probabilities are below the
         * threshold, 002's 0.75 (the 2AFC midpoint) by default: written
         * here as the paper gives it, not read from the parameters */
        const double paper = 0.75;
        const double *ps = t.p_spatial + (size_t)(d * 4 + e) * t.nlevels, *pw = t.p_switch + (size_t)(d * 4 + e) * t.nlevels;
        int raw = t.level_raw[d * 4 + e];
        CHECK(ps[raw] < paper && pw[raw] < paper);
        /* and the raw level is the coarsest such */
        for (int k = raw + 1; k < t.nlevels; k++) CHECK(ps[k] >= paper || pw[k] >= paper);
        any_coarse |= l > 0;
        any_fine |= l == 0;
      }
    CHECK(any_coarse && any_fine);   /* the table decides something: level 0 looked at, coarser away */
    /* the lookup matches the table at its grid points, every mode */
    jnd_gaze_lookup lut;
    CHECK_OK(jnd_gaze_lookup_from_table(&t, &lut));
    for (int d = 0; d < 3 && lut.level; d++)
      for (int e = 0; e < 4; e++)
        for (int mode = 0; mode < 3; mode++)
          CHECK(jnd_gaze_lookup_level(&lut, dist[d], ecc[e], (jnd_gaze_lookup_mode)mode) == t.level[d * 4 + e]);
    jnd_gaze_lookup_free(&lut);
  }
  jnd_gaze_table_free(&t);
  /* bad input */
  static const double bad_ecc[] = {0, 95}, inside[] = {0.5}, down[] = {40, 20};
  p.eccentricities_deg = bad_ecc, p.neccentricities = 2;
  CHECK_STATUS(jnd_gaze_table_run(s, &p, &t), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "--eccentricities") != NULL);
  p.eccentricities_deg = ecc, p.neccentricities = 4;
  p.distances_m = inside, p.ndistances = 1;
  CHECK_STATUS(jnd_gaze_table_run(s, &p, &t), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "--distances") != NULL);
  p.distances_m = down, p.ndistances = 2;
  CHECK_STATUS(jnd_gaze_table_run(s, &p, &t), JND_ERR_ARG);
  jnd_scene_free(s);
  /* a chain of one level, when none is to be made */
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 16;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  p.distances_m = dist, p.ndistances = 3;
  p.build_chain = 0;
  if (s) CHECK_STATUS(jnd_gaze_table_run(s, &p, &t), JND_ERR_ARG);
  CHECK(strstr(jnd_last_error(), "one level") != NULL);
  jnd_scene_free(s);
}

/* ---- the lookup ---- */

static void fill_table(jnd_gaze_table *t, double *d, double *e, int *level) {
  memset(t, 0, sizeof *t);
  t->nd = 3, t->ne = 4, t->nlevels = 4;
  t->distances_m = d, t->eccentricities_deg = e, t->level = t->level_raw = level;
}

TEST(lookup_matches_the_table_at_grid_points_and_interpolates_between) {
  double d[3] = {1, 2, 4}, e[4] = {0, 10, 20, 40};
  int level[12] = {0, 0, 1, 2, /**/ 0, 1, 2, 3, /**/ 1, 2, 3, 3};
  jnd_gaze_table t;
  fill_table(&t, d, e, level);
  jnd_gaze_lookup lut;
  CHECK_OK(jnd_gaze_lookup_from_table(&t, &lut));
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 4; j++)
      for (int mode = 0; mode < 3; mode++)
        CHECK(jnd_gaze_lookup_level(&lut, d[i], e[j], (jnd_gaze_lookup_mode)mode) == level[i * 4 + j]);
  /* between grid points */
  CHECK_NEAR(jnd_gaze_lookup_level(&lut, 1.5, 0, JND_GAZE_BILINEAR), 0.0, 1e-9);
  CHECK_NEAR(jnd_gaze_lookup_level(&lut, 1.5, 15, JND_GAZE_BILINEAR), 1.0, 1e-9);
  CHECK_NEAR(jnd_gaze_lookup_level(&lut, 3, 30, JND_GAZE_BILINEAR), (2 + 3 + 3 + 3) / 4.0, 1e-9);
  CHECK(jnd_gaze_lookup_level(&lut, 3.9, 39, JND_GAZE_FLOOR) == 2);     /* the finer corner: safe */
  CHECK(jnd_gaze_lookup_level(&lut, 3.9, 39, JND_GAZE_NEAREST) == 3);
  CHECK(jnd_gaze_lookup_level(&lut, 1.2, 12, JND_GAZE_NEAREST) == 0);
  /* nearest: the corner on the near side of the cell's middle, either way */
  CHECK(jnd_gaze_lookup_level(&lut, 1.4, 10, JND_GAZE_NEAREST) == 0);
  CHECK(jnd_gaze_lookup_level(&lut, 1.6, 10, JND_GAZE_NEAREST) == 1);
  CHECK(jnd_gaze_lookup_level(&lut, 2, 14, JND_GAZE_NEAREST) == 1);
  CHECK(jnd_gaze_lookup_level(&lut, 2, 16, JND_GAZE_NEAREST) == 2);
  /* outside the grid: clamped */
  CHECK(jnd_gaze_lookup_level(&lut, 0.1, -5, JND_GAZE_FLOOR) == 0);
  CHECK(jnd_gaze_lookup_level(&lut, 100, 90, JND_GAZE_FLOOR) == 3);
  /* every mode: the edge's value, never extrapolated past the table */
  for (int mode = 0; mode < 3; mode++) {
    CHECK_NEAR(jnd_gaze_lookup_level(&lut, 100, 90, (jnd_gaze_lookup_mode)mode), 3, 1e-9);
    CHECK_NEAR(jnd_gaze_lookup_level(&lut, 8, 10, (jnd_gaze_lookup_mode)mode), 2, 1e-9);
    CHECK_NEAR(jnd_gaze_lookup_level(&lut, 0.5, -3, (jnd_gaze_lookup_mode)mode), 0, 1e-9);
  }
  jnd_gaze_lookup_free(&lut);
}

TEST(table_csv_reads_back_and_bad_tables_are_refused) {
  double d[3] = {1, 2, 4}, e[4] = {0, 10, 20, 40};
  int level[12] = {0, 0, 1, 2, 0, 1, 2, 3, 1, 2, 3, 3};
  double ps[48], pw[48];
  for (int i = 0; i < 48; i++) ps[i] = pw[i] = 0.6;
  jnd_gaze_table t;
  fill_table(&t, d, e, level);
  t.p_spatial = ps, t.p_switch = pw;
  char path[512];
  snprintf(path, sizeof path, "%s/gaze_table.csv", getenv("JND_TMP") ? getenv("JND_TMP") : "/tmp");
  CHECK_OK(jnd_make_dirs(getenv("JND_TMP") ? getenv("JND_TMP") : "/tmp"));
  CHECK_OK(jnd_gaze_table_write_csv(&t, path));
  jnd_gaze_lookup lut;
  CHECK_OK(jnd_gaze_lookup_load(path, &lut));
  CHECK(lut.nd == 3 && lut.ne == 4);
  for (int i = 0; i < 3 && lut.level; i++)
    for (int j = 0; j < 4; j++) CHECK(jnd_gaze_lookup_level(&lut, d[i], e[j], JND_GAZE_NEAREST) == level[i * 4 + j]);
  jnd_gaze_lookup_free(&lut);
  const char *bad[] = {
      "distance_m,eccentricity_deg\n1,0\n",                          /* no level column */
      "distance_m,eccentricity_deg,level\n1,0,1\n1,10,1\n2,0,1\n",   /* incomplete grid */
      "distance_m,eccentricity_deg,level\n1,0,1\n1,0,2\n",           /* repeated point */
      "distance_m,eccentricity_deg,level\n0,0,1\n",                  /* distance 0 */
      "distance_m,eccentricity_deg,level\n1,91,1\n",                 /* eccentricity > 90 */
      "distance_m,eccentricity_deg,level\n1,0,1.5\n",                /* not a whole level */
      "distance_m,eccentricity_deg,level\n",                         /* no rows */
  };
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    CHECK_STATUS(jnd_gaze_lookup_parse("t.csv", bad[i], strlen(bad[i]), &lut), JND_ERR_FORMAT);
    CHECK(strncmp(jnd_last_error(), "t.csv: ", 7) == 0);
  }
}

/* ---- fitting ---- */

/* synthetic observers: each stimulus answered `reps` times with the true model's P */
static char *synthetic_csv(const jnd_gaze_model *m, int temporal, int stimuli, int reps, uint64_t seed) {
  size_t cap = (size_t)stimuli * reps * 64 + 64, n = 0;
  char *buf = malloc(cap);
  uint64_t z = seed;
  n += (size_t)snprintf(buf + n, cap - n, temporal ? "stimulus,t_jnd,seen\n" : "stimulus,xor_deg,v_jnd,eccentricity_deg,seen\n");
  for (int s = 0; s < stimuli; s++) {
    /* terms spread in log over the range where P goes from chance to certain */
    z = z * 6364136223846793005ULL + 1442695040888963407ULL;
    double u1 = (double)(z >> 11) / 9007199254740992.0;
    z = z * 6364136223846793005ULL + 1442695040888963407ULL;
    double u2 = (double)(z >> 11) / 9007199254740992.0;
    z = z * 6364136223846793005ULL + 1442695040888963407ULL;
    double x = 0.002 * pow(60, u1), v = 0.05 * pow(60, u2), e = 60.0 * (double)(z >> 11) / 9007199254740992.0, p;
    if (temporal) p = jnd_gaze_switch_probability(m, v);
    else {
      if (s % 3 == 0) v = 0;         /* silhouette only */
      if (s % 3 == 1) x = 0;         /* shading only */
      p = jnd_gaze_spatial_probability(m, jnd_gaze_weight(m, e) * x, v);
    }
    for (int r = 0; r < reps; r++) {
      z = z * 6364136223846793005ULL + 1442695040888963407ULL;
      int seen = (double)(z >> 11) / 9007199254740992.0 < p;
      if (temporal) n += (size_t)snprintf(buf + n, cap - n, "%d,%.9g,%d\n", s, v, seen);
      else n += (size_t)snprintf(buf + n, cap - n, "%d,%.9g,%.9g,%.9g,%d\n", s, x, v, e, seen);
    }
  }
  return buf;
}

TEST(fit_recovers_synthetic_observers_within_their_intervals) {
  jnd_gaze_model truth;
  jnd_gaze_model_defaults(&truth);
  truth.alpha = 1.5, truth.beta = 0.15, truth.s_deg = 20, truth.b = 3, truth.w_vdp = 0.8, truth.k_s = 2.5,
  truth.gamma = 3;
  truth.w_t = 0.6, truth.gamma_t = 2.5;
  const double want[6] = {truth.alpha, truth.beta, truth.s_deg, truth.w_vdp, truth.k_s, truth.gamma};
  /* many answers per stimulus: the weight's four parameters are weakly
   * identified (a softplus and a hinge differ little), so the test asks for
   * the intervals the data give at 99.7% (3 SE), each containing the truth */
  char *text = synthetic_csv(&truth, 0, 400, 300, 7);
  jnd_gaze_data d;
  CHECK_OK(jnd_gaze_data_parse("synthetic.csv", text, strlen(text), &d));
  free(text);
  CHECK(d.stimuli == 400 && d.n == 400 * 300 && !d.temporal);
  jnd_gaze_fit_params fp;
  jnd_gaze_fit_defaults(&fp);
  fp.confidence = 0.997;
  fp.start.b = truth.b;   /* not fitted: the weight's floor is the analyst's (docs/gaze.md) */
  jnd_gaze_fit_result r;
  CHECK_OK(jnd_gaze_fit(&d, &fp, &r));
  CHECK(r.nparams == 6);
  int determined = 0;
  for (int i = 0; i < r.nparams; i++) {
    fprintf(stderr, "%-6s true %.4g fit %.4g [%.4g, %.4g]\n", r.names[i], want[i], r.value[i], r.ci_lo[i], r.ci_hi[i]);
    if (isnan(r.ci_lo[i])) continue;   /* a flat direction: judged by the predictions below */
    determined++;
    CHECK(r.ci_lo[i] <= want[i] && want[i] <= r.ci_hi[i]);
    CHECK(r.ci_lo[i] < r.value[i] && r.value[i] < r.ci_hi[i]);
  }
  CHECK(determined == 6);
  /* whatever the parameters, the fitted curve is the true one: P over the
   * range of the terms, and the weight over eccentricity */
  double worst = 0;
  for (double e = 0; e <= 60; e += 5)
    for (double x = 0.002; x < 0.12; x *= 1.5)
      for (double v = 0; v < 3; v += 0.25)
        worst = fmax(worst, fabs(jnd_gaze_spatial_probability(&r.model, jnd_gaze_weight(&r.model, e) * x, v) -
                                 jnd_gaze_spatial_probability(&truth, jnd_gaze_weight(&truth, e) * x, v)));
  fprintf(stderr, "largest difference of P, fitted vs true: %.4f\n", worst);
  CHECK(worst < 0.04);   /* 300 answers per stimulus: proportions known to ±0.03 */
  /* the fitted model predicts what the observers saw */
  fprintf(stderr, "all: r %.3f MAE %.3f; %d folds: r %.3f ± %.3f, MAE %.3f ± %.3f\n", r.r_all, r.mae_all, r.folds,
          r.r_mean, r.r_sd, r.mae_mean, r.mae_sd);
  CHECK(r.r_all > 0.95 && r.mae_all < 0.03);
  CHECK(r.folds == 4 && r.r_mean > 0.95 && r.mae_mean < 0.03);
  jnd_gaze_data_free(&d);

  /* the temporal model */
  text = synthetic_csv(&truth, 1, 200, 100, 11);
  CHECK_OK(jnd_gaze_data_parse("switch.csv", text, strlen(text), &d));
  free(text);
  CHECK(d.temporal);
  CHECK_OK(jnd_gaze_fit(&d, &fp, &r));
  CHECK(r.nparams == 2);
  CHECK(r.ci_lo[0] <= truth.w_t && truth.w_t <= r.ci_hi[0]);
  CHECK(r.ci_lo[1] <= truth.gamma_t && truth.gamma_t <= r.ci_hi[1]);
  CHECK_NEAR(r.model.w_t, truth.w_t, 0.1);
  /* the intervals are two-sided normal ones on the log scale: at 99.7%
   * each side is 2.9677 standard errors, at 68.27% one (a one-sided
   * quantile would give 2.748 and 0.475) */
  jnd_gaze_fit_result r1;
  fp.confidence = 0.682689492137086;   /* erf(1/√2): ±1 SE */
  CHECK_OK(jnd_gaze_fit(&d, &fp, &r1));
  for (int i = 0; i < 2; i++) {
    CHECK_NEAR(r1.value[i], r.value[i], 1e-12);
    CHECK_NEAR(log(r.ci_hi[i] / r.value[i]) / log(r1.ci_hi[i] / r1.value[i]), 2.96774, 0.001);
    CHECK_NEAR(log(r.value[i] / r.ci_lo[i]) / log(r1.value[i] / r1.ci_lo[i]), 2.96774, 0.001);
  }
  jnd_gaze_data_free(&d);
}

TEST(bad_trial_files_are_refused_naming_the_row) {
  const char *bad[] = {
      "xor_deg,v_jnd,seen\n0.1,1,1\n",                              /* no eccentricity */
      "xor_deg,v_jnd,eccentricity_deg,seen\n0.1,1,10,2\n",          /* answer not 0/1 */
      "xor_deg,v_jnd,eccentricity_deg,seen\n0.1,1,10,yes\n",
      "xor_deg,v_jnd,eccentricity_deg,seen\n0.1,1,95,1\n",          /* eccentricity > 90 */
      "xor_deg,v_jnd,eccentricity_deg,seen\n-1,1,10,1\n",           /* negative term */
      "xor_deg,v_jnd,eccentricity_deg\n0.1,1,10\n",                 /* no answers */
      "t_jnd,seen\n",                                               /* no trials */
  };
  jnd_gaze_data d;
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    CHECK_STATUS(jnd_gaze_data_parse("d.csv", bad[i], strlen(bad[i]), &d), JND_ERR_FORMAT);
    CHECK(strncmp(jnd_last_error(), "d.csv: ", 7) == 0);
    CHECK(d.trials == NULL && d.n == 0);
  }
}

RUN_TESTS(weight_falls_with_eccentricity_to_its_floor, no_difference_is_chance_and_unit_magnitude_is_the_midpoint,
          geometric_term_of_a_grown_disc_is_its_weighted_growth_in_degrees,
          switch_is_seen_more_when_larger_and_less_away_from_the_gaze, spatial_p_rises_with_coarseness_and_falls_with_eccentricity,
          table_level_never_gets_finer_with_distance_or_eccentricity,
          lookup_matches_the_table_at_grid_points_and_interpolates_between,
          table_csv_reads_back_and_bad_tables_are_refused, fit_recovers_synthetic_observers_within_their_intervals,
          bad_trial_files_are_refused_naming_the_row)
