/* Properties of the scene layer (import, maps, resampling) and of the
 * renderer (coverage, shading, determinism, outputs). Renders are small
 * (128²) so that the suite stays fast on llvmpipe. */
#include <stdint.h>
#include <stdio.h>
#include <sys/stat.h>

#include "core/fastmath.h"
#include "jnd.h"
#include "scene/scene.h"
#include "test.h"

#define SIZE 128
#define ASSIMP_MODELS "/usr/share/assimp/models"

static jnd_scene *builtin_scene(int shape) {
  jnd_builtin_params p;
  jnd_builtin_defaults(&p);
  p.map_size = 256;
  p.shape = shape;
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_builtin(&p, &s));
  return s;
}

static jnd_renderer *renderer(void) {
  static jnd_renderer *r;   /* one context for the whole file, as the tasks use it */
  if (!r) {
    jnd_renderer_params p;
    jnd_renderer_defaults(&p);
    p.width = p.height = SIZE;
    if (jnd_renderer_create(&p, &r) == JND_ERR_GL) TEST_SKIP_REST("no OpenGL renderer: %s", jnd_last_error());
    CHECK(r != NULL);
  }
  return r;
}

static jnd_view front_view(const jnd_scene *s, double coverage) {
  jnd_view_sampling vs;
  jnd_view_sampling_defaults(&vs);
  vs.count = 1;
  vs.coverage = coverage;
  jnd_view v;
  jnd_views_sample(s, &vs, &v);
  v.outputs = JND_OUT_COLOR | JND_OUT_MASK | JND_OUT_MIP | JND_OUT_DEPTH | JND_OUT_MOTION;
  return v;
}

static double mean(const jnd_image *img, int ch) {
  double s = 0;
  size_t n = (size_t)img->w * img->h;
  const float *p = img->data + (size_t)ch * n;
  for (size_t i = 0; i < n; i++) s += p[i];
  return s / n;
}

/* Mean absolute difference of two linear images after the display transform.
 * TODO: use jnd diff (jnd_model_diff) once the vision model lands. */
static double mad(const jnd_image *a, const jnd_image *b) {
  jnd_image sa, sb;
  if (jnd_render_to_srgb(a, &sa) || jnd_render_to_srgb(b, &sb)) return 1e9;
  double s = 0;
  size_t n = (size_t)a->w * a->h * a->c;
  for (size_t i = 0; i < n; i++) s += fabs(sa.data[i] - sb.data[i]);
  jnd_image_free(&sa);
  jnd_image_free(&sb);
  return s / n;
}

/* jnd_render_to_srgb encodes a span at a time, vectorised: every sample as
 * the scalar curve gives it, bit for bit (NaN and out-of-range included),
 * so that shown frames do not depend on the instruction set */
TEST(the_vectorised_srgb_curve_is_the_scalar_one) {
  jnd_image lin;
  const int n = 1 << 16;
  CHECK_OK(jnd_image_alloc(&lin, n / 4, 4, 1));
  for (int i = 0; i < n; i++) lin.data[i] = -0.1f + 1.3f * (float)i / (n - 1) + 1e-7f * (float)(i % 7);
  lin.data[17] = NAN;
  lin.data[18] = INFINITY;
  lin.data[19] = 0.0031308f;
  jnd_image enc;
  CHECK_OK(jnd_render_to_srgb(&lin, &enc));
  int same = 0;
  for (int i = 0; i < n; i++) {
    float want = jnd_srgb_encode(lin.data[i]);
    same += memcmp(&want, &enc.data[i], sizeof want) == 0;
  }
  CHECK(same == n);
  jnd_image_free(&lin);
  jnd_image_free(&enc);
}

static int render(const jnd_scene *s, const jnd_view *v, jnd_frame *f) {
  jnd_status st = jnd_render(renderer(), s, v, f);
  CHECK_OK(st);
  return st == JND_OK;
}

/* ---- scene ---- */

TEST(builtin_maps_are_addressable_by_material_and_slot) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  CHECK(jnd_scene_map_count(s) == 4);
  int i = jnd_scene_map_find(s, "builtin/normal");
  CHECK(i >= 0);
  jnd_map_info info;
  CHECK_OK(jnd_scene_map_info(s, i, &info));
  CHECK(strcmp(info.name, "builtin/normal") == 0);
  CHECK(info.slot == JND_MAP_NORMAL && info.kind == JND_MAP_KIND_NORMAL);
  CHECK(info.width == 256 && info.orig_width == 256);
  CHECK(jnd_scene_map_find(s, "builtin/nothing") == -1);
  CHECK(jnd_scene_map_find(s, "other/baseColor") == -1);
  CHECK_OK(jnd_scene_map_resize(s, i, 100, 60));   /* not a power of two */
  CHECK_OK(jnd_scene_map_info(s, i, &info));
  CHECK(info.width == 100 && info.height == 60 && info.orig_width == 256);
  jnd_scene_map_restore(s, i);
  CHECK_OK(jnd_scene_map_info(s, i, &info));
  CHECK(info.width == 256);
  jnd_scene_free(s);
}

TEST(resampling_a_constant_map_keeps_it_constant) {
  jnd_image in, out;
  CHECK_OK(jnd_image_alloc(&in, 37, 23, 3));
  for (size_t i = 0; i < (size_t)37 * 23 * 3; i++) in.data[i] = 0.3f;
  CHECK_OK(jnd_resample_map(&in, 11, 50, JND_MAP_KIND_COLOR, 0, &out));
  double lo = 1, hi = 0;
  for (size_t i = 0; i < (size_t)11 * 50 * 3; i++) {
    lo = fmin(lo, out.data[i]);
    hi = fmax(hi, out.data[i]);
  }
  CHECK_NEAR(lo, 0.3, 1e-4);
  CHECK_NEAR(hi, 0.3, 1e-4);
  jnd_image_free(&in);
  jnd_image_free(&out);
}

