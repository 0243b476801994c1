/* The judge: the rendered judgement every task shares. Partial re-renders
 * equal full ones, states are recognised by content, the reference state is
 * invisible by definition, early decisions stop at a failure, views added
 * later are referenced in the reference state, ground planes are framed out.
 * Renders are small (96²) so that the suite stays fast on llvmpipe. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/core.h"
#include "jnd.h"
#include "test.h"


static jnd_scene *parts_scene(int parts, int ground) {
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 64;
  bp.parts = parts;
  bp.ground = ground;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&bp, &s));
  return s;
}

static void small(jnd_judge_params *p, int views, int partial) {
  jnd_judge_defaults(p);
  p->views.sampling.count = views;
  p->views.render.width = p->views.render.height = 96;
  p->views.render.anisotropy = 1;   /* llvmpipe: anisotropic filtering of tiny frames is slow */
  p->partial = partial;
}

static int map_of(const jnd_scene *s, const char *name) {
  int i = jnd_scene_map_find(s, name);
  CHECK(i >= 0);
  return i;
}

TEST(partial_rendering_equals_the_full_rendering) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(3, 0);
  jnd_judge_params pp, pf;
  small(&pp, 4, 1);
  small(&pf, 4, 0);
  jnd_judge *jp = NULL, *jf = NULL;
  CHECK_OK(jnd_judge_create(s, &pp, &jp));
  CHECK_OK(jnd_judge_create(s, &pf, &jf));
  if (!jp || !jf) goto done;
  /* two materials change at once, one of them a normal map */
  CHECK_OK(jnd_scene_map_resize(s, map_of(s, "part1/baseColor"), 8, 8));
  CHECK_OK(jnd_scene_map_resize(s, map_of(s, "part0/normal"), 16, 16));
  double P1[4], P2[4];
  jnd_judgement r1, r2;
  CHECK_OK(jnd_judge_eval(jp, 0, 4, 0, P1, &r1));
  CHECK_OK(jnd_judge_eval(jf, 0, 4, 0, P2, &r2));
  jnd_judge_counts cp, cf;
  jnd_judge_get_counts(jp, &cp);
  jnd_judge_get_counts(jf, &cf);
  CHECK(cp.partial_renderings >= 1 && cp.renderings == 0);
  CHECK(cf.partial_renderings == 0 && cf.renderings == 4);
  int visible = 0;
  for (int v = 0; v < 4; v++) {
    CHECK_NEAR(P1[v], P2[v], 1e-4);
    visible += P2[v] > 0.01;
    jnd_image a = {0}, b = {0};
    int ca[4], cb[4];
    CHECK_OK(jnd_judge_view_images(jp, v, NULL, &a, NULL, NULL, ca));
    CHECK_OK(jnd_judge_view_images(jf, v, NULL, &b, NULL, NULL, cb));
    CHECK(ca[0] == cb[0] && ca[1] == cb[1] && a.w == b.w && a.h == b.h);
    double worst = 0;
    if (a.w == b.w && a.h == b.h)
      for (size_t i = 0; i < (size_t)a.w * a.h * 3; i++) worst = fmax(worst, fabs(a.data[i] - b.data[i]));
    CHECK(worst <= 1.0 / 255);
    jnd_image_free(&a);
    jnd_image_free(&b);
  }
  CHECK(visible >= 1);   /* the candidate is not the reference in disguise */
done:
  jnd_judge_free(jp);
  jnd_judge_free(jf);
  jnd_scene_free(s);
}

/* Judges of two window sizes lending one renderer, asked in turn (each
 * resizes it; partial re-renders read depths kept at their own size), give
 * what judges with renderers of their own give, and do not free it. */
