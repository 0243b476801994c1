/* Levels of detail a glTF file already has: the MSFT_lod extension on nodes
 * (KhronosGroup/glTF extensions/2.0/Vendor/MSFT_lod). A node with
 * "extensions": {"MSFT_lod": {"ids": [a, b, ...]}} is the finest level; node
 * a stands in for it at level 1, b at level 2, and so on (a node with fewer
 * ids keeps its coarsest one for the levels beyond). assimp ignores the
 * extension, so each level is imported from a variant of the file in which
 * every such node carries its level's mesh, children and transform, and the
 * LOD nodes themselves are out of the node tree. Material-level MSFT_lod is
 * not read (docs/lod.md).
 *
 * This file only rewrites bytes (no assimp, no files), so that a fuzzer can
 * feed it anything. */
#include <cjson/cJSON.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"
#include "scene/scene.h"

enum { MAX_LOD_LEVELS = 64 };

static cJSON *get(const cJSON *o, const char *k) { return cJSON_GetObjectItemCaseSensitive(o, k); }

/* the ids array of node i's MSFT_lod, or NULL */
static const cJSON *lod_ids(const cJSON *node) {
  return get(get(get(node, "extensions"), "MSFT_lod"), "ids");
}

/* removes from the integer array arr every value v with drop[v] set */
static void strip(cJSON *arr, const unsigned char *drop, int nnodes) {
  if (!cJSON_IsArray(arr)) return;
  for (int i = cJSON_GetArraySize(arr) - 1; i >= 0; i--) {
    const cJSON *x = cJSON_GetArrayItem(arr, i);
    if (cJSON_IsNumber(x) && x->valuedouble >= 0 && x->valuedouble < nnodes && drop[(int)x->valuedouble])
      cJSON_DeleteItemFromArray(arr, i);
  }
}

static void replace_member(cJSON *dst, const cJSON *src, const char *key) {
  cJSON_DeleteItemFromObjectCaseSensitive(dst, key);
  const cJSON *v = get(src, key);
  if (v) cJSON_AddItemToObject(dst, key, cJSON_Duplicate(v, 1));
}

jnd_status jnd_gltf_lod_variant(const char *name, const unsigned char *file, size_t n, int level, int *nlevels,
                                unsigned char **out, size_t *out_n) {
  *nlevels = 1;
  if (out) *out = NULL;
  if (out_n) *out_n = 0;
  const unsigned char *json = NULL, *bin = NULL;
  size_t json_n = 0, bin_n = 0;
  int glb = jnd_glb_split(file, n, &json, &json_n, &bin, &bin_n);
  if (glb < 0) {
    *nlevels = 0;
    return jnd_fail(JND_ERR_FORMAT, "%s: GLB parse error: its JSON chunk is missing or runs past the end of the file", name);
  }
  cJSON *root = cJSON_ParseWithLength((const char *)json, json_n);
  if (!root) {
    *nlevels = 0;
    const char *at = cJSON_GetErrorPtr();
    size_t off = at && at >= (const char *)json && at <= (const char *)json + json_n ? (size_t)(at - (const char *)json) : 0;
    return jnd_fail(JND_ERR_FORMAT, "%s: glTF parse error: the JSON does not parse (at byte %zu of it)", name, off);
  }
  jnd_status st = JND_OK;
  cJSON *nodes = get(root, "nodes");
  int nn = cJSON_IsArray(nodes) ? cJSON_GetArraySize(nodes) : 0;
  unsigned char *is_lod = jnd_calloc((size_t)nn + 1, 1);
  if (!is_lod) {
    cJSON_Delete(root);
    return JND_ERR_NOMEM;
  }
  /* the levels, and which nodes are LOD nodes */
  int levels = 1;
  for (int i = 0; i < nn && !st; i++) {
    const cJSON *ids = lod_ids(cJSON_GetArrayItem(nodes, i));
    if (!ids) continue;
    int m = cJSON_IsArray(ids) ? cJSON_GetArraySize(ids) : -1;
    if (m < 0 || m + 1 > MAX_LOD_LEVELS) {
      st = jnd_fail(JND_ERR_FORMAT, "%s: node %d: MSFT_lod ids must be an array of at most %d nodes", name, i,
                    MAX_LOD_LEVELS - 1);
      break;
    }
    for (int k = 0; k < m; k++) {
      const cJSON *x = cJSON_GetArrayItem(ids, k);
      double v = cJSON_IsNumber(x) ? x->valuedouble : -1;
      if (!(v >= 0 && v < nn) || v != (int)v || (int)v == i) {
        st = jnd_fail(JND_ERR_FORMAT, "%s: node %d: MSFT_lod id %d is not another node", name, i, k);
        break;
      }
      is_lod[(int)v] = 1;
    }
    if (m + 1 > levels) levels = m + 1;
  }
  for (int i = 0; i < nn && !st; i++)
    if (is_lod[i] && lod_ids(cJSON_GetArrayItem(nodes, i)))
      st = jnd_fail(JND_ERR_FORMAT, "%s: node %d is a level of another node and has MSFT_lod itself", name, i);
  *nlevels = st ? 1 : levels;
  if (st || !out || levels == 1) {
    free(is_lod);
    cJSON_Delete(root);
    if (!st && out && level != 0)
      st = jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the file has 1)", name, level);
    return st;
  }
  if (level < 0 || level >= levels) {
    free(is_lod);
    cJSON_Delete(root);
    return jnd_fail(JND_ERR_ARG, "%s: level %d out of range (the file has %d)", name, level, levels);
  }
  /* each node with MSFT_lod takes its level's content; then no node or scene
   * refers to a LOD node any more */
  cJSON *orig = cJSON_Duplicate(nodes, 1);
  for (int i = 0; i < nn && orig; i++) {
    cJSON *node = cJSON_GetArrayItem(nodes, i);
    const cJSON *ids = lod_ids(node);
    if (!ids) continue;
    int m = cJSON_GetArraySize(ids);
    if (level > 0 && m > 0) {
      int id = (int)cJSON_GetArrayItem(ids, (level < m ? level : m) - 1)->valuedouble;
      const cJSON *src = cJSON_GetArrayItem(orig, id);
      static const char *const keys[] = {"mesh", "children", "matrix", "translation", "rotation", "scale", "skin",
                                         "weights"};
      for (size_t k = 0; k < sizeof keys / sizeof *keys; k++) replace_member(node, src, keys[k]);
    }
    cJSON_DeleteItemFromObjectCaseSensitive(get(node, "extensions"), "MSFT_lod");
  }
  cJSON_Delete(orig);
  for (int i = 0; i < nn; i++) strip(get(cJSON_GetArrayItem(nodes, i), "children"), is_lod, nn);
  cJSON *scenes = get(root, "scenes");
  for (int i = 0; i < cJSON_GetArraySize(scenes); i++) strip(get(cJSON_GetArrayItem(scenes, i), "nodes"), is_lod, nn);
  free(is_lod);
  char *text = cJSON_PrintUnformatted(root);
  cJSON_Delete(root);
  if (!text) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", name);
  size_t tn = strlen(text);
  if (glb) {
    jnd_buf b;
    st = jnd_glb_join(text, tn, bin, bin_n, &b);
    free(text);
    if (st) return st;
    *out = b.p;
    *out_n = b.n;
  } else {
    *out = (unsigned char *)text;
    *out_n = tn;
  }
  return JND_OK;
}
