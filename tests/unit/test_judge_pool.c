/* The judge's P is pooled over the object (000 §6: P93 of the object's
 * pixels; docs/judge.md), recomputed here from the JND map and the object
 * mask the judge hands out: a sort, 000 eq. 4 written out, and the pixels
 * of the mask only. The crop around the object holds background (a ground
 * plane, which the mask leaves out, and the sky), whose JND is near 0: a
 * pool over the whole crop gives another P, and the check can tell them
 * apart. Renders are 96², two views. */
#include <math.h>
#include <stdlib.h>

#include "jnd.h"
#include "test.h"

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* 000 §6 by hand: the pct-th percentile of the map's values where mask >
 * 0.5 (all values when mask is NULL), linear between order statistics,
 * then 000 eq. 4, P = 1 − 0.5^(J^β) (the identity calibration) */
static double pooled_by_hand(const jnd_image *map, const jnd_image *mask, double pct, double beta, int *count) {
  size_t n = (size_t)map->w * map->h, k = 0;
  float *v = malloc(n * sizeof *v);
  if (!v) return NAN;
  for (size_t i = 0; i < n; i++)
    if (!mask || mask->data[i] > 0.5f) v[k++] = map->data[i];
  *count = (int)k;
  if (k == 0) {
    free(v);
    return 0;
  }
  qsort(v, k, sizeof *v, cmp_float);
  double r = pct / 100 * (double)(k - 1);
  size_t lo = (size_t)floor(r), hi = lo + 1 < k ? lo + 1 : lo;
  double j = v[lo] + (r - (double)lo) * (v[hi] - v[lo]);
  free(v);
  return 1 - pow(0.5, pow(j, beta));
}

static void small(jnd_judge_params *p) {
  jnd_judge_defaults(p);
  p->views.sampling.count = 2;
  p->views.render.width = p->views.render.height = 96;
  p->views.render.anisotropy = 1;
}

TEST(a_views_p_is_pooled_over_the_object_pixels_only) {
  if (!test_renderer_available()) {
    TEST_SKIP("no OpenGL context");
    return;
  }
  jnd_scene *s = NULL;   /* the builtin on a ground plane (material "ground", no maps) */
  CHECK_OK(jnd_scene_open("builtin:box,ground", 64, &s));
  if (!s) return;
  jnd_judge_params jp;
  small(&jp);
  jnd_judge *j = NULL;
  CHECK_OK(jnd_judge_create(s, &jp, &j));
  int obj = jnd_scene_map_find(s, "builtin/baseColor");   /* the ground has no maps */
  CHECK(obj >= 0);
  if (!j || obj < 0) {
    jnd_scene_free(s);
    return;
  }
  jnd_map_info mi;
  jnd_scene_map_info(s, obj, &mi);
  CHECK_OK(jnd_scene_map_resize(s, obj, mi.width / 2, mi.height / 2));
  double P[2];
  jnd_judgement r;
  CHECK_OK(jnd_judge_eval(j, 0, 2, 0, P, &r));
  for (int v = 0; v < 2; v++) {
    jnd_image map = {0}, mask = {0};
    int crop[4];
    CHECK_OK(jnd_judge_view_images(j, v, &map, NULL, &mask, NULL, crop));
    CHECK(map.w == mask.w && map.h == mask.h && map.w == crop[2] && map.h == crop[3]);
    int on = 0, all = 0;
    double want = pooled_by_hand(&map, &mask, jp.calibration.percentile, jp.calibration.beta, &on);
    double whole = pooled_by_hand(&map, NULL, jp.calibration.percentile, jp.calibration.beta, &all);
    fprintf(stderr, "view %d: P %.6f, over the object %.6f (%d px), over the crop %.6f (%d px)\n", v, P[v], want, on,
            whole, all);
    /* the crop has background around the object, and pooling it in would
     * give another P: the comparison below can tell the two apart */
    CHECK(on > 0 && on < all);
    CHECK(fabs(whole - want) > 1e-3);
    CHECK_NEAR(P[v], want, 1e-5);
    jnd_image_free(&map);
    jnd_image_free(&mask);
  }
  CHECK_NEAR(jp.calibration.percentile, 93, 0);   /* 000 §6: P93 */
  jnd_judge_free(j);
  jnd_scene_free(s);
}

RUN_TESTS(a_views_p_is_pooled_over_the_object_pixels_only)
