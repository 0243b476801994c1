/* A scene with every level of detail written as one binary glTF 2.0 file,
 * the levels tied together by the MSFT_lod extension and their switch
 * points given as extras.MSFT_screencoverage (KhronosGroup/glTF
 * extensions/2.0/Vendor/MSFT_lod), which Babylon.js reads and three.js
 * reads through its extension plugins.
 *
 * Layout: node 0 holds level 0 and the extension, {"ids": [1, 2, ...]};
 * node k holds level k; only node 0 is in the scene, so a reader without
 * MSFT_lod shows level 0. Level k is mesh k, with one primitive per scene
 * mesh that has triangles at that level (its vertices compacted to those
 * the level uses). The scene's meshes have their node transforms applied
 * already (object units). Materials are written from the scene's own
 * (factors, alpha, double-sidedness), maps as the 8-bit PNGs they are used
 * as now, with their samplers and KHR_texture_transform. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "scene/scene.h"

enum { GL_FLOAT_T = 5126, GL_UINT_T = 5125, ARRAY_BUFFER = 34962, ELEMENT_ARRAY_BUFFER = 34963 };

typedef struct {
  jnd_buf bin;
  cJSON *views, *accessors;
} writer;

/* appends data as a buffer view (4-byte aligned); returns its index */
static int add_view(writer *w, const void *data, size_t n, int target) {
  jnd_buf_pad4(&w->bin, 0);
  cJSON *v = cJSON_CreateObject();
  cJSON_AddNumberToObject(v, "buffer", 0);
  cJSON_AddNumberToObject(v, "byteOffset", (double)w->bin.n);
  cJSON_AddNumberToObject(v, "byteLength", (double)n);
  if (target) cJSON_AddNumberToObject(v, "target", target);
  jnd_buf_put(&w->bin, data, n);
  cJSON_AddItemToArray(w->views, v);
  return cJSON_GetArraySize(w->views) - 1;
}

static int add_accessor(writer *w, int view, int component, size_t count, const char *type, const float *mn,
                        const float *mx, int ncomp) {
  cJSON *a = cJSON_CreateObject();
  cJSON_AddNumberToObject(a, "bufferView", view);
  cJSON_AddNumberToObject(a, "componentType", component);
  cJSON_AddNumberToObject(a, "count", (double)count);
  cJSON_AddStringToObject(a, "type", type);
  if (mn && mx) {
    cJSON *lo = cJSON_AddArrayToObject(a, "min"), *hi = cJSON_AddArrayToObject(a, "max");
    for (int k = 0; k < ncomp; k++) {
      cJSON_AddItemToArray(lo, cJSON_CreateNumber(mn[k]));
      cJSON_AddItemToArray(hi, cJSON_CreateNumber(mx[k]));
    }
  }
  cJSON_AddItemToArray(w->accessors, a);
  return cJSON_GetArraySize(w->accessors) - 1;
}

/* The vertex attributes of the GLB (interleaved layout of jnd_mesh):
 * offset in floats, components, names. */
