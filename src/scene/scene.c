/* The scene object: meshes, materials and addressable texture maps. */
#include <math.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"

static const char *const slot_names[JND_MAP_SLOTS] = {
    "baseColor", "metallicRoughness", "normal", "occlusion", "emissive"};

const char *jnd_map_slot_name(jnd_map_slot slot) {
  return (unsigned)slot < JND_MAP_SLOTS ? slot_names[slot] : "?";
}

jnd_map_kind jnd_map_slot_kind(jnd_map_slot slot) {
  switch (slot) {
    case JND_MAP_BASE_COLOR:
    case JND_MAP_EMISSIVE: return JND_MAP_KIND_COLOR;
    case JND_MAP_NORMAL: return JND_MAP_KIND_NORMAL;
    default: return JND_MAP_KIND_DATA;
  }
}

/* A process-wide counter so that a renderer can tell a map (or a scene) it
 * uploaded from a new one that happens to reuse the same memory. It is the
 * only shared state and is atomic. */
static _Atomic uint64_t version_counter = 1;
uint64_t jnd_scene_next_version(void) { return atomic_fetch_add(&version_counter, 1); }

jnd_scene *jnd_scene_new(const char *path) {
  jnd_scene *s = jnd_calloc(1, sizeof *s);
  if (!s) return NULL;
  snprintf(s->path, sizeof s->path, "%s", path);
  s->id = jnd_scene_next_version();
  s->ground_mesh = -1;
  return s;
}

jnd_scene *jnd_scene_twin(const jnd_scene *s) {
  jnd_scene *t = jnd_alloc(1, sizeof *t);
  jnd_mesh *m = jnd_alloc(s->nmeshes ? (size_t)s->nmeshes : 1, sizeof *m);
  if (!t || !m) {
    free(t);
    free(m);
    return NULL;
  }
  *t = *s;
  memcpy(m, s->meshes, (size_t)s->nmeshes * sizeof *m);
  t->meshes = m;
  t->id = jnd_scene_next_version();   /* a renderer tells it from s */
  t->twin_of = s;
  return t;
}

void jnd_scene_free(jnd_scene *s) {
  if (!s) return;
  if (s->twin_of) {   /* the rest is its original's */
    free(s->meshes);
    free(s);
    return;
  }
  if (s->nlod > 0) {
    jnd_scene_lod_free(s);   /* the levels own every mesh array */
  } else {
    for (int i = 0; i < s->nmeshes; i++) {
      free(s->meshes[i].vertices);
      free(s->meshes[i].indices);
    }
  }
  for (int i = 0; i < s->nmaps; i++) {
    jnd_image_free(&s->maps[i].orig);
    jnd_image_free(&s->maps[i].now);
    free(s->maps[i].source);
  }
  for (int i = 0; i < s->nwarnings; i++) free(s->warnings[i]);
  free(s->warnings);
  free(s->meshes);
  free(s->materials);
  free(s->maps);
  free(s);
}

jnd_status jnd_scene_add_warning(jnd_scene *s, const char *fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  char **w = realloc(s->warnings, (size_t)(s->nwarnings + 1) * sizeof *w);
  if (!w) return jnd_fail(JND_ERR_NOMEM, "out of memory");
  s->warnings = w;
  if (!(w[s->nwarnings] = strdup(buf))) return jnd_fail(JND_ERR_NOMEM, "out of memory");
  s->nwarnings++;
  return JND_OK;
}

void jnd_material_defaults(jnd_material *m, const char *name) {
  memset(m, 0, sizeof *m);
  snprintf(m->name, sizeof m->name, "%s", name);
  for (int i = 0; i < 4; i++) m->base_color[i] = 1;
  m->metallic = 1;   /* glTF 2.0 defaults */
  m->roughness = 1;
  m->normal_scale = 1;
  m->occlusion_strength = 1;
  m->alpha_cutoff = 0.5f;
  for (int i = 0; i < JND_MAP_SLOTS; i++) m->map[i] = -1;
}

int jnd_scene_add_map(jnd_scene *s, int material, jnd_map_slot slot, jnd_image *img) {
  jnd_map *m = realloc(s->maps, (size_t)(s->nmaps + 1) * sizeof *m);
  if (!m) {
    jnd_image_free(img);
    jnd_fail(JND_ERR_NOMEM, "out of memory");
    return -1;
  }
  s->maps = m;
  jnd_map *mp = &m[s->nmaps];
  memset(mp, 0, sizeof *mp);
  mp->orig = *img;
  memset(img, 0, sizeof *img);
  mp->uvxf[0] = mp->uvxf[4] = 1.0f; /* no texture transform */
  mp->version = jnd_scene_next_version();
  mp->image = s->nmaps;
  s->materials[material].map[slot] = s->nmaps;
  return s->nmaps++;
}

