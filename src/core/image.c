/* jnd_image: float32, planar, w × h × c. */
#include <stdlib.h>
#include <string.h>

#include "core/core.h"

jnd_status jnd_check_size(int w, int h, int c, const char *what) {
  if (w <= 0 || h <= 0 || c <= 0)
    return jnd_fail(JND_ERR_FORMAT, "%s: empty image (%d × %d × %d)", what, w, h, c);
  if (w > JND_MAX_SIDE || h > JND_MAX_SIDE || (size_t)w * (size_t)h > JND_MAX_PIXELS)
    return jnd_fail(JND_ERR_LIMIT, "%s: %d × %d pixels is over the limit (%d a side, %zu pixels)",
                    what, w, h, JND_MAX_SIDE, (size_t)JND_MAX_PIXELS);
  if (c > 64) return jnd_fail(JND_ERR_LIMIT, "%s: %d channels is over the limit of 64", what, c);
  return JND_OK;
}

jnd_status jnd_image_alloc(jnd_image *img, int w, int h, int c) {
  memset(img, 0, sizeof *img);
  jnd_status s = jnd_check_size(w, h, c, "image");
  if (s != JND_OK) return s;
  img->data = jnd_calloc((size_t)w * h * c, sizeof(float));
  if (!img->data) return JND_ERR_NOMEM;
  img->w = w;
  img->h = h;
  img->c = c;
  return JND_OK;
}

void jnd_image_free(jnd_image *img) {
  if (!img) return;
  free(img->data);
  memset(img, 0, sizeof *img);
}

float *jnd_image_plane(const jnd_image *img, int ch) {
  return img->data + (size_t)ch * img->w * img->h;
}

size_t jnd_first_outside(const float *v, size_t n, float lo, float hi) {
  enum { BLOCK = 4096 };
  for (size_t b = 0; b < n; b += BLOCK) {
    const size_t e = n - b < BLOCK ? n : b + BLOCK;
    int bad = 0;
#pragma omp simd reduction(| : bad)
    for (size_t i = b; i < e; i++) bad |= !(v[i] >= lo && v[i] <= hi);
    if (!bad) continue;
    for (size_t i = b; i < e; i++)
      if (!(v[i] >= lo && v[i] <= hi)) return i;
  }
  return n;
}