TEST(colour_maps_are_filtered_in_linear_light) {
  /* a one-pixel black/white checker halved: the mean of linear 0 and 1 is
   * 0.5, which sRGB encodes as 0.735, not 0.5 */
  jnd_image in, out;
  CHECK_OK(jnd_image_alloc(&in, 64, 64, 1));
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 64; x++) in.data[y * 64 + x] = (float)((x + y) & 1);
  CHECK_OK(jnd_resample_map(&in, 32, 32, JND_MAP_KIND_COLOR, 1, &out));
  CHECK_NEAR(out.data[16 * 32 + 16], 0.735, 0.02);
  jnd_image_free(&out);
  CHECK_OK(jnd_resample_map(&in, 32, 32, JND_MAP_KIND_DATA, 1, &out));
  CHECK_NEAR(out.data[16 * 32 + 16], 0.5, 0.02);
  jnd_image_free(&in);
  jnd_image_free(&out);
}

TEST(resampled_normal_maps_hold_unit_vectors) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_image in, out;
  CHECK_OK(jnd_scene_map_get(s, jnd_scene_map_find(s, "builtin/normal"), 1, &in));
  CHECK_OK(jnd_resample_map(&in, 77, 77, JND_MAP_KIND_NORMAL, 1, &out));
  size_t P = (size_t)77 * 77;
  double worst = 0;
  for (size_t i = 0; i < P; i++) {
    double l = 0;
    for (int c = 0; c < 3; c++) {
      double v = 2 * out.data[c * P + i] - 1;
      l += v * v;
    }
    worst = fmax(worst, fabs(sqrt(l) - 1));
  }
  CHECK_LT(worst, 0.01);
  jnd_image_free(&in);
  jnd_image_free(&out);
  jnd_scene_free(s);
}

TEST(broken_files_are_refused_as_malformed) {
  static const char *const bad[] = {
      ASSIMP_MODELS "/glTF2/MissingBin/BoxTextured.gltf",
      ASSIMP_MODELS "/glTF2/RecursiveNodes/RecursiveNodes.gltf",
      ASSIMP_MODELS "/glTF2/SchemaFailures/sceneWrongType.gltf",
      ASSIMP_MODELS "/glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
      ASSIMP_MODELS "/glTF2/wrongTypes/badArray.gltf",
      ASSIMP_MODELS "/glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf",
  };
  struct stat st;
  if (stat(ASSIMP_MODELS, &st) != 0) {
    TEST_SKIP("%s not installed", ASSIMP_MODELS);
    return;
  }
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    jnd_scene *s = NULL;
    CHECK_STATUS(jnd_scene_load(bad[i], &s), JND_ERR_FORMAT);
    CHECK(s == NULL);
    CHECK(strncmp(jnd_last_error(), bad[i], strlen(bad[i])) == 0);
    CHECK(strchr(jnd_last_error(), '\n') == NULL);
  }
  jnd_scene *s = NULL;
  CHECK_STATUS(jnd_scene_load("/nonexistent/model.glb", &s), JND_ERR_IO);
}

TEST(truncated_glb_is_refused) {
  const char *src = ASSIMP_MODELS "/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
  FILE *f = fopen(src, "rb");
  if (!f) {
    TEST_SKIP("%s not installed", src);
    return;
  }
  unsigned char buf[4096];
  size_t n = fread(buf, 1, sizeof buf, f);
  fclose(f);
  char path[1200];
  snprintf(path, sizeof path, "%s/truncated.glb", test_tmp_dir());
  f = fopen(path, "wb");
  fwrite(buf, 1, n / 2, f);
  fclose(f);
  jnd_scene *s = NULL;
  CHECK_STATUS(jnd_scene_load(path, &s), JND_ERR_FORMAT);
}

TEST(obj_with_missing_texture_falls_back_to_the_factor_with_a_warning) {
  char dir[1100], path[1200];
  snprintf(dir, sizeof dir, "%s", test_tmp_dir());
  snprintf(path, sizeof path, "%s/quad.mtl", dir);
  FILE *f = fopen(path, "w");
  fputs("newmtl Paint\nKd 0.8 0.2 0.1\nNs 50\nmap_Kd missing.png\n", f);
  fclose(f);
  snprintf(path, sizeof path, "%s/quad.obj", dir);
  f = fopen(path, "w");
  fputs("mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 0 1\nusemtl Paint\nf 1/1/1 2/2/1 3/3/1 4/4/1\n", f);
  fclose(f);
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(path, &s));
  if (!s) return;
  CHECK(jnd_scene_triangle_count(s) == 2);
  CHECK(jnd_scene_warning_count(s) == 1);
  CHECK(strstr(jnd_scene_warning(s, 0), "Paint/baseColor") != NULL);
  CHECK(jnd_scene_map_count(s) == 0);
  int found = 0;
  for (int i = 0; i < jnd_scene_material_count(s); i++) found |= strcmp(jnd_scene_material_name(s, i), "Paint") == 0;
  CHECK(found);
  jnd_view v;
  jnd_view_defaults(&v);
  v.outputs = JND_OUT_COLOR | JND_OUT_MASK;
  jnd_frame fr;
  if (render(s, &v, &fr)) {
    CHECK_LT(0.1, mean(&fr.mask, 0));
    CHECK_LT(mean(&fr.color, 2), mean(&fr.color, 0));   /* the red Kd shows */
    jnd_frame_free(&fr);
  }
  jnd_scene_free(s);
}

/* ---- renderer ---- */

