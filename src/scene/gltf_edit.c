/* A glTF 2.0 document edited, not regenerated: read from a .gltf or .glb,
 * the images some material slots sample replaced by new pixels, written
 * back as a copy (the input is never touched). Everything jnd does not
 * model (animations, extensions, extras) survives, because only the members
 * an edit needs are changed.
 *
 * 1. Read: the GLB container split (jnd_glb_split), the JSON parsed, the
 *    binary chunk kept.
 * 2. Materials: which glTF material each of a scene's materials is, the way
 *    assimp loads them (jnd_gltf_doc_materials).
 * 3. Images: each replaced slot's image re-encoded as the file had it (PNG
 *    or JPEG, jnd_image_encode_8bit — the one PNG-in-glTF encoder, shared
 *    with gltf_write.c). Slots that sample one image at one size keep one
 *    image (a packed occlusion-roughness-metallic image, a texture two
 *    materials share); an image still used at another size — by a slot left
 *    as it was — becomes two images, the second with its own texture.
 * 4. Write: a .glb is rewritten as one .glb whose binary chunk holds every
 *    buffer view compacted, the new images in place of the old ones; a
 *    .gltf gets its images and external buffers as files beside it. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "scene/scene.h"

#define MAX_MODEL (1u << 30)

struct jnd_gltf_doc {
  char src[4096], src_dir[4096];
  unsigned char *file;      /* the file as read */
  const unsigned char *bin; /* a GLB's binary chunk, inside file */
  size_t bin_n;
  int glb;
  cJSON *root;
  int nimg0;                /* images the file had */
  jnd_buf *enc;             /* encoded new images ... */
  int *enc_img, *enc_jpeg;  /* ... the image index each is written as, and its format */
  int nenc;
};

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

/* 1 */
jnd_status jnd_gltf_doc_read(const char *src, jnd_gltf_doc **out) {
  *out = NULL;
  jnd_gltf_doc *d = jnd_calloc(1, sizeof *d);
  if (!d) return JND_ERR_NOMEM;
  size_t fn = 0;
  jnd_status s = jnd_read_file(src, MAX_MODEL, &d->file, &fn);
  if (s != JND_OK) {
    free(d);
    return s;
  }
  const unsigned char *json_bytes = NULL;
  size_t json_n = 0;
  d->glb = jnd_glb_split(d->file, fn, &json_bytes, &json_n, &d->bin, &d->bin_n);
  if (d->glb >= 0) d->root = cJSON_ParseWithLength((const char *)json_bytes, json_n);
  if (!d->root) {
    jnd_gltf_doc_free(d);
    return jnd_fail(JND_ERR_FORMAT, "%s: not a glTF 2.0 file (only glTF models can be written back)", src);
  }
  snprintf(d->src, sizeof d->src, "%s", src);
  dir_of(src, d->src_dir, sizeof d->src_dir);
  d->nimg0 = cJSON_GetArraySize(item(d->root, "images"));
  *out = d;
  return JND_OK;
}

void jnd_gltf_doc_free(jnd_gltf_doc *d) {
  if (!d) return;
  for (int e = 0; e < d->nenc; e++) free(d->enc[e].p);
  free(d->enc);
  free(d->enc_img);
  free(d->enc_jpeg);
  cJSON_Delete(d->root);
  free(d->file);
  free(d);
}

/* 2. assimp loads a glTF's materials lazily, in the order meshes first
 * reference them while the default scene's nodes are read (a node's
 * children before its own mesh, a mesh's primitives in order), and leaves
 * out the ones no mesh uses (an unused material, or one only a
 * KHR_materials_variants mapping names): so the scene's material j is the
 * j-th distinct material of that walk. A glTF node has at most one parent
 * (glTF 2.0 §3.5.3: nodes form disjoint trees), so each node is walked
 * once: a file that names a node twice, or in a cycle, cannot make the walk
 * exponential (children [0, 0] at every one of 64 levels was 2^64 calls).
 * The walk keeps its own stack (at most one entry a node), so a tree of any
 * depth is walked whole, as assimp reads it (a depth bound of 64 left the
 * materials below it to the file's order). */
static void note_materials(const cJSON *root, const cJSON *nd, int *order, int *n, int cap) {
  const cJSON *mesh = cJSON_GetArrayItem(item(root, "meshes"), int_of(nd, "mesh", -1)), *prim;
  cJSON_ArrayForEach(prim, item(mesh, "primitives")) {
    int m = int_of(prim, "material", -1), seen = m < 0;
    for (int k = 0; k < *n && !seen; k++) seen = order[k] == m;
    if (!seen && *n < cap) order[(*n)++] = m;
  }
}

