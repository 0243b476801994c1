/* libFuzzer target: the PNG decoder (chunk validation, then zlib's inflate
 * where it can, else stb_image) on arbitrary bytes; and differential: where
 * the zlib path and stb_image alone both accept an input, they must give the
 * same pixels, bit for bit, and the same info; and an 8-bit RGB file kept
 * as its codes (jnd_png_decode_rgb8, what jnd diff reads) must decode
 * exactly when the planes do, to their samples. */
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  jnd_image img, ref;
  jnd_image_info info, ref_info;
  jnd_status s = jnd_decode_png("fuzz.png", data, size, &img, &info);
  /* other PNGs went through stb_image already */
  if (s == JND_OK && jnd_png_plain(data, size)) {
    jnd_status r = jnd_decode_png_stb("fuzz.png", data, size, &ref, &ref_info);
    if (r == JND_OK && (img.w != ref.w || img.h != ref.h || img.c != ref.c ||
                        memcmp(img.data, ref.data, sizeof(float) * img.w * img.h * img.c) != 0 ||
                        memcmp(&info, &ref_info, sizeof info) != 0))
      abort();
    fuzz_check_image(r, &ref, &ref_info);
  }
  if (jnd_png_validate("fuzz.png", data, size) == JND_OK && jnd_png_is_rgb8(data, size)) {
    unsigned char *rgb = NULL;
    int w, h;
    jnd_status c = jnd_png_decode_rgb8("fuzz.png", data, size, &rgb, &w, &h);
    if ((c == JND_OK) != (s == JND_OK)) abort();
    for (size_t i = 0; c == JND_OK && i < (size_t)w * h * 3; i++)
      if (w != img.w || h != img.h || jnd_image_plane(&img, (int)(i % 3))[i / 3] != (float)(rgb[i] * (1.0 / 255)))
        abort();
    free(rgb);
  }
  fuzz_check_image(s, &img, &info);
  return 0;
}
