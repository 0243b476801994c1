/* Cameras and lights: matrices, and deterministic sampling of views around
 * an object. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "render/render.h"
#include "scene/scene.h"

void jnd_mat4_identity(double m[16]) {
  memset(m, 0, 16 * sizeof *m);
  m[0] = m[5] = m[10] = m[15] = 1;
}

void jnd_mat4_mul(const double a[16], const double b[16], double out[16]) {
  double r[16];
  for (int c = 0; c < 4; c++)
    for (int rr = 0; rr < 4; rr++) {
      double s = 0;
      for (int k = 0; k < 4; k++) s += a[k * 4 + rr] * b[c * 4 + k];
      r[c * 4 + rr] = s;
    }
  memcpy(out, r, sizeof r);
}

static void normalize3(double v[3]) {
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (int k = 0; k < 3; k++) v[k] /= l;
}
static void cross3(const double a[3], const double b[3], double o[3]) {
  o[0] = a[1] * b[2] - a[2] * b[1];
  o[1] = a[2] * b[0] - a[0] * b[2];
  o[2] = a[0] * b[1] - a[1] * b[0];
}

void jnd_mat4_look_at(const double eye[3], const double target[3], const double up[3], double out[16]) {
  double f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]}, s[3], u[3];
  normalize3(f);
  cross3(f, up, s);
  if (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] < 1e-12) {   /* looking along up */
    double alt[3] = {0, 0, 1};
    cross3(f, alt, s);
  }
  normalize3(s);
  cross3(s, f, u);
  jnd_mat4_identity(out);
  for (int k = 0; k < 3; k++) {
    out[k * 4 + 0] = s[k];
    out[k * 4 + 1] = u[k];
    out[k * 4 + 2] = -f[k];
  }
  out[12] = -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
  out[13] = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
  out[14] = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
}

void jnd_mat4_perspective(double fov_y_deg, double aspect, double zn, double zf, double out[16]) {
  double f = 1.0 / tan(fov_y_deg * M_PI / 360);
  memset(out, 0, 16 * sizeof *out);
  out[0] = f / aspect;
  out[5] = f;
  out[10] = (zf + zn) / (zn - zf);
  out[11] = -1;
  out[14] = 2 * zf * zn / (zn - zf);
}

int jnd_mat4_invert(const double m[16], double out[16]) {
  double a[4][8];
  for (int r = 0; r < 4; r++)
    for (int c = 0; c < 4; c++) {
      a[r][c] = m[c * 4 + r];
      a[r][c + 4] = r == c;
    }
  for (int c = 0; c < 4; c++) {
    int piv = c;
    for (int r = c + 1; r < 4; r++)
      if (fabs(a[r][c]) > fabs(a[piv][c])) piv = r;
    if (fabs(a[piv][c]) < 1e-300) return 0;
    if (piv != c)
      for (int k = 0; k < 8; k++) {
        double t = a[c][k];
        a[c][k] = a[piv][k];
        a[piv][k] = t;
      }
    double d = a[c][c];
    for (int k = 0; k < 8; k++) a[c][k] /= d;
    for (int r = 0; r < 4; r++)
      if (r != c) {
        double f = a[r][c];
        for (int k = 0; k < 8; k++) a[r][k] -= f * a[c][k];
      }
  }
  for (int r = 0; r < 4; r++)
    for (int c = 0; c < 4; c++) out[c * 4 + r] = a[r][c + 4];
  return 1;
}

void jnd_mat3_normal(const double m[16], double out[9]) {
  double inv[16];
  if (!jnd_mat4_invert(m, inv)) jnd_mat4_identity(inv);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) out[c * 3 + r] = inv[r * 4 + c];   /* transpose */
}

void jnd_view_defaults(jnd_view *v) {
  memset(v, 0, sizeof *v);
  v->camera.eye[2] = 3;
  v->camera.up[1] = 1;
  v->camera.fov_y_deg = 45;
  jnd_mat4_identity(v->model);
  jnd_mat4_identity(v->prev_model);
  v->prev_camera = v->camera;
  v->env_intensity = 1;
  v->exposure = 1;
  v->outputs = JND_OUT_COLOR;
}

void jnd_view_sampling_defaults(jnd_view_sampling *p) {
  memset(p, 0, sizeof *p);
  p->count = 8;
  p->seed = 1;
  p->coverage = 0.8;
  p->fov_y_deg = 45;
  p->aspect = 1;
  p->min_elevation_deg = NAN;   /* automatic: JND_ELEVATION_MIN_DEG, or above the ground */
  p->max_elevation_deg = JND_ELEVATION_MAX_DEG;
  p->lights = 1;
  p->light_intensity = 2;
}

