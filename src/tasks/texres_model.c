/* A copy of a glTF 2.0 model whose texture maps are the scene's maps at the
 * sizes in use (jnd texres's output; the input is never touched).
 *
 * The glTF JSON is edited, not regenerated, so everything jnd does not model
 * (animations, extensions, extras) survives. A map is found through its
 * material's textureInfo (glTF material index = jnd material index: assimp
 * keeps the file's order); its image is re-encoded as the file had it (PNG
 * or JPEG). texres gives every slot that samples one image one size (a
 * packed occlusion-roughness-metallic image, a texture two materials share
 * stay one image); an image still used at two sizes — by a material the
 * scene does not have (no mesh uses it, or only a KHR_materials_variants
 * mapping names it) at its own size — becomes two images, the second with
 * its own texture, so that the material nobody judged is left as it was.
 * A .glb is rewritten as one .glb whose
 * binary chunk holds every buffer view compacted, the resized images in
 * place of the old ones; a .gltf gets its images and external buffers as
 * files beside it. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"

#define MAX_MODEL (1u << 30)

static const cJSON *item(const cJSON *o, const char *k) { return cJSON_GetObjectItemCaseSensitive(o, k); }

static int int_of(const cJSON *o, const char *k, int dflt) {
  const cJSON *x = item(o, k);
  return cJSON_IsNumber(x) ? x->valueint : dflt;
}

/* sets o[k] = v, adding the member where o lacks it (glTF leaves out members
 * at their defaults, byteOffset 0 above all) */
static void set_number(cJSON *o, const char *k, double v) {
  if (!cJSON_IsObject(o)) return;
  if (item(o, k))
    cJSON_ReplaceItemInObjectCaseSensitive(o, k, cJSON_CreateNumber(v));
  else
    cJSON_AddNumberToObject(o, k, v);
}

/* appends it to the array arr (which owns it then), or frees it */
static void append(cJSON *arr, cJSON *it) {
  if (!arr || !cJSON_AddItemToArray(arr, it)) cJSON_Delete(it);
}

/* the textureInfo object of a slot in a glTF material */
static cJSON *texture_info(cJSON *mat, jnd_map_slot slot) {
  cJSON *pbr = cJSON_GetObjectItemCaseSensitive(mat, "pbrMetallicRoughness");
  switch (slot) {
  case JND_MAP_BASE_COLOR: return cJSON_GetObjectItemCaseSensitive(pbr, "baseColorTexture");
  case JND_MAP_METALLIC_ROUGHNESS: return cJSON_GetObjectItemCaseSensitive(pbr, "metallicRoughnessTexture");
  case JND_MAP_NORMAL: return cJSON_GetObjectItemCaseSensitive(mat, "normalTexture");
  case JND_MAP_OCCLUSION: return cJSON_GetObjectItemCaseSensitive(mat, "occlusionTexture");
  case JND_MAP_EMISSIVE: return cJSON_GetObjectItemCaseSensitive(mat, "emissiveTexture");
  default: return NULL;
  }
}

/* Which glTF material each of the scene's materials is. assimp loads a
 * glTF's materials lazily, in the order meshes first reference them while
 * the default scene's nodes are read (a node's children before its own
 * mesh, a mesh's primitives in order), and leaves out the ones no mesh
 * uses (an unused material, or one only a KHR_materials_variants mapping
 * names): so the scene's material j is the j-th distinct material of that
 * walk. out[j] (scene materials) receives its glTF index, or -1 for a
 * material the file does not have (assimp's default). The walk is checked
 * against what the scene kept (names, textured slots); a mismatch is an
 * error, not a copy whose maps differ from the report. */
static void walk_node(const cJSON *root, int node, int depth, int *order, int *n, int cap) {
  const cJSON *nd = cJSON_GetArrayItem(item(root, "nodes"), node);
  if (!nd || depth > 64) return;
  const cJSON *ch;
  cJSON_ArrayForEach(ch, item(nd, "children")) if (cJSON_IsNumber(ch)) walk_node(root, ch->valueint, depth + 1, order, n, cap);
  const cJSON *mesh = cJSON_GetArrayItem(item(root, "meshes"), int_of(nd, "mesh", -1)), *prim;
  cJSON_ArrayForEach(prim, item(mesh, "primitives")) {
    int m = int_of(prim, "material", -1), seen = m < 0;
    for (int k = 0; k < *n && !seen; k++) seen = order[k] == m;
    if (!seen && *n < cap) order[(*n)++] = m;
  }
}