typedef struct {
  const cJSON *node, *next;   /* a node on the walk (NULL: the scene), and its next child to enter */
} walk_frame;

/* the scene's trees, from its root nodes: each node's children, then its
 * own mesh's materials into order (at most cap); each node entered once */
static jnd_status walk_scene(const cJSON *root, const cJSON *scene, int *order, int *n, int cap) {
  const cJSON *nodes = item(root, "nodes"), *roots = item(scene, "nodes");
  size_t nn = (size_t)cJSON_GetArraySize(nodes) + 1;
  unsigned char *walked = jnd_calloc(nn, 1);
  walk_frame *stack = jnd_calloc(nn, sizeof *stack);   /* the scene, then at most every node */
  if (!walked || !stack) {
    free(walked);
    free(stack);
    return JND_ERR_NOMEM;
  }
  int sp = 0;
  stack[sp++] = (walk_frame){NULL, roots ? roots->child : NULL};
  while (sp > 0) {
    walk_frame *f = &stack[sp - 1];
    if (!f->next) {   /* its children done: its own mesh */
      if (f->node) note_materials(root, f->node, order, n, cap);
      sp--;
      continue;
    }
    const cJSON *c = f->next;
    f->next = c->next;
    int k = cJSON_IsNumber(c) ? c->valueint : -1;
    const cJSON *nd = cJSON_GetArrayItem(nodes, k), *ch = item(nd, "children");
    if (!nd || walked[k]) continue;
    walked[k] = 1;
    stack[sp++] = (walk_frame){nd, ch ? ch->child : NULL};
  }
  free(walked);
  free(stack);
  return JND_OK;
}

jnd_status jnd_gltf_doc_materials(const jnd_gltf_doc *d, const jnd_scene *scene, const unsigned char *need,
                                  int *out) {
  const cJSON *root = d->root;
  int nm = jnd_scene_material_count(scene), n = 0;
  for (int j = 0; j < nm; j++) out[j] = -1;
  const cJSON *sc = cJSON_GetArrayItem(item(root, "scenes"), int_of(root, "scene", 0));
  jnd_status s = walk_scene(root, sc, out, &n, nm);
  if (s != JND_OK) return s;
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
    for (int k = 0; k < JND_MAP_SLOTS && ok; k++)
      if (need && need[(size_t)j * JND_MAP_SLOTS + (size_t)k]) ok = texture_info((cJSON *)mat, (jnd_map_slot)k) != NULL;
    if (!ok)
      return jnd_fail(JND_ERR_FORMAT, "%s: cannot tell which glTF material '%s' is (the model copy would not match)",
                      d->src, name);
  }
  return JND_OK;
}

/* image img is JPEG (by mimeType or the uri's extension) */
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

/* the glTF image a slot of glTF material g samples, or -1; *info its textureInfo, *tex its texture */
static int slot_image(const jnd_gltf_doc *d, int g, jnd_map_slot slot, cJSON **info, int *tex) {
  cJSON *in = g >= 0 ? texture_info(cJSON_GetArrayItem(item(d->root, "materials"), g), slot) : NULL;
  int t = int_of(in, "index", -1);
  int img = int_of(cJSON_GetArrayItem(item(d->root, "textures"), t), "source", -1);
  if (info) *info = in;
  if (tex) *tex = t;
  return in && img >= 0 && img < d->nimg0 ? img : -1;
}