TEST(object_fills_the_coverage_asked_for) {
  jnd_scene *s = builtin_scene(1);   /* a sphere: its silhouette is the bounding circle */
  if (!s) return;
  jnd_view a = front_view(s, 0.8), b = front_view(s, 0.4);
  jnd_frame fa, fb;
  if (render(s, &a, &fa) && render(s, &b, &fb)) {
    double ca = mean(&fa.mask, 0), cb = mean(&fb.mask, 0);
    /* a disc of diameter 0.8 · height covers π·0.4² of a square image */
    CHECK_NEAR(ca, M_PI * 0.4 * 0.4, 0.03);
    CHECK_NEAR(ca / cb, 4.0, 0.4);
    jnd_frame_free(&fa);
    jnd_frame_free(&fb);
  }
  jnd_scene_free(s);
}

TEST(normal_map_changes_shading) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_view v = front_view(s, 0.8);
  jnd_frame with, flat;
  int i = jnd_scene_map_find(s, "builtin/normal");
  jnd_image up;
  CHECK_OK(jnd_image_alloc(&up, 4, 4, 3));
  for (int k = 0; k < 16; k++) {
    up.data[k] = up.data[16 + k] = 0.5f;
    up.data[32 + k] = 1.0f;
  }
  if (render(s, &v, &with)) {
    CHECK_OK(jnd_scene_map_set(s, i, &up));
    if (render(s, &v, &flat)) {
      /* over the object's pixels */
      double cover = mean(&with.mask, 0);
      CHECK_LT(0.02, mad(&with.color, &flat.color) / cover);
      CHECK_NEAR(cover, mean(&flat.mask, 0), 1e-6);   /* shading only */
      jnd_frame_free(&flat);
    }
    jnd_frame_free(&with);
  }
  jnd_image_free(&up);
  jnd_scene_free(s);
}

/* The builtin sphere as a polished metal: what it shows is the environment. */
static void polish(jnd_scene *s) {
  int i = jnd_scene_map_find(s, "builtin/metallicRoughness");
  jnd_image mr;
  CHECK_OK(jnd_image_alloc(&mr, 2, 2, 3));
  for (int k = 0; k < 4; k++) {
    mr.data[k] = 1;
    mr.data[4 + k] = 0.1f;
    mr.data[8 + k] = 1;
  }
  CHECK_OK(jnd_scene_map_set(s, i, &mr));
  jnd_image_free(&mr);
}

TEST(environment_changes_the_specular_response) {
  jnd_scene *s = builtin_scene(1);
  if (!s) return;
  polish(s);
  jnd_view v = front_view(s, 0.8);
  v.nlights = 0;
  jnd_frame a, b, off;
  if (render(s, &v, &a)) {
    v.env_rotation_deg = 120;
    if (render(s, &v, &b)) {
      CHECK_LT(0.02, mad(&a.color, &b.color));
      jnd_frame_free(&b);
    }
    v.env_intensity = 0;
    if (render(s, &v, &off)) {
      CHECK_LT(mean(&off.color, 1) * 10 + 1e-4, mean(&a.color, 1));   /* no IBL: nearly black */
      jnd_frame_free(&off);
    }
    jnd_frame_free(&a);
  }
  jnd_scene_free(s);
}

/* A polished metal under a uniform environment of colour rgb (an EXR file
 * of w × h), rendered by a renderer of its own: the mean red and green. */
static void metal_in(jnd_scene *s, const char *path, int w, const float rgb[3], double out[2]) {
  jnd_image env;
  out[0] = out[1] = -1;
  CHECK_OK(jnd_image_alloc(&env, w, w / 2, 3));
  for (int c = 0; c < 3; c++)
    for (size_t i = 0; i < (size_t)env.w * env.h; i++) env.data[(size_t)c * env.w * env.h + i] = rgb[c];
  CHECK_OK(jnd_image_write_exr(path, &env, NULL, 0));
  jnd_image_free(&env);
  jnd_renderer_params p;
  jnd_renderer_defaults(&p);
  p.width = p.height = SIZE;
  p.env_path = path;
  jnd_renderer *r = NULL;
  CHECK_OK(jnd_renderer_create(&p, &r));
  jnd_view v = front_view(s, 0.8);
  v.nlights = 0;
  jnd_frame f;
  if (r && jnd_render(r, s, &v, &f) == JND_OK) {
    out[0] = mean(&f.color, 0);
    out[1] = mean(&f.color, 1);
    jnd_frame_free(&f);
  }
  jnd_renderer_free(r);
}

/* Renderers keep the last prepared environment for the next one (it is
 * slow to prefilter): a file rewritten in between must be prepared again,
 * and the same file give the same light. */
TEST(an_environment_file_rewritten_between_renderers_lights_the_next_one) {
  jnd_scene *s = builtin_scene(1);
  if (!s || !renderer()) return;
  polish(s);
  char path[1100];
  snprintf(path, sizeof path, "%s/environment.exr", test_tmp_dir());
  const float red[3] = {2, 0.1f, 0.1f}, green[3] = {0.1f, 2, 0.1f};
  double a[2], b[2], c[2];
  metal_in(s, path, 32, red, a);
  metal_in(s, path, 32, red, b);   /* the same size: the cache's identity is not the size alone */
  metal_in(s, path, 32, green, c);
  CHECK(a[0] > 2 * a[1]);          /* red light */
  CHECK(a[0] == b[0] && a[1] == b[1]);
  CHECK(c[1] > 2 * c[0]);          /* green light, not the red file's */
  jnd_scene_free(s);
}

TEST(rendering_is_deterministic) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_view v = front_view(s, 0.7);
  jnd_frame a, b;
  if (render(s, &v, &a) && render(s, &v, &b)) {
    size_t n = (size_t)SIZE * SIZE;
    CHECK(memcmp(a.color.data, b.color.data, n * 3 * sizeof(float)) == 0);
    CHECK(memcmp(a.mip.data, b.mip.data, n * JND_MAP_SLOTS * sizeof(float)) == 0);
    jnd_frame_free(&a);
    jnd_frame_free(&b);
  }
  jnd_scene_free(s);
}

