/* The perceptual choice and the switch distances of a level-of-detail chain
 * (src/tasks/lod_switch.c): the decisions on made-up oracles whose answers
 * are known, then the rendered judgement on a small chain. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "jnd.h"
#include "tasks/tasks.h"
#include "test.h"

#define CHECK_EQ(a, b) CHECK_NEAR((a), (b), 0)

/* ---- the decisions on oracles ---- */

/* level k passes from grid index from[k] on (from[k] < 0: never); calls counted */
typedef struct {
  const int *from;
  int calls;
} table;

static int table_passes(void *user, int k, int g) {
  table *t = user;
  t->calls++;
  return t->from[k] >= 0 && g >= t->from[k];
}

TEST(bisection_finds_the_nearest_passing_distance_of_every_threshold) {
  /* one level besides level 0, its threshold anywhere on a 40-point grid */
  for (int th = 0; th < 40; th++) {
    int from[2] = {0, th}, idx[2], perc;
    table t = {from, 0};
    CHECK_OK(lod_switch_search(2, 40, table_passes, NULL, &t, &perc, idx));
    CHECK_EQ(idx[0], 0);
    CHECK_EQ(idx[1], th);
    CHECK_EQ(perc, th == 0 ? 1 : 0);
    CHECK(t.calls <= 3 + 6);   /* the viewing condition, both ends, log2(40) steps */
  }
}

TEST(switch_distances_grow_with_the_level_by_construction) {
  /* level 3 passes everywhere (say, a copy of level 0), level 2 from 20 on,
   * level 1 from 7: the coarser level is never shown nearer than the finer */
  int from[5] = {0, 7, 20, 0, 30}, idx[5], perc;
  table t = {from, 0};
  CHECK_OK(lod_switch_search(5, 40, table_passes, NULL, &t, &perc, idx));
  CHECK_EQ(idx[1], 7);
  CHECK_EQ(idx[2], 20);
  CHECK_EQ(idx[3], 20);
  CHECK_EQ(idx[4], 30);
  CHECK_EQ(perc, 3);   /* the coarsest level passing at the viewing condition */
  for (int k = 1; k < 5; k++) CHECK(idx[k] >= idx[k - 1]);
}

TEST(the_perceptual_level_is_the_coarsest_passing_at_the_viewing_condition) {
  /* levels 1 and 2 pass at the viewing condition (grid index 0), level 3
   * only from 5 on: the choice is 2, not the first passing level 1 */
  int from[4] = {0, 0, 0, 5}, idx[4], perc;
  table t = {from, 0};
  CHECK_OK(lod_switch_search(4, 40, table_passes, NULL, &t, &perc, idx));
  CHECK_EQ(perc, 2);
  CHECK_EQ(idx[1], 0);
  CHECK_EQ(idx[2], 0);
  CHECK_EQ(idx[3], 5);
}

TEST(a_level_failing_at_the_far_end_is_never_shown_nor_any_coarser) {
  int from[4] = {0, 3, -1, 10}, idx[4], perc;
  table t = {from, 0};
  CHECK_OK(lod_switch_search(4, 16, table_passes, NULL, &t, &perc, idx));
  CHECK_EQ(idx[1], 3);
  CHECK_EQ(idx[2], -1);
  CHECK_EQ(idx[3], -1);
  CHECK_EQ(perc, 0);
}

/* the table with judges: a grid distance is ready (its references made)
 * once it has been asked about */
typedef struct {
  table t;
  unsigned char asked[64];
  int distances;   /* distinct grid distances asked about: judges made */
} judged_table;

static int judged_passes(void *user, int k, int g) {
  judged_table *j = user;
  if (!j->asked[g]) j->asked[g] = 1, j->distances++;
  return table_passes(&j->t, k, g);
}

static int judged_ready(void *user, int g) {
  return ((judged_table *)user)->asked[g];
}