TEST(judges_sharing_a_renderer_judge_as_their_own_renderers_do) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge_params pa, pb;
  small(&pa, 2, 1);
  small(&pb, 2, 1);
  pb.views.render.width = pb.views.render.height = 64;
  jnd_renderer_params rp = pa.views.render;
  rp.width = rp.height = 40;   /* neither judge's size */
  jnd_renderer *shared = NULL;
  CHECK_OK(jnd_renderer_create(&rp, &shared));
  jnd_judge *own[2] = {NULL, NULL}, *lent[2] = {NULL, NULL};
  CHECK_OK(jnd_judge_create(s, &pa, &own[0]));
  CHECK_OK(jnd_judge_create(s, &pb, &own[1]));
  pa.renderer = pb.renderer = shared;
  CHECK_OK(jnd_judge_create(s, &pa, &lent[0]));
  CHECK_OK(jnd_judge_create(s, &pb, &lent[1]));
  if (!shared || !own[0] || !own[1] || !lent[0] || !lent[1]) goto done;
  int i = map_of(s, "part1/baseColor");
  for (int size = 8; size <= 16; size *= 2) {
    CHECK_OK(jnd_scene_map_resize(s, i, size, size));
    for (int k = 0; k < 2; k++) {
      double P[2], Q[2];
      CHECK_OK(jnd_judge_eval(lent[k], 0, 2, 0, P, NULL));
      CHECK_OK(jnd_judge_eval(own[k], 0, 2, 0, Q, NULL));
      for (int v = 0; v < 2; v++) CHECK(P[v] == Q[v] && P[v] > 0);
    }
  }
  jnd_judge_counts c;
  jnd_judge_get_counts(lent[1], &c);
  CHECK(c.partial_renderings >= 2);   /* the partial path ran on the lent renderer */
  jnd_judge_free(lent[0]);
  jnd_judge_free(lent[1]);
  lent[0] = lent[1] = NULL;
  CHECK_OK(jnd_renderer_resize(shared, 32, 32));   /* still the caller's */
done:
  for (int k = 0; k < 2; k++) {
    jnd_judge_free(own[k]);
    jnd_judge_free(lent[k]);
  }
  jnd_renderer_free(shared);
  jnd_scene_free(s);
}

TEST(the_reference_state_is_invisible_and_never_rendered) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge_params p;
  small(&p, 3, 1);
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  double P[3];
  jnd_judgement r;
  /* a map resized to its own size is the reference again */
  int i = map_of(s, "part0/baseColor");
  CHECK_OK(jnd_scene_map_resize(s, i, 64, 64));
  CHECK_OK(jnd_judge_eval(j, 0, 3, 0, P, &r));
  jnd_judge_counts c;
  jnd_judge_get_counts(j, &c);
  CHECK(c.renderings == 0 && c.partial_renderings == 0);
  for (int v = 0; v < 3; v++) CHECK(P[v] == 0);
  CHECK(r.criterion.pass && r.criterion.statistic == 0 && r.judged == 3);
done:
  jnd_judge_free(j);
  jnd_scene_free(s);
}

TEST(a_state_judged_before_is_answered_from_memory) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge_params p;
  small(&p, 3, 1);
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  int i = map_of(s, "part1/baseColor");
  double P[3], Q[3];
  CHECK_OK(jnd_scene_map_resize(s, i, 16, 16));
  CHECK_OK(jnd_judge_eval(j, 0, 3, 0, P, NULL));
  jnd_judge_counts a, b;
  jnd_judge_get_counts(j, &a);
  /* another state, then the first again by a new resize (same content, new version) */
  CHECK_OK(jnd_scene_map_resize(s, i, 32, 32));
  CHECK_OK(jnd_judge_eval(j, 0, 3, 0, Q, NULL));
  CHECK_OK(jnd_scene_map_resize(s, i, 16, 16));
  jnd_judge_get_counts(j, &a);
  CHECK_OK(jnd_judge_eval(j, 0, 3, 0, Q, NULL));
  jnd_judge_get_counts(j, &b);
  CHECK(b.renderings + b.partial_renderings == a.renderings + a.partial_renderings);
  CHECK(b.reused == a.reused + 3 && b.states == 2);
  for (int v = 0; v < 3; v++) CHECK(P[v] == Q[v]);
