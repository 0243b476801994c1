/* The built-in asset: a rounded box (or a sphere), or several of them each
 * with its own material, optionally standing on a ground plane, with
 * procedural PBR materials, so that the renderer and the tasks can run
 * without any file. Also where a model name is resolved: `builtin...` here,
 * anything else a file (jnd_scene_open). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "scene/scene.h"

void jnd_builtin_defaults(jnd_builtin_params *p) {
  memset(p, 0, sizeof *p);
  p->map_size = 2048;
  p->shape = 0;
  p->seed = 1;
  p->parts = 1;
  p->ground = 0;
}

/* ---- tileable value noise ---- */

static double hash01(uint64_t x) { return (double)(jnd_mix64(x) >> 11) * (1.0 / 9007199254740992.0); }

static double lattice(uint64_t seed, int octave, int x, int y) {
  return hash01(seed * 0x9E3779B97F4A7C15ULL + (uint64_t)octave * 0x632BE59BD9B4E019ULL +
                (uint64_t)(uint32_t)x * 0x85EBCA77ULL + (uint64_t)(uint32_t)y * 0xC2B2AE3DULL * 31);
}

/* Value noise with `cells` lattice cells across the tile, at (u, v) in [0,1). */
static double vnoise(uint64_t seed, int octave, int cells, double u, double v) {
  double x = u * cells, y = v * cells;
  int x0 = (int)floor(x), y0 = (int)floor(y);
  double fx = x - x0, fy = y - y0;
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  int xa = ((x0 % cells) + cells) % cells, xb = (xa + 1) % cells;
  int ya = ((y0 % cells) + cells) % cells, yb = (ya + 1) % cells;
  double a = lattice(seed, octave, xa, ya), b = lattice(seed, octave, xb, ya);
  double c = lattice(seed, octave, xa, yb), d = lattice(seed, octave, xb, yb);
  return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy;
}

/* fBm from `cells0` cells up to `max_cells`, gain 0.5; 0..1. */
static double fbm(uint64_t seed, int first_octave, int cells0, int max_cells, double u, double v) {
  double sum = 0, amp = 1, norm = 0;
  int o = first_octave;
  for (int cells = cells0; cells <= max_cells; cells *= 2, o++) {
    sum += amp * vnoise(seed, o, cells, u, v);
    norm += amp;
    amp *= 0.55;
  }
  return norm > 0 ? sum / norm : 0.5;
}

/* The four maps of material mat. variant 0 is the original asset's; others
 * move the finest detail an octave or two coarser (so that parts differ in
 * what their maps can lose) and tint the paints. */