static jnd_status material_map(const cJSON *root, const jnd_scene *scene, const char *src, int *out) {
  int nm = jnd_scene_material_count(scene), n = 0;
  for (int j = 0; j < nm; j++) out[j] = -1;
  const cJSON *scenes = item(root, "scenes"), *sc = cJSON_GetArrayItem(scenes, int_of(root, "scene", 0)), *nd;
  cJSON_ArrayForEach(nd, item(sc, "nodes")) if (cJSON_IsNumber(nd)) walk_node(root, nd->valueint, 0, out, &n, nm);
  const cJSON *materials = item(root, "materials");
  if (n == 0)   /* no scene to walk (not a file assimp loaded): the file's own order */
    for (int j = 0; j < nm && j < cJSON_GetArraySize(materials); j++) out[j] = j;
  for (int j = 0; j < nm; j++) {
    const cJSON *mat = cJSON_GetArrayItem(materials, out[j]);
    const char *name = jnd_scene_material_name(scene, j);
    const cJSON *gname = item(mat, "name");
    int ok = 1;
    if (mat && cJSON_IsString(gname) && gname->valuestring[0]) {
      size_t l = strlen(gname->valuestring);
      ok = strncmp(name, gname->valuestring, l) == 0 && (name[l] == 0 || name[l] == '#');
    }
    /* every map the copy changes must have its slot there */
    for (int k = 0; k < JND_MAP_SLOTS && ok; k++) {
      char full[256];
      snprintf(full, sizeof full, "%s/%s", name, jnd_map_slot_name((jnd_map_slot)k));
      jnd_map_info mi;
      int i = jnd_scene_map_find(scene, full);
      if (i >= 0 && jnd_scene_map_info(scene, i, &mi) == JND_OK && (mi.width != mi.orig_width || mi.height != mi.orig_height))
        ok = texture_info((cJSON *)mat, (jnd_map_slot)k) != NULL;
    }
    if (!ok)
      return jnd_fail(JND_ERR_FORMAT, "%s: cannot tell which glTF material '%s' is (the model copy would not match)",
                      src, name);
  }
  return JND_OK;
}

/* image i is JPEG (by mimeType or the uri's extension) */
static int is_jpeg(const cJSON *img) {
  const cJSON *m = item(img, "mimeType"), *u = item(img, "uri");
  if (cJSON_IsString(m)) return strcmp(m->valuestring, "image/jpeg") == 0;
  if (cJSON_IsString(u)) {
    const char *s = u->valuestring, *dot = strrchr(s, '.');
    if (strncmp(s, "data:image/jpeg", 15) == 0) return 1;
    return dot && (strcasecmp(dot, ".jpg") == 0 || strcasecmp(dot, ".jpeg") == 0);
  }
  return 0;
}

static void dir_of(const char *path, char *dir, size_t n) {
  snprintf(dir, n, "%s", path);
  char *s = strrchr(dir, '/');
  if (s) *s = 0;
  else snprintf(dir, n, ".");
}

static const char *base_of(const char *path) {
  const char *s = strrchr(path, '/');
  return s ? s + 1 : path;
}

/* copies an external file (uri relative to src_dir) into out_dir under its
 * base name; rewrites the uri */
static jnd_status copy_uri(cJSON *o, const char *src_dir, const char *out_dir) {
  cJSON *u = cJSON_GetObjectItemCaseSensitive(o, "uri");
  if (!cJSON_IsString(u) || strncmp(u->valuestring, "data:", 5) == 0) return JND_OK;
  char from[4200], to[4200];
  snprintf(from, sizeof from, "%s/%s", src_dir, u->valuestring);
  snprintf(to, sizeof to, "%s/%s", out_dir, base_of(u->valuestring));
  unsigned char *data;
  size_t n;
  jnd_status s = jnd_read_file(from, MAX_MODEL, &data, &n);
  if (s != JND_OK) return s;
  s = jnd_write_file_atomic(to, data, n);
  free(data);
  if (s == JND_OK) cJSON_SetValuestring(u, base_of(u->valuestring));
  return s;
}