enum { NATTR = 6, ATTR_TANGENT = 2, ATTR_UV0 = 3, ATTR_UV1 = 4, ATTR_COLOR = 5 };
static const int attr_off[NATTR] = {0, 3, 6, 10, 12, 14}, attr_ncomp[NATTR] = {3, 3, 4, 2, 2, 4};
static const char *const attr_names[NATTR] = {"POSITION", "NORMAL", "TANGENT", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0"};
static const char *const attr_types[NATTR] = {"VEC3", "VEC3", "VEC4", "VEC2", "VEC2", "VEC4"};

/* The used vertices of (idx, ntris) into verts' nverts, in first-use order:
 * order[u] is the input vertex of output vertex u, ind the indices renumbered
 * (may be NULL). Returns the count, or SIZE_MAX out of memory (*order
 * then NULL). */
static size_t compact(size_t nverts, const uint32_t *idx, size_t ntris, uint32_t **order, uint32_t *ind) {
  uint32_t *remap = jnd_alloc(nverts ? nverts : 1, sizeof *remap);
  *order = jnd_alloc(nverts ? nverts : 1, sizeof **order);
  if (!remap || !*order) {
    free(remap);
    free(*order);
    *order = NULL;
    return SIZE_MAX;
  }
  for (size_t v = 0; v < nverts; v++) remap[v] = UINT32_MAX;
  size_t nu = 0;
  for (size_t i = 0; i < 3 * ntris; i++) {
    if (remap[idx[i]] == UINT32_MAX) {
      remap[idx[i]] = (uint32_t)nu;
      (*order)[nu++] = idx[i];
    }
    if (ind) ind[i] = remap[idx[i]];
  }
  free(remap);
  return nu;
}

/* Which attributes a primitive of material mat carries (bit a: attr_names[a]):
 * POSITION and NORMAL always; a uv set only when one of the material's maps
 * samples it, TANGENT only with a normal map (the only use of either; the
 * glTF validator calls them UNUSED_OBJECT otherwise and a GPU would hold
 * them for nothing); COLOR_0 where a used vertex's colour is not white. */
static unsigned attributes(const jnd_scene *s, int mat, const float *verts, const uint32_t *order, size_t nu) {
  unsigned a = 1u | 2u;
  const jnd_material *m = mat >= 0 && mat < s->nmaterials ? &s->materials[mat] : NULL;
  for (int k = 0; m && k < JND_MAP_SLOTS; k++)
    if (m->map[k] >= 0) a |= 1u << (s->maps[m->map[k]].uv_set ? ATTR_UV1 : ATTR_UV0);
  if (m && m->map[JND_MAP_NORMAL] >= 0) a |= 1u << ATTR_TANGENT;
  for (size_t u = 0; u < nu && !(a & (1u << ATTR_COLOR)); u++)
    for (int k = 0; k < 4; k++)
      if (verts[(size_t)order[u] * JND_VTX_FLOATS + attr_off[ATTR_COLOR] + k] != 1) a |= 1u << ATTR_COLOR;
  return a;
}

/* one primitive: the used vertices of (verts, idx) compacted, each attribute its own view */
static jnd_status add_primitive(writer *w, cJSON *prims, const jnd_scene *s, const float *verts, size_t nverts,
                                const uint32_t *idx, size_t ntris, int material, int written_material) {
  uint32_t *ind = jnd_alloc(3 * ntris, sizeof *ind), *order = NULL;
  size_t nu = ind ? compact(nverts, idx, ntris, &order, ind) : SIZE_MAX;
  float *attr = nu != SIZE_MAX ? jnd_alloc(nu ? nu : 1, 4 * sizeof(float)) : NULL;
  if (!attr) {
    free(ind);
    free(order);
    return JND_ERR_NOMEM;
  }
  unsigned want = attributes(s, material, verts, order, nu);
  cJSON *prim = cJSON_CreateObject(), *at = cJSON_AddObjectToObject(prim, "attributes");
  for (int a = 0; a < NATTR; a++) {
    if (!(want & (1u << a))) continue;
    float mn[4], mx[4];
    for (int k = 0; k < attr_ncomp[a]; k++) mn[k] = INFINITY, mx[k] = -INFINITY;
    for (size_t u = 0; u < nu; u++) {
      const float *src = verts + (size_t)order[u] * JND_VTX_FLOATS + attr_off[a];
      for (int k = 0; k < attr_ncomp[a]; k++) {
        attr[u * attr_ncomp[a] + k] = src[k];
        if (src[k] < mn[k]) mn[k] = src[k];
        if (src[k] > mx[k]) mx[k] = src[k];
      }
    }
    int view = add_view(w, attr, nu * attr_ncomp[a] * sizeof(float), ARRAY_BUFFER);
    int acc = add_accessor(w, view, GL_FLOAT_T, nu, attr_types[a], a == 0 ? mn : NULL, a == 0 ? mx : NULL,
                           attr_ncomp[a]);
    cJSON_AddNumberToObject(at, attr_names[a], acc);
  }
  int view = add_view(w, ind, 3 * ntris * sizeof *ind, ELEMENT_ARRAY_BUFFER);
  cJSON_AddNumberToObject(prim, "indices", add_accessor(w, view, GL_UINT_T, 3 * ntris, "SCALAR", NULL, NULL, 1));
  if (written_material >= 0) cJSON_AddNumberToObject(prim, "material", written_material);
  cJSON_AddItemToArray(prims, prim);
  free(ind);
  free(attr);
  free(order);
  return JND_OK;
}

/* mesh i at level k: the vertex array it indexes and its triangles */
static void level_mesh(const jnd_scene *s, int k, int i, const float **verts, size_t *nv, const uint32_t **idx,
                       size_t *nt) {
  if (s->nlod > 0) {
    const jnd_lod_mesh *m = &s->lod[k].mesh[i];
    *verts = m->vertices ? m->vertices : s->lod[0].mesh[i].vertices;
    *nv = m->vertices ? m->nverts : s->lod[0].mesh[i].nverts;
    *idx = m->indices;
    *nt = m->ntris;
  } else {
    *verts = s->meshes[i].vertices, *nv = s->meshes[i].nverts, *idx = s->meshes[i].indices, *nt = s->meshes[i].ntris;
  }
}

jnd_status jnd_scene_lod_bytes(const jnd_scene *s, int level, size_t *bytes) {
  *bytes = 0;
  if (level < 0 || level >= jnd_scene_lod_count(s))
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the chain has %d)", s->path, level, jnd_scene_lod_count(s));
  for (int i = 0; i < s->nmeshes; i++) {
    const float *verts;
    const uint32_t *idx;
    size_t nv, nt;
    level_mesh(s, level, i, &verts, &nv, &idx, &nt);
    if (nt == 0) continue;
    uint32_t *order = NULL;
    size_t nu = compact(nv, idx, nt, &order, NULL);
    if (nu == SIZE_MAX) return JND_ERR_NOMEM;
    unsigned want = attributes(s, s->meshes[i].material, verts, order, nu);
    free(order);
    size_t per_vertex = 0;
    for (int a = 0; a < NATTR; a++)
      if (want & (1u << a)) per_vertex += (size_t)attr_ncomp[a] * sizeof(float);
    *bytes += nu * per_vertex + 3 * nt * sizeof(uint32_t);
  }
  return JND_OK;
}