TEST(restoring_a_map_restores_the_image_exactly) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_view v = front_view(s, 0.8);
  int i = jnd_scene_map_find(s, "builtin/baseColor");
  jnd_frame a, half, b;
  if (render(s, &v, &a)) {
    CHECK_OK(jnd_scene_map_resize(s, i, 32, 32));
    if (render(s, &v, &half)) {
      CHECK_LT(0.002, mad(&a.color, &half.color));   /* a blurrier albedo shows */
      jnd_frame_free(&half);
    }
    jnd_scene_map_restore(s, i);
    if (render(s, &v, &b)) {
      CHECK(memcmp(a.color.data, b.color.data, (size_t)SIZE * SIZE * 3 * sizeof(float)) == 0);
      jnd_frame_free(&b);
    }
    jnd_frame_free(&a);
  }
  jnd_scene_free(s);
}

TEST(mip_level_rises_by_one_per_halving_of_size_on_screen) {
  jnd_scene *s = builtin_scene(1);
  if (!s) return;
  jnd_view near = front_view(s, 0.8), far = front_view(s, 0.2);
  jnd_frame a, b;
  if (render(s, &near, &a) && render(s, &far, &b)) {
    /* the median level over the object, baseColor channel */
    double la = 0, lb = 0;
    int na = 0, nb = 0;
    for (size_t k = 0; k < (size_t)SIZE * SIZE; k++) {
      if (a.mip.data[k] >= 0 && a.material.data[k] == 0) la += a.mip.data[k], na++;
      if (b.mip.data[k] >= 0 && b.material.data[k] == 0) lb += b.mip.data[k], nb++;
    }
    CHECK(na > 0 && nb > 0);
    CHECK(a.mip.data[0] == -1 && a.material.data[0] == -1);   /* corner: background */
    if (na && nb) CHECK_NEAR(lb / nb - la / na, 2.0, 0.6);   /* 4× smaller: 2 levels */
    jnd_frame_free(&a);
    jnd_frame_free(&b);
  }
  jnd_scene_free(s);
}

TEST(motion_vectors_follow_the_camera) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_view v = front_view(s, 0.8);
  jnd_frame still, moved;
  if (render(s, &v, &still)) {
    double m = 0;
    for (size_t k = 0; k < (size_t)SIZE * SIZE * 2; k++) m = fmax(m, fabs(still.motion.data[k]));
    CHECK_LT(m, 1e-3);
    jnd_frame_free(&still);
  }
  /* the previous camera was 0.05 units to the right (right = view × up): the
   * camera moved left, so the content moved right on screen. A point at depth
   * z moves 0.05·f/z pixels (f = 64 / tan(fov/2), the focal length in pixels),
   * and the object's pixels lie between the target's depth d and d − r, r the
   * bounding radius (1.549 for the builtin asset, view_sampling's test) */
  v.has_prev = 1;
  v.prev_camera = v.camera;
  double tx = v.camera.target[0] - v.camera.eye[0], tz = v.camera.target[2] - v.camera.eye[2];
  double l = sqrt(tx * tx + tz * tz);
  for (int k = 0; k < 3; k++) v.prev_camera.target[k] = v.camera.target[k];
  v.prev_camera.eye[0] += 0.05 * -tz / l;
  v.prev_camera.eye[2] += 0.05 * tx / l;
  v.prev_camera.target[0] += 0.05 * -tz / l;
  v.prev_camera.target[2] += 0.05 * tx / l;
  double d = 0, f = (SIZE / 2.0) / tan(v.camera.fov_y_deg * M_PI / 360.0);
  for (int k = 0; k < 3; k++) d += (v.camera.target[k] - v.camera.eye[k]) * (v.camera.target[k] - v.camera.eye[k]);
  d = sqrt(d);
  if (render(s, &v, &moved)) {
    double mx = 0, my = 0;
    int n = 0;
    for (size_t k = 0; k < (size_t)SIZE * SIZE; k++)
      if (moved.mask.data[k] > 0.99) mx += moved.motion.data[k], my += moved.motion.data[SIZE * SIZE + k], n++;
    CHECK(n > 0);
    if (n) {
      CHECK_LT(0.05 * f / d, mx / n); /* rightwards, at least as far as the target plane moves */
      CHECK_LT(mx / n, 0.05 * f / (d - 1.549));
      CHECK_LT(fabs(my / n), 0.1 * mx / n); /* and sideways only */
    }
    jnd_frame_free(&moved);
  }
  jnd_scene_free(s);
}

TEST(view_sampling_is_deterministic_and_seeded) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_view_sampling p;
  jnd_view_sampling_defaults(&p);
  p.count = 5;
  jnd_view a[5], b[5], c[5];
  CHECK_OK(jnd_views_sample(s, &p, a));
  CHECK_OK(jnd_views_sample(s, &p, b));
  p.seed = 2;
  CHECK_OK(jnd_views_sample(s, &p, c));
  CHECK(memcmp(a[3].camera.eye, b[3].camera.eye, sizeof a[3].camera.eye) == 0);
  CHECK(memcmp(&a[3].lights[0], &b[3].lights[0], sizeof(jnd_light)) == 0);
  CHECK(memcmp(a[3].camera.eye, c[3].camera.eye, sizeof a[3].camera.eye) != 0);
  double d = jnd_camera_distance_for_coverage(1.549, 0.8, 45);
  CHECK_NEAR(sqrt(a[0].camera.eye[0] * a[0].camera.eye[0] + a[0].camera.eye[1] * a[0].camera.eye[1] +
                  a[0].camera.eye[2] * a[0].camera.eye[2]),
             d, 0.01);
  jnd_scene_free(s);
}

/* Compares a frame with tests/data/render/NAME (JND_UPDATE_GOLDEN=1
 * rewrites it): by mean absolute difference and by the vision model's
 * probability of detection, not by bytes, so that other llvmpipe or GPU
 * versions pass. */