static jnd_status make_maps(jnd_scene *s, int mat, int S, uint64_t seed, int variant) {
  jnd_image base = {0}, mr = {0}, nrm = {0}, occ = {0};
  float *height = jnd_alloc((size_t)S * S, sizeof(float));
  jnd_status st = height ? JND_OK : JND_ERR_NOMEM;
  if (!st) st = jnd_image_alloc(&base, S, S, 3);
  if (!st) st = jnd_image_alloc(&mr, S, S, 3);
  if (!st) st = jnd_image_alloc(&nrm, S, S, 3);
  if (!st) st = jnd_image_alloc(&occ, S, S, 1);
  if (st) {
    free(height);
    jnd_image_free(&base);
    jnd_image_free(&mr);
    jnd_image_free(&nrm);
    jnd_image_free(&occ);
    return st;
  }
  size_t P = (size_t)S * S;
  int fine = S / (4 << (variant % 3)) > 8 ? S / (4 << (variant % 3)) : 8;   /* finest octave: a period of 4 pixels */
  double tint = 0.12 * (variant % 4);
  const int tiles = 4;                /* a 4 × 4 grid of panels with rivets */
#pragma omp parallel for schedule(static)
  for (int y = 0; y < S; y++) {
    for (int x = 0; x < S; x++) {
      double u = (x + 0.5) / S, v = (y + 0.5) / S;
      double low = fbm(seed, 0, 4, 32, u, v);
      double detail = fbm(seed, 10, 64, fine, u, v);
      /* panels: a groove along the tile borders, a rivet near each corner */
      double tu = u * tiles - floor(u * tiles), tv = v * tiles - floor(v * tiles);
      double edge = fmin(fmin(tu, 1 - tu), fmin(tv, 1 - tv));
      double groove = edge < 0.02 ? -1.0 : edge < 0.04 ? -(0.04 - edge) / 0.02 : 0.0;
      double rx = fmin(tu, 1 - tu) - 0.09, ry = fmin(tv, 1 - tv) - 0.09;
      double rd = sqrt(rx * rx + ry * ry) / 0.035;
      double rivet = rd < 1 ? sqrt(1 - rd * rd) : 0;
      double h = 0.35 * low + 0.15 * detail + 0.35 * groove + 0.5 * rivet;
      height[(size_t)y * S + x] = (float)h;
      size_t i = (size_t)y * S + x;
      /* albedo: two paints mixed by the low noise, fine speckle on top */
      double t = jnd_clampd((low - 0.35) * 3.0, 0, 1);
      double c1[3] = {0.62 - tint, 0.30 + tint, 0.18}, c2[3] = {0.20, 0.34, 0.52 - tint}, metal[3] = {0.85, 0.80, 0.70};
      double speck = 0.75 + 0.5 * detail;
      for (int k = 0; k < 3; k++) {
        double a = (c1[k] + (c2[k] - c1[k]) * t) * speck;
        if (rivet > 0) a = metal[k];
        if (groove < 0) a *= 0.5;
        base.data[k * P + i] = (float)jnd_clampd(a, 0, 1);   /* stored "as sRGB": a design value */
      }
      double rough = 0.3 + 0.5 * fbm(seed, 20, 16, fine / 2, u, v);
      if (rivet > 0) rough = 0.2;
      mr.data[0 * P + i] = 1;                     /* R: unused (glTF packs occlusion here) */
      mr.data[1 * P + i] = (float)jnd_clampd(rough, 0, 1);
      mr.data[2 * P + i] = rivet > 0 ? 1.0f : 0.0f;
    }
  }
  /* normal map from the height field (glTF convention: +Y up the image) and
   * occlusion from how far a pixel lies below its neighbourhood */
  const double strength = S / 24.0;   /* height units per pixel → slope, resolution-independent */
#pragma omp parallel for schedule(static)
  for (int y = 0; y < S; y++) {
    for (int x = 0; x < S; x++) {
      int xm = (x + S - 1) % S, xp = (x + 1) % S, ym = (y + S - 1) % S, yp = (y + 1) % S;
      double dx = (height[(size_t)y * S + xp] - height[(size_t)y * S + xm]) * 0.5 * strength;
      double drow = (height[(size_t)yp * S + x] - height[(size_t)ym * S + x]) * 0.5 * strength;
      double n[3] = {-dx, drow, 1};
      double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      size_t i = (size_t)y * S + x;
      for (int k = 0; k < 3; k++) nrm.data[k * P + i] = (float)(0.5 + 0.5 * n[k] / l);
      double h = height[i];
      occ.data[i] = (float)jnd_clampd(1.0 + 1.2 * (h < 0 ? h : 0) - 0.15 * (1 - h), 0.2, 1.0);
    }
  }
  free(height);
  if (jnd_scene_add_map(s, mat, JND_MAP_BASE_COLOR, &base) < 0 ||
      jnd_scene_add_map(s, mat, JND_MAP_METALLIC_ROUGHNESS, &mr) < 0 ||
      jnd_scene_add_map(s, mat, JND_MAP_NORMAL, &nrm) < 0 ||
      jnd_scene_add_map(s, mat, JND_MAP_OCCLUSION, &occ) < 0) {
    jnd_image_free(&base);
    jnd_image_free(&mr);
    jnd_image_free(&nrm);
    jnd_image_free(&occ);
    return JND_ERR_NOMEM;
  }
  return JND_OK;
}

static void put_vertex(float *d, const double p[3], const double n[3], double u, double v) {
  memset(d, 0, JND_VTX_FLOATS * sizeof(float));
  for (int k = 0; k < 3; k++) {
    d[k] = (float)p[k];
    d[3 + k] = (float)n[k];
  }
  d[10] = d[12] = (float)u;
  d[11] = d[13] = (float)v;
  d[14] = d[15] = d[16] = d[17] = 1;
}

/* A rounded box of half-size 1 and edge radius 0.25: each face of a cube is
 * a grid whose points are pushed onto the rounded surface. Each face maps
 * the whole texture. */
