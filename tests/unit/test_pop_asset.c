/* Popping of rendered switches (issue 12 items 5–6): the motions move the
 * camera or the object as stated, a switch between two identical levels
 * gives no region, the reprojected depth leaves a rigid moving object
 * visible in the previous frame, and the switch distance's bracket holds
 * what the bisection promises (max R < 1 at the distance, >= 1 just nearer). */
#include <math.h>

#include "jnd.h"
#include "tasks/tasks.h"
#include "test.h"

#define SIZE 64

static jnd_model *model(void) {
  jnd_model_params p;
  jnd_model_defaults(&p);
  jnd_model *m = NULL;
  CHECK_OK(jnd_model_create(&p, &m));
  return m;
}

static jnd_scene *builtin(void) {
  jnd_builtin_params p;
  jnd_builtin_defaults(&p);
  p.map_size = 64;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&p, &s));
  return s;
}

static jnd_renderer *renderer(void) {
  static jnd_renderer *r;
  if (!r) {
    jnd_renderer_params p;
    jnd_renderer_defaults(&p);
    p.width = p.height = SIZE;
    if (jnd_renderer_create(&p, &r) == JND_ERR_GL) TEST_SKIP_REST("no OpenGL renderer: %s", jnd_last_error());
    CHECK(r != NULL);
  }
  return r;
}

static jnd_view view(const jnd_scene *s, double coverage) {
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = 1;
  vs.coverage = coverage;
  jnd_view v;
  CHECK_OK(jnd_views_sample(s, &vs, &v));
  return v;
}

static double dist(const double a[3], const double b[3]) {
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(an_orbit_turns_the_eye_about_the_target_at_its_speed) {
  jnd_view v, w;
  jnd_view_defaults(&v); /* eye (0, 0, 3), target the origin */
  jnd_pop_motion m;
  jnd_pop_motion_defaults(&m);
  m.speed = 90;
  jnd_pop_motion_pose(&v, &m, 0.5, &w); /* 45° counter-clockwise seen from above */
  CHECK_NEAR(dist(w.camera.eye, w.camera.target), 3, 1e-12);
  CHECK_NEAR(w.camera.eye[0], 3 * sin(M_PI / 4), 1e-12);
  CHECK_NEAR(w.camera.eye[2], 3 * cos(M_PI / 4), 1e-12);
  CHECK_NEAR(w.camera.eye[1], 0, 1e-12);
  CHECK(w.camera.target[0] == 0 && w.camera.target[2] == 0);
  m.speed = 0;
  jnd_pop_motion_pose(&v, &m, 0.5, &w);
  CHECK(w.camera.eye[0] == v.camera.eye[0] && w.camera.eye[2] == v.camera.eye[2]);
}

TEST(a_translation_moves_eye_and_target_along_the_cameras_axes_in_metres) {
  jnd_view v, w;
  jnd_view_defaults(&v); /* looking down −Z: right is +X */
  jnd_pop_motion m;
  jnd_pop_motion_defaults(&m);
  m.kind = JND_POP_TRANSLATE;
  m.speed = 2;     /* m/s */
  m.unit_m = 0.5;  /* an object unit is half a metre: 4 units a second */
  jnd_pop_motion_pose(&v, &m, 0.25, &w);
  CHECK_NEAR(w.camera.eye[0], 1, 1e-12);
  CHECK_NEAR(w.camera.target[0], 1, 1e-12);
  CHECK_NEAR(w.camera.eye[2], 3, 1e-12);
  m.direction[0] = 0;
  m.direction[2] = -1; /* forwards */
  jnd_pop_motion_pose(&v, &m, 0.25, &w);
  CHECK_NEAR(w.camera.eye[2], 2, 1e-12);
  CHECK_NEAR(w.camera.eye[0], 0, 1e-12);
}

TEST(a_spin_rotates_the_object_about_the_target_not_the_camera) {
  jnd_view v, w;
  jnd_view_defaults(&v);
  v.camera.target[0] = 1; /* spin about the vertical through (1, 0, 0) */
  jnd_pop_motion m;
  jnd_pop_motion_defaults(&m);
  m.kind = JND_POP_OBJECT;
  m.speed = 180;
  jnd_pop_motion_pose(&v, &m, 0.5, &w); /* 90°: the origin goes to (1, 0, 1) */
  CHECK(w.camera.eye[0] == v.camera.eye[0] && w.camera.eye[2] == v.camera.eye[2]);
  CHECK_NEAR(w.model[12], 1, 1e-12);
  CHECK_NEAR(w.model[14], 1, 1e-12);
  CHECK_NEAR(w.model[0], 0, 1e-12); /* +X goes to −Z */
  CHECK_NEAR(w.model[2], -1, 1e-12);
}

TEST(identical_levels_do_not_pop_at_rest_or_in_motion) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = builtin();
  CHECK_OK(jnd_scene_lod_add(s, builtin(), "the same"));
  jnd_model *m = model();
  jnd_view v = view(s, 0.8);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  double speeds[2] = {0, 120};
  for (int k = 0; k < 2; k++) {
    mo.speed = speeds[k];
    jnd_pop_result r;
    CHECK_OK(jnd_pop_render(m, renderer(), s, &v, &mo, 0, 3, &pp, &r));
    CHECK(r.nregions == 0);
    CHECK(r.max_delta_e94 == 0);
    CHECK(r.w == SIZE && r.h == SIZE);
    CHECK(r.object_pixels > 100 && r.object_pixels < SIZE * SIZE); /* the mask is the object */
    CHECK(r.disocclusion.present == (k == 1));
    /* a rigid object orbited: every point was seen one frame earlier (the
     * reprojected depth); with this frame's own depth, depth changes of
     * 2° a frame would make pixels look occluded */
    if (k == 1) CHECK(r.disocclusion.below_half < r.object_pixels / 50);
    /* the flicker weight (004 §4) needs a previous frame: in motion only */
    CHECK(r.flicker.present == (k == 1));
    jnd_pop_result_free(&r);
  }
  CHECK(jnd_scene_lod_selected(s) == 0);
  jnd_pop_result r;
  CHECK_STATUS(jnd_pop_render(m, renderer(), s, &v, &mo, 1, 0, &pp, &r), JND_ERR_ARG);
  jnd_model_free(m);
  jnd_scene_free(s);
}