static void check_golden(const jnd_image *color, const char *name) {
  char path[1200];
  snprintf(path, sizeof path, "%s", __FILE__);   /* .../tests/unit/test_render.c */
  char *cut = strstr(path, "/unit/test_render.c");
  if (!cut) return;
  snprintf(cut, sizeof path - (size_t)(cut - path), "/data/render/%s", name);
  jnd_image srgb, gold;
  jnd_image_info gi;
  CHECK_OK(jnd_render_to_srgb(color, &srgb));
  if (getenv("JND_UPDATE_GOLDEN")) CHECK_OK(jnd_image_write_png(path, &srgb, 8));
  if (jnd_image_read(path, &gold, &gi) != JND_OK) {
    fprintf(stderr, "%s\n", jnd_last_error());
    CHECK(!"golden image missing");
    jnd_image_free(&srgb);
    return;
  }
  CHECK(gold.w == srgb.w && gold.h == srgb.h && gold.c == 3);
  if (gold.w == srgb.w && gold.h == srgb.h && gold.c == 3) {
    double d = 0;
    size_t n = (size_t)gold.w * gold.h * 3;
    for (size_t k = 0; k < n; k++) d += fabs(gold.data[k] - srgb.data[k]);
    CHECK_LT(d / n, 0.01);
    /* how likely a viewer notices the difference (jnd diff) */
    jnd_model_params mp;
    jnd_model_defaults(&mp);
    jnd_model *m = NULL;
    jnd_diff_stats st;
    jnd_image_info si = gi;
    if (jnd_model_create(&mp, &m) == JND_OK) {
      CHECK_OK(jnd_diff_files(m, &gold, &gi, &srgb, &si, NULL, NULL, NULL, &st));
      CHECK_LT(st.p_detect, 0.25);
      jnd_model_free(m);
      return;   /* gold and srgb were consumed */
    }
  }
  jnd_image_free(&gold);
  jnd_image_free(&srgb);
}

TEST(golden_builtin_frame_matches) {
  jnd_scene *s = builtin_scene(0);
  if (!s) return;
  jnd_view v = front_view(s, 0.8);
  jnd_frame f;
  if (render(s, &v, &f)) {
    check_golden(&f.color, "builtin_128.png");
    jnd_frame_free(&f);
  }
  jnd_scene_free(s);
}

TEST(golden_box_textured_frame_matches) {
  jnd_scene *s = NULL;
  if (jnd_scene_load(ASSIMP_MODELS "/glTF2/BoxTextured-glTF/BoxTextured.gltf", &s) != JND_OK) {
    TEST_SKIP("%s", jnd_last_error());
    return;
  }
  jnd_view v = front_view(s, 0.8);
  jnd_frame f;
  if (render(s, &v, &f)) {
    check_golden(&f.color, "box_textured_128.png");
    jnd_frame_free(&f);
  }
  jnd_scene_free(s);
}

/* A quad facing +Z whose uv u runs along +X and v down the image (image up
 * is +Y), with a constant normal map tilted by `tilt` (tangent space). */
static jnd_scene *tilted_quad(const double tilt[3]) {
  char dir[1100], path[1200];
  snprintf(dir, sizeof dir, "%s", test_tmp_dir());
  jnd_image nm;
  CHECK_OK(jnd_image_alloc(&nm, 8, 8, 3));
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < 64; k++) nm.data[c * 64 + k] = (float)(0.5 + 0.5 * tilt[c]);
  snprintf(path, sizeof path, "%s/tilt.png", dir);
  CHECK_OK(jnd_image_write_png(path, &nm, 16));
  jnd_image_free(&nm);
  snprintf(path, sizeof path, "%s/tilt.mtl", dir);
  FILE *f = fopen(path, "w");
  fputs("newmtl Tilt\nKd 0.8 0.8 0.8\nNs 0\nnorm tilt.png\n", f);
  fclose(f);
  snprintf(path, sizeof path, "%s/tilt.obj", dir);
  f = fopen(path, "w");
  fputs("mtllib tilt.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vn 0 0 1\nusemtl Tilt\nf 1/1/1 2/2/1 3/3/1 4/4/1\n", f);
  fclose(f);
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(path, &s));
  return s;
}

static double lit_by(const jnd_scene *s, double dx, double dy) {
  jnd_view v;
  jnd_view_defaults(&v);
  v.env_intensity = 0;
  v.nlights = 1;
  memset(&v.lights[0], 0, sizeof v.lights[0]);
  v.lights[0].type = JND_LIGHT_DIRECTIONAL;
  v.lights[0].direction[0] = -dx;   /* travels away from (dx, dy, 1) */
  v.lights[0].direction[1] = -dy;
  v.lights[0].direction[2] = -1;
  v.lights[0].color[0] = v.lights[0].color[1] = v.lights[0].color[2] = 1;
  v.lights[0].intensity = 1;
  jnd_frame f;
  double m = 0;
  if (render(s, &v, &f)) {
    m = mean(&f.color, 1);
    jnd_frame_free(&f);
  }
  return m;
}

TEST(normal_maps_follow_the_gltf_tangent_convention) {
  /* +X of the map tilts the surface toward +u, +Y (green) toward the top of
   * the image: a light from that side makes it brighter */
  const double right[3] = {0.6, 0, 0.8}, up[3] = {0, 0.6, 0.8};
  jnd_scene *s = tilted_quad(right);
  if (s) {
    CHECK(jnd_scene_map_find(s, "Tilt/normal") >= 0);
    CHECK_LT(1.3 * lit_by(s, -1, 0), lit_by(s, 1, 0));
    jnd_scene_free(s);
  }
  s = tilted_quad(up);
  if (s) {
    CHECK_LT(1.3 * lit_by(s, 0, -1), lit_by(s, 0, 1));
    jnd_scene_free(s);
  }
}