TEST(asking_ready_distances_first_keeps_the_answers_and_makes_fewer_judges) {
  /* 2000 chains of 8 levels on lod's default 35-point grid: a first switch
   * anywhere, each next 0 to 5 steps farther (as on the teapot's screens),
   * and past the far end never. With and without preferring the distances
   * already judged, the same answers; with, fewer judges over all */
  jnd_rng rng;
  jnd_rng_seed(&rng, 7);
  int without = 0, with = 0;
  for (int trial = 0; trial < 2000; trial++) {
    int from[8] = {0};
    from[1] = (int)(jnd_rng_next(&rng) % 34);
    for (int k = 2; k < 8; k++) {
      from[k] = from[k - 1] < 0 ? -1 : from[k - 1] + (int)(jnd_rng_next(&rng) % 6);
      if (from[k] > 34) from[k] = -1;
    }
    int idx0[8], idx1[8], p0, p1;
    judged_table a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    a.t.from = b.t.from = from;
    CHECK_OK(lod_switch_search(8, 35, judged_passes, NULL, &a, &p0, idx0));
    CHECK_OK(lod_switch_search(8, 35, judged_passes, judged_ready, &b, &p1, idx1));
    CHECK_EQ(p0, p1);
    for (int k = 0; k < 8; k++) {
      CHECK_EQ(idx0[k], from[k]);
      CHECK_EQ(idx1[k], from[k]);
    }
    without += a.distances;
    with += b.distances;
  }
  printf("judges made: %d bisecting, %d preferring ready distances\n", without, with);
  CHECK(with < 0.95 * without);
}

static int failing_oracle(void *user, int k, int g) {
  (void)user, (void)k, (void)g;
  return -1;
}

TEST(an_oracle_error_is_an_error) {
  int idx[3], perc;
  CHECK_STATUS(lod_switch_search(3, 8, failing_oracle, NULL, NULL, &perc, idx), JND_ERR_INTERNAL);
}

TEST(a_switch_distance_is_the_farthest_of_its_components_and_the_finer_level) {
  /* level 1: the criterion decides; 2: popping does; 3: the finer level's
   * distance (both components nearer); 4: a tie goes to the criterion; 5:
   * popping not searched (NaN) leaves the criterion; 6: popping ties with
   * the finer level (its search started there and found no popping): the
   * finer level decides; 7: pops everywhere */
  const double crit[8] = {0, 2, 3, 4, 9, 10, 9.5, 11};
  const double pop[8] = {NAN, 1, 8, 5, 9, NAN, 10, INFINITY};
  double d[8];
  jnd_lod_switch_by by[8];
  lod_switch_combine(8, crit, pop, d, by);
  const double want[8] = {0, 2, 8, 8, 9, 10, 10, INFINITY};
  const jnd_lod_switch_by wby[8] = {JND_LOD_SWITCH_REFERENCE, JND_LOD_SWITCH_CRITERION, JND_LOD_SWITCH_POP,
                                    JND_LOD_SWITCH_FINER,     JND_LOD_SWITCH_CRITERION, JND_LOD_SWITCH_CRITERION,
                                    JND_LOD_SWITCH_FINER,     JND_LOD_SWITCH_POP};
  for (int k = 0; k < 8; k++) {
    CHECK(d[k] == want[k]);
    CHECK_EQ(by[k], wby[k]);
  }
  CHECK(strcmp(jnd_lod_switch_by_name(JND_LOD_SWITCH_POP), "popping") == 0);
}

TEST(coverage_and_distance_are_inverses) {
  for (double c = 0.01; c < 1; c *= 1.7) {
    double d = jnd_camera_distance_for_coverage(2.0, c, 45);
    CHECK_NEAR(jnd_coverage_at_distance(2.0, d, 45), c, 1e-9);
  }
  CHECK(jnd_coverage_at_distance(1, INFINITY, 45) == 0);
}

/* ---- the rendered judgement ---- */

/* the builtin sphere (small maps), its chain, and a copy of level 0 added as
 * the last level (copy NULL: none) */
static jnd_scene *sphere_chain(const double *errors, int nerrors, int *copy) {
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 32;
  bp.shape = 1;
  jnd_scene *s = NULL, *c = NULL;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  if (copy) CHECK_OK(jnd_scene_builtin(&bp, &c));
  if (!s || (copy && !c)) return NULL;
  jnd_lod_params lp;
  jnd_lod_defaults(&lp);
  lp.errors = errors;
  lp.nerrors = nerrors;
  CHECK_OK(jnd_scene_lod_build(s, &lp));
  if (!copy) return s;
  CHECK_OK(jnd_scene_lod_add(s, c, "copy"));
  *copy = jnd_scene_lod_count(s) - 1;
  CHECK(*copy >= 2);
  return s;
}

static jnd_scene *sphere_with_copy(int *copy) {
  static const double errors[2] = {1.0 / 64, 1.0 / 16};
  return sphere_chain(errors, 2, copy);
}