/* 004 §4's flicker input: this frame's pixels shaded with the previous
 * frame's setup agree with the previous frame at each pixel's previous
 * position (bilinear), clearly better than this frame's own shading does, when
 * the object turns fast (20° a frame) under fixed lights: what is left is
 * resampling, not lighting. Without a previous pose the setting changes
 * nothing. */
TEST(shading_with_the_previous_setup_matches_the_previous_frame) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = builtin();
  jnd_view v = view(s, 0.8), cur, prev;
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  mo.kind = JND_POP_OBJECT;
  mo.speed = 20 * 60.0; /* 20° a frame at 60 fps */
  jnd_pop_motion_pose(&v, &mo, 1 / 60.0, &cur);
  jnd_pop_motion_pose(&v, &mo, 0, &prev);
  cur.has_prev = 1;
  cur.prev_camera = prev.camera;
  memcpy(cur.prev_model, prev.model, sizeof cur.prev_model);
  cur.outputs = JND_OUT_COLOR | JND_OUT_MOTION | JND_OUT_MASK;
  prev.outputs = JND_OUT_COLOR | JND_OUT_MASK;
  jnd_view shade = cur;
  shade.shade_prev = 1;
  shade.outputs = JND_OUT_COLOR;
  jnd_frame fc, fp, fs;
  CHECK_OK(jnd_render(renderer(), s, &cur, &fc));
  CHECK_OK(jnd_render(renderer(), s, &prev, &fp));
  CHECK_OK(jnd_render(renderer(), s, &shade, &fs));
  const int w = SIZE, h = SIZE;
  double e_shade = 0, e_cur = 0;
  int n = 0;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t i = (size_t)y * w + x;
      if (fc.mask.data[i] < 1) continue;
      double qx = x - jnd_image_plane(&fc.motion, 0)[i], qy = y - jnd_image_plane(&fc.motion, 1)[i];
      int x0 = (int)floor(qx), y0 = (int)floor(qy);
      if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) continue;
      double tx = qx - x0, ty = qy - y0;
      int inside = 1;
      for (int k = 0; k < 4; k++) inside &= fp.mask.data[(size_t)(y0 + (k >> 1)) * w + x0 + (k & 1)] >= 1;
      if (!inside) continue;
      for (int c = 0; c < 3; c++) {
        const float *P = jnd_image_plane(&fp.color, c);
        double pv = (1 - ty) * ((1 - tx) * P[(size_t)y0 * w + x0] + tx * P[(size_t)y0 * w + x0 + 1]) +
                    ty * ((1 - tx) * P[(size_t)(y0 + 1) * w + x0] + tx * P[(size_t)(y0 + 1) * w + x0 + 1]);
        e_shade += fabs(jnd_image_plane(&fs.color, c)[i] - pv);
        e_cur += fabs(jnd_image_plane(&fc.color, c)[i] - pv);
      }
      n++;
    }
  CHECK(n > SIZE * SIZE / 20);
  /* both errors share the floor of resampling a textured surface (about
   * 0.035 here); shaded with this pose's setup instead, the two are equal */
  CHECK(e_shade < 0.7 * e_cur);
  /* no previous pose: the plain rendering */
  jnd_frame f1, f2;
  jnd_view still = prev;
  still.outputs = JND_OUT_COLOR;
  CHECK_OK(jnd_render(renderer(), s, &still, &f1));
  still.shade_prev = 1;
  CHECK_OK(jnd_render(renderer(), s, &still, &f2));
  CHECK(memcmp(f1.color.data, f2.color.data, sizeof(float) * 3 * w * h) == 0);
  jnd_frame_free(&f1);
  jnd_frame_free(&f2);
  jnd_frame_free(&fc);
  jnd_frame_free(&fp);
  jnd_frame_free(&fs);
  jnd_scene_free(s);
}