TEST(assimp_test_models_render_with_plausible_coverage) {
  static const char *const good[] = {
      "/glTF2/BoxTextured-glTF/BoxTextured.gltf",
      "/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
      "/glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf",
      "/glTF2/BoxTexcoords-glTF/boxTexcoords.gltf",
      "/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
      "/glTF2/ClearCoat-glTF/ClearCoatTest.gltf",
      "/glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
  };
  struct stat st;
  if (stat(ASSIMP_MODELS, &st) != 0) {
    TEST_SKIP("%s not installed", ASSIMP_MODELS);
    return;
  }
  for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
    char path[512];
    snprintf(path, sizeof path, ASSIMP_MODELS "%s", good[i]);
    jnd_scene *s = NULL;
    CHECK_OK(jnd_scene_load(path, &s));
    if (!s) continue;
    jnd_view v = front_view(s, 0.8);
    jnd_frame f;
    if (render(s, &v, &f)) {
      double c = mean(&f.mask, 0), lum = mean(&f.color, 1);
      if (!(c > 0.05 && c < 0.6)) fprintf(stderr, "%s: coverage %.3f\n", path, c);
      CHECK(c > 0.05 && c < 0.6);
      CHECK(lum > 0.005 && isfinite(lum));
      jnd_frame_free(&f);
    }
    jnd_scene_free(s);
  }
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(ASSIMP_MODELS "/glTF2/BoxTextured-glTF/BoxTextured.gltf", &s));
  if (s) {
    CHECK(jnd_scene_map_count(s) >= 1);
    jnd_map_info info;
    CHECK_OK(jnd_scene_map_info(s, 0, &info));
    CHECK(info.slot == JND_MAP_BASE_COLOR && info.orig_width > 0);
    jnd_scene_free(s);
  }
}

/* A quad facing +Z with material Paint: Kd, opacity d. */
static jnd_scene *paint_quad(double d) {
  char dir[1100], path[1200];
  snprintf(dir, sizeof dir, "%s", test_tmp_dir());
  snprintf(path, sizeof path, "%s/paint.mtl", dir);
  FILE *f = fopen(path, "w");
  fprintf(f, "newmtl Paint\nKd 0.8 0.8 0.8\nNs 10\nd %g\n", d);
  fclose(f);
  snprintf(path, sizeof path, "%s/paint.obj", dir);
  f = fopen(path, "w");
  fputs("mtllib paint.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nusemtl Paint\n"
        "f 1//1 2//1 3//1 4//1\n", f);
  fclose(f);
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(path, &s));
  return s;
}

TEST(mirrored_uvs_get_their_own_tangent_frames) {
  /* two quads side by side, the right one's u mirrored: the vertices on the
   * mirror line are shared by both and must be split (as MikkTSpace does) */
  char path[1200];
  snprintf(path, sizeof path, "%s/mirror.obj", test_tmp_dir());
  FILE *f = fopen(path, "w");
  fputs("v -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 1 -1 0\nv 1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 2/2/1 5/1/1 6/4/1 3/3/1\n", f);
  fclose(f);
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(path, &s));
  if (!s) return;
  const jnd_mesh *m = &s->meshes[0];
  CHECK(m->nverts == 8);
  int pos = 0, neg = 0;
  for (size_t v = 0; v < m->nverts; v++) {
    const float *d = m->vertices + v * JND_VTX_FLOATS;
    if (d[9] > 0) pos++;
    else neg++;
    /* the tangent follows +u: +X on the left quad, −X on the mirrored one */
    CHECK_NEAR(fabs(d[6]), 1.0, 1e-5);
    CHECK(d[0] < -0.5 ? d[6] > 0 : d[0] > 0.5 ? d[6] < 0 : 1);
  }
  CHECK(pos == 4 && neg == 4);
  jnd_scene_free(s);
}

TEST(blended_surfaces_cover_by_their_opacity) {
  jnd_scene *opaque = paint_quad(1), *half = paint_quad(0.5);
  if (opaque && half) {
    jnd_view v;
    jnd_view_defaults(&v);
    v.outputs = JND_OUT_COLOR | JND_OUT_MASK;
    jnd_frame a, b;
    if (render(opaque, &v, &a)) {
      if (render(half, &v, &b)) {
        CHECK_NEAR(mean(&b.mask, 0) / mean(&a.mask, 0), 0.5, 0.02);
        CHECK_NEAR(mean(&b.color, 1) / mean(&a.color, 1), 0.5, 0.05);   /* over black */
        jnd_frame_free(&b);
      }
      jnd_frame_free(&a);
    }
  }
  jnd_scene_free(opaque);
  jnd_scene_free(half);
}

TEST(point_and_spot_lights_light_the_side_they_are_on) {
  jnd_scene *s = paint_quad(1);
  if (!s) return;
  jnd_view v;
  jnd_view_defaults(&v);
  v.env_intensity = 0;
  v.nlights = 1;
  jnd_light *L = &v.lights[0];
  memset(L, 0, sizeof *L);
  L->type = JND_LIGHT_POINT;
  L->color[0] = L->color[1] = L->color[2] = 1;
  L->intensity = 5;
  L->position[2] = 1;
  jnd_frame front, back, spot_in, spot_out;
  if (render(s, &v, &front)) {
    L->position[2] = -1;   /* behind the quad: it faces away */
    if (render(s, &v, &back)) {
      CHECK_LT(mean(&back.color, 0) + 0.01, mean(&front.color, 0));
      jnd_frame_free(&back);
    }
    jnd_frame_free(&front);
  }
  L->type = JND_LIGHT_SPOT;
  L->position[2] = 1;
  L->direction[2] = -1;
  L->inner_deg = 10;
  L->outer_deg = 20;
  if (render(s, &v, &spot_in)) {
    L->direction[0] = 1;   /* turned 45° away: the cone misses the quad's centre */
    if (render(s, &v, &spot_out)) {
      size_t c = (size_t)(SIZE / 2) * SIZE + SIZE / 2;
      CHECK_LT(spot_out.color.data[c] + 0.01, spot_in.color.data[c]);
      jnd_frame_free(&spot_out);
    }
    jnd_frame_free(&spot_in);
  }
  jnd_scene_free(s);
}