done:
  jnd_judge_free(j);
  jnd_scene_free(s);
}

TEST(deciding_stops_at_the_first_failing_view) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(1, 0);
  jnd_judge_params p;
  small(&p, 6, 1);
  p.criterion.q = 0;   /* no view may be above */
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  /* one texel of base colour: visible from everywhere */
  CHECK_OK(jnd_scene_map_resize(s, map_of(s, "builtin/baseColor"), 1, 1));
  double P[6];
  jnd_judgement r;
  CHECK_OK(jnd_judge_eval(j, 0, 6, JND_JUDGE_DECIDE, P, &r));
  CHECK(r.judged == 1 && !r.criterion.pass);
  int known = 0;
  for (int v = 0; v < 6; v++) known += !isnan(P[v]);
  CHECK(known == 1);
  /* without the flag every view is judged; the one known is not judged again */
  jnd_judge_counts a, b;
  jnd_judge_get_counts(j, &a);
  CHECK_OK(jnd_judge_eval(j, 0, 6, 0, P, &r));
  jnd_judge_get_counts(j, &b);
  CHECK(r.judged == 6 && b.view_judgements == a.view_judgements + 5 && b.reused == a.reused + 1);
  for (int v = 0; v < 6; v++) CHECK(P[v] > 0.2);
done:
  jnd_judge_free(j);
  jnd_scene_free(s);
}

TEST(views_added_later_are_referenced_in_the_reference_state) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge_params p;
  small(&p, 2, 1);
  jnd_judge *j = NULL, *k = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  int i = map_of(s, "part0/baseColor");
  CHECK_OK(jnd_scene_map_resize(s, i, 8, 8));
  /* held-out views from another seed, added while the candidate is in place */
  jnd_view_set vs = p.views;
  vs.sampling.seed = 99;
  jnd_view *extra = NULL;
  int n = 0, first = -1;
  CHECK_OK(jnd_view_set_make(s, &vs, &extra, &n));
  CHECK_OK(jnd_judge_add_views(j, extra, n, &first));
  CHECK(first == 2 && jnd_judge_view_count(j) == 4);
  jnd_map_info mi;
  jnd_scene_map_info(s, i, &mi);
  CHECK(mi.width == 8);   /* the candidate is back in place */
  double P[2], Q[2];
  CHECK_OK(jnd_judge_eval(j, first, 2, 0, P, NULL));
  /* a judge made on those views from the start agrees */
  jnd_scene_map_restore(s, i);
  jnd_judge_params q = p;
  q.views.sampling.seed = 99;
  CHECK_OK(jnd_judge_create(s, &q, &k));
  CHECK_OK(jnd_scene_map_resize(s, i, 8, 8));
  if (k) CHECK_OK(jnd_judge_eval(k, 0, 2, 0, Q, NULL));
  for (int v = 0; v < 2 && k; v++) CHECK_NEAR(P[v], Q[v], 1e-9);
  CHECK(P[0] > 0 || P[1] > 0);
  free(extra);
done:
  jnd_judge_free(j);
  jnd_judge_free(k);
  jnd_scene_free(s);
}

TEST(views_of_an_asset_on_the_ground_come_from_above_and_frame_the_asset) {
  jnd_scene *plain = parts_scene(1, 0), *grounded = parts_scene(1, 1);
  double c0[3], r0, c1[3], r1, call[3], rall;
  int g0, g1;
  jnd_scene_subject_bounds(plain, c0, &r0, &g0);
  jnd_scene_subject_bounds(grounded, c1, &r1, &g1);
  jnd_scene_bounds(grounded, call, &rall);
  CHECK(g0 == -1 && g1 == 1);
  CHECK_NEAR(r1, r0, 1e-6);   /* the floor does not enlarge what is framed */
  CHECK(rall > 2 * r1);
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = 16;
  jnd_view v0[16], v1[16];
  CHECK_OK(jnd_views_sample(plain, &vs, v0));
  CHECK_OK(jnd_views_sample(grounded, &vs, v1));
  int below = 0;
  for (int i = 0; i < 16; i++) {
    below += v0[i].camera.eye[1] < c0[1];
    double d[3], len = 0;
    for (int k = 0; k < 3; k++) d[k] = v1[i].camera.eye[k] - c1[k], len += d[k] * d[k];
    CHECK(asin(d[1] / sqrt(len)) * 180 / M_PI >= 10 - 1e-9);   /* above the ground's horizon */
  }
  CHECK(below > 0);   /* without a ground, views come from below too */
  jnd_scene_free(plain);
  jnd_scene_free(grounded);
}