/* the largest R of the switch to level at distance d (−inf: no region) */
static double max_r_with(jnd_renderer *rr, jnd_model *m, jnd_scene *s, const jnd_view *v, const jnd_pop_motion *mo,
                         int level, double d) {
  jnd_view at = *v;
  double len = dist(v->camera.eye, v->camera.target);
  for (int k = 0; k < 3; k++)
    at.camera.eye[k] = v->camera.target[k] + (v->camera.eye[k] - v->camera.target[k]) / len * d;
  at.camera.znear = at.camera.zfar = 0; /* the renderer's own, from the scene's bounds */
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_result r;
  CHECK_OK(jnd_pop_render(m, rr, s, &at, mo, level - 1, 0, &pp, &r));
  double x = r.nregions ? r.max_rating : -INFINITY;
  jnd_pop_result_free(&r);
  return x;
}

static double max_r(jnd_model *m, jnd_scene *s, const jnd_view *v, const jnd_pop_motion *mo, int level, double d) {
  return max_r_with(renderer(), m, s, v, mo, level, d);
}

/* the built-in asset and one level of it at 10 % error: coarse enough to
 * pop when the object fills the image height */
static jnd_scene *builtin_with_a_coarse_level(void) {
  jnd_scene *s = builtin();
  jnd_lod_params lp;
  jnd_lod_defaults(&lp);
  double errors[1] = {0.1};
  lp.errors = errors;
  lp.nerrors = 1;
  CHECK_OK(jnd_scene_lod_build(s, &lp));
  CHECK(jnd_scene_lod_count(s) == 2);
  return s;
}

/* the switch search on one view of the built-in asset with a coarse level,
 * from coverage_near (grid ratio 1.1) at speed (°/s, an orbit) */
static jnd_pop_switch search_switch(jnd_renderer *r, jnd_scene *s, jnd_model *m, const jnd_view *v,
                                    double coverage_near, double speed) {
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_switch_params sp;
  jnd_pop_switch_defaults(&sp);
  sp.tolerance = 0.1;
  sp.coverage_near = coverage_near;
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  mo.speed = speed;
  jnd_pop_switch sw;
  CHECK_OK(jnd_pop_switch_distance(m, r, s, v, 1, &mo, 1, &pp, &sp, &sw));
  return sw;
}

