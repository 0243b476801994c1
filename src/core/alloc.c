/* Checked allocation: sizes that overflow or memory that cannot be had become
 * JND_ERR_NOMEM messages instead of crashes. */
#include <stdint.h>
#include <stdlib.h>

#include "core/core.h"

void *jnd_alloc(size_t count, size_t size) {
  if (size && count > SIZE_MAX / size) {
    jnd_fail(JND_ERR_NOMEM, "allocation of %zu × %zu bytes overflows", count, size);
    return NULL;
  }
  size_t bytes = count * size;
  void *p = malloc(bytes > 0 ? bytes : 1);
  if (!p) jnd_fail(JND_ERR_NOMEM, "out of memory allocating %zu bytes", count * size);
  return p;
}

void *jnd_calloc(size_t count, size_t size) {
  void *p = calloc(count ? count : 1, size ? size : 1);
  if (!p) jnd_fail(JND_ERR_NOMEM, "out of memory allocating %zu × %zu bytes", count, size);
  return p;
}