/* A level of detail (jnd lod, issue 11) is a scene state like a map size,
 * per mesh or for the whole scene: the judge renders it whole, answers it
 * from memory when it is selected again, references views added while it
 * is in place with the reference's levels, and the reference's levels
 * selected again are the reference (P = 0, nothing rendered). */
TEST(a_level_of_detail_is_a_state_the_judge_renders_and_recognises) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = parts_scene(2, 0);
  jnd_lod_params lp;
  jnd_lod_defaults(&lp);
  const double ratio[1] = {0.1};
  lp.errors = NULL;
  lp.ratios = ratio;
  lp.nratios = 1;
  CHECK_OK(jnd_scene_lod_build(s, &lp));
  CHECK(jnd_scene_lod_count(s) == 2);
  jnd_judge_params p;
  small(&p, 2, 1);
  /* pooled by the maximum: the question is whether a view shows the level's
   * difference at all, not how visible it is (on a 96² frame the 93rd
   * percentile of a small object's difference may be 0) */
  p.calibration.percentile = 100;
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  /* one object at the coarse level */
  CHECK_OK(jnd_scene_lod_select_mesh(s, 0, 1));
  CHECK(jnd_scene_lod_mesh_level(s, 0) == 1 && jnd_scene_lod_mesh_level(s, 1) == 0);
  double P[4];
  jnd_judgement r;
  jnd_judge_counts c0, c1, c2;
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, P, &r));
  jnd_judge_get_counts(j, &c0);
  CHECK(P[0] > 0 && P[1] > 0);
  CHECK(c0.renderings == 2 && c0.partial_renderings == 0);   /* geometry changed: whole frames */
  /* selected again (after a detour through level 0): the same state */
  CHECK_OK(jnd_scene_lod_select_mesh(s, 0, 0));
  CHECK_OK(jnd_scene_lod_select_mesh(s, 0, 1));
  double Q[2];
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, Q, NULL));
  jnd_judge_get_counts(j, &c1);
  CHECK(c1.renderings == c0.renderings && Q[0] == P[0] && Q[1] == P[1]);
  /* views added while the level is in place are referenced at level 0 */
  jnd_view_set vs = p.views;
  vs.sampling.seed = 7;
  jnd_view *extra = NULL;
  int n = 0, first = -1;
  CHECK_OK(jnd_view_set_make(s, &vs, &extra, &n));
  CHECK_OK(jnd_judge_add_views(j, extra, n, &first));
  CHECK(jnd_scene_lod_mesh_level(s, 0) == 1);   /* the level is back in place */
  CHECK_OK(jnd_judge_eval(j, first, 2, 0, P + 2, NULL));
  /* the level's difference on a 96² frame is far below threshold (P of
   * 1e-8 to 1e-4), so one view's P may round to 0 in single precision;
   * referenced at level 1, both would be exactly 0 */
  CHECK(P[2] > 0 || P[3] > 0);
  /* the whole scene back at level 0: the reference, never rendered */
  CHECK_OK(jnd_scene_lod_select(s, 0));
  jnd_judge_get_counts(j, &c1);
  CHECK_OK(jnd_judge_eval(j, 0, 4, 0, P, &r));
  jnd_judge_get_counts(j, &c2);
  for (int v = 0; v < 4; v++) CHECK(P[v] == 0);
  CHECK(c2.renderings == c1.renderings && r.criterion.pass);
  CHECK_STATUS(jnd_scene_lod_select_mesh(s, 0, 2), JND_ERR_ARG);
  CHECK_STATUS(jnd_scene_lod_select_mesh(s, 2, 0), JND_ERR_ARG);
  free(extra);