/* jnd_lod_switch_analyse; 0 (the scene freed) when it failed or there is no
 * renderer (the test skipped) */
static int analysed(jnd_scene *s, const jnd_poi_screen *scr, const jnd_lod_switch_params *p, jnd_lod_switch_result *r) {
  jnd_status st = jnd_lod_switch_analyse(s, scr, p, r);
  if (st == JND_ERR_GL) TEST_SKIP("no OpenGL renderer: %s", jnd_last_error());
  else CHECK_OK(st);
  if (st) jnd_scene_free(s);
  return st == JND_OK;
}

static void small_params(jnd_lod_switch_params *p) {
  jnd_lod_switch_defaults(p);
  p->judge.views.sampling.count = 2;
  p->max_px = 128;
  p->tolerance = 0.5;
  p->far_coverage = 0.05;
  p->pop = 0;
}

TEST(a_level_identical_to_level_0_has_p_0_and_inherits_the_finer_distance) {
  int copy = 0;
  jnd_scene *s = sphere_with_copy(&copy);
  if (!s) return;
  jnd_poi_screen scr;
  CHECK_OK(jnd_poi_screen_parse("standard-fhd", &scr));
  jnd_lod_switch_params p;
  small_params(&p);
  p.coverage = 0.12;   /* 130 px on 1080: the window holds it whole */
  jnd_lod_switch_result r;
  if (!analysed(s, &scr, &p, &r)) return;
  CHECK_EQ(r.nlevels, copy + 1);
  CHECK_EQ(jnd_scene_lod_selected(s), 0);
  /* the copy passes at the viewing condition with every view at P = 0 */
  CHECK_EQ(r.perceptual_level, copy);
  CHECK(r.p_max[copy] == 0);
  CHECK(r.statistic[copy] == 0);
  /* the coarse levels are seen at the viewing condition */
  CHECK(r.p_max[1] > 0);
  CHECK(r.p_max[1] > r.p_max[copy]);
  /* switch distances: 0 for level 0, growing with the level; the copy is
   * shown from where the level before it is, never nearer */
  CHECK(r.switch_distance[0] == 0);
  for (int k = 1; k < r.nlevels; k++) CHECK(r.switch_distance[k] >= r.switch_distance[k - 1]);
  CHECK(r.switch_distance_criterion[copy] == r.switch_distance_criterion[copy - 1]);
  CHECK(isnan(r.switch_distance_pop[0]));   /* popping off in small_params */
  CHECK(r.switch_distance[1] > r.view_distance);   /* the coarse levels are seen where the copy is not */
  for (int k = 1; k < r.nlevels; k++)
    if (isfinite(r.switch_distance[k])) CHECK(r.switch_coverage[k] <= r.view_coverage + 1e-12);
  jnd_lod_switch_result_free(&r);
  jnd_scene_free(s);
}

TEST(a_far_distance_is_judged_at_the_screens_own_scale) {
  /* a 4K screen: at the viewing condition (coverage 0.3, 648 px) the object
   * does not fit the 128-pixel window and is judged on the screen scaled
   * down; farther away, wherever it fits (below 96 px: coverage 0.044),
   * at the screen's own pixels per degree. The chain goes coarse enough
   * (3% of the extent) for a level to switch only there. */
  static const double errors[5] = {0.0005, 0.001, 0.002, 0.008, 0.03};
  int copy = 0;
  jnd_scene *s = sphere_chain(errors, 5, &copy);
  if (!s) return;
  double centre[3], radius;
  int ground;
  jnd_scene_subject_bounds(s, centre, &radius, &ground);
  jnd_poi_screen scr;
  CHECK_OK(jnd_poi_screen_parse("standard-4k", &scr));
  jnd_lod_switch_params p;
  small_params(&p);
  p.coverage = 0.3;
  p.far_coverage = 0.01;
  jnd_lod_switch_result r;
  if (!analysed(s, &scr, &p, &r)) return;
  CHECK_NEAR(r.scale, 96 / (0.3 * 2160), 0.01);
  CHECK_EQ(r.window_px, 128);
  int full = 0, judged = 0;
  for (int k = 1; k < r.nlevels; k++) {
    double d = r.switch_distance_criterion[k];
    if (!isfinite(d)) continue;
    judged++;
    double px = jnd_coverage_at_distance(radius, d, 45) * 2160;
    if (px + 32 <= 128) {
      CHECK(r.switch_scale[k] == 1);
      full++;
    } else {
      CHECK_NEAR(r.switch_scale[k], 96 / px, 1e-6);
    }
  }
  CHECK(judged >= 1);
  CHECK(full >= 1);   /* a level switches where the object fits: judged at full scale */
  jnd_lod_switch_result_free(&r);
  jnd_scene_free(s);
}

