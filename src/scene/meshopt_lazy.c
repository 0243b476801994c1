/* meshoptimizer opened when a command first builds a LOD chain (core.h,
 * jnd_lazy_symbol): the functions of meshoptimizer that lod.c calls, with
 * meshoptimizer's prototypes, each forwarding to the library's own. Built
 * where CMake read meshoptimizer's soname (JND_MESHOPT_SONAME); elsewhere
 * jnd links it as before and this file holds only jnd_meshopt_ready.
 * meshoptimizer is C++: linking it loaded libstdc++ and libgcc_s at every
 * start, 1.7 ms of each process here (a program linked with it and nothing
 * else started in 3.3 ms against 1.5 ms; docs/speed.md "Eleventh pass"),
 * for `jnd diff` as for every other command that never simplifies a mesh.
 * meshoptimizer's functions have no way to fail, so jnd_scene_lod_build
 * asks jnd_meshopt_ready first and reports a library that cannot be opened;
 * a shim whose function cannot be found does nothing and returns 0. */
#include <stddef.h>

#include <meshoptimizer.h>

#include "core/core.h"
#include "scene/scene.h"

#ifdef JND_MESHOPT_SONAME
static jnd_lazy_lib meshopt = {JND_MESHOPT_SONAME, NULL};

int jnd_meshopt_ready(void) { return jnd_lazy_symbol(&meshopt, "meshopt_simplify") != NULL; }

size_t meshopt_simplify(unsigned int *destination, const unsigned int *indices, size_t index_count,
                        const float *vertex_positions, size_t vertex_count, size_t vertex_positions_stride,
                        size_t target_index_count, float target_error, unsigned int options, float *result_error) {
  JND_LAZY_FN(&meshopt,
              size_t (*)(unsigned int *, const unsigned int *, size_t, const float *, size_t, size_t, size_t, float,
                         unsigned int, float *),
              meshopt_simplify);
  return f ? f(destination, indices, index_count, vertex_positions, vertex_count, vertex_positions_stride,
               target_index_count, target_error, options, result_error)
           : 0;
}

size_t meshopt_simplifySloppy(unsigned int *destination, const unsigned int *indices, size_t index_count,
                              const float *vertex_positions, size_t vertex_count, size_t vertex_positions_stride,
                              size_t target_index_count, float target_error, float *result_error) {
  JND_LAZY_FN(&meshopt,
              size_t (*)(unsigned int *, const unsigned int *, size_t, const float *, size_t, size_t, size_t, float,
                         float *),
              meshopt_simplifySloppy);
  return f ? f(destination, indices, index_count, vertex_positions, vertex_count, vertex_positions_stride,
               target_index_count, target_error, result_error)
           : 0;
}

float meshopt_simplifyScale(const float *vertex_positions, size_t vertex_count, size_t vertex_positions_stride) {
  JND_LAZY_FN(&meshopt, float (*)(const float *, size_t, size_t), meshopt_simplifyScale);
  return f ? f(vertex_positions, vertex_count, vertex_positions_stride) : 0.0f;
}

void meshopt_generateShadowIndexBufferMulti(unsigned int *destination, const unsigned int *indices,
                                            size_t index_count, size_t vertex_count,
                                            const struct meshopt_Stream *streams, size_t stream_count) {
  JND_LAZY_FN(&meshopt,
              void (*)(unsigned int *, const unsigned int *, size_t, size_t, const struct meshopt_Stream *, size_t),
              meshopt_generateShadowIndexBufferMulti);
  if (f) f(destination, indices, index_count, vertex_count, streams, stream_count);
}

size_t meshopt_optimizeVertexFetchRemap(unsigned int *destination, const unsigned int *indices, size_t index_count,
                                        size_t vertex_count) {
  JND_LAZY_FN(&meshopt, size_t (*)(unsigned int *, const unsigned int *, size_t, size_t),
              meshopt_optimizeVertexFetchRemap);
  return f ? f(destination, indices, index_count, vertex_count) : 0;
}
#else
int jnd_meshopt_ready(void) { return 1; }
#endif