done:
  jnd_judge_free(j);
  jnd_scene_free(s);
}

TEST(the_periphery_is_judged_less_visible_than_the_fovea) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_judge_params p;
  small(&p, 2, 1);
  p.model.has_gaze = 1;
  p.model.gaze_x = p.model.gaze_y = 47.5;   /* the frame's centre, where the object is */
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  /* the same change (the base colour blurred) seen at the fovea, then with
   * the object about 40° out (2000 px left at the display's ppd) */
  CHECK_OK(jnd_scene_map_resize(s, map_of(s, "part0/baseColor"), 4, 4));
  double fovea[2], periphery[2], again[2];
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, fovea, NULL));
  CHECK_OK(jnd_judge_set_gaze(j, 1, -2000, 47.5));
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, periphery, NULL));
  CHECK_OK(jnd_judge_set_gaze(j, 1, 47.5, 47.5));
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, again, NULL));
  for (int v = 0; v < 2; v++) {
    CHECK(fovea[v] > 0);
    CHECK(periphery[v] < 0.5 * fovea[v]);    /* much less visible out of the gaze */
    CHECK(again[v] == fovea[v]);             /* the fixation point moved back: the same P */
  }
  CHECK(fovea[0] > 0.5 || fovea[1] > 0.5);   /* seen where the viewer looks (one view shows part 0 little) */
  /* view 1 alone looks away; then the judge-wide point again is every view's */
  double one_out[2], all[2];
  CHECK_OK(jnd_judge_set_view_gaze(j, 1, 1, -2000, 47.5));
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, one_out, NULL));
  CHECK(one_out[0] == fovea[0] && one_out[1] < 0.5 * fovea[1]);
  CHECK_OK(jnd_judge_set_gaze(j, 1, 47.5, 47.5));
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, all, NULL));
  for (int v = 0; v < 2; v++) CHECK(all[v] == fovea[v]);
  /* a judge made without a fixation point has none to move */
  jnd_judge *k = NULL;
  small(&p, 1, 1);
  CHECK_OK(jnd_judge_create(s, &p, &k));
  if (k) CHECK_STATUS(jnd_judge_set_gaze(k, 1, 0, 0), JND_ERR_ARG);
  jnd_judge_free(k);
done:
  jnd_judge_free(j);
  jnd_scene_free(s);
}

TEST(each_view_is_judged_at_its_own_gaze_point) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_judge_params p;
  small(&p, 2, 1);   /* no judge-wide fixation point: the views keep their crops */
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  CHECK_OK(jnd_scene_map_resize(s, map_of(s, "part0/baseColor"), 4, 4));
  double none[2], fovea[2], split[2], swapped[2], back[2];
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, none, NULL));
  /* both views looked at: the object at 0° */
  double x0, y0, x1, y1;
  CHECK_OK(jnd_judge_set_view_eccentricity(j, 0, 0, &x0, &y0));
  CHECK_OK(jnd_judge_set_view_eccentricity(j, 1, 0, &x1, &y1));
  CHECK(x0 > 0 && x0 < 96 && y0 > 0 && y0 < 96);   /* the object's centre, inside the 96² frame */
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, fovea, NULL));
  /* view 0's object 40° out, view 1's still looked at: only view 0 changes */
  double gx, gy;
  CHECK_OK(jnd_judge_set_view_eccentricity(j, 0, 40, &gx, &gy));
  CHECK(gx < x0 - 1000 && gy == y0);   /* far to the left of the object, on its row */
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, split, NULL));
  /* and the other way round */
  CHECK_OK(jnd_judge_set_view_gaze(j, 0, 1, x0, y0));
  CHECK_OK(jnd_judge_set_view_eccentricity(j, 1, 40, NULL, NULL));
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, swapped, NULL));
  for (int v = 0; v < 2; v++) CHECK(fovea[v] > 0);
  CHECK(fovea[0] > 0.5 || fovea[1] > 0.5);   /* seen where the viewer looks (one view shows part 0 little) */
  CHECK(split[0] < 0.5 * fovea[0] && split[1] == fovea[1]);
  CHECK(swapped[0] == fovea[0] && swapped[1] < 0.5 * fovea[1]);
  /* the points removed: each view judged as with none */
  CHECK_OK(jnd_judge_set_view_gaze(j, 0, 0, 0, 0));
  CHECK_OK(jnd_judge_set_view_gaze(j, 1, 0, 0, 0));
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, back, NULL));
  for (int v = 0; v < 2; v++) CHECK(back[v] == none[v]);
  CHECK_STATUS(jnd_judge_set_view_gaze(j, 2, 1, 0, 0), JND_ERR_ARG);
  CHECK_STATUS(jnd_judge_set_view_eccentricity(j, 0, 95, NULL, NULL), JND_ERR_ARG);
