/* stub */
#include "core/core.h"
jnd_status jnd_texres_write_model(const jnd_scene *scene, const char *src_path, const char *out_dir, char *out_path,
                                  size_t n) {
  return JND_OK;
}