const char *jnd_scene_path(const jnd_scene *s) { return s->path; }
int jnd_scene_mesh_count(const jnd_scene *s) { return s->nmeshes; }
int jnd_scene_material_count(const jnd_scene *s) { return s->nmaterials; }

size_t jnd_scene_triangle_count(const jnd_scene *s) {
  size_t n = 0;
  for (int i = 0; i < s->nmeshes; i++) n += s->meshes[i].ntris;
  return n;
}

const char *jnd_scene_material_name(const jnd_scene *s, int material) {
  return material >= 0 && material < s->nmaterials ? s->materials[material].name : NULL;
}

void jnd_scene_bounds(const jnd_scene *s, double centre[3], double *radius) {
  for (int k = 0; k < 3; k++) centre[k] = s->centre[k];
  *radius = s->radius;
}

int jnd_scene_warning_count(const jnd_scene *s) { return s->nwarnings; }
const char *jnd_scene_warning(const jnd_scene *s, int i) {
  return i >= 0 && i < s->nwarnings ? s->warnings[i] : "";
}

static void sub3(const float *a, const float *b, double *o);
static double dot3(const double *a, const double *b);

/* The sphere around the vertices of the meshes with use[i] set (all when
 * use is NULL): the centre of their box, the radius to the farthest. 0 when
 * there are none. */
static int sphere_of(const jnd_scene *s, const unsigned char *use, double centre[3], double *radius) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < s->nmeshes; i++) {
    if (use && !use[i]) continue;
    for (size_t v = 0; v < s->meshes[i].nverts; v++) {
      const float *p = s->meshes[i].vertices + v * JND_VTX_FLOATS;
      for (int k = 0; k < 3; k++) {
        if (p[k] < lo[k]) lo[k] = p[k];
        if (p[k] > hi[k]) hi[k] = p[k];
      }
    }
  }
  if (!(lo[0] <= hi[0])) return 0;
  for (int k = 0; k < 3; k++) centre[k] = 0.5 * (lo[k] + hi[k]);
  double r2 = 0;
  for (int i = 0; i < s->nmeshes; i++) {
    if (use && !use[i]) continue;
    for (size_t v = 0; v < s->meshes[i].nverts; v++) {
      const float *p = s->meshes[i].vertices + v * JND_VTX_FLOATS;
      double d2 = 0;
      for (int k = 0; k < 3; k++) d2 += (p[k] - centre[k]) * (p[k] - centre[k]);
      if (d2 > r2) r2 = d2;
    }
  }
  *radius = r2 > 0 ? sqrt(r2) : 1;
  return 1;
}

/* A ground plane: a mesh whose area faces straight up or down (99%), whose
 * heights lie within 0.1% of the scene's size of each other and at or below
 * every other mesh, and whose horizontal extent covers all the others'. The
 * lowest such mesh, or -1. Only with at least one other mesh. */