typedef struct {
  int map;            /* scene map */
  cJSON *info;        /* textureInfo */
  int tex, img;       /* glTF texture and image */
  int w, h, changed;
  int target;         /* image index written for it */
} slot_use;

jnd_status jnd_texres_write_model(const jnd_scene *scene, const char *src, const char *out_dir, char *out_path,
                                  size_t out_n) {
  unsigned char *file = NULL;
  size_t fn = 0;
  jnd_status s = jnd_read_file(src, MAX_MODEL, &file, &fn);
  if (s != JND_OK) return s;
  const unsigned char *json_bytes = NULL, *bin = NULL;
  size_t json_n = 0, bin_n = 0;
  int glb = jnd_glb_split(file, fn, &json_bytes, &json_n, &bin, &bin_n);
  if (glb < 0) goto bad;
  const char *json_text = (const char *)json_bytes;
  cJSON *root = cJSON_ParseWithLength(json_text, json_n);
  if (!root) goto bad;
  cJSON *materials = cJSON_GetObjectItemCaseSensitive(root, "materials");
  cJSON *textures = cJSON_GetObjectItemCaseSensitive(root, "textures");
  cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images");
  cJSON *views = cJSON_GetObjectItemCaseSensitive(root, "bufferViews");
  cJSON *buffers = cJSON_GetObjectItemCaseSensitive(root, "buffers");
  int nimg0 = cJSON_GetArraySize(images), nmaps = jnd_scene_map_count(scene);
  slot_use *use = jnd_calloc((size_t)nmaps + 1, sizeof *use);
  int *used_orig = jnd_calloc((size_t)nimg0 + 1, sizeof *used_orig);
  int *replaced = jnd_calloc((size_t)nimg0 + 1, sizeof *replaced);
  int *gmat = jnd_calloc((size_t)jnd_scene_material_count(scene) + 1, sizeof *gmat);
  jnd_buf *enc = NULL;
  int nuse = 0, nenc = 0;
  char src_dir[4096];
  dir_of(src, src_dir, sizeof src_dir);
  if (!use || !used_orig || !replaced || !gmat) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  if ((s = material_map(root, scene, src, gmat)) != JND_OK) goto done;
  /* an image that any material's slot uses at its own size (a material the
   * scene does not have, an unchanged slot) stays as it is */
  int ngm = cJSON_GetArraySize(materials);
  for (int g = 0; g < ngm; g++)
    for (int k = 0; k < JND_MAP_SLOTS; k++) {
      const cJSON *info = texture_info(cJSON_GetArrayItem(materials, g), (jnd_map_slot)k);
      int img = int_of(cJSON_GetArrayItem(textures, int_of(info, "index", -1)), "source", -1);
      if (!info || img < 0 || img >= nimg0) continue;
      int changed = 0;
      for (int j = 0; j < jnd_scene_material_count(scene) && !changed; j++) {
        if (gmat[j] != g) continue;
        char full[256];
        snprintf(full, sizeof full, "%s/%s", jnd_scene_material_name(scene, j), jnd_map_slot_name((jnd_map_slot)k));
        jnd_map_info mi;
        int i = jnd_scene_map_find(scene, full);
        changed = i >= 0 && jnd_scene_map_info(scene, i, &mi) == JND_OK &&
                  (mi.width != mi.orig_width || mi.height != mi.orig_height);
      }
      if (!changed) used_orig[img] = 1;
    }
  for (int i = 0; i < nmaps; i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    cJSON *info = mi.material >= 0 ? texture_info(cJSON_GetArrayItem(materials, gmat[mi.material]), mi.slot) : NULL;
    int t = int_of(info, "index", -1);
    int img = int_of(cJSON_GetArrayItem(textures, t), "source", -1);
    if (!info || img < 0 || img >= nimg0) continue;
    slot_use *u = &use[nuse++];
    u->map = i;
    u->info = info;
    u->tex = t;
    u->img = img;
    u->w = mi.width;
    u->h = mi.height;
    u->changed = mi.width != mi.orig_width || mi.height != mi.orig_height;
    u->target = img;
  }
  /* one encoded image per (image, size) */
  enc = jnd_calloc((size_t)nuse + 1, sizeof *enc);
  int *enc_img = jnd_calloc((size_t)nuse + 1, sizeof *enc_img);
  int *enc_jpeg = jnd_calloc((size_t)nuse + 1, sizeof *enc_jpeg);
  if (!enc || !enc_img || !enc_jpeg) {
    free(enc_img);
    free(enc_jpeg);
    s = JND_ERR_NOMEM;
    goto done;
  }
  for (int k = 0; k < nuse; k++) {
    slot_use *u = &use[k];
    if (!u->changed) continue;
    int found = -1;
    for (int j = 0; j < k; j++)
      if (use[j].changed && use[j].img == u->img && use[j].w == u->w && use[j].h == u->h) found = j;
    if (found >= 0) {
      u->target = use[found].target;
    } else {
      if (!used_orig[u->img] && !replaced[u->img]) {
        u->target = u->img;
        replaced[u->img] = 1;
      } else {
        cJSON *copy = cJSON_Duplicate(cJSON_GetArrayItem(images, u->img), 1);
        cJSON_DeleteItemFromObjectCaseSensitive(copy, "uri");
        cJSON_DeleteItemFromObjectCaseSensitive(copy, "bufferView");
        append(images, copy);
        u->target = cJSON_GetArraySize(images) - 1;
      }
      jnd_image im = {0};
      if ((s = jnd_scene_map_get(scene, u->map, 0, &im)) != JND_OK) {
        free(enc_img);
        free(enc_jpeg);
        goto done;
      }
      enc_jpeg[nenc] = is_jpeg(cJSON_GetArrayItem(images, u->img)) && im.c != 2 && im.c != 4;
      s = jnd_image_encode_8bit(&im, enc_jpeg[nenc], &enc[nenc]);
      jnd_image_free(&im);
      if (s != JND_OK) {
        free(enc_img);
        free(enc_jpeg);
        goto done;
      }
      enc_img[nenc++] = u->target;
    }
    if (u->target != u->img) { /* a texture for the new image */
      cJSON *tcopy = cJSON_Duplicate(cJSON_GetArrayItem(textures, u->tex), 1);
      set_number(tcopy, "source", u->target);
      append(textures, tcopy);
      set_number(u->info, "index", cJSON_GetArraySize(textures) - 1);
    }
  }
  char path[4400];
  const char *name = base_of(src);
  snprintf(path, sizeof path, "%s/%s", out_dir, name);
  if (glb) {
    /* the binary chunk rebuilt view by view; resized images replace their views' bytes */
    if (!views) views = cJSON_AddArrayToObject(root, "bufferViews");
    jnd_buf nb = {0};
    int nviews = cJSON_GetArraySize(views);
    for (int v = 0; v < nviews; v++) {
      cJSON *bv = cJSON_GetArrayItem(views, v);
      if (int_of(bv, "buffer", 0) != 0) continue;
      int off_i = int_of(bv, "byteOffset", 0), len_i = int_of(bv, "byteLength", 0);
      if (off_i < 0 || len_i < 0) {
        nb.failed = 1;
        break;
      }
      size_t off = (size_t)off_i, len = (size_t)len_i;
      const unsigned char *data = NULL;
      for (int e = 0; e < nenc; e++)
        if (enc_img[e] < nimg0 && int_of(cJSON_GetArrayItem(images, enc_img[e]), "bufferView", -1) == v)
          data = enc[e].p, len = enc[e].n;
      if (!data) {
        if (!bin || off > bin_n || len > bin_n - off) {
          nb.failed = 1;
          break;
        }
        data = bin + off;
      }
      jnd_buf_pad4(&nb, 0);
      set_number(bv, "byteOffset", (double)nb.n);
      set_number(bv, "byteLength", (double)len);
      jnd_buf_put(&nb, data, len);
    }
    /* images that had no view of their own (new ones, or uri images) */
    for (int e = 0; e < nenc; e++) {
      cJSON *im = cJSON_GetArrayItem(images, enc_img[e]);
      if (enc_img[e] < nimg0 && item(im, "bufferView")) continue;
      jnd_buf_pad4(&nb, 0);
      cJSON *bv = cJSON_CreateObject();
      cJSON_AddNumberToObject(bv, "buffer", 0);
      cJSON_AddNumberToObject(bv, "byteOffset", (double)nb.n);
      cJSON_AddNumberToObject(bv, "byteLength", (double)enc[e].n);
      append(views, bv);
      cJSON_DeleteItemFromObjectCaseSensitive(im, "uri");
      set_number(im, "bufferView", cJSON_GetArraySize(views) - 1);
      if (!item(im, "mimeType")) cJSON_AddStringToObject(im, "mimeType", enc_jpeg[e] ? "image/jpeg" : "image/png");
      jnd_buf_put(&nb, enc[e].p, enc[e].n);
    }
    jnd_buf_pad4(&nb, 0);
    cJSON *b0 = cJSON_GetArrayItem(buffers, 0);
    if (!b0 && nb.n) { /* the binary chunk needs its buffer */
      if (!buffers) buffers = cJSON_AddArrayToObject(root, "buffers");
      b0 = cJSON_CreateObject();
      append(buffers, b0);
    }
    if (b0) set_number(b0, "byteLength", (double)nb.n);
    for (int b = 1; b < cJSON_GetArraySize(buffers) && s == JND_OK; b++)
      s = copy_uri(cJSON_GetArrayItem(buffers, b), src_dir, out_dir);
    for (int i = 0; i < cJSON_GetArraySize(images) && s == JND_OK; i++)
      if (!item(cJSON_GetArrayItem(images, i), "bufferView")) s = copy_uri(cJSON_GetArrayItem(images, i), src_dir, out_dir);
    char *js = s == JND_OK ? cJSON_PrintUnformatted(root) : NULL;
    jnd_buf g = {0};
    if (js && !nb.failed) {
      s = jnd_glb_join(js, strlen(js), nb.p, nb.n, &g);
      if (s == JND_OK) s = jnd_write_file_atomic(path, g.p, g.n);
    } else if (s == JND_OK) {
      s = jnd_fail(JND_ERR_FORMAT, "%s: a buffer view lies outside the binary chunk", src);
    }
    free(js);
    free(g.p);
    free(nb.p);
  } else {
    /* .gltf: resized images as files beside it; other external files copied */
    char stem[256];
    snprintf(stem, sizeof stem, "%s", name);
    char *dot = strrchr(stem, '.');
    if (dot) *dot = 0;
    for (int e = 0; e < nenc && s == JND_OK; e++) {
      cJSON *im = cJSON_GetArrayItem(images, enc_img[e]);
      char fname[400], full[4800];
      int jpeg = enc_jpeg[e];
      snprintf(fname, sizeof fname, "%s_image%d.%s", stem, enc_img[e], jpeg ? "jpg" : "png");
      snprintf(full, sizeof full, "%s/%s", out_dir, fname);
      s = jnd_write_file_atomic(full, enc[e].p, enc[e].n);
      cJSON_DeleteItemFromObjectCaseSensitive(im, "bufferView");
      cJSON_DeleteItemFromObjectCaseSensitive(im, "uri");
      cJSON_AddStringToObject(im, "uri", fname);
    }
    for (int b = 0; b < cJSON_GetArraySize(buffers) && s == JND_OK; b++)
      s = copy_uri(cJSON_GetArrayItem(buffers, b), src_dir, out_dir);
    for (int i = 0; i < nimg0 && s == JND_OK; i++) {
      int done_here = 0;
      for (int e = 0; e < nenc; e++) done_here |= enc_img[e] == i;
      if (!done_here) s = copy_uri(cJSON_GetArrayItem(images, i), src_dir, out_dir);
    }
    char *js = s == JND_OK ? cJSON_Print(root) : NULL;
    if (js) s = jnd_write_file_atomic(path, js, strlen(js));
    else if (s == JND_OK) s = JND_ERR_NOMEM;
    free(js);
  }
  if (s == JND_OK && out_path) snprintf(out_path, out_n, "%s", path);
  free(enc_img);
  free(enc_jpeg);
done:
  for (int e = 0; enc && e < nuse; e++) free(enc[e].p);
  free(enc);
  free(use);
  free(used_orig);
  free(replaced);
  free(gmat);
  cJSON_Delete(root);
  free(file);
  return s;
bad:
  free(file);
  return jnd_fail(JND_ERR_FORMAT, "%s: not a glTF 2.0 file (only glTF models can be written back)", src);
}
