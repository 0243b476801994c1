/* The files an asset is made of: the model file and what it references — a
 * glTF's buffers and images (by URI, relative to the model's folder; data:
 * URIs are inside the file), an OBJ's material libraries (mtllib) and the
 * texture maps those name. The output writer registers them as inputs, so
 * that no run writes over a file the asset reads (docs/outputs.md). The
 * same resolution as the importer's (import.c, assimp's OBJ reader). */
#include <ctype.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cjson/cJSON.h>

#include "core/core.h"
#include "io/io.h"
#include "scene/scene.h"

#define MAX_ASSET_BYTES ((size_t)1 << 31)

void jnd_uri_decode(char *s) {
  char *o = s;
  for (char *p = s; *p; p++) {
    if (p[0] == '%' && isxdigit((unsigned char)p[1]) && isxdigit((unsigned char)p[2])) {
      char hex[3] = {p[1], p[2], 0};
      *o++ = (char)strtol(hex, NULL, 16);
      p += 2;
    } else {
      *o++ = *p;
    }
  }
  *o = 0;
}

void jnd_model_relative(const char *model, const char *ref, int uri, char *full, size_t n) {
  char rel[1024];
  snprintf(rel, sizeof rel, "%s", ref);
  if (uri) jnd_uri_decode(rel);
  for (char *p = rel; *p; p++)
    if (*p == '\\') *p = '/';
  const char *slash = strrchr(model, '/');
  if (rel[0] == '/' || !slash)
    snprintf(full, n, "%s", rel);
  else
    snprintf(full, n, "%.*s/%s", (int)(slash - model), model, rel);
}

typedef struct {
  char **v;
  int n, cap;
} list;

static int list_add(list *l, const char *model, const char *ref, int uri) {
  if (l->n == l->cap) {
    int c = l->cap ? l->cap * 2 : 8;
    char **v = realloc(l->v, (size_t)c * sizeof *v);
    if (!v) return 0;
    l->v = v;
    l->cap = c;
  }
  char full[2048];
  if (model) jnd_model_relative(model, ref, uri, full, sizeof full);
  else snprintf(full, sizeof full, "%s", ref);
  if (!(l->v[l->n] = malloc(strlen(full) + 1))) return 0;
  memcpy(l->v[l->n++], full, strlen(full) + 1);
  return 1;
}

/* every "uri" of buffers[] and images[] that is not a data: URI */
static int gltf_refs(const char *path, const unsigned char *file, size_t n, list *l) {
  const unsigned char *json, *bin;
  size_t json_n, bin_n;
  if (jnd_glb_split(file, n, &json, &json_n, &bin, &bin_n) < 0) return 1;   /* the importer reports it */
  cJSON *root = cJSON_ParseWithLength((const char *)json, json_n);
  if (!root) return 1;
  int ok = 1;
  const char *arrays[] = {"buffers", "images"};
  for (int a = 0; a < 2 && ok; a++) {
    const cJSON *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(root, arrays[a])) {
      const cJSON *u = cJSON_GetObjectItemCaseSensitive(e, "uri");
      if (cJSON_IsString(u) && strncmp(u->valuestring, "data:", 5) != 0) ok = ok && list_add(l, path, u->valuestring, 1);
    }
  }
  cJSON_Delete(root);
  return ok;
}

/* the rest of a line after its keyword, trimmed: the last word for a map
 * (options such as "-bm 0.5" come before the file name) */
static const char *last_word(char *line) {
  size_t k = strlen(line);
  while (k > 0 && isspace((unsigned char)line[k - 1])) line[--k] = 0;
  char *w = line + k;
  while (w > line && !isspace((unsigned char)w[-1])) w--;
  return w;
}