TEST(maps_keep_their_texture_coordinate_set) {
  jnd_scene *s = NULL;
  const char *path = ASSIMP_MODELS "/glTF2/BoxTexcoords-glTF/boxTexcoords.gltf";
  struct stat st;
  if (stat(path, &st) != 0) {
    TEST_SKIP("%s not installed", path);
    return;
  }
  CHECK_OK(jnd_scene_load(path, &s));
  if (!s) return;
  jnd_map_info info;
  int i = jnd_scene_map_find(s, "Material/metallicRoughness");
  CHECK(i >= 0);
  if (i >= 0) {
    CHECK_OK(jnd_scene_map_info(s, i, &info));
    CHECK(info.uv_set == 1);
  }
  i = jnd_scene_map_find(s, "Material/baseColor");
  if (i >= 0) {
    CHECK_OK(jnd_scene_map_info(s, i, &info));
    CHECK(info.uv_set == 0);
  }
  jnd_scene_free(s);
}

/* A glTF quad facing +z with an asymmetric texture (red ramps along u, green
 * along v, a blue checker), uvs uv[4][2], and `ext` as its baseColorTexture's
 * "extensions" object ("" for none). */
static jnd_scene *texture_quad(const char *name, const float uv[4][2], const char *ext) {
  char dir[1100], path[1300];
  snprintf(dir, sizeof dir, "%s", test_tmp_dir());
  /* 512² so that the quad minifies it and the mip levels are not clamped at 0 */
  enum { T = 512 };
  jnd_image tex;
  CHECK_OK(jnd_image_alloc(&tex, T, T, 3));
  for (int y = 0; y < T; y++)
    for (int x = 0; x < T; x++) {
      size_t i = (size_t)y * T + x;
      tex.data[i] = (x + 0.5f) / T;
      tex.data[T * T + i] = (y + 0.5f) / T;
      tex.data[2 * T * T + i] = ((x / 32 + y / 32) & 1) ? 0.9f : 0.1f;
    }
  snprintf(path, sizeof path, "%s/quad_tex.png", dir);
  CHECK_OK(jnd_image_write_png(path, &tex, 8));
  jnd_image_free(&tex);
  float geo[4 * 3 + 4 * 3 + 4 * 2] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  for (int k = 0; k < 4; k++) {
    geo[24 + 2 * k] = uv[k][0];
    geo[24 + 2 * k + 1] = uv[k][1];
  }
  const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  snprintf(path, sizeof path, "%s/%s.bin", dir, name);
  FILE *f = fopen(path, "wb");
  fwrite(geo, sizeof geo, 1, f);
  fwrite(idx, sizeof idx, 1, f);
  fclose(f);
  snprintf(path, sizeof path, "%s/%s.gltf", dir, name);
  f = fopen(path, "w");
  fprintf(f,
          "{\"asset\": {\"version\": \"2.0\"}, \"extensionsUsed\": [\"KHR_texture_transform\"],\n"
          " \"buffers\": [{\"byteLength\": 140, \"uri\": \"%s.bin\"}],\n"
          " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 48},\n"
          "   {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 48}, {\"buffer\": 0, \"byteOffset\": 96, \"byteLength\": 32},\n"
          "   {\"buffer\": 0, \"byteOffset\": 128, \"byteLength\": 12}],\n"
          " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\",\n"
          "     \"min\": [-1, -1, 0], \"max\": [1, 1, 0]},\n"
          "   {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC3\"},\n"
          "   {\"bufferView\": 2, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},\n"
          "   {\"bufferView\": 3, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}],\n"
          " \"images\": [{\"uri\": \"quad_tex.png\"}], \"textures\": [{\"source\": 0}],\n"
          " \"materials\": [{\"name\": \"Quad\", \"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0%s%s},\n"
          "   \"metallicFactor\": 0, \"roughnessFactor\": 1}}],\n"
          " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"NORMAL\": 1, \"TEXCOORD_0\": 2},\n"
          "   \"indices\": 3, \"material\": 0}]}],\n"
          " \"nodes\": [{\"mesh\": 0}], \"scenes\": [{\"nodes\": [0]}], \"scene\": 0}\n",
          name, ext[0] ? ", \"extensions\": " : "", ext);
  fclose(f);
  jnd_scene *s = NULL;
  CHECK_OK(jnd_scene_load(path, &s));
  return s;
}