/* map i as a PNG image, its sampler and texture; returns the texture index or −1 */
static int add_texture(writer *w, const jnd_scene *s, int i, cJSON *images, cJSON *samplers, cJSON *textures,
                       jnd_status *st) {
  const jnd_map *m = &s->maps[i];
  jnd_buf png = {0};
  if ((*st = jnd_image_encode_8bit(jnd_map_image(m), 0, &png))) {
    jnd_buf_free(&png);
    return -1;
  }
  int view = add_view(w, png.p, png.n, 0);
  jnd_buf_free(&png);
  cJSON *img = cJSON_CreateObject();
  cJSON_AddNumberToObject(img, "bufferView", view);
  cJSON_AddStringToObject(img, "mimeType", "image/png");
  cJSON_AddItemToArray(images, img);
  static const int wrap[3] = {10497, 33071, 33648};   /* REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT */
  cJSON *smp = cJSON_CreateObject();
  cJSON_AddNumberToObject(smp, "magFilter", m->mag_nearest ? 9728 : 9729);
  cJSON_AddNumberToObject(smp, "minFilter", m->min_nearest ? 9986 : 9987);
  cJSON_AddNumberToObject(smp, "wrapS", wrap[m->wrap_s]);
  cJSON_AddNumberToObject(smp, "wrapT", wrap[m->wrap_t]);
  cJSON_AddItemToArray(samplers, smp);
  cJSON *tex = cJSON_CreateObject();
  cJSON_AddNumberToObject(tex, "sampler", cJSON_GetArraySize(samplers) - 1);
  cJSON_AddNumberToObject(tex, "source", cJSON_GetArraySize(images) - 1);
  cJSON_AddItemToArray(textures, tex);
  return cJSON_GetArraySize(textures) - 1;
}

