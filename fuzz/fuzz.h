/* Shared by the fuzz targets: what every successful decode must satisfy. A
 * violated property aborts, so libFuzzer records the input as a crash. */
#ifndef JND_FUZZ_H
#define JND_FUZZ_H
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "io/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A decoded image: within the limits, channels as the info says, and (for
 * linear formats) every sample finite. On failure the image must be empty. */
static inline void fuzz_check_image(jnd_status s, jnd_image *img, const jnd_image_info *info) {
  if (s != JND_OK) {
    if (img->data || img->w || img->h || img->c) abort();
    if (!jnd_last_error()[0]) abort();
    return;
  }
  if (!img->data || img->w < 1 || img->h < 1 || img->c < 1 || img->c > 64) abort();
  if (img->w > JND_MAX_SIDE || img->h > JND_MAX_SIDE || (size_t)img->w * img->h > JND_MAX_PIXELS) abort();
  if (info->channels != img->c) abort();
  size_t n = (size_t)img->w * img->h * img->c;
  for (size_t i = 0; i < n; i++)
    if (!isfinite(img->data[i])) abort();
  jnd_image_free(img);
}

#define JND_FUZZ_DECODER(decode, name)                                   \
  int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {        \
    jnd_image img;                                                       \
    jnd_image_info info;                                                 \
    fuzz_check_image(decode(name, data, size, &img, &info), &img, &info); \
    return 0;                                                            \
  }
#endif