TEST(the_switch_distance_brackets_the_limit) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = builtin_with_a_coarse_level();
  jnd_model *m = model();
  jnd_view v = view(s, 0.8);
  /* from the whole image height: the object still whole in the frame, and
   * the level's change 3.6 JND there (1.3 at half the height, no region) */
  jnd_pop_switch sw = search_switch(renderer(), s, m, &v, 1.0, 0);
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_switch_params sp;
  jnd_pop_switch_defaults(&sp);
  CHECK(sw.status == JND_POP_SWITCH_FOUND);
  CHECK(sw.distance_popping < sw.distance && sw.distance <= sw.distance_popping * 1.1);
  CHECK(sw.evaluations > 3);
  /* recomputed here: below the limit at the distance, at or above it just nearer */
  double at = max_r(m, s, &v, &mo, 1, sw.distance), nearer = max_r(m, s, &v, &mo, 1, sw.distance_popping);
  CHECK_LT(at, 1);
  CHECK(at == sw.max_rating || (isinf(at) && isinf(sw.max_rating)));
  CHECK(nearer >= 1);
  /* the 1-pixel rule: the level's error covers one pixel of the image height there */
  jnd_lod_level_info li;
  CHECK_OK(jnd_scene_lod_info(s, 1, &li));
  CHECK_NEAR(li.error_abs * SIZE / (2 * sw.distance_pixel_rule * tan(45 * M_PI / 360)), 1, 1e-9);
  /* level 0 has no switch to it */
  CHECK_STATUS(jnd_pop_switch_distance(m, renderer(), s, &v, 1, &mo, 0, &pp, &sp, &sw), JND_ERR_ARG);
  jnd_model_free(m);
  jnd_scene_free(s);
}

/* At a far distance the search renders only the object's window and puts
 * it back in the frame (docs/pop.md "Switch decisions"): the R it finds
 * there is the whole frame's, moving views included (their motion and
 * depth come back in place too). A window off-centre, of the wrong field of
 * view or missing the motion would change R by far more than the shading's
 * last bits. */
TEST(a_far_distance_rendered_in_the_objects_window_rates_as_the_whole_frame) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  const int big = 256;
  jnd_renderer *r = NULL;
  jnd_renderer_params rp;
  jnd_renderer_defaults(&rp);
  rp.width = rp.height = big;
  CHECK_OK(jnd_renderer_create(&rp, &r));
  jnd_scene *s = builtin_with_a_coarse_level();
  jnd_model *m = model();
  jnd_view v = view(s, 0.8);
  jnd_pop_switch sw = search_switch(r, s, m, &v, 0.5, 120);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  mo.speed = 120;
  CHECK(sw.status == JND_POP_SWITCH_FOUND);
  int w, h;
  jnd_renderer_size(r, &w, &h);
  CHECK(w == big && h == big);   /* the caller's frame again */
  double centre[3], radius;
  jnd_scene_subject_bounds(s, centre, &radius, NULL);
  /* both distances of the bracket were rendered in a window: the object
   * and its margins fill well under the frame */
  CHECK(jnd_coverage_at_distance(radius, sw.distance_popping, 45) * big + 2 * 16 < 0.8 * big);
  double R[2] = {max_r_with(r, m, s, &v, &mo, 1, sw.distance), max_r_with(r, m, s, &v, &mo, 1, sw.distance_popping)};
  CHECK_LT(R[0], 1);
  CHECK(R[1] >= 1);
  CHECK(isinf(R[0]) ? isinf(sw.max_rating) : fabs(R[0] - sw.max_rating) < 0.01);
  /* one far pair, moving, whole and windowed: the same regions and map but
   * for the shading's last bits (window 70 of 256 pixels) */
  jnd_view far = v;
  far.camera.znear = far.camera.zfar = 0;
  double len = dist(v.camera.eye, v.camera.target), dfar = jnd_camera_distance_for_coverage(radius, 0.15, 45);
  for (int k = 0; k < 3; k++) far.camera.eye[k] = v.camera.target[k] + (v.camera.eye[k] - v.camera.target[k]) / len * dfar;
  jnd_pop_result whole, win;
  CHECK_OK(pop_render_window(m, r, s, &far, &mo, 0, 0, &pp, 0, &whole));
  CHECK_OK(pop_render_window(m, r, s, &far, &mo, 0, 0, &pp, 70, &win));
  CHECK(whole.w == big && win.w == big && whole.jnd.w == big && win.jnd.w == big);
  CHECK(whole.nregions > 0 && whole.nregions == win.nregions);
  CHECK(fabs(whole.max_rating - win.max_rating) < 1e-3 * fabs(whole.max_rating) + 1e-3);
  double total = 0, diff = 0;   /* a pixel can differ more: a disocclusion weight flips on a depth's last bit */
  for (size_t q = 0; q < (size_t)big * big; q++) {
    total += whole.jnd.data[q];
    diff += fabs(whole.jnd.data[q] - win.jnd.data[q]);
  }
  CHECK(total > 10 && diff < 2e-3 * total);   /* 8e-4 measured */
  jnd_pop_result_free(&whole);
  jnd_pop_result_free(&win);
  CHECK_STATUS(pop_render_window(m, r, s, &far, &mo, 0, 0, &pp, 71, &win), JND_ERR_ARG);   /* not centred */
  jnd_model_free(m);
  jnd_scene_free(s);
  jnd_renderer_free(r);
}