static int find_ground(const jnd_scene *s) {
  if (s->nmeshes < 2) return -1;
  double eps = 1e-3 * 2 * s->radius;
  int best = -1;
  double best_y = INFINITY;
  for (int i = 0; i < s->nmeshes; i++) {
    const jnd_mesh *m = &s->meshes[i];
    double flat = 0, all = 0, ylo = INFINITY, yhi = -INFINITY, box[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
    for (size_t t = 0; t < m->ntris; t++) {
      const float *a = m->vertices + (size_t)m->indices[3 * t] * JND_VTX_FLOATS;
      const float *b = m->vertices + (size_t)m->indices[3 * t + 1] * JND_VTX_FLOATS;
      const float *c = m->vertices + (size_t)m->indices[3 * t + 2] * JND_VTX_FLOATS;
      double e1[3], e2[3];
      sub3(b, a, e1);
      sub3(c, a, e2);
      double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      double area = sqrt(dot3(n, n));
      all += area;
      if (area > 0 && fabs(n[1]) > 0.999 * area) flat += area;
    }
    for (size_t v = 0; v < m->nverts; v++) {
      const float *p = m->vertices + v * JND_VTX_FLOATS;
      ylo = fmin(ylo, p[1]);
      yhi = fmax(yhi, p[1]);
      box[0] = fmin(box[0], p[0]), box[1] = fmax(box[1], p[0]);
      box[2] = fmin(box[2], p[2]), box[3] = fmax(box[3], p[2]);
    }
    if (!(all > 0) || flat < 0.99 * all || yhi - ylo > eps || !(ylo < best_y)) continue;
    int ok = 1;
    for (int j = 0; j < s->nmeshes && ok; j++) {
      if (j == i) continue;
      for (size_t v = 0; v < s->meshes[j].nverts && ok; v++) {
        const float *p = s->meshes[j].vertices + v * JND_VTX_FLOATS;
        ok = p[1] >= yhi - eps && p[0] >= box[0] && p[0] <= box[1] && p[2] >= box[2] && p[2] <= box[3];
      }
    }
    if (ok) best = i, best_y = ylo;
  }
  return best;
}

void jnd_scene_compute_bounds(jnd_scene *s) {
  if (!sphere_of(s, NULL, s->centre, &s->radius)) {
    s->centre[0] = s->centre[1] = s->centre[2] = 0;
    s->radius = 1;
  }
  memcpy(s->subject_centre, s->centre, sizeof s->centre);
  s->subject_radius = s->radius;
  s->ground_mesh = find_ground(s);
  if (s->ground_mesh < 0) return;
  unsigned char *use = calloc((size_t)s->nmeshes, 1);
  if (!use) {
    s->ground_mesh = -1;
    return;
  }
  for (int i = 0; i < s->nmeshes; i++) use[i] = i != s->ground_mesh;
  if (!sphere_of(s, use, s->subject_centre, &s->subject_radius)) s->ground_mesh = -1;
  free(use);
}

void jnd_scene_subject_bounds(const jnd_scene *s, double centre[3], double *radius, int *ground) {
  for (int k = 0; k < 3; k++) centre[k] = s->subject_centre[k];
  *radius = s->subject_radius;
  if (ground) {
    *ground = s->ground_mesh >= 0 ? s->meshes[s->ground_mesh].material : -1;
    /* a material the ground shares with the subject is no ground material */
    for (int i = 0; i < s->nmeshes && *ground >= 0; i++)
      if (i != s->ground_mesh && s->meshes[i].material == *ground) *ground = -1;
  }
}

/* ---- tangents ---- */

static void sub3(const float *a, const float *b, double *o) {
  for (int k = 0; k < 3; k++) o[k] = (double)a[k] - b[k];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The handedness of triangle t's uv mapping: +1, −1, or 0 when degenerate. */
static int uv_handedness(const jnd_mesh *m, size_t t) {
  const uint32_t *ix = m->indices + 3 * t;
  const float *a = m->vertices + (size_t)ix[0] * JND_VTX_FLOATS, *b = m->vertices + (size_t)ix[1] * JND_VTX_FLOATS,
              *c = m->vertices + (size_t)ix[2] * JND_VTX_FLOATS;
  double det = ((double)b[10] - a[10]) * -((double)c[11] - a[11]) - ((double)c[10] - a[10]) * -((double)b[11] - a[11]);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

/* Where the uv mapping is mirrored (a symmetric model sharing one half of a
 * texture), vertices on the mirror line are used by triangles of both
 * handedness; MikkTSpace gives each side its own tangent frame, so such a
 * vertex is duplicated for its left-handed triangles. */
static void split_mirrored_vertices(jnd_mesh *m) {
  unsigned char *seen = calloc(m->nverts, 1);   /* bit 0: right-handed use, bit 1: left-handed */
  if (!seen) return;
  for (size_t t = 0; t < m->ntris; t++) {
    int h = uv_handedness(m, t);
    for (int k = 0; k < 3 && h; k++) seen[m->indices[3 * t + k]] |= h > 0 ? 1 : 2;
  }
  size_t extra = 0;
  for (size_t v = 0; v < m->nverts; v++) extra += seen[v] == 3;
  if (extra == 0 || m->nverts + extra > UINT32_MAX) {
    free(seen);
    return;
  }
  float *nv = realloc(m->vertices, (m->nverts + extra) * JND_VTX_FLOATS * sizeof(float));
  uint32_t *dup = malloc(m->nverts * sizeof *dup);
  if (!nv || !dup) {
    if (nv) m->vertices = nv;
    free(seen);
    free(dup);
    return;
  }
  m->vertices = nv;
  size_t next = m->nverts;
  for (size_t v = 0; v < m->nverts; v++) {
    dup[v] = (uint32_t)v;
    if (seen[v] != 3) continue;
    memcpy(nv + next * JND_VTX_FLOATS, nv + v * JND_VTX_FLOATS, JND_VTX_FLOATS * sizeof(float));
    dup[v] = (uint32_t)next++;
  }
  for (size_t t = 0; t < m->ntris; t++)
    if (uv_handedness(m, t) < 0)
      for (int k = 0; k < 3; k++) m->indices[3 * t + k] = dup[m->indices[3 * t + k]];
  m->nverts = next;
  free(seen);
  free(dup);
}

void jnd_mesh_compute_tangents(jnd_mesh *m) {
  split_mirrored_vertices(m);
  double *acc = calloc(m->nverts * 6, sizeof *acc);   /* tangent xyz, bitangent xyz */
  if (!acc) return;
  for (size_t t = 0; t < m->ntris; t++) {
    const uint32_t *ix = m->indices + 3 * t;
    const float *v[3] = {m->vertices + (size_t)ix[0] * JND_VTX_FLOATS,
                         m->vertices + (size_t)ix[1] * JND_VTX_FLOATS,
                         m->vertices + (size_t)ix[2] * JND_VTX_FLOATS};
    double e1[3], e2[3];
    sub3(v[1], v[0], e1);
    sub3(v[2], v[0], e2);
    /* v runs down the image (glTF's convention); the bitangent of glTF's
     * tangent space points up the image, so v is negated here. */
    double du1 = (double)v[1][10] - v[0][10], dv1 = -((double)v[1][11] - v[0][11]);
    double du2 = (double)v[2][10] - v[0][10], dv2 = -((double)v[2][11] - v[0][11]);
    double det = du1 * dv2 - du2 * dv1;
    if (fabs(det) < 1e-20) continue;
    double r = 1.0 / det, T[3], B[3];
    for (int k = 0; k < 3; k++) {
      T[k] = (e1[k] * dv2 - e2[k] * dv1) * r;
      B[k] = (e2[k] * du1 - e1[k] * du2) * r;
    }
    /* Weight each corner by its angle, as MikkTSpace does, so that the
     * result does not depend on how a polygon was split into triangles. */
    for (int c = 0; c < 3; c++) {
      double a[3], b[3];
      sub3(v[(c + 1) % 3], v[c], a);
      sub3(v[(c + 2) % 3], v[c], b);
      double la = sqrt(dot3(a, a)), lb = sqrt(dot3(b, b));
      if (la <= 0 || lb <= 0) continue;
      double w = acos(jnd_clampd(dot3(a, b) / (la * lb), -1, 1));
      double *d = acc + (size_t)ix[c] * 6;
      for (int k = 0; k < 3; k++) {
        d[k] += w * T[k];
        d[3 + k] += w * B[k];
      }
    }
  }
  for (size_t i = 0; i < m->nverts; i++) {
    float *v = m->vertices + i * JND_VTX_FLOATS;
    double n[3] = {v[3], v[4], v[5]}, *t = acc + i * 6, *b = t + 3;
    double d = dot3(n, t), o[3];
    for (int k = 0; k < 3; k++) o[k] = t[k] - n[k] * d;
    double l = sqrt(dot3(o, o));
    if (l < 1e-12) {   /* no usable uv gradient: any vector perpendicular to n */
      double a[3] = {fabs(n[0]) < 0.9 ? 1 : 0, fabs(n[0]) < 0.9 ? 0 : 1, 0};
      d = dot3(n, a);
      for (int k = 0; k < 3; k++) o[k] = a[k] - n[k] * d;
      l = sqrt(dot3(o, o));
    }
    double c[3] = {n[1] * o[2] - n[2] * o[1], n[2] * o[0] - n[0] * o[2], n[0] * o[1] - n[1] * o[0]};
    for (int k = 0; k < 3; k++) v[6 + k] = (float)(o[k] / l);
    v[9] = dot3(c, b) < 0 ? -1.0f : 1.0f;
  }
  free(acc);
}

/* ---- maps ---- */

int jnd_scene_map_count(const jnd_scene *s) { return s->nmaps; }

static int map_owner(const jnd_scene *s, int i, int *slot) {
  for (int m = 0; m < s->nmaterials; m++)
    for (int k = 0; k < JND_MAP_SLOTS; k++)
      if (s->materials[m].map[k] == i) {
        *slot = k;
        return m;
      }
  return -1;
}

jnd_status jnd_scene_map_info(const jnd_scene *s, int i, jnd_map_info *info) {
  if (i < 0 || i >= s->nmaps) return jnd_fail(JND_ERR_ARG, "map index %d out of range", i);
  const jnd_map *m = &s->maps[i];
  memset(info, 0, sizeof *info);
  int slot = 0;
  info->material = map_owner(s, i, &slot);
  info->slot = (jnd_map_slot)slot;
  info->kind = jnd_map_slot_kind(info->slot);
  snprintf(info->name, sizeof info->name, "%s/%s",
           info->material >= 0 ? s->materials[info->material].name : "?", slot_names[slot]);
  const jnd_image *use = jnd_map_image(m);
  info->width = use->w;
  info->height = use->h;
  info->orig_width = m->orig.w;
  info->orig_height = m->orig.h;
  info->channels = use->c;
  info->uv_set = m->uv_set;
  info->image = m->image;
  memcpy(info->uv_transform, m->uvxf, sizeof info->uv_transform);
  return JND_OK;
}

int jnd_scene_map_find(const jnd_scene *s, const char *name) {
  const char *slash = strrchr(name, '/');
  if (!slash) return -1;
  size_t n = (size_t)(slash - name);
  for (int m = 0; m < s->nmaterials; m++) {
    if (strlen(s->materials[m].name) != n || strncmp(s->materials[m].name, name, n) != 0) continue;
    for (int k = 0; k < JND_MAP_SLOTS; k++)
      if (strcmp(slot_names[k], slash + 1) == 0) return s->materials[m].map[k];
  }
  return -1;
}

jnd_status jnd_scene_map_resize(jnd_scene *s, int i, int w, int h) {
  if (i < 0 || i >= s->nmaps) return jnd_fail(JND_ERR_ARG, "map index %d out of range", i);
  jnd_map *m = &s->maps[i];
  if (w == m->orig.w && h == m->orig.h) {
    jnd_scene_map_restore(s, i);
    return JND_OK;
  }
  int slot = 0;
  map_owner(s, i, &slot);
  jnd_image out = {0};
  jnd_status st = jnd_resample_map_threads(&m->orig, w, h, jnd_map_slot_kind((jnd_map_slot)slot),
                                           m->wrap_s == JND_WRAP_REPEAT && m->wrap_t == JND_WRAP_REPEAT,
                                           s->threads, &out);
  if (st) return st;
  jnd_image_free(&m->now);
  m->now = out;
  m->version = jnd_scene_next_version();
  return JND_OK;
}

jnd_status jnd_scene_map_set(jnd_scene *s, int i, const jnd_image *img) {
  if (i < 0 || i >= s->nmaps) return jnd_fail(JND_ERR_ARG, "map index %d out of range", i);
  if (!img || !img->data || img->c < 1 || img->c > 4)
    return jnd_fail(JND_ERR_ARG, "a map needs 1-4 channels");
  jnd_image copy = {0};
  jnd_status st = jnd_image_alloc(&copy, img->w, img->h, img->c);
  if (st) return st;
  memcpy(copy.data, img->data, (size_t)img->w * img->h * img->c * sizeof(float));
  jnd_map *m = &s->maps[i];
  jnd_image_free(&m->now);
  m->now = copy;
  m->version = jnd_scene_next_version();
  return JND_OK;
}

void jnd_scene_map_restore(jnd_scene *s, int i) {
  if (i < 0 || i >= s->nmaps) return;
  jnd_map *m = &s->maps[i];
  if (!m->now.data) return;
  jnd_image_free(&m->now);
  m->version = jnd_scene_next_version();
}

jnd_status jnd_scene_map_get(const jnd_scene *s, int i, int orig, jnd_image *out) {
  if (i < 0 || i >= s->nmaps) return jnd_fail(JND_ERR_ARG, "map index %d out of range", i);
  const jnd_image *src = orig ? &s->maps[i].orig : jnd_map_image(&s->maps[i]);
  jnd_status st = jnd_image_alloc(out, src->w, src->h, src->c);
  if (st) return st;
  memcpy(out->data, src->data, (size_t)src->w * src->h * src->c * sizeof(float));
  return JND_OK;
}