double jnd_camera_distance_for_coverage(double radius, double coverage, double fov_y_deg) {
  /* a sphere at distance d subtends a half-angle asin(r/d); its image spans
   * tan(asin(r/d)) / tan(fov/2) of the half-height */
  double t = coverage * tan(fov_y_deg * M_PI / 360);
  return radius / sin(atan(t));
}

/* The band of elevations sampled views come from: from 60° below the
 * horizon to 75° above it (a player rarely looks straight down on an object
 * or from right under it); with a ground plane, from 10° above the ground's
 * horizon, since nobody looks at it from below the floor. */
#define JND_ELEVATION_MIN_GROUND_DEG 10.0

jnd_status jnd_views_sample(const jnd_scene *scene, const jnd_view_sampling *p, jnd_view *views) {
  if (p->count < 1) return jnd_fail(JND_ERR_ARG, "views: count %d is not positive", p->count);
  if (!(p->fov_y_deg > 0 && p->fov_y_deg < 180))
    return jnd_fail(JND_ERR_ARG, "views: field of view %g is outside (0, 180)", p->fov_y_deg);
  if (p->distance <= 0 && !(p->coverage > 0 && p->coverage <= 10))
    return jnd_fail(JND_ERR_ARG, "views: coverage %g is outside (0, 10]", p->coverage);
  if (p->lights < 0 || p->lights > JND_MAX_LIGHTS)
    return jnd_fail(JND_ERR_ARG, "views: %d lights (at most %d)", p->lights, JND_MAX_LIGHTS);
  double c[3], r, call[3], rall;
  int ground;
  jnd_scene_subject_bounds(scene, c, &r, &ground);
  jnd_scene_bounds(scene, call, &rall);
  double el0 = isnan(p->min_elevation_deg) ? (ground >= 0 ? JND_ELEVATION_MIN_GROUND_DEG : JND_ELEVATION_MIN_DEG)
                                           : p->min_elevation_deg;
  double el1 = isnan(p->max_elevation_deg) ? JND_ELEVATION_MAX_DEG : p->max_elevation_deg;
  if (!(el0 >= -90 && el1 <= 90 && el0 <= el1))
    return jnd_fail(JND_ERR_ARG, "views: elevations %g..%g are not within -90..90 and in order", el0, el1);
  double dist = p->distance > 0 ? p->distance : jnd_camera_distance_for_coverage(r, p->coverage, p->fov_y_deg);
  if (dist <= r * 1.0001 && p->distance <= 0) dist = r * 1.0001;
  jnd_rng rng;
  jnd_rng_seed(&rng, p->seed);
  double rot = 2 * M_PI * jnd_rng_uniform(&rng);
  /* Fibonacci spiral on the band of elevations: equal areas per view */
  double z0 = sin(el0 * M_PI / 180), z1 = sin(el1 * M_PI / 180);
  const double golden = M_PI * (3 - sqrt(5.0));
  for (int i = 0; i < p->count; i++) {
    jnd_view *v = &views[i];
    jnd_view_defaults(v);
    double y = z1 + (z0 - z1) * (i + 0.5) / p->count;
    double rr = sqrt(fmax(0, 1 - y * y)), az = rot + golden * i;
    double d[3] = {rr * sin(az), y, rr * cos(az)};
    for (int k = 0; k < 3; k++) {
      v->camera.eye[k] = c[k] + dist * d[k];
      v->camera.target[k] = c[k];
    }
    v->camera.up[0] = v->camera.up[2] = 0;
    v->camera.up[1] = 1;
    v->camera.fov_y_deg = p->fov_y_deg;
    v->camera.znear = fmax(dist - 1.5 * r, dist * 1e-3);
    v->camera.zfar = dist + 1.5 * r;
    if (ground >= 0) {   /* the floor runs towards the camera and far behind the object */
      double e = 0;
      for (int k = 0; k < 3; k++) e += (v->camera.eye[k] - call[k]) * (v->camera.eye[k] - call[k]);
      v->camera.znear = dist * 0.02;
      v->camera.zfar = sqrt(e) + 1.01 * rall;
    }
    v->prev_camera = v->camera;
    v->nlights = p->lights;
    for (int l = 0; l < p->lights; l++) {
      /* from above (elevation 20–70°), within ±100° of the camera's azimuth */
      double el = (20 + 50 * jnd_rng_uniform(&rng)) * M_PI / 180;
      double la = az + (jnd_rng_uniform(&rng) * 200 - 100) * M_PI / 180;
      jnd_light *L = &v->lights[l];
      memset(L, 0, sizeof *L);
      L->type = JND_LIGHT_DIRECTIONAL;
      L->direction[0] = -cos(el) * sin(la);
      L->direction[1] = -sin(el);
      L->direction[2] = -cos(el) * cos(la);
      L->color[0] = L->color[1] = L->color[2] = 1;
      L->intensity = p->light_intensity;
    }
  }
  return JND_OK;
}