/* the largest popping rating R over the views of r's screen when level k
 * replaces level k − 1 at distance d, measured anew: the views sampled as
 * jnd_lod_switch_analyse samples them (the window's field of view, the
 * screen's pixels per degree times r.scale), each switch rendered and
 * predicted by pop (static) */
static double max_rating_at(jnd_scene *s, const jnd_lod_switch_params *p, const jnd_lod_switch_result *r, int k,
                            double start, double d) {
  jnd_judge_params jp = p->judge;
  jnd_view_sampling vs = jp.views.sampling;
  double fov = vs.fov_y_deg > 0 ? vs.fov_y_deg : 45;
  /* the window and scale of the search's start (docs/lod.md): the object's
   * diameter there plus the 16-pixel margins, the screen scaled down where
   * that exceeds max_px */
  double centre[3], radius;
  int ground;
  jnd_scene_subject_bounds(s, centre, &radius, &ground);
  double object_px = fmin(jnd_coverage_at_distance(radius, start, fov), 1.0) * r->screen.height_px;
  int side = (int)ceil(object_px) + 32;
  double scale = 1;
  if (side > p->max_px) {
    side = p->max_px;
    scale = (p->max_px - 32) / object_px;
  }
  vs.fov_y_deg = 2 * atan(side / (scale * r->screen.height_px) * tan(fov * M_PI / 360)) * 180 / M_PI;
  vs.aspect = 1;
  vs.distance = d;
  jnd_display_defaults(&jp.model.display);
  jp.model.display.ppd = r->screen.ppd * scale;
  jp.model.display.task = JND_TASK_FLICKER;   /* a switch in place (docs/model.md "Viewing task") */
  jp.views.render.width = jp.views.render.height = side;
  jnd_view views[8];
  jnd_model *m = NULL;
  jnd_renderer *R = NULL;
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  pp.picture = 0;
  double worst = -INFINITY;
  CHECK(vs.count <= 8);
  CHECK_OK(jnd_views_sample(s, &vs, views));
  CHECK_OK(jnd_model_create(&jp.model, &m));
  CHECK_OK(jnd_renderer_create(&jp.views.render, &R));
  for (int v = 0; v < vs.count && m && R; v++) {
    jnd_pop_result pr;
    CHECK_OK(jnd_pop_render(m, R, s, &views[v], &mo, k - 1, 0, &pp, &pr));
    if (pr.nregions && pr.max_rating > worst) worst = pr.max_rating;
    jnd_pop_result_free(&pr);
  }
  jnd_renderer_free(R);
  jnd_model_free(m);
  return worst;
}

TEST(popping_decides_a_switch_and_the_switch_does_not_pop_there) {
  /* the sphere's chain on a small 20 ppd screen with a lenient criterion
   * (p 0.8): level 3 passes it against level 0 at the viewing condition,
   * but the switch from level 2 pops there (largest R >= 1) — 000's
   * criterion pools P over the object, 004's rating adds up a small region
   * of large differences — so popping decides its distance */
  static const double errors[4] = {0.0005, 0.001, 0.002, 0.004};
  int copy = 0;
  jnd_scene *s = sphere_chain(errors, 4, &copy);
  if (!s) return;
  jnd_poi_screen scr;
  CHECK_OK(jnd_poi_screen_parse("320x240@20", &scr));
  jnd_lod_switch_params p;
  small_params(&p);
  p.judge.views.sampling.count = 1;
  p.max_px = 96;
  p.pop = 1;
  p.judge.criterion.p = 0.8;   /* lenient: the criterion lets coarse levels in near, where their switches pop */
  jnd_lod_switch_result r;
  if (!analysed(s, &scr, &p, &r)) return;
  int decided = 0;
  for (int k = 1; k < r.nlevels; k++) {
    CHECK(r.switch_distance[k] >= r.switch_distance[k - 1]);
    CHECK(r.switch_distance[k] >= r.switch_distance_criterion[k]);
    if (!isnan(r.switch_distance_pop[k])) CHECK(r.switch_distance[k] >= r.switch_distance_pop[k]);
    if (r.switch_by[k] != JND_LOD_SWITCH_POP || !isfinite(r.switch_distance[k])) continue;
    decided++;
    CHECK(r.switch_distance[k] == r.switch_distance_pop[k]);
    CHECK(r.switch_distance_pop[k] > r.switch_distance_criterion[k]);
    CHECK(r.pop_max_rating[k] < 1);
    /* measured again at the distance written: below 1; and where the
     * criterion and the finer level would have let it be shown, where the
     * search started: at least 1 (both in the start's window and scale) */
    double from = fmax(r.switch_distance_criterion[k], r.switch_distance[k - 1]);
    CHECK(r.switch_distance[k] > from);
    double again = max_rating_at(s, &p, &r, k, from, r.switch_distance[k]);
    CHECK_LT(again, 1);
    /* the rating the search reported (−inf: no popping region), in the same window */
    CHECK(again == r.pop_max_rating[k] || fabs(again - r.pop_max_rating[k]) <= 1e-6);
    CHECK(max_rating_at(s, &p, &r, k, from, from) >= 1);
  }
  CHECK(decided >= 1);
  CHECK(r.pop_evaluations > 0);
  jnd_lod_switch_result_free(&r);
  jnd_scene_free(s);
}

