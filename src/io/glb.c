/* The binary glTF container (glTF 2.0 §4.4): a 12-byte header, a JSON chunk
 * and an optional BIN chunk; and a growable byte buffer to build one in.
 * Shared by every glTF reader and writer of jnd (texres's model copy, the
 * level-of-detail chain's MSFT_lod reader and writer). */
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "io/io.h"

enum { GLB_MAGIC = 0x46546C67u, CHUNK_JSON = 0x4E4F534Au, CHUNK_BIN = 0x004E4942u };

void jnd_buf_put(jnd_buf *b, const void *data, size_t n) {
  if (b->failed || n == 0) return;
  if (b->n + n > b->cap || b->n + n < b->n) {
    size_t cap = b->cap ? b->cap : 65536;
    while (cap < b->n + n && cap <= SIZE_MAX / 2) cap *= 2;
    unsigned char *q = cap >= b->n + n ? realloc(b->p, cap) : NULL;
    if (!q) {
      b->failed = 1;
      return;
    }
    b->p = q;
    b->cap = cap;
  }
  memcpy(b->p + b->n, data, n);
  b->n += n;
}

void jnd_buf_pad4(jnd_buf *b, unsigned char fill) {
  while (b->n % 4 && !b->failed) jnd_buf_put(b, &fill, 1);
}

void jnd_buf_free(jnd_buf *b) {
  free(b->p);
  memset(b, 0, sizeof *b);
}

int jnd_glb_split(const unsigned char *file, size_t n, const unsigned char **json, size_t *json_n,
                  const unsigned char **bin, size_t *bin_n) {
  *bin = NULL;
  *bin_n = 0;
  if (n < 4 || memcmp(file, "glTF", 4) != 0) {
    *json = file;
    *json_n = n;
    return 0;
  }
  uint32_t len0, type0;
  if (n < 20) return -1;
  memcpy(&len0, file + 12, 4);
  memcpy(&type0, file + 16, 4);
  if (type0 != CHUNK_JSON || 20 + (size_t)len0 > n) return -1;
  *json = file + 20;
  *json_n = len0;
  size_t off = 20 + (size_t)len0;
  if (off + 8 <= n) {
    uint32_t len1, type1;
    memcpy(&len1, file + off, 4);
    memcpy(&type1, file + off + 4, 4);
    if (type1 == CHUNK_BIN && len1 <= n - off - 8) {
      *bin = file + off + 8;
      *bin_n = len1;
    }
  }
  return 1;
}

jnd_status jnd_glb_join(const char *json, size_t json_n, const unsigned char *bin, size_t bin_n, jnd_buf *out) {
  memset(out, 0, sizeof *out);
  size_t jpad = (json_n + 3) / 4 * 4, bpad = (bin_n + 3) / 4 * 4;
  size_t total = 12 + 8 + jpad + (bin_n ? 8 + bpad : 0);
  if (total > UINT32_MAX) return jnd_fail(JND_ERR_LIMIT, "a binary glTF of more than 4 GiB");
  uint32_t h[5] = {GLB_MAGIC, 2, (uint32_t)total, (uint32_t)jpad, CHUNK_JSON};
  jnd_buf_put(out, h, sizeof h);
  jnd_buf_put(out, json, json_n);
  jnd_buf_pad4(out, ' ');
  if (bin_n) {
    uint32_t c[2] = {(uint32_t)bpad, CHUNK_BIN};
    jnd_buf_put(out, c, sizeof c);
    jnd_buf_put(out, bin, bin_n);
    jnd_buf_pad4(out, 0);
  }
  if (out->failed) {
    jnd_buf_free(out);
    return jnd_fail(JND_ERR_NOMEM, "out of memory building a binary glTF");
  }
  return JND_OK;
}