void jnd_view_set_defaults(jnd_view_set *vs) {
  memset(vs, 0, sizeof *vs);
  jnd_view_sampling_defaults(&vs->sampling);
  jnd_renderer_defaults(&vs->render);
}

jnd_status jnd_view_set_make(const jnd_scene *scene, const jnd_view_set *vs, jnd_view **out, int *count) {
  *out = NULL;
  *count = 0;
  if (!vs->cameras && vs->cameras_path) {   /* the cameras file, then as explicit cameras */
    jnd_view *cams = NULL;
    int n = 0;
    jnd_status st = jnd_views_read(vs->cameras_path, scene, vs->sampling.fov_y_deg, &cams, &n);
    if (st != JND_OK) return st;
    jnd_view_set with = *vs;
    with.cameras = cams;
    with.ncameras = n;
    st = jnd_view_set_make(scene, &with, out, count);
    free(cams);
    return st;
  }
  if (vs->render.width < 1 || vs->render.height < 1)
    return jnd_fail(JND_ERR_ARG, "views: image size %d × %d", vs->render.width, vs->render.height);
  jnd_view_sampling s = vs->sampling;
  s.aspect = (double)vs->render.width / vs->render.height;
  int n = vs->cameras ? vs->ncameras : s.count;
  if (n < 1) return jnd_fail(JND_ERR_ARG, "views: no views (%d)", n);
  jnd_view *v = jnd_calloc((size_t)n, sizeof *v);
  if (!v) return JND_ERR_NOMEM;
  s.count = n;
  jnd_status st = jnd_views_sample(scene, &s, v);
  if (st == JND_OK && vs->cameras) {
    /* explicit cameras; those without lights get the sampled ones of the same index */
    for (int i = 0; i < n; i++) {
      jnd_view sampled = v[i];
      v[i] = vs->cameras[i];
      if (v[i].nlights < 0) {
        v[i].nlights = sampled.nlights;
        memcpy(v[i].lights, sampled.lights, sizeof v[i].lights);
      }
    }
  }
  if (st != JND_OK) {
    free(v);
    return st;
  }
  *out = v;
  *count = n;
  return JND_OK;
}

/* ---- views from JSON (jnd render --cameras) ---- */

static int json_vec3(const cJSON *o, const char *key, double v[3]) {
  const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, key);
  if (!a) return 0;
  if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3) return -1;
  for (int k = 0; k < 3; k++) {
    const cJSON *x = cJSON_GetArrayItem(a, k);
    if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) return -1;
    v[k] = x->valuedouble;
  }
  return 1;
}

static double json_num(const cJSON *o, const char *key, double dflt) {
  const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsNumber(x) && isfinite(x->valuedouble) ? x->valuedouble : dflt;
}

/* A camera from {"eye", "target", "up", "fov_y_deg"|"fov", "znear", "zfar"};
 * 0 when it cannot make a view matrix (eye on the target, up along the line
 * of sight) or a projection (field of view, clip planes). */
static int camera_from_json(const cJSON *o, const double centre[3], double fov, jnd_camera *c) {
  memset(c, 0, sizeof *c);
  for (int k = 0; k < 3; k++) c->target[k] = centre[k];
  c->up[1] = 1;
  if (!cJSON_IsObject(o) || json_vec3(o, "eye", c->eye) != 1) return 0;
  if (json_vec3(o, "target", c->target) < 0 || json_vec3(o, "up", c->up) < 0) return 0;
  c->fov_y_deg = json_num(o, "fov_y_deg", json_num(o, "fov", fov));
  c->znear = json_num(o, "znear", 0);
  c->zfar = json_num(o, "zfar", 0);
  double d[3], x[3];
  for (int k = 0; k < 3; k++) d[k] = c->target[k] - c->eye[k];
  x[0] = d[1] * c->up[2] - d[2] * c->up[1];
  x[1] = d[2] * c->up[0] - d[0] * c->up[2];
  x[2] = d[0] * c->up[1] - d[1] * c->up[0];
  double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], uu = c->up[0] * c->up[0] + c->up[1] * c->up[1] + c->up[2] * c->up[2];
  double xx = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
  if (!(dd > 0 && isfinite(dd) && uu > 0 && isfinite(uu) && xx > 1e-12 * dd * uu)) return 0;
  if (c->znear < 0 || c->zfar < 0 || (c->zfar > 0 && c->zfar <= c->znear)) return 0;
  return c->fov_y_deg > 0 && c->fov_y_deg < 180;
}