/* The perceptual level at camera distance d alone (a grid of one distance):
 * the coarsest level that passes there; -1 when it failed */
static int level_at(jnd_scene *s, const jnd_poi_screen *scr, const jnd_lod_switch_params *p0, double d, double radius) {
  jnd_lod_switch_params p = *p0;
  p.distance = d;
  p.far_coverage = jnd_coverage_at_distance(radius, d, 45);
  jnd_lod_switch_result r;
  if (jnd_lod_switch_analyse(s, scr, &p, &r) != JND_OK) return -1;
  int k = r.perceptual_level;
  jnd_lod_switch_result_free(&r);
  return k;
}

/* docs/lod.md "The same image at every pixel count": the shared Stanford
 * bunny (69 K triangles, its default chain) on two screens of the same size
 * in degrees (28.6° tall), one with twice the pixels a side. The one with
 * more pixels shows every difference the other shows, at least as well: no
 * level switches nearer on it, and at each distance judged alone its
 * perceptual level is never coarser; on each screen a farther viewer never
 * rejects a level a nearer one accepts (the level chosen grows with the
 * distance). Judged with one renderer (lent). Shading once per pixel
 * (jnd_renderer_params.pixel_shading, the old rendering) ties the two
 * screens here; e2e.lod_shared_slow's 101 K-triangle teapot is where it
 * inverted them (docs/lod.md). */
