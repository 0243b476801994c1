/* Shared libraries opened on first use (core.h, jnd_lazy_symbol). The
 * callers are one shim file per library, each defining the functions jnd
 * calls with the library's own prototypes (its headers check them) and
 * forwarding to the symbols found here: src/scene/assimp_lazy.c,
 * src/tasks/lapacke_lazy.c. CMakeLists.txt links the library itself instead
 * where its soname cannot be read at configure time. */
#include <dlfcn.h>

#include "core/core.h"

void *jnd_lazy_symbol(jnd_lazy_lib *lib, const char *name) {
  void *h = lib->handle;
  if (!h) {
    /* two threads may both open it: the loader counts, the handle is one */
    h = dlopen(lib->soname, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char *why = dlerror();
      jnd_fail(JND_ERR_IO, "%s: %s", lib->soname, why ? why : "cannot be loaded");
      return NULL;
    }
    lib->handle = h;
  }
  void *f = dlsym(h, name);
  if (!f) jnd_fail(JND_ERR_IO, "%s: no %s in it", lib->soname, name);
  return f;
}