/* a textureInfo for map i; KHR_texture_transform where it has one */
static cJSON *texture_info(const jnd_scene *s, int i, int tex, int *uses_transform) {
  const jnd_map *m = &s->maps[i];
  cJSON *t = cJSON_CreateObject();
  cJSON_AddNumberToObject(t, "index", tex);
  if (m->uv_set) cJSON_AddNumberToObject(t, "texCoord", m->uv_set);
  const float *x = m->uvxf;
  if (!(x[0] == 1 && x[1] == 0 && x[2] == 0 && x[3] == 0 && x[4] == 1 && x[5] == 0)) {
    /* x = T(o) R(r) S(s) with R = [cos −sin; sin cos] (src/scene/import.c) */
    double r = atan2(x[3], x[0]), sx = hypot(x[0], x[3]), sy = hypot(x[1], x[4]);
    cJSON *e = cJSON_AddObjectToObject(cJSON_AddObjectToObject(t, "extensions"), "KHR_texture_transform");
    cJSON *o = cJSON_AddArrayToObject(e, "offset"), *sc = cJSON_AddArrayToObject(e, "scale");
    cJSON_AddItemToArray(o, cJSON_CreateNumber(x[2]));
    cJSON_AddItemToArray(o, cJSON_CreateNumber(x[5]));
    cJSON_AddNumberToObject(e, "rotation", r);
    cJSON_AddItemToArray(sc, cJSON_CreateNumber(sx));
    cJSON_AddItemToArray(sc, cJSON_CreateNumber(sy));
    *uses_transform = 1;
  }
  return t;
}