TEST(more_pixels_never_accept_a_coarser_level_and_farther_never_rejects) {
  const char *data = test_shared_data();
  if (!data) {
    TEST_SKIP("no shared data");
    return;
  }
  char path[1200];
  snprintf(path, sizeof path, "%s/meshes/stanford-bunny.obj", data);
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(path, &s));
  if (!s) return;
  jnd_lod_params lp;
  jnd_lod_defaults(&lp);
  CHECK_OK(jnd_scene_lod_build(s, &lp));
  double centre[3], radius;
  int ground;
  jnd_scene_subject_bounds(s, centre, &radius, &ground);
  jnd_poi_screen scr[2];
  CHECK_OK(jnd_poi_screen_parse("1920x1080@37.8", &scr[0]));
  CHECK_OK(jnd_poi_screen_parse("3840x2160@75.6", &scr[1]));
  jnd_lod_switch_params p;
  small_params(&p);
  p.max_px = 512;
  p.coverage = 0.2;
  p.far_coverage = 0.05;
  p.tolerance = 1;   /* coverages 0.2, 0.1, 0.05 */
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = rp.height = 64;
  jnd_renderer *ren = NULL;
  jnd_status st = jnd_renderer_create(&rp, &ren);
  if (st == JND_ERR_GL) {
    jnd_scene_free(s);
    TEST_SKIP("no OpenGL renderer: %s", jnd_last_error());
    return;
  }
  CHECK_OK(st);
  p.judge.renderer = ren;
  jnd_lod_switch_result r[2];
  for (int i = 0; i < 2; i++) CHECK_OK(jnd_lod_switch_analyse(s, &scr[i], &p, &r[i]));
  for (int k = 0; k < r[0].nlevels; k++) {
    fprintf(stderr, "level %d switches at %.3g (%s), %.3g (%s)\n", k, r[0].switch_distance_criterion[k], scr[0].name,
            r[1].switch_distance_criterion[k], scr[1].name);
    CHECK(r[1].switch_distance_criterion[k] >= r[0].switch_distance_criterion[k]);
  }
  CHECK(r[1].perceptual_level <= r[0].perceptual_level);
  /* the distances of the search's grid, each judged alone */
  int last[2] = {0, 0}, shown = 0;
  const double d0 = r[0].view_distance, dfar = jnd_camera_distance_for_coverage(radius, p.far_coverage, 45);
  const int ngrid = (int)ceil(log(dfar / d0) / log1p(p.tolerance)) + 1;
  CHECK_EQ(ngrid, 3);
  for (int g = 0; g < ngrid; g++) {
    const double d = g == ngrid - 1 ? dfar : d0 * pow(1 + p.tolerance, g);
    int lv[2];
    for (int i = 0; i < 2; i++) {
      lv[i] = level_at(s, &scr[i], &p, d, radius);
      CHECK(lv[i] >= last[i]);   /* farther: never a finer level */
      last[i] = lv[i];
    }
    fprintf(stderr, "distance %.3g: level %d (%s), %d (%s)\n", d, lv[0], scr[0].name, lv[1], scr[1].name);
    CHECK(lv[1] >= 0 && lv[1] <= lv[0]);   /* more pixels: never a coarser level */
    shown += lv[1] > 0;
  }
  CHECK(shown >= 2);   /* levels above 0 are chosen: the test can fail */
  for (int i = 0; i < 2; i++) jnd_lod_switch_result_free(&r[i]);
  jnd_renderer_free(ren);
  jnd_scene_free(s);
}

TEST(bad_switch_parameters_are_refused) {
  int copy = 0;
  jnd_scene *s = sphere_with_copy(&copy);
  if (!s) return;
  jnd_poi_screen scr;
  CHECK_OK(jnd_poi_screen_parse("phone", &scr));
  jnd_lod_switch_params p;
  jnd_lod_switch_result r;
  small_params(&p);
  p.tolerance = 0;
  CHECK_STATUS(jnd_lod_switch_analyse(s, &scr, &p, &r), JND_ERR_ARG);
  small_params(&p);
  p.far_coverage = 2;
  CHECK_STATUS(jnd_lod_switch_analyse(s, &scr, &p, &r), JND_ERR_ARG);
  small_params(&p);
  p.judge.views.sampling.count = 0;
  CHECK_STATUS(jnd_lod_switch_analyse(s, &scr, &p, &r), JND_ERR_ARG);
  p.judge.views.sampling.count = JND_VIEWS_MAX + 1;   /* the CLI's --judge-views limit too */
  CHECK_STATUS(jnd_lod_switch_analyse(s, &scr, &p, &r), JND_ERR_ARG);
  small_params(&p);
  p.pop = 1;
  p.pop_motion = JND_POP_TRANSLATE;   /* metres per second: not a switch table's speed */
  CHECK_STATUS(jnd_lod_switch_analyse(s, &scr, &p, &r), JND_ERR_ARG);
  small_params(&p);
  p.pop = 1;
  p.pop_speed = NAN;
  CHECK_STATUS(jnd_lod_switch_analyse(s, &scr, &p, &r), JND_ERR_ARG);
  jnd_scene_free(s);
}

RUN_TESTS(bisection_finds_the_nearest_passing_distance_of_every_threshold,
          the_perceptual_level_is_the_coarsest_passing_at_the_viewing_condition,
          switch_distances_grow_with_the_level_by_construction,
          a_level_failing_at_the_far_end_is_never_shown_nor_any_coarser,
          asking_ready_distances_first_keeps_the_answers_and_makes_fewer_judges, an_oracle_error_is_an_error,
          a_switch_distance_is_the_farthest_of_its_components_and_the_finer_level,
          coverage_and_distance_are_inverses, a_level_identical_to_level_0_has_p_0_and_inherits_the_finer_distance,
          a_far_distance_is_judged_at_the_screens_own_scale,
          popping_decides_a_switch_and_the_switch_does_not_pop_there,
          more_pixels_never_accept_a_coarser_level_and_farther_never_rejects, bad_switch_parameters_are_refused)