static int light_from_json(const cJSON *o, jnd_light *L) {
  memset(L, 0, sizeof *L);
  const cJSON *t = cJSON_GetObjectItemCaseSensitive(o, "type");
  if (!cJSON_IsString(t)) return 0;
  if (strcmp(t->valuestring, "directional") == 0) L->type = JND_LIGHT_DIRECTIONAL;
  else if (strcmp(t->valuestring, "point") == 0) L->type = JND_LIGHT_POINT;
  else if (strcmp(t->valuestring, "spot") == 0) L->type = JND_LIGHT_SPOT;
  else return 0;
  L->color[0] = L->color[1] = L->color[2] = 1;
  if (json_vec3(o, "position", L->position) < 0 || json_vec3(o, "direction", L->direction) < 0 ||
      json_vec3(o, "color", L->color) < 0)
    return 0;
  L->intensity = json_num(o, "intensity", 1);
  L->range = json_num(o, "range", 0);
  L->inner_deg = json_num(o, "inner_deg", 20);
  L->outer_deg = json_num(o, "outer_deg", 30);
  return 1;
}

jnd_status jnd_views_parse(const char *name, const char *text, size_t n, const double centre[3], double fov_y_deg,
                           jnd_view **out, int *count) {
  *out = NULL;
  *count = 0;
  cJSON *root = cJSON_ParseWithLength(text, n);
  const cJSON *list = root;
  if (cJSON_IsObject(root)) list = cJSON_GetObjectItemCaseSensitive(root, "views");
  if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) < 1) {
    cJSON_Delete(root);
    return jnd_fail(JND_ERR_FORMAT, "%s: not a JSON list of cameras (or {\"views\": [...]})", name);
  }
  int nv = cJSON_GetArraySize(list);
  jnd_view *views = jnd_calloc((size_t)nv, sizeof *views);
  if (!views) {
    cJSON_Delete(root);
    return JND_ERR_NOMEM;
  }
  jnd_status s = JND_OK;
  for (int i = 0; i < nv && s == JND_OK; i++) {
    const cJSON *e = cJSON_GetArrayItem(list, i);
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(e, "camera");
    jnd_view *v = &views[i];
    jnd_view_defaults(v);
    if (!camera_from_json(cam ? cam : e, centre, fov_y_deg, &v->camera)) {
      s = jnd_fail(JND_ERR_FORMAT, "%s: camera %d is invalid", name, i);
      break;
    }
    v->prev_camera = v->camera;
    const cJSON *prev = cJSON_GetObjectItemCaseSensitive(e, "prev");
    if (!prev) prev = cJSON_GetObjectItemCaseSensitive(e, "prev_camera");
    if (prev) {
      if (!camera_from_json(prev, centre, fov_y_deg, &v->prev_camera)) {
        s = jnd_fail(JND_ERR_FORMAT, "%s: camera %d's previous camera is invalid", name, i);
        break;
      }
      v->has_prev = 1;
    }
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(e, "lights");
    v->nlights = -1; /* not given: the caller fills them */
    if (cJSON_IsArray(lights)) {
      v->nlights = 0;
      const cJSON *l;
      cJSON_ArrayForEach(l, lights) {
        if (v->nlights >= JND_MAX_LIGHTS || !light_from_json(l, &v->lights[v->nlights])) {
          s = jnd_fail(JND_ERR_FORMAT, "%s: camera %d: a light is invalid (or more than %d)", name, i,
                       JND_MAX_LIGHTS);
          break;
        }
        v->nlights++;
      }
    }
  }
  cJSON_Delete(root);
  if (s != JND_OK) {
    free(views);
    return s;
  }
  *out = views;
  *count = nv;
  return JND_OK;
}

jnd_status jnd_views_read(const char *path, const jnd_scene *scene, double fov_y_deg, jnd_view **out, int *count) {
  unsigned char *text = NULL;
  size_t n = 0;
  jnd_status st = jnd_read_file(path, (size_t)64 << 20, &text, &n);
  if (st != JND_OK) return st;
  double centre[3], radius;
  jnd_scene_subject_bounds(scene, centre, &radius, NULL);
  st = jnd_views_parse(path, (const char *)text, n, centre, fov_y_deg, out, count);
  free(text);
  return st;
}