done:
  jnd_judge_free(j);
  jnd_scene_free(s);
}

/* budget's levels each add texres's confirmation and held-out views with
 * the same seeds: a view equal to one the judge has is its twin, neither
 * rendered nor judged again, and gets a reference of its own once it is
 * given a fixation point of its own (or the view it equals is). */
TEST(a_view_added_again_is_rendered_and_judged_once) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_judge_params p;
  small(&p, 2, 1);
  jnd_scene *s = parts_scene(2, 0);
  jnd_judge *j = NULL;
  jnd_view *again = NULL;
  CHECK_OK(jnd_judge_create(s, &p, &j));
  if (!j) goto done;
  CHECK_OK(jnd_scene_map_resize(s, map_of(s, "part0/baseColor"), 4, 4));
  double P[2], Q[2], R[4];
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, P, NULL));
  CHECK(P[0] > 0 && P[1] > 0);
  jnd_judge_counts a, b, c;
  jnd_judge_get_counts(j, &a);
  int n = 0, first = -1;
  CHECK_OK(jnd_view_set_make(s, &p.views, &again, &n));
  CHECK(n == 2);
  CHECK(again[1].nlights >= 1);
  again[1].lights[0].direction[0] = nextafter(again[1].lights[0].direction[0], 2);   /* one bit off: another view */
  CHECK_OK(jnd_judge_add_views(j, again, n, &first));
  CHECK(first == 2 && jnd_judge_view_count(j) == 4);
  jnd_judge_get_counts(j, &b);
  CHECK(b.references > a.references);   /* the changed view's own */
  free(again);
  again = NULL;
  CHECK_OK(jnd_view_set_make(s, &p.views, &again, &n));
  CHECK_OK(jnd_judge_add_views(j, again, 1, &first));   /* view 0 again: nothing rendered */
  CHECK(first == 4);
  jnd_judge_get_counts(j, &c);
  CHECK(c.references == b.references);
  CHECK_OK(jnd_judge_eval(j, 4, 1, 0, Q, NULL));
  jnd_judge_get_counts(j, &a);
  CHECK(Q[0] == P[0] && a.view_judgements == c.view_judgements && a.reused == c.reused + 1);
  CHECK(jnd_judge_mip_min(j, 0, 4, 1) == jnd_judge_mip_min(j, 0, 0, 1));
  /* a fixation point of its own: the twin is rendered and judged apart */
  CHECK_OK(jnd_judge_set_view_eccentricity(j, 4, 40, NULL, NULL));
  jnd_judge_get_counts(j, &b);
  CHECK(b.references > a.references);
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, R, NULL));
  CHECK_OK(jnd_judge_eval(j, 4, 1, 0, Q, NULL));
  CHECK(R[0] == P[0] && R[1] == P[1] && Q[0] < 0.5 * P[0]);
  /* and the view it was a twin of keeps judging as before */
  CHECK_OK(jnd_judge_set_view_eccentricity(j, 4, 0, NULL, NULL));
  CHECK_OK(jnd_judge_set_view_gaze(j, 4, 0, 0, 0));
  CHECK_OK(jnd_judge_eval(j, 4, 1, 0, Q, NULL));
  CHECK(Q[0] == P[0]);