static cJSON *floats(const float *v, int n) {
  cJSON *a = cJSON_CreateArray();
  for (int k = 0; k < n; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
  return a;
}

jnd_status jnd_scene_write_lod_glb(const jnd_scene *s, const char *path, const double *coverage) {
  return jnd_scene_write_lod_glb_from(s, path, coverage, 0);
}

jnd_status jnd_scene_write_lod_glb_from(const jnd_scene *s, const char *path, const double *coverage, int first) {
  if (first < 0 || first >= jnd_scene_lod_count(s))
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the chain has %d)", s->path, first, jnd_scene_lod_count(s));
  int n = jnd_scene_lod_count(s) - first;   /* levels written; written level j is the scene's first + j */
  writer w = {0};
  cJSON *root = cJSON_CreateObject();
  cJSON *asset = cJSON_AddObjectToObject(root, "asset");
  cJSON_AddStringToObject(asset, "version", "2.0");
  char gen[64];
  snprintf(gen, sizeof gen, "jnd %s", jnd_version());
  cJSON_AddStringToObject(asset, "generator", gen);
  cJSON *used = cJSON_AddArrayToObject(root, "extensionsUsed");
  if (n > 1) cJSON_AddItemToArray(used, cJSON_CreateString("MSFT_lod"));
  cJSON_AddNumberToObject(root, "scene", 0);
  cJSON *scn = cJSON_CreateObject(), *sroots = cJSON_AddArrayToObject(scn, "nodes");
  cJSON_AddItemToArray(sroots, cJSON_CreateNumber(0));
  cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "scenes"), scn);
  cJSON *nodes = cJSON_AddArrayToObject(root, "nodes"), *meshes = cJSON_AddArrayToObject(root, "meshes");
  cJSON *materials = cJSON_AddArrayToObject(root, "materials");
  cJSON *textures = cJSON_CreateArray(), *images = cJSON_CreateArray(), *samplers = cJSON_CreateArray();
  w.accessors = cJSON_AddArrayToObject(root, "accessors");
  w.views = cJSON_AddArrayToObject(root, "bufferViews");
  jnd_status st = JND_OK;

  /* What the file draws: a material no mesh uses (assimp adds a default
   * one to every import it converts) is not written, nor an image that only
   * such materials sample — the written asset holds what it shows.
   * written[mi]: the material's index in the file, -1 when left out. */
  int *written = jnd_calloc((size_t)s->nmaterials + 1, sizeof *written);
  char *sampled = jnd_calloc((size_t)s->nmaps + 1, 1);
  if (!written || !sampled) st = JND_ERR_NOMEM;
  for (int i = 0; i < s->nmeshes && !st; i++)
    if (s->meshes[i].material >= 0 && s->meshes[i].material < s->nmaterials) written[s->meshes[i].material] = 1;
  for (int mi = 0, nw = 0; mi < s->nmaterials && !st; mi++) {
    if (!written[mi]) {
      written[mi] = -1;
      continue;
    }
    written[mi] = nw++;
    for (int k = 0; k < JND_MAP_SLOTS; k++)
      if (s->materials[mi].map[k] >= 0 && s->materials[mi].map[k] < s->nmaps) sampled[s->materials[mi].map[k]] = 1;
  }

  /* textures first: their bytes lead the binary chunk */
  int *tex = jnd_alloc((size_t)s->nmaps + 1, sizeof *tex), uses_transform = 0;
  if (!tex && !st) st = JND_ERR_NOMEM;
  for (int i = 0; i < s->nmaps && !st; i++) {
    if (!sampled[i]) {
      tex[i] = -1;
      continue;
    }
    /* an image that several slots sample (a packed occlusion-roughness-metal
     * image) is written once, as the GPU holds it, when it is used at one
     * size and sampled alike */
    const jnd_map *m = &s->maps[i], *f = &s->maps[m->image];
    const jnd_image *a = jnd_map_image(m), *b = jnd_map_image(f);
    if (m->image < i && tex[m->image] >= 0 && a->w == b->w && a->h == b->h && a->c == b->c && m->wrap_s == f->wrap_s &&
        m->wrap_t == f->wrap_t && m->mag_nearest == f->mag_nearest && m->min_nearest == f->min_nearest)
      tex[i] = tex[m->image];
    else
      tex[i] = add_texture(&w, s, i, images, samplers, textures, &st);
  }
  for (int mi = 0; mi < s->nmaterials && !st; mi++) {
    if (written[mi] < 0) continue;
    const jnd_material *m = &s->materials[mi];
    cJSON *o = cJSON_CreateObject(), *pbr = cJSON_AddObjectToObject(o, "pbrMetallicRoughness");
    cJSON_AddStringToObject(o, "name", m->name);
    cJSON_AddItemToObject(pbr, "baseColorFactor", floats(m->base_color, 4));
    cJSON_AddNumberToObject(pbr, "metallicFactor", m->metallic);
    cJSON_AddNumberToObject(pbr, "roughnessFactor", m->roughness);
    const int *mp = m->map;
    if (mp[JND_MAP_BASE_COLOR] >= 0)
      cJSON_AddItemToObject(pbr, "baseColorTexture", texture_info(s, mp[JND_MAP_BASE_COLOR], tex[mp[JND_MAP_BASE_COLOR]], &uses_transform));
    if (mp[JND_MAP_METALLIC_ROUGHNESS] >= 0)
      cJSON_AddItemToObject(pbr, "metallicRoughnessTexture",
                            texture_info(s, mp[JND_MAP_METALLIC_ROUGHNESS], tex[mp[JND_MAP_METALLIC_ROUGHNESS]], &uses_transform));
    if (mp[JND_MAP_NORMAL] >= 0) {
      cJSON *t = texture_info(s, mp[JND_MAP_NORMAL], tex[mp[JND_MAP_NORMAL]], &uses_transform);
      cJSON_AddNumberToObject(t, "scale", m->normal_scale);
      cJSON_AddItemToObject(o, "normalTexture", t);
    }
    if (mp[JND_MAP_OCCLUSION] >= 0) {
      cJSON *t = texture_info(s, mp[JND_MAP_OCCLUSION], tex[mp[JND_MAP_OCCLUSION]], &uses_transform);
      cJSON_AddNumberToObject(t, "strength", m->occlusion_strength);
      cJSON_AddItemToObject(o, "occlusionTexture", t);
    }
    if (mp[JND_MAP_EMISSIVE] >= 0)
      cJSON_AddItemToObject(o, "emissiveTexture", texture_info(s, mp[JND_MAP_EMISSIVE], tex[mp[JND_MAP_EMISSIVE]], &uses_transform));
    cJSON_AddItemToObject(o, "emissiveFactor", floats(m->emissive, 3));
    static const char *const modes[3] = {"OPAQUE", "MASK", "BLEND"};
    cJSON_AddStringToObject(o, "alphaMode", modes[m->alpha_mode]);
    if (m->alpha_mode == JND_ALPHA_MASK) cJSON_AddNumberToObject(o, "alphaCutoff", m->alpha_cutoff);
    cJSON_AddBoolToObject(o, "doubleSided", m->double_sided);
    cJSON_AddItemToArray(materials, o);
  }
  free(tex);
  free(sampled);
  if (uses_transform) cJSON_AddItemToArray(used, cJSON_CreateString("KHR_texture_transform"));
  if (cJSON_GetArraySize(images) > 0) {
    cJSON_AddItemToObject(root, "images", images);
    cJSON_AddItemToObject(root, "samplers", samplers);
    cJSON_AddItemToObject(root, "textures", textures);
  } else {
    cJSON_Delete(images);
    cJSON_Delete(samplers);
    cJSON_Delete(textures);
  }

  /* one mesh and one node per level */
  for (int k = 0; k < n && !st; k++) {
    cJSON *mesh = cJSON_CreateObject(), *prims = cJSON_AddArrayToObject(mesh, "primitives");
    char name[32];
    snprintf(name, sizeof name, "LOD%d", k);
    cJSON_AddStringToObject(mesh, "name", name);
    for (int i = 0; i < s->nmeshes && !st; i++) {
      const float *verts;
      const uint32_t *idx;
      size_t nv, nt;
      level_mesh(s, first + k, i, &verts, &nv, &idx, &nt);
      int mat = s->meshes[i].material;
      if (nt > 0)
        st = add_primitive(&w, prims, s, verts, nv, idx, nt, mat, mat >= 0 && mat < s->nmaterials ? written[mat] : -1);
    }
    if (!st && cJSON_GetArraySize(prims) == 0) st = jnd_fail(JND_ERR_ARG, "%s: level %d has no triangles", path, k);
    cJSON_AddItemToArray(meshes, mesh);
    cJSON *node = cJSON_CreateObject();
    cJSON_AddStringToObject(node, "name", name);
    cJSON_AddNumberToObject(node, "mesh", k);
    if (k == 0 && n > 1) {
      cJSON *ids = cJSON_AddArrayToObject(cJSON_AddObjectToObject(cJSON_AddObjectToObject(node, "extensions"), "MSFT_lod"), "ids");
      for (int j = 1; j < n; j++) cJSON_AddItemToArray(ids, cJSON_CreateNumber(j));
      if (coverage) {
        cJSON *cov = cJSON_AddArrayToObject(cJSON_AddObjectToObject(node, "extras"), "MSFT_screencoverage");
        for (int j = 0; j < n; j++) cJSON_AddItemToArray(cov, cJSON_CreateNumber(coverage[j]));
      }
    }
    cJSON_AddItemToArray(nodes, node);
  }
  if (cJSON_GetArraySize(used) == 0) cJSON_DeleteItemFromObjectCaseSensitive(root, "extensionsUsed");
  if (cJSON_GetArraySize(materials) == 0) cJSON_DeleteItemFromObjectCaseSensitive(root, "materials"); /* glTF: minItems 1 */
  free(written);
  cJSON *buf = cJSON_CreateObject();
  cJSON_AddNumberToObject(buf, "byteLength", (double)((w.bin.n + 3) / 4 * 4));
  cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "buffers"), buf);
  if (!st && w.bin.failed) st = jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  char *text = st ? NULL : cJSON_PrintUnformatted(root);
  cJSON_Delete(root);
  if (!st && !text) st = jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  jnd_buf glb = {0};
  if (!st) st = jnd_glb_join(text, strlen(text), w.bin.p, w.bin.n, &glb);
  if (!st) st = jnd_write_file_atomic(path, glb.p, glb.n);
  free(text);
  jnd_buf_free(&glb);
  jnd_buf_free(&w.bin);
  return st;
}