static jnd_status make_rounded_box(jnd_mesh *m) {
  const int N = 48;
  const double r = 0.25, b = 1 - r;
  m->nverts = (size_t)6 * (N + 1) * (N + 1);
  m->ntris = (size_t)6 * N * N * 2;
  m->vertices = jnd_alloc(m->nverts, JND_VTX_FLOATS * sizeof(float));
  m->indices = jnd_alloc(m->ntris * 3, sizeof(uint32_t));
  if (!m->vertices || !m->indices) return JND_ERR_NOMEM;
  /* face frames: normal axis, u axis, v axis (v down the texture) */
  static const int fr[6][3][3] = {
      {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
      {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},
      {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}}};
  size_t vi = 0, ti = 0;
  for (int f = 0; f < 6; f++) {
    size_t first = vi;
    for (int j = 0; j <= N; j++)
      for (int i = 0; i <= N; i++) {
        double a = 2.0 * i / N - 1, c = 2.0 * j / N - 1, p[3], q[3], n[3];
        for (int k = 0; k < 3; k++) p[k] = fr[f][0][k] + a * fr[f][1][k] + c * fr[f][2][k];
        double l = 0;
        for (int k = 0; k < 3; k++) {
          q[k] = jnd_clampd(p[k], -b, b);
          n[k] = p[k] - q[k];
          l += n[k] * n[k];
        }
        l = sqrt(l);
        for (int k = 0; k < 3; k++) {
          n[k] /= l;
          p[k] = q[k] + r * n[k];
        }
        put_vertex(m->vertices + vi * JND_VTX_FLOATS, p, n, (double)i / N, (double)j / N);
        vi++;
      }
    for (int j = 0; j < N; j++)
      for (int i = 0; i < N; i++) {
        uint32_t a = (uint32_t)(first + (size_t)j * (N + 1) + i), b1 = a + 1, c = a + (N + 1), d = c + 1;
        /* counter-clockwise seen from outside: u × v points inward here, so a, c, b */
        uint32_t tri[6] = {a, c, b1, b1, c, d};
        memcpy(m->indices + 3 * ti, tri, sizeof tri);
        ti += 2;
      }
  }
  return JND_OK;
}

static jnd_status make_sphere(jnd_mesh *m) {
  const int NU = 96, NV = 48;
  m->nverts = (size_t)(NU + 1) * (NV + 1);
  m->ntris = (size_t)NU * NV * 2;
  m->vertices = jnd_alloc(m->nverts, JND_VTX_FLOATS * sizeof(float));
  m->indices = jnd_alloc(m->ntris * 3, sizeof(uint32_t));
  if (!m->vertices || !m->indices) return JND_ERR_NOMEM;
  size_t vi = 0, ti = 0;
  for (int j = 0; j <= NV; j++)
    for (int i = 0; i <= NU; i++) {
      double th = M_PI * j / NV, ph = 2 * M_PI * i / NU;
      double n[3] = {sin(th) * sin(ph), cos(th), sin(th) * cos(ph)};
      put_vertex(m->vertices + (vi++) * JND_VTX_FLOATS, n, n, 2.0 * i / NU, (double)j / NV);
    }
  for (int j = 0; j < NV; j++)
    for (int i = 0; i < NU; i++) {
      uint32_t a = (uint32_t)(j * (NU + 1) + i), b = a + 1, c = a + (NU + 1), d = c + 1;
      uint32_t tri[6] = {a, c, b, b, c, d};
      memcpy(m->indices + 3 * ti, tri, sizeof tri);
      ti += 2;
    }
  return JND_OK;
}

/* Moves a mesh by (dx, 0, dz). */
static void translate(jnd_mesh *m, double dx, double dz) {
  for (size_t v = 0; v < m->nverts; v++) {
    m->vertices[v * JND_VTX_FLOATS + 0] += (float)dx;
    m->vertices[v * JND_VTX_FLOATS + 2] += (float)dz;
  }
}

/* A flat square at height y, half-side h, facing up, one uv square. */
static jnd_status make_ground(jnd_mesh *m, double y, double h) {
  m->nverts = 4;
  m->ntris = 2;
  m->vertices = jnd_alloc(4, JND_VTX_FLOATS * sizeof(float));
  m->indices = jnd_alloc(6, sizeof(uint32_t));
  if (!m->vertices || !m->indices) return JND_ERR_NOMEM;
  const double up[3] = {0, 1, 0};
  for (int i = 0; i < 4; i++) {
    double p[3] = {(i & 1) ? h : -h, y, (i & 2) ? h : -h};
    put_vertex(m->vertices + (size_t)i * JND_VTX_FLOATS, p, up, (i & 1) ? 1 : 0, (i & 2) ? 1 : 0);
  }
  static const uint32_t tri[6] = {0, 2, 1, 1, 2, 3};   /* counter-clockwise seen from above */
  memcpy(m->indices, tri, sizeof tri);
  return JND_OK;
}

enum { BUILTIN_MAX_PARTS = 8 };
#define PART_SPACING 2.6   /* object units between part centres (parts are 2 across) */