done:
  free(again);
  jnd_judge_free(j);
  jnd_scene_free(s);
}

/* a 64² frame over black: a grey disc (coverage 1 inside) with a grating on it */
static void disc_frame(jnd_image *c, jnd_image *cov, double contrast) {
  CHECK_OK(jnd_image_alloc(c, 64, 64, 3));
  CHECK_OK(jnd_image_alloc(cov, 64, 64, 1));
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 64; x++) {
      size_t q = (size_t)y * 64 + x;
      int in = (x - 31.5) * (x - 31.5) + (y - 31.5) * (y - 31.5) < 24 * 24;
      cov->data[q] = in;
      for (int ch = 0; ch < 3; ch++)
        c->data[(size_t)ch * 4096 + q] = in ? (float)(0.3 * (1 + contrast * sin(x * 0.8))) : 0;
    }
}

TEST(showing_composes_over_the_background_by_coverage) {
  jnd_display d;
  jnd_display_defaults(&d);
  jnd_image c = {0}, cov = {0}, ones = {0}, a = {0}, b = {0}, grey = {0}, g = {0};
  disc_frame(&c, &cov, 0.2);
  CHECK_OK(jnd_image_alloc(&ones, 64, 64, 1));
  for (size_t q = 0; q < 4096; q++) ones.data[q] = 1;
  /* fully covered: as rendered */
  CHECK_OK(jnd_judge_show(&d, &c, NULL, 0.18, NULL, &a, NULL));
  CHECK_OK(jnd_judge_show(&d, &c, &ones, 0.18, NULL, &b, NULL));
  int differ = 0;
  for (size_t i = 0; i < 3 * 4096; i++) differ += a.data[i] != b.data[i];
  CHECK(differ == 0);
  /* an uncovered pixel, and one marked grey, show the background */
  CHECK_OK(jnd_image_alloc(&grey, 64, 64, 3));
  for (size_t i = 0; i < 3 * 4096; i++) grey.data[i] = 0.18f;
  CHECK_OK(jnd_judge_show(&d, &grey, NULL, 0, NULL, &g, NULL));
  unsigned char mark[4096] = {0};
  mark[32 * 64 + 32] = 1;   /* inside the disc */
  jnd_image_free(&b);
  CHECK_OK(jnd_judge_show(&d, &c, &cov, 0.18, mark, &b, NULL));
  for (int ch = 0; ch < 3; ch++) {
    CHECK(b.data[(size_t)ch * 4096 + 0] == g.data[(size_t)ch * 4096]);
    CHECK(b.data[(size_t)ch * 4096 + 32 * 64 + 32] == g.data[(size_t)ch * 4096]);
    CHECK(b.data[(size_t)ch * 4096 + 32 * 64 + 33] != g.data[(size_t)ch * 4096]);
  }
  jnd_image_free(&c), jnd_image_free(&cov), jnd_image_free(&ones), jnd_image_free(&a), jnd_image_free(&b);
  jnd_image_free(&grey), jnd_image_free(&g);
}

static double map_mean(const jnd_image *m) {
  double s = 0;
  for (size_t q = 0; q < (size_t)m->w * m->h; q++) s += m->data[q];
  return s / ((double)m->w * m->h);
}

