/* libFuzzer target: the PNG decoder (chunk validation, then zlib's inflate
 * where it can, else stb_image) on arbitrary bytes; and differential: where
 * the zlib path and stb_image alone both accept an input, they must give the
 * same pixels, bit for bit, and the same info. */
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
  fuzz_check_image(s, &img, &info);
  return 0;
}