jnd_status jnd_scene_builtin(const jnd_builtin_params *p, jnd_scene **out) {
  jnd_builtin_params d;
  if (!p) {
    jnd_builtin_defaults(&d);
    p = &d;
  }
  *out = NULL;
  if (p->map_size < 8 || p->map_size > 8192)
    return jnd_fail(JND_ERR_ARG, "builtin: map size %d outside [8, 8192]", p->map_size);
  if (p->parts < 1 || p->parts > BUILTIN_MAX_PARTS)
    return jnd_fail(JND_ERR_ARG, "builtin: %d parts outside [1, %d]", p->parts, BUILTIN_MAX_PARTS);
  jnd_scene *s = jnd_scene_new("builtin");
  if (!s) return JND_ERR_NOMEM;
  int n = p->parts, cols = (int)ceil(sqrt((double)n)), rows = (n + cols - 1) / cols;
  s->materials = jnd_calloc((size_t)n + 1, sizeof *s->materials);
  s->meshes = jnd_calloc((size_t)n + 1, sizeof *s->meshes);
  jnd_status st = s->materials && s->meshes ? JND_OK : JND_ERR_NOMEM;
  for (int k = 0; k < n && !st; k++) {
    char name[32];
    if (n == 1) snprintf(name, sizeof name, "builtin");
    else snprintf(name, sizeof name, "part%d", k);
    jnd_material_defaults(&s->materials[k], name);
    s->materials[k].metallic = 1;   /* the maps carry the values */
    s->materials[k].roughness = 1;
    s->nmaterials++;
    jnd_mesh *m = &s->meshes[s->nmeshes++];
    m->material = k;
    /* one shape, or boxes and spheres in turn */
    int sphere = n == 1 ? p->shape == 1 : (k + (p->shape == 1)) % 2 == 1;
    st = sphere ? make_sphere(m) : make_rounded_box(m);
    if (!st) {
      jnd_mesh_compute_tangents(m);
      translate(m, (k % cols - 0.5 * (cols - 1)) * PART_SPACING, (k / cols - 0.5 * (rows - 1)) * PART_SPACING);
      st = make_maps(s, k, p->map_size, p->seed + (uint64_t)k, k);
    }
  }
  if (!st && p->ground) {
    /* a plain floor under the parts, three times as wide: no maps */
    jnd_material *g = &s->materials[s->nmaterials];
    jnd_material_defaults(g, "ground");
    for (int k = 0; k < 3; k++) g->base_color[k] = 0.45f;
    g->metallic = 0;
    g->roughness = 0.9f;
    jnd_mesh *m = &s->meshes[s->nmeshes++];
    m->material = s->nmaterials++;
    st = make_ground(m, -1.0, 1.5 * PART_SPACING * (cols > rows ? cols : rows));
    if (!st) jnd_mesh_compute_tangents(m);
  }
  if (st) {
    jnd_scene_free(s);
    return st == JND_ERR_NOMEM ? jnd_fail(st, "builtin: out of memory") : st;
  }
  jnd_scene_compute_bounds(s);
  *out = s;
  return JND_OK;
}

/* "builtin" alone, or followed by ":" and a comma list of box, sphere,
 * parts=N, ground; p keeps its other fields. 0: not a builtin name. */
int jnd_builtin_parse(const char *name, jnd_builtin_params *p) {
  if (strncmp(name, "builtin", 7) != 0 || (name[7] && name[7] != ':')) return 0;
  if (!name[7]) return 1;
  char buf[128];
  snprintf(buf, sizeof buf, "%s", name + 8);
  char *save = NULL;
  for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
    char *end;
    if (strcmp(t, "box") == 0) p->shape = 0;
    else if (strcmp(t, "sphere") == 0) p->shape = 1;
    else if (strcmp(t, "ground") == 0) p->ground = 1;
    else if (strncmp(t, "parts=", 6) == 0 && (p->parts = (int)strtol(t + 6, &end, 10), end != t + 6 && !*end)) continue;
    else return -1;
  }
  return 1;
}

jnd_status jnd_scene_open(const char *name, int map_size, jnd_scene **out) {
  *out = NULL;
  if (!name) return jnd_fail(JND_ERR_ARG, "no model given");
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  if (map_size > 0) bp.map_size = map_size;
  int b = jnd_builtin_parse(name, &bp);
  if (b < 0)
    return jnd_fail(JND_ERR_ARG, "%s: not a built-in asset (builtin[:box|sphere][,parts=N][,ground])", name);
  if (b == 0) return jnd_scene_load(name, out);
  jnd_status st = jnd_scene_builtin(&bp, out);
  if (st != JND_OK) return jnd_fail(st, "%s: %s", name, jnd_last_error());
  return JND_OK;
}