TEST(a_pair_judge_makes_one_model_per_ppd_whatever_the_pairs) {
  jnd_model_params mp;
  jnd_model_defaults(&mp);
  mp.threads = 1;
  jnd_pair_judge *pj = NULL, *fresh = NULL;
  CHECK_OK(jnd_pair_judge_create(&mp, &pj));
  if (!pj) return;
  jnd_image a = {0}, ca = {0}, b = {0}, cb = {0};
  disc_frame(&a, &ca, 0.1);
  disc_frame(&b, &cb, 0.3);
  jnd_pair_view v = {.has_gaze = 1, .gaze_x = 31.5, .gaze_y = 31.5, .background = 0.18};
  /* sequential pairs at several fixation points and frequencies share one model */
  double mean[4];
  jnd_image first = {0};
  for (int i = 0; i < 4; i++) {
    jnd_image m = {0};
    v.gaze_x = i < 2 ? 31.5 : -1500;
    v.temporal_hz = i % 2 ? 3 : 0;
    CHECK_OK(jnd_pair_judge_compare(pj, &a, &ca, &b, &cb, &v, &m));
    mean[i] = map_mean(&m);
    if (i == 0) first = m;
    else jnd_image_free(&m);
  }
  CHECK(jnd_pair_judge_models(pj) == 1);
  CHECK(mean[0] > 0.5 && mean[1] > 0);
  CHECK(mean[2] < 0.5 * mean[0]);   /* out of the gaze: less visible, statically */
  CHECK(mean[3] < 0.5 * mean[1]);   /* and as a flicker */
  /* the map does not depend on which model answered: a fresh judge's is the same */
  v.gaze_x = 31.5, v.temporal_hz = 0;
  CHECK_OK(jnd_pair_judge_create(&mp, &fresh));
  jnd_image m2 = {0};
  if (fresh) CHECK_OK(jnd_pair_judge_compare(fresh, &a, &ca, &b, &cb, &v, &m2));
  int differ = !m2.data || !first.data;
  for (size_t q = 0; !differ && q < 4096; q++) differ = m2.data[q] != first.data[q];
  CHECK(!differ);
  /* another pixels per degree: a second model */
  v.ppd = 2 * mp.display.ppd;
  jnd_image m3 = {0};
  CHECK_OK(jnd_pair_judge_compare(pj, &a, &ca, &b, &cb, &v, &m3));
  CHECK(jnd_pair_judge_models(pj) == 2);
  /* pairs in parallel: at most one model per thread and ppd, the same maps */
  int bad = 0;
  v.ppd = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : bad)
  for (int i = 0; i < 8; i++) {
    jnd_image m = {0};
    jnd_pair_view w = v;
    if (jnd_pair_judge_compare(pj, &a, &ca, &b, &cb, &w, &m) != JND_OK) bad++;
    else
      for (size_t q = 0; q < 4096; q++) bad += m.data[q] != first.data[q];
    jnd_image_free(&m);
  }
  CHECK(bad == 0);
  CHECK(jnd_pair_judge_models(pj) <= 1 + jnd_threads(0));
  /* frames of different sizes are refused */
  jnd_image small_img = {0};
  CHECK_OK(jnd_image_alloc(&small_img, 32, 32, 3));
  jnd_image m4 = {0};
  CHECK_STATUS(jnd_pair_judge_compare(pj, &a, &ca, &small_img, NULL, &v, &m4), JND_ERR_ARG);
  jnd_image_free(&small_img);
  jnd_image_free(&first), jnd_image_free(&m2), jnd_image_free(&m3);
  jnd_image_free(&a), jnd_image_free(&ca), jnd_image_free(&b), jnd_image_free(&cb);
  jnd_pair_judge_free(pj);
  jnd_pair_judge_free(fresh);
}

RUN_TESTS(partial_rendering_equals_the_full_rendering, judges_sharing_a_renderer_judge_as_their_own_renderers_do, the_reference_state_is_invisible_and_never_rendered,
          a_state_judged_before_is_answered_from_memory, deciding_stops_at_the_first_failing_view,
          views_added_later_are_referenced_in_the_reference_state,
          views_of_an_asset_on_the_ground_come_from_above_and_frame_the_asset,
          a_level_of_detail_is_a_state_the_judge_renders_and_recognises,
          the_periphery_is_judged_less_visible_than_the_fovea, each_view_is_judged_at_its_own_gaze_point,
          a_view_added_again_is_rendered_and_judged_once,
          showing_composes_over_the_background_by_coverage,
          a_pair_judge_makes_one_model_per_ppd_whatever_the_pairs)