/* 3 */
jnd_status jnd_gltf_doc_set_images(jnd_gltf_doc *d, const jnd_scene *scene, const jnd_gltf_image_edit *edits,
                                   int nedits) {
  cJSON *materials = (cJSON *)item(d->root, "materials");
  cJSON *textures = (cJSON *)item(d->root, "textures");
  cJSON *images = (cJSON *)item(d->root, "images");
  /* target[k]: the image edit k's slot samples in the copy; from[k]: the one it sampled */
  int nimg0 = d->nimg0, *target = jnd_calloc((size_t)nedits + 1, sizeof *target);
  int *from = jnd_calloc((size_t)nedits + 1, sizeof *from);
  int *used_orig = jnd_calloc((size_t)nimg0 + 1, sizeof *used_orig);
  int *replaced = jnd_calloc((size_t)nimg0 + 1, sizeof *replaced);
  d->enc = jnd_calloc((size_t)nedits + 1, sizeof *d->enc);
  d->enc_img = jnd_calloc((size_t)nedits + 1, sizeof *d->enc_img);
  d->enc_jpeg = jnd_calloc((size_t)nedits + 1, sizeof *d->enc_jpeg);
  jnd_status s = JND_OK;
  if (!target || !from || !used_orig || !replaced || !d->enc || !d->enc_img || !d->enc_jpeg) {
    s = JND_ERR_NOMEM;
    goto done;
  }
  /* an image that any slot left as it is uses (a material the scene does
   * not have, an unchanged slot) stays as it is */
  int ngm = cJSON_GetArraySize(materials);
  for (int g = 0; g < ngm; g++)
    for (int k = 0; k < JND_MAP_SLOTS; k++) {
      int img = slot_image(d, g, (jnd_map_slot)k, NULL, NULL), edited = 0;
      if (img < 0) continue;
      for (int e = 0; e < nedits && !edited; e++) edited = edits[e].material == g && edits[e].slot == (jnd_map_slot)k;
      if (!edited) used_orig[img] = 1;
    }
  /* one encoded image per (image, size) */
  for (int k = 0; k < nedits; k++) {
    const jnd_gltf_image_edit *u = &edits[k];
    cJSON *info;
    int tex, img = slot_image(d, u->material, u->slot, &info, &tex);
    target[k] = -1;
    from[k] = img;
    if (img < 0) continue;
    int found = -1;
    for (int j = 0; j < k; j++)
      if (target[j] >= 0 && from[j] == img && edits[j].width == u->width && edits[j].height == u->height)
        found = j;
    if (found >= 0) {
      target[k] = target[found];
    } else {
      if (!used_orig[img] && !replaced[img]) {
        target[k] = img;
        replaced[img] = 1;
      } else {
        cJSON *copy = cJSON_Duplicate(cJSON_GetArrayItem(images, img), 1);
        cJSON_DeleteItemFromObjectCaseSensitive(copy, "uri");
        cJSON_DeleteItemFromObjectCaseSensitive(copy, "bufferView");
        append(images, copy);
        target[k] = cJSON_GetArraySize(images) - 1;
      }
      jnd_image im = {0};
      if ((s = jnd_scene_map_get(scene, u->map, 0, &im)) != JND_OK) goto done;
      d->enc_jpeg[d->nenc] = is_jpeg(cJSON_GetArrayItem(images, img)) && im.c != 2 && im.c != 4;
      s = jnd_image_encode_8bit(&im, d->enc_jpeg[d->nenc], &d->enc[d->nenc]);
      jnd_image_free(&im);
      if (s != JND_OK) goto done;
      d->enc_img[d->nenc++] = target[k];
    }
    if (target[k] != img) { /* a texture for the new image */
      cJSON *tcopy = cJSON_Duplicate(cJSON_GetArrayItem(textures, tex), 1);
      set_number(tcopy, "source", target[k]);
      append(textures, tcopy);
      set_number(info, "index", cJSON_GetArraySize(textures) - 1);
    }
  }
done:
  free(target);
  free(from);
  free(used_orig);
  free(replaced);
  return s;
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

/* 4, .glb: the binary chunk rebuilt view by view; new images replace their views' bytes */
static jnd_status write_glb(jnd_gltf_doc *d, const char *out_dir, const char *path) {
  cJSON *root = d->root;
  cJSON *images = (cJSON *)item(root, "images");
  cJSON *views = (cJSON *)item(root, "bufferViews");
  cJSON *buffers = (cJSON *)item(root, "buffers");
  if (!views) views = cJSON_AddArrayToObject(root, "bufferViews");
  jnd_status s = JND_OK;
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
    for (int e = 0; e < d->nenc; e++)
      if (d->enc_img[e] < d->nimg0 && int_of(cJSON_GetArrayItem(images, d->enc_img[e]), "bufferView", -1) == v)
        data = d->enc[e].p, len = d->enc[e].n;
    if (!data) {
      if (!d->bin || off > d->bin_n || len > d->bin_n - off) {
        nb.failed = 1;
        break;
      }
      data = d->bin + off;
    }
    jnd_buf_pad4(&nb, 0);
    set_number(bv, "byteOffset", (double)nb.n);
    set_number(bv, "byteLength", (double)len);
    jnd_buf_put(&nb, data, len);
  }
  /* images that had no view of their own (new ones, or uri images) */
  for (int e = 0; e < d->nenc; e++) {
    cJSON *im = cJSON_GetArrayItem(images, d->enc_img[e]);
    if (d->enc_img[e] < d->nimg0 && item(im, "bufferView")) continue;
    jnd_buf_pad4(&nb, 0);
    cJSON *bv = cJSON_CreateObject();
    cJSON_AddNumberToObject(bv, "buffer", 0);
    cJSON_AddNumberToObject(bv, "byteOffset", (double)nb.n);
    cJSON_AddNumberToObject(bv, "byteLength", (double)d->enc[e].n);
    append(views, bv);
    cJSON_DeleteItemFromObjectCaseSensitive(im, "uri");
    set_number(im, "bufferView", cJSON_GetArraySize(views) - 1);
    if (!item(im, "mimeType")) cJSON_AddStringToObject(im, "mimeType", d->enc_jpeg[e] ? "image/jpeg" : "image/png");
    jnd_buf_put(&nb, d->enc[e].p, d->enc[e].n);
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
    s = copy_uri(cJSON_GetArrayItem(buffers, b), d->src_dir, out_dir);
  for (int i = 0; i < cJSON_GetArraySize(images) && s == JND_OK; i++)
    if (!item(cJSON_GetArrayItem(images, i), "bufferView"))
      s = copy_uri(cJSON_GetArrayItem(images, i), d->src_dir, out_dir);
  char *js = s == JND_OK ? cJSON_PrintUnformatted(root) : NULL;
  jnd_buf g = {0};
  if (js && !nb.failed) {
    s = jnd_glb_join(js, strlen(js), nb.p, nb.n, &g);
    if (s == JND_OK) s = jnd_write_file_atomic(path, g.p, g.n);
  } else if (s == JND_OK) {
    s = jnd_fail(JND_ERR_FORMAT, "%s: a buffer view lies outside the binary chunk", d->src);
  }
  free(js);
  free(g.p);
  free(nb.p);
  return s;
}

/* 4, .gltf: new images as files beside it; other external files copied */
static jnd_status write_gltf(jnd_gltf_doc *d, const char *out_dir, const char *path) {
  cJSON *images = (cJSON *)item(d->root, "images");
  cJSON *buffers = (cJSON *)item(d->root, "buffers");
  jnd_status s = JND_OK;
  char stem[256];
  snprintf(stem, sizeof stem, "%.255s", base_of(d->src));
  char *dot = strrchr(stem, '.');
  if (dot) *dot = 0;
  for (int e = 0; e < d->nenc && s == JND_OK; e++) {
    cJSON *im = cJSON_GetArrayItem(images, d->enc_img[e]);
    char fname[400], full[4800];
    int jpeg = d->enc_jpeg[e];
    snprintf(fname, sizeof fname, "%s_image%d.%s", stem, d->enc_img[e], jpeg ? "jpg" : "png");
    snprintf(full, sizeof full, "%s/%s", out_dir, fname);
    s = jnd_write_file_atomic(full, d->enc[e].p, d->enc[e].n);
    cJSON_DeleteItemFromObjectCaseSensitive(im, "bufferView");
    cJSON_DeleteItemFromObjectCaseSensitive(im, "uri");
    cJSON_AddStringToObject(im, "uri", fname);
  }
  for (int b = 0; b < cJSON_GetArraySize(buffers) && s == JND_OK; b++)
    s = copy_uri(cJSON_GetArrayItem(buffers, b), d->src_dir, out_dir);
  for (int i = 0; i < d->nimg0 && s == JND_OK; i++) {
    int done_here = 0;
    for (int e = 0; e < d->nenc; e++) done_here |= d->enc_img[e] == i;
    if (!done_here) s = copy_uri(cJSON_GetArrayItem(images, i), d->src_dir, out_dir);
  }
  char *js = s == JND_OK ? cJSON_Print(d->root) : NULL;
  if (js) s = jnd_write_file_atomic(path, js, strlen(js));
  else if (s == JND_OK) s = JND_ERR_NOMEM;
  free(js);
  return s;
}

jnd_status jnd_gltf_doc_write(jnd_gltf_doc *d, const char *out_dir, char *out_path, size_t n) {
  char path[4400];
  snprintf(path, sizeof path, "%s/%s", out_dir, base_of(d->src));
  jnd_status s = d->glb ? write_glb(d, out_dir, path) : write_gltf(d, out_dir, path);
  if (s == JND_OK && out_path) snprintf(out_path, n, "%s", path);
  return s;
}