/* OBJ: "mtllib a.mtl b.mtl", then in each library the map statements */
static int obj_refs(const char *path, const unsigned char *file, size_t n, int is_mtl, list *l) {
  int ok = 1;
  for (size_t pos = 0; pos < n && ok;) {
    size_t e = pos;
    while (e < n && file[e] != '\n') e++;
    char line[2048];
    size_t k = e - pos < sizeof line - 1 ? e - pos : sizeof line - 1;
    memcpy(line, file + pos, k);
    line[k] = 0;
    pos = e + 1;
    char *p = line;
    while (isspace((unsigned char)*p)) p++;
    char *kw = p;
    while (*p && !isspace((unsigned char)*p)) p++;
    if (!*p) continue;
    *p++ = 0;
    if (!is_mtl && strcmp(kw, "mtllib") == 0) {
      char *save = NULL;
      for (char *w = strtok_r(p, " \t\r", &save); w && ok; w = strtok_r(NULL, " \t\r", &save)) {
        size_t before = (size_t)l->n;
        ok = list_add(l, path, w, 0);
        if (!ok) break;
        unsigned char *mtl = NULL;
        size_t mn = 0;
        char *name = l->v[before];
        if (jnd_read_file(name, MAX_ASSET_BYTES, &mtl, &mn) == JND_OK) {
          char *copy = malloc(strlen(name) + 1);
          if (copy) {
            memcpy(copy, name, strlen(name) + 1);
            ok = obj_refs(copy, mtl, mn, 1, l);
          } else {
            ok = 0;
          }
          free(copy);
          free(mtl);
        }
      }
    } else if (is_mtl && (strncasecmp(kw, "map_", 4) == 0 || strcasecmp(kw, "bump") == 0 || strcasecmp(kw, "disp") == 0 ||
                          strcasecmp(kw, "decal") == 0 || strcasecmp(kw, "refl") == 0 || strcasecmp(kw, "norm") == 0)) {
      const char *w = last_word(p);
      if (*w) ok = list_add(l, path, w, 0);
    }
  }
  return ok;
}

/* a GLB's header and JSON chunk only (the binary chunk can be most of a
 * large file, and holds no references): 1 when read, as a GLB that
 * jnd_glb_split takes (its binary chunk left off) */
static int glb_head(const char *path, unsigned char **out, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  unsigned char h[20];
  int ok = fread(h, 1, 20, f) == 20 && memcmp(h, "glTF", 4) == 0 && memcmp(h + 16, "JSON", 4) == 0;
  uint32_t len = ok ? (uint32_t)h[12] | (uint32_t)h[13] << 8 | (uint32_t)h[14] << 16 | (uint32_t)h[15] << 24 : 0;
  unsigned char *b = ok && len < (1u << 30) ? malloc(20 + (size_t)len) : NULL;
  ok = b && fread(b + 20, 1, len, f) == len;
  fclose(f);
  if (!ok) {
    free(b);
    return 0;
  }
  memcpy(b, h, 20);
  uint32_t total = 20 + len;   /* the container's length as if it ended after the JSON chunk */
  for (int k = 0; k < 4; k++) b[8 + k] = (unsigned char)(total >> (8 * k));
  *out = b;
  *n = total;
  return 1;
}

jnd_status jnd_asset_files(const char *path, char ***files, int *count) {
  *files = NULL;
  *count = 0;
  list l = {0};
  if (!list_add(&l, NULL, path, 0)) return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  unsigned char *file = NULL;
  size_t n = 0;
  const char *ext = strrchr(path, '.');
  int ok = 1;
  if (ext && strcasecmp(ext, ".glb") == 0 && glb_head(path, &file, &n)) {
    ok = gltf_refs(path, file, n, &l);
    free(file);
  } else if (ext && (strcasecmp(ext, ".gltf") == 0 || strcasecmp(ext, ".glb") == 0 || strcasecmp(ext, ".obj") == 0) &&
             jnd_read_file(path, MAX_ASSET_BYTES, &file, &n) == JND_OK) {
    ok = strcasecmp(ext, ".obj") == 0 ? obj_refs(path, file, n, 0, &l) : gltf_refs(path, file, n, &l);
    free(file);
  }
  if (!ok) {
    jnd_asset_files_free(l.v, l.n);
    return jnd_fail(JND_ERR_NOMEM, "%s: out of memory", path);
  }
  *files = l.v;
  *count = l.n;
  return JND_OK;
}

void jnd_asset_files_free(char **files, int count) {
  for (int k = 0; k < count; k++) free(files[k]);
  free(files);
}

const char *jnd_asset_length_unit(const char *path) {
  const char *dot = path ? strrchr(path, '.') : NULL;
  return dot && (strcasecmp(dot, ".gltf") == 0 || strcasecmp(dot, ".glb") == 0) ? "m" : "object units";
}