TEST(gltf_texture_transform_is_applied_as_its_extension_defines) {
  /* KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, with
   * R = [cos −sin; sin cos]. The quad with the extension must look like the
   * quad whose uvs carry the transform already (the map is affine, so per
   * vertex is exact), and not like the untransformed quad. */
  const double ox = 0.25, oy = 0.125, r = 0.3, sx = 2, sy = 3;
  const float uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  float moved[4][2];
  for (int k = 0; k < 4; k++) {
    double u = uv[k][0] * sx, v = uv[k][1] * sy;
    moved[k][0] = (float)(cos(r) * u - sin(r) * v + ox);
    moved[k][1] = (float)(sin(r) * u + cos(r) * v + oy);
  }
  jnd_scene *a = texture_quad("quad_xf", uv,
                              "{\"KHR_texture_transform\": {\"offset\": [0.25, 0.125], \"rotation\": 0.3, "
                              "\"scale\": [2, 3]}}");
  jnd_scene *b = texture_quad("quad_moved", moved, "");
  jnd_scene *c = texture_quad("quad_plain", uv, "");
  if (!a || !b || !c) return;
  jnd_map_info info;
  CHECK_OK(jnd_scene_map_info(a, 0, &info));
  const double want[6] = {cos(r) * sx, -sin(r) * sy, ox, sin(r) * sx, cos(r) * sy, oy};
  for (int k = 0; k < 6; k++) CHECK_NEAR(info.uv_transform[k], want[k], 1e-5);
  CHECK_OK(jnd_scene_map_info(c, 0, &info));
  CHECK(info.uv_transform[0] == 1 && info.uv_transform[1] == 0 && info.uv_transform[4] == 1);
  jnd_view v; /* from +z, as lit_by's */
  jnd_view_defaults(&v);
  v.outputs = JND_OUT_COLOR | JND_OUT_MIP;
  jnd_frame fa = {0}, fb = {0}, fc = {0};
  if (render(a, &v, &fa) && render(b, &v, &fb) && render(c, &v, &fc)) {
    double same = mad(&fa.color, &fb.color), other = mad(&fa.color, &fc.color);
    fprintf(stderr, "  transformed vs pre-transformed uvs %.5f, vs untransformed %.5f\n", same, other);
    CHECK(same < 0.004);
    CHECK(other > 0.03);
    /* the mip estimate sees the transform: about log2(sqrt(2 × 3)) = 1.3 levels coarser */
    double ma = 0, mc = 0;
    int n = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; i++)
      if (fa.mip.data[i] >= 0 && fc.mip.data[i] >= 0) ma += fa.mip.data[i], mc += fc.mip.data[i], n++;
    CHECK(n > 0);
    if (n) CHECK_NEAR((ma - mc) / n, 0.5 * log2(sx * sy), 0.35);
  }
  jnd_frame_free(&fa);
  jnd_frame_free(&fb);
  jnd_frame_free(&fc);
  jnd_scene_free(a);
  jnd_scene_free(b);
  jnd_scene_free(c);
}

TEST(views_json_is_parsed_and_impossible_cameras_are_refused) {
  const double centre[3] = {0, 1, 0};
  jnd_view *v = NULL;
  int n = 0;
  const char *ok = "{\"views\": [{\"eye\": [0, 1, 5]}, {\"camera\": {\"eye\": [3, 1, 0], \"fov\": 30},"
                   " \"prev\": {\"eye\": [3, 1, 0.1]}, \"lights\": [{\"type\": \"point\", \"position\": [1, 2, 3]}]}]}";
  CHECK_OK(jnd_views_parse("ok.json", ok, strlen(ok), centre, 45, &v, &n));
  CHECK(n == 2);
  if (v && n == 2) {
    CHECK(v[0].camera.target[1] == 1 && v[0].camera.fov_y_deg == 45 && v[0].nlights == -1 && !v[0].has_prev);
    CHECK(v[1].camera.fov_y_deg == 30 && v[1].has_prev && v[1].nlights == 1);
    CHECK(v[1].lights[0].type == JND_LIGHT_POINT && v[1].lights[0].intensity == 1);
  }
  free(v);
  const char *bad[] = {
      "{\"views\": []}",                                             /* no views */
      "[{\"eye\": [0, 1, 0]}]",                                      /* eye on the target (the centre) */
      "[{\"eye\": [0, 5, 0]}]",                                      /* looking along up */
      "[{\"eye\": [0, 0, 5], \"up\": [0, 0, 0]}]",                   /* no up */
      "[{\"eye\": [0, 0, 5], \"znear\": 2, \"zfar\": 1}]",           /* clip planes */
      "[{\"eye\": [0, 0, 5], \"fov\": 180}]",                        /* field of view */
      "[{\"eye\": [0, 0]}]",                                         /* not a vector */
      "[{\"eye\": [0, 0, 5], \"lights\": [{\"type\": \"area\"}]}]",  /* unknown light */
      "not json",
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    v = NULL;
    n = 7;
    CHECK_STATUS(jnd_views_parse("bad.json", bad[i], strlen(bad[i]), centre, 45, &v, &n), JND_ERR_FORMAT);
    CHECK(v == NULL && n == 0 && strstr(jnd_last_error(), "bad.json") != NULL);
  }
  /* nine lights: one more than JND_MAX_LIGHTS */
  char many[2048] = "[{\"eye\": [0, 0, 5], \"lights\": [";
  for (int i = 0; i < 9; i++) strcat(many, i ? ", {\"type\": \"directional\"}" : "{\"type\": \"directional\"}");
  strcat(many, "]}]");
  CHECK_STATUS(jnd_views_parse("many.json", many, strlen(many), centre, 45, &v, &n), JND_ERR_FORMAT);
}

static void close_renderer(void) {
  jnd_renderer_free(renderer());
}

RUN_TESTS(the_vectorised_srgb_curve_is_the_scalar_one, views_json_is_parsed_and_impossible_cameras_are_refused, gltf_texture_transform_is_applied_as_its_extension_defines, builtin_maps_are_addressable_by_material_and_slot, resampling_a_constant_map_keeps_it_constant,
          colour_maps_are_filtered_in_linear_light, resampled_normal_maps_hold_unit_vectors,
          broken_files_are_refused_as_malformed, truncated_glb_is_refused,
          obj_with_missing_texture_falls_back_to_the_factor_with_a_warning, object_fills_the_coverage_asked_for,
          normal_map_changes_shading, environment_changes_the_specular_response,
          an_environment_file_rewritten_between_renderers_lights_the_next_one, rendering_is_deterministic,
          restoring_a_map_restores_the_image_exactly, mip_level_rises_by_one_per_halving_of_size_on_screen,
          motion_vectors_follow_the_camera, view_sampling_is_deterministic_and_seeded,
          golden_builtin_frame_matches, golden_box_textured_frame_matches,
          normal_maps_follow_the_gltf_tangent_convention, mirrored_uvs_get_their_own_tangent_frames,
          blended_surfaces_cover_by_their_opacity,
          point_and_spot_lights_light_the_side_they_are_on, maps_keep_their_texture_coordinate_set,
          assimp_test_models_render_with_plausible_coverage,
          close_renderer)
