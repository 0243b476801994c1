/* jnd texres's copy of a glTF 2.0 model: its texture maps at the sizes
 * texres chose (the input is never touched). The task's part is which
 * slots change — a map whose size in use differs from the file's — and
 * which pixels they get (the scene's map at its size in use); reading,
 * editing and writing the glTF document is the scene layer's
 * (src/scene/gltf_edit.c). A material the scene does not have (no mesh
 * uses it, or only a KHR_materials_variants mapping names it) is left as
 * it was: nobody judged it. */
#include <stdio.h>
#include <stdlib.h>

#include "core/core.h"
#include "scene/scene.h"

/* the map the scene holds for material j's slot k, when its size in use is
 * not the file's; -1 otherwise */
static int resized_map(const jnd_scene *scene, int j, jnd_map_slot k) {
  char full[256];
  snprintf(full, sizeof full, "%s/%s", jnd_scene_material_name(scene, j), jnd_map_slot_name(k));
  jnd_map_info mi;
  int i = jnd_scene_map_find(scene, full);
  return i >= 0 && jnd_scene_map_info(scene, i, &mi) == JND_OK &&
                 (mi.width != mi.orig_width || mi.height != mi.orig_height)
             ? i
             : -1;
}

jnd_status jnd_texres_write_model(const jnd_scene *scene, const char *src, const char *out_dir, char *out_path,
                                  size_t out_n) {
  jnd_gltf_doc *doc = NULL;
  jnd_status s = jnd_gltf_doc_read(src, &doc);
  if (s != JND_OK) return s;
  int nm = jnd_scene_material_count(scene), nmaps = jnd_scene_map_count(scene), nedits = 0;
  unsigned char *need = jnd_calloc((size_t)nm * JND_MAP_SLOTS + 1, 1);
  int *gmat = jnd_calloc((size_t)nm + 1, sizeof *gmat);
  jnd_gltf_image_edit *edits = jnd_calloc((size_t)nmaps + 1, sizeof *edits);
  if (!need || !gmat || !edits) s = JND_ERR_NOMEM;
  /* every map the copy changes must have its slot in the file's material */
  for (int j = 0; j < nm && s == JND_OK; j++)
    for (int k = 0; k < JND_MAP_SLOTS; k++) need[(size_t)j * JND_MAP_SLOTS + (size_t)k] = resized_map(scene, j, (jnd_map_slot)k) >= 0;
  if (s == JND_OK) s = jnd_gltf_doc_materials(doc, scene, need, gmat);
  /* the resized maps in the scene's order (each map is one material's
   * slot: scene.c): the copy's new images and textures are numbered in it */
  for (int i = 0; i < nmaps && s == JND_OK; i++) {
    jnd_map_info mi;
    jnd_scene_map_info(scene, i, &mi);
    if (mi.material < 0 || (mi.width == mi.orig_width && mi.height == mi.orig_height)) continue;
    edits[nedits++] = (jnd_gltf_image_edit){gmat[mi.material], mi.slot, i, mi.width, mi.height};
  }
  if (s == JND_OK) s = jnd_gltf_doc_set_images(doc, scene, edits, nedits);
  if (s == JND_OK) s = jnd_gltf_doc_write(doc, out_dir, out_path, out_n);
  free(need);
  free(gmat);
  free(edits);
  jnd_gltf_doc_free(doc);
  return s;
}
