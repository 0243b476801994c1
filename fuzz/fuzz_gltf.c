/* libFuzzer target: the glTF readers jnd has of its own, on arbitrary bytes
 * as the source model: texres's glTF writer (src/scene/gltf_edit.c, through src/tasks/texres_model.c) and
 * the MSFT_lod reader of the level-of-detail chain (src/scene/gltf_lod.c,
 * which rewrites the file once per level for assimp to import; every level
 * it reports must rewrite, and a rewrite must parse as the container it came
 * in). First texres's writer: It parses the GLB container and the
 * glTF JSON itself (assimp has read the model before, but the writer reads
 * the file again), re-encodes resized maps into images and rebuilds the
 * binary chunk. Any input must give JND_OK with the model written, or an
 * error with a message; never a crash, a leak or a read outside the file.
 * The scene is the built-in asset with its first map halved, so that the
 * re-encoding and image-splitting paths run. */
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fuzz.h"
#include "scene/scene.h"

static jnd_scene *scene;
static char dir[256], out_dir[300];

static void clear_dir(const char *d) {
  DIR *dp = opendir(d);
  if (!dp) return;
  struct dirent *e;
  char p[600];
  while ((e = readdir(dp))) {
    if (e->d_name[0] == '.') continue;
    snprintf(p, sizeof p, "%s/%s", d, e->d_name);
    unlink(p);
  }
  closedir(dp);
}

static void setup(void) {
  jnd_builtin_params bp;
  jnd_builtin_defaults(&bp);
  bp.map_size = 16;
  if (jnd_scene_builtin(&bp, &scene) != JND_OK) abort();
  if (jnd_scene_map_resize(scene, 0, 8, 8) != JND_OK) abort();
  snprintf(dir, sizeof dir, "/tmp/jnd-fuzz-gltf-%d", (int)getpid());
  snprintf(out_dir, sizeof out_dir, "%s/out", dir);
  mkdir(dir, 0700);
  mkdir(out_dir, 0700);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (!scene) setup();
  char src[400], out_path[4400];
  /* the writer picks the container from the bytes; the name only sets the copy's */
  snprintf(src, sizeof src, "%s/model.%s", dir, size >= 4 && memcmp(data, "glTF", 4) == 0 ? "glb" : "gltf");
  FILE *f = fopen(src, "wb");
  if (!f) abort();
  if (size && fwrite(data, size, 1, f) != 1) abort();
  fclose(f);
  jnd_status s = jnd_texres_write_model(scene, src, out_dir, out_path, sizeof out_path);
  if (s == JND_OK) {
    struct stat st;
    if (stat(out_path, &st) != 0 || st.st_size == 0) abort();
  } else if (!jnd_last_error()[0]) {
    abort();
  }
  clear_dir(out_dir);

  /* MSFT_lod: the level count, then every level's variant */
  int levels = 0;
  jnd_status ls = jnd_gltf_lod_variant("model", data, size, 0, &levels, NULL, NULL);
  if (ls != JND_OK && !jnd_last_error()[0]) abort();
  if (ls == JND_OK && (levels < 1 || levels > 64)) abort();
  for (int k = 0; ls == JND_OK && levels > 1 && k < levels && k < 8; k++) {
    unsigned char *var = NULL;
    size_t vn = 0;
    int again = 0;
    if (jnd_gltf_lod_variant("model", data, size, k, &again, &var, &vn) != JND_OK || again != levels || !var) abort();
    const unsigned char *json, *bin;
    size_t jn, bn;
    int glb = jnd_glb_split(var, vn, &json, &jn, &bin, &bn);
    if (glb != (size >= 4 && memcmp(data, "glTF", 4) == 0)) abort();
    /* a variant has no MSFT_lod left, so it reports one level */
    int one = 0;
    if (jnd_gltf_lod_variant("variant", var, vn, 0, &one, NULL, NULL) != JND_OK || one != 1) abort();
    free(var);
  }
  return 0;
}
