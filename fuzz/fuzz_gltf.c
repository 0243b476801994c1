/* libFuzzer target: jnd texres's glTF writer (src/tasks/texres_model.c) on
 * arbitrary bytes as the source model. It parses the GLB container and the
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
  return 0;
}