TEST(a_level_read_from_a_file_has_a_pixel_rule_distance_from_its_measured_error) {
  /* jnd lod's GLB carries no meshoptimizer error: its levels' pixel rule
   * used to be null; now their error is measured from level 0's surface */
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = builtin_with_a_coarse_level();
  char path[4096];
  snprintf(path, sizeof path, "%s/pop_levels.glb", test_tmp_dir());
  double cov[3] = {0.5, 0.1, 0};
  CHECK_OK(jnd_scene_write_lod_glb(s, path, cov));
  jnd_lod_level_info made;
  CHECK_OK(jnd_scene_lod_info(s, 1, &made));
  jnd_scene_free(s);
  CHECK_OK(jnd_scene_load(path, &s));
  CHECK(jnd_scene_lod_count(s) == 2);
  jnd_lod_level_info li;
  CHECK_OK(jnd_scene_lod_info(s, 1, &li));
  CHECK(!isfinite(li.error_abs)); /* the file holds none */
  jnd_model *m = model();
  jnd_view v = view(s, 0.8);
  jnd_pop_params pp;
  jnd_pop_defaults(&pp);
  jnd_pop_switch_params sp;
  jnd_pop_switch_defaults(&sp);
  sp.tolerance = 0.5;
  jnd_pop_motion mo;
  jnd_pop_motion_defaults(&mo);
  jnd_pop_switch sw;
  CHECK_OK(jnd_pop_switch_distance(m, renderer(), s, &v, 1, &mo, 1, &pp, &sp, &sw));
  jnd_surface_distance d;
  CHECK_OK(jnd_scene_lod_distance(s, 1, 16384, 1, &d));
  CHECK(isfinite(sw.distance_pixel_rule) && d.max > 0);
  CHECK_NEAR(d.max * SIZE / (2 * sw.distance_pixel_rule * tan(45 * M_PI / 360)), 1, 1e-9);
  /* the measured error is of the order of meshoptimizer's bound for the level */
  CHECK(d.max > 0.1 * made.error_abs && d.max < 3 * made.error_abs);
  remove(path);
  jnd_model_free(m);
  jnd_scene_free(s);
}

RUN_TESTS(an_orbit_turns_the_eye_about_the_target_at_its_speed,
          a_translation_moves_eye_and_target_along_the_cameras_axes_in_metres,
          a_spin_rotates_the_object_about_the_target_not_the_camera, identical_levels_do_not_pop_at_rest_or_in_motion,
          the_switch_distance_brackets_the_limit, a_far_distance_rendered_in_the_objects_window_rates_as_the_whole_frame,
          a_level_read_from_a_file_has_a_pixel_rule_distance_from_its_measured_error,
          shading_with_the_previous_setup_matches_the_previous_frame)
